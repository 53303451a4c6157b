"""Exact volume and surface integrals of triangle meshes.

Formulas
--------
Solid (divergence theorem): every face (a, b, c) with an expansion point p forms a
signed tetrahedron (p, a, b, c).  With the corners taken relative to p,
``det = a . (b x c) = a . ((b - a) x (c - a))``, ``V = det / 6``, ``int (x - p) dV = V (a + b + c) / 4`` and
``int (x - p)(x - p)^T dV = det / 120 (a a^T + b b^T + c c^T + s s^T)``, ``s = a + b + c``
(Tonon 2004, "Explicit exact formulas for the 3-D tetrahedron inertia tensor in terms
of its vertex coordinates", J. Math. Stat. 1(1); Eberly, "Polyhedral Mass Properties
(Revisited)", Geometric Tools).  Summed over a closed, consistently outward-wound mesh
these are exact for any p; the sum of the per-face terms is all the kernel computes.

Thin shell (uniform surface density): ``A = |(b - a) x (c - a)| / 2``,
``int (x - p) dA = A s / 3``, ``int (x - p)(x - p)^T dA = A / 12 (a a^T + b b^T + c c^T + s s^T)``.
The shell needs neither a closed mesh nor a consistent winding.

Only the 6 distinct entries of each symmetric second moment are accumulated
(xx, yy, zz, xy, yz, zx), in one pass over the faces of the compiled kernel
(``inertia._ext.integrals``, ``src/ext/integrals/sums.hpp``): blocks of 256 faces summed in 4 lanes,
block sums added into chunk totals, chunk totals in order, so the bits depend on the arrays alone.

Error analysis
--------------
Notation: u = 2^-53; p the expansion point; for a face, a, b, c its corners relative
to p, ``n = (b - a) x (c - a)`` (twice its area vector) and rho_f the largest of
|a|, |b|, |c|; V the volume, g = COM - p, C = S - V g g^T the central second moment
(S = int (x - p)(x - p)^T dV), k^2 = tr(C) / V the polar radius of gyration squared,
and ``kappa = |g|^2 / k^2`` the offset ratio of p.

1. *Shift.*  ``y = fl(x - p)`` is computed once per vertex, before any product.  When
   x_i and p_i are within a factor 2 of each other -- always so for a mesh lying far
   from the origin, where |y| << |p| -- the subtraction is exact (Sterbenz's lemma);
   otherwise its error is at most u |y_i|.  Either way the perturbation is relative to
   the mesh's own size, never to its distance from the origin: from here on the mesh
   is, to rounding, a mesh at the origin.

2. *Per-face terms.*  The edges b - a, c - a are differences of neighbouring points
   (again Sterbenz-exact or accurate to u of the edge), so n has relative error O(u)
   and ``det = a . n`` an error O(u |a| |n|) <= O(u rho_f |n|).  (The textbook form
   ``a . (b x c)`` errs by O(u |a| |b| |c|): for a face of size h at distance rho
   from p that is (rho / h)^2 times worse.)  ``Q = a a^T + b b^T + c c^T + s s^T`` is
   accurate to O(u rho_f^2).  The sums add a factor of the summation depth
   (blocks of 256 faces: ~256 + F / 256 terms).  So, with gamma a
   small multiple of u: |dV| <~ gamma sum rho_f |n_f|, |dF| <~ gamma sum rho_f^2 |n_f|,
   |dS| <~ gamma sum rho_f^3 |n_f|.

3. *Central moment.*  Relative to tr(C) = V k^2 the error of S is gamma K with the
   geometric number ``K = sum_f rho_f^3 |n_f| / (V k^2)``: 10 for a ball about its
   center, moving with the mesh (so independent of where it lies), and growing like
   (d / L)^3 when p is at distance d from a body of size L.  The subtraction
   ``C = S - V g g^T`` cancels a further factor ~kappa (both terms are ~ tr(C) kappa
   when |g| >> k).  The diagonal of the inertia is formed as ``C_yy + C_zz`` etc.,
   never as ``tr(C) - C_xx``, so thin bodies keep their small moments.
   The central tensor is therefore accurate to ~ u (K + kappa) relative to its trace.

   Expanding about the origin instead (as trimesh does) gives K ~ 1e21 for a unit cube
   at d = 1e7: a central tensor with negative moments.

4. *Choice of p; one pass or two.*  p is the bounding-box center (exact for the
   translated cube: its coordinates are then exact binary fractions).  For compact
   bodies kappa is small -- 0 for centrally symmetric bodies, 0.19 for a cone -- and one
   pass is enough.
   kappa and K are large only for lopsided bodies (a ball with a long spike: the box
   center lies far out on the spike) or a p far outside the body.  As rho_f about p is
   at most rho_f about the COM plus |g|, K about p exceeds K about the COM by roughly
   (1 + sqrt(kappa))^3 at most.  So after the first pass kappa is computed from the
   sums (free), and when it exceeds :data:`REFINE_KAPPA` a second pass is made about
   p' = p + g, the computed COM (whose error is a tiny fraction of k), which brings
   kappa to ~0 and K to its value about the COM.  What no single expansion point can
   fix: a small part far from both p and the COM keeps its own (d / L)^3.

   A caller's ``reference`` is never used as the expansion point: the integrals are
   computed about p (and p') and then moved to ``reference`` with the exact identities
   ``int (x - r) = F + V d``, ``int (x - r)(x - r)^T = S + F d^T + d F^T + V d d^T``
   (``d = p - r``), each accurate relative to its own size.  Recovering the *central*
   tensor from integrals about a far ``reference`` would reintroduce the kappa
   cancellation -- so pass ``reference=None`` (the default) and give
   :func:`central_inertia` the reference that comes back.

The shell integrals have positive weights |n_f|; the same analysis holds with
``K = sum_f rho_f^2 |n_f| / (A k^2)``.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InputError
from .._ext import integrals as _k

#: Second pass about the computed COM when ``kappa = |COM - p|^2 / k^2`` exceeds this
#: (see "Error analysis", item 4).  Below it, expanding about the box center costs at
#: most a factor ~(1 + 2)^3 = 27 in rounding error over expanding about the COM, and
#: compact bodies (kappa well below 1) never pay for the second pass.
REFINE_KAPPA = 4.0

#: At most this many refinement passes (one is enough unless the first pass was
#: made about a point so far off that its COM estimate is itself inaccurate).
MAX_REFINE = 2

# (3, 3) symmetric matrix from the sums xx, yy, zz, xy, yz, zx stored at out[4:10]
_SYM = np.array([[4, 7, 9], [7, 5, 8], [9, 8, 6]])
# divisors of (measure, first, second) sums: solid det/6, det s/24, det Q/120;
# shell w/2, w s/6, w Q/24 with w = twice the face area
_SOLID_SCALE = (6.0, 24.0, 120.0)
_SHELL_SCALE = (2.0, 6.0, 24.0)


def reference_point(vertices: np.ndarray) -> np.ndarray:
    """Center of the axis-aligned bounding box (3,) m of ``vertices`` (V, 3) m, V >= 1.

    Inside or near the body, cheap, deterministic, and equivariant under translation.
    """
    return _k.bbox_center(np.ascontiguousarray(vertices, dtype=np.float64))


def winding_numbers(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Generalized winding numbers (P,) of the triangles ``tri`` (T, 3, 3) at ``points`` (P, 3).

    Sum of signed solid angles / 4 pi (Van Oosterom & Strackee 1983,
    ``tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)``): +-1 inside a
    closed surface, 0 outside.
    """
    return _k.winding_numbers(np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 3),
                              np.ascontiguousarray(tri, dtype=np.float64).reshape(-1, 3, 3))


