"""Numba kernels of the self-crossing check of one closed shell (the NumPy twins are in
:mod:`inertia.geometry.self_crossing`; tests compare them).

* :func:`star_certificate`: every face sees the point ``c`` strictly on its inner side, and a
  ray from ``c`` crosses the surface exactly once.  Then the radial projection from ``c`` is
  one-to-one, so no two faces can cross: a proof in one pass over the faces.
* :func:`first_crossing`: the face-pair search for the shells the certificate cannot prove
  (a torus, a T-handle): a uniform grid (cells hashed, faces filed per cell by a counting
  sort, with copies of their boxes), each pair of faces whose boxes overlap tested once (in
  the lowest cell their boxes share), pairs that share an edge skipped (they cannot cross), as
  are pairs around a vertex :func:`certified_fans` proves, and the exact test of
  :func:`inertia.geometry.intersections.crossing`: an edge of one face strictly through the
  interior of the other.

Written as flat scalar arithmetic (numba compiles it to registers), so some lines repeat.
"""

from __future__ import annotations

import numba as nb
import numpy as np

from ._heightfield_numba import CELL_EDGES, box_and_median_edge, face_normal, face_twins, unproved_faces, vertex_slots

_JIT = dict(cache=True, nogil=True, boundscheck=False)

#: shells of fewer faces are searched whole (the cell proof of :mod:`._heightfield_numba` pays
#: from about this size)
HEIGHTFIELD_MIN_FACES = 256
#: the faces the cell proof leaves are searched without the fans' certificates while they are
#: fewer than 1 in this many (measured break-even on jittered tori: about 1 in 20)
KEPT_WITHOUT_FANS = 16

#: kernels whose cached machine code shows the module warm (:mod:`inertia._core.compiled`)
WARM_PROBE = ("star_certificate", "find_crossing")

# the clean-solid pass's per-face star test (C++: src/ext/integrals/star.hpp)
#: the certificate's ray (the first direction of ``_selfcross_numba.star_certificate``)
STAR_RAY = (0.2672612419124244, 0.5345224838248488, 0.8017837257372732)
#: the certificate's tolerances (``self_crossing.STAR_RTOL`` and the ray's edge margin)
STAR_RTOL = 1e-9


@nb.njit(**_JIT)
def star_face(ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, nx, ny, nz, d, star):
    """One face of the star certificate from p (a = corner - p, e1, e2 the edges, n = e1 x e2,
    d = a . n): p strictly inside its plane, and whether the ray leaves through it."""
    if not (d > 0.0 and d * d > STAR_RTOL * STAR_RTOL * (ax * ax + ay * ay + az * az) * (nx * nx + ny * ny + nz * nz)):
        star[1] = 1
        return
    ux, uy, uz = STAR_RAY
    un = ux * nx + uy * ny + uz * nz
    if un <= 0.0:
        return                            # the ray cannot leave through a face turned away
    # Moller-Trumbore with det = -un < 0: barycentrics s = ns / det, w = nw / det, no division
    px = uy * e2z - uz * e2y
    py = uz * e2x - ux * e2z
    pz = ux * e2y - uy * e2x
    ns = ax * px + ay * py + az * pz      # = (-a . p) * -1: s = ns / un
    qx = -ay * e1z + az * e1y
    qy = -az * e1x + ax * e1z
    qz = -ax * e1y + ay * e1x
    nw = -(ux * qx + uy * qy + uz * qz)   # w = nw / un
    m = 1e-9 * un
    if ns < -m or nw < -m or ns + nw > un + m:
        return
    if ns < m or nw < m or ns + nw > un - m:
        star[1] = 2                       # through an edge or a vertex, to rounding
        return
    star[0] += 1



