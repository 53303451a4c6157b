"""Scalar topology kernels of :mod:`inertia.geometry.robust`, vertex by vertex in O(n).

Like :mod:`._robust_kernels`, written once in plain scalar Python (the slow fallback) and
compiled by numba (:mod:`._robust_numba`); nothing here imports numba.

Everything is read from the faces around each vertex (:func:`vertex_faces`, a counting
sort), so no hash table is needed:

* :func:`dedupe_faces` merges faces with the same corner set into one face with a
  multiplicity (orientation parity gives the sign of each copy);
* :func:`vertex_pass` proves, vertex by vertex, that no two faces around a vertex cut each
  other (their projections along one direction tile a disc or a sector), finds the face
  across each manifold, consistently wound edge of equal multiplicities, and counts the
  boundary edges (non-zero net multiplicity: open, or inconsistently wound), which
  :func:`boundary_edges` then writes out and the caps close;
* :func:`patch_labels` joins the uncut faces across those edges (union-find);
* :func:`weighted_sums` adds the signed-tetrahedron integrals of weighted faces.

The scalar style of :mod:`._robust_kernels` holds here too: loading a face's corners
relative to a point is written out where it is used (a helper returning a 9-tuple costs
measurably in the inner loops); ``duplicates`` lists those few lines.
"""

from __future__ import annotations

import math

import numpy as np

__all__ = ["ear_clip", "face_boxes", "vertex_faces", "dedupe_faces", "boundary_edges", "vertex_pass",
           "patch_labels", "patch_reps", "tetra_add", "weighted_sums"]

TWO_PI = 2.0 * math.pi
#: The compiled twin replaces this with ``numba.prange`` (parallel loops); plain Python runs them in order.
prange = range


def face_boxes(V, F, lo, hi):
    """Axis-aligned boxes of the faces: ``lo``, ``hi`` (F, 3)."""
    for f in range(F.shape[0]):
        for c in range(3):
            a = V[F[f, 0], c]
            b = V[F[f, 1], c]
            d = V[F[f, 2], c]
            lo[f, c] = min(a, min(b, d))
            hi[f, c] = max(a, max(b, d))


def vertex_faces(F, n_vertices, key_min, ptr, idx):
    """CSR of faces by vertex: ``idx[ptr[v]:ptr[v + 1]]``, in increasing face order.

    ``key_min``: register each face under its lowest corner only (else under all three).
    """
    for v in range(n_vertices + 1):
        ptr[v] = 0
    nf = F.shape[0]
    for f in range(nf):
        if key_min:
            ptr[min(F[f, 0], min(F[f, 1], F[f, 2])) + 1] += 1
        else:
            for k in range(3):
                ptr[F[f, k] + 1] += 1
    for v in range(n_vertices):
        ptr[v + 1] += ptr[v]
    fill = ptr[:n_vertices].copy()
    for f in range(nf):
        if key_min:
            v = min(F[f, 0], min(F[f, 1], F[f, 2]))
            idx[fill[v]] = f
            fill[v] += 1
        else:
            for k in range(3):
                v = F[f, k]
                idx[fill[v]] = f
                fill[v] += 1


def _odd(a, b, c):
    """Parity of the permutation sorting (a, b, c) (distinct): True when odd."""
    odd = False
    if a > b:
        a, b = b, a
        odd = not odd
    if b > c:
        b, c = c, b
        odd = not odd
    if a > b:
        odd = not odd
    return odd


