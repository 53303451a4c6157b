"""The demo's report folder: ``index.html`` with the numbers, the plots, the animation and
the interactive 3D page.

Every file is written atomically.  The folder gets a marker file (:data:`MARKER`) when we
create it; an existing folder without the marker is never written into unless
``force=True``, so a typo in ``--out`` cannot clobber someone's files.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from .._core.errors import InputError

MARKER = ".inertia-report"


def prepare_folder(out_dir, *, force: bool = False) -> Path:
    """Create ``out_dir`` (or reuse one we created); refuse a foreign folder unless ``force``."""
    out = Path(out_dir)
    if out.exists() and not out.is_dir():
        raise InputError(f"{out} exists and is not a folder")
    if out.is_dir() and any(out.iterdir()) and not (out / MARKER).exists() and not force:
        raise InputError(f"{out} exists and was not created by inertia: choose another --out, or pass --force "
                         "to write the report into it anyway")
    out.mkdir(parents=True, exist_ok=True)
    (out / MARKER).write_text("written by inertia demo; inertia may overwrite the files of this folder\n")
    return out


def _fmt(x, digits: int = 6) -> str:
    return f"{x:.{digits}g}"


def write_index(out: Path, *, title: str, credit: str | None, props, study, files: dict, extra: dict) -> Path:
    """``index.html`` linking every file of the report (``files``: role -> list of names)."""
    from .._core.atomic import write_text_atomic

    moments, R = props.principal()
    rows = [("mass", f"{_fmt(props.mass)} kg"),
            ("center of mass", f"[{', '.join(_fmt(x) for x in props.com)}] m"),
            ("principal moments I1 &le; I2 &le; I3", f"[{', '.join(_fmt(x) for x in moments)}] kg m&sup2;"),
            ("validity", "physical" if not props.check() else "; ".join(html.escape(v.message) for v in props.check())),
            ("spin", f"&omega;0 = [{', '.join(_fmt(x, 4) for x in study.omega0_body)}] rad/s about the principal axes"),
            ("predicted flip interval 2K(m)/&lambda;", f"{_fmt(study.flip_interval, 10)} s"),
            ("flips found in the exact solution", ", ".join(_fmt(x, 6) for x in study.detected_flips) + " s")]
    for name, tr in study.integrators.items():
        rows.append((f"{html.escape(name)} (h = {_fmt(tr['h'], 4)} s): max error",
                     f"energy {tr['energy_error'].max():.2e}, |L| {tr['momentum_error'].max():.2e}"))
    table = "\n".join(f"<tr><th>{k}</th><td>{v}</td></tr>" for k, v in rows)
    inertia_rows = "\n".join("<tr>" + "".join(f"<td>{x:.6e}</td>" for x in row) + "</tr>" for row in props.inertia_com)
    figs = []
    for role, caption in (("omega", "Body angular velocity; dashed lines: predicted flips"),
                          ("invariants", "Energy and |L| error of each integrator (log scale)"),
                          ("polhodes", "Polhodes on the angular-momentum sphere; red: the separatrix"),
                          ("body", "Principal axes, six point masses and the equivalent box, to scale")):
        if role in files:
            png, svg = files[role]
            figs.append(f'<figure><img src="{png}" alt="{html.escape(caption)}"><figcaption>{html.escape(caption)} '
                        f'(<a href="{svg}">SVG</a>)</figcaption></figure>')
    anim = ""
    if "animation" in files:
        (name,) = files["animation"]
        tag = (f'<video src="{name}" controls loop muted playsinline></video>' if name.endswith(".mp4")
               else f'<img src="{name}" alt="animation of the flip">')
        anim = f"<h2>The flip</h2><figure>{tag}<figcaption>Tumbling body, six point masses and the fixed " \
               f"angular momentum (black), from the exact solution</figcaption></figure>"
    page = ""
    if "page" in files:
        page = f'<h2>Interactive 3D</h2><p><a href="{files["page"][0]}">Open the interactive page</a>: sliders for ' \
               "the mass and moments move the six points; play the tumbling motion.</p>"
    data_link = f'<p>All numbers: <a href="{files["data"][0]}">{files["data"][0]}</a></p>' if "data" in files else ""
    credit_html = f"<p class=credit>{html.escape(credit)}</p>" if credit else ""
    text = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><meta name="viewport" content="width=device-width, initial-scale=1">
<title>{html.escape(title)}</title>
<style>body{{font-family:system-ui,sans-serif;max-width:960px;margin:auto;padding:1rem;color:#222}}
table{{border-collapse:collapse}}th,td{{text-align:left;padding:2px 8px;border-bottom:1px solid #ddd;font-size:.9rem}}
td{{font-family:monospace}}img,video{{max-width:100%}}figure{{margin:1rem 0}}
.credit{{color:#666;font-size:.85rem}}</style>
</head><body>
<h1>{html.escape(title)}</h1>
{credit_html}
<table>{table}</table>
<h2>Inertia about the center of mass [kg m&sup2;] (body axes, products negated: L = I&omega;)</h2>
<table>{inertia_rows}</table>
{anim}
{page}
<h2>Plots</h2>
{''.join(figs)}
{data_link}
</body></html>
"""
    path = out / "index.html"
    write_text_atomic(path, text)
    return path