@nb.njit(**_JIT)
def _ray_hits(vertices, faces, c, ux, uy, uz, rtol):
    """Faces the ray from c along u crosses (Moller-Trumbore); -1 when a hit is too close to an
    edge or a vertex to be counted safely."""
    hits = 0
    for t in range(faces.shape[0]):
        ia = faces[t, 0]
        ib = faces[t, 1]
        ic = faces[t, 2]
        ax = vertices[ia, 0] - c[0]
        ay = vertices[ia, 1] - c[1]
        az = vertices[ia, 2] - c[2]
        e1x = vertices[ib, 0] - c[0] - ax
        e1y = vertices[ib, 1] - c[1] - ay
        e1z = vertices[ib, 2] - c[2] - az
        e2x = vertices[ic, 0] - c[0] - ax
        e2y = vertices[ic, 1] - c[1] - ay
        e2z = vertices[ic, 2] - c[2] - az
        px = uy * e2z - uz * e2y
        py = uz * e2x - ux * e2z
        pz = ux * e2y - uy * e2x
        det = e1x * px + e1y * py + e1z * pz
        if det == 0.0:
            continue                     # the ray runs parallel to the face (it sees c strictly inside)
        s = (-ax * px - ay * py - az * pz) / det
        qx = -ay * e1z + az * e1y
        qy = -az * e1x + ax * e1z
        qz = -ax * e1y + ay * e1x
        w = (ux * qx + uy * qy + uz * qz) / det
        if s < -rtol or w < -rtol or s + w > 1.0 + rtol:
            continue
        if s < rtol or w < rtol or s + w > 1.0 - rtol:
            return -1                    # through an edge or a vertex, to rounding: not countable
        dist = (e2x * qx + e2y * qy + e2z * qz) / det
        if dist > 0.0:
            hits += 1
    return hits


@nb.njit(**_JIT)
def star_certificate(vertices, faces, c):
    """True when the closed, consistently outward shell is star-shaped from ``c`` with a
    one-to-one radial projection (see the module docstring): it then cannot cross itself.

    One pass with the clean kernel's own per-face test (:func:`star_face`: ``c``
    strictly inside each face's plane, and the faces the first ray leaves through); the other
    directions only when that ray grazes an edge."""
    star = np.zeros(2, dtype=np.int64)
    for t in range(faces.shape[0]):
        ia = faces[t, 0]
        ib = faces[t, 1]
        ic = faces[t, 2]
        ax = vertices[ia, 0] - c[0]
        ay = vertices[ia, 1] - c[1]
        az = vertices[ia, 2] - c[2]
        e1x = vertices[ib, 0] - vertices[ia, 0]
        e1y = vertices[ib, 1] - vertices[ia, 1]
        e1z = vertices[ib, 2] - vertices[ia, 2]
        e2x = vertices[ic, 0] - vertices[ia, 0]
        e2y = vertices[ic, 1] - vertices[ia, 1]
        e2z = vertices[ic, 2] - vertices[ia, 2]
        nx = e1y * e2z - e1z * e2y
        ny = e1z * e2x - e1x * e2z
        nz = e1x * e2y - e1y * e2x
        star_face(ax, ay, az, e1x, e1y, e1z, e2x, e2y, e2z, nx, ny, nz, ax * nx + ay * ny + az * nz, star)
        if star[1] == 1:
            return False                  # a face does not see c strictly inside
    if star[1] == 0:
        return star[0] == 1
    directions = ((-0.6396021490668313, 0.42640143271122083, 0.6396021490668313),
                  (0.5163977794943222, -0.7745966692414834, 0.3651483716701107))
    for k in range(2):
        vx, vy, vz = directions[k]
        n = _ray_hits(vertices, faces, c, vx, vy, vz, 1e-9)
        if n >= 0:
            return n == 1
    return False


@nb.njit(**_JIT)
def _orient(ax, ay, az, bx, by, bz, cx, cy, cz, dx, dy, dz):
    """Six times the signed volume of the tetrahedron (a, b, c, d)."""
    ux = bx - ax
    uy = by - ay
    uz = bz - az
    vx = cx - ax
    vy = cy - ay
    vz = cz - az
    wx = dx - ax
    wy = dy - ay
    wz = dz - az
    return (uy * vz - uz * vy) * wx + (uz * vx - ux * vz) * wy + (ux * vy - uy * vx) * wz


