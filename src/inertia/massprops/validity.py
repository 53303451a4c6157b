"""Physical validity of mass properties, with every violation named and quantified.

Conditions (checked in this order, all reported as :class:`~inertia.errors.Finding`):

* ``non_positive_mass``: mass must be finite and > 0;
* ``non_finite``: every entry of the inertia matrix (and COM, if given) finite;
* ``not_symmetric``: ``|I_ij - I_ji| <= SYMMETRY_RTOL * max|I|``;
* ``not_positive_definite``: smallest principal moment ``> PHYSICAL_RTOL * trace`` (a rod
  or a point has a zero moment and is reported);
* ``triangle_inequality``: ``I1 + I2 >= I3 - PHYSICAL_RTOL * trace`` over the ascending
  principal moments.  Every mass distribution satisfies it (``I1 + I2 - I3 = 2 sum m z^2``
  in principal axes); a flat plate meets it with equality.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InputError, InvalidInertiaError
from .._core.findings import Finding
from .._core.tolerances import PHYSICAL_RTOL, SYMMETRY_RTOL
from .._core.validation import as_float_array

_TINY = float(np.finfo(float).tiny)     # the smallest normal float64


def check_inertia(inertia, mass=None, com=None, *, rtol: float = PHYSICAL_RTOL,
                  symmetry_rtol: float = SYMMETRY_RTOL) -> list[Finding]:
    """Every physical-validity violation of one inertia matrix (empty list when valid).

    Parameters
    ----------
    inertia : (3, 3) float, kg m^2, about the COM.
    mass : float, kg, optional.
    com : (3,) float, m, optional (only checked for finiteness).
    rtol, symmetry_rtol : float
        Tolerances, see the module docstring.
    """
    out: list[Finding] = []
    if mass is not None:
        m = float(mass)
        if not (math.isfinite(m) and m > 0):
            out.append(Finding("non_positive_mass", f"mass must be positive and finite, got {m:.6g} kg",
                               values={"mass": m}))
    if com is not None:
        c = np.asarray(com, float)
        if c.shape != (3,) or not all(map(math.isfinite, c.tolist())):
            out.append(Finding("non_finite", f"center of mass must be 3 finite numbers, got {c.tolist()}",
                               values={"com": c.tolist()}))
    I = np.asarray(inertia, float)
    if I.shape != (3, 3):
        raise InputError(f"inertia must have shape (3, 3), got {I.shape}")
    # nine numbers: plain Python is several times faster than NumPy reductions here
    rows = I.tolist()
    flat = rows[0] + rows[1] + rows[2]
    if not all(map(math.isfinite, flat)):
        out.append(Finding("non_finite", f"inertia holds non-finite entries: {rows}", values={"inertia": rows}))
        return out
    scale = max(map(abs, flat))
    asym = max(abs(rows[0][1] - rows[1][0]), abs(rows[0][2] - rows[2][0]), abs(rows[1][2] - rows[2][1]))
    if asym > symmetry_rtol * max(scale, _TINY):
        i, j = np.unravel_index(np.argmax(np.abs(I - I.T)), I.shape)
        out.append(Finding("not_symmetric",
                             f"inertia is not symmetric: I[{i},{j}] = {I[i, j]:.6g} but I[{j},{i}] = {I[j, i]:.6g} "
                             f"(difference {asym:.3g} > {symmetry_rtol:g} * max|I| = {symmetry_rtol * scale:.3g})",
                             values={"asymmetry": asym}))
    # Work on I / max|I|: 0.5 (I + I^T), the eigensolver's squares and the trace cannot overflow
    # or underflow, whatever the magnitude (1e-300 to 1e308); moments are scaled back for messages.
    s = scale if scale > 0.0 else 1.0
    if not out and _clearly_physical(rows, s, rtol):
        return out
    unit = np.linalg.eigvalsh(0.5 * (I / s + I.T / s))
    with np.errstate(over="ignore"):
        moments = unit * s
    tol_unit = rtol * max(abs(float(np.sum(unit))), _TINY)
    tol = tol_unit * s
    if unit[0] <= tol_unit:
        out.append(Finding("not_positive_definite",
                             f"inertia is not positive definite: principal moments {_fmt(moments)} kg m^2, "
                             f"smallest {moments[0]:.6g} <= tolerance {tol:.3g}",
                             values={"moments": moments.tolist(), "tolerance": tol}))
    margin_unit = float(unit[0] + unit[1] - unit[2])
    margin = margin_unit * s
    if margin_unit < -tol_unit:
        out.append(Finding("triangle_inequality",
                             f"inertia fails the triangle inequality: I1 + I2 = {moments[0] + moments[1]:.6g} < "
                             f"I3 = {moments[2]:.6g} (margin {margin:.3g}; principal moments about the COM, kg m^2)",
                             values={"moments": moments.tolist(), "margin": margin, "tolerance": tol}))
    return out


def _clearly_physical(rows, s: float, rtol: float) -> bool:
    """A shortcut that proves a symmetric tensor physical without an eigensolver (pure Python).

    With ``C = tr(I)/2 - I`` (the second moments of the mass about the COM), the principal
    moments are ``c_i + c_j`` and the triangle margin ``I1 + I2 - I3`` is ``2 c_min``.  When
    every Gershgorin disc of ``C`` lies above ``rtol * trace`` (with room for rounding), every
    moment exceeds the tolerance and the margin is positive, so :func:`check_inertia` would
    find nothing.  Otherwise (a thin or rotated body) the eigenvalues decide.
    """
    (a, b, c), (d, e, f), (g, h, k) = rows
    a, b, c, d, e, f, g, h, k = a / s, b / s, c / s, d / s, e / s, f / s, g / s, h / s, k / s
    half = 0.5 * (a + e + k)
    xy, xz, yz = 0.5 * (b + d), 0.5 * (c + g), 0.5 * (f + h)
    low = min(half - a - abs(xy) - abs(xz), half - e - abs(xy) - abs(yz), half - k - abs(xz) - abs(yz))
    return low > 2.0 * (rtol + 1e-14) * abs(a + e + k)


def is_physical(inertia, mass=None, **kwargs) -> bool:
    """True when :func:`check_inertia` finds no violation."""
    return not check_inertia(inertia, mass, **kwargs)


def raise_if_invalid(inertia, mass=None, com=None, *, what: str = "mass properties", **kwargs) -> None:
    """Raise :class:`InvalidInertiaError` listing every violation, if any."""
    v = check_inertia(inertia, mass, com, **kwargs)
    if v:
        raise InvalidInertiaError(f"{what} are not physical: " + "; ".join(x.message for x in v), findings=v)


def _fmt(a) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in np.asarray(a).ravel()) + ")"


def as_principal_moments(moments, name: str = "moments", *, validate: bool = True,
                         allow_batch: bool = True) -> np.ndarray:
    """Principal moments ``(..., 3)`` [kg m^2] of bodies, in any order: the one moments validator.

    Used by every entry point that takes principal moments (``integrate``, the step functions,
    ``exact_solution``, the flip predictions, the CLI).  Raises
    :class:`~inertia.errors.InputError` for a wrong shape or a non-finite value, and
    :class:`~inertia.errors.InvalidInertiaError` (with the violations) for moments that are not
    those of a physical body: a moment not above ``PHYSICAL_RTOL * trace`` (zero or negative),
    or, when ``validate``, the triangle inequality ``I1 + I2 >= I3`` violated by more than
    ``PHYSICAL_RTOL * trace``, the rules of :func:`check_inertia`.  ``validate=False`` accepts
    any positive moments: Euler's equations do not need the triangle inequality, and textbook
    test bodies (Hairer, Lubich and Wanner's ``(2/3, 1, 2)``) violate it.
    """
    I = as_float_array(moments, name, (3,), allow_batch=allow_batch)
    flat = I.reshape(-1, 3)
    # the rules of check_inertia on diag(I), vectorised, scaled so no sum overflows
    scale = np.maximum(np.abs(flat).max(axis=1), _TINY)
    s = np.sort(flat, axis=1) / scale[:, None]
    tol = rtol_of_trace = PHYSICAL_RTOL * np.maximum(np.abs(s.sum(axis=1)), _TINY)
    bad = s[:, 0] <= tol
    if validate:
        bad |= s[:, 0] + s[:, 1] - s[:, 2] < -rtol_of_trace
    if np.any(bad):
        k = int(np.argmax(bad))
        violations = check_inertia(np.diag(flat[k]))
        if not validate:
            violations = [v for v in violations if v.code != "triangle_inequality"]
        where = "" if I.ndim == 1 else f" at batch index {tuple(int(i) for i in np.unravel_index(k, I.shape[:-1]))}"
        raise InvalidInertiaError(f"{name} = {_fmt(flat[k])} kg m^2{where} are not the principal moments of a "
                                  f"physical body: " + "; ".join(v.message for v in violations), findings=violations)
    return I