def dedupe_faces(F, ptr, idx, out, mult):
    """Faces with distinct corners, equal corner sets merged; returns how many were written.

    ``ptr, idx``: :func:`vertex_faces` with ``key_min``.  ``out`` (F, 3) receives the groups
    in order of first appearance with their net multiplicity ``mult`` (copies oriented like
    the first copy count +1, the others -1); groups that cancel are dropped, a group with a
    negative net count is written flipped.
    """
    nf = F.shape[0]
    leader = np.arange(nf)
    net = np.zeros(nf)
    for v in range(ptr.shape[0] - 1):
        for i in range(ptr[v], ptr[v + 1]):
            f = idx[i]
            if leader[f] != f:
                continue
            a = F[f, 0]
            b = F[f, 1]
            c = F[f, 2]
            if a == b or b == c or c == a:
                leader[f] = -1
                continue
            net[f] = 1.0
            s = a + b + c
            hi = max(a, max(b, c))
            odd = _odd(a, b, c)
            for j in range(i + 1, ptr[v + 1]):
                g = idx[j]
                if leader[g] != g:
                    continue
                x = F[g, 0]
                y = F[g, 1]
                z = F[g, 2]
                # same lowest corner (v); equal sets iff equal sums and equal highest corners
                if x + y + z == s and max(x, max(y, z)) == hi and x != y and y != z and z != x:
                    leader[g] = f
                    net[f] += 1.0 if _odd(x, y, z) == odd else -1.0
    n = 0
    for f in range(nf):
        if leader[f] != f or net[f] == 0.0:
            continue
        m = net[f]
        out[n, 0] = F[f, 0]
        out[n, 1] = F[f, 1] if m > 0 else F[f, 2]
        out[n, 2] = F[f, 2] if m > 0 else F[f, 1]
        mult[n] = abs(m)
        n += 1
    return n


def _star(F, ptr, idx, v, A, B, W, Q):
    """Corners after v (A[t], B[t]) of the faces W[t] around v, and v's position Q[t] in
    the face; returns their number."""
    k = 0
    for i in range(ptr[v], ptr[v + 1]):
        f = idx[i]
        q = 0 if F[f, 0] == v else (1 if F[f, 1] == v else 2)
        A[k] = F[f, (q + 1) % 3]
        B[k] = F[f, (q + 2) % 3]
        W[k] = f
        Q[k] = q
        k += 1
    return k


def _max_valence(ptr):
    kmax = 1
    for v in range(ptr.shape[0] - 1):
        kmax = max(kmax, ptr[v + 1] - ptr[v])
    return kmax