@nb.njit(**_JIT)
def _edge_through(V, p, q, a, b, c, eps):
    """Segment V[p] V[q] passes strictly through the interior of triangle V[a] V[b] V[c]."""
    sp = _orient(V[a, 0], V[a, 1], V[a, 2], V[b, 0], V[b, 1], V[b, 2], V[c, 0], V[c, 1], V[c, 2],
                 V[p, 0], V[p, 1], V[p, 2])
    sq = _orient(V[a, 0], V[a, 1], V[a, 2], V[b, 0], V[b, 1], V[b, 2], V[c, 0], V[c, 1], V[c, 2],
                 V[q, 0], V[q, 1], V[q, 2])
    if not ((sp > eps and sq < -eps) or (sp < -eps and sq > eps)):
        return False
    u = _orient(V[p, 0], V[p, 1], V[p, 2], V[q, 0], V[q, 1], V[q, 2], V[a, 0], V[a, 1], V[a, 2],
                V[b, 0], V[b, 1], V[b, 2])
    v = _orient(V[p, 0], V[p, 1], V[p, 2], V[q, 0], V[q, 1], V[q, 2], V[b, 0], V[b, 1], V[b, 2],
                V[c, 0], V[c, 1], V[c, 2])
    w = _orient(V[p, 0], V[p, 1], V[p, 2], V[q, 0], V[q, 1], V[q, 2], V[c, 0], V[c, 1], V[c, 2],
                V[a, 0], V[a, 1], V[a, 2])
    return (u > eps and v > eps and w > eps) or (u < -eps and v < -eps and w < -eps)


@nb.njit(**_JIT)
def face_frames(V, F):
    """Per face: the normal ``n = (b - a) x (c - a)`` (F, 3) and the bounding-box diagonal (F,)."""
    nf = F.shape[0]
    N = np.empty((nf, 3))
    diag = np.empty(nf)
    for t in range(nf):
        a = F[t, 0]
        b = F[t, 1]
        c = F[t, 2]
        N[t, 0], N[t, 1], N[t, 2] = face_normal(V, a, b, c)
        d0 = max(V[a, 0], V[b, 0], V[c, 0]) - min(V[a, 0], V[b, 0], V[c, 0])
        d1 = max(V[a, 1], V[b, 1], V[c, 1]) - min(V[a, 1], V[b, 1], V[c, 1])
        d2 = max(V[a, 2], V[b, 2], V[c, 2]) - min(V[a, 2], V[b, 2], V[c, 2])
        diag[t] = np.sqrt(d0 * d0 + d1 * d1 + d2 * d2)
    return N, diag


@nb.njit(**_JIT)
def _straddles(V, F, N, i, j, eps):
    """The corners of face i lie strictly on both sides of face j's plane: the orientation
    ``n_j . (p - a_j)`` (the same quantity as ``_orient``) of each corner p of face i."""
    a = F[j, 0]
    pos = False
    neg = False
    for k in range(3):
        p = F[i, k]
        o = (N[j, 0] * (V[p, 0] - V[a, 0]) + N[j, 1] * (V[p, 1] - V[a, 1]) + N[j, 2] * (V[p, 2] - V[a, 2]))
        pos = pos or o > eps
        neg = neg or o < -eps
    return pos and neg


@nb.njit(**_JIT)
def faces_cross(V, F, N, diag, i, j, rtol):
    """Faces i and j cross: an edge of one strictly through the other (tolerance ``rtol`` L^3,
    L the larger box diagonal of the two).  A face whose corners do not lie strictly on both
    sides of the other's plane cannot have an edge through it, nor can the other: rejected
    after three orientation tests each way (normals and diagonals from :func:`face_frames`)."""
    L = max(diag[i], diag[j])
    eps = rtol * L * L * L
    if not (_straddles(V, F, N, i, j, eps) and _straddles(V, F, N, j, i, eps)):
        return False
    for k in range(3):
        if _edge_through(V, F[i, k], F[i, (k + 1) % 3], F[j, 0], F[j, 1], F[j, 2], eps):
            return True
        if _edge_through(V, F[j, k], F[j, (k + 1) % 3], F[i, 0], F[i, 1], F[i, 2], eps):
            return True
    return False