def _plain(v):
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, (np.floating, np.integer)):
        return v.item()
    if isinstance(v, dict):
        return {k: _plain(x) for k, x in v.items()}
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    return v


def build_report(out_dir, props, *, title: str, credit: str | None = None, mesh=None, video: bool = True,
                 force: bool = False, progress=None, animation_format: str = "gif") -> dict:
    """Write the whole report; returns ``{"index": path, "files": {...}, "study": FlipStudy, ...}``.

    ``progress(step_name)`` is called before each step (for a progress bar).
    """
    from .._core.atomic import write_text_atomic
    from ..dynamics.flip_study import flip_study
    from ..particles.models import six_point_model
    from . import plots
    from .page import page_data, write_page

    step = progress or (lambda name: None)
    out = prepare_folder(out_dir, force=force)
    step("simulating the flip")
    study = flip_study(props.principal()[0])
    six = six_point_model(props)
    files: dict = {}
    info: dict = {}
    step("plotting")
    r = plots.omega_plot(study, out)
    files["omega"], info["omega"] = r["files"], r
    r = plots.invariants_plot(study, out)
    files["invariants"], info["invariants"] = r["files"], r
    files["polhodes"] = plots.polhode_plot(study, out)["files"]
    files["body"] = plots.body_plot(props, six, out)["files"]
    if video:
        step("animating")
        from ..massprops.equivalent import equivalent_box
        from .animation import render_frames, write_animation

        R = props.principal()[1]
        pts = (six.positions_body - props.com) @ R
        frames, _ = render_frames(study, pts, np.asarray(equivalent_box(props).size) / 2)
        a = write_animation(frames, out / f"flip.{animation_format}")
        files["animation"], info["animation"] = [a["file"]], a
    step("writing the 3D page")
    pdata = page_data(props, study, name=title, mesh=mesh)
    write_page(out / "body3d.html", pdata)
    files["page"] = ["body3d.html"]
    data = {"title": title, "mass": props.mass, "com": props.com, "inertia_com": props.inertia_com,
            "principal_moments": props.principal()[0], "R_body_principal": props.principal()[1],
            "omega0_body_principal": study.omega0_body, "flip_interval": study.flip_interval,
            "flip_times_marked": info["omega"]["flip_times"], "flips_detected": study.detected_flips,
            "integrators": info["invariants"]["max_errors"], "six_points_principal": pdata["six_points"],
            "animation": info.get("animation")}
    write_text_atomic(out / "report.json", json.dumps(_plain(data), indent=2))
    files["data"] = ["report.json"]
    index = write_index(out, title=title, credit=credit, props=props, study=study, files=files, extra=info)
    return {"index": index, "files": files, "study": study, "info": info, "folder": out}


def linked_files(index_path) -> list[str]:
    """Every local file ``index.html`` links to (src/href), for checks."""
    import re

    text = Path(index_path).read_text(encoding="utf-8")
    return sorted({m for m in re.findall(r'(?:src|href)="([^"#:]+)"', text) if not m.startswith("http")})

