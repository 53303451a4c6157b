"""The report's ``index.html``: a header with the body and its key numbers, the flip video,
the interactive 3D page embedded, the plots in a grid with captions saying what to look at,
and the numbers in tables, every one with its unit.  Light and dark themes (the reader's
system setting, or the button), print-friendly (the video's poster and no 3D page on paper).
"""

from __future__ import annotations

import html
import math
from importlib.resources import files as package_files

import numpy as np

from .page import length_unit

#: what each plot shows and what to look at in it
CAPTIONS = {
    "omega": ("Body angular velocity",
              "The intermediate component \u03c9\u2082 reverses at each dashed line: every reversal is a flip, and the "
              "lines are the predicted times 2K(m)/\u03bb apart. \u03c9\u2081 and \u03c9\u2083 pulse only while "
              "the body turns over."),
    "polhodes": ("Polhodes on the angular-momentum sphere",
                 "Seen from the body, the tip of L runs on the sphere |L| = const. Near the minor or the major axis "
                 "the curves are small loops (a stable spin). This spin (dashed) follows the separatrix (purple) "
                 "from one end of the intermediate axis to the other: each crossing is a flip."),
    "invariants": ("What the integrators keep",
                   "Relative energy and |L| errors of two fixed-step integrators against the exact solution. The "
                   "splitting method keeps |L| to rounding and its energy error bounded; RK4 drifts slowly in both. "
                   "Errors below 10\u207b\u00b9\u2077 are drawn at 10\u207b\u00b9\u2077."),
    "body": ("The body and its models, to scale",
             "The body (shaded), its principal axes (red, green, blue for moments ascending), the six point masses "
             "and the equivalent uniform box, in the body frame. The six points sit at the centres of the box's "
             "faces."),
}


#: plots drawn wide (time on the horizontal axis): a whole row of the grid each
WIDE = ("omega", "invariants")


def sci(x: float, digits: int = 4) -> str:
    """``x`` in HTML with ``digits`` significant digits, as ``m &times; 10<sup>e</sup>`` when
    it is very small or large; no ``-0``."""
    x = float(x)
    if not math.isfinite(x):
        return "n/a"
    if x == 0:
        return "0"
    e = math.floor(math.log10(abs(x)))
    if -3 <= e < 4:
        text = f"{x:.{max(digits - 1 - e, 0)}f}"
        return text[1:] if text.startswith("-") and not text.strip("-0.") else text
    m = x / 10 ** e
    return f"{m:.{digits - 1}f} &times; 10<sup>{'&minus;' if e < 0 else ''}{abs(e)}</sup>"


def _exponent(values) -> int:
    """The power of ten of the largest magnitude (0 for all zeros)."""
    big = float(np.max(np.abs(values)))
    return math.floor(math.log10(big)) if big > 0 else 0


def _power(e: int) -> str:
    """``10^e`` in HTML (with a trailing space), or nothing for e = 0."""
    return f"10<sup>{'&minus;' if e < 0 else ''}{abs(e)}</sup> " if e else ""


def _clean(x: float, sig: int) -> str:
    """``sig`` significant digits for numbers near 1, fixed decimals otherwise; no ``-0``."""
    x = float(x)
    decimals = max(sig - 1 - (math.floor(math.log10(abs(x))) if x else 0), 0) if abs(x) >= 1 else sig - 1
    text = f"{x:.{decimals}f}"
    return text[1:] if text.startswith("-") and not text.strip("-0.") else text