def vertex_pass(V, F, M, ptr, idx, verts, ok, nbr, n_boundary, kinds):
    """For each vertex v of ``verts`` (in parallel when compiled): is v certified (``ok[v]``),
    the faces across the edges v owns (``nbr``), how many boundary edges v owns (``n_boundary[v]``),
    and how many of its edges are open (used once), inconsistently wound (twice, the same
    way) or non-manifold (more than twice), counting multiplicities (``kinds[v]``, (3,)).

    ``ok[v]``: no two faces around v share a point other than v and their common edges.
    Sufficient test: the faces around v form one fan (their link edges a -> b, the corners
    after v, make a single cycle, or a single path at a boundary), and projected along the
    mean normal n every face is positively oriented (beyond a 1e-9 relative margin) and the
    angular sectors cover the circle once (cycle: a direction inside the first sector lies in
    no other sector, beyond a 1e-9 margin) or less (path: the angles add up to less than one
    turn).  Then the projections of the faces lie in disjoint sectors around v, so two faces
    can meet only where their projections do: in v and along a shared edge.

    Edge {v, x} is v's when v < x.  ``nbr[f, e]`` (edge e of face f runs from corner e to
    corner e + 1): the other face of that edge when exactly two faces use it, in opposite
    directions, with equal multiplicities (left alone otherwise: -1 from the caller).  A
    boundary edge has a net multiplicity (faces v -> x minus faces x -> v) other than 0.
    """
    kmax = _max_valence(ptr)
    n_chunks = 64
    nv = verts.shape[0]
    for ch in prange(n_chunks):
        A = np.empty(kmax, np.int64)
        B = np.empty(kmax, np.int64)
        W = np.empty(kmax, np.int64)
        Q = np.empty(kmax, np.int64)
        L = np.empty((kmax, 6), np.int64)
        flag = np.empty(kmax, np.bool_)
        C = np.empty((kmax, 9))
        for j in range(nv * ch // n_chunks, nv * (ch + 1) // n_chunks):
            v = verts[j]
            k = _star(F, ptr, idx, v, A, B, W, Q)
            ok[v] = False
            _link(A, B, k, L)
            n_boundary[v] = _vertex_edges(M, v, A, B, W, Q, k, L, nbr, kinds)
            if k < 2:
                continue
            kind = _fan_kind(L, k, flag)
            if kind != 0:
                ok[v] = _fan_flat(V, v, A, B, L, k, kind, C)


def _link(A, B, k, L):
    """One pass over the pairs of v's link edges A[t] -> B[t]: ``L[t]`` = (next: the first u with
    A[u] == B[t], previous: the first u with B[u] == A[t], how many u have A[u] == A[t], B[u] ==
    B[t], A[u] == B[t], B[u] == A[t]); -1 for none."""
    for t in range(k):
        a = A[t]
        b = B[t]
        nxt = -1
        prv = -1
        ca = 0
        cb = 0
        cn = 0
        cp = 0
        for u in range(k):
            au = A[u]
            bu = B[u]
            ca += au == a
            cb += bu == b
            if au == b:
                cn += 1
                if nxt < 0:
                    nxt = u
            if bu == a:
                cp += 1
                if prv < 0:
                    prv = u
        L[t, 0] = nxt
        L[t, 1] = prv
        L[t, 2] = ca
        L[t, 3] = cb
        L[t, 4] = cn
        L[t, 5] = cp


def _vertex_edges(M, v, A, B, W, Q, k, L, nbr, kinds):
    """Pair the faces of v's manifold edges {v, x}, x > v, into ``nbr``; count open,
    inconsistent and non-manifold ones into ``kinds[v]`` (if given); returns the number of
    boundary edges (net multiplicity not 0).  Edges met more than once on a side go to
    :func:`_edge_uses`."""
    n_bnd = 0
    count = kinds.shape[0] > 0
    k_open = 0
    k_inc = 0
    k_nm = 0
    for t in range(k):
        # edge v -> A[t]
        x = A[t]
        if x > v:
            if L[t, 2] > 1 or L[t, 5] > 1:
                if _first_in(A, t, x):
                    m_out, m_in = _edge_uses(M, x, A, B, W, k)
                    n_bnd += abs(m_out - m_in) >= 0.5
                    k_open, k_inc, k_nm = _count_kind(k_open, k_inc, k_nm, m_out, m_in)
            else:
                m_out = M[W[t]]
                m_in = 0.0
                u = L[t, 1]
                if u >= 0:
                    m_in = M[W[u]]
                    if m_out == m_in:
                        nbr[W[t], Q[t]] = W[u]
                        nbr[W[u], (Q[u] + 2) % 3] = W[t]
                n_bnd += abs(m_out - m_in) >= 0.5
                if m_out != 1.0 or m_in != 1.0:
                    k_open, k_inc, k_nm = _count_kind(k_open, k_inc, k_nm, m_out, m_in)
        # edge B[t] -> v with no face v -> B[t]
        x = B[t]
        if x > v and L[t, 4] == 0:
            if L[t, 3] > 1:
                if _first_in(B, t, x):
                    m_out, m_in = _edge_uses(M, x, A, B, W, k)
                    n_bnd += abs(m_out - m_in) >= 0.5
                    k_open, k_inc, k_nm = _count_kind(k_open, k_inc, k_nm, m_out, m_in)
            else:
                n_bnd += M[W[t]] >= 0.5
                k_open, k_inc, k_nm = _count_kind(k_open, k_inc, k_nm, 0.0, M[W[t]])
    if count:
        kinds[v, 0] = k_open
        kinds[v, 1] = k_inc
        kinds[v, 2] = k_nm
    return n_bnd


def _first_in(X, t, x):
    for u in range(t):
        if X[u] == x:
            return False
    return True


def _count_kind(k_open, k_inc, k_nm, m_out, m_in):
    """Counts of open, inconsistently wound, non-manifold edges, with edge (m_out, m_in) added."""
    uses = m_out + m_in
    if uses < 1.5:
        k_open += 1
    elif uses < 2.5:
        if m_out != m_in:
            k_inc += 1
    else:
        k_nm += 1
    return k_open, k_inc, k_nm


def _edge_uses(M, x, A, B, W, k):
    """(multiplicity v -> x, multiplicity x -> v) of edge {v, x} over v's star."""
    m_out = 0.0
    m_in = 0.0
    for u in range(k):
        if A[u] == x:
            m_out += M[W[u]]
        if B[u] == x:
            m_in += M[W[u]]
    return m_out, m_in


def boundary_edges(F, M, ptr, idx, n_boundary, out, out_mult):
    """Write the boundary edges (tail, head) and their net multiplicities of the vertices with
    ``n_boundary[v] > 0`` (:func:`vertex_pass`); returns their count.  Edge {v, x} is
    v's when v < x; its net multiplicity is that of the faces v -> x less that of x -> v."""
    kmax = _max_valence(ptr)
    A = np.empty(kmax, np.int64)
    B = np.empty(kmax, np.int64)
    W = np.empty(kmax, np.int64)
    Q = np.empty(kmax, np.int64)
    n = 0
    for v in range(ptr.shape[0] - 1):
        if n_boundary[v] == 0:
            continue
        k = _star(F, ptr, idx, v, A, B, W, Q)
        for t in range(2 * k):
            x = A[t] if t < k else B[t - k]
            if x < v or _seen_before(A, B, k, t, x):
                continue
            m_out, m_in = _edge_uses(M, x, A, B, W, k)
            if abs(m_out - m_in) >= 0.5:
                out[n, 0] = v if m_out > m_in else x
                out[n, 1] = x if m_out > m_in else v
                out_mult[n] = abs(m_out - m_in)
                n += 1
    return n


def _seen_before(A, B, k, t, x):
    """x already appeared among the link corners listed before position t (A then B)."""
    for u in range(t):
        if (A[u] if u < k else B[u - k]) == x:
            return True
    return False


def _fan_kind(L, k, flag):
    """How the link edges of a vertex connect (:func:`_link`): 2 one cycle, 1 one path, 0 neither.

    The tails must be distinct, and the walk along ``next`` from the start (the edge whose tail
    is nobody's head, else edge 0) must reach all k edges, then stop (path) or come back to
    the start (cycle).
    """
    start = 0
    n_starts = 0
    for t in range(k):
        if L[t, 2] > 1:
            return 0
        if L[t, 5] == 0:
            start = t
            n_starts += 1
        flag[t] = False
    if n_starts > 1:
        return 0
    t = start
    count = 0
    last = -1
    while t != -1 and not flag[t]:
        flag[t] = True
        count += 1
        last = t
        t = L[t, 0]
    if count != k:
        return 0
    if n_starts == 0:
        return 2 if L[last, 0] == start else 0
    return 1 if L[last, 0] == -1 else 0


def _fan_flat(V, v, A, B, L, k, kind, C):
    """The fan around v projects along its mean normal into disjoint sectors (see :func:`vertex_pass`).
    ``C`` (k, 9) receives each face's cross product and corner vectors; a link vertex's
    coordinates are read once (B[t] is the A of the next edge, :func:`_link`)."""
    px = V[v, 0]
    py = V[v, 1]
    pz = V[v, 2]
    nx = 0.0
    ny = 0.0
    nz = 0.0
    for t in range(k):
        C[t, 3] = V[A[t], 0] - px
        C[t, 4] = V[A[t], 1] - py
        C[t, 5] = V[A[t], 2] - pz
    for t in range(k):
        ax = C[t, 3]
        ay = C[t, 4]
        az = C[t, 5]
        u = L[t, 0]          # the edge starting at B[t]: its corner vector is B[t]'s, already read
        if u >= 0:
            bx = C[u, 3]
            by = C[u, 4]
            bz = C[u, 5]
        else:
            bx = V[B[t], 0] - px
            by = V[B[t], 1] - py
            bz = V[B[t], 2] - pz
        C[t, 0] = ay * bz - az * by
        C[t, 1] = az * bx - ax * bz
        C[t, 2] = ax * by - ay * bx
        C[t, 6] = bx
        C[t, 7] = by
        C[t, 8] = bz
        nx += C[t, 0]
        ny += C[t, 1]
        nz += C[t, 2]
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    if not ln > 0.0:
        return False
    nx /= ln
    ny /= ln
    nz /= ln
    for t in range(k):
        # cn > 1e-9 |c|, squared (no square root in the loop)
        cn = C[t, 0] * nx + C[t, 1] * ny + C[t, 2] * nz
        if not (cn > 0.0 and cn * cn > 1e-18 * (C[t, 0] * C[t, 0] + C[t, 1] * C[t, 1] + C[t, 2] * C[t, 2])):
            return False
    if kind == 1:
        total = 0.0
        for t in range(k):
            ax = C[t, 3]
            ay = C[t, 4]
            az = C[t, 5]
            bx = C[t, 6]
            by = C[t, 7]
            bz = C[t, 8]
            an = ax * nx + ay * ny + az * nz
            bn = bx * nx + by * ny + bz * nz
            total += math.atan2(C[t, 0] * nx + C[t, 1] * ny + C[t, 2] * nz,
                                ax * bx + ay * by + az * bz - an * bn)
        return total < TWO_PI - 1e-9
    # cycle: u = bisector of sector 0; sector t contains u iff a_t . w >= 0 >= b_t . w, w = u x n
    ax = C[0, 3]
    ay = C[0, 4]
    az = C[0, 5]
    bx = C[0, 6]
    by = C[0, 7]
    bz = C[0, 8]
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    ux = ax / la + bx / lb
    uy = ay / la + by / lb
    uz = az / la + bz / lb
    wx = uy * nz - uz * ny
    wy = uz * nx - ux * nz
    wz = ux * ny - uy * nx
    lw = math.sqrt(wx * wx + wy * wy + wz * wz)
    if not lw > 0.0:
        return False
    for t in range(1, k):
        ax = C[t, 3]
        ay = C[t, 4]
        az = C[t, 5]
        bx = C[t, 6]
        by = C[t, 7]
        bz = C[t, 8]
        aw = ax * wx + ay * wy + az * wz
        bw = bx * wx + by * wy + bz * wz
        # a . w >= -1e-9 |w| |a| and b . w <= 1e-9 |w| |b|, squared
        m2 = 1e-18 * lw * lw
        if ((aw >= 0.0 or aw * aw <= m2 * (ax * ax + ay * ay + az * az))
                and (bw <= 0.0 or bw * bw <= m2 * (bx * bx + by * by + bz * bz))):
            return False          # u in (or within the margin of) another sector
    return True


def _find(parent, x):
    r = x
    while parent[r] != r:
        r = parent[r]
    while parent[x] != r:
        y = parent[x]
        parent[x] = r
        x = y
    return r


def patch_labels(nbr, cut, labels):
    """Connected patches of uncut faces joined by ``nbr`` (:func:`vertex_pass`); ``labels[f]``
    in 0..n-1 (cut faces alone in theirs), returns n."""
    nf = labels.shape[0]
    parent = np.arange(nf)
    for f in range(nf):
        if cut[f]:
            continue
        for e in range(3):
            g = nbr[f, e]
            if g < 0 or cut[g]:
                continue
            rf = _find(parent, f)
            rg = _find(parent, g)
            if rf < rg:
                parent[rg] = rf
            elif rg < rf:
                parent[rf] = rg
    n = 0
    for f in range(nf):
        r = _find(parent, f)
        if r == f:
            labels[f] = n
            n += 1
        else:
            labels[f] = labels[r]
    return n


def patch_reps(V, F, labels, uncut, reps):
    """``reps[l]``: the uncut face of largest area in patch l (-1 if none)."""
    best = np.full(reps.shape[0], -1.0)
    for i in range(reps.shape[0]):
        reps[i] = -1
    for f in range(F.shape[0]):
        if not uncut[f]:
            continue
        ax = V[F[f, 1], 0] - V[F[f, 0], 0]
        ay = V[F[f, 1], 1] - V[F[f, 0], 1]
        az = V[F[f, 1], 2] - V[F[f, 0], 2]
        bx = V[F[f, 2], 0] - V[F[f, 0], 0]
        by = V[F[f, 2], 1] - V[F[f, 0], 1]
        bz = V[F[f, 2], 2] - V[F[f, 0], 2]
        cx = ay * bz - az * by
        cy = az * bx - ax * bz
        cz = ax * by - ay * bx
        a2 = cx * cx + cy * cy + cz * cz
        lab = labels[f]
        if a2 > best[lab]:
            best[lab] = a2
            reps[lab] = f


def tetra_add(acc, weight, ax, ay, az, bx, by, bz, cx, cy, cz):
    """``acc`` (10,) += weight x the signed tetrahedron (0, a, b, c) integrals, times 6, 24
    (x3), 120 (x6): volume, int y (3), int y y^T (xx, yy, zz, xy, xz, yz)."""
    det = weight * (ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx))
    sx = ax + bx + cx
    sy = ay + by + cy
    sz = az + bz + cz
    acc[0] += det
    acc[1] += det * sx
    acc[2] += det * sy
    acc[3] += det * sz
    acc[4] += det * (ax * ax + bx * bx + cx * cx + sx * sx)
    acc[5] += det * (ay * ay + by * by + cy * cy + sy * sy)
    acc[6] += det * (az * az + bz * bz + cz * cz + sz * sz)
    acc[7] += det * (ax * ay + bx * by + cx * cy + sx * sy)
    acc[8] += det * (ax * az + bx * bz + cx * cz + sx * sz)
    acc[9] += det * (ay * az + by * bz + cy * cz + sy * sz)


