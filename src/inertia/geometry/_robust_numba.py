"""Numba-compiled twins of :mod:`._robust_kernels`, :mod:`._robust_topo` and :mod:`._robust_capk`
(optional; imports numba at its top).

Only :mod:`inertia.geometry.robust` imports this module, lazily, and falls back to the
plain-Python kernels when numba is missing.  The kernels are compiled from the very same
source text: each kernel file is executed once more into one private namespace (compiled
under the file's own name, so numba's on-disk cache can locate it) and every function there
is replaced by its ``numba.njit`` version before any is called, so that the compiled
functions call each other (a helper one file imports from another is rebuilt over the
namespace, so it calls the compiled kernels too).  Both backends therefore make the same
decisions.  A kernel
that loops with ``prange`` (its iterations are independent: each writes its own slots) is
also compiled with ``parallel=True``; that version runs when the loop is long and a core
is idle.
"""

from __future__ import annotations

import os
import types

import numba as nb
import numpy as np

from . import _robust_capk, _robust_clip, _robust_kernels, _robust_topo

_MODULES = (_robust_topo, _robust_kernels, _robust_capk, _robust_clip)
_JIT = {"cache": True, "nogil": True, "boundscheck": False}


def _compiled_namespace():
    ns = {"__name__": __name__}
    for mod in _MODULES:
        path = mod.__file__
        with open(path, encoding="utf-8") as fh:
            code = compile(fh.read(), path, "exec")
        ns["__file__"] = path
        exec(code, ns)  # noqa: S102 (our own kernel files, see the module docstring)
    ns["prange"] = nb.prange
    ours = {ns["__name__"]} | {mod.__name__ for mod in _MODULES}
    exported = {}
    for name, obj in list(ns.items()):
        if isinstance(obj, types.FunctionType) and obj.__module__ in ours:
            # a helper one kernel file imports from another is rebuilt over this namespace
            fn = types.FunctionType(obj.__code__, ns, obj.__name__, obj.__defaults__)
            ns[name] = nb.njit(**_JIT)(fn)
            if "prange" in obj.__code__.co_names:
                exported[name] = _by_size(nb.njit(parallel=True, **_JIT)(fn), ns[name])
    return ns, exported


def _by_size(parallel, serial):
    """Run ``parallel`` when the first array argument has at least PARALLEL_FROM rows and a
    core is idle, else ``serial`` (starting the threads costs more than a short loop, and
    threads that wait for a busy core cost more than they save)."""
    def run(*args):
        first = next((a for a in args if isinstance(a, np.ndarray)), None)
        big = first is not None and first.ndim > 0 and len(first) >= PARALLEL_FROM
        return (parallel if big and _idle_core() else serial)(*args)
    run.__name__ = parallel.__name__
    return run


def _idle_core() -> bool:
    """At least one core is idle by the 1-minute load average (always True where it is unknown)."""
    try:
        return os.getloadavg()[0] <= (os.cpu_count() or 1) - 1
    except (AttributeError, OSError):
        return True


#: kernels whose cached machine code shows the module warm (:mod:`inertia._core.compiled`)
WARM_PROBE = ("vertex_pass", "weighted_sums", "winding_rest")

#: Loops over fewer items than this run on one thread.
PARALLEL_FROM = 4096
_NS, _PARALLEL = _compiled_namespace()
globals().update({name: _PARALLEL.get(name, _NS[name]) for mod in _MODULES for name in mod.__all__})
