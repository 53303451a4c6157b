"""The compiled welding and checking kernels against the NumPy code they stand in for.

Truth: the NumPy implementations (sort-based weld, k-d tree merge, full analysis), which the
rest of the suite checks against closed forms.  The compiled kernels must give the same
groups, the same arrays and the same verdicts, on the test meshes (made and real) and on meshes built
to hit each branch (signed zeros, NaN rows, chains of near pairs, cell boundaries, every
defect).
"""

from __future__ import annotations

import numpy as np
import pytest

from inertia.geometry import mesh_arrays as mesh_checks
from inertia.geometry import mesh_io
from inertia.geometry.checks import analyse_mesh
from inertia.geometry.mesh_arrays import compact_vertices, validate_inputs, weld_map_numpy

nbk = pytest.importorskip("inertia.geometry._topology_numba")

TEST_MESHES = ["ballA.off", "featuretype.stl", "idler_riser_binary_solid_header.stl", "wingnut.obj", "soup.stl",
        "teapot_open.stl", "cycloidal.ply", "tray_bottom_ascii.stl", "spot.obj"]


@pytest.fixture
def numpy_only(monkeypatch):
    """Run the library as if numba were not installed."""
    monkeypatch.setattr(mesh_checks, "_topology_state", False)


def _raw(meshes, name):
    """The file's arrays as trimesh reads them, before any welding."""
    trimesh = pytest.importorskip("trimesh")
    loaded = trimesh.load(str(meshes.path(name)), process=False)
    return mesh_io._scene_triangles(trimesh, loaded, name)


def _box_soup(rng):
    """A unit cube as a triangle soup (every corner repeated per face), shuffled faces."""
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    f = f[rng.permutation(len(f))]
    return corners[f].reshape(-1, 3), np.arange(3 * len(f)).reshape(-1, 3)


# ---------------------------------------------------------------- exact weld
def test_weld_map_matches_numpy_on_hand_built_rows():
    v = np.array([[0.0, 1, 2], [-0.0, 1, 2], [np.nan, 0, 0], [np.nan, 0, 0], [0.0, 1, 2], [3, 4, 5],
                  [np.inf, 1, 1], [3, 4, 5], [0, -0.0, 2 + 4.5e-16], [0, 0, 2], [0, 0.0, 2]])
    rep = nbk.weld_map(v)
    assert rep.tolist() == [0, 0, 2, 3, 0, 5, 6, 5, 8, 9, 9]  # -0.0 == 0.0; NaN/inf rows stay alone
    assert np.array_equal(rep, weld_map_numpy(v))


def test_weld_map_matches_numpy_with_many_groups_and_table_growth():
    rng = np.random.default_rng(7)
    pool = rng.normal(size=(5000, 3))
    v = pool[rng.integers(0, len(pool), size=40000)]   # ~5000 groups: the table doubles several times
    assert np.array_equal(nbk.weld_map(v), weld_map_numpy(v))
    grid = np.array(np.meshgrid(*[np.arange(30.0)] * 3)).reshape(3, -1).T   # equal low bits: hash spread
    grid = np.concatenate([grid, grid[::-1]])
    assert np.array_equal(nbk.weld_map(grid), weld_map_numpy(grid))


def test_weld_vertices_is_the_same_with_and_without_numba(meshes, monkeypatch):
    for name in ("featuretype.stl", "spot.obj", "wingnut.obj"):
        v, f = _raw(meshes, name)
        fast = mesh_checks.weld_vertices(v, f)
        monkeypatch.setattr(mesh_checks, "_topology_state", False)
        slow = mesh_checks.weld_vertices(v, f)
        monkeypatch.setattr(mesh_checks, "_topology_state", None)
        assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1]), name


def test_weld_keeps_the_lowest_index_coordinates_and_drops_unreferenced():
    v = np.array([[9.0, 9, 9], [0, 0, 0], [1, 0, 0], [0, 1, 0], [-0.0, 0, 0], [0, 0, 1]])
    f = np.array([[4, 2, 3], [4, 3, 5], [4, 5, 2], [2, 5, 3]])
    fast = nbk.weld_compact(v, f)
    rep = weld_map_numpy(v)
    slow = compact_vertices(v, rep[f])
    assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1])
    assert fast[0].shape == (4, 3) and np.signbit(fast[0][0, 0]) == np.signbit(v[1, 0])


