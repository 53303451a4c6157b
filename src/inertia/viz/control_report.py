"""The report's section on holding the spin (``inertia demo --control``): the side-by-side video,
the plots and the numbers of :func:`inertia.control.studies.showcase`, in the report's own styles."""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

#: what each figure shows and what to look at in it
CAPTIONS = {
    "passive": ("A constant wheel momentum along the spin axis",
                "Each point is a 60 s (spacecraft: longer) run from a wobble of 10\u207b\u00b3 of the spin rate, its "
                "largest tilt plotted. Below the dual-spin threshold h_min = (I\u2083 \u2212 I\u2082)\u03a9 the spin "
                "departs; above it, it holds. Dotted: where the simulation puts the threshold."),
    "monte_carlo": ("Monte Carlo: controllers designed on wrong models",
                    "Every run's controller was designed on a model whose principal moments are off by up to 20 % "
                    "each and whose principal axes are turned by up to 5 degrees; the body is the true one. The "
                    "histogram is each run's largest tilt after settling; red bars would be failures."),
    "active": ("{name}: held and free",
               "Top: the tilt of the spin axis from the angular momentum, with the LQR (blue) and with the wheels "
               "idle (red, the flip). Below: the three wheels' momenta and torques against their limits (dashed)."),
}


def _slug(name: str) -> str:
    return "".join(c if c.isalnum() else "-" for c in name.lower()).strip("-")


def _figure(names, title: str, text: str, wide: bool = True) -> str:
    png, svg = names
    cls = ' class="wide"' if wide else ""
    return (f'<figure{cls}><img src="{png}" alt="{html.escape(title)}"><figcaption><b>{html.escape(title)}</b>'
            f'{html.escape(text)} <span class="files">(<a href="{svg}">SVG</a>)</span></figcaption></figure>')


def _row(cells, head=False) -> str:
    tag = "th" if head else "td"
    return "<tr>" + "".join(f"<{tag}{' class=n' if k else ''}>{c}</{tag}>" for k, c in enumerate(cells)) + "</tr>"


def tables(sc) -> str:
    """The numbers: the threshold, the hold, the Monte Carlo, per body."""
    rows_p = [_row(["body", "h<sub>min</sub> formula [N m s]", "simulated [N m s]", "difference"], True)]
    rows_a = [_row(["body", "capture [s]", "largest tilt after settling [deg]", "largest torque / limit",
                    "largest wheel momentum / limit"], True)]
    rows_m = [_row(["body", "runs held", "median / 99th pct / worst tilt [deg]", "designs [s]", "runs [s]"], True)]
    for name in sc.setups:
        p, a, m = sc.passive[name], sc.active[name], sc.monte_carlo[name]
        g = a.setup.gyrostat
        rows_p.append(_row([html.escape(name), f"{p.h_min:.5g}", f"{p.h_threshold:.5g}",
                            f"{100 * p.threshold_error:+.2f} %"]))
        rows_a.append(_row([html.escape(name), f"{a.capture_time:.3g}", f"{np.degrees(a.max_tilt_after_settle):.2e}",
                            f"{np.abs(a.torque).max() / g.max_torque.max():.2f}",
                            f"{np.abs(a.held[:, 13:]).max() / g.max_momentum.max():.2f}"]))
        q = np.degrees(np.percentile(m.max_tilt, [50, 99, 100]))
        rows_m.append(_row([html.escape(name), f"{m.success.sum()} of {m.success.size} ({m.success_rate:.1%})",
                            " / ".join(f"{x:.2e}" for x in q), f"{m.design_seconds:.2f}", f"{m.rollout_seconds:.2f}"]))
    card = '<div class="card"><h3>{}</h3><table>{}</table></div>'
    return ('<div class="tables">' + card.format("Dual-spin threshold", "".join(rows_p))
            + card.format("Active hold (LQR on three wheels)", "".join(rows_a))
            + card.format("Monte Carlo", "".join(rows_m)) + "</div>")


def setups_text(sc) -> str:
    parts = []
    for name, st in sc.setups.items():
        g = st.gyrostat
        parts.append(f"<b>{html.escape(name)}</b>: {st.spin_rate:g} rad/s about its intermediate axis, three wheels "
                     f"({g.max_torque.max():g} N m, {g.max_momentum.max():g} N m s each), torques every "
                     f"{1e3 * st.period:g} ms, {st.duration:g} s runs, judged from {st.settle:g} s: the spin axis "
                     f"must stay within {np.degrees(st.max_tilt):g} degree of the angular momentum.")
    return " ".join(parts)


def write_control(out: Path, sc, mesh, *, video: bool = True, animation_format: str = "mp4") -> tuple[dict, str]:
    """Write the section's files into ``out``; returns ``(files by role, section HTML)``."""
    from .._core.atomic import write_text_atomic
    from .control_animation import render_hold
    from .control_plots import active_plot, monte_carlo_plot, passive_plot

    out = Path(out)
    files = {"control-passive": passive_plot(sc.passive, out)["files"],
             "control-monte-carlo": monte_carlo_plot(sc.monte_carlo, out)["files"]}
    figs = [_figure(files["control-passive"], *CAPTIONS["passive"])]
    for name, run in sc.active.items():
        stem = f"control-{_slug(name)}"
        files[stem] = active_plot(run, out, stem)["files"]
        title, text = CAPTIONS["active"]
        figs.append(_figure(files[stem], title.format(name=name), text, wide=False))
    figs.append(_figure(files["control-monte-carlo"], *CAPTIONS["monte_carlo"]))
    media = ""
    first = next(iter(sc.active.values()))
    if video and mesh is not None:
        info = render_hold(first, mesh, out / f"control.{animation_format}", poster=out / "control-poster.png")
        files["control-video"], files["control-poster"] = [info["file"]], [info["poster"]]
        name = info["file"]
        media = (f'<video src="{name}" poster="control-poster.png" controls autoplay loop muted playsinline></video>'
                 if name.endswith(".mp4") else f'<img src="{name}" alt="held and free, side by side">')
        media += '<img class="poster" src="control-poster.png" alt="held and free, side by side">'
    data = {name: {"h_min": sc.passive[name].h_min, "h_threshold_simulated": sc.passive[name].h_threshold,
                   "capture_time_s": sc.active[name].capture_time,
                   "max_tilt_after_settle_rad": sc.active[name].max_tilt_after_settle,
                   "monte_carlo_success_rate": sc.monte_carlo[name].success_rate,
                   "monte_carlo_max_tilt_rad": sc.monte_carlo[name].max_tilt.tolist()} for name in sc.setups}
    write_text_atomic(out / "control.json", json.dumps(data, indent=1))
    files["control-data"] = ["control.json"]
    aside = ("<p>A spin about the intermediate axis is unstable: left, the wheels idle and the body turns over and "
             "back. Right, the same body from the same state with three reaction wheels driven by a discrete LQR "
             "designed on the gyrostat's own error-state Jacobians: the spin axis goes onto the angular momentum "
             "(amber, fixed in space) and stays. The strip plots both tilts on a log scale.</p>"
             f"<p>{setups_text(sc)}</p>")
    head = f'<div class="flip"><div>{media}</div><div class="aside">{aside}</div></div>' if media else \
        f'<div class="aside">{aside}</div>'
    section = (f'<section id="control"><h2>Holding the spin with reaction wheels</h2>{head}'
               f'<div class="grid" style="margin-top:1rem">{"".join(figs)}</div>'
               f'<div style="margin-top:1rem">{tables(sc)}</div></section>')
    return files, section
