"""Input coercion with messages that name the argument, the expected and the received shape."""

from __future__ import annotations

import math

import numpy as np

from .errors import InputError
from .tolerances import QUAT_NORM_TOL, SYMMETRY_RTOL


def as_float_array(value, name: str, shape_tail: tuple[int, ...], *, allow_batch: bool = True,
                   finite: bool = True) -> np.ndarray:
    """Return ``value`` as a float64 array whose trailing shape is ``shape_tail``.

    Raises InputError naming ``name`` when the value is not numeric, has the wrong
    shape, or (with ``finite``, the default) holds NaN/inf.  ``finite=False`` lets NaN and
    inf through, for functions that report on data that may have diverged.
    """
    arr = as_real_array(value, name)
    k = len(shape_tail)
    ok = arr.ndim >= k and arr.shape[arr.ndim - k:] == shape_tail if k else True
    if ok and not allow_batch and arr.ndim != k:
        ok = False
    if not ok:
        dims = ["..."] * allow_batch + [str(s) for s in shape_tail]
        want = "(" + ", ".join(dims) + ("," if len(dims) == 1 else "") + ")"
        raise InputError(f"{name} must have shape {want}, got {arr.shape}")
    if finite and not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0]
        raise InputError(f"{name} holds a non-finite value ({arr[tuple(bad)]}) at index {tuple(int(i) for i in bad)}")
    return arr