# ---------------------------------------------------------------- near merge
def _kd_groups(v, tol):
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial import cKDTree

    pairs = cKDTree(v).query_pairs(tol, output_type="ndarray")
    n = len(v)
    g = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, label = connected_components(g, directed=False)
    rep = np.full(label.max() + 1, n)
    np.minimum.at(rep, label, np.arange(n))
    return rep[label]


def test_near_merge_groups_match_the_kd_tree():
    rng = np.random.default_rng(3)
    tol = 1e-3
    base = rng.uniform(-1, 1, size=(3000, 3))
    # chains: points 0.9 tol apart along a line join transitively, across several cells
    chain = np.array([0.5, 0.5, 0.5]) + np.outer(np.arange(40) * 0.9 * tol, [1, 0, 0])
    # pairs straddling cell boundaries at distance just under and just over tol
    edge = nbk.NEAR_CELL_TOLS * tol * 7
    straddle = np.array([[edge - 0.4 * tol, 0.1, 0.1], [edge + 0.5 * tol, 0.1, 0.1],
                         [edge - 0.6 * tol, -0.3, 0.2], [edge + 0.45 * tol, -0.3, 0.2 + 0.2 * tol],
                         [-edge - 0.5 * tol, 0.7, -0.7], [-edge + 0.6 * tol, 0.7, -0.7]])
    jitter = base[:500] + rng.normal(scale=0.3 * tol, size=(500, 3))
    v = np.concatenate([base, chain, straddle, jitter])[rng.permutation(3546)]
    rep = nbk.near_merge_map(v, tol)
    assert np.array_equal(rep, _kd_groups(v, tol))
    assert len(np.unique(rep)) < len(v) - 500  # the cases above did merge


def test_merge_close_vertices_is_the_same_with_and_without_numba(meshes, monkeypatch):
    # featuretype and idler_riser need the near merge (split copies 1e-16 apart)
    for name in ("featuretype.stl", "idler_riser_binary_solid_header.stl", "ballA.off", "spot.obj"):
        v, f = _raw(meshes, name)
        fast = mesh_io._merge_close_vertices(v, f, mesh_io.MERGE_RTOL)
        monkeypatch.setattr(mesh_checks, "_topology_state", False)
        slow = mesh_io._merge_close_vertices(v, f, mesh_io.MERGE_RTOL)
        monkeypatch.setattr(mesh_checks, "_topology_state", None)
        assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1]), name
        welded = mesh_checks.weld_vertices(v, f)[0]
        if name in ("featuretype.stl", "idler_riser_binary_solid_header.stl"):
            assert len(fast[0]) < len(welded), name  # the near merge did something here


def test_grid_declines_coordinates_it_cannot_index_and_extremes_still_match(monkeypatch):
    v = np.array([[0.0, 0, 0], [1e300, 0, 0], [0, 1, 0], [0, 0, 1e-300]])
    assert nbk.near_merge_map(v, 1e-290).shape == (0,)   # |x| / tol beyond int64: the caller's k-d tree
    # the merge tolerance is capped by the faces' own short edges (here 1e-300): no vertex of
    # this tetrahedron merges, although 64 ulps of 1e300 would swallow 0, 1 and 1e-300; the grid
    # cannot index such a tolerance and declines, and both paths keep the four vertices
    f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    out_v, out_f, done = nbk.weld_and_merge(v, f, 1e-310)
    assert not done or len(out_v) == 4
    fast = mesh_io._merge_close_vertices(v, f, 1e-310)
    assert len(fast[0]) == 4
    monkeypatch.setattr(mesh_checks, "_topology_state", False)
    slow = mesh_io._merge_close_vertices(v, f, 1e-310)
    assert np.array_equal(fast[0], slow[0]) and np.array_equal(fast[1], slow[1])


# ---------------------------------------------------------------- the clean-mesh verdict
def _report_key(r):
    return (r.codes, r.n_vertices, r.n_faces, r.n_welded, r.n_components, r.watertight, r.winding_consistent)


