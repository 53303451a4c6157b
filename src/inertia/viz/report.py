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


def build_report(out_dir, props, *, title: str, credit: str | None = None, description: str = "", mesh=None,
                 video: bool = True, force: bool = False, progress=None, animation_format: str = "auto",
                 video_view: str = "body", control=None) -> dict:
    """Write the whole report; returns ``{"index": path, "files": {...}, "study": FlipStudy, ...}``.

    ``title``: the body's name; ``description``: one line about it (dimensions, source file);
    ``mesh``: ``(vertices (V, 3) m, faces)`` in the body frame, drawn in the pictures
    (decimated over :data:`~.display_mesh.MAX_DISPLAY_FACES` faces);
    ``animation_format``: ``"mp4"``, ``"gif"`` or ``"auto"`` (MP4 where imageio-ffmpeg is present);
    ``video_view``: ``"body"`` or ``"model"`` (box, six points, axes).
    ``progress(step_name)`` is called before each step (for a progress bar).
    ``control``: an :class:`inertia.control.studies.Showcase`, drawn as the section on holding the spin.
    """
    from .._core.atomic import write_text_atomic
    from ..dynamics.flip_study import flip_study
    from ..particles.models import six_point_model
    from . import plots
    from .display_mesh import display_mesh
    from .page import page_data, write_page

    step = progress or (lambda name: None)
    out = prepare_folder(out_dir, force=force)
    step("simulating the flip")
    study = flip_study(props.principal().moments)
    six = six_point_model(props)
    display = display_mesh(props, mesh)
    files: dict = {}
    info: dict = {}
    step("plotting")
    r = plots.omega_plot(study, out)
    files["omega"], info["omega"] = r["files"], r
    r = plots.invariants_plot(study, out)
    files["invariants"], info["invariants"] = r["files"], r
    files["polhodes"] = plots.polhode_plot(study, out)["files"]
    files["body"] = plots.body_plot(props, six, out, display=display)["files"]
    if video:
        step("animating")
        a = _animate(out, props, study, display, title, animation_format, video_view)
        files["animation"], files["poster"], info["animation"] = [a["file"]], [a["poster"]], a
    step("writing the 3D page")
    pdata = page_data(props, study, name=title, description=description, display=display)
    write_page(out / "body3d.html", pdata)
    files["page"] = ["body3d.html"]
    data = {"title": title, "mass": props.mass, "com": props.com, "inertia_com": props.inertia_com,
            "principal_moments": props.principal().moments, "R_body_principal": props.principal().R_body_principal,
            "omega0_body_principal": study.omega0_body, "flip_interval": study.flip_interval,
            "flip_times_marked": info["omega"]["flip_times"], "flips_detected": study.detected_flips,
            "integrators": info["invariants"]["max_errors"], "six_points_principal": pdata["six_points"],
            "display_mesh": None if display is None else {"faces": len(display.faces),
                                                          "source_faces": display.source_faces},
            "animation": info.get("animation")}
    write_text_atomic(out / "report.json", json.dumps(_plain(data), indent=2))
    files["data"] = ["report.json"]
    extra = ""
    if control is not None:
        from .animation import video_format
        from .control_report import write_control

        step("holding the spin")
        cfiles, extra = write_control(out, control, display, video=video, animation_format=video_format()
                                      if animation_format == "auto" else animation_format)
        files.update(cfiles)
    index = write_index(out, title=title, credit=credit, description=description, props=props, study=study,
                        files=files, info=info, extra=extra)
    return {"index": index, "files": files, "study": study, "info": info, "folder": out}


def _animate(out: Path, props, study, display, title: str, animation_format: str, view: str) -> dict:
    """The flip video (and its poster, the frame of the first flip) for the report."""
    from ..massprops.equivalent import equivalent_box
    from ..particles.models import six_point_model
    from .animation import FlipScene, render_flip, video_format

    fmt = video_format() if animation_format == "auto" else animation_format
    if fmt not in ("mp4", "gif"):
        raise InputError(f"animation format must be mp4, gif or auto, got {animation_format!r}")
    R = props.principal().R_body_principal
    six = (six_point_model(props).positions_body - props.com) @ R
    scene = FlipScene(study, display, six, np.asarray(equivalent_box(props).size) / 2, title)
    return render_flip(scene, out / f"flip.{fmt}", view=view, poster=out / "flip-poster.png")


def write_index(out: Path, *, title: str, credit: str | None, description: str, props, study, files: dict,
                info: dict, extra: str = "") -> Path:
    """``index.html`` linking every file of the report (``files``: role -> list of names)."""
    from .._core.atomic import write_text_atomic
    from .._core.version import __version__
    from .report_page import index_html

    lede = html.escape(description) if description else ""
    if credit:
        lede += f'<br><span style="font-size:.85rem">{html.escape(credit)}</span>'
    links = ", ".join(f'<a href="{n}">{n}</a>' for role in ("data", "omega", "polhodes", "invariants", "body")
                      for n in files.get(role, []) if n.endswith((".json", ".svg")))
    footer = (f"Written by inertia {__version__} (<code>inertia demo</code>). SI units inside; lengths shown in the "
              f"unit named beside them. Every number in this report: {links}.")
    text = index_html(name=title, lede=lede, props=props, study=study, files=files, info=info, footer=footer,
                      extra=extra)
    path = out / "index.html"
    write_text_atomic(path, text)
    return path


def linked_files(index_path) -> list[str]:
    """Every local file ``index.html`` links to (src/href), for checks."""
    import re

    text = Path(index_path).read_text(encoding="utf-8")
    return sorted({m for m in re.findall(r'(?:src|href)="([^"#:]+)"', text) if not m.startswith("http")})

