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
(xx, yy, zz, xy, yz, zx).  Two backends compute the same per-face terms:

* ``"numpy"``: faces in chunks of :data:`NUMPY_CHUNK`, gathered into one cache-sized
  (3, 4, chunk) block (the corners a, b, c and their sum s, one row per coordinate);
  the 6 entries are 6 dot products of length 4 x chunk, so no (F, 3, 3) temporaries.
* ``"numba"`` (:mod:`._integrals_numba`): one pass over the faces, no temporaries,
  blocked summation.  Optional; ``backend="auto"`` uses it when numba imports and the
  NumPy backend otherwise.

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
   (pairwise/BLAS blocks in NumPy, blocks of 256 faces in numba).  So, with gamma a
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

   For contrast, trimesh expands about the origin: for a unit cube at d = 1e7,
   K ~ 1e21 and its central tensor comes out wrong by ~2e5 relative, with negative
   moments (see the tests).

4. *Choice of p; one pass or two.*  p is the bounding-box center (exact for the
   translated cube: its coordinates are then exact binary fractions).  For compact
   bodies kappa is small -- 0 for centrally symmetric bodies, 0.19 for a cone, and
   0.00 to 0.07 for the real meshes of the test data -- and one pass is enough.
   kappa and K are large only for lopsided bodies (a ball with a long spike: the box
   center lies far out on the spike) or a p far outside the body.  As rho_f about p is
   at most rho_f about the COM plus |g|, K about p exceeds K about the COM by roughly
   (1 + sqrt(kappa))^3 at most.  So after the first pass kappa is computed from the
   sums (free), and when it exceeds :data:`REFINE_KAPPA` a second pass is made about
   p' = p + g, the computed COM (whose error is a tiny fraction of k), which brings
   kappa to ~0 and K to its value about the COM.  Measured on a unit cube with a
   1e-6 thick needle 1e3 long: one pass 7e-8 relative error, two passes 2e-16.
   (What no single expansion point can fix: a small part far from both p and the COM
   keeps its own (d / L)^3; a 1e-3 cube 1e3 away from a unit cube still gives 5e-13.)

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

import numpy as np

from .._core.errors import InputError, MissingDependencyError

#: Second pass about the computed COM when ``kappa = |COM - p|^2 / k^2`` exceeds this
#: (see "Error analysis", item 4).  Below it, expanding about the box center costs at
#: most a factor ~(1 + 2)^3 = 27 in rounding error over expanding about the COM;
#: compact bodies (kappa < 0.2 measured) never pay for the second pass.
REFINE_KAPPA = 4.0

#: At most this many refinement passes (one is enough unless the first pass was
#: made about a point so far off that its COM estimate is itself inaccurate).
MAX_REFINE = 2

#: Faces per chunk of the NumPy backend.  The (3, 4, chunk) working blocks (192 KiB)
#: stay in cache, and every BLAS call stays below OpenBLAS's threading thresholds
#: (dot: n <= 10000, the 6 dots here are 4 x 2048 long; gemv: m n < 9216), so the
#: reductions run on the calling thread.  Threaded BLAS on busy cores was measured 60x
#: slower (a 131072-long dot on 2 loaded cores: 1.8 ms against 30 us single-threaded),
#: and a thread count that varies between machines would also vary the summation order.
NUMPY_CHUNK = 2048

_BACKENDS = ("auto", "numpy", "numba")

# (3, 3) symmetric matrix from the sums xx, yy, zz, xy, yz, zx stored at out[4:10]
_SYM = np.array([[4, 7, 9], [7, 5, 8], [9, 8, 6]])
# divisors of (measure, first, second) sums: solid det/6, det s/24, det Q/120;
# shell w/2, w s/6, w Q/24 with w = twice the face area
_SOLID_SCALE = (6.0, 24.0, 120.0)
_SHELL_SCALE = (2.0, 6.0, 24.0)


# ---------------------------------------------------------------------- NumPy backend
def reference_point(vertices: np.ndarray) -> np.ndarray:
    """Center of the axis-aligned bounding box (3,) m of ``vertices`` (V, 3) m.

    Inside or near the body, cheap, deterministic, and equivariant under translation.
    Column by column, because ``min(axis=0)`` over an (V, 3) array is ~20x slower.
    """
    v = np.asarray(vertices, dtype=np.float64)
    return np.array([0.5 * (v[:, k].min() + v[:, k].max()) for k in range(3)])