def _both_reports(v, f, welded=False):
    v, f = validate_inputs(v, f)
    fast = analyse_mesh(v, f, welded=welded)
    full = analyse_mesh(v, f, welded=welded, full=True)
    return fast.report, full.report


@pytest.mark.parametrize("name", TEST_MESHES)
def test_clean_verdict_and_report_match_the_full_analysis_on_test_meshes(meshes, name):
    v, f = mesh_io.load_mesh(meshes.path(name))
    fast, full = _both_reports(v, f, welded=True)
    assert _report_key(fast) == _report_key(full)
    assert fast.area == pytest.approx(full.area, rel=1e-12)
    if full.ok and full.n_components == 1:
        assert fast.volume == pytest.approx(full.volume, rel=1e-12)
    raw = _raw(meshes, name)            # unwelded: the kernel welds by itself
    fast, full = _both_reports(*raw)
    assert _report_key(fast) == _report_key(full)


def _octahedron():
    v = np.array([[1.0, 0, 0], [-1, 0, 0], [0, 1, 0], [0, -1, 0], [0, 0, 1], [0, 0, -1]])
    f = np.array([(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)])
    return v, f


def _defect_cases():
    v, f = _octahedron()
    two = (np.concatenate([v, v + [5, 0, 0]]), np.concatenate([f, f + 6]))
    nan = v.copy()
    nan[3, 1] = np.nan
    extra_nan = (np.concatenate([v, [[np.nan, 0, 0]]]), f)       # unreferenced NaN vertex
    flipped = f.copy()
    flipped[0] = flipped[0, [0, 2, 1]]
    tiny = v.copy()
    tiny[4] = [0, 0, 1e-14]                                       # flattened top: zero-area faces
    fan = np.concatenate([f, [[0, 2, 4]]])                        # a third face on three edges
    return {"clean": (v, f), "two_components": two, "inverted": (v, f[:, [0, 2, 1]]),
            "open": (v, f[:-1]), "flipped_face": (v, flipped), "non_manifold": (v, fan),
            "duplicate": (v, np.concatenate([f, f[:1, [0, 2, 1]]])), "nan": (nan, f), "extra_nan": extra_nan,
            "collapsed": (v, np.concatenate([f, [[0, 0, 1]]])), "bad_index": (v, np.concatenate([f, [[0, 1, 9]]])),
            "flat": (tiny, f), "soup": _box_soup(np.random.default_rng(1))}


@pytest.mark.parametrize("case", sorted(_defect_cases()))
def test_clean_verdict_is_given_only_to_meshes_without_any_defect(case):
    v, f = _defect_cases()[case]
    fast, full = _both_reports(v, f)
    assert _report_key(fast) == _report_key(full)
    out = np.empty(2)
    vv, ff = validate_inputs(v, f)
    rep = weld_map_numpy(vv)
    ok = nbk.closed_single_shell(vv, rep[np.clip(ff, 0, len(vv) - 1)], 1e-12, out) if case != "bad_index" else \
        nbk.closed_single_shell(vv, ff, 1e-12, out)
    assert ok == (full.codes == () and full.n_components == 1), case
    if ok:
        assert out[1] == pytest.approx(full.volume, rel=1e-12)


def test_high_valence_vertex_uses_the_sorted_matching():
    """A cone over a 200-gon: the apex and the base center each carry 200 edges."""
    n = 200
    t = 2 * np.pi * np.arange(n) / n
    ring = np.stack([np.cos(t), np.sin(t), np.zeros(n)], axis=1)
    v = np.concatenate([ring, [[0, 0, 1], [0, 0, 0]]])
    apex, center = n, n + 1
    side = [(i, (i + 1) % n, apex) for i in range(n)]
    base = [((i + 1) % n, i, center) for i in range(n)]
    f = np.array(side + base)
    out = np.empty(2)
    assert nbk.closed_single_shell(v, f, 1e-12, out)
    assert out[1] == pytest.approx(n / 2 * np.sin(2 * np.pi / n) / 3, rel=1e-12)
    g = f.copy()
    g[5] = g[5, [1, 0, 2]]                     # one flipped side face: inconsistent at the apex
    assert not nbk.closed_single_shell(v, g, 1e-12, out)
    assert not nbk.closed_single_shell(v, f[:-1], 1e-12, out)  # open at the center


