"""Numba kernel of the mesh checks' common case: is a welded mesh one closed, consistently
wound, outward, non-degenerate shell?  (See :mod:`._topology_numba`, which re-exports it.)

One numeric kernel that reads better whole (half-edge sort, pairing, orientation and volume
in one pass): split, its phases would pass large temporaries between calls.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_JIT = dict(cache=True, nogil=True, boundscheck=False)


# union-find with the lowest index as root (shared with _topology_numba.near_merge_map)
@nb.njit(**_JIT)
def find_root(parent, i):
    """Root of i, halving the path as it goes."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@nb.njit(**_JIT)
def union_low(parent, a, b):
    """Join the sets of a and b; the lower root becomes the root (so roots are group minima)."""
    ra = find_root(parent, a)
    rb = find_root(parent, b)
    if ra < rb:
        parent[rb] = ra
    elif rb < ra:
        parent[ra] = rb


@nb.njit(**_JIT)
def closed_single_shell(vertices, faces, area_rtol, out):
    """True when the mesh is one closed, consistently wound component of positive volume.

    ``faces`` index distinct positions (welded).  "Closed single shell" here means every
    check of ``checks.analyse_mesh`` passes with no defect and no note: indices in range,
    finite vertices, no face repeating a vertex or of area <= ``area_rtol`` x its longest
    edge^2, every edge used by exactly two faces in opposite directions, one
    edge-connected component, signed volume > 0.  Duplicate faces need no test: a face
    whose three edges are each shared with its duplicate forms, with it, a closed component
    of its own, so one component means F = 2 and volume 0, which fails anyway.

    On True, ``out[0]`` is the total area and ``out[1]`` the signed volume (coordinates
    relative to the bounding-box center of the used vertices, as in the NumPy analysis).

    Four passes over the faces: count the half-edges per lower vertex (and check indices),
    then (over the vertices) the bounding box of the used ones,
    then per face the area, the signed volume and the filing of its half-edges in a table
    by lower vertex (CSR), then the matching of each vertex's list, then the components.
    """
    nv = vertices.shape[0]
    nf = faces.shape[0]
    if nf < 4 or nv < 4 or nv >= 2 ** 31 or 3 * nf >= 2 ** 31:
        return False
    # half-edges a -> b are filed under min(a, b)
    start = np.zeros(nv + 1, dtype=np.int64)
    used = np.zeros(nv, dtype=np.bool_)
    for t in range(nf):
        ia = faces[t, 0]
        ib = faces[t, 1]
        ic = faces[t, 2]
        if ia < 0 or ia >= nv or ib < 0 or ib >= nv or ic < 0 or ic >= nv:
            return False
        if ia == ib or ib == ic or ic == ia:
            return False
        used[ia] = True
        used[ib] = True
        used[ic] = True
        start[min(ia, ib) + 1] += 1
        start[min(ib, ic) + 1] += 1
        start[min(ic, ia) + 1] += 1
    big = np.inf
    lo0, lo1, lo2 = big, big, big
    hi0, hi1, hi2 = -big, -big, -big
    for i in range(nv):
        x = vertices[i, 0]
        y = vertices[i, 1]
        z = vertices[i, 2]
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(z)):
            return False              # any vertex, used or not, as the NumPy check does
        start[i + 1] += start[i]
        if not used[i]:
            continue
        lo0 = min(lo0, x)
        hi0 = max(hi0, x)
        lo1 = min(lo1, y)
        hi1 = max(hi1, y)
        lo2 = min(lo2, z)
        hi2 = max(hi2, z)
    r0 = 0.5 * (lo0 + hi0)
    r1 = 0.5 * (lo1 + hi1)
    r2 = 0.5 * (lo2 + hi2)
    twice_area = 0.0
    det_sum = 0.0
    fill = start[:-1].copy()
    upper = np.empty(3 * nf, dtype=np.int32)     # the other vertex + 1, negated when running down
    owner = np.empty(3 * nf, dtype=np.int32)     # the face of the half-edge
    for t in range(nf):
        ia = faces[t, 0]
        ib = faces[t, 1]
        ic = faces[t, 2]
        ax = vertices[ia, 0] - r0
        ay = vertices[ia, 1] - r1
        az = vertices[ia, 2] - r2
        ux = (vertices[ib, 0] - r0) - ax
        uy = (vertices[ib, 1] - r1) - ay
        uz = (vertices[ib, 2] - r2) - az
        wx = (vertices[ic, 0] - r0) - ax
        wy = (vertices[ic, 1] - r1) - ay
        wz = (vertices[ic, 2] - r2) - az
        nx = uy * wz - uz * wy
        ny = uz * wx - ux * wz
        nz = ux * wy - uy * wx
        a2 = np.sqrt(nx * nx + ny * ny + nz * nz)
        # zero area relative to the face's own size (longest edge squared), not the mesh's
        vx, vy, vz = wx - ux, wy - uy, wz - uz
        e2 = max(ux * ux + uy * uy + uz * uz, wx * wx + wy * wy + wz * wz, vx * vx + vy * vy + vz * vz)
        if not (0.5 * a2 > area_rtol * e2):
            return False
        twice_area += a2
        det_sum += ax * nx + ay * ny + az * nz
        for k in range(3):
            a = faces[t, k]
            b = faces[t, (k + 1) % 3]
            if a < b:
                j = fill[a]
                fill[a] += 1
                upper[j] = b + 1
            else:
                j = fill[b]
                fill[b] += 1
                upper[j] = -(a + 1)
            owner[j] = t
    if not (det_sum > 0.0):
        return False
    # each vertex's list: every upper vertex exactly twice, once in each direction
    parent = np.arange(nf)
    for i in range(nv):
        s0 = start[i]
        s1 = start[i + 1]
        if s1 - s0 > 24:   # a high-valence vertex: sort its list so the matching stays linear
            order = np.argsort(np.abs(upper[s0:s1]))
            upper[s0:s1] = upper[s0:s1][order]
            owner[s0:s1] = owner[s0:s1][order]
            j = s0
            while j < s1:
                if j + 1 >= s1 or abs(upper[j + 1]) != abs(upper[j]):
                    return False                 # met once: open
                if j + 2 < s1 and abs(upper[j + 2]) == abs(upper[j]):
                    return False                 # met three times or more: non-manifold
                if upper[j + 1] != -upper[j]:
                    return False                 # both faces run the same way
                union_low(parent, owner[j], owner[j + 1])
                j += 2
            continue
        for j in range(s0, s1):
            u = upper[j]
            if u == 0:
                continue                         # already matched
            partner = -1
            for q in range(j + 1, s1):
                w = upper[q]
                if w == u:
                    return False                 # same direction twice: inconsistent or non-manifold
                if w == -u:
                    if partner >= 0:
                        return False             # non-manifold
                    partner = q
            if partner < 0:
                return False                     # met once: open
            union_low(parent, owner[j], owner[partner])
            upper[partner] = 0
    for t in range(nf):
        if find_root(parent, t) != 0:
            return False                 # more than one component (nesting needs the full check)
    out[0] = 0.5 * twice_area
    out[1] = det_sum / 6.0
    return True