def _first_bad_face(faces: np.ndarray, n_vertices: int) -> int:
    """Index of the first face holding a vertex index outside [0, n_vertices)."""
    bad = np.any((faces < 0) | (faces >= n_vertices), axis=1)
    return int(np.argmax(bad))


def _numpy_sums(vertices, faces, p, out, shell):
    """NumPy version of ``_integrals_numba.solid_sums`` / ``shell_sums`` (same ``out`` layout)."""
    n_faces = faces.shape[0]
    out[:] = 0.0
    if n_faces == 0:
        return -1
    if faces.min() < 0 or faces.max() >= vertices.shape[0]:
        return _first_bad_face(faces, vertices.shape[0])
    # local coordinates, one row per coordinate so that gathers and products are contiguous
    yT = (vertices - p).T.copy()
    m = 0
    for start in range(0, n_faces, NUMPY_CHUNK):
        fc = faces[start:start + NUMPY_CHUNK]
        if fc.shape[0] != m:
            m = fc.shape[0]
            G = np.empty((3, 4, m))      # G[:, 0:3] corners a, b, c; G[:, 3] their sum s
            W = np.empty((3, 4, m))      # G weighted by the per-face weight
            w = np.empty(m)
        np.take(yT, fc.T, axis=1, out=G[:, :3], mode="clip")   # indices checked above
        ax, bx, cx = G[0, 0], G[0, 1], G[0, 2]
        ay, by, cy = G[1, 0], G[1, 1], G[1, 2]
        az, bz, cz = G[2, 0], G[2, 1], G[2, 2]
        # edges u = b - a, v = c - a; n = u x v is twice the area vector
        ux, uy, uz = bx - ax, by - ay, bz - az
        vx, vy, vz = cx - ax, cy - ay, cz - az
        nx = uy * vz
        nx -= uz * vy
        ny = uz * vx
        ny -= ux * vz
        nz = ux * vy
        nz -= uy * vx
        if shell:
            # w = |n| = twice the area
            np.multiply(nx, nx, out=w)
            w += ny * ny
            w += nz * nz
            np.sqrt(w, out=w)
        else:
            # w = det = a . (b x c) = a . n (the edge form: error relative to |a| |n|)
            np.multiply(ax, nx, out=w)
            w += ay * ny
            w += az * nz
        np.add(G[:, 0], G[:, 1], out=G[:, 3])
        G[:, 3] += G[:, 2]
        out[0] += w.sum()
        out[1:4] += G[:, 3] @ w
        np.multiply(G, w, out=W)
        P = G.reshape(3, 4 * m)
        Q = W.reshape(3, 4 * m)
        # sum_f w (a a^T + b b^T + c c^T + s s^T)_ij = row i of W . row j of G
        out[4] += Q[0] @ P[0]
        out[5] += Q[1] @ P[1]
        out[6] += Q[2] @ P[2]
        out[7] += Q[0] @ P[1]
        out[8] += Q[1] @ P[2]
        out[9] += Q[2] @ P[0]
    return -1


class _Kernels:
    """One backend: ``center(v) -> (3,)``, ``solid(v, f, p, out) -> int``, ``shell(...) -> int``."""

    __slots__ = ("name", "center", "solid", "shell")

    def __init__(self, name, center, solid, shell):
        self.name, self.center, self.solid, self.shell = name, center, solid, shell


_NUMPY = _Kernels("numpy", reference_point,
                  lambda v, f, p, out: _numpy_sums(v, f, p, out, False),
                  lambda v, f, p, out: _numpy_sums(v, f, p, out, True))

def _numba_kernels(required: bool, work: int = 0):
    """The numba kernels; None for the NumPy path (numba missing, or the rule of
    :func:`inertia._core.compiled.kernels` says so), or raise if ``required`` and numba is missing."""
    from .._core.compiled import kernels

    if required:
        try:
            from . import _integrals_numba as nbk
        except ImportError as exc:
            raise MissingDependencyError(
                "backend='numba' needs numba, which cannot be imported "
                f"({type(exc).__name__}: {exc}); install it with pip install 'inertia[fast]' or use "
                "backend='numpy'") from None
    else:
        nbk = kernels("inertia.geometry._integrals_numba", work=work)
        if nbk is None:
            return None

    def center(v, _bbox=nbk.bbox_center):
        p = np.empty(3)
        _bbox(v, p)
        return p

    return _Kernels("numba", center, nbk.solid_sums, nbk.shell_sums)


