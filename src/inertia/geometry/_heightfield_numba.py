"""Numba kernels: a proof, cell by cell of a coarse grid, that a closed shell does not cross
itself, for the shells the star certificate cannot prove (a torus, a bracket), so that the
face-pair search runs only where the proof fails.

The argument.  If two faces cross, they share a point x, and x lies in some cell C of a grid;
both faces' boxes hold x, so both are among the faces whose boxes meet C (the cell's *patch*).
So it is enough that no two faces of each patch meet but along the edges and vertices they
share.  A patch proves that when it is a *height field* along one of the six axis directions
d (projecting along an axis drops a coordinate: the projected corners are the input numbers,
no rounding):

1. every face is positively oriented seen along d (the d-component of its normal beyond a
   margin of 1e-12 of its box diagonal squared: the normal's own rounding is below 1e-15);
2. the patch's *border* (its edges whose face across is not in the patch) is one closed loop
   that leaves and enters each vertex at most once, and its projection is a simple polygon
   (every pair of border edges that are not neighbours in the loop apart, by boxes or by
   orientation signs beyond their rounding bound).

Why that is enough.  Take a point y of the plane on no projected edge and count the faces
whose projections hold y.  A face turning counterclockwise holds y exactly when its border
winds once around y, so the count is how often the sum of the faces' borders winds around y.
In that sum an edge inside the patch comes twice, once each way (the shell is closed and
consistently wound: the face across runs it the other way), and cancels; what is left is the
border loop, which, simple, winds at most once around any point.  So no two projected faces
overlap on an open set.  Two faces that met at a point they do not share would: where the
point is inside either projection at once; on a side inside the patch, the face across covers
the other side of it (and meets the first only along that side); at a vertex inside the
patch, its fan covers a whole neighbourhood (once: more would count two); and two points of
the border are apart unless neighbours in the loop share them (a loop folding onto itself
meets a third border edge, or, of three edges, winds around nothing, which positive faces
cannot be).  So no two faces of a proved patch meet but along the edges and vertices they
share; no test of the fans around the vertices is needed (a fan that winds twice, or turns
more than once on the border, makes the border loop cross itself).

A patch that fails is cut into 8 and each part tried again (twice); the faces of the parts
still unproved go to the face-pair search (:func:`._selfcross_numba.first_crossing`).

Every test that rounding could decide is made with a margin, and the doubtful side is
"not proved": the proof is never wrong, at worst it leaves a cell to the search.  Cells are
filed in scaled coordinates ``(x - origin) (1 / h)`` widened by :data:`CELL_SLACK` cells (the
rounding of that product is 1e-10 cells at most on the grid sizes used), so a face is filed in
every cell its box meets.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_JIT = dict(cache=True, nogil=True, boundscheck=False)

#: a face is positively oriented along the axis when its normal's component there is above
#: this times its box diagonal squared (the component's rounding is below 1e-15 of that)
ORIENT_MARGIN = 1e-12
#: cells (scaled units) by which a face's box is widened when filed (rounding is < 1e-10)
CELL_SLACK = 1e-9
#: the rounding bound of a 2-D orientation, relative to |t1| + |t2| (Shewchuk's is 3.3e-16)
_CCW_BOUND = 1e-15
#: a patch is cut into 8 parts up to this many times before its faces go to the search
MAX_DEPTH = 2
#: a patch of fewer faces is not cut (its faces go to the search)
MIN_CUT = 8
#: the grid's cells are this many times the median longest edge of the faces
CELL_EDGES = 4.0
#: the median longest edge (the grids' cell size) is taken over at most about this many faces
MEDIAN_SAMPLE = 1024
#: at most this many cells per face in the grid (cells grow until it holds)
MAX_CELLS_PER_FACE = 4


@nb.njit(**_JIT)
def vertex_slots(F, nv):
    """The faces around each vertex, by a counting sort: vertex v's slots are
    ``start[v]:start[v + 1]``; slot s holds the face ``fac[s]`` and, in it, the corner after v
    ``nxt[s]``."""
    nf = F.shape[0]
    start = np.zeros(nv + 1, dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            start[F[t, k] + 1] += 1
    for i in range(nv):
        start[i + 1] += start[i]
    fill = start[:-1].copy()
    nxt = np.empty(3 * nf, dtype=np.int64)
    fac = np.empty(3 * nf, dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            v = F[t, k]
            s = fill[v]
            fill[v] += 1
            nxt[s] = F[t, (k + 1) % 3]
            fac[s] = t
    return start, fac, nxt


@nb.njit(**_JIT)
def face_twins(F, nv):
    """``adj[t, k]``: the face across the edge ``F[t, k] -> F[t, k + 1]`` (the one face with
    the edge the other way), and True; False when an edge has no such face or several (the
    shell is then not a closed, consistently wound surface: nothing is proved)."""
    nf = F.shape[0]
    start, fac, nxt = vertex_slots(F, nv)
    adj = np.empty((nf, 3), dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            a = F[t, k]
            b = F[t, (k + 1) % 3]
            found = -1
            for s in range(start[b], start[b + 1]):
                if nxt[s] == a:
                    if found >= 0:
                        return adj, False
                    found = fac[s]
            if found < 0:
                return adj, False
            adj[t, k] = found
    return adj, True


@nb.njit(**_JIT)
def _orient_sign(pu, pw, qu, qw, ru, rw):
    """Sign of the 2-D orientation (p, q, r): 1, -1, or 0 when rounding could decide it."""
    t1 = (qu - pu) * (rw - pw)
    t2 = (qw - pw) * (ru - pu)
    det = t1 - t2
    bound = _CCW_BOUND * (abs(t1) + abs(t2))
    if det > bound:
        return 1
    if det < -bound:
        return -1
    return 0


@nb.njit(**_JIT)
def _simple_loop(V, iu, iw, loop, m, fwork, order):
    """The closed polygon ``loop[:m]`` (vertex numbers, projected on iu, iw) is simple: every
    pair of edges that are not neighbours in the loop proved apart.  The edges are sorted by
    their lowest u; each is compared with those that start before it ends (a sweep).
    ``fwork``: 3 m floats; ``order``: m integers."""
    pu = fwork[:m]
    pw = fwork[m:2 * m]
    lo_u = fwork[2 * m:3 * m]
    for i in range(m):
        pu[i] = V[loop[i], iu]
        pw[i] = V[loop[i], iw]
    for i in range(m):
        i2 = i + 1 if i + 1 < m else 0
        x = min(pu[i], pu[i2])
        lo_u[i] = x
        r = i                             # insertion sort of the edges by lowest u
        while r > 0 and lo_u[order[r - 1]] > x:
            order[r] = order[r - 1]
            r -= 1
        order[r] = i
    for r in range(m):
        i = order[r]
        i2 = i + 1 if i + 1 < m else 0
        i0 = i - 1 if i > 0 else m - 1
        pu1 = pu[i]
        pw1 = pw[i]
        pu2 = pu[i2]
        pw2 = pw[i2]
        hu = max(pu1, pu2)
        lw = min(pw1, pw2)
        hw = max(pw1, pw2)
        for q in range(r + 1, m):
            j = order[q]
            if lo_u[j] > hu:
                break                     # this one and the rest start after edge i ends
            if j == i2 or j == i0:
                continue                  # neighbours in the loop meet at their corner
            j2 = j + 1 if j + 1 < m else 0
            qw1 = pw[j]
            qw2 = pw[j2]
            if min(qw1, qw2) > hw or max(qw1, qw2) < lw:
                continue                  # the boxes are apart
            qu1 = pu[j]
            qu2 = pu[j2]
            s1 = _orient_sign(pu1, pw1, pu2, pw2, qu1, qw1)
            s2 = _orient_sign(pu1, pw1, pu2, pw2, qu2, qw2)
            if s1 != 0 and s1 == s2:
                continue                  # q on one side of p's line
            s3 = _orient_sign(qu1, qw1, qu2, qw2, pu1, pw1)
            s4 = _orient_sign(qu1, qw1, qu2, qw2, pu2, pw2)
            if s3 != 0 and s3 == s4:
                continue
            return False
    return True


@nb.njit(**_JIT)
def _turn_bits(nx, ny, nz, m):
    """The orientation bits of a face of normal ``n`` (margin ``m``): see :func:`orientation_bits`."""
    bits = 0
    if nx > m:
        bits |= 1
    elif nx < -m:
        bits |= 8
    if ny > m:
        bits |= 2
    elif ny < -m:
        bits |= 16
    if nz > m:
        bits |= 4
    elif nz < -m:
        bits |= 32
    return bits


@nb.njit(**_JIT)
def face_normal(V, a, b, c):
    """``(b - a) x (c - a)``, the normal of face ``a, b, c`` (:func:`._selfcross_numba.face_frames` too)."""
    ux = V[b, 0] - V[a, 0]
    uy = V[b, 1] - V[a, 1]
    uz = V[b, 2] - V[a, 2]
    vx = V[c, 0] - V[a, 0]
    vy = V[c, 1] - V[a, 1]
    vz = V[c, 2] - V[a, 2]
    return uy * vz - uz * vy, uz * vx - ux * vz, ux * vy - uy * vx


@nb.njit(**_JIT)
def orientation_bits(V, F):
    """Per face, the axis directions along which it turns counterclockwise (test 1 of the
    module docstring): bits 1, 2, 4 for +x, +y, +z and 8, 16, 32 for -x, -y, -z (uint8), set
    where the normal's component is beyond :data:`ORIENT_MARGIN` times the face's box
    diagonal squared.  A patch is oriented along the directions of all its faces' bits."""
    return boxes_and_bits(V, F, np.zeros(3), 1.0)[2]