def as_real_array(value, name: str) -> np.ndarray:
    """``value`` as a float64 array of any shape; InputError naming ``name`` for what is not a
    real number: strings, objects, complex values (the imaginary part is never dropped) and
    booleans."""
    try:
        raw = np.asarray(value)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric, got {type(value).__name__}: {exc}") from None
    if raw.dtype == bool or np.issubdtype(raw.dtype, np.complexfloating):
        kind = "booleans" if raw.dtype == bool else "complex values"
        raise InputError(f"{name} must hold real numbers, got {kind} (dtype {raw.dtype})")
    try:
        return np.asarray(raw, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric, got {type(value).__name__}: {exc}") from None


def as_vector3(value, name: str, *, allow_batch: bool = False) -> np.ndarray:
    return as_float_array(value, name, (3,), allow_batch=allow_batch)


def as_matrix3(value, name: str, *, allow_batch: bool = False) -> np.ndarray:
    return as_float_array(value, name, (3, 3), allow_batch=allow_batch)


def as_positive_scalar(value, name: str, *, allow_zero: bool = False) -> float:
    """A finite positive float (or non-negative when ``allow_zero``); bools and complex refused."""
    if isinstance(value, (bool, np.bool_, complex, np.complexfloating)):
        raise InputError(f"{name} must be a real number, got {value!r}")
    try:
        x = float(value)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number, got {value!r}") from None
    if not math.isfinite(x) or x < 0 or (x == 0 and not allow_zero):
        rel = "non-negative" if allow_zero else "positive"
        raise InputError(f"{name} must be finite and {rel}, got {x!r}")
    return x


def as_rotation_matrix(value, name: str = "R", *, atol: float = 1e-9, allow_batch: bool = True) -> np.ndarray:
    """A proper rotation matrix (..., 3, 3): orthonormal with det +1 to ``atol``."""
    R = as_float_array(value, name, (3, 3), allow_batch=allow_batch)
    err = np.abs(np.swapaxes(R, -1, -2) @ R - np.eye(3)).max(initial=0.0)
    if err > atol:
        raise InputError(f"{name} is not orthonormal: max |R^T R - 1| = {err:.3g} > {atol:g}")
    det = np.linalg.det(R)
    if np.any(det < 0):
        raise InputError(f"{name} is a reflection (det = {float(np.min(det)):.6g}), not a proper rotation")
    return R


def resolve_mass(measure: float, density, mass, *, what: str, measure_name: str = "volume") -> tuple[float, float]:
    """Return ``(mass, density)`` from exactly one of ``density`` or ``mass``.

    ``measure`` is the volume (m^3) or, for thin shells, the area (m^2).
    """
    if (density is None) == (mass is None):
        raise InputError(f"{what}: give exactly one of density= or mass=, got "
                         f"{'both' if density is not None else 'neither'}")
    if not math.isfinite(measure) or measure <= 0:
        raise InputError(f"{what}: {measure_name} must be positive and finite, got {measure!r}")
    if density is not None:
        rho = as_positive_scalar(density, "density")
        if not math.isfinite(rho * measure):
            raise InputError(f"{what}: the mass, density {rho:g} x {measure_name} {measure:g}, is larger than a "
                             "double holds (1.8e308 kg)")
        return rho * measure, rho
    m = as_positive_scalar(mass, "mass")
    return m, m / measure   # may overflow: central_inertia(..., mass=m) scales the moments first


def as_unit_quat(q, name: str = "q_world_body", *, allow_batch: bool = True) -> np.ndarray:
    """Unit quaternions ``(..., 4)`` (w, x, y, z), renormalised; refused beyond :data:`QUAT_NORM_TOL`.

    A norm within ``QUAT_NORM_TOL`` of 1 is drift and is divided out; anything further (a zero
    or garbage quaternion) raises :class:`InputError` naming the argument, the norm and where.
    """
    arr = as_float_array(q, name, (4,), allow_batch=allow_batch)
    norm = np.linalg.norm(arr, axis=-1, keepdims=True)
    dev = np.abs(norm - 1.0)
    if np.any(dev > QUAT_NORM_TOL):
        k = tuple(int(i) for i in np.unravel_index(np.argmax(dev), dev.shape)[:-1])
        where = f" at batch index {k}" if k else ""
        raise InputError(f"{name} must be a unit quaternion (w, x, y, z) (|q| - 1 within {QUAT_NORM_TOL:g}), "
                         f"got |q| = {float(norm[k][0]):.12g}{where}: {arr[k].tolist()}")
    return arr / norm


def as_time_step(h, name: str = "h") -> float:
    """A finite, non-zero time step [s]: the one rule for every integrator and transition function.

    A negative step integrates backwards in time (every method is defined for it; the
    symmetric ones retrace their steps exactly); zero, NaN and inf are refused.
    """
    try:
        hf = float(h)
    except (TypeError, ValueError):
        raise InputError(f"{name} must be a number (the time step in s), got {h!r}") from None
    if not math.isfinite(hf) or hf == 0.0:
        raise InputError(f"{name} must be a finite non-zero time step in s (negative integrates backwards), "
                         f"got {h!r}")
    return hf


def as_count(value, name: str, minimum: int = 0) -> int:
    """An integer ``>= minimum`` (a Python or NumPy integer; bools and floats are refused)."""
    if isinstance(value, (bool, np.bool_)) or not isinstance(value, (int, np.integer)) or value < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}, got {value!r}")
    return int(value)


def as_symmetric_matrix3(value, name: str, *, allow_batch: bool = True) -> np.ndarray:
    """Symmetric matrices ``(..., 3, 3)``: ``max|A - A^T| <= SYMMETRY_RTOL * max|A|``."""
    A = as_float_array(value, name, (3, 3), allow_batch=allow_batch)
    asym = np.abs(A - np.swapaxes(A, -1, -2)).max(initial=0.0)
    scale = np.abs(A).max(initial=0.0)
    if asym > SYMMETRY_RTOL * scale:
        raise InputError(f"{name} must be symmetric, got max |I - I^T| = {asym:.3g} (largest entry {scale:.3g})")
    return A


def frozen_array(value) -> np.ndarray:
    """A read-only float64 copy: the attribute arrays of the library's immutable value types."""
    a = np.array(value, dtype=np.float64, copy=True)
    a.setflags(write=False)
    return a