def weighted_sums(V, F, w, px, py, pz, out):
    """``out`` (10,) += sum_f w_f of the signed tetrahedron (p, face f) integrals, times
    6, 24, 24, 24, 120 (x6): volume, int y (3), int y y^T (xx, yy, zz, xy, xz, yz), y = x - p.

    Summed in blocks of 256 faces, then the blocks (rounding grows with the block count).
    """
    nf = F.shape[0]
    blk = np.zeros(10)
    for s in range(0, nf, 256):
        for i in range(10):
            blk[i] = 0.0
        for f in range(s, min(nf, s + 256)):
            wf = w[f]
            if wf == 0.0:
                continue
            ax = V[F[f, 0], 0] - px
            ay = V[F[f, 0], 1] - py
            az = V[F[f, 0], 2] - pz
            bx = V[F[f, 1], 0] - px
            by = V[F[f, 1], 1] - py
            bz = V[F[f, 1], 2] - pz
            cx = V[F[f, 2], 0] - px
            cy = V[F[f, 2], 1] - py
            cz = V[F[f, 2], 2] - pz
            tetra_add(blk, wf, ax, ay, az, bx, by, bz, cx, cy, cz)
        for i in range(10):
            out[i] += blk[i]


def ear_clip(P, out):
    """Triangulate the simple polygon P (n, 2) (in order) by ear clipping: triangles (a, b, c)
    of vertex indices into ``out`` (n - 2, 3), in P's order; returns n - 2, or -1 when P is
    not simple (two non-adjacent edges meet, or an edge turns back) or no ear is found.

    O(n^2): the simplicity test compares every pair of edges; an ear is a convex vertex whose
    triangle holds no other remaining vertex (boundary included: conservative).
    """
    n = P.shape[0]
    if n < 3:
        return -1
    scale = 0.0
    area2 = 0.0
    for i in range(n):
        j = (i + 1) % n
        scale = max(scale, abs(P[i, 0]), abs(P[i, 1]))
        area2 += P[i, 0] * P[j, 1] - P[j, 0] * P[i, 1]
    if area2 == 0.0:
        return -1
    sgn = 1.0 if area2 > 0.0 else -1.0
    tiny = 1e-14 * scale * scale
    # simple: no edge turns back, non-adjacent edges do not meet
    for i in range(n):
        a = (i + n - 1) % n
        c = (i + 1) % n
        cr = (P[i, 0] - P[a, 0]) * (P[c, 1] - P[i, 1]) - (P[i, 1] - P[a, 1]) * (P[c, 0] - P[i, 0])
        dt = (P[i, 0] - P[a, 0]) * (P[c, 0] - P[i, 0]) + (P[i, 1] - P[a, 1]) * (P[c, 1] - P[i, 1])
        if abs(cr) <= tiny and dt < 0.0:
            return -1
    for i in range(n):
        for j in range(i + 2, n):
            if i == 0 and j == n - 1:
                continue
            if _segments_meet(P, i, (i + 1) % n, j, (j + 1) % n, tiny):
                return -1
    prv = np.empty(n, np.int64)
    nxt = np.empty(n, np.int64)
    for i in range(n):
        prv[i] = (i + n - 1) % n
        nxt[i] = (i + 1) % n
    left = n
    b = 0
    nt = 0
    misses = 0
    while left > 3:
        a = prv[b]
        c = nxt[b]
        if _is_ear(P, prv, nxt, a, b, c, sgn, tiny):
            out[nt, 0] = a
            out[nt, 1] = b
            out[nt, 2] = c
            nt += 1
            nxt[a] = c
            prv[c] = a
            left -= 1
            misses = 0
            b = c
        else:
            misses += 1
            if misses > left:
                return -1
            b = c
    out[nt, 0] = prv[b]
    out[nt, 1] = b
    out[nt, 2] = nxt[b]
    return nt + 1


