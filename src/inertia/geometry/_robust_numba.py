"""Numba-compiled twins of :mod:`._robust_kernels` (optional; imports numba at its top).

Only :mod:`inertia.geometry.robust` imports this module, lazily, and falls back to the
plain-Python kernels when numba is missing.  The kernels are compiled from the very same
source text: it is executed once more into a private namespace (compiled under the kernel
file's own name, so numba's on-disk cache can locate it) and every function there is
replaced by its ``numba.njit`` version before any is called, so that the compiled
functions call each other.  Both backends therefore make the same decisions.
"""

from __future__ import annotations

import types

import numba as nb

from . import _robust_kernels as _k

_JIT = {"cache": True, "nogil": True, "boundscheck": False}


def _compiled_namespace():
    path = _k.__file__
    with open(path, encoding="utf-8") as fh:
        code = compile(fh.read(), path, "exec")
    ns = {"__name__": __name__, "__file__": path}
    exec(code, ns)  # noqa: S102 (our own kernel file, see the module docstring)
    for name, obj in list(ns.items()):
        if isinstance(obj, types.FunctionType) and obj.__module__ == ns["__name__"]:
            ns[name] = nb.njit(**_JIT)(obj)
    return ns


_NS = _compiled_namespace()
winding_rest = _NS["winding_rest"]
grid_pairs = _NS["grid_pairs"]
crossing_windings = _NS["crossing_windings"]
pieces_clean = _NS["pieces_clean"]