def cards(props, study, box, unit_factor) -> str:
    """The header's key numbers."""
    unit, f = unit_factor
    m = props.mass
    mass = (f"{m * 1e3:.4g}", "g") if m < 1 else (f"{m:.4g}", "kg")
    moments = props.principal().moments
    e = math.floor(math.log10(float(moments.max())))
    items = [("mass", *mass),
             ("principal moments I\u2081, I\u2082, I\u2083",
              ", ".join(f"{x / 10 ** e:.3g}" for x in moments), f"&times; 10<sup>{e}</sup> kg m&sup2;".replace(
                  "<sup>-", "<sup>&minus;")),
             ("spin about the intermediate axis", f"{float(np.linalg.norm(study.omega0_body)):.3g}", "rad/s"),
             ("a flip every", f"{study.flip_interval:.4g}", "s (predicted, 2K(m)/&lambda;)"),
             ("equivalent box", " &times; ".join(f"{x * f:.3g}" for x in box.size), unit)]
    return "".join(f'<div class="card"><div class="k">{k}</div><div class="v">{v} <span class="u">{u}</span>'
                   "</div></div>" for k, v, u in items)


def _row(key: str, value: str) -> str:
    return f"<tr><th>{key}</th><td>{value}</td></tr>"


def properties_table(props, unit_factor) -> str:
    """Mass properties with units, body frame."""
    unit, f = unit_factor
    pf = props.principal()
    issues = props.check()
    validity = '<span class="ok">physical (triangle inequality holds)</span>' if not issues else \
        '<span class="bad">' + "; ".join(html.escape(v.message) for v in issues) + "</span>"
    e = _exponent(props.inertia_com)
    matrix = "".join("<tr>" + "".join(f"<td>{_clean(x / 10 ** e, 4)}</td>" for x in row) + "</tr>"
                     for row in props.inertia_com)
    axes = "".join(f"<tr><td>e<sub>{k + 1}</sub></td>" + "".join(f"<td>{_clean(x, 4)}</td>" for x in col)
                   + "</tr>" for k, col in enumerate(pf.R_body_principal.T))
    volume = f"{sci(props.volume)} m&sup3;" if props.volume == props.volume else "n/a (thin shell)"
    rows = [_row("mass", f"{sci(props.mass, 6)} kg"), _row("volume", volume),
            _row("center of mass", f"({', '.join(_clean(x * f, 4) for x in props.com)}) {unit}, body frame"),
            _row(f"inertia tensor about the center of mass [{_power(e)}kg m&sup2;], body axes, products negated "
                 "(L = I&omega;)", f'<table class="matrix">{matrix}</table>'),
            _row("principal moments I<sub>1</sub> &le; I<sub>2</sub> &le; I<sub>3</sub>",
                 ", ".join(_clean(x / 10 ** e, 4) for x in pf.moments) + f" &times; {_power(e)}kg m&sup2;"),
            _row("principal axes (unit vectors, body frame)", f'<table class="matrix">{axes}</table>'),
            _row("validity", validity)]
    return '<div class="card"><h3>Mass properties</h3><table>' + "".join(rows) + "</table></div>"


def flip_table(study) -> str:
    """Predicted and found flips, and what each integrator keeps."""
    w = study.omega0_body
    found = study.detected_flips
    predicted = study.flip_times[: len(found)]
    rows = [_row("spin &omega;<sub>0</sub> (principal axes 1, 2, 3)", f"({', '.join(sci(x, 3) for x in w)}) rad/s"),
            _row("predicted flip interval 2K(m)/&lambda;", f"{study.flip_interval:.6g} s"),
            _row("predicted flips", ", ".join(f"{x:.4f}" for x in predicted) + " s"),
            _row("flips found in the exact motion", ", ".join(f"{x:.4f}" for x in found) + " s")]
    head = ("<tr><th>integrator</th><th class=n>h [s]</th><th class=n>max |&Delta;E/E|</th>"
            "<th class=n>max |&Delta;|L||/|L|</th><th class=n>max attitude error [rad]</th></tr>")
    body = "".join(f"<tr><td>{html.escape(name)}</td><td class=n>{tr['h']:.3g}</td>"
                   f"<td class=n>{tr['energy_error'].max():.1e}</td><td class=n>{tr['momentum_error'].max():.1e}</td>"
                   f"<td class=n>{tr['attitude_error'].max():.1e}</td></tr>" for name, tr in study.integrators.items())
    return ('<div class="card"><h3>The flip</h3><table>' + "".join(rows) + "</table>"
            '<h3 style="margin-top:1rem">Integrators against the exact solution</h3>'
            f"<table>{head}{body}</table></div>")