def test_mesh_properties_are_identical_with_and_without_numba(meshes, monkeypatch):
    import inertia

    for name in ("featuretype.stl", "wingnut.obj", "ballA.off"):
        path = meshes.path(name)
        fast = inertia.mesh_file_properties(path, density=1000.0)
        monkeypatch.setattr(mesh_checks, "_topology_state", False)
        slow = inertia.mesh_file_properties(path, density=1000.0)
        monkeypatch.setattr(mesh_checks, "_topology_state", None)
        assert fast.mass == slow.mass and np.array_equal(fast.inertia_com, slow.inertia_com), name


# ---------------------------------------------------------------- binary STL straight from bytes
def _write_stl(path, corners):
    rec = np.zeros(len(corners), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = corners
    path.write_bytes(b"x".ljust(80) + len(corners).to_bytes(4, "little") + rec.tobytes())


def test_stl_bytes_kernel_equals_the_soup_route(meshes, tmp_path):
    """Welding float32 bits straight from the file gives the arrays of the float64 soup route."""
    cases = {name: meshes.path(name)
             for name in ("featuretype.stl", "idler_riser_binary_solid_header.stl", "soup.stl")}
    rng = np.random.default_rng(5)
    v, f = _box_soup(rng)
    corners = v.reshape(-1, 3, 3).astype("<f4")
    corners[0, 0] = [-0.0, 0.0, -0.0]                    # signed zeros weld with 0
    corners[3, 1, 2] = np.nan                             # a NaN row stays alone
    corners[4, 2, 0] = np.inf
    corners[5] += rng.normal(scale=1e-12, size=(3, 3)).astype("<f4")  # float32 rounding
    _write_stl(tmp_path / "hand.stl", corners)
    cases["hand"] = tmp_path / "hand.stl"
    for name, path in cases.items():
        n = mesh_io._stl_kind(path)
        soup = mesh_io._read_binary_stl(path, n)
        for rtol in (mesh_io.MERGE_RTOL, 0.0, 1e-3):
            expect = mesh_io._merge_close_vertices(*soup, rtol)
            records = np.fromfile(path, dtype=mesh_io._STL_BITS, count=n, offset=84)
            got_v, got_f, done = nbk.stl_weld_and_merge(records["corners"], rtol)
            assert done
            assert np.array_equal(got_v, expect[0], equal_nan=True) and np.array_equal(got_f, expect[1]), (name, rtol)
            assert np.array_equal(np.signbit(got_v), np.signbit(expect[0])), name


def _near_pair_exists(v, tol):
    """Brute force: two rows within ``tol`` in every coordinate."""
    for i in range(len(v) - 1):
        if np.any(np.all(np.abs(v[i + 1:] - v[i]) <= tol, axis=1)):
            return True
    return False


def test_float32_apart_never_misses_a_near_pair():
    """The one-pass proof that float32 rows hold no near pair (the binary STL weld's shortcut
    past the merge grid) says True only when brute force finds none, and says it for ordinary
    point sets (else it saves nothing)."""
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
            i, j, k = rng.integers(n), rng.integers(n), rng.integers(3)
            v[j] = v[i]
            v[j, k] = np.nextafter(v[i, k], np.float32(np.inf))
        elif kind == 2:      # mirror images across a plane near 0 (same large coordinates)
            i, j = rng.integers(n), rng.integers(n)
            v[j] = v[i]
            v[i, 0] = np.float32(0.3 * tol)
            v[j, 0] = np.float32(-0.3 * tol)
        elif kind == 3:      # a copy within tol in every coordinate
            i, j = rng.integers(n), rng.integers(n)
            v[j] = (v[i].astype(np.float64) + rng.uniform(-0.4, 0.4, 3) * tol).astype(np.float32)
        v64 = np.unique(v.astype(np.float64), axis=0)                  # distinct rows, as the weld leaves them
        apart = nbk.float32_apart(np.ascontiguousarray(v64), tol, float(np.abs(v64).max()))
        if apart:
            assert not _near_pair_exists(v64, tol), (trial, tol)
            proved += 1
        elif kind in (1, 3):
            assert _near_pair_exists(v64, tol) or tol < 1e-7 * scale   # (a step can exceed a tiny tol)
    assert proved >= 6                  # most plain sets (a quarter of the trials) and some others
    # an ordinary mesh: a torus of 5,000 faces centred on 0, as its STL's float32 holds it
    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, 100, endpoint=False), np.linspace(0, 2 * np.pi, 25, endpoint=False))
    torus = np.stack([(1 + 0.3 * np.cos(w)) * np.cos(u), (1 + 0.3 * np.cos(w)) * np.sin(u), 0.3 * np.sin(w)], -1)
    torus = np.ascontiguousarray(torus.reshape(-1, 3).astype(np.float32).astype(np.float64))
    assert nbk.float32_apart(torus, 1e-10 * 2.6, 1.3)
    near = torus[:1].copy()
    near[0, 1:] += float(np.float32(1e-11))          # a float32 copy of vertex 0 = (1.3, 0, 0), 1.4e-11 away
    assert not nbk.float32_apart(np.concatenate([torus, near]), 1e-10 * 2.6, 1.3)
    # mirror images across x = 0 whose x is below 2^26 tol (the same key): apart by 0.02, proved
    # apart by comparing them; mirror images 0.6 tol apart are a near pair
    mirrored = np.array([[0.01, 0.5, 0.2], [-0.01, 0.5, 0.2]], dtype=np.float32).astype(np.float64)
    assert nbk.float32_apart(np.concatenate([torus, mirrored]), 1e-10 * 2.6, 1.3)
    mirrored[:, 0] = np.float32([0.3e-10 * 2.6, -0.3e-10 * 2.6])
    assert not nbk.float32_apart(np.concatenate([torus, mirrored]), 1e-10 * 2.6, 1.3)