@nb.njit(**_JIT)
def boxes_and_bits(V, F, origin, inv):
    """``(lo, hi, bits)``: each face's box in scaled coordinates ``(x - origin) inv`` (F, 3)
    twice, and its :func:`orientation_bits`, in one pass over the corners (the normals and box
    diagonals of every face are not kept: the search computes those of the faces it keeps)."""
    nf = F.shape[0]
    bl = np.empty((nf, 3))
    bh = np.empty((nf, 3))
    bits = np.empty(nf, dtype=np.uint8)
    for t in range(nf):
        a = F[t, 0]
        b = F[t, 1]
        c = F[t, 2]
        dd = 0.0
        for k in range(3):
            lo = min(V[a, k], V[b, k], V[c, k])
            hi = max(V[a, k], V[b, k], V[c, k])
            bl[t, k] = (lo - origin[k]) * inv
            bh[t, k] = (hi - origin[k]) * inv
            dd += (hi - lo) * (hi - lo)
        nx, ny, nz = face_normal(V, a, b, c)
        bits[t] = _turn_bits(nx, ny, nz, ORIENT_MARGIN * dd)
    return bl, bh, bits


@nb.njit(**_JIT)
def patch_check(V, F, omask, adj, faces, n, mark, fstamp, vwork, iwork, fwork):
    """0 when the faces ``faces[:n]`` form a height field along one axis (see the module
    docstring): then no two of them meet but where they share edges and vertices.  Else the
    first test failed: 1 a face not turned along the axis, 2 two border edges out of (or into)
    a vertex, 3 fewer than three border edges, 4 more than one border loop, 5 a border loop
    not simple.  ``omask``: :func:`orientation_bits` of the faces.  ``mark`` is a number not
    used by an earlier call with the same work arrays: ``fstamp`` (F,) and ``vwork`` (V, 3)
    int64 (per vertex: stamp, border edge out and in), ``iwork`` int64 and ``fwork``
    float64 of 6 n and 9 n."""
    if n < 2:
        return 0
    # the directions along which every face turns counterclockwise (bits: orientation_bits)
    bits = 63
    for i in range(n):
        t = faces[i]
        bits &= omask[t]
        if bits == 0:
            return 1
        fstamp[t] = mark                   # (a patch refused here leaves some stamped: mark changes)
    if bits & 1:
        ax = 0
    elif bits & 2:
        ax = 1
    elif bits & 4:
        ax = 2
    elif bits & 8:
        ax = 3
    elif bits & 16:
        ax = 4
    else:
        ax = 5
    # (u, w, d) right-handed: the faces turn counterclockwise in (u, w) seen along d
    if ax == 0:
        iu, iw = 1, 2
    elif ax == 1:
        iu, iw = 2, 0
    elif ax == 2:
        iu, iw = 0, 1
    elif ax == 3:
        iu, iw = 2, 1
    elif ax == 4:
        iu, iw = 0, 2
    else:
        iu, iw = 1, 0
    # the border: the edges whose face across is not in the patch, each vertex's out and in
    # (vwork[v, 1] and vwork[v, 2], valid while vwork[v, 0] is mark)
    n_border = 0
    first = -1
    for i in range(n):
        t = faces[i]
        for k in range(3):
            if fstamp[adj[t, k]] != mark:  # the edge v -> a is on the patch's border
                v = F[t, k]
                a = F[t, (k + 1) % 3]
                if vwork[v, 0] != mark:
                    vwork[v, 0] = mark
                    vwork[v, 1] = -1
                    vwork[v, 2] = -1
                if vwork[a, 0] != mark:
                    vwork[a, 0] = mark
                    vwork[a, 1] = -1
                    vwork[a, 2] = -1
                if vwork[v, 1] >= 0 or vwork[a, 2] >= 0:
                    return 2               # two border edges out of v, or into a
                vwork[v, 1] = a
                vwork[a, 2] = v
                n_border += 1
                first = v
    if n_border < 3:
        return 3
    # one loop: from a border vertex, n_border steps along the edges out come back to it, and
    # not before (no edge is met twice: a vertex has one edge in)
    v = first
    for i in range(n_border):
        iwork[i] = v
        v = vwork[v, 1]
        if v < 0 or (v == first and i < n_border - 1):
            return 4
    if v != first:
        return 4
    return 0 if _simple_loop(V, iu, iw, iwork, n_border, fwork, iwork[n_border:]) else 5