@nb.njit(**_JIT)
def _bucket(x, y, z, mask):
    h = (x * 73856093) ^ (y * 19349663) ^ (z * 83492791)
    return h & mask


@nb.njit(**_JIT)
def certified_fans(V, F, N):
    """Per vertex: :func:`certified_fans_of` for every vertex."""
    return certified_fans_of(V, F, N, np.ones(V.shape[0], dtype=np.bool_))


@nb.njit(**_JIT)
def certified_fans_of(V, F, N, wanted):
    """Per vertex: True when no two faces around it meet but at the vertex and along their
    common edges, so no pair of them can cross.  Sufficient: the corners after the vertex
    (a -> b in each face, turned so that the vertex comes first) close into cycles (each
    corner met as often as an ``a`` as a ``b``), and :func:`_fan_certified`.  Only the
    vertices ``wanted`` are tried (the others are False)."""
    nv = V.shape[0]
    start, around, _ = vertex_slots(F, nv)
    cert = np.zeros(nv, dtype=np.bool_)
    kmax = 0
    for i in range(nv):
        kmax = max(kmax, start[i + 1] - start[i])
    A = np.empty(kmax, dtype=np.int64)
    B = np.empty(kmax, dtype=np.int64)
    for v in range(nv):
        s0 = start[v]
        k = start[v + 1] - s0
        if k < 3 or not wanted[v]:
            continue
        for u in range(k):
            t = around[s0 + u]
            if F[t, 0] == v:
                A[u] = F[t, 1]
                B[u] = F[t, 2]
            elif F[t, 1] == v:
                A[u] = F[t, 2]
                B[u] = F[t, 0]
            else:
                A[u] = F[t, 0]
                B[u] = F[t, 1]
        ok = True
        for u in range(k):                  # the link closes: each corner as often an a as a b
            ca = 0
            cb = 0
            for w in range(k):
                ca += A[w] == A[u]
                cb += B[w] == A[u]
            if ca != cb:
                ok = False
                break
        if ok:
            cert[v] = _fan_certified(V, N, v, around[s0:s0 + k], A, B, k)
    return cert


@nb.njit(**_JIT)
def certified_fans_around(V, F, N, adj, wanted):
    """:func:`certified_fans_of` of a closed shell whose edges are matched (``adj``: the face
    across each edge, :func:`._heightfield_numba.face_twins`), for a few vertices: each fan is
    walked face to face across its edges instead of sorting every face by vertex.  A fan
    walked is a cycle of corners by construction; it must hold every face at the vertex (a
    vertex where two cones of faces touch has two cycles: not certified)."""
    nv = V.shape[0]
    nf = F.shape[0]
    valence = np.zeros(nv, dtype=np.int32)
    seed = np.full(nv, -1, dtype=np.int64)      # a corner 3 t + k at the vertex
    kmax = 0
    for t in range(nf):
        for k in range(3):
            v = F[t, k]
            if wanted[v]:
                valence[v] += 1
                kmax = max(kmax, valence[v])
                if seed[v] < 0:
                    seed[v] = 3 * t + k
    cert = np.zeros(nv, dtype=np.bool_)
    ts = np.empty(kmax, dtype=np.int64)
    A = np.empty(kmax, dtype=np.int64)
    B = np.empty(kmax, dtype=np.int64)
    for v in range(nv):
        if seed[v] < 0 or valence[v] < 3:
            continue
        t0 = seed[v] // 3
        c = seed[v] % 3
        t = t0
        n = 0
        while True:
            if n == valence[v]:
                n = -1                           # more faces in the walk than at the vertex
                break
            ts[n] = t
            A[n] = F[t, (c + 1) % 3]
            B[n] = F[t, (c + 2) % 3]
            n += 1
            t = adj[t, (c + 2) % 3]             # across the edge b -> v: the face with v -> b
            if t == t0:
                break
            c = 0 if F[t, 0] == v else (1 if F[t, 1] == v else 2)
        if n == valence[v]:
            cert[v] = _fan_certified(V, N, v, ts, A, B, n)
    return cert