def test_stl_weld_merges_a_split_vertex_near_zero_as_the_soup_route_does(tmp_path):
    """A binary STL whose vertex on the plane x = 0 is split into copies one float32 step
    apart (x = +-1e-30): merged, as the float64 soup route merges it."""
    rng = np.random.default_rng(2)
    v, f = _box_soup(rng)
    corners = (v.reshape(-1, 3, 3) - 0.5).astype("<f4")               # centred: coordinates +-0.5
    hit = np.argwhere(np.all(corners == np.float32(-0.5), axis=2))
    t, k = hit[0]
    corners[t, k, 0] = np.float32(1e-30)                               # the corner (-0.5, -0.5, -0.5) moved onto x ~ 0
    for t2, k2 in hit[1:]:
        corners[t2, k2, 0] = np.float32(-1e-30)                        # its other copies: a step apart
    _write_stl(tmp_path / "split.stl", corners)
    n = mesh_io._stl_kind(tmp_path / "split.stl")
    records = np.fromfile(tmp_path / "split.stl", dtype=mesh_io._STL_BITS, count=n, offset=84)
    got_v, got_f, done = nbk.stl_weld_and_merge(records["corners"], mesh_io.MERGE_RTOL)
    expect = mesh_io._merge_close_vertices(*mesh_io._read_binary_stl(tmp_path / "split.stl", n), mesh_io.MERGE_RTOL)
    assert done and np.array_equal(got_v, expect[0]) and np.array_equal(got_f, expect[1])
    assert len(got_v) == 8                                             # the split copies merged


