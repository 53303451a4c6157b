"""The interactive 3D page: one self-contained HTML file that works offline.

three.js (vendored, MIT, see ``vendor/README.md``) is inlined through an import map whose
entry is a ``data:`` URL, so the page loads nothing from a network and opens from a
``file://`` URL.  The numbers are embedded as JSON (``<script id="inertia-data">``): the
six points are recomputed in the page from the slider values with the library's formula
``d_i^2 = 3/(2M) (I_j + I_k - I_i)``, and ``window.inertiaState`` exposes what the page
shows (points, validity, frame, attitude) for tests and curious users.
"""

from __future__ import annotations

import base64
import json
from importlib.resources import files

import numpy as np

#: largest mesh (faces) embedded in the page; larger bodies are shown by their equivalent box
MAX_PAGE_FACES = 20_000


def three_js_data_url() -> str:
    src = files("inertia.viz").joinpath("vendor", "three.module.min.js").read_bytes()
    return "data:text/javascript;base64," + base64.b64encode(src).decode("ascii")


def page_data(props, study, *, name: str, mesh=None, n_frames: int = 240) -> dict:
    """The JSON the page embeds; every position in the principal frame (COM at the origin)."""
    from ..dynamics.exact import exact_solution
    from ..massprops.equivalent import equivalent_box
    from ..particles.models import six_point_model

    cf = props.canonical()
    R = cf.R_body_principal
    six = six_point_model(props)
    six_principal = (six.positions_body - props.com) @ R
    t = np.linspace(study.t[0], study.t[-1], n_frames)
    q, _ = exact_solution(study.moments, study.omega0_body, t)
    data = {
        "name": name,
        "mass": float(props.mass),
        "moments": [float(x) for x in cf.moments],
        "six_points": six_principal.tolist(),
        "box_size": [float(x) for x in equivalent_box(props).size],
        "scale": float(max(np.abs(six_principal).max(), 1e-12)),
        "flip_interval": float(study.flip_interval),
        "L_direction": (study.L_world / np.linalg.norm(study.L_world)).tolist(),
        "trajectory": {"t": [round(float(x), 6) for x in t], "q": np.round(q, 7).tolist()},
        "mesh": None,
    }
    if mesh is not None and len(mesh[1]) <= MAX_PAGE_FACES:
        vertices, faces = mesh
        data["mesh"] = {"vertices": np.round((np.asarray(vertices) - props.com) @ R, 7).tolist(),
                        "faces": np.asarray(faces).tolist()}
    return data


def write_page(path, data: dict) -> None:
    """Write the self-contained page atomically."""
    from .._core.atomic import write_text_atomic

    template = files("inertia.viz").joinpath("templates", "page.html").read_text(encoding="utf-8")
    payload = json.dumps(data, separators=(",", ":")).replace("</", "<\\/")  # no early </script>
    html = template.replace("__DATA__", payload).replace("__THREE_URL__", three_js_data_url())
    write_text_atomic(path, html)
