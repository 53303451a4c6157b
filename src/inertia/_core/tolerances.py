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

#: Magnitudes a tensor, mass or rate may have (in SI units) for the library to compute with
#: it: inside [REPRESENTABLE_MIN, REPRESENTABLE_MAX] the squares and products that the checks,
#: the principal axes and the dynamics form (I w^2, m |c|^2, I^2) stay finite and normal in
#: double precision (about 1e-308 to 1e308).  Every physical body is far inside (the Sun's
#: moment of inertia is about 6e46 kg m^2; a 1 um grain's about 1e-27); beyond it a value is
#: refused by name ("not_representable") instead of turning into inf or NaN downstream.
REPRESENTABLE_MAX = 1e150
REPRESENTABLE_MIN = 1e-150
