"""Scalar kernels of :mod:`inertia.geometry.robust`, written once in plain Python.

The functions here use only scalar arithmetic, ``math`` and NumPy array indexing, so the
same source runs as plain Python (the slow but correct fallback) and compiled by numba
(:mod:`._robust_numba` wraps each with ``numba.njit``).  Nothing here imports numba.

Conventions: triangles are (3, 3) corner arrays or index triples into ``V`` (N, 3);
``eps`` is a length (the geometric tolerance, a tiny multiple of the mesh size).  Every
intersection test is *conservative*: it answers ``True`` ("may cut") whenever the
configuration is within ``eps`` of touching, so that ``False`` is safe to rely on.

Repetition here is deliberate: the kernels are written as flat scalar arithmetic (numba
compiles it to registers; a helper returning tuples, or a loop over the three coordinates,
costs measurably in the inner loops), so a few lines of the same shape recur between kernels
that differ in what they accumulate.  ``duplicates`` lists them; they stay.
"""

from __future__ import annotations

import math

import numpy as np

from ._robust_capk import solid_angle

__all__ = ["winding_rest", "grid_pairs"]

#: The compiled twin replaces this with ``numba.prange`` (parallel loops); plain Python runs them in order.
prange = range

FOUR_PI = 4.0 * math.pi
#: Contacts at angles below this (radians) from a triangle's edge count as along the edge.
ANGLE_TOL = 1e-12


def winding_rest(pts, owner, V, F, mult, out):
    """Generalised winding number at ``pts`` (P, 3), leaving out face ``owner[i]`` for point i.

    ``w(p) = sum_f mult_f Omega_f(p) / 4 pi`` with the Van Oosterom-Strackee solid angle
    ``tan(Omega / 2) = a . (b x c) / (|a||b||c| + (a.b)|c| + (b.c)|a| + (c.a)|b|)``,
    a, b, c the corners relative to p (positive seen from behind an outward face).
    """
    nf = F.shape[0]
    for i in range(pts.shape[0]):
        px = pts[i, 0]
        py = pts[i, 1]
        pz = pts[i, 2]
        o = owner[i]
        s = 0.0
        for f in range(nf):
            if f != o:
                s += mult[f] * solid_angle(V, F, f, px, py, pz)
        out[i] = s / FOUR_PI


