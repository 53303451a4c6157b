"""Small numba kernels shared by the mesh checks: union-find with the lowest index as root,
and generalized winding numbers (the compiled twin of the NumPy evaluation).  The common
case of a solid mesh is :mod:`._solid_numba`.
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
