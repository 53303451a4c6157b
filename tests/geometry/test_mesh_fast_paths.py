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
from inertia._ext import integrals as _ext

from inertia.geometry import mesh_arrays as mesh_checks
from inertia.geometry import mesh_io
from inertia.geometry.checks import analyse_mesh
from inertia.geometry.mesh_arrays import validate_inputs, weld_map

clean_solid = _ext.clean_solid

TEST_MESHES = ["ballA.off", "featuretype.stl", "idler_riser_binary_solid_header.stl", "wingnut.obj", "soup.stl",
        "teapot_open.stl", "cycloidal.ply", "tray_bottom_ascii.stl", "spot.obj"]


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


def _face_twins(f):
    """(F, 3): the face across the edge from corner k of each face to corner k + 1 (a closed,
    consistently wound mesh: the face holding the reversed edge)."""
    owner = {(int(f[t, k]), int(f[t, (k + 1) % 3])): t for t in range(len(f)) for k in range(3)}
    return np.array([[owner[int(f[t, (k + 1) % 3]), int(f[t, k])] for k in range(3)] for t in range(len(f))])


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
    # two shells around the center: the star test's ray leaves twice (nested), or the inner shell's
    # faces turn away from it (a cavity); neither is one component
    nested = (np.concatenate([v, 0.5 * v]), np.concatenate([f, f + 6]))
    cavity = (np.concatenate([v, 0.5 * v]), np.concatenate([f, f[:, [0, 2, 1]] + 6]))
    return {"clean": (v, f), "two_components": two, "inverted": (v, f[:, [0, 2, 1]]), "nested": nested,
            "cavity": cavity,
            "open": (v, f[:-1]), "flipped_face": (v, flipped), "non_manifold": (v, fan),
            "duplicate": (v, np.concatenate([f, f[:1, [0, 2, 1]]])), "nan": (nan, f), "extra_nan": extra_nan,
            "collapsed": (v, np.concatenate([f, [[0, 0, 1]]])), "bad_index": (v, np.concatenate([f, [[0, 1, 9]]])),
            "flat": (tiny, f), "soup": _box_soup(np.random.default_rng(1))}


@pytest.mark.parametrize("case", sorted(_defect_cases()))
def test_clean_verdict_is_given_only_to_meshes_without_any_defect(case):
    v, f = _defect_cases()[case]
    fast, full = _both_reports(v, f)
    assert _report_key(fast) == _report_key(full)
    vv, ff = validate_inputs(v, f)
    rep = weld_map(vv)
    out = clean_solid(vv, rep[np.clip(ff, 0, len(vv) - 1)] if case != "bad_index" else ff, 1e-12)
    assert (out is not None) == (full.codes == () and full.n_components == 1), case
    if out is not None:
        assert out[0] / 6 == pytest.approx(full.volume, rel=1e-12)


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
    adj = np.full((len(f), 3), -1)
    out = clean_solid(v, f, 1e-12, adj=adj)
    assert out is not None and out[0] / 6 == pytest.approx(n / 2 * np.sin(2 * np.pi / n) / 3, rel=1e-12)
    if out[14] == 0.0:                         # not proved star-shaped: the twins were noted, both paths
        np.testing.assert_array_equal(adj, _face_twins(f))
    g = f.copy()
    g[5] = g[5, [1, 0, 2]]                     # one flipped side face: inconsistent at the apex
    assert clean_solid(v, g, 1e-12) is None
    assert clean_solid(v, f[:-1], 1e-12) is None  # open at the center


# ---------------------------------------------------------------- checks and sums in one pass
def test_clean_solid_sums_are_the_bits_of_solid_sums_over_several_chunks():
    """The fused check returns the volume sums of the integrals kernel bit for bit (the same
    two-level blocked summation), here over five chunks of faces and a last partial block of 4
    lanes, far from the origin."""
    trimesh = pytest.importorskip("trimesh")

    m = trimesh.creation.icosphere(subdivisions=6)                 # 81,920 faces
    rng = np.random.default_rng(5)
    v = np.ascontiguousarray(m.vertices * [1.0, 2.0, 0.5] + rng.normal(size=3) * 1e3)
    f = np.ascontiguousarray(m.faces[:-2], dtype=np.int64)           # an open cap: not clean, then closed
    assert len(f) > 4 * _ext.SUM_CHUNK and len(f) % 4 == 2
    assert clean_solid(v, f, 1e-14, 1e60) is None
    f = np.ascontiguousarray(np.concatenate([f, m.faces[-2:]]), dtype=np.int64)
    out = clean_solid(v, f, 1e-14, 1e60, adj=np.full((len(f), 3), -1))
    assert out is not None
    assert np.array_equal(_ext.solid_sums(v, f, out[11:14].copy()), out[:10])
    used_lo, used_hi = v.min(axis=0), v.max(axis=0)
    assert np.array_equal(out[11:14], 0.5 * (used_lo + used_hi))


def test_clean_solid_finds_each_edges_twin_as_face_twins_does():
    """The face across each edge, noted by the fused check as it matches the edges, is the one
    a dictionary of directed edges finds, on shells that the pass does not prove star-shaped
    (the check then needs them), with vertices of low and high valence (the check's two
    matching paths: the center of the cone's base, pushed up into the cone as a dimple, has 64
    faces); and the face across twice is the face itself, through the same edge."""
    trimesh = pytest.importorskip("trimesh")

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
        out = clean_solid(v, f, 1e-14, 1e60, adj=twins)
        assert out is not None and out[14] == 0.0                    # not proved star-shaped
        np.testing.assert_array_equal(twins, _face_twins(f))
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