def _plane_dist(A, B, out):
    """Signed distances (times |n_A|) of B's corners to A's plane into ``out`` (3,); return |n_A|."""
    ux = A[1, 0] - A[0, 0]
    uy = A[1, 1] - A[0, 1]
    uz = A[1, 2] - A[0, 2]
    vx = A[2, 0] - A[0, 0]
    vy = A[2, 1] - A[0, 1]
    vz = A[2, 2] - A[0, 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    for k in range(3):
        out[k] = nx * (B[k, 0] - A[0, 0]) + ny * (B[k, 1] - A[0, 1]) + nz * (B[k, 2] - A[0, 2])
    return math.sqrt(nx * nx + ny * ny + nz * nz)


def _one_side(d, tol):
    """True when all three distances are strictly (beyond ``tol``) on one side."""
    return (d[0] > tol and d[1] > tol and d[2] > tol) or (d[0] < -tol and d[1] < -tol and d[2] < -tol)


def _coplanar_overlap(A, B, eps):
    """2-D separating-axis test of two coplanar triangles (axes: in-plane edge normals)."""
    nx = (A[1, 1] - A[0, 1]) * (A[2, 2] - A[0, 2]) - (A[1, 2] - A[0, 2]) * (A[2, 1] - A[0, 1])
    ny = (A[1, 2] - A[0, 2]) * (A[2, 0] - A[0, 0]) - (A[1, 0] - A[0, 0]) * (A[2, 2] - A[0, 2])
    nz = (A[1, 0] - A[0, 0]) * (A[2, 1] - A[0, 1]) - (A[1, 1] - A[0, 1]) * (A[2, 0] - A[0, 0])
    for t in range(2):
        T = A if t == 0 else B
        for e in range(3):
            ex = T[(e + 1) % 3, 0] - T[e, 0]
            ey = T[(e + 1) % 3, 1] - T[e, 1]
            ez = T[(e + 1) % 3, 2] - T[e, 2]
            ax = ny * ez - nz * ey
            ay = nz * ex - nx * ez
            az = nx * ey - ny * ex
            la = math.sqrt(ax * ax + ay * ay + az * az)
            if la == 0.0:
                continue
            lo1 = hi1 = A[0, 0] * ax + A[0, 1] * ay + A[0, 2] * az
            lo2 = hi2 = B[0, 0] * ax + B[0, 1] * ay + B[0, 2] * az
            for k in range(1, 3):
                q1 = A[k, 0] * ax + A[k, 1] * ay + A[k, 2] * az
                q2 = B[k, 0] * ax + B[k, 1] * ay + B[k, 2] * az
                lo1 = min(lo1, q1)
                hi1 = max(hi1, q1)
                lo2 = min(lo2, q2)
                hi2 = max(hi2, q2)
            tol = eps * la
            if lo1 > hi2 + tol or lo2 > hi1 + tol:
                return False
    return True


def _line_interval(T, d, tol, Dx, Dy, Dz, out):
    """Interval of ``T`` (meeting the other plane) along the direction D; into ``out`` (2,)."""
    lo = math.inf
    hi = -math.inf
    for k in range(3):
        if abs(d[k]) <= tol:
            q = T[k, 0] * Dx + T[k, 1] * Dy + T[k, 2] * Dz
            lo = min(lo, q)
            hi = max(hi, q)
        j = (k + 1) % 3
        if (d[k] > tol and d[j] < -tol) or (d[k] < -tol and d[j] > tol):
            s = d[k] / (d[k] - d[j])
            x = T[k, 0] + s * (T[j, 0] - T[k, 0])
            y = T[k, 1] + s * (T[j, 1] - T[k, 1])
            z = T[k, 2] + s * (T[j, 2] - T[k, 2])
            q = x * Dx + y * Dy + z * Dz
            lo = min(lo, q)
            hi = max(hi, q)
    out[0] = lo
    out[1] = hi


def tris_cut(A, B, eps, scratch):
    """Conservative test: may triangles A and B (3, 3) share a point (closed sets, within eps)?

    Separating planes first (Moeller 1997): B strictly on one side of A's plane, or A of
    B's, means no contact; coplanar pairs use the 2-D separating-axis test; otherwise
    both triangles cut the line of the two planes in an interval, and they meet iff the
    intervals overlap.  ``scratch`` is a (8,) work array.
    """
    dB = scratch[0:3]
    dA = scratch[3:6]
    iv = scratch[6:8]
    nA = _plane_dist(A, B, dB)
    tolA = eps * nA
    if _one_side(dB, tolA):
        return False
    nB = _plane_dist(B, A, dA)
    tolB = eps * nB
    if _one_side(dA, tolB):
        return False
    if nA == 0.0 or nB == 0.0:
        return True      # degenerate triangle touching the other's plane: assume contact
    if abs(dB[0]) <= tolA and abs(dB[1]) <= tolA and abs(dB[2]) <= tolA:
        return _coplanar_overlap(A, B, eps)
    # direction of the planes' line, D = nA x nB (unnormalised; intervals scale alike)
    ux = A[1, 0] - A[0, 0]
    uy = A[1, 1] - A[0, 1]
    uz = A[1, 2] - A[0, 2]
    vx = A[2, 0] - A[0, 0]
    vy = A[2, 1] - A[0, 1]
    vz = A[2, 2] - A[0, 2]
    ax = uy * vz - uz * vy
    ay = uz * vx - ux * vz
    az = ux * vy - uy * vx
    ux = B[1, 0] - B[0, 0]
    uy = B[1, 1] - B[0, 1]
    uz = B[1, 2] - B[0, 2]
    vx = B[2, 0] - B[0, 0]
    vy = B[2, 1] - B[0, 1]
    vz = B[2, 2] - B[0, 2]
    bx = uy * vz - uz * vy
    by = uz * vx - ux * vz
    bz = ux * vy - uy * vx
    Dx = ay * bz - az * by
    Dy = az * bx - ax * bz
    Dz = ax * by - ay * bx
    lD = math.sqrt(Dx * Dx + Dy * Dy + Dz * Dz)
    if lD == 0.0:
        return True
    _line_interval(A, dA, tolB, Dx, Dy, Dz, iv)
    a0 = iv[0]
    a1 = iv[1]
    _line_interval(B, dB, tolA, Dx, Dy, Dz, iv)
    tol = 2.0 * eps * lD
    return a0 <= iv[1] + tol and iv[0] <= a1 + tol


def _load(V, F, f, T):
    for k in range(3):
        for c in range(3):
            T[k, c] = V[F[f, k], c]


def faces_cut(V, F, f, g, eps, A, B, scratch):
    """Does face g cut the interior of face f (or vice versa)?  Shared corners handled.

    * 3 shared corners (a duplicate): ``True``;
    * a shared edge: only a fold (coplanar, both opposite corners on the same side);
    * a shared corner v: the planes' line through v meets both triangles in segments
      starting at v; they cut iff those segments point the same way (conservatively:
      unless one triangle lies strictly on one side of the other's plane);
    * no shared corner: :func:`tris_cut`.

    One kernel that reads better whole (compiled by numba: its phases share scalar state).
    """
    _load(V, F, f, A)
    _load(V, F, g, B)
    ns = 0
    sa = -1
    sb = -1
    for i in range(3):
        for j in range(3):
            if F[f, i] == F[g, j]:
                ns += 1
                sa = i
                sb = j
    if ns == 0:
        return tris_cut(A, B, eps, scratch)
    if ns == 3:
        return True
    dB = scratch[0:3]
    dA = scratch[3:6]
    nA = _plane_dist(A, B, dB)
    nB = _plane_dist(B, A, dA)
    if nA == 0.0 or nB == 0.0:
        return True
    tolA = eps * nA
    tolB = eps * nB
    if ns == 2:
        # corners not on the shared edge
        oa = 3 - sum_shared(F, f, g)
        ob = 3 - sum_shared(F, g, f)
        if abs(dB[ob]) > tolA:
            return False        # not coplanar: they meet along the edge only
        # coplanar: a fold when the opposite corners are on the same side of the edge
        i0 = (oa + 1) % 3
        i1 = (oa + 2) % 3
        ex = A[i1, 0] - A[i0, 0]
        ey = A[i1, 1] - A[i0, 1]
        ez = A[i1, 2] - A[i0, 2]
        s1 = _side(A, i0, ex, ey, ez, A[oa, 0], A[oa, 1], A[oa, 2])
        s2 = _side(A, i0, ex, ey, ez, B[ob, 0], B[ob, 1], B[ob, 2])
        return s1 * s2 >= 0.0
    # one shared corner: sa in A, sb in B
    dB[sb] = 0.0
    dA[sa] = 0.0
    b1 = (sb + 1) % 3
    b2 = (sb + 2) % 3
    a1 = (sa + 1) % 3
    a2 = (sa + 2) % 3
    if (dB[b1] > tolA and dB[b2] > tolA) or (dB[b1] < -tolA and dB[b2] < -tolA):
        return False
    if (dA[a1] > tolB and dA[a2] > tolB) or (dA[a1] < -tolB and dA[a2] < -tolB):
        return False
    if abs(dB[b1]) <= tolA and abs(dB[b2]) <= tolA:
        return _sectors_overlap(A, sa, B, sb, eps)
    # the planes' line L through v meets each triangle in a segment from v along +-D
    # (or only in v): they cut iff some direction lies in both closed sectors at v and
    # strictly inside at least one (contact along an edge line does not cut an interior)
    ux = A[a1, 0] - A[sa, 0]
    uy = A[a1, 1] - A[sa, 1]
    uz = A[a1, 2] - A[sa, 2]
    vx = A[a2, 0] - A[sa, 0]
    vy = A[a2, 1] - A[sa, 1]
    vz = A[a2, 2] - A[sa, 2]
    nax = uy * vz - uz * vy
    nay = uz * vx - ux * vz
    naz = ux * vy - uy * vx
    ux = B[b1, 0] - B[sb, 0]
    uy = B[b1, 1] - B[sb, 1]
    uz = B[b1, 2] - B[sb, 2]
    vx = B[b2, 0] - B[sb, 0]
    vy = B[b2, 1] - B[sb, 1]
    vz = B[b2, 2] - B[sb, 2]
    nbx = uy * vz - uz * vy
    nby = uz * vx - ux * vz
    nbz = ux * vy - uy * vx
    Dx = nay * nbz - naz * nby
    Dy = naz * nbx - nax * nbz
    Dz = nax * nby - nay * nbx
    if Dx == 0.0 and Dy == 0.0 and Dz == 0.0:
        return True
    for sgn in (-1.0, 1.0):
        ca, sa_ = _sector_flags(A, sa, sgn * Dx, sgn * Dy, sgn * Dz, nax, nay, naz)
        cb, sb_ = _sector_flags(B, sb, sgn * Dx, sgn * Dy, sgn * Dz, nbx, nby, nbz)
        if ca and cb and (sa_ or sb_):
            return True
    return False


def _sector_flags(T, s, dx, dy, dz, nx, ny, nz):
    """Direction d in T's sector at corner s (T's normal n): ``(in the closed sector, strictly inside)``.

    Angles below ANGLE_TOL rad count as on the sector's edge (closed: inside; strict: not).
    """
    p = (s + 1) % 3
    q = (s + 2) % 3
    e1x = T[p, 0] - T[s, 0]
    e1y = T[p, 1] - T[s, 1]
    e1z = T[p, 2] - T[s, 2]
    e2x = T[q, 0] - T[s, 0]
    e2y = T[q, 1] - T[s, 1]
    e2z = T[q, 2] - T[s, 2]
    c1 = (e1y * dz - e1z * dy) * nx + (e1z * dx - e1x * dz) * ny + (e1x * dy - e1y * dx) * nz
    c2 = (dy * e2z - dz * e2y) * nx + (dz * e2x - dx * e2z) * ny + (dx * e2y - dy * e2x) * nz
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    ld = math.sqrt(dx * dx + dy * dy + dz * dz)
    t1 = ANGLE_TOL * ln * ld * math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
    t2 = ANGLE_TOL * ln * ld * math.sqrt(e2x * e2x + e2y * e2y + e2z * e2z)
    return (c1 >= -t1 and c2 >= -t2), (c1 > t1 and c2 > t2)


def sum_shared(F, f, g):
    """Sum of the corner positions (0, 1, 2) of face f that are also corners of face g."""
    s = 0
    for i in range(3):
        for j in range(3):
            if F[f, i] == F[g, j]:
                s += i
    return s


def _side(A, i0, ex, ey, ez, px, py, pz):
    """In-plane side of point p relative to the edge from A[i0] along e (sign of a dot with A's normal)."""
    nx = (A[1, 1] - A[0, 1]) * (A[2, 2] - A[0, 2]) - (A[1, 2] - A[0, 2]) * (A[2, 1] - A[0, 1])
    ny = (A[1, 2] - A[0, 2]) * (A[2, 0] - A[0, 0]) - (A[1, 0] - A[0, 0]) * (A[2, 2] - A[0, 2])
    nz = (A[1, 0] - A[0, 0]) * (A[2, 1] - A[0, 1]) - (A[1, 1] - A[0, 1]) * (A[2, 0] - A[0, 0])
    qx = px - A[i0, 0]
    qy = py - A[i0, 1]
    qz = pz - A[i0, 2]
    cx = ey * qz - ez * qy
    cy = ez * qx - ex * qz
    cz = ex * qy - ey * qx
    return cx * nx + cy * ny + cz * nz


def _sectors_overlap(A, sa, B, sb, eps):
    """Coplanar triangles sharing corner v: do their angular sectors at v overlap (beyond ANGLE_TOL rad)?

    Sector of (v, p, q) is the cone of directions alpha (p - v) + beta (q - v), alpha, beta >= 0.
    The convex sectors overlap with positive angle iff an edge direction of one lies
    strictly inside the other, or both have the same bisector direction inside each other.
    """
    nx = (A[1, 1] - A[0, 1]) * (A[2, 2] - A[0, 2]) - (A[1, 2] - A[0, 2]) * (A[2, 1] - A[0, 1])
    ny = (A[1, 2] - A[0, 2]) * (A[2, 0] - A[0, 0]) - (A[1, 0] - A[0, 0]) * (A[2, 2] - A[0, 2])
    nz = (A[1, 0] - A[0, 0]) * (A[2, 1] - A[0, 1]) - (A[1, 1] - A[0, 1]) * (A[2, 0] - A[0, 0])
    for t in range(2):
        T = A if t == 0 else B
        s = sa if t == 0 else sb
        U = B if t == 0 else A
        su = sb if t == 0 else sa
        # directions to test: U's two edges from v and U's bisector (centroid direction)
        for k in range(3):
            if k < 2:
                j = (su + 1 + k) % 3
                dx = U[j, 0] - U[su, 0]
                dy = U[j, 1] - U[su, 1]
                dz = U[j, 2] - U[su, 2]
            else:
                dx = 0.5 * (U[(su + 1) % 3, 0] + U[(su + 2) % 3, 0]) - U[su, 0]
                dy = 0.5 * (U[(su + 1) % 3, 1] + U[(su + 2) % 3, 1]) - U[su, 1]
                dz = 0.5 * (U[(su + 1) % 3, 2] + U[(su + 2) % 3, 2]) - U[su, 2]
            if _strictly_inside(T, s, dx, dy, dz, nx, ny, nz):
                return True
    return False


def _strictly_inside(T, s, dx, dy, dz, nx, ny, nz):
    """Direction d strictly (beyond ANGLE_TOL rad) inside T's sector at corner s (normal n of the common plane)."""
    p = (s + 1) % 3
    q = (s + 2) % 3
    e1x = T[p, 0] - T[s, 0]
    e1y = T[p, 1] - T[s, 1]
    e1z = T[p, 2] - T[s, 2]
    e2x = T[q, 0] - T[s, 0]
    e2y = T[q, 1] - T[s, 1]
    e2z = T[q, 2] - T[s, 2]
    # orientation of the sector relative to n
    o = (e1y * e2z - e1z * e2y) * nx + (e1z * e2x - e1x * e2z) * ny + (e1x * e2y - e1y * e2x) * nz
    c1 = (e1y * dz - e1z * dy) * nx + (e1z * dx - e1x * dz) * ny + (e1x * dy - e1y * dx) * nz
    c2 = (dy * e2z - dz * e2y) * nx + (dz * e2x - dx * e2z) * ny + (dx * e2y - dy * e2x) * nz
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    ld = math.sqrt(dx * dx + dy * dy + dz * dz)
    l1 = math.sqrt(e1x * e1x + e1y * e1y + e1z * e1z)
    l2 = math.sqrt(e2x * e2x + e2y * e2y + e2z * e2z)
    if o < 0.0:
        c1 = -c1
        c2 = -c2
    return c1 > ANGLE_TOL * ln * ld * l1 and c2 > ANGLE_TOL * ln * ld * l2


def grid_pairs(V, F, lo, hi, small, cert, mode, origin, cell, eps, out):
    """Pairs (f, g), f < g, of faces whose boxes overlap and that may cut each other (:func:`faces_cut`).

    Broad phase: a uniform grid of cubes of side ``cell``, bucketed by a counting sort of
    hashed cell keys (cells may share a bucket).  ``mode`` 0 registers the faces with
    ``small[f]`` and reports pairs among them; mode 1 registers every face and reports the
    pairs with at least one face not ``small`` (call it with a coarser cell).  Faces sharing
    a vertex v with ``cert[v]`` are skipped: they cannot cut each other
    (:func:`._robust_topo.vertex_pass`).  A pair is examined in the bucket of the cell
    holding the low corner of the intersection of the two boxes only (both faces are
    registered in that cell); a pair may still come twice when cells share a bucket.
    The buckets are scanned in 64 chunks (in parallel when compiled).

    Writes up to ``len(out)`` pairs into ``out`` (K, 2) and returns how many there are in
    all (call again with more room if larger).
    """
    start, who, corner, box, ilo = _grid_build(F, lo, hi, small, mode, origin, cell, eps)
    T = start.shape[0] - 1
    kmax = 1
    for b in range(T):
        kmax = max(kmax, start[b + 1] - start[b])
    n_chunks = 64
    counts = np.zeros(n_chunks, np.int64)
    buf = _scan_chunks(V, F, lo, hi, eps, start, who, corner, box, ilo, cert, small, mode, kmax, n_chunks, 64,
                       counts)
    need = 0
    for ch in range(n_chunks):
        need = max(need, counts[ch])
    if need > 64:
        buf = _scan_chunks(V, F, lo, hi, eps, start, who, corner, box, ilo, cert, small, mode, kmax, n_chunks, need,
                           counts)
    cnt = 0
    for ch in range(n_chunks):
        for i in range(counts[ch]):
            if cnt < out.shape[0]:
                out[cnt, 0] = buf[ch, i, 0]
                out[cnt, 1] = buf[ch, i, 1]
            cnt += 1
    return cnt


def _scan_chunks(V, F, lo, hi, eps, start, who, corner, box, ilo, cert, small, mode, kmax, n_chunks, cap, counts):
    """Run :func:`_grid_chunk` on ``n_chunks`` ranges of buckets (in parallel when compiled);
    returns their pairs (n_chunks, cap, 2), ``counts`` how many each found."""
    T = start.shape[0] - 1
    buf = np.empty((n_chunks, cap, 2), np.int64)
    for ch in prange(n_chunks):
        counts[ch] = _grid_chunk(V, F, lo, hi, eps, start, who, corner, box, ilo, cert, small, mode,
                                 T * ch // n_chunks, T * (ch + 1) // n_chunks, kmax, buf[ch])
    return buf


def _grid_build(F, lo, hi, small, mode, origin, cell, eps):
    """The grid's buckets: ``start`` (T + 1,) and per entry its face, corners and box.

    The entries keep copies of their faces' boxes (float32, relative to ``origin``, widened
    so that they hold the boxes) and corners, so that a bucket is read in sequence.
    """
    nf = F.shape[0]
    ilo = np.empty((nf, 3), np.int64)
    ihi = np.empty((nf, 3), np.int64)
    n_entries = 0
    for f in range(nf):
        if mode == 0 and not small[f]:
            continue
        span = 1
        for c in range(3):
            ilo[f, c] = int(math.floor((lo[f, c] - eps - origin[c]) / cell))
            ihi[f, c] = int(math.floor((hi[f, c] + eps - origin[c]) / cell))
            span *= ihi[f, c] - ilo[f, c] + 1
        n_entries += span
    T = 16
    while T < n_entries:
        T *= 2
    mask = T - 1
    start = np.zeros(T + 1, np.int32)
    for f in range(nf):
        if mode == 0 and not small[f]:
            continue
        for i in range(ilo[f, 0], ihi[f, 0] + 1):
            for j in range(ilo[f, 1], ihi[f, 1] + 1):
                for k in range(ilo[f, 2], ihi[f, 2] + 1):
                    start[(((i * 73856093) ^ (j * 19349663) ^ (k * 83492791)) & mask) + 1] += 1
    for b in range(T):
        start[b + 1] += start[b]
    fill = start[:T].copy()
    who = np.empty(n_entries, np.int32)
    corner = np.empty((n_entries, 3), np.int32)
    box = np.empty((n_entries, 6), np.float32)
    grow = np.float32(2.4e-7)      # float32 rounds to nearest: widen so the copy holds the box
    for f in range(nf):
        if mode == 0 and not small[f]:
            continue
        b0 = np.float32(lo[f, 0] - eps - origin[0])
        b1 = np.float32(lo[f, 1] - eps - origin[1])
        b2 = np.float32(lo[f, 2] - eps - origin[2])
        b3 = np.float32(hi[f, 0] + eps - origin[0])
        b4 = np.float32(hi[f, 1] + eps - origin[1])
        b5 = np.float32(hi[f, 2] + eps - origin[2])
        b0 -= abs(b0) * grow
        b1 -= abs(b1) * grow
        b2 -= abs(b2) * grow
        b3 += abs(b3) * grow
        b4 += abs(b4) * grow
        b5 += abs(b5) * grow
        for i in range(ilo[f, 0], ihi[f, 0] + 1):
            for j in range(ilo[f, 1], ihi[f, 1] + 1):
                for k in range(ilo[f, 2], ihi[f, 2] + 1):
                    b = ((i * 73856093) ^ (j * 19349663) ^ (k * 83492791)) & mask
                    e = fill[b]
                    who[e] = f
                    corner[e, 0] = F[f, 0]
                    corner[e, 1] = F[f, 1]
                    corner[e, 2] = F[f, 2]
                    box[e, 0] = b0
                    box[e, 1] = b1
                    box[e, 2] = b2
                    box[e, 3] = b3
                    box[e, 4] = b4
                    box[e, 5] = b5
                    fill[b] += 1
    return start, who, corner, box, ilo


def _grid_chunk(V, F, lo, hi, eps, start, who, corner, box, ilo, cert, small, mode, b_start, b_end, kmax, out):
    """Cutting pairs found in buckets ``b_start..b_end-1`` into ``out``; returns how many
    (more than ``len(out)``: call again with more room).

    The box test and the certified-corner test are branch-free; their survivors are
    collected before the rarer tests: the low-corner bucket, then :func:`faces_cut`.  In
    mode 1 each big face scans its whole bucket.
    """
    mask = start.shape[0] - 2
    hits = np.empty(kmax, np.int64)
    A = np.empty((3, 3))
    B = np.empty((3, 3))
    scratch = np.empty(8)
    cnt = 0
    for b in range(b_start, b_end):
        e1 = start[b + 1]
        for ea in range(start[b], e1):
            f = who[ea]
            if mode == 1 and small[f]:
                continue            # mode 1: pairs with a big face, scanned from that face
            x0 = box[ea, 0]
            y0 = box[ea, 1]
            z0 = box[ea, 2]
            x1 = box[ea, 3]
            y1 = box[ea, 4]
            z1 = box[ea, 5]
            c0 = corner[ea, 0]
            c1 = corner[ea, 1]
            c2 = corner[ea, 2]
            k0 = cert[c0]
            k1 = cert[c1]
            k2 = cert[c2]
            nh = 0
            for eb in range(start[b] if mode == 1 else ea + 1, e1):
                g0 = corner[eb, 0]
                g1 = corner[eb, 1]
                g2 = corner[eb, 2]
                hits[nh] = eb
                # boxes overlap and no certified common corner (branch-free)
                nh += ((box[eb, 0] <= x1) & (box[eb, 3] >= x0) & (box[eb, 1] <= y1) & (box[eb, 4] >= y0)
                       & (box[eb, 2] <= z1) & (box[eb, 5] >= z0)
                       & ~((k0 & ((c0 == g0) | (c0 == g1) | (c0 == g2))) | (k1 & ((c1 == g0) | (c1 == g1) | (c1 == g2)))
                           | (k2 & ((c2 == g0) | (c2 == g1) | (c2 == g2)))))
            for h in range(nh):
                eb = hits[h]
                g = who[eb]
                if g == f or (mode == 1 and not small[g] and g < f):
                    continue
                i = max(ilo[f, 0], ilo[g, 0])
                j = max(ilo[f, 1], ilo[g, 1])
                k = max(ilo[f, 2], ilo[g, 2])
                if (((i * 73856093) ^ (j * 19349663) ^ (k * 83492791)) & mask) != b:
                    continue
                if _boxes_apart(lo, hi, f, g, eps) or not faces_cut(V, F, f, g, eps, A, B, scratch):
                    continue
                if cnt < out.shape[0]:
                    out[cnt, 0] = min(f, g)
                    out[cnt, 1] = max(f, g)
                cnt += 1
    return cnt


def _boxes_apart(lo, hi, f, g, eps):
    for c in range(3):
        if lo[g, c] > hi[f, c] + eps or lo[f, c] > hi[g, c] + eps:
            return True
    return False
