"""The compiled clean-mesh check against the full analysis it stands in for.

Truth: the full analysis, which the rest of the suite checks against closed forms.  The
compiled check must give the same verdicts, on the test meshes (made and real) and on meshes
built to hit each branch (every defect).  Welding and merging: test_weld_merge.py.
"""

from __future__ import annotations

import numpy as np
import pytest

from inertia.geometry import mesh_arrays as mesh_checks
from inertia.geometry import mesh_io
from inertia.geometry.checks import analyse_mesh
from inertia.geometry.mesh_arrays import validate_inputs, weld_map

nbk = pytest.importorskip("inertia.geometry._solid_numba")

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
    rep = weld_map(vv)
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
    from inertia.geometry._heightfield_numba import face_twins

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
        ref, closed = face_twins(f, len(v))
        assert closed
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