@nb.njit(**_JIT)
def winding_numbers(points, tri):
    """Generalized winding numbers of the triangles ``tri`` (T, 3, 3) at ``points`` (P, 3).

    The compiled twin of :func:`inertia.geometry.intersections.winding_numbers_numpy` (same
    Van Oosterom-Strackee solid angle per triangle, summed per point without temporaries).
    """
    out = np.empty(points.shape[0])
    for p in range(points.shape[0]):
        px, py, pz = points[p, 0], points[p, 1], points[p, 2]
        total = 0.0
        for t in range(tri.shape[0]):
            ax, ay, az = tri[t, 0, 0] - px, tri[t, 0, 1] - py, tri[t, 0, 2] - pz
            bx, by, bz = tri[t, 1, 0] - px, tri[t, 1, 1] - py, tri[t, 1, 2] - pz
            cx, cy, cz = tri[t, 2, 0] - px, tri[t, 2, 1] - py, tri[t, 2, 2] - pz
            la = np.sqrt(ax * ax + ay * ay + az * az)
            lb = np.sqrt(bx * bx + by * by + bz * bz)
            lc = np.sqrt(cx * cx + cy * cy + cz * cz)
            num = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
            den = (la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (ax * cx + ay * cy + az * cz) * lb
                   + (bx * cx + by * cy + bz * cz) * la)
            total += 2.0 * np.arctan2(num, den)
        out[p] = total / (4.0 * np.pi)
    return out
