"""The cell-by-cell height-field proof that a shell does not cross itself (the cell proof of
``inertia._ext.selfcross``): each of its conditions refuses the patch it is there to refuse, a
proved patch never holds a crossing pair, the proof leaves both faces of every crossing pair to
the search, and the search finds a crossing exactly when some pair crosses.

Truth: patches built by hand with a known defect (two stacked sheets, a strip that turns more
than once, a fan that winds twice, a turned-over face), and every crossing pair by brute force
in exact integer arithmetic (:mod:`._exact_crossings`)."""

from __future__ import annotations

import numpy as np
import pytest
from inertia._ext import selfcross as k

from ._exact_crossings import cross, crosses_rationally, crossing_pairs, integer_shell

trimesh = pytest.importorskip("trimesh")

_NO_TWINS = np.empty((0, 3), dtype=np.int64)        # find_crossing finds the edges' twins itself


def _check(v, f):
    """patch_check of the whole of ``f`` (edges without a face across point to a face outside)."""
    v = np.ascontiguousarray(v, dtype=np.float64)
    f = np.ascontiguousarray(f, dtype=np.int64)
    adj = np.full((len(f), 3), len(f), dtype=np.int64)     # a face outside the patch
    where = {}
    for t, row in enumerate(f):
        for c in range(3):
            where[(row[c], row[(c + 1) % 3])] = t
    for t, row in enumerate(f):
        for c in range(3):
            adj[t, c] = where.get((row[(c + 1) % 3], row[c]), len(f))
    return k.patch_check(v, f, adj, np.arange(len(f)))


def _grid(n=4, z=None):
    """An n x n grid of the unit square, counterclockwise seen from +z; heights ``z(x, y)``."""
    x, y = np.meshgrid(np.linspace(0, 1, n + 1), np.linspace(0, 1, n + 1), indexing="ij")
    v = np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size) if z is None else z(x.ravel(), y.ravel())])
    idx = np.arange((n + 1) ** 2).reshape(n + 1, n + 1)
    f = []
    for i in range(n):
        for j in range(n):
            a, b, c, d = idx[i, j], idx[i + 1, j], idx[i + 1, j + 1], idx[i, j + 1]
            f += [(a, b, c), (a, c, d)]
    return v, np.array(f)


def test_a_height_field_disk_is_proved_along_whichever_axis_it_faces():
    v, f = _grid(5, lambda x, y: 0.2 * np.sin(3 * x) * np.cos(2 * y))
    assert _check(v, f) == 0
    for perm, flip in (((1, 2, 0), False), ((2, 0, 1), False), ((0, 1, 2), True)):
        w = v[:, perm]
        g = f[:, ::-1] if flip else f                 # facing -z: wound the other way
        if flip:
            w = w * np.array([1, 1, -1])
        assert _check(w, g) == 0


def test_each_condition_refuses_its_patch():
    v, f = _grid(3)
    bad = v.copy()
    bad[5, :2] = (2.0, 2.0)                          # an inner vertex dragged outside: faces turn over
    assert _check(bad, f) == 1

    a, b = _grid(2)
    two = np.vstack([a, a + (0.3, 0.3, 1.0)])         # two sheets, one above the other: two loops
    assert _check(two, np.vstack([b, b + len(a)])) == 4

    # a strip around the origin turning 1.2 times, rising: each face faces +z, no face meets
    # another, but the projection covers some points twice: its border is not simple (the
    # fans around its vertices are not tested: the border shows every fold)
    m = 40
    th = np.linspace(0.0, 2.4 * np.pi, m + 1)
    inner = np.column_stack([np.cos(th), np.sin(th), 0.05 * th])
    outer = np.column_stack([2 * np.cos(th), 2 * np.sin(th), 0.05 * th])
    v = np.vstack([inner, outer])
    f = [(j, m + 1 + j, m + 2 + j) for j in range(m)] + [(j, m + 2 + j, j + 1) for j in range(m)]
    assert _check(v, np.array(f)) == 5

    # a fan around a vertex that winds twice (a rising helix of corners): its border, the
    # helix, winds twice around the vertex, so two of its edges cross
    k = 12
    ang = np.arange(k) * 4 * np.pi / k
    ring = np.column_stack([np.cos(ang), np.sin(ang), 0.1 * np.arange(k)])
    v = np.vstack([[0.0, 0.0, 0.5], ring])
    f = np.array([(0, 1 + i, 1 + (i + 1) % k) for i in range(k)])
    assert _check(v, f) == 5

    # a wedge on the border turning by more than a full turn: its border runs over itself
    k = 10
    ang = np.linspace(0.0, 2 * np.pi + 0.8, k + 1)
    ring = np.column_stack([np.cos(ang), np.sin(ang), 0.1 * np.arange(k + 1)])
    v = np.vstack([[0.0, 0.0, 0.0], ring])
    f = np.array([(0, 1 + i, 2 + i) for i in range(k)])
    assert _check(v, f) == 5


