"""Welding, near merging, compaction and components (the compiled topology kernels).

Truth, written here independently of the kernels: brute-force O(n^2) grouping of rows,
``np.unique`` over rows, scipy's k-d tree pairs and ``csgraph.connected_components``, and the
merge rule of :func:`inertia.geometry.mesh_io._merge_close_vertices` stated in NumPy.  Every
kernel must give exactly the groups of the truth, each standing for its lowest index, on the
test meshes (made and real) and on inputs built to hit each branch (signed zeros, NaN rows,
table growth, chains of near pairs, cell boundaries, float32 neighbours).
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest
from inertia._ext import topology as k

import inertia
from inertia.errors import InputError
from inertia.geometry import mesh_io
from inertia.geometry.mesh_arrays import compact_vertices, connected_components, weld_map, weld_vertices

RAW_MESHES = ["featuretype.stl", "idler_riser_binary_solid_header.stl", "spot.obj", "wingnut.obj", "ballA.off",
              "soup.stl"]


def _raw(meshes, name):
    """The file's arrays as trimesh reads them, before any welding."""
    trimesh = pytest.importorskip("trimesh")
    loaded = trimesh.load(str(meshes.path(name)), process=False)
    return mesh_io._scene_triangles(trimesh, loaded, name)


def _soup(v, f):
    """Every corner its own vertex."""
    return np.ascontiguousarray(v[f].reshape(-1, 3)), np.arange(3 * len(f)).reshape(-1, 3)


# ------------------------------------------------------------------------- truth
def _brute_weld_map(v):
    """For each row, the lowest index of an equal row (== per coordinate, so -0.0 == 0.0);
    a row with a NaN or infinity stands alone.  O(n^2)."""
    rep = np.arange(len(v))
    finite = np.isfinite(v).all(axis=1)
    for i in range(len(v)):
        if finite[i]:
            rep[i] = int(np.argmax(np.all(v[: i + 1] == v[i], axis=1) & finite[: i + 1]))
    return rep


def _unique_weld_map(v):
    """The same map for finite rows, by a sort (np.unique over rows gives each first index)."""
    _, first, inverse = np.unique(v + 0.0, axis=0, return_index=True, return_inverse=True)
    return first[inverse.ravel()]


def _truth_compact(v, f):
    """Unreferenced vertices dropped, the rest renumbered in their order."""
    used, inverse = np.unique(f, return_inverse=True)
    return v[used], inverse.reshape(f.shape)


