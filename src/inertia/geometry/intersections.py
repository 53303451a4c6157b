"""Overlapping closed shells: two components of a mesh whose volumes overlap.

Two closed, outward shells that overlap are summed by the divergence-theorem integrals (the
overlap counted twice).  :mod:`inertia.geometry.checks` reports them as ``overlapping_shells``
when, for two components whose bounding boxes overlap, one's surface runs both strictly
inside and strictly outside the other: the generalised winding number of one at the face
surface points of the other is near 1 for some and near 0 for others, or a face of one crosses a
face of the other (an edge strictly through the interior).  Touching parts (a shared face,
coplanar contact), nested shells (a cavity, a part inside a hollow one) and parts apart are
never flagged.

Not detected by default: a single closed shell that passes through itself (its own faces
crossing).  Searching all face pairs of a shell costs far more than the mass properties;
``robust=True`` (:mod:`inertia.geometry.robust`) finds such crossings and integrates the
solid they bound.
"""

from __future__ import annotations

import numpy as np

from .mesh_arrays import pairs_within_groups

#: orientation tests closer to zero than this times L^3 count as touching (L: the larger
#: bounding-box diagonal of the two triangles), i.e. distances below about 1e-9 L
CROSS_RTOL = 1e-9
#: largest component searched for faces crossing faces of the same component
SELF_CHECK_MAX_FACES = 200_000
#: pairs tested per chunk (memory bound: about 1 kB per pair in temporaries)
_CHUNK = 200_000


def _orient(a, b, c, d):
    """Six times the signed volume of the tetrahedra (a, b, c, d), row-wise."""
    return np.einsum("ij,ij->i", np.cross(b - a, c - a), d - a)


def _edge_crosses(p, q, a, b, c, eps):
    """Segment pq passes strictly through the interior of triangle abc (row-wise)."""
    sp, sq = _orient(a, b, c, p), _orient(a, b, c, q)
    opposite = ((sp > eps) & (sq < -eps)) | ((sp < -eps) & (sq > eps))
    u, v, w = _orient(p, q, a, b), _orient(p, q, b, c), _orient(p, q, c, a)
    inside = ((u > eps) & (v > eps) & (w > eps)) | ((u < -eps) & (v < -eps) & (w < -eps))
    return opposite & inside


def _straddles(A, B, eps):
    """The corners of A[i] lie strictly on both sides of B[i]'s plane (row-wise)."""
    o = np.stack([_orient(B[:, 0], B[:, 1], B[:, 2], A[:, k]) for k in range(3)], axis=1)
    return (o > eps[:, None]).any(axis=1) & (o < -eps[:, None]).any(axis=1)


def crossing(T1, T2) -> np.ndarray:
    """(N,) bool: triangles T1[i] (N, 3, 3) and T2[i] cross (an edge of one through the other).

    A pair where one triangle's corners do not lie strictly on both sides of the other's
    plane cannot cross (no edge of the one pierces that plane, and the other's edges lie in
    it, meeting the one at most on its boundary): rejected first, as the compiled twin does.
    """
    L = np.maximum(np.linalg.norm(T1.max(axis=1) - T1.min(axis=1), axis=1),
                   np.linalg.norm(T2.max(axis=1) - T2.min(axis=1), axis=1))
    eps = CROSS_RTOL * L**3
    hit = np.zeros(len(T1), dtype=bool)
    keep = _straddles(T1, T2, eps) & _straddles(T2, T1, eps)
    if not keep.all():
        hit[keep] = crossing(T1[keep], T2[keep]) if keep.any() else hit[keep]
        return hit
    for A, B in ((T1, T2), (T2, T1)):
        for i, j in ((0, 1), (1, 2), (2, 0)):
            hit |= _edge_crosses(A[:, i], A[:, j], B[:, 0], B[:, 1], B[:, 2], eps)
    return hit


