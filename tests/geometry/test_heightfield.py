"""The cell-by-cell height-field proof that a shell does not cross itself
(:mod:`inertia.geometry._heightfield_numba`): each of its conditions refuses the patch it is
there to refuse, a proved patch never holds a crossing pair (every pair tested by the exact
edge-through-face test), and the search that uses the proof finds a crossing exactly when the
whole face-pair search does.

Truth: patches built by hand with a known defect (two stacked sheets, a strip that turns more
than once, a fan that winds twice, a turned-over face), and the face-pair search itself."""

from __future__ import annotations

import numpy as np
import pytest

pytest.importorskip("numba")
trimesh = pytest.importorskip("trimesh")

from inertia.geometry import _heightfield_numba as hf  # noqa: E402
from inertia.geometry import _selfcross_numba as sc  # noqa: E402
from inertia.geometry.intersections import CROSS_RTOL  # noqa: E402

_NO_TWINS = np.empty((0, 3), dtype=np.int64)        # find_crossing finds the edges' twins itself


def _check(v, f, adj=None):
    """patch_check of the whole of ``f`` (edges without a face across point to a face outside)."""
    v = np.ascontiguousarray(v, dtype=np.float64)
    f = np.ascontiguousarray(f, dtype=np.int64)
    if adj is None:
        adj = np.full((len(f), 3), len(f), dtype=np.int64)     # a face outside the patch
        where = {}
        for t, row in enumerate(f):
            for k in range(3):
                where[(row[k], row[(k + 1) % 3])] = t
        for t, row in enumerate(f):
            for k in range(3):
                adj[t, k] = where.get((row[(k + 1) % 3], row[k]), len(f))
    n = len(f)
    return hf.patch_check(v, f, hf.orientation_bits(v, f), adj, np.arange(n), n, 0, np.full(n + 1, -1),
                          np.full((len(v), 3), -1), np.empty(6 * n, dtype=np.int64), np.empty(9 * n))


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
    longest = np.sqrt(np.max([((tri[:, (k + 1) % 3] - tri[:, k]) ** 2).sum(1) for k in range(3)], axis=0))
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


def _jittered(rng, it):
    """A closed shell (torus or sphere), its vertices moved at random by up to about an edge."""
    if it % 3:
        m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=int(rng.integers(12, 40)),
                                   minor_sections=int(rng.integers(8, 20)))
    else:
        m = trimesh.creation.icosphere(int(rng.integers(2, 4)))
    v = np.array(m.vertices, float)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    edge = np.median(np.linalg.norm(v[f[:, 0]] - v[f[:, 1]], axis=1))
    v = v + rng.normal(0, rng.choice([0.0, 0.1, 0.3, 0.6, 1.2]) * edge, v.shape)
    return np.ascontiguousarray(v), f


def test_a_proved_patch_never_holds_a_crossing_pair():
    """On jittered shells, every pair of faces of every patch the proof accepts is tested with
    the exact edge-through-face test: none crosses (while the rejected patches hold many)."""
    rng = np.random.default_rng(5)
    proved = crossing_in_rejected = 0
    for it in range(30):
        v, f = _jittered(rng, it)
        N, diag = sc.face_frames(v, f)
        adj, closed = hf.face_twins(f, len(v))
        assert closed
        fstamp, vwork = np.full(len(f), -1), np.full((len(v), 3), -1)
        omask = hf.orientation_bits(v, f)
        for mark, faces in enumerate(_cells(v, f, rng.choice([2.0, 4.0, 8.0]))):
            n = len(faces)
            code = hf.patch_check(v, f, omask, adj, faces, n, mark, fstamp, vwork,
                                  np.empty(6 * n, dtype=np.int64), np.empty(9 * n))
            crossing = any(sc.faces_cross(v, f, N, diag, faces[i], faces[j], CROSS_RTOL)
                           for i in range(n) for j in range(i + 1, n)
                           if len(set(f[faces[i]]) & set(f[faces[j]])) < 2)
            if code == 0:
                proved += 1
                assert not crossing, (it, mark)
            else:
                crossing_in_rejected += crossing
    assert proved > 100 and crossing_in_rejected > 20     # both kinds were met


def _full_search(v, f):
    """The face-pair search over every face (no cell proof)."""
    N, diag = sc.face_frames(v, f)
    longest = max(np.median(np.linalg.norm(v[f] - v[np.roll(f, 1, axis=1)], axis=2).max(axis=1)), 1e-300)
    out = np.zeros(2, dtype=np.int64)
    cell = longest
    while True:
        found = sc.first_crossing(v, f, N, diag, sc.certified_fans(v, f, N), v[f].reshape(-1, 3).min(0),
                                  cell, 64, CROSS_RTOL, out)
        if found >= 0:
            return found
        cell *= 2.0