def _kd_groups(v, tol):
    """rep[i]: lowest index of i's group of vertices joined by pairs at distance <= tol (scipy)."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components as scipy_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(v).query_pairs(tol, output_type="ndarray")
    n = len(v)
    _, label = scipy_components(coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n)),
                                directed=False)
    lowest = np.full(label.max() + 1, n)
    np.minimum.at(lowest, label, np.arange(n))
    return lowest[label]


def _truth_merge(v, f, rtol):
    """The merge rule in NumPy: weld (np.unique), then join vertices within tol = max(rtol x
    diagonal, 64 ulps of the largest |coordinate|), tol at most a quarter of the 1st percentile
    of the positive edge lengths when it exceeds a quarter of the shortest; lowest index wins.
    ``rtol`` 0: the weld alone."""
    v, f = _truth_compact(v, _unique_weld_map(v)[f])
    if not rtol > 0:
        return v, f
    extent = v.max(axis=0) - v.min(axis=0)
    tol = max(rtol * float(np.linalg.norm(extent)), 64 * np.finfo(float).eps * float(np.abs(v).max()))
    if len(v) < 2 or not tol > 0:
        return v, f
    e = np.linalg.norm(v[f] - v[np.roll(f, -1, axis=1)], axis=2).ravel()
    e = np.sort(e[e > 0])
    if tol > 0.25 * e[0]:
        tol = min(tol, 0.25 * e[(len(e) - 1) // 100])
    return _truth_compact(v, _kd_groups(v, tol)[f])


def _same(got, expect):
    assert np.array_equal(got[1], expect[1])
    assert np.array_equal(got[0], expect[0], equal_nan=True)
    assert np.array_equal(np.signbit(got[0]), np.signbit(expect[0]))


# ------------------------------------------------------------------------- exact weld
def test_weld_map_joins_equal_rows_with_signed_zeros_and_leaves_nan_rows_alone():
    v = np.array([[0.0, 1, 2], [-0.0, 1, 2], [np.nan, 0, 0], [np.nan, 0, 0], [0.0, 1, 2], [3, 4, 5],
                  [np.inf, 1, 1], [3, 4, 5], [0, -0.0, 2 + 4.5e-16], [0, 0, 2], [0, 0.0, 2], [np.inf, 1, 1]])
    assert weld_map(v).tolist() == [0, 0, 2, 3, 0, 5, 6, 5, 8, 9, 9, 11]
    assert np.array_equal(weld_map(v), _brute_weld_map(v))


def test_weld_map_equals_brute_force_with_many_groups_and_table_growth():
    rng = np.random.default_rng(7)
    pool = rng.normal(size=(2500, 3))
    pool[rng.random((2500, 3)) < 0.05] = 0.0
    v = pool[rng.integers(0, len(pool), size=3000)]                  # most rows distinct: the table doubles
    v[rng.random((3000, 3)) < 0.02] *= -1.0                          # some zeros become -0.0
    assert np.array_equal(weld_map(v), _brute_weld_map(v))
    grid = np.array(np.meshgrid(*[np.arange(14.0)] * 3)).reshape(3, -1).T   # equal low bits: the hash must spread
    grid = np.concatenate([grid, grid[::-1]])
    assert np.array_equal(weld_map(grid), _brute_weld_map(grid))
    assert weld_map(np.zeros((0, 3))).shape == (0,)


def test_weld_vertices_equals_a_sort_on_the_test_meshes(meshes):
    for name in RAW_MESHES:
        v, f = _raw(meshes, name)
        for vv, ff in ((v, f), _soup(v, f)):
            assert np.array_equal(weld_map(vv), _unique_weld_map(vv)), name
            _same(weld_vertices(vv, ff), _truth_compact(vv, _unique_weld_map(vv)[ff]))


def test_weld_keeps_the_lowest_index_coordinates_and_drops_unreferenced():
    v = np.array([[9.0, 9, 9], [0, 0, 0], [1, 0, 0], [0, 1, 0], [-0.0, 0, 0], [0, 0, 1]])
    f = np.array([[4, 2, 3], [4, 3, 5], [4, 5, 2], [2, 5, 3]])
    wv, wf = weld_vertices(v, f)
    assert wv.tolist() == [[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]] and not np.signbit(wv[0, 0])
    assert wf.tolist() == [[0, 1, 2], [0, 2, 3], [0, 3, 1], [1, 3, 2]]
    cv, cf = compact_vertices(v, f)
    _same((cv, cf), _truth_compact(v, f))


def test_weld_refuses_indices_outside_the_vertices():
    v = np.zeros((4, 3))
    with pytest.raises(InputError, match=r"faces\[1, 2\] = 4 names no vertex \(there are 4\)"):
        k.weld_compact(v, np.array([[0, 1, 2], [1, 2, 4]]))
    with pytest.raises(InputError, match=r"faces\[0, 0\] = -1"):
        compact_vertices(v, np.array([[-1, 1, 2]]))
    with pytest.raises(InputError, match="bad|outside"):
        weld_vertices(v, np.array([[0, 1, 7]]))


# ------------------------------------------------------------------------- near merge
def test_near_merge_groups_match_the_kd_tree():
    rng = np.random.default_rng(3)
    tol = 1e-3
    base = rng.uniform(-1, 1, size=(3000, 3))
    # chains: points 0.9 tol apart along a line join transitively, across several cells
    chain = np.array([0.5, 0.5, 0.5]) + np.outer(np.arange(40) * 0.9 * tol, [1, 0, 0])
    # pairs straddling the grid's cell boundaries (256 tol wide) just under and just over tol apart
    edge = 256 * tol * 7
    straddle = np.array([[edge - 0.4 * tol, 0.1, 0.1], [edge + 0.5 * tol, 0.1, 0.1],
                         [edge - 0.6 * tol, -0.3, 0.2], [edge + 0.45 * tol, -0.3, 0.2 + 0.2 * tol],
                         [-edge - 0.5 * tol, 0.7, -0.7], [-edge + 0.6 * tol, 0.7, -0.7]])
    jitter = base[:500] + rng.normal(scale=0.3 * tol, size=(500, 3))
    v = np.concatenate([base, chain, straddle, jitter])[rng.permutation(3546)]
    for t in (tol, 3 * tol, 0.1):
        rep = k.near_merge_map(v, t)
        assert np.array_equal(rep, _kd_groups(v, t)), t
    assert len(np.unique(k.near_merge_map(v, tol))) < len(v) - 500    # the cases above did merge


def test_merge_close_vertices_equals_the_rule_on_the_test_meshes(meshes):
    # featuretype and idler_riser need the near merge (split copies 1e-16 apart)
    for name in RAW_MESHES:
        v, f = _raw(meshes, name)
        for rtol in (mesh_io.MERGE_RTOL, 1e-3):
            got = mesh_io._merge_close_vertices(v, f, rtol)
            _same(got, _truth_merge(v, f, rtol))
        if name in ("featuretype.stl", "idler_riser_binary_solid_header.stl"):
            assert len(got[0]) < len(weld_vertices(v, f)[0]), name      # the near merge did something here


def test_merge_far_below_the_coordinates_runs_on_the_tree_and_extremes_keep_their_vertices():
    # the grid cannot number cells of 256 tol at 1e300 / 1e-290: it declines
    assert k.near_merge_map(np.array([[0.0, 0, 0], [1e300, 0, 0]]), 1e-290).shape == (0,)
    # a tetrahedron whose short edges (1e-300) cap the tolerance: no vertex merges
    v = np.array([[0.0, 0, 0], [1e300, 0, 0], [0, 1, 0], [0, 0, 1e-300]])
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    assert len(mesh_io._merge_close_vertices(v, f, 1e-310)[0]) == 4
    # small features at the origin of a mesh reaching 1e30 (a grid 1e-7 apart): tol, a quarter of
    # the short edges, is 1e-38 of the coordinates, beyond the grid; the k-d tree merges the copy
    small = np.stack(np.meshgrid(*[np.arange(7) * 1e-7] * 3), axis=-1).reshape(-1, 3)
    n = len(small)
    v = np.concatenate([small, [[1e30, 0, 0], [0, 1e30, 0]], small[:1] + 1e-12])
    f = np.concatenate([np.stack([np.arange(n - 2), np.arange(1, n - 1), np.arange(2, n)], axis=1),
                        [[n, n + 1, 0], [n + 2, 1, 2]]])
    assert k.weld_and_merge(v, f, 1e-10)[2] > 0                     # the grid declined: the tolerance is handed back
    got = mesh_io._merge_close_vertices(v, f, 1e-10)
    assert len(got[0]) == n + 2
    _same(got, _truth_merge(v, f, 1e-10))


# ------------------------------------------------------------------------- binary STL from its bytes
def _write_stl(path, corners):
    rec = np.zeros(len(corners), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = corners
    path.write_bytes(b"x".ljust(80) + len(corners).to_bytes(4, "little") + rec.tobytes())


def _stl_soup(path):
    """The corners of a binary STL as float64 (3 n, 3), faces arange."""
    n = int.from_bytes(path.read_bytes()[80:84], "little")
    corners = np.fromfile(path, dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")], count=n, offset=84)
    return corners["v"].astype(np.float64).reshape(-1, 3), np.arange(3 * n).reshape(n, 3)


def _box_corners(rng):
    """A unit cube as a triangle soup (3 corners a face), faces shuffled."""
    c = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return c[f[rng.permutation(len(f))]]


def test_binary_stl_is_welded_and_merged_as_its_corners_are(meshes, tmp_path):
    """load_mesh of a binary STL gives the arrays of the merge rule applied to its float32
    corners read as float64, signed zeros welded, NaN and infinite corners alone."""
    cases = {name: meshes.path(name) for name in ("featuretype.stl", "idler_riser_binary_solid_header.stl", "soup.stl")}
    rng = np.random.default_rng(5)
    corners = _box_corners(rng).astype("<f4")
    corners[0, 0] = [-0.0, 0.0, -0.0]                    # signed zeros weld with 0
    bad = corners.copy()
    corners[5] += rng.normal(scale=1e-12, size=(3, 3)).astype("<f4")
    _write_stl(tmp_path / "hand.stl", corners)
    cases["hand"] = tmp_path / "hand.stl"
    bad[3, 1, 2] = np.nan                                # a NaN corner stays alone
    bad[4, 2, 0] = np.inf
    _write_stl(tmp_path / "nan.stl", bad)
    for name, path in cases.items():
        for rtol in (mesh_io.MERGE_RTOL, 0.0, 1e-3):
            got = inertia.load_mesh(path, merge_rtol=rtol)
            soup = _stl_soup(path)
            _same(got, _truth_merge(*soup, rtol))
            _same(got, mesh_io._merge_close_vertices(*soup, rtol))
    v, f = _stl_soup(tmp_path / "nan.stl")
    data = np.frombuffer((tmp_path / "nan.stl").read_bytes(), np.uint8)
    got = k.stl_weld_and_merge(data, 12, 1e-10)
    assert got[2] == 0.0
    _same(got[:2], _truth_compact(v, _brute_weld_map(v)[f]))             # NaN rows: no merge at all
    assert len(got[0]) == 8 + 2


def test_stl_weld_merges_a_split_vertex_near_zero(tmp_path):
    """A binary STL whose vertex on the plane x = 0 is split into copies one float32 step apart
    (x = +-1e-30): merged, as the rule merges the float64 soup."""
    corners = (_box_corners(np.random.default_rng(2)) - 0.5).astype("<f4")   # centred: coordinates +-0.5
    hit = np.argwhere(np.all(corners == np.float32(-0.5), axis=2))
    corners[hit[0][0], hit[0][1], 0] = np.float32(1e-30)          # the corner (-0.5, -0.5, -0.5) moved onto x ~ 0
    for t, c in hit[1:]:
        corners[t, c, 0] = np.float32(-1e-30)                      # its other copies: a step apart
    _write_stl(tmp_path / "split.stl", corners)
    got = inertia.load_mesh(tmp_path / "split.stl")
    _same(got, _truth_merge(*_stl_soup(tmp_path / "split.stl"), mesh_io.MERGE_RTOL))
    assert len(got[0]) == 8


def test_stl_kernel_refuses_a_buffer_shorter_than_its_records():
    with pytest.raises(InputError, match="cannot hold 3 triangles"):
        k.stl_weld_and_merge(np.zeros(84 + 50 * 3 - 1, np.uint8), 3, 1e-10)


def _near_pair_exists(v, tol):
    """Brute force: two rows within ``tol`` in every coordinate."""
    return any(np.any(np.all(np.abs(v[i + 1:] - v[i]) <= tol, axis=1)) for i in range(len(v) - 1))


def test_float32_apart_never_misses_a_near_pair():
    """The one-pass proof that float32 rows hold no near pair (the binary STL's shortcut past
    the merge grid) says True only when brute force finds none, and says it for ordinary point
    sets (else it saves nothing)."""
    rng = np.random.default_rng(11)
    proved = 0
    for trial in range(60):
        n = 400
        scale = 10.0 ** rng.uniform(-6, 6)
        v = rng.uniform(-1, 1, size=(n, 3)) * scale
        v[rng.random((n, 3)) < 0.1] *= 10.0 ** rng.uniform(-12, -3)     # coordinates near 0 ...
        v[rng.random((n, 3)) < 0.02] = 0.0                             # ... and on 0
        v = v.astype(np.float32)
        tol = float(scale) * 10.0 ** rng.choice([-10, -7, -5, -3])
        kind = trial % 4
        if kind == 1:        # a copy one float32 step away in one coordinate
            i, j, c = rng.integers(n), rng.integers(n), rng.integers(3)
            v[j] = v[i]
            v[j, c] = np.nextafter(v[i, c], np.float32(np.inf))
        elif kind == 2:      # mirror images across a plane near 0 (same large coordinates)
            i, j = rng.integers(n), rng.integers(n)
            v[j] = v[i]
            v[i, 0] = np.float32(0.3 * tol)
            v[j, 0] = np.float32(-0.3 * tol)
        elif kind == 3:      # a copy within tol in every coordinate
            i, j = rng.integers(n), rng.integers(n)
            v[j] = (v[i].astype(np.float64) + rng.uniform(-0.4, 0.4, 3) * tol).astype(np.float32)
        v64 = np.unique(v.astype(np.float64), axis=0)                  # distinct rows, as the weld leaves them
        if k.float32_apart(np.ascontiguousarray(v64), tol, float(np.abs(v64).max())):
            assert not _near_pair_exists(v64, tol), (trial, tol)
            proved += 1
        elif kind in (1, 3):
            assert _near_pair_exists(v64, tol) or tol < 1e-7 * scale   # (a step can exceed a tiny tol)
    assert proved >= 6                  # most plain sets (a quarter of the trials) and some others
    # an ordinary mesh: a torus of 5,000 faces centred on 0, as its STL's float32 holds it
    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, 100, endpoint=False), np.linspace(0, 2 * np.pi, 25, endpoint=False))
    torus = np.stack([(1 + 0.3 * np.cos(w)) * np.cos(u), (1 + 0.3 * np.cos(w)) * np.sin(u), 0.3 * np.sin(w)], -1)
    torus = np.ascontiguousarray(torus.reshape(-1, 3).astype(np.float32).astype(np.float64))
    assert k.float32_apart(torus, 1e-10 * 2.6, 1.3)
    near = torus[:1].copy()
    near[0, 1:] += float(np.float32(1e-11))          # a float32 copy of vertex 0 = (1.3, 0, 0), 1.4e-11 away
    assert not k.float32_apart(np.concatenate([torus, near]), 1e-10 * 2.6, 1.3)
    # mirror images across x = 0 below 2^26 tol (the same key): apart by 0.02, proved apart by
    # comparing them; mirror images 0.6 tol apart are a near pair
    mirrored = np.array([[0.01, 0.5, 0.2], [-0.01, 0.5, 0.2]], dtype=np.float32).astype(np.float64)
    assert k.float32_apart(np.concatenate([torus, mirrored]), 1e-10 * 2.6, 1.3)
    mirrored[:, 0] = np.float32([0.3e-10 * 2.6, -0.3e-10 * 2.6])
    assert not k.float32_apart(np.concatenate([torus, mirrored]), 1e-10 * 2.6, 1.3)


# ------------------------------------------------------------------------- components
def test_connected_components_number_as_scipy_does():
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components as scipy_components

    rng = np.random.default_rng(9)
    for n, m in ((1, 0), (10, 0), (50, 30), (2000, 1500), (2000, 4000)):
        a, b = rng.integers(0, n, m), rng.integers(0, n, m)
        count, labels = connected_components(n, a, b)
        expect = scipy_components(coo_matrix((np.ones(m), (a, b)), shape=(n, n)), directed=False)
        assert count == expect[0] and np.array_equal(labels, expect[1]), (n, m)
    with pytest.raises(InputError, match=r"edge 0 = \(0, 5\) names a node outside 0..5-1"):
        connected_components(5, [0], [5])


# ------------------------------------------------------------------------- determinism
_DETERMINISM = """
import hashlib, sys
import numpy as np
from inertia._ext import topology as k
rng = np.random.default_rng(21)
t = np.linspace(0, 2 * np.pi, 300, endpoint=False)
ring = np.stack([np.cos(t), np.sin(t), np.zeros_like(t)], axis=1)
v = np.concatenate([ring + [0, 0, z] for z in np.linspace(0, 1, 200)])
f = np.stack([np.arange(len(v) - 301), np.arange(1, len(v) - 300), np.arange(300, len(v) - 1)], axis=1)
soup = np.ascontiguousarray(v[f].reshape(-1, 3) + rng.normal(scale=1e-15, size=(3 * len(f), 3)))
sf = np.arange(len(soup)).reshape(-1, 3)
rec = np.zeros(len(f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
rec["v"] = v[f]
data = np.frombuffer(b"x".ljust(80) + len(f).to_bytes(4, "little") + rec.tobytes(), np.uint8)
h = hashlib.sha256()
for arr in (k.weld_map(soup), *k.weld_compact(soup, sf), *k.weld_and_merge(soup, sf, 1e-10)[:2],
            *k.stl_weld_and_merge(data, len(f), 1e-10)[:2], k.near_merge_map(soup, 1e-9),
            k.connected_components(len(soup), sf[:, 0], sf[:, 1])[1]):
    h.update(np.ascontiguousarray(arr).tobytes())
sys.stdout.write(h.hexdigest())
"""


def test_same_bits_twice_in_process_and_in_a_fresh_process():
    def digest():
        out = {}
        exec(compile(_DETERMINISM.replace("sys.stdout.write(h.hexdigest())", "out['h'] = h.hexdigest()"),
                     "determinism", "exec"), {"out": out})
        return out["h"]

    first, second = digest(), digest()
    fresh = subprocess.run([sys.executable, "-c", _DETERMINISM], capture_output=True, text=True, check=True).stdout
    assert first == second == fresh
