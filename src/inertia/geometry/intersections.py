"""Overlapping closed shells: two components of a mesh whose volumes overlap.

Two closed, outward shells that overlap are summed by the divergence-theorem integrals (the
overlap counted twice).  :mod:`inertia.geometry.checks` reports them as ``overlapping_shells``
when, for two components whose bounding boxes overlap, one's surface runs both strictly
inside and strictly outside the other: the generalised winding number of one at the face
surface points of the other is near 1 for some and near 0 for others, or a face of one crosses a
face of the other (an edge strictly through the interior).  Touching parts (a shared face,
coplanar contact), nested shells (a cavity, a part inside a hollow one) and parts apart are
never flagged.

Not found here: a single closed shell that passes through itself (its own faces crossing).
That is the self-crossing check's job (:mod:`inertia.geometry.self_crossing`: a certificate,
then a face-pair search, ``self_crossing="search"`` of :func:`inertia.mesh_properties`), and
``on_defect="robust"`` (:mod:`inertia.geometry.robust`) integrates the solid such a shell
bounds.
"""

from __future__ import annotations

import numpy as np

from .._ext import selfcross as _k

#: orientation tests closer to zero than this times L^3 count as touching (L: the larger
#: bounding-box diagonal of the two triangles), i.e. distances below about 1e-9 L
CROSS_RTOL = _k.CROSS_RTOL


def crossing(T1, T2) -> np.ndarray:
    """(N,) bool: triangles T1[i] (N, 3, 3) and T2[i] cross (an edge of one strictly through
    the interior of the other, every orientation beyond :data:`CROSS_RTOL` L^3)."""
    return _k.triangles_cross(np.ascontiguousarray(T1, dtype=np.float64), np.ascontiguousarray(T2, dtype=np.float64))


def winding_numbers(points: np.ndarray, tri: np.ndarray) -> np.ndarray:
    """Generalized winding number of the triangle set ``tri`` (T, 3, 3) at ``points`` (P, 3).

    Sum of signed solid angles / 4 pi (Van Oosterom & Strackee 1983,
    ``tan(Omega/2) = a.(b x c) / (|a||b||c| + (a.b)|c| + (a.c)|b| + (b.c)|a|)``):
    +-1 inside a closed surface, 0 outside: where the corners (joined where equal) form one, the
    signed number of crossings of a ray off it.
    """
    return _k.winding_numbers(np.ascontiguousarray(points, dtype=np.float64),
                              np.ascontiguousarray(tri, dtype=np.float64))


#: surface points of one component tested against another (evenly sampled beyond this)
MAX_SAMPLE_POINTS = 256
#: faces in the common box of two components beyond which the face-crossing test (the
#: fallback for slivers the sampled points miss) is not run
MAX_CROSSING_FACES = 20_000
#: sample points tried inside a component of F faces: this / F (at least 16, at most
#: MAX_SAMPLE_POINTS)
MAX_WINDING_WORK = 1_000_000


def overlapping_components(vertices, faces, labels, comp_lo, comp_hi):
    """Pairs of closed components whose volumes overlap: ``[(a, b, point), ...]``.

    ``faces`` (F, 3) and ``labels`` (F,) their components; ``comp_lo``/``comp_hi`` (K, 3) the
    components' bounding boxes; ``point`` is a point of one surface inside the other.  For each
    pair whose boxes overlap: a point of either surface strictly inside the other (|winding
    number| > 3/4) while that surface also runs strictly outside it (sample points: each face's
    centroid and a point near each corner, those in the other's box, evenly thinned to
    :data:`MAX_SAMPLE_POINTS` or fewer for large shells); else a face of one crossing a face of
    the other (the slivers the samples miss).
    """
    K = len(comp_lo)
    if K < 2:
        return []
    vertices = np.ascontiguousarray(vertices, dtype=np.float64)
    order = np.argsort(labels, kind="stable")
    starts = np.searchsorted(labels[order], np.arange(K + 1))
    pairs = list(_box_pairs(comp_lo, comp_hi))
    partners = {}
    for a, b in pairs:
        partners.setdefault(a, []).append(b)
        partners.setdefault(b, []).append(a)
    faces_of = {k: np.ascontiguousarray(faces[order[starts[k]:starts[k + 1]]], dtype=np.int64) for k in partners}
    inside = {}                 # (x, y): a point of y inside x, or None; x's shell built once for all its partners
    for x, ys in partners.items():
        n_max = max(16, min(MAX_SAMPLE_POINTS, MAX_WINDING_WORK // max(len(faces_of[x]), 1)))
        found = _k.runs_inside(vertices, faces_of[x], comp_lo[x], comp_hi[x], [faces_of[y] for y in ys], n_max)
        inside.update(((x, y), p) for y, p in zip(ys, found))
    found = []
    for a, b in pairs:
        point = inside[a, b] if inside[a, b] is not None else inside[b, a]
        if point is None:
            pair = _k.crossing_between(vertices, faces_of[a], faces_of[b], np.maximum(comp_lo[a], comp_lo[b]),
                                       np.minimum(comp_hi[a], comp_hi[b]), MAX_CROSSING_FACES)
            point = None if pair is None else vertices[faces_of[a][pair[0]]].mean(axis=0)
        if point is not None:
            found.append((int(a), int(b), np.asarray(point)))
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
