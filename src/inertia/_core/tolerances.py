"""Named tolerances of the mass-properties layer, kept in one place.

Each is relative to a natural scale of the quantity tested, so the checks do not
depend on units.  All are keyword-overridable where they are used.
"""

import math

from .units import LENGTH_UNITS

#: Symmetry: |I - I^T| <= SYMMETRY_RTOL * max|I| (elementwise).  Loose enough for
#: tensors printed with ~12 significant digits, tight enough to catch sign slips.
SYMMETRY_RTOL = 1e-9

#: Positive definiteness and the triangle inequality: a principal moment (or the
#: triangle margin I1 + I2 - I3) may fall below zero by at most
#: PHYSICAL_RTOL * trace(I) before it counts as a violation.  Rounding in an exact
#: computation is ~1e-15 * trace; a flat plate sits exactly on I1 + I2 = I3.
PHYSICAL_RTOL = 1e-12

#: Principal moments closer than REPEATED_MOMENTS_RTOL * max(moments) are repeated: one rule
#: for the canonical form (the axes in the repeated plane are then fixed by the deterministic
#: rule of :func:`inertia.massprops.principal.principal_axes`, not by the eigensolver) and for
#: the exact solution (symmetric-top or sphere formulas).  1e-13 (about 450 ulp) sits between
#: the two limits: eigenvalues of a rotated tensor carry rounding of a few ulp of its norm
#: (1e-15), which must count as repeated; and the asymmetric elliptic formulas still agree
#: with DOP853 to 1e-11 at a relative gap of 1e-12 (tests/dynamics/test_exact.py), which must
#: count as distinct.
REPEATED_MOMENTS_RTOL = 1e-13

#: Mesh checks: the largest coordinate magnitude a mesh may hold (in metres after unit
#: conversion, or in the caller's unit).  Second moments grow as size**5 (times a density
#: up to ~1e4), so 1e60 keeps every integral below ~1e305, inside float64; beyond it a
#: vertex is the defect ``out_of_range``, not an overflow read as "zero-area faces".
COORDINATE_LIMIT = 1e60

#: Mesh checks: a face is degenerate when its area is below
#: DEGENERATE_AREA_RTOL * (its longest edge)**2: relative to the face itself, so small faces
#: of a large or far-away mesh are not called degenerate.
DEGENERATE_AREA_RTOL = 1e-14

#: A quaternion argument whose norm differs from 1 by more than this is refused (a zero or
#: garbage quaternion is a bug, not drift); closer ones are renormalised silently (a solver's
#: or filter's drift).  Every function taking ``q_world_body`` uses it.
QUAT_NORM_TOL = 1e-6

#: Robot files: the least mass [kg] and principal moment [kg m^2] a moving body may have in a
#: simulator.  MuJoCo (its mjMINVAL) refuses a body with degrees of freedom whose mass or a
#: principal moment, with every body welded to it, is below 1e-15 ("mass and inertia of moving
#: bodies must be larger than mjMINVAL"), and a ``fullinertia`` with an eigenvalue below it
#: ("inertia must have positive eigenvalues"); Gazebo (DART) and Pinocchio need them positive.
#: Absolute, not relative: a 1 kg link with moments of 1e-35 kg m^2 is rounding noise however
#: well shaped.  ``inertia fix`` never writes a tensor below it.
SIMULATOR_MIN_VALUE = 1e-15

#: the unit roundoff of float32 (half an ulp at 1): a coordinate stored as float32 (binary STL,
#: many glTF and PLY files) is within this fraction of its magnitude of the true value
FLOAT32_ROUNDOFF = 2.0 ** -24


#: the length units' factors to metres, the units float32 coordinates may have been written in
_FACTORS = tuple(LENGTH_UNITS.values())


def _float32_like(y: float) -> bool:
    """``y`` is a normal float32 value to within 1e-12 of itself (24 significant bits): its
    mantissa, scaled to 2^24, is an integer to that precision (powers of two scale exactly)."""
    m, e = math.frexp(y)
    t = m * 16777216.0
    return -124 <= e <= 128 and abs(t - round(t)) <= 1e-12 * abs(t)


def coordinate_precision(vertices, radius: float) -> float:
    """The relative precision of a body's inertia that its mesh coordinates allow: 0 for
    double-precision data, else ``4 FLOAT32_ROUNDOFF max|v| / radius`` when every coordinate,
    in one of the length units of :data:`inertia._core.units.LENGTH_UNITS`, is a float32 value
    (binary STL, many glTF and PLY files).

    ``radius``: the body's largest radius of gyration (m, the units of ``vertices``).  A
    coordinate off by ``d`` moves a moment ``m r^2`` by about ``2 m r d``; twice that bounds it.
    """
    import numpy as np

    v = np.asarray(vertices, dtype=np.float64)
    if v.size == 0 or not radius > 0:
        return 0.0
    # a few coordinates first, in plain Python: float64 data fails them for every unit at once
    few = [x for x in v.ravel()[:12].tolist() if x != 0.0 and math.isfinite(x)]
    units = []
    for f in _FACTORS:   # plain loops: this runs on every mesh, most often failing at once
        for x in few:
            if not _float32_like(x / f):
                break
        else:
            units.append(f)
    if not units:
        return 0.0
    biggest = max(float(v.max()), -float(v.min()))
    if not 0.0 < biggest < math.inf:
        return 0.0
    for factor in units:
        if biggest / factor > 3e38:          # beyond float32's range
            continue
        raw = v if factor == 1.0 else v / factor
        as_f32 = raw.astype(np.float32)
        if np.array_equal(as_f32, raw) or (   # exact (a binary STL in metres), else within 1e-12
                float(np.abs(as_f32.astype(np.float64) - raw).max()) <= 1e-12 * (biggest / factor)):
            return min(4.0 * FLOAT32_ROUNDOFF * biggest / radius, 0.5)
    return 0.0
