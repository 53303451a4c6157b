"""The interactive 3D page: one self-contained HTML file that works offline.

three.js and its OrbitControls (vendored, MIT, see ``vendor/README.md``) are inlined through
an import map whose entries are ``data:`` URLs, so the page loads nothing from a network and
opens from a ``file://`` URL.  The numbers are embedded as JSON (``<script
id="inertia-data">``).  The page shows the body (or its equivalent box, ellipsoid, six or
four point masses) turning by the exact solution, the angular momentum fixed in space, and
beside it the polhode on the momentum sphere with the current point.  The models are
recomputed in the page from the slider values with the library's formulas (second moments
``s_i = (I_j + I_k - I_i)/2``: six points at ``+-sqrt(3 s_i/M)``, box half-edges the same,
ellipsoid semi-axes ``sqrt(5 s_i/M)``, four points at ``sigma_k sqrt(s_i/M)``), and
``window.inertiaState`` exposes what the page shows (points, validity, frame, attitude,
camera, mode) for tests and curious users.
"""

from __future__ import annotations

import base64
import html
import json
from importlib.resources import files

import numpy as np


def vendor_bytes(name: str) -> bytes:
    return files("inertia.viz").joinpath("vendor", name).read_bytes()


def data_url(name: str, mime: str = "text/javascript") -> str:
    """A vendored file as a ``data:`` URL."""
    return f"data:{mime};base64," + base64.b64encode(vendor_bytes(name)).decode("ascii")


def length_unit(scale_m: float) -> tuple[str, float]:
    """The unit lengths are shown in on a page: mm below half a metre, else m; (name, factor)."""
    return ("mm", 1e3) if scale_m < 0.5 else ("m", 1.0)


def page_data(props, study, *, name: str, description: str = "", display=None, n_frames: int = 480) -> dict:
    """The JSON the page embeds; positions in the principal frame (COM at the origin) unless
    named ``_body``.  ``display``: a :class:`~.display_mesh.DisplayMesh` or None."""
    from ..dynamics.exact import exact_solution
    from ..massprops.equivalent import equivalent_box, equivalent_ellipsoid
    from ..particles.models import four_point_model, six_point_model
    from . import polhodes
    from .raster import Camera

    pf = props.principal()
    R = pf.R_body_principal
    six_principal = (six_point_model(props).positions_body - props.com) @ R
    four_principal = (four_point_model(props).positions_body - props.com) @ R
    box = equivalent_box(props)
    radius = max(float(np.linalg.norm(box.size) / 2), display.radius if display is not None else 0.0)
    t = np.linspace(study.t[0], study.t[-1], n_frames)
    q, w = exact_solution(study.moments, study.omega0_body, t)
    m = w * study.moments
    L = study.L_world / np.linalg.norm(study.L_world)
    unit, factor = length_unit(radius)
    r6 = lambda a: np.round(np.asarray(a, float), 6).tolist()  # noqa: E731 - 1e-6 of the unit sphere
    data = {
        "name": name, "description": description,
        "mass": float(props.mass), "com_body": props.com.tolist(), "R_body_principal": R.tolist(),
        "moments": [float(x) for x in pf.moments],
        "six_points": six_principal.tolist(), "four_points": four_principal.tolist(),
        "box_size": [float(x) for x in box.size],
        "ellipsoid_semi_axes": [float(x) for x in equivalent_ellipsoid(props).dims],
        "scale": float(max(np.abs(six_principal).max(), 1e-12)), "radius": radius,
        "length_unit": unit, "length_factor": factor,
        "flip_interval": float(study.flip_interval),
        "flip_times": [float(x) for x in study.flip_times],
        "spin": [float(x) for x in study.omega0_body],
        "L_direction": L.tolist(), "L_norm": float(np.linalg.norm(study.L_world)),
        "camera_toward": Camera.looking_at_origin(L, center=(0, 0), scale=1.0).toward.tolist(),
        "trajectory": {"t": [round(float(x), 6) for x in t], "q": np.round(q, 7).tolist(),
                       "m": r6(m / np.linalg.norm(m, axis=1, keepdims=True))},
        "polhodes": {"fan": [r6(c[::2]) for c in polhodes.fan(study.moments)],
                     "separatrix": [r6(c[::2]) for c in polhodes.separatrix(study.moments)],
                     "path": r6(polhodes.path(study)[::2])},
        "mesh": None,
    }
    if display is not None:
        data["mesh"] = {"vertices": np.round(display.vertices, 7).tolist(), "faces": display.faces.tolist(),
                        "part": display.part.tolist(), "source_faces": display.source_faces,
                        "note": display.note()}
    return data


def write_page(path, data: dict) -> None:
    """Write the self-contained page atomically."""
    from .._core.atomic import write_text_atomic

    template = files("inertia.viz").joinpath("templates", "page.html").read_text(encoding="utf-8")
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")  # no early </script>
    imports = json.dumps({"imports": {"three": data_url("three.module.min.js"),
                                      "three/addons/OrbitControls.js": data_url("OrbitControls.js")}})
    title = html.escape(f"{data['name']}: inertia in 3D")
    write_text_atomic(path, template.replace("__DATA__", payload).replace("__IMPORTMAP__", imports)
                      .replace("__TITLE__", title))
