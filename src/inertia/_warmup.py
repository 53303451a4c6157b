"""Compile every numba kernel into numba's cache: ``python -m inertia._warmup``.

Started in the background, detached and at low priority, by :mod:`inertia._core.compiled` when
a call finds a kernel's cache cold (a fresh install), so that no call waits for the compiler.
It runs the library's own entry points on tiny inputs with ``INERTIA_COMPILED=always``, so every
kernel is compiled with the argument types real calls use.  Run it by hand after installing to
compile ahead (about half a minute).  It prints nothing and never fails loudly: a kernel it did
not compile is compiled on first use, as before.
"""

from __future__ import annotations

import os
import sys
import tempfile
from pathlib import Path


def _meshes():
    import numpy as np

    tet_v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    tet_f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]], dtype=np.int64)
    soup_v = tet_v[tet_f].reshape(-1, 3)
    soup_f = np.arange(12, dtype=np.int64).reshape(4, 3)
    return tet_v, tet_f, soup_v, soup_f


def _files(folder: Path, tet_v, tet_f):
    """A tiny binary STL, ASCII STL and OBJ of the tetrahedron."""
    import numpy as np

    rec = np.zeros(len(tet_f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = tet_v[tet_f]
    (folder / "t.stl").write_bytes(b"warmup".ljust(80) + len(tet_f).to_bytes(4, "little") + rec.tobytes())
    facets = "".join("facet normal 0 0 0\n outer loop\n" + "".join(f"  vertex {x} {y} {z}\n" for x, y, z in tri)
                     + " endloop\nendfacet\n" for tri in tet_v[tet_f])
    (folder / "a.stl").write_text(f"solid t\n{facets}endsolid t\n")
    (folder / "t.obj").write_text("".join(f"v {x} {y} {z}\n" for x, y, z in tet_v)
                                  + "".join(f"f {a + 1} {b + 1} {c + 1}\n" for a, b, c in tet_f))
    return [folder / "t.stl", folder / "a.stl", folder / "t.obj"]


def _steps():
    """Each step exercises a path; the probes' kernels (clean_solid, solid_sums) come last."""
    import numpy as np

    import inertia
    from inertia.geometry import check_mesh

    tet_v, tet_f, soup_v, soup_f = _meshes()
    yield lambda: check_mesh(tet_v, tet_f[:3])                              # the full analysis
    yield lambda: check_mesh(np.vstack([tet_v, tet_v * 0.3 + 0.1]),          # nesting: winding numbers
                             np.vstack([tet_f, tet_f[:, ::-1] + 4]))
    yield lambda: inertia.mesh_properties(tet_v, tet_f, density=1.0, shell=True)
    with tempfile.TemporaryDirectory() as tmp:
        for path in _files(Path(tmp), tet_v, tet_f):
            yield lambda path=path: inertia.mesh_file_properties(path, density=1.0)
    yield lambda: inertia.mesh_properties(soup_v, soup_f, density=1.0)       # weld, then the clean check
    yield lambda: inertia.mesh_properties(tet_v, tet_f, density=1.0)


def main() -> int:
    os.environ["INERTIA_COMPILED"] = "always"
    try:
        os.nice(10)
    except (AttributeError, OSError):
        pass
    try:
        for step in _steps():
            try:
                step()
            except Exception:      # a step that fails leaves its kernels to compile on first use
                pass
    finally:
        lock = os.environ.get("INERTIA_WARMUP_LOCK")
        if lock:
            try:
                os.unlink(lock)
            except OSError:
                pass
    return 0


if __name__ == "__main__":
    sys.exit(main())