def _cells(v, f, cell_edges):
    """The patches of the proof's grid: per cell, the faces whose boxes meet it."""
    tri = v[f]
    longest = np.sqrt(np.max([((tri[:, (c + 1) % 3] - tri[:, c]) ** 2).sum(1) for c in range(3)], axis=0))
    h = cell_edges * np.median(longest)
    o = v.min(0)
    lo = np.floor((tri.min(1) - o) / h - 1e-9).astype(int)
    hi = np.floor((tri.max(1) - o) / h + 1e-9).astype(int)
    cells = {}
    for t in range(len(f)):
        for x in range(lo[t, 0], hi[t, 0] + 1):
            for y in range(lo[t, 1], hi[t, 1] + 1):
                for z in range(lo[t, 2], hi[t, 2] + 1):
                    cells.setdefault((x, y, z), []).append(t)
    return [np.array(c, dtype=np.int64) for c in cells.values()]


def test_a_proved_patch_never_holds_a_crossing_pair():
    """On tangled shells, every pair of faces of every patch the proof accepts is tested with the
    exact brute force: none crosses (while the rejected patches hold many)."""
    rng = np.random.default_rng(5)
    proved = crossing_in_rejected = 0
    for it in range(16):
        v, f = integer_shell(rng, it)
        adj = k.face_twins(f, len(v))
        assert adj is not None
        for faces in _cells(v, f, rng.choice([2.0, 4.0, 8.0])):
            i, j = np.triu_indices(len(faces), 1)
            i, j = faces[i], faces[j]
            apart = (f[i, :, None] == f[j, None, :]).sum(axis=(1, 2)) < 2
            crossing = bool(cross(v, f, i[apart], j[apart]).any())
            if k.patch_check(v, f, adj, faces) == 0:
                proved += 1
                assert not crossing, it
            else:
                crossing_in_rejected += crossing
    assert proved > 100 and crossing_in_rejected > 20     # both kinds were met


def test_the_search_with_and_without_the_proof_finds_what_brute_force_finds():
    """find_crossing (cells proved, the rest searched) and the search of every pair find a
    crossing exactly when some pair crosses, on shells from smooth to badly tangled, and name a
    pair that crosses."""
    rng = np.random.default_rng(17)
    found_any = 0
    for it in range(80):
        v, f = integer_shell(rng, it, min_faces=k.HEIGHTFIELD_MIN_FACES)   # the proof runs from this size
        truth = crossing_pairs(v, f)
        for prove in (True, False):
            got = k.find_crossing(v, f, _NO_TWINS, prove)
            assert (got is not None) == bool(truth), (it, prove)
            assert got is None or got in truth
        found_any += bool(truth)
    assert 15 < found_any < 75


def test_the_proof_leaves_both_faces_of_every_crossing_pair_to_the_search():
    """unproved_faces keeps both faces of each pair that crosses (the search sees only the kept
    faces), on tangled shells with cells of 2 to 8 edges: proved cells, cut ones, and parts."""
    rng = np.random.default_rng(23)
    pairs_seen = proved_some = 0
    for it in range(40):
        v, f = integer_shell(rng, it, min_faces=400)
        adj = k.face_twins(f, len(v))
        assert adj is not None
        edge = np.median(np.linalg.norm(v[f] - v[np.roll(f, 1, axis=1)], axis=2).max(axis=1))
        keep = k.unproved_faces(v, f, adj, rng.choice([2.0, 4.0, 8.0]) * edge)
        proved_some += int(keep.sum()) < len(f)
        for a, b in crossing_pairs(v, f):
            pairs_seen += 1
            assert keep[a] and keep[b], (it, a, b)
    assert pairs_seen > 100 and proved_some > 10


def test_a_wall_pushed_through_a_torus_is_found():
    """A rippled torus proved embedded; one ring of its tube pushed through the opposite wall is
    found, whichever cells the crossing lies in."""
    m = trimesh.creation.torus(1.0, 0.3, major_sections=120, minor_sections=24)
    v = np.array(m.vertices, float)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    assert k.find_crossing(v, f, _NO_TWINS) is None
    edge = np.median(np.linalg.norm(v[f] - v[np.roll(f, 1, axis=1)], axis=2).max(axis=1))
    assert k.unproved_faces(v, f, k.face_twins(f, len(v)), k.CELL_EDGES * edge).sum() < len(f) // 10
    ring = np.hypot(v[:, 0], v[:, 1])
    for angle in np.linspace(0, 2 * np.pi, 7)[:-1]:
        w = v.copy()
        near = np.abs(np.angle(np.exp(1j * (np.arctan2(v[:, 1], v[:, 0]) - angle)))) < 0.03
        outer = near & (ring > 1.0)
        w[outer, :2] *= (0.55 / ring[outer])[:, None]           # the outer wall through the inner one
        got = k.find_crossing(np.ascontiguousarray(w), f, _NO_TWINS)
        assert got is not None, angle
        assert crosses_rationally(w[f[got[0]]], w[f[got[1]]])


def test_a_shell_among_many_vertices_is_searched_on_its_own():
    """One component of a large mesh (its faces use 1 % of the vertex array) gives the same
    answer and the same pair as the shell alone."""
    m = trimesh.creation.torus(1.0, 0.3, major_sections=60, minor_sections=12)
    v = np.array(m.vertices)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    others = np.random.default_rng(0).random((100_000, 3)) + 5.0
    for w in (v, v * np.where(np.arange(len(v)) == 0, 0.2, 1.0)[:, None]):   # embedded, then a vertex through
        got = k.find_crossing(np.ascontiguousarray(np.vstack([others, w])), f + len(others), _NO_TWINS)
        assert got == k.find_crossing(np.ascontiguousarray(w), f, _NO_TWINS)
    assert got is not None