def _kernels(backend: str, work: int = 0) -> _Kernels:
    if backend == "auto":
        return _numba_kernels(required=False, work=work) or _NUMPY
    if backend == "numpy":
        return _NUMPY
    if backend == "numba":
        return _numba_kernels(required=True)
    raise InputError(f"backend must be one of {_BACKENDS}, got {backend!r}")


# ---------------------------------------------------------------------- driver
def _mesh_arrays(vertices, faces):
    """Validated ``(vertices (V, 3) float64, faces (F, 3) int32/int64)``, both C-contiguous."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    if v.ndim != 2 or v.shape[1] != 3:
        raise InputError(f"vertices must have shape (V, 3), got {v.shape}")
    if v.shape[0] == 0:
        raise InputError("vertices is empty: a mesh needs at least one vertex")
    f = np.asarray(faces)
    if f.ndim != 2 or f.shape[1] != 3:
        raise InputError(f"faces must have shape (F, 3), got {f.shape}")
    if f.dtype != np.int64 and f.dtype != np.int32:
        if f.dtype.kind not in "iu" and f.size:
            raise InputError(f"faces must hold integer vertex indices, got dtype {f.dtype}")
        f = f.astype(np.intp)
    return v, np.ascontiguousarray(f)


def solid_sums_moments(out: np.ndarray):
    """``(volume, first (3,), second (3, 3))`` from the unscaled sums of a solid kernel
    (``out[:10]`` as ``solid_sums`` writes them)."""
    return float(out[0] / _SOLID_SCALE[0]), out[1:4] / _SOLID_SCALE[1], out[_SYM] / _SOLID_SCALE[2]


def _sums(kernel, v, f, p, scale):
    """Run one kernel pass about ``p``; return ``(measure, first (3,), second (3, 3))``."""
    out = np.empty(10)
    bad = kernel(v, f, p, out)
    if bad >= 0:
        raise InputError(f"face {bad} = {f[bad].tolist()} holds a vertex index outside [0, {v.shape[0]})")
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


def _integrals(kernels, kernel, v, f, reference, scale):
    """Integrals about the box center (or the COM, item 4 of the error analysis), moved to ``reference``."""
    if reference is not None:
        r = np.asarray(reference, dtype=np.float64)
        if r.shape != (3,) or not np.isfinite(r).all():
            raise InputError(f"reference must be a finite (3,) point, got {reference!r}")
    p = kernels.center(v)
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


def solid_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None,
                    *, backend: str = "auto"):
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
    backend : {"auto", "numpy", "numba"}
        ``"auto"`` uses numba when it can be imported, NumPy otherwise; ``"numba"``
        without numba raises :class:`~inertia.errors.MissingDependencyError`.

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
    kernels = _kernels(backend, len(f))
    return _integrals(kernels, kernels.solid, v, f, reference, _SOLID_SCALE)


def shell_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None,
                    *, backend: str = "auto"):
    """Surface integrals of a triangle mesh (orientation-free; need not be closed).

    Same parameters as :func:`solid_integrals`.  Returns ``(area m^2,
    int (x - r) dA (3,) m^3, int (x - r)(x - r)^T dA (3, 3) m^4, r (3,) m)``.
    """
    v, f = _mesh_arrays(vertices, faces)
    kernels = _kernels(backend, len(f))
    return _integrals(kernels, kernels.shell, v, f, reference, _SHELL_SCALE)


def central_inertia(measure: float, first: np.ndarray, second: np.ndarray, reference: np.ndarray, density: float):
    """Turn integrals about ``reference`` into the COM and the inertia about it, for a uniform ``density``.

    Parameters
    ----------
    measure : float, volume m^3 (or area m^2 for a shell).
    first : (3,) float, ``int (x - r)``.
    second : (3, 3) float, ``int (x - r)(x - r)^T``.
    reference : (3,) float, m, the point r.
    density : float, kg/m^3 (kg/m^2 for a shell).

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
                               float(density))


def central_from_floats(measure: float, first, second, reference, rho: float):
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
    inertia = np.array([[rho * (cyy + czz), -rho * cxy, -rho * czx],
                        [-rho * cxy, rho * (czz + cxx), -rho * cyz],
                        [-rho * czx, -rho * cyz, rho * (cxx + cyy)]])
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
