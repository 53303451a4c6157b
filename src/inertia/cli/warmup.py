"""``inertia warm-up``: compile every numba kernel into numba's cache ahead of use, then
build the ahead-of-time library of the mesh kernels (:mod:`inertia._core.aot`).

Also started in the background (``python -m inertia.cli.warmup``: detached, at low priority,
silent) by :mod:`inertia._core.compiled` when a call finds a kernel's cache cold (a fresh
install), so that no call waits for the compiler.  It runs the library's own entry points on
tiny inputs with ``INERTIA_COMPILED=always``, so every kernel is compiled with the argument
types real calls use.  A kernel it did not compile is compiled on first use, as before.
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


def _torus(nu: int = 12, nv: int = 8):
    """A closed torus grid (not star-shaped: the self-crossing search runs on it)."""
    import numpy as np

    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False), np.linspace(0, 2 * np.pi, nv, endpoint=False),
                       indexing="ij")
    v = np.stack([(3 + np.cos(w)) * np.cos(u), (3 + np.cos(w)) * np.sin(u), np.sin(w)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a, b = i * nv + j, ((i + 1) % nu) * nv + j
    c, d = ((i + 1) % nu) * nv + (j + 1) % nv, i * nv + (j + 1) % nv
    return v, np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])


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

    from ..geometry import check_mesh
    from ..massprops.mesh import mesh_file_properties, mesh_properties

    tet_v, tet_f, soup_v, soup_f = _meshes()
    yield lambda: check_mesh(tet_v, tet_f[:3])                              # the full analysis
    yield lambda: check_mesh(np.vstack([tet_v, tet_v * 0.3 + 0.1]),          # nesting: winding numbers
                             np.vstack([tet_f, tet_f[:, ::-1] + 4]))
    yield lambda: mesh_properties(tet_v, tet_f, density=1.0, shell=True)
    yield lambda: mesh_properties(*_torus(), density=1.0)                     # the self-crossing search
    yield lambda: mesh_properties(tet_v, tet_f[:3], density=1.0, robust=True)  # the robust path
    with tempfile.TemporaryDirectory() as tmp:
        for path in _files(Path(tmp), tet_v, tet_f):
            yield lambda path=path: mesh_file_properties(path, density=1.0)
    yield lambda: mesh_properties(soup_v, soup_f, density=1.0)       # weld, then the clean check
    yield lambda: mesh_properties(tet_v, tet_f, density=1.0)


HELP = "compile the numba kernels ahead of use (about half a minute, once per install)"
DESCRIPTION = ("Compile every compiled kernel into numba's cache now, so that no later call waits for the "
               "compiler, then build the mesh kernels into a library in the user's cache folder, which a "
               "process loads without importing numba (needs a C compiler; without one numba serves).  "
               "The first call after an install starts this in the background by itself; run it by hand "
               "to have it done before you start.")
EPILOG = """\
examples:
  inertia warm-up

exit status: 0 (a kernel that could not be compiled now is compiled on first use)."""


def register(sub) -> None:
    from . import _format as fmt

    p = fmt.add_command(sub, "warm-up", HELP, DESCRIPTION, EPILOG)
    p.set_defaults(func=run)


def run(args) -> int:
    import time

    t0 = time.perf_counter()
    library = main(background=False)
    from ._format import emit

    emit(f"compiled kernels ready in {time.perf_counter() - t0:.1f} s")
    emit(library)
    return 0


def main(background: bool = True) -> str:
    """Compile every kernel into numba's cache, then build the ahead-of-time library; returns
    what became of the library (a sentence)."""
    os.environ["INERTIA_COMPILED"] = "always"
    if background:
        try:
            os.nice(10)
        except (AttributeError, OSError):
            pass
    try:
        import warnings

        for step in _steps():
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")   # the steps' meshes are defective on purpose
                    step()
            except Exception:      # a step that fails leaves its kernels to compile on first use
                pass
        return build_library(force=not background)
    finally:
        lock = os.environ.get("INERTIA_WARMUP_LOCK")
        if lock:
            try:
                os.unlink(lock)
            except OSError:
                pass
    return 0


def build_library(force: bool = False):
    """Build the ahead-of-time library of the mesh kernels (:mod:`inertia._core.aot`) when it
    is missing or stale (``force``: also after a failed attempt); returns what happened, as
    a sentence."""
    from .._core import aot
    from ..geometry import aot_library

    if aot.load() is not None:
        return f"ahead-of-time kernels up to date ({aot.library_path()})"
    if not force and not aot.wanted():
        return "ahead-of-time kernels: an earlier build failed for these sources (numba serves)"
    try:
        path = aot_library.build()
    except Exception as exc:  # noqa: BLE001 - no compiler, no setuptools: numba serves
        return f"ahead-of-time kernels not built ({type(exc).__name__}: {exc}); numba serves"
    return f"ahead-of-time kernels built: {path}"


if __name__ == "__main__":
    main()
    sys.exit(0)
