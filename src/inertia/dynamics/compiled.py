"""When the compiled (numba) kernels run: the ``backend`` argument of ``integrate`` and ``rollout``.

``backend="numpy"`` always runs the NumPy reference; ``backend="numba"`` the compiled kernel
(numba must be installed: the ``fast`` extra); ``backend="auto"`` compares estimates of the
two costs for the call at hand:

* NumPy: a vectorised step costs a fixed ~25-75 us plus ~0.1-0.3 us per body
  (:data:`NUMPY_STEP_SECONDS`, :data:`NUMPY_BODY_STEP_SECONDS`, the cheapest methods);
* compiled: the work at :data:`COMPILED_BODY_STEP_SECONDS` (1e7 body-steps/s, the slowest
  method on one body) plus what the kernel costs before its first call in this process:
  nothing once it ran, :data:`LOAD_SECONDS` to import numba and load it from numba's on-disk
  cache, or its compilation when that cache is cold (``bench/integrate.py --cold``: 1.1-1.6
  s of CPU for an ``integrate`` loop, 3.2-4.3 s for a ``rollout`` kernel, per method).

``INERTIA_COMPILED=never`` or ``always`` (:mod:`inertia._core.compiled`) overrides ``auto``.
Unlike a mesh call, a long integration does compile in the caller's time when that pays:
its NumPy path can be minutes, a compile is seconds.

Small calls therefore stay on NumPy (a few thousand steps of one body take well under a
second there) unless the kernel is already loaded.  So that a loop of many small calls does
not keep paying the NumPy price, the NumPy time estimated for the calls that stayed on NumPy
accumulates: once it exceeds the kernel's first-call cost, the next call compiles (the
classic rent-or-buy rule, at most twice the better choice made in hindsight).  Both paths
compute the same steps; they differ by rounding (see each kernel module).
"""

from __future__ import annotations

import sys
from typing import Callable

from .._core.errors import InputError, MissingDependencyError

__all__ = ["BACKENDS", "numba_available", "check_backend", "use_compiled", "first_call_seconds"]

#: Accepted values of ``backend``.
BACKENDS = ("auto", "numpy", "numba")

#: Measured on the development machine (bench/integrate.py); rough on purpose.
NUMPY_STEP_SECONDS = 25e-6
NUMPY_BODY_STEP_SECONDS = 1e-7
COMPILED_BODY_STEP_SECONDS = 1e-7
LOAD_SECONDS = 0.3
#: compiling one method's ``integrate`` loop with a cold cache (a rollout kernel passes its own)
COMPILE_SECONDS = 1.5

# NumPy seconds (estimated) spent by calls that could have compiled: the "rent" paid so far
_rent = {"seconds": 0.0}


def numba_available() -> bool:
    """True when numba can be imported (the ``fast`` extra is installed)."""
    try:
        import numba  # noqa: F401
    except ImportError:
        return False
    return True


def check_backend(backend) -> str:
    if backend not in BACKENDS:
        raise InputError(f"backend must be one of {BACKENDS}, got {backend!r}")
    return backend


def first_call_seconds(dispatcher, compile_seconds: float = COMPILE_SECONDS) -> float:
    """What a numba kernel costs before its first call: 0 once loaded, else a load or a compile."""
    from .._core.compiled import is_cached

    if dispatcher.signatures:
        return 0.0
    return LOAD_SECONDS if is_cached(dispatcher, unknown=False) else compile_seconds


def use_compiled(backend: str, method, compiled_methods, steps: int, bodies: int,
                 kernel: Callable[[], object], *, numpy_scale: float = 1.0,
                 compile_seconds: float = COMPILE_SECONDS) -> bool:
    """True to run the compiled kernel for ``steps`` steps of ``bodies`` bodies.

    ``kernel()`` imports and returns the numba dispatcher of ``method`` (it imports numba);
    ``numpy_scale`` scales the NumPy estimate (a rollout's 6-DOF step costs more).
    """
    check_backend(backend)
    if backend == "numpy":
        return False
    compiled = isinstance(method, str) and method in compiled_methods
    if backend == "numba":
        if not compiled:
            raise InputError(f"backend='numba' compiles the methods {tuple(compiled_methods)}, got "
                             f"method={method!r}; use backend='numpy' (or 'auto') for it")
        if not numba_available():
            raise MissingDependencyError("backend='numba' needs numba, which is not installed: "
                                         "pip install 'inertia[fast]', or use backend='numpy'")
        return True
    if not compiled:
        return False
    from .._core.compiled import mode

    if mode() == "never":                            # INERTIA_COMPILED: the user's word first
        return False
    if mode() == "always":
        return numba_available()
    numpy_s = numpy_scale * steps * (NUMPY_STEP_SECONDS + NUMPY_BODY_STEP_SECONDS * bodies)
    compiled_s = COMPILED_BODY_STEP_SECONDS * steps * bodies
    if sys.modules.get("numba") is None and numpy_s + _rent["seconds"] < LOAD_SECONDS:
        _rent["seconds"] += numpy_s                  # not worth importing numba to find out
        return False
    if not numba_available():
        return False
    try:
        dispatcher = kernel()
    except ImportError:
        return False
    if first_call_seconds(dispatcher, compile_seconds) + compiled_s <= numpy_s + _rent["seconds"]:
        return True
    _rent["seconds"] += numpy_s
    return False