def test_the_search_with_the_proof_agrees_with_the_whole_search():
    """find_crossing (cells proved, the rest searched) finds a crossing exactly when the search
    of every pair does, on shells from smooth to badly tangled, and names a pair that crosses."""
    rng = np.random.default_rng(17)
    found_any = 0
    for it in range(150):
        v, f = _jittered(rng, it)
        if len(f) < sc.HEIGHTFIELD_MIN_FACES:           # the proof runs from this size
            v, f = trimesh.remesh.subdivide(v, f)
            v, f = np.ascontiguousarray(v, dtype=float), np.ascontiguousarray(f, dtype=np.int64)
        out = np.zeros(2, dtype=np.int64)
        got = sc.find_crossing(v, f, _NO_TWINS, 64, CROSS_RTOL, out)
        assert got == _full_search(v, f), it
        if got:
            found_any += 1
            N, diag = sc.face_frames(v, f)
            assert sc.faces_cross(v, f, N, diag, out[0], out[1], CROSS_RTOL)
    assert 20 < found_any < 140


def _crossing_pairs(v, f):
    """Every pair of faces that cross (boxes first, then the exact test), faces sharing an edge
    left out."""
    N, diag = sc.face_frames(v, f)
    lo, hi = v[f].min(1), v[f].max(1)
    pairs = []
    for a in range(len(f)):
        near = np.nonzero(np.all((lo[a + 1:] <= hi[a]) & (hi[a + 1:] >= lo[a]), axis=1))[0] + a + 1
        for b in near:
            if len(set(f[a]) & set(f[b])) < 2 and sc.faces_cross(v, f, N, diag, a, b, CROSS_RTOL):
                pairs.append((a, b))
    return pairs


def test_the_proof_leaves_both_faces_of_every_crossing_pair_to_the_search():
    """unproved_faces keeps both faces of each pair that crosses (the search sees only the kept
    faces), on tangled shells with cells of 2 to 8 edges: proved cells, cut ones, and parts."""
    rng = np.random.default_rng(23)
    pairs_seen = proved_some = 0
    for it in range(40):
        v, f = _jittered(rng, it)
        if len(f) < 400:
            v, f = trimesh.remesh.subdivide(v, f)
            v, f = np.ascontiguousarray(v, dtype=float), np.ascontiguousarray(f, dtype=np.int64)
        adj, closed = hf.face_twins(f, len(v))
        assert closed
        origin, top, edge = hf.box_and_median_edge(v, f)
        keep = np.zeros(len(f), dtype=bool)
        n_keep = hf.unproved_faces(v, f, adj, origin, top, rng.choice([2.0, 4.0, 8.0]) * edge, keep)
        assert n_keep == keep.sum()
        proved_some += n_keep < len(f)
        for a, b in _crossing_pairs(v, f):
            pairs_seen += 1
            assert keep[a] and keep[b], (it, a, b)
    assert pairs_seen > 100 and proved_some > 20


def test_a_wall_pushed_through_a_torus_is_found():
    """A rippled torus proved embedded; one ring of its tube pushed through the opposite wall is
    found, whichever cells the crossing lies in."""
    m = trimesh.creation.torus(1.0, 0.3, major_sections=120, minor_sections=24)
    v = np.array(m.vertices, float)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    out = np.zeros(2, dtype=np.int64)
    assert sc.find_crossing(v, f, _NO_TWINS, 64, CROSS_RTOL, out) == 0
    keep = np.zeros(len(f), dtype=bool)
    origin, top, edge = hf.box_and_median_edge(v, f)
    assert hf.unproved_faces(v, f, hf.face_twins(f, len(v))[0], origin, top, hf.CELL_EDGES * edge,
                             keep) < len(f) // 10
    ring = np.hypot(v[:, 0], v[:, 1])
    for angle in np.linspace(0, 2 * np.pi, 7)[:-1]:
        w = v.copy()
        near = np.abs(np.angle(np.exp(1j * (np.arctan2(v[:, 1], v[:, 0]) - angle)))) < 0.03
        outer = near & (ring > 1.0)
        w[outer, :2] *= (0.55 / ring[outer])[:, None]           # the outer wall through the inner one
        assert sc.find_crossing(np.ascontiguousarray(w), f, _NO_TWINS, 64, CROSS_RTOL, out) == 1, angle
        assert sc.faces_cross(w, f, *sc.face_frames(w, f), out[0], out[1], CROSS_RTOL)


def test_a_shell_among_many_vertices_is_searched_on_its_own():
    """One component of a large mesh (its faces use 1 % of the vertex array) gives the same
    answer and the same pair as the shell alone."""
    m = trimesh.creation.torus(1.0, 0.3, major_sections=60, minor_sections=12)
    v = np.array(m.vertices)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    others = np.random.default_rng(0).random((100_000, 3)) + 5.0
    out, alone = np.zeros(2, dtype=np.int64), np.zeros(2, dtype=np.int64)
    for w in (v, v * np.where(np.arange(len(v)) == 0, 0.2, 1.0)[:, None]):   # embedded, then a vertex through
        got = sc.find_crossing(np.ascontiguousarray(np.vstack([others, w])), f + len(others), _NO_TWINS, 64, CROSS_RTOL, out)
        assert got == sc.find_crossing(np.ascontiguousarray(w), f, _NO_TWINS, 64, CROSS_RTOL, alone)
        assert tuple(out) == tuple(alone) if got else True
    assert got == 1