# ---------------------------------------------------------------- checks and sums in one pass
def test_clean_solid_sums_are_the_bits_of_solid_sums_over_several_chunks():
    """The fused check returns the volume sums of the integrals kernel bit for bit (the same
    two-level blocked summation), here over five chunks of faces, far from the origin."""
    trimesh = pytest.importorskip("trimesh")
    from inertia.geometry import _integrals_numba as nbi
    from inertia.geometry._solid_numba import CHUNK

    m = trimesh.creation.icosphere(subdivisions=6)                 # 81,920 faces
    assert len(m.faces) > 4 * CHUNK
    rng = np.random.default_rng(5)
    v = np.ascontiguousarray(m.vertices * [1.0, 2.0, 0.5] + rng.normal(size=3) * 1e3)
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    out = np.empty(15)
    twins = np.full((len(f), 3), -1)
    assert nbk.clean_solid(v, f, 1e-14, 1e60, out, twins)
    ref = np.empty(10)
    assert nbi.solid_sums(v, f, out[11:14].copy(), ref) == -1
    assert np.array_equal(ref, out[:10])
    used_lo, used_hi = v.min(axis=0), v.max(axis=0)
    assert np.array_equal(out[11:14], 0.5 * (used_lo + used_hi))


def test_clean_solid_finds_each_edges_twin_as_face_twins_does():
    """The face across each edge, noted by the fused check as it matches the edges, is the one
    the self-crossing proof's own counting sort finds (``face_twins``), on shells that the
    pass does not prove star-shaped (the check then needs them), with vertices of low and
    high valence (the check's two matching paths: the center of the cone's base, pushed up
    into the cone as a dimple, has 64 faces); and the face across twice is the face itself,
    through the same edge."""
    trimesh = pytest.importorskip("trimesh")
    from inertia._ext.selfcross import face_twins

    cone = trimesh.creation.cone(0.5, 1.0, sections=64)
    dimple = np.array(cone.vertices)
    base = np.flatnonzero(np.all(np.abs(dimple) < 1e-12, axis=1))
    assert len(base) == 1
    dimple[base, 2] = 0.7                                        # below the side everywhere: no crossing
    shells = [trimesh.creation.torus(1.0, 0.3, major_sections=50, minor_sections=20),
              trimesh.Trimesh(dimple, cone.faces, process=False)]
    rng = np.random.default_rng(3)
    for m in shells:
        f = np.ascontiguousarray(m.faces, dtype=np.int64)
        turn = rng.integers(0, 3, len(f))[:, None]                  # each face's corners turned, faces shuffled
        f = np.ascontiguousarray(f[np.arange(len(f))[:, None], (np.arange(3) + turn) % 3][rng.permutation(len(f))])
        v = np.ascontiguousarray(m.vertices, dtype=np.float64)
        twins = np.full((len(f), 3), -1)
        out = np.empty(15)
        assert nbk.clean_solid(v, f, 1e-14, 1e60, out, twins)
        assert out[14] == 0.0                                        # not proved star-shaped
        ref = face_twins(f, len(v))
        assert ref is not None
        np.testing.assert_array_equal(twins, ref)
        t = np.arange(len(f))[:, None, None]
        back = twins[twins]                                          # (F, 3, 3): the twin's twins
        assert ((back == t).sum(axis=2) == 1).all()                  # the face itself, once
        k_back = np.argmax(back == t, axis=2)                        # through the twin's edge k_back
        start, end = f, np.roll(f, -1, axis=1)                       # edge k runs start -> end
        assert (start[twins, k_back] == end).all() and (end[twins, k_back] == start).all()


def test_public_call_tries_the_faces_as_given_then_welds():
    """A triangle soup (every corner its own vertex) is not closed as given: the call welds and
    gives the same properties as the welded mesh; an indexed closed mesh needs no weld."""
    import inertia

    rng = np.random.default_rng(2)
    v_soup, f_soup = _box_soup(rng)
    soup = inertia.mesh_properties(v_soup, f_soup, density=1.0)
    v, f = mesh_checks.weld_vertices(v_soup, f_soup)
    indexed = inertia.mesh_properties(v, f, density=1.0)
    assert soup.mass == pytest.approx(1.0, rel=1e-15) and indexed.mass == pytest.approx(1.0, rel=1e-15)
    np.testing.assert_allclose(soup.inertia_com, np.eye(3) / 6, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(indexed.inertia_com, soup.inertia_com, rtol=1e-14, atol=1e-16)
    # a bad index must never be wrapped by the weld (rep[-1]): refused by name
    f_bad = f_soup.copy()
    f_bad[0, 0] = -1
    with pytest.raises(inertia.MeshError, match="bad_index"):
        inertia.mesh_properties(v_soup, f_bad, density=1.0)