@nb.njit(**_JIT)
def _fan_certified(V, N, v, ts, A, B, k):
    """The fan of faces ``ts[:k]`` around ``v`` (face u turns v -> A[u] -> B[u]; the corners
    close into cycles) is flat: every face is positively oriented seen along the sum of their
    normals (beyond a 1e-6 relative margin), and a direction inside the first face's sector
    (its bisector) lies in no other face's sector (beyond a 1e-9 margin).  Then the projected
    sectors wind around the vertex once, so they are disjoint, and faces whose projections
    meet only at the vertex meet only there."""
    nx = 0.0
    ny = 0.0
    nz = 0.0
    for u in range(k):
        t = ts[u]
        nx += N[t, 0]
        ny += N[t, 1]
        nz += N[t, 2]
    nn = np.sqrt(nx * nx + ny * ny + nz * nz)
    if not (nn > 0.0):
        return False
    for u in range(k):
        t = ts[u]
        m = np.sqrt(N[t, 0] ** 2 + N[t, 1] ** 2 + N[t, 2] ** 2)
        if not (N[t, 0] * nx + N[t, 1] * ny + N[t, 2] * nz > 1e-6 * m * nn):
            return False
    nx /= nn
    ny /= nn
    nz /= nn
    # the bisector of the first sector: the unit projections of its two edges, added
    r0 = r1 = r2 = 0.0
    for c in (A[0], B[0]):
        ex = V[c, 0] - V[v, 0]
        ey = V[c, 1] - V[v, 1]
        ez = V[c, 2] - V[v, 2]
        h = ex * nx + ey * ny + ez * nz
        ex -= h * nx
        ey -= h * ny
        ez -= h * nz
        le = np.sqrt(ex * ex + ey * ey + ez * ez)
        if not (le > 0.0):
            return False
        r0 += ex / le
        r1 += ey / le
        r2 += ez / le
    lr = np.sqrt(r0 * r0 + r1 * r1 + r2 * r2)
    if not (lr > 0.0):
        return False
    for u in range(1, k):
        inside = True
        for c, sgn in ((A[u], 1.0), (B[u], -1.0)):
            ex = V[c, 0] - V[v, 0]
            ey = V[c, 1] - V[v, 1]
            ez = V[c, 2] - V[v, 2]
            # n . (e x r) for the first edge, n . (r x e) for the second
            o = sgn * (nx * (ey * r2 - ez * r1) + ny * (ez * r0 - ex * r2) + nz * (ex * r1 - ey * r0))
            eps = 1e-9 * np.sqrt(ex * ex + ey * ey + ez * ez) * lr
            if o < -eps:
                inside = False
                break
            if o <= eps:
                return False                 # on the sector's edge, to rounding: no proof
        if inside:
            return False
    return True