def candidate_pairs(vertices, faces, cell: float, max_cells_per_face: int = 64):
    """Pairs (i < j) of faces whose bounding boxes share a grid cell (a superset of the crossings)."""
    tri = vertices[faces]
    origin = vertices.min(axis=0)
    while True:   # cell ranges in floats first: a face 1e20 cells long must not overflow int64
        lo_f = np.floor((tri.min(axis=1) - origin) / cell)
        hi_f = np.floor((tri.max(axis=1) - origin) / cell)
        if not len(tri) or ((hi_f - lo_f + 1).prod(axis=1).max() <= max_cells_per_face and hi_f.max() < 4e18):
            break
        cell *= 2.0                                   # a few huge faces: coarser grid
    lo, hi = lo_f.astype(np.int64), hi_f.astype(np.int64)
    span = hi - lo + 1
    n_cells = span.prod(axis=1)
    face = np.repeat(np.arange(len(faces)), n_cells)
    k = np.arange(len(face)) - np.repeat(np.cumsum(n_cells) - n_cells, n_cells)
    sx, sy = np.repeat(span[:, 0], n_cells), np.repeat(span[:, 1], n_cells)
    ix = np.repeat(lo[:, 0], n_cells) + k % sx
    iy = np.repeat(lo[:, 1], n_cells) + (k // sx) % sy
    iz = np.repeat(lo[:, 2], n_cells) + k // (sx * sy)
    key = (ix * 73856093) ^ (iy * 19349663) ^ (iz * 83492791)   # hashed cell id (collisions: more pairs)
    order = np.lexsort((face, key))
    key, face = key[order], face[order]
    starts = np.flatnonzero(np.r_[True, key[1:] != key[:-1]])
    counts = np.diff(np.r_[starts, len(key)])
    firsts, seconds = pairs_within_groups(face, starts, counts)
    if not firsts:
        return np.zeros((0, 2), dtype=np.int64)
    a, b = np.concatenate(firsts), np.concatenate(seconds)
    pairs = np.unique(np.stack([np.minimum(a, b), np.maximum(a, b)], axis=1), axis=0)
    return pairs[pairs[:, 0] != pairs[:, 1]]


def winding_numbers(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Generalized winding number of the closed triangle set ``tri`` (T, 3, 3) at ``points`` (P, 3).

    Sum of signed solid angles / 4 pi (Van Oosterom & Strackee 1983,
    ``tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)``):
    +-1 inside a closed surface, 0 outside.  Compiled with numba when available (one pass,
    no temporaries); :func:`winding_numbers_numpy` otherwise (tests compare the two).
    """
    from .mesh_arrays import topology_kernels

    kernels = topology_kernels()
    if kernels is not None:
        return kernels.winding_numbers(np.ascontiguousarray(points, dtype=np.float64),
                                       np.ascontiguousarray(tri, dtype=np.float64))
    return winding_numbers_numpy(points, tri)


def winding_numbers_numpy(points: np.ndarray, tri: np.ndarray, chunk: int = 250_000) -> np.ndarray:
    """NumPy version of :func:`winding_numbers` (chunks of ``chunk`` point-triangle pairs)."""
    out = np.empty(len(points))
    step = max(1, chunk // max(len(tri), 1))
    for s in range(0, len(points), step):
        p = points[s:s + step, None, None, :]
        r = tri[None, :, :, :] - p                        # (p, T, 3, 3)
        a, b, c = r[..., 0, :], r[..., 1, :], r[..., 2, :]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        num = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        den = (la * lb * lc + np.einsum("ptk,ptk->pt", a, b) * lc + np.einsum("ptk,ptk->pt", a, c) * lb
               + np.einsum("ptk,ptk->pt", b, c) * la)
        out[s:s + step] = (2.0 * np.arctan2(num, den)).sum(axis=1) / (4.0 * np.pi)
    return out


#: surface points of one component tested against another (evenly sampled beyond this)
MAX_SAMPLE_POINTS = 256
#: faces in the common box of two components beyond which the face-crossing test (the
#: fallback for slivers the sampled points miss) is not run
MAX_CROSSING_FACES = 20_000
#: points x faces of one winding-number evaluation (fewer points for large components)
MAX_WINDING_WORK = 1_000_000
#: barycentric weights of the sample points of a face: centroid, then near each corner
_SAMPLE_WEIGHTS = np.array([[1 / 3, 1 / 3, 1 / 3], [0.8, 0.1, 0.1], [0.1, 0.8, 0.1], [0.1, 0.1, 0.8]])


def _runs_inside_and_outside(tri_a, tri_b, lo_a, hi_a):
    """A point of B's surface strictly inside A while B also runs strictly outside A, or None."""
    # sample points of B's surface: each face's centroid and a point near each of its corners
    # (a centroid alone misses a corner of B poking into A)
    cen = (_SAMPLE_WEIGHTS @ tri_b).reshape(-1, 3)
    in_box = np.all((cen > lo_a) & (cen < hi_a), axis=1)
    if not in_box.any():
        return None
    idx = np.flatnonzero(in_box)
    n_max = max(16, min(MAX_SAMPLE_POINTS, MAX_WINDING_WORK // max(len(tri_a), 1)))
    if len(idx) > n_max:
        idx = idx[np.linspace(0, len(idx) - 1, n_max).astype(np.int64)]
    w = np.abs(winding_numbers(cen[idx], tri_a))
    inside = w > 0.75
    if not inside.any():
        return None
    outside = (~in_box).any() or bool((w < 0.25).any())
    return cen[idx[np.argmax(inside)]] if outside else None


def overlapping_components(vertices, faces, labels, comp_lo, comp_hi):
    """Pairs of closed components whose volumes overlap: ``[(a, b, point), ...]``.

    ``faces`` (F, 3) and ``labels`` (F,) their components; ``comp_lo``/``comp_hi`` (K, 3) the
    components' bounding boxes; ``point`` is a point of one surface inside the other.
    """
    K = len(comp_lo)
    found = []
    if K < 2:
        return found
    order = np.argsort(labels, kind="stable")
    starts = np.searchsorted(labels[order], np.arange(K + 1))

    def tri(k):
        return vertices[faces[order[starts[k]:starts[k + 1]]]]

    for a, b in _box_pairs(comp_lo, comp_hi):
        tri_a, tri_b = tri(a), tri(b)
        point = _runs_inside_and_outside(tri_a, tri_b, comp_lo[a], comp_hi[a])
        if point is None:
            point = _runs_inside_and_outside(tri_b, tri_a, comp_lo[b], comp_hi[b])
        if point is None:
            point = _first_crossing(tri_a, tri_b, np.maximum(comp_lo[a], comp_lo[b]),
                                    np.minimum(comp_hi[a], comp_hi[b]))
        if point is not None:
            found.append((int(a), int(b), point))
    return found


def _box_pairs(lo, hi):
    """Pairs (a < b) of boxes that overlap with positive volume (sort and sweep along x)."""
    order = np.argsort(lo[:, 0], kind="stable")
    lo_x = lo[order, 0]
    for i, a in enumerate(order):
        end = np.searchsorted(lo_x, hi[a, 0], side="left")
        cand = order[i + 1:end]
        if len(cand) == 0:
            continue
        ok = np.all((lo[cand] < hi[a]) & (hi[cand] > lo[a]), axis=1)
        for b in cand[ok]:
            yield (int(a), int(b)) if a < b else (int(b), int(a))


def _first_crossing(tri_a, tri_b, lo, hi):
    """A point where a face of A crosses a face of B (faces inside the common box ``lo..hi``), or None."""
    sel = []
    for t in (tri_a, tri_b):
        sel.append(t[np.all((t.min(axis=1) <= hi) & (t.max(axis=1) >= lo), axis=1)])
    A, B = sel
    if len(A) == 0 or len(B) == 0 or len(A) + len(B) > MAX_CROSSING_FACES:
        return None
    both = np.concatenate([A, B])
    verts = both.reshape(-1, 3)
    faces = np.arange(len(verts)).reshape(-1, 3)
    cell = 2.0 * float(np.mean(np.linalg.norm(both[:, [1, 2, 0]] - both, axis=2)))
    if not cell > 0:
        return None
    pairs = candidate_pairs(verts, faces, cell)
    pairs = pairs[(pairs[:, 0] < len(A)) & (pairs[:, 1] >= len(A))]
    for s in range(0, len(pairs), _CHUNK):
        p = pairs[s:s + _CHUNK]
        hit = crossing(both[p[:, 0]], both[p[:, 1]])
        if hit.any():
            return both[p[np.argmax(hit), 0]].mean(axis=0)
    return None
