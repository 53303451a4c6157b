"""The dual-spin stability threshold: a wheel's momentum along the spin axis that stabilises a spin.

A body spins at ``Omega`` about its principal axis k, carrying a constant wheel momentum ``h``
along that axis (``h`` the wheel's absolute axial momentum with the inertia of
:mod:`inertia.dynamics.gyrostat`, or its relative momentum with the inertia that includes the
wheel: both give the same numbers).  Small transverse motions grow or oscillate as
``exp(lambda t)`` with

    lambda^2 = -[(I_k - I_i) Omega + h] [(I_k - I_j) Omega + h] / (I_i I_j)

(Hughes, *Spacecraft Attitude Dynamics*, 1986, section 9.3; Wie, *Space Vehicle Dynamics and
Control*, 2nd ed., 2008, eq. 7.120), i, j the two other axes.  The spin is unstable exactly for
``h`` strictly between the two roots ``-(I_k - I_i) Omega`` and ``-(I_k - I_j) Omega``.  About the
intermediate axis (k = 2) with ``Omega > 0`` that interval is ``(-(I2 - I1) Omega, (I3 - I2) Omega)``:
a wheel spinning with the body needs ``h > h_min = (I3 - I2) Omega``.  With ``h = 0`` it is the
free body's rule (the intermediate axis unstable, the outer ones stable).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_float_array

__all__ = ["DualSpinThreshold", "dual_spin_threshold", "dual_spin_exponent"]


@dataclass(frozen=True)
class DualSpinThreshold:
    """The wheel momenta (N m s, along the spin axis) for which the spin is unstable: the open
    interval ``(h_low, h_high)``; empty (``h_low == h_high``) when the axis has a repeated moment.
    ``h_min`` is the smallest momentum in the sense of the spin that stabilises it (0 when the
    spin is stable without a wheel)."""

    h_low: float
    h_high: float
    h_min: float


def _other_axes(axis) -> tuple[int, int, int]:
    if axis not in (0, 1, 2):
        raise InputError(f"axis must be the index 0, 1 or 2 of a principal axis, got {axis!r}")
    return axis, (axis + 1) % 3, (axis + 2) % 3


def dual_spin_exponent(moments, axis: int, spin_rate: float, h) -> np.ndarray:
    """``lambda^2`` (1/s^2) of the transverse motion: > 0 diverges at ``sqrt``, < 0 nutates at ``sqrt(-)``.

    moments : (3,) float, principal moments (kg m^2), in the order of the axes; axis : 0, 1 or 2;
    spin_rate : rad/s; h : float or array, N m s along the spin axis.

    >>> float(dual_spin_exponent([1.0, 2.0, 3.0], 1, 1.0, 0.0))  # the free body's intermediate axis
    0.3333333333333333
    """
    I = as_float_array(moments, "moments", (3,), allow_batch=False)
    k, i, j = _other_axes(axis)
    W = float(spin_rate)
    h = np.asarray(h, dtype=float)
    return -((I[k] - I[i]) * W + h) * ((I[k] - I[j]) * W + h) / (I[i] * I[j])


def dual_spin_threshold(moments, axis: int, spin_rate: float) -> DualSpinThreshold:
    """The unstable interval of wheel momentum for a spin about principal axis ``axis``.

    >>> t = dual_spin_threshold([600.0, 800.0, 900.0], 1, 0.1)   # Basilisk's body about its 800 axis
    >>> round(t.h_low, 9), round(t.h_high, 9), round(t.h_min, 9)
    (-20.0, 10.0, 10.0)
    """
    I = as_float_array(moments, "moments", (3,), allow_batch=False)
    k, i, j = _other_axes(axis)
    W = float(spin_rate)
    if not np.isfinite(W):
        raise InputError(f"spin_rate must be finite, got {spin_rate!r}")
    r1, r2 = -(I[k] - I[i]) * W, -(I[k] - I[j]) * W
    lo, hi = min(r1, r2), max(r1, r2)
    # the smallest |h| with the sign of the spin outside (lo, hi): none needed if 0 is outside
    if not lo < 0.0 < hi:
        h_min = 0.0
    else:
        h_min = hi if W >= 0 else lo
    return DualSpinThreshold(float(lo), float(hi), float(h_min))