@nb.njit(**_JIT)
def first_crossing(V, F, N, diag, cert, origin, cell, max_per_face, rtol, out):
    """A pair of crossing faces into ``out`` (2,): returns 1, 0 when there is none, -1 when a
    face spans more than ``max_per_face`` cells (the caller retries with a coarser grid).
    ``N``, ``diag``: :func:`face_frames`; ``cert``: :func:`certified_fans`.

    The cells are hashed into buckets (no keys stored: a bucket may hold several cells); the
    faces are filed per bucket by a counting sort, each entry with a copy of its face's box
    (float32, widened outward so that it holds the box) and corners, so that a bucket is read
    in sequence.  A pair is tested only when the boxes overlap, the faces share no edge (such
    neighbours cannot cross) and no vertex that :func:`certified_fans` proves, and the bucket
    is that of the lowest cell both boxes cover (each pair once whatever the collisions); then
    the exact test :func:`faces_cross`.
    """
    nf = F.shape[0]
    lo = np.empty((nf, 3), dtype=np.int64)
    hi = np.empty((nf, 3), dtype=np.int64)
    n_reg = 0
    for t in range(nf):
        span = 1.0                    # in floats: a face 1e20 cells long must not overflow int64
        for a in range(3):
            mn = np.floor((min(V[F[t, 0], a], V[F[t, 1], a], V[F[t, 2], a]) - origin[a]) / cell)
            mx = np.floor((max(V[F[t, 0], a], V[F[t, 1], a], V[F[t, 2], a]) - origin[a]) / cell)
            span *= mx - mn + 1.0
            if span > max_per_face or mx > 4.0e18:   # too many cells, or cell numbers beyond int64
                return -1
            lo[t, a] = np.int64(mn)
            hi[t, a] = np.int64(mx)
        n_reg += np.int64(span)
    cap = 16
    while cap < n_reg:
        cap *= 2
    mask = cap - 1
    counts = np.zeros(cap + 1, dtype=np.int64)
    for t in range(nf):
        for x in range(lo[t, 0], hi[t, 0] + 1):
            for y in range(lo[t, 1], hi[t, 1] + 1):
                for z in range(lo[t, 2], hi[t, 2] + 1):
                    counts[_bucket(x, y, z, mask) + 1] += 1
    for b in range(cap):
        counts[b + 1] += counts[b]
    fill = counts[:-1].copy()
    who = np.empty(n_reg, dtype=np.int32)           # per entry, in bucket order: the face,
    box = np.empty((n_reg, 6), dtype=np.float32)    # its box (relative to origin, widened)
    cor = np.empty((n_reg, 3), dtype=np.int32)      # and its corners
    grow = np.float32(2.4e-7)                       # float32 rounds to nearest: widen to hold the box
    bx = np.empty(6, dtype=np.float32)
    for t in range(nf):
        for a in range(3):
            bx[a] = np.float32(min(V[F[t, 0], a], V[F[t, 1], a], V[F[t, 2], a]) - origin[a])
            bx[a] -= abs(bx[a]) * grow + np.float32(1e-38)
            bx[a + 3] = np.float32(max(V[F[t, 0], a], V[F[t, 1], a], V[F[t, 2], a]) - origin[a])
            bx[a + 3] += abs(bx[a + 3]) * grow + np.float32(1e-38)
        for x in range(lo[t, 0], hi[t, 0] + 1):
            for y in range(lo[t, 1], hi[t, 1] + 1):
                for z in range(lo[t, 2], hi[t, 2] + 1):
                    b = _bucket(x, y, z, mask)
                    r = fill[b]
                    fill[b] += 1
                    who[r] = t
                    for a in range(6):
                        box[r, a] = bx[a]
                    for a in range(3):
                        cor[r, a] = F[t, a]
    for b in range(cap):
        c1 = counts[b + 1]
        for p in range(counts[b], c1):
            x0 = box[p, 0]
            y0 = box[p, 1]
            z0 = box[p, 2]
            x1 = box[p, 3]
            y1 = box[p, 4]
            z1 = box[p, 5]
            a0 = cor[p, 0]
            a1 = cor[p, 1]
            a2 = cor[p, 2]
            for q in range(p + 1, c1):
                if (box[q, 0] > x1 or box[q, 3] < x0 or box[q, 1] > y1 or box[q, 4] < y0
                        or box[q, 2] > z1 or box[q, 5] < z0):
                    continue                 # the boxes are apart
                shared = 0
                common = -1
                for k in range(3):
                    c = cor[q, k]
                    if c == a0 or c == a1 or c == a2:
                        shared += 1
                        common = c
                if shared >= 2:
                    continue                 # the same face (in two cells of one bucket), or neighbours across an edge
                if shared == 1 and cert[common]:
                    continue                 # faces around a certified vertex cannot cross
                i = who[p]
                j = who[q]
                # the lowest cell both boxes cover: the pair is tested in its bucket only
                if _bucket(max(lo[i, 0], lo[j, 0]), max(lo[i, 1], lo[j, 1]), max(lo[i, 2], lo[j, 2]), mask) != b:
                    continue
                if faces_cross(V, F, N, diag, i, j, rtol):
                    out[0] = min(i, j)
                    out[1] = max(i, j)
                    return 1
    return 0