@nb.njit(**_JIT)
def box_and_median_edge(V, F):
    """The low and high corners (3,) of the vertices the faces use, and the median of the
    faces' longest edges (the cell of the face-pair search's grid), taken over at most
    :data:`MEDIAN_SAMPLE` faces evenly spread (a cell size, not a measurement)."""
    nf = F.shape[0]
    lx = ly = lz = np.inf
    hx = hy = hz = -np.inf
    for t in range(nf):
        for k in range(3):
            a = F[t, k]
            x = V[a, 0]
            y = V[a, 1]
            z = V[a, 2]
            lx = min(lx, x)
            ly = min(ly, y)
            lz = min(lz, z)
            hx = max(hx, x)
            hy = max(hy, y)
            hz = max(hz, z)
    origin = np.array([lx, ly, lz])
    top = np.array([hx, hy, hz])
    stride = max(1, nf // MEDIAN_SAMPLE)
    longest = np.empty((nf + stride - 1) // stride)
    for i in range(longest.shape[0]):
        t = i * stride
        m = 0.0
        for k in range(3):
            a = F[t, k]
            b = F[t, (k + 1) % 3]
            dx = V[b, 0] - V[a, 0]
            dy = V[b, 1] - V[a, 1]
            dz = V[b, 2] - V[a, 2]
            m = max(m, dx * dx + dy * dy + dz * dz)
        longest[i] = m
    return origin, top, np.sqrt(np.median(longest))


@nb.njit(**_JIT)
def unproved_faces(V, F, adj, origin, top, h, keep):
    """Set ``keep[t]`` for the faces of the patches that :func:`patch_check` does
    not prove, cutting each failed cell into 8 up to :data:`MAX_DEPTH` times; returns how many.
    ``adj``: :func:`face_twins`; ``origin``, ``top``, and ``h`` (the cell, :data:`CELL_EDGES`
    median longest edges): :func:`box_and_median_edge`."""
    nf = F.shape[0]
    nv = V.shape[0]
    if not (h > 0.0 and h < np.inf):
        for t in range(nf):
            keep[t] = True
        return nf
    # the grid's cells at most MAX_CELLS_PER_FACE per face, and 1e5 per axis
    while True:
        dims = np.empty(3, dtype=np.int64)
        cells = 1.0
        for c in range(3):
            d = np.floor((top[c] - origin[c]) / h + CELL_SLACK) + 1.0
            cells *= d
            dims[c] = np.int64(min(d, 1e5))
        if cells <= MAX_CELLS_PER_FACE * nf + 64 and dims.max() < 100000:
            break
        h *= 2.0
    inv = 1.0 / h                          # a product for each division: 5 % of the proof's time
    bl, bh, omask = boxes_and_bits(V, F, origin, inv)
    ncell = dims[0] * dims[1] * dims[2]
    counts = np.zeros(ncell + 1, dtype=np.int64)
    ilo = np.empty((nf, 3), dtype=np.int64)
    ihi = np.empty((nf, 3), dtype=np.int64)
    for t in range(nf):
        for c in range(3):
            ilo[t, c] = max(np.int64(np.floor(bl[t, c] - CELL_SLACK)), 0)
            ihi[t, c] = min(np.int64(np.floor(bh[t, c] + CELL_SLACK)), dims[c] - 1)
        if ilo[t, 0] == ihi[t, 0] and ilo[t, 1] == ihi[t, 1] and ilo[t, 2] == ihi[t, 2]:
            # most faces (a quarter of a cell long) lie in one cell: no loop nest
            counts[(ilo[t, 0] * dims[1] + ilo[t, 1]) * dims[2] + ilo[t, 2] + 1] += 1
            continue
        for x in range(ilo[t, 0], ihi[t, 0] + 1):
            for y in range(ilo[t, 1], ihi[t, 1] + 1):
                for z in range(ilo[t, 2], ihi[t, 2] + 1):
                    counts[(x * dims[1] + y) * dims[2] + z + 1] += 1
    for i in range(ncell):
        counts[i + 1] += counts[i]
    fill = counts[:-1].copy()
    entries = np.empty(counts[ncell], dtype=np.int64)
    for t in range(nf):
        if ilo[t, 0] == ihi[t, 0] and ilo[t, 1] == ihi[t, 1] and ilo[t, 2] == ihi[t, 2]:
            i = (ilo[t, 0] * dims[1] + ilo[t, 1]) * dims[2] + ilo[t, 2]
            entries[fill[i]] = t
            fill[i] += 1
            continue
        for x in range(ilo[t, 0], ihi[t, 0] + 1):
            for y in range(ilo[t, 1], ihi[t, 1] + 1):
                for z in range(ilo[t, 2], ihi[t, 2] + 1):
                    i = (x * dims[1] + y) * dims[2] + z
                    entries[fill[i]] = t
                    fill[i] += 1
    fstamp = np.full(nf, -1, dtype=np.int64)
    vwork = np.full((nv, 3), -1, dtype=np.int64)
    biggest = 1
    for i in range(ncell):
        biggest = max(biggest, counts[i + 1] - counts[i])
    iwork = np.empty(6 * biggest, dtype=np.int64)
    fwork = np.empty(9 * biggest)
    # work stack of the cut parts: faces, and the part's low corner and size (scaled); the parts
    # of a part of m faces take 8 m slots above it, and a part holds at most its parent's faces:
    # (8 MAX_DEPTH + 1) times the largest cell at most
    room = biggest * (8 * MAX_DEPTH + 1)
    stack_faces = np.empty(room, dtype=np.int64)
    st_start = np.empty(8 * MAX_DEPTH + 1, dtype=np.int64)
    st_n = np.empty(8 * MAX_DEPTH + 1, dtype=np.int64)
    st_lo = np.empty((8 * MAX_DEPTH + 1, 3))
    st_size = np.empty(8 * MAX_DEPTH + 1)
    st_depth = np.empty(8 * MAX_DEPTH + 1, dtype=np.int64)
    mark = 0
    n_keep = 0
    for x in range(dims[0]):
        for y in range(dims[1]):
            for z in range(dims[2]):
                i = (x * dims[1] + y) * dims[2] + z
                c0 = counts[i]
                n = counts[i + 1] - c0
                if n < 2:
                    continue
                if patch_check(V, F, omask, adj, entries[c0:], n, mark, fstamp, vwork, iwork, fwork) == 0:
                    mark += 1
                    continue
                mark += 1
                # cut it: depth-first over the parts
                for k in range(n):
                    stack_faces[k] = entries[c0 + k]
                sp = 1
                st_start[0] = 0
                st_n[0] = n
                st_lo[0, 0] = x
                st_lo[0, 1] = y
                st_lo[0, 2] = z
                st_size[0] = 1.0
                st_depth[0] = 0
                first_pop = True
                while sp > 0:
                    sp -= 1
                    s0 = st_start[sp]
                    m = st_n[sp]
                    depth = st_depth[sp]
                    if not first_pop:
                        if m < 2 or patch_check(V, F, omask, adj, stack_faces[s0:], m, mark, fstamp,
                                                vwork, iwork, fwork) == 0:
                            mark += 1
                            continue
                        mark += 1
                    first_pop = False
                    if depth >= MAX_DEPTH or m < MIN_CUT:
                        for k in range(m):
                            t = stack_faces[s0 + k]
                            if not keep[t]:
                                keep[t] = True
                                n_keep += 1
                        continue
                    half = 0.5 * st_size[sp]
                    lx = st_lo[sp, 0]
                    ly = st_lo[sp, 1]
                    lz = st_lo[sp, 2]
                    # the parts' faces go above this part's (which stays until its parts are
                    # done), part p's in m slots from base + m p.  A face goes to the parts on
                    # the sides of the three inner planes that its box reaches (with the slack):
                    # every part it meets (a face that meets a part meets this one, so it is
                    # here), and at worst a few more (sound: a patch of more faces proves more)
                    base = s0 + m
                    mx = lx + half
                    my = ly + half
                    mz = lz + half
                    for part in range(8):
                        st_n[sp + part] = 0
                    for k in range(m):
                        t = stack_faces[s0 + k]
                        x0 = 0 if bl[t, 0] <= mx + CELL_SLACK else 1
                        x1 = 2 if bh[t, 0] >= mx - CELL_SLACK else 1
                        y0 = 0 if bl[t, 1] <= my + CELL_SLACK else 1
                        y1 = 2 if bh[t, 1] >= my - CELL_SLACK else 1
                        z0 = 0 if bl[t, 2] <= mz + CELL_SLACK else 1
                        z1 = 2 if bh[t, 2] >= mz - CELL_SLACK else 1
                        if x1 - x0 + y1 - y0 + z1 - z0 == 3:    # in one part (most): no loop nest
                            part = x0 + 2 * y0 + 4 * z0
                            stack_faces[base + part * m + st_n[sp + part]] = t
                            st_n[sp + part] += 1
                            continue
                        for zb in range(z0, z1):
                            for yb in range(y0, y1):
                                for xb in range(x0, x1):
                                    part = xb + 2 * yb + 4 * zb
                                    stack_faces[base + part * m + st_n[sp + part]] = t
                                    st_n[sp + part] += 1
                    for part in range(8):
                        st_start[sp] = base + part * m
                        st_lo[sp, 0] = lx + half * (part & 1)
                        st_lo[sp, 1] = ly + half * ((part >> 1) & 1)
                        st_lo[sp, 2] = lz + half * ((part >> 2) & 1)
                        st_size[sp] = half
                        st_depth[sp] = depth + 1
                        sp += 1
    return n_keep