# ---------------------------------------------------------------------- driver
def _mesh_arrays(vertices, faces):
    """Validated ``(vertices (V, 3) float64, faces (F, 3) int64)``, both C-contiguous."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise InputError(f"vertices must have shape (V, 3), got {v.shape}")
    if v.shape[0] == 0:
        raise InputError("vertices is empty: a mesh needs at least one vertex")
    f = np.asarray(faces)
    if f.ndim != 2 or f.shape[1] != 3:
        raise InputError(f"faces must have shape (F, 3), got {f.shape}")
    if f.dtype.kind not in "iu" and f.size:
        raise InputError(f"faces must hold integer vertex indices, got dtype {f.dtype}")
    return v, np.ascontiguousarray(f, dtype=np.int64)


def solid_sums_moments(out: np.ndarray):
    """``(volume, first (3,), second (3, 3))`` from the unscaled sums of a solid kernel
    (``out[:10]`` as ``solid_sums`` writes them)."""
    return float(out[0] / _SOLID_SCALE[0]), out[1:4] / _SOLID_SCALE[1], out[_SYM] / _SOLID_SCALE[2]


def _sums(kernel, v, f, p, scale):
    """One kernel pass about ``p`` (it refuses a face with a vertex index outside [0, V));
    ``(measure, first (3,), second (3, 3))``."""
    out = kernel(v, f, p)
    if not np.isfinite(out).all():
        used = np.zeros(v.shape[0], bool)
        used[f.ravel()] = True
        bad_v = np.flatnonzero(used & ~np.isfinite(v).all(axis=1))
        where = (f"vertex {int(bad_v[0])} = {v[bad_v[0]].tolist()} is not finite" if bad_v.size
                 else "the coordinates overflow float64")
        raise InputError(f"mesh integrals are not finite: {where}")
    return out[0] / scale[0], out[1:4] / scale[1], out[_SYM] / scale[2]


def offset_ratio(measure: float, first: np.ndarray, second: np.ndarray) -> float:
    """``kappa = |g|^2 / k^2`` of the error analysis (0 when it is meaningless, e.g. zero measure)."""
    return _offset_ratio(measure, first.tolist(), float(second[0, 0] + second[1, 1] + second[2, 2]))


def _offset_ratio(measure: float, first, trace: float) -> float:
    """:func:`offset_ratio` from ``first`` (3 floats) and the trace of ``second``."""
    if measure == 0.0:
        return 0.0
    f0, f1, f2 = first
    ff = f0 * f0 + f1 * f1 + f2 * f2          # = measure^2 |g|^2
    tr_C = trace - ff / measure
    if not tr_C * measure > 0.0:              # not a body (open/degenerate mesh): nothing to refine
        return 0.0
    return ff / (measure * tr_C)


def _integrals(kernel, v, f, reference, scale):
    """Integrals about the box center (or the COM, item 4 of the error analysis), moved to ``reference``."""
    if reference is not None:
        r = np.asarray(reference, dtype=np.float64)
        if r.shape != (3,) or not np.isfinite(r).all():
            raise InputError(f"reference must be a finite (3,) point, got {reference!r}")
    p = _k.bbox_center(v)
    measure, first, second = _sums(kernel, v, f, p, scale)
    for _ in range(MAX_REFINE):
        # lopsided body: expand again about the computed COM (error analysis, item 4)
        if not offset_ratio(measure, first, second) > REFINE_KAPPA:
            break
        p = p + first / measure
        measure, first, second = _sums(kernel, v, f, p, scale)
    if reference is None:
        return float(measure), first, second, p
    # move the integrals from p to r: x - r = (x - p) + d
    d = p - r
    Fd = np.multiply.outer(first, d)
    return (float(measure), first + measure * d,
            second + Fd + Fd.T + measure * np.multiply.outer(d, d), r.copy())


def solid_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None):
    """Volume integrals of a closed triangle mesh.

    Parameters
    ----------
    vertices : (V, 3) float, m.
    faces : (F, 3) int, vertex indices, counter-clockwise seen from outside.
    reference : (3,) float, m, optional
        Point the integrals are taken about.  Default: the bounding-box center, or the
        computed COM when the body is lopsided (see the module's error analysis).
        A given point is never used for the computation itself; the integrals are
        moved to it exactly afterwards.

    Returns
    -------
    volume : float, m^3 (signed: negative when the mesh is wound inward).
    first : (3,) float, ``int (x - r) dV``, m^4.
    second : (3, 3) float, ``int (x - r)(x - r)^T dV``, m^5.
    reference : (3,) float, m, the point r the integrals are about.

    Raises
    ------
    InputError
        Wrong shapes, non-integer faces, a vertex index out of range, or a non-finite
        vertex used by a face.
    """
    v, f = _mesh_arrays(vertices, faces)
    return _integrals(_k.solid_sums, v, f, reference, _SOLID_SCALE)


def shell_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None):
    """Surface integrals of a triangle mesh (orientation-free; need not be closed).

    Same parameters as :func:`solid_integrals`.  Returns ``(area m^2,
    int (x - r) dA (3,) m^3, int (x - r)(x - r)^T dA (3, 3) m^4, r (3,) m)``.
    """
    v, f = _mesh_arrays(vertices, faces)
    return _integrals(_k.shell_sums, v, f, reference, _SHELL_SCALE)


def central_inertia(measure: float, first: np.ndarray, second: np.ndarray, reference: np.ndarray, density: float,
                    mass: float | None = None):
    """Turn integrals about ``reference`` into the COM and the inertia about it, for a uniform ``density``.

    Parameters
    ----------
    measure : float, volume m^3 (or area m^2 for a shell).
    first : (3,) float, ``int (x - r)``.
    second : (3, 3) float, ``int (x - r)(x - r)^T``.
    reference : (3,) float, m, the point r.
    density : float, kg/m^3 (kg/m^2 for a shell).
    mass : float, optional, kg, ``density * measure``: given, the inertia is ``mass (C / measure)``
        where ``density C`` would overflow (a huge mass on a small body: the density does not fit).

    Returns
    -------
    com : (3,) float, m, ``r + c`` with ``c = first / measure``.
    inertia : (3, 3) float, kg m^2, about the COM, negated-product convention:
        ``density (tr(C) 1 - C)`` with ``C = second - measure c c^T``; the diagonal is
        formed as ``C_yy + C_zz`` etc. (no subtraction from the trace).
    """
    if not (measure != 0.0 and np.isfinite(measure)):
        raise InputError(f"cannot locate the center of mass: the measure (volume or area) is {measure!r}")
    return central_from_floats(measure, first.tolist(), second.tolist(), np.asarray(reference).tolist(),
                               float(density), mass)


def central_from_floats(measure: float, first, second, reference, rho: float, mass: float | None = None):
    """:func:`central_inertia` on Python floats (``first``, ``reference``: 3; ``second``: 3 rows
    of 3; ``measure`` finite, non-zero), the same arithmetic: 3 x 3 NumPy operations would cost
    more than the rest of a small mesh."""
    f0, f1, f2 = first
    gx, gy, gz = f0 / measure, f1 / measure, f2 / measure
    (sxx, sxy, sxz), (syx, syy, syz), (szx, szy, szz) = second
    # C = second - measure c c^T, symmetrised
    cxx = sxx - measure * gx * gx
    cyy = syy - measure * gy * gy
    czz = szz - measure * gz * gz
    cxy = 0.5 * (sxy + syx) - measure * gx * gy
    cyz = 0.5 * (syz + szy) - measure * gy * gz
    czx = 0.5 * (szx + sxz) - measure * gz * gx
    # Python floats: IEEE products as NumPy's, and an overflow is inf, never a warning
    ixx, iyy, izz = rho * (cyy + czz), rho * (czz + cxx), rho * (cxx + cyy)
    ixy, iyz, izx = rho * -cxy, rho * -cyz, rho * -czx
    if mass is not None and not all(map(math.isfinite, (ixx, iyy, izz, ixy, iyz, izx))):
        C = np.array([[cyy + czz, -cxy, -czx], [-cxy, czz + cxx, -cyz], [-czx, -cyz, cxx + cyy]])
        inertia = mass * (C / measure)   # rho = mass / measure overflowed: scale first
    else:
        inertia = np.array([[ixx, ixy, izx], [ixy, iyy, iyz], [izx, iyz, izz]])
    return np.array([reference[0] + gx, reference[1] + gy, reference[2] + gz]), inertia


def solid_sums_floats(out: np.ndarray):
    """:func:`solid_sums_moments` as Python floats, with the reference point and the offset
    ratio: ``(volume, first (3), second (3 rows of 3), reference (3) = out[11:14], kappa)``
    (the clean-solid kernel's ``out``; see :func:`offset_ratio`)."""
    s = out.tolist()
    a, b, c = _SOLID_SCALE
    volume = s[0] / a
    first = (s[1] / b, s[2] / b, s[3] / b)
    xx, yy, zz, yz, xy, xz = s[4] / c, s[5] / c, s[6] / c, s[8] / c, s[7] / c, s[9] / c
    second = ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
    return volume, first, second, (s[11], s[12], s[13]), _offset_ratio(volume, first, xx + yy + zz)
