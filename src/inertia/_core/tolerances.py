"""Named tolerances of the mass-properties layer, kept in one place.

Each is relative to a natural scale of the quantity tested, so the checks do not
depend on units.  All are keyword-overridable where they are used.
"""

#: Symmetry: |I - I^T| <= SYMMETRY_RTOL * max|I| (elementwise).  Loose enough for
#: tensors printed with ~12 significant digits, tight enough to catch sign slips.
SYMMETRY_RTOL = 1e-9

#: Positive definiteness and the triangle inequality: a principal moment (or the
#: triangle margin I1 + I2 - I3) may fall below zero by at most
#: PHYSICAL_RTOL * trace(I) before it counts as a violation.  Rounding in an exact
#: computation is ~1e-15 * trace; a flat plate sits exactly on I1 + I2 = I3.
PHYSICAL_RTOL = 1e-12

#: Principal moments closer than DEGENERATE_RTOL * max(moments) are treated as
#: repeated: their axes are then fixed by the deterministic rule of
#: :func:`inertia.massprops.principal.principal_axes`, not by the eigensolver.
DEGENERATE_RTOL = 1e-9

#: Mesh checks: a face is degenerate when its area is below
#: DEGENERATE_AREA_RTOL * (bounding-box diagonal)**2.
DEGENERATE_AREA_RTOL = 1e-14
