"""The rule that picks the compiled kernels or their NumPy twins (inertia._core.compiled), run
in fresh processes with INERTIA_COMPILED=auto (the suite itself runs with ``always``):

* a small job in a process without numba stays on the NumPy path and never imports numba;
* a cold cache (an empty NUMBA_CACHE_DIR) never makes the caller compile: the NumPy path runs
  and the background warm-up is started;
* a warm cache runs the compiled kernel;
and in every case the numbers equal the compiled ones to rounding."""

from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest


def _sphere(n: int):
    """A closed UV sphere: n rings of 2n quads between the poles (triangulated), radius 1."""
    theta = np.linspace(0, np.pi, n + 1)[1:-1]
    phi = np.linspace(0, 2 * np.pi, 2 * n, endpoint=False)
    ring = np.stack([np.outer(np.sin(theta), np.cos(phi)), np.outer(np.sin(theta), np.sin(phi)),
                     np.outer(np.cos(theta), np.ones_like(phi))], axis=-1).reshape(-1, 3)
    v = np.vstack([[0, 0, 1], ring, [0, 0, -1]])
    m = 2 * n
    faces = [[0, 1 + (j + 1) % m, 1 + j] for j in range(m)]
    for i in range(n - 2):
        for j in range(m):
            a, b = 1 + i * m + j, 1 + i * m + (j + 1) % m
            c, d = a + m, b + m
            faces += [[a, b, d], [a, d, c]]
    last = len(v) - 1
    base = 1 + (n - 2) * m
    faces += [[last, base + j, base + (j + 1) % m] for j in range(m)]
    return v, np.array(faces, dtype=np.int64)[:, ::-1].copy()   # outward


def _run(tmp_path, n: int, *, pre: str = "", env: dict | None = None) -> dict:
    code = (
        "import json, sys\nimport numpy as np\n" + pre + "\nimport inertia\nfrom inertia._core import compiled\n"
        "started = []\ncompiled.start_warmup = lambda: started.append(1) or True\n"
        f"sys.path.insert(0, {str(os.path.dirname(__file__))!r})\nfrom test_compiled import _sphere\n"
        f"v, f = _sphere({n})\np = inertia.mesh_properties(v, f, density=1.0)\n"
        "mod = sys.modules.get('inertia.geometry._solid_numba')\n"
        "print(json.dumps({'mass': p.mass, 'inertia': p.inertia_com.tolist(), 'numba': 'numba' in sys.modules,\n"
        "                  'started': bool(started), 'compiled': bool(mod and mod.clean_solid.signatures)}))\n")
    # a cache folder of its own: no ahead-of-time library (inertia._core.aot) unless the test puts one
    full_env = {**os.environ, "INERTIA_COMPILED": "auto", "INERTIA_CACHE_DIR": str(tmp_path / "cache"), **(env or {})}
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=full_env, timeout=300,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    return json.loads(out.stdout.strip().splitlines()[-1])


def _reference(n: int):
    import inertia

    v, f = _sphere(n)
    return inertia.mesh_properties(v, f, density=1.0)


def test_small_job_stays_on_numpy_and_never_imports_numba(tmp_path):
    got = _run(tmp_path, 12)
    assert not got["numba"] and not got["compiled"] and not got["started"]
    ref = _reference(12)                        # compiled (the suite runs with INERTIA_COMPILED=always)
    assert got["mass"] == pytest.approx(ref.mass, rel=1e-13)
    np.testing.assert_allclose(got["inertia"], ref.inertia_com, rtol=1e-12, atol=1e-15)
    # and the mass is the closed form of the inscribed polyhedron's volume, not a sphere's: a sanity
    assert 0.9 * 4 / 3 * np.pi < got["mass"] < 4 / 3 * np.pi


def test_never_keeps_everything_on_numpy_even_for_large_jobs(tmp_path):
    got = _run(tmp_path, 60, pre="import numba", env={"INERTIA_COMPILED": "never"})
    assert not got["compiled"] and not got["started"]
    assert got["mass"] == pytest.approx(_reference(60).mass, rel=1e-13)