def _cross2(P, a, b, c):
    return (P[b, 0] - P[a, 0]) * (P[c, 1] - P[a, 1]) - (P[b, 1] - P[a, 1]) * (P[c, 0] - P[a, 0])


def _segments_meet(P, a, b, c, d, tiny):
    """Closed segments ab and cd share a point (within ``tiny`` of the cross products)."""
    d1 = _cross2(P, a, b, c)
    d2 = _cross2(P, a, b, d)
    d3 = _cross2(P, c, d, a)
    d4 = _cross2(P, c, d, b)
    if ((d1 > tiny and d2 > tiny) or (d1 < -tiny and d2 < -tiny) or (d3 > tiny and d4 > tiny)
            or (d3 < -tiny and d4 < -tiny)):
        return False
    if abs(d1) <= tiny and abs(d2) <= tiny:
        # collinear: do the projections overlap?
        for k in range(2):
            lo1 = min(P[a, k], P[b, k])
            hi1 = max(P[a, k], P[b, k])
            lo2 = min(P[c, k], P[d, k])
            hi2 = max(P[c, k], P[d, k])
            if lo1 > hi2 or lo2 > hi1:
                return False
    return True


def _is_ear(P, prv, nxt, a, b, c, sgn, tiny):
    """b is convex (beyond tiny) and no other remaining vertex lies in the closed triangle abc."""
    if sgn * _cross2(P, a, b, c) <= tiny:
        return False
    q = nxt[c]
    while q != a:
        if (sgn * _cross2(P, a, b, q) >= -tiny and sgn * _cross2(P, b, c, q) >= -tiny
                and sgn * _cross2(P, c, a, q) >= -tiny):
            return False
        q = nxt[q]
    return True