def figure(role: str, names) -> str:
    png, svg = names
    title, text = CAPTIONS[role]
    wide = ' class="wide"' if role in WIDE else ""
    return (f'<figure{wide}><img src="{png}" alt="{html.escape(title)}"><figcaption><b>{title}</b>'
            f'{html.escape(text)} <span class="files">(<a href="{svg}">SVG</a>)</span></figcaption></figure>')


def video_section(anim: dict, poster: str | None) -> str:
    name = anim["file"]
    what = "the body" if anim.get("view") == "body" else "the equivalent box, the six point masses and the axes"
    speed = "in real time" if abs(anim.get("speed", 1) - 1) < 1e-6 else f"at {anim['speed']:.3g}&times; real time"
    poster_attr = f' poster="{poster}"' if poster else ""
    media = (f'<video src="{name}"{poster_attr} controls autoplay loop muted playsinline></video>'
             if name.endswith(".mp4") else f'<img src="{name}" alt="the flip, animated">')
    still = f'<img class="poster" src="{poster}" alt="the body at its first flip">' if poster else ""
    return f"""<section id="flip"><h2>The flip</h2><div class="flip"><div>{media}{still}</div>
<div class="aside"><p>The video shows {what} spinning about its intermediate axis, {speed}: {anim['frames']} frames,
{anim['fps']:.3g} fps, {anim['duration_s']:.3g} s, {anim['width']}&times;{anim['height']} px. Every frame is the exact
torque-free solution at its time; nothing is integrated.</p>
<p>The <b>amber arrow</b> is the angular momentum L: it stays fixed in space while the body turns over, again and
again. The strip below the body plots the body angular velocity,
<span style="color:#d9534f">&omega;<sub>1</sub></span>, <span style="color:#3aa76d">&omega;<sub>2</sub></span>,
<span style="color:#3b82f6">&omega;<sub>3</sub></span> [rad/s]; the dashed lines are the predicted flips, and the
banner names each one as it happens.</p></div></div></section>"""


def page_section(page: str) -> str:
    return f"""<section id="turn" class="noprint"><h2>Turn it yourself</h2>
<p>Drag to turn, scroll to zoom, right-drag to pan. Switch between the body, its equivalent box and ellipsoid, and its
six- and four-point models; play the motion and watch the polhode beside it. <a href="{page}">Open the 3D page on its
own</a>.</p><iframe src="{page}" title="interactive 3D view of the body"></iframe></section>"""


def index_html(*, name: str, lede: str, props, study, files: dict, info: dict, footer: str, extra: str = "") -> str:
    """The whole ``index.html``; ``extra``: more sections (HTML) before the numbers."""
    from ..massprops.equivalent import equivalent_box

    unit_factor = length_unit(float(np.linalg.norm(equivalent_box(props).size)))
    sections = []
    if "animation" in files:
        poster = files.get("poster", [None])[0]
        sections.append(video_section(info["animation"], poster))
    if "page" in files:
        sections.append(page_section(files["page"][0]))
    figs = "".join(figure(role, files[role]) for role in ("omega", "polhodes", "body", "invariants") if role in files)
    sections.append(f'<section id="plots"><h2>Plots</h2><div class="grid">{figs}</div></section>')
    if extra:
        sections.append(extra)
    sections.append('<section id="numbers"><h2>The numbers</h2><div class="tables">'
                    f"{properties_table(props, unit_factor)}{flip_table(study)}</div></section>")
    template = package_files("inertia.viz").joinpath("templates", "report.html").read_text(encoding="utf-8")
    cards_html = cards(props, study, equivalent_box(props), unit_factor)
    for key, value in (("__TITLE__", html.escape(f"{name}: inertia report")), ("__NAME__", html.escape(name)),
                       ("__LEDE__", lede), ("__CARDS__", cards_html), ("__SECTIONS__", "\n".join(sections)),
                       ("__FOOTER__", footer)):
        template = template.replace(key, value)
    return template