@nb.njit(**_JIT)
def find_crossing(V, F, adj, max_per_face, rtol, out):
    """:func:`first_crossing` with its grid chosen here: the origin at the low corner of the
    used vertices, cells as long as the median of the faces' longest edges (the NumPy twin's
    ``self_crossing._cell``), twice as long while a face spans more than ``max_per_face``;
    the face frames and fan certificates computed once for every grid tried.  Returns 1 (a
    pair in ``out``) or 0.  A shell that uses few of many vertices (one component of a large
    mesh) is first renumbered to its own vertices, so that the work is of its size.  ``adj``:
    the face across each edge as :func:`._heightfield_numba.face_twins` gives it (from
    ``inertia._ext.integrals.clean_solid``, which has matched the edges already), or an empty
    array: then found here."""
    if V.shape[0] > 4 * F.shape[0] + 1024:
        used = np.unique(F)
        return _find_crossing(np.ascontiguousarray(V[used]), np.searchsorted(used, F), adj, max_per_face, rtol, out)
    return _find_crossing(V, F, adj, max_per_face, rtol, out)


@nb.njit(**_JIT)
def _find_crossing(V, F, adj, max_per_face, rtol, out):
    """:func:`find_crossing` once the vertices are the shell's own (not recursive: numba
    compiles a recursive call with other argument types badly)."""
    nf = F.shape[0]
    origin, top, cell = box_and_median_edge(V, F)
    h = CELL_EDGES * cell                       # the cell proof's grid (it proves nothing if h is not finite)
    if not (cell > 0.0 and cell < np.inf):
        cell = 1.0
    rows = np.arange(nf)
    if nf >= HEIGHTFIELD_MIN_FACES:
        closed = adj.shape[0] == nf
        if not closed:
            adj, closed = face_twins(F, V.shape[0])
        if closed:
            keep = np.zeros(nf, dtype=np.bool_)
            n_keep = unproved_faces(V, F, adj, origin, top, h, keep)
            if n_keep == 0:
                return 0                        # every cell proved
            if n_keep < nf:
                rows = np.nonzero(keep)[0]
    if rows.shape[0] * KEPT_WITHOUT_FANS < nf:
        # a few faces left: the fans' certificates (a pass over every face, then ~100 ns a
        # vertex) cost more than the pairs they spare (on 1-5 % of a torus's faces: 30 against
        # 4 us); the search needs the frames of those faces only
        cert = np.zeros(V.shape[0], dtype=np.bool_)
        Fs = np.ascontiguousarray(F[rows])
        Ns, diags = face_frames(V, Fs)
    else:
        N, diag = face_frames(V, F)             # per mesh, not per grid tried
        if rows.shape[0] < nf:
            wanted = np.zeros(V.shape[0], dtype=np.bool_)
            for r in rows:
                for k in range(3):
                    wanted[F[r, k]] = True
            cert = certified_fans_around(V, F, N, adj, wanted)   # rows < nf: the cell proof ran, adj matched
            Fs = np.ascontiguousarray(F[rows])  # search the faces of the cells not proved
            Ns = np.ascontiguousarray(N[rows])
            diags = diag[rows]
        else:
            cert = certified_fans(V, F, N)
            Fs = F
            Ns = N
            diags = diag
    while True:
        found = first_crossing(V, Fs, Ns, diags, cert, origin, cell, max_per_face, rtol, out)
        if found >= 0:
            if found == 1:
                i = rows[out[0]]
                j = rows[out[1]]
                out[0] = min(i, j)
                out[1] = max(i, j)
            return found
        cell *= 2.0
