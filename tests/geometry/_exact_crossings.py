"""Truth for the self-crossing tests: every pair of faces that cross, by brute force in exact
integer arithmetic, on shells whose vertices are small integers.

Two faces cross when an edge of one passes strictly through the interior of the other: its ends
strictly on both sides of the other's plane, and the line through it strictly inside the three
edges' planes (the triple products of the edge with each side, all of one sign).  With corners
below 2^9 every such product is an exact int64, and the compiled test's tolerance (1e-9 L^3,
L < 900) is below 1: the two agree exactly there, so any disagreement is a bug."""

from __future__ import annotations

from fractions import Fraction

import numpy as np

#: integer corners lie in 0..SPAN (orientations then exact in int64, the tolerance below 1)
SPAN = 500


def integer_shell(rng, it: int, min_faces: int = 0):
    """A closed shell (a torus, or a sphere every third time) scaled to 0..SPAN, its vertices
    moved at random by up to about an edge and rounded to integers: (vertices float64, faces)."""
    import trimesh

    while True:
        if it % 3:
            m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=int(rng.integers(12, 40)),
                                       minor_sections=int(rng.integers(8, 20)))
        else:
            m = trimesh.creation.icosphere(int(rng.integers(2, 4)))
        v, f = np.array(m.vertices, float), np.ascontiguousarray(m.faces, dtype=np.int64)
        while len(f) < min_faces:
            v, f = trimesh.remesh.subdivide(v, f)
        v = (v - v.min(0)) / np.ptp(v).max() * (SPAN - 40) + 20
        edge = np.median(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1))
        v = v + rng.normal(0, rng.choice([0.0, 0.1, 0.3, 0.6, 1.2]) * edge, v.shape)
        v = np.clip(np.round(v), 0, SPAN)
        return np.ascontiguousarray(v), np.ascontiguousarray(f, dtype=np.int64)


def _orient(a, b, c, d):
    """Six times the signed volume of (a, b, c, d), row-wise, int64."""
    u, v, w = b - a, c - a, d - a
    return ((u[:, 1] * v[:, 2] - u[:, 2] * v[:, 1]) * w[:, 0] + (u[:, 2] * v[:, 0] - u[:, 0] * v[:, 2]) * w[:, 1]
            + (u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]) * w[:, 2])


def _edge_through(p, q, a, b, c):
    sp, sq = _orient(a, b, c, p), _orient(a, b, c, q)
    s = np.stack([_orient(p, q, a, b), _orient(p, q, b, c), _orient(p, q, c, a)])
    return (sp * sq < 0) & ((s > 0).all(axis=0) | (s < 0).all(axis=0))


def cross(v, f, i, j) -> np.ndarray:
    """(N,) bool: faces f[i] and f[j] cross (integer vertices ``v``), exactly."""
    V = np.asarray(v).astype(np.int64)
    A, B = V[f[i]], V[f[j]]
    hit = np.zeros(len(A), dtype=bool)
    for S, T in ((A, B), (B, A)):
        for k in range(3):
            hit |= _edge_through(S[:, k], S[:, (k + 1) % 3], T[:, 0], T[:, 1], T[:, 2])
    return hit


def crossing_pairs(v, f) -> set:
    """Every pair (i < j) of faces that cross (boxes first, then the exact test)."""
    tri = np.asarray(v)[f]
    lo, hi = tri.min(axis=1), tri.max(axis=1)
    pairs = set()
    for s in range(0, len(f), 256):               # boxes that overlap, 256 rows at a time
        meet = np.all((lo[None, :] <= hi[s:s + 256, None]) & (hi[None, :] >= lo[s:s + 256, None]), axis=2)
        i, j = np.nonzero(meet)
        i += s
        i, j = i[i < j], j[i < j]
        hit = cross(v, f, i, j)
        pairs.update(zip(i[hit].tolist(), j[hit].tolist()))
    return pairs


def crosses_rationally(A, B) -> bool:
    """Triangles A and B (3, 3) of any float coordinates cross, in rational arithmetic."""
    def orient(a, b, c, d):
        a, b, c, d = ([Fraction(x) for x in p] for p in (a, b, c, d))
        u = [b[k] - a[k] for k in range(3)]
        w = [c[k] - a[k] for k in range(3)]
        z = [d[k] - a[k] for k in range(3)]
        return ((u[1] * w[2] - u[2] * w[1]) * z[0] + (u[2] * w[0] - u[0] * w[2]) * z[1]
                + (u[0] * w[1] - u[1] * w[0]) * z[2])

    def edge_through(p, q, T):
        s = [orient(p, q, T[k], T[(k + 1) % 3]) for k in range(3)]
        return orient(*T, p) * orient(*T, q) < 0 and (all(x > 0 for x in s) or all(x < 0 for x in s))

    return any(edge_through(P[k], P[(k + 1) % 3], Q) for P, Q in ((A, B), (B, A)) for k in range(3))
