"""A closed shell that passes through itself: found (certificate, then face-pair search), named,
and weighed against the solid it bounds once; the same answers in every process.

Truth: closed forms of the solids (a box with a column pushed through its floor), the star
property of meshes built star-shaped, every crossing pair by brute force in exact integer
arithmetic (:mod:`._exact_crossings`), and the robust path's solid for the weighing."""

from __future__ import annotations

import numpy as np
import pytest
from inertia._ext import selfcross as k

import inertia
from inertia.errors import MeshDefectWarning
from inertia.geometry import self_crossing as sc
from inertia.geometry.checks import check_mesh

from ._exact_crossings import crosses_rationally, crossing_pairs, integer_shell

trimesh = pytest.importorskip("trimesh")
_NO_TWINS = np.empty((0, 3), dtype=np.int64)


def _grid_box(n: int, size: float = 9.0):
    """A closed box [-size/2, size/2]^3 whose faces are n x n grids (triangulated), outward."""
    m = trimesh.creation.box(extents=(size, size, size))
    v, f = m.vertices, m.faces
    for _ in range(n):
        v, f = trimesh.remesh.subdivide(v, f)
    return np.array(v, float), np.array(f, dtype=np.int64)


def _pushed_box():
    """The box with the 3 x 3 middle vertices of its top (a 4 x 4 grid) pushed down to z = -9,
    through the floor at z = -4.5: the top is a height field z_top(x, y) over the square."""
    v, f = _grid_box(2)
    top = (np.abs(v[:, 2] - 4.5) < 1e-12) & (np.abs(v[:, 0]) < 2.3) & (np.abs(v[:, 1]) < 2.3)
    v = v.copy()
    v[top, 2] = -9.0
    return v, f


def _height_field_volumes(v, f, n=1200):
    """(solid, signed) volumes of the pushed box by the midpoint rule over the square: the solid
    it bounds once is {-4.5 < z < z_top} where z_top > -4.5; the signed integral counts the
    part below the floor negative."""
    mtri = pytest.importorskip("matplotlib.tri")
    was_top = np.all(np.abs(_grid_box(2)[0][f][:, :, 2] - 4.5) < 1e-12, axis=1)
    tri = mtri.Triangulation(v[:, 0], v[:, 1], f[was_top])
    x = (np.arange(n) + 0.5) / n * 9.0 - 4.5
    X, Y = np.meshgrid(x, x)
    h = mtri.LinearTriInterpolator(tri, v[:, 2])(X, Y).filled(np.nan) + 4.5
    cell = (9.0 / n) ** 2
    return float(np.maximum(h, 0).sum() * cell), float(h.sum() * cell)


def _star_mesh(rng, n_sub=3):
    """A sphere with radii varied smoothly: star-shaped from the origin by construction."""
    m = trimesh.creation.icosphere(subdivisions=n_sub)
    d = m.vertices
    r = 1.0 + 0.3 * np.sin(3 * d[:, 0] + rng.uniform(0, 6)) * np.cos(2 * d[:, 1]) + 0.2 * d[:, 2] ** 2
    return np.array(d * r[:, None]), np.array(m.faces, dtype=np.int64)


def test_the_certificate_proves_star_shaped_meshes_and_not_a_torus():
    rng = np.random.default_rng(1)
    for _ in range(5):
        v, f = _star_mesh(rng)
        assert sc.star_certificate(v, f, np.zeros(3))                 # the origin sees every face
        assert sc.first_crossing(v, f) is None                        # and the search agrees
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16)
    tv, tf = np.array(torus.vertices), np.array(torus.faces, dtype=np.int64)
    assert not sc.star_certificate(tv, tf, np.zeros(3))               # the hole: not star-shaped
    assert sc.first_crossing(tv, tf) is None                          # yet embedded
    # a center outside the body certifies nothing
    v, f = _star_mesh(rng)
    assert not sc.star_certificate(v, f, np.array([5.0, 0.0, 0.0]))


def test_a_box_pushed_through_its_floor_is_refused_by_name():
    v, f = _pushed_box()
    r = check_mesh(v, f)
    assert r.codes == ("self_intersecting",) and r.watertight and r.winding_consistent
    assert "cross near" in r.findings[0].message
    with pytest.raises(inertia.MeshError, match="self_intersecting") as err:
        inertia.mesh_properties(v, f, density=1.0)
    assert "on_defect='robust'" in str(err.value) and ("on_defect", "robust") in err.value.remedies
    # what the refusal protects from: the signed volume (what trimesh returns) is not the solid's
    solid, signed = _height_field_volumes(v, f)
    assert trimesh.Trimesh(v, f, process=False).volume == pytest.approx(signed, rel=1e-4)
    assert signed < 0.9 * solid
    with pytest.warns(MeshDefectWarning, match="robust solid"):
        robust = inertia.mesh_properties(v, f, density=1.0, on_defect="robust", robust_tol=1e-3)
    assert robust.mass == pytest.approx(solid, rel=2e-3)


def test_the_search_finds_a_crossing_exactly_when_brute_force_does():
    """On closed shells from smooth to tangled (integer corners: the brute force over every pair
    of faces is exact), the search names a pair exactly when some pair crosses, and the pair it
    names crosses; the pushed box's pair crosses in rational arithmetic."""
    rng = np.random.default_rng(4)
    found = 0
    for it in range(60):
        v, f = integer_shell(rng, it)
        truth = crossing_pairs(v, f)
        got = sc.first_crossing(v, f)
        assert (got is not None) == bool(truth), it
        if got is not None:
            found += 1
            assert tuple(got.faces) in truth
            np.testing.assert_allclose(got.point, v[f[got.faces[0]]].mean(axis=0))
    assert 10 < found < 55                       # both kinds were met
    v, f = _pushed_box()
    found = sc.first_crossing(v, f)
    assert crosses_rationally(*(v[f[i]] for i in found.faces))


def test_large_unproven_shells_carry_a_note(monkeypatch):
    monkeypatch.setattr(sc, "SEARCH_MAX_FACES", 100)
    import inertia.geometry.checks as checks

    monkeypatch.setattr(checks, "SEARCH_MAX_FACES", 100)
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16)
    p = inertia.mesh_properties(np.array(torus.vertices), np.array(torus.faces), density=1.0)
    assert [(x.code, x.severity) for x in p.findings] == [("self_crossing_unchecked", "note")]
    assert p.mass == pytest.approx(torus.volume, rel=1e-12)           # the number is unchanged


def test_certificate_mode_notes_what_it_does_not_prove():
    """self_crossing='certificate' (bulk work): a shell the one-pass proof does not cover is not
    searched; the result carries the note self_crossing_unchecked (never silence), a proved
    shell carries nothing, and an unknown mode is refused by name."""
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16)
    p = inertia.mesh_properties(np.array(torus.vertices), np.array(torus.faces), density=1.0,
                                self_crossing="certificate")
    assert [(x.code, x.severity) for x in p.findings] == [("self_crossing_unchecked", "note")]
    assert p.mass == pytest.approx(torus.volume, rel=1e-12)
    v, f = _pushed_box()                   # unproven and unsearched: here its tensor gives it away
    with pytest.raises(inertia.InvalidInertiaError):
        inertia.mesh_properties(v, f, density=1.0, self_crossing="certificate")
    sphere = trimesh.creation.icosphere(subdivisions=2)
    q = inertia.mesh_properties(np.array(sphere.vertices), np.array(sphere.faces), density=1.0,
                                self_crossing="certificate")
    assert q.findings == () and q.mass == pytest.approx(sphere.volume, rel=1e-12)
    with pytest.raises(inertia.InputError, match="self_crossing must be one of"):
        inertia.mesh_properties(v, f, density=1.0, self_crossing="skip")


def test_batch_rows_name_the_mode_in_their_options(tmp_path):
    pytest.importorskip("pyarrow")
    from inertia.batch.run import run_batch

    v, f = _pushed_box()
    trimesh.Trimesh(v, f, process=False).export(tmp_path / "pushed.stl")
    trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16).export(tmp_path / "torus.stl")
    out = tmp_path / "rows.csv"
    run_batch([tmp_path / "torus.stl"], out, scheduler="synchronous", progress=False, self_crossing="certificate")
    text = out.read_text()
    assert "self_crossing=certificate" in text and "self_crossing_unchecked" in text
    out2 = tmp_path / "rows2.csv"
    run_batch([tmp_path / "pushed.stl", tmp_path / "torus.stl"], out2, scheduler="synchronous", progress=False)
    text = out2.read_text()
    assert "self_intersecting" in text and "self_crossing_unchecked" not in text   # the default searches


def test_fans_walked_across_edges_are_certified_as_fans_sorted_by_vertex():
    """The fans' certificates found by walking each fan across the matched edges (twins given)
    agree with those of every face sorted by vertex (no twins) on smooth and jittered closed
    shells, and a vertex where two cones of faces touch is refused, though the cone it walks is
    flat alone."""
    rng = np.random.default_rng(3)
    n_cert = 0
    for it in range(40):
        m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=int(rng.integers(6, 30)),
                                   minor_sections=int(rng.integers(4, 16))) if it % 2 else \
            trimesh.creation.icosphere(int(rng.integers(1, 4)))
        f = np.ascontiguousarray(m.faces, dtype=np.int64)
        v = np.array(m.vertices, float)
        v = np.ascontiguousarray(v + rng.normal(0, rng.choice([0.0, 0.01, 0.05, 0.1]) * np.ptp(v), v.shape))
        adj = k.face_twins(f, len(v))
        wanted = rng.random(len(v)) < 0.5
        sorted_ = k.certified_fans(v, f, wanted, _NO_TWINS)
        np.testing.assert_array_equal(k.certified_fans(v, f, wanted, adj), sorted_)
        assert not sorted_[~wanted].any()
        n_cert += int(sorted_.sum())
    assert n_cert > 1000

    # two icosahedra touching at one vertex (index 0 of both): the edges all match, vertex 0
    # has two cones of five faces; one cone alone is flat and is certified (jittered: a regular
    # one puts the first sector's bisector on another's edge, which is not certified)
    ico = trimesh.creation.icosphere(0)
    a, fa = np.array(ico.vertices), np.array(ico.faces, dtype=np.int64)
    a = a + np.random.default_rng(1).normal(0, 0.02, a.shape)
    b = 2.0 * a[0] - a                                  # point-mirrored through vertex 0
    v = np.ascontiguousarray(np.vstack([a, b[1:]]))
    fb = np.where(fa == 0, 0, fa + len(a) - 1)[:, ::-1]  # outward again after the mirror
    f = np.ascontiguousarray(np.vstack([fa, fb]))
    adj = k.face_twins(f, len(v))
    wanted = np.ones(len(v), dtype=bool)
    around = k.certified_fans(v, f, wanted, adj)
    assert not around[0] and around[1:].sum() >= 10
    np.testing.assert_array_equal(around, k.certified_fans(v, f, wanted, _NO_TWINS))
    cone = np.ascontiguousarray(fa[(fa == 0).any(axis=1)])
    assert k.certified_fans(v, cone, wanted, _NO_TWINS)[0]


def test_a_certified_fan_never_hides_a_crossing():
    """The search skips pairs of faces around a vertex whose fan is certified flat: on tangled
    shells, where hundreds of such pairs cross (exact brute force), no crossing pair has its
    common vertex certified, while a smooth mesh has every vertex certified."""
    smooth = trimesh.creation.torus(1.0, 0.3, major_sections=30, minor_sections=12)
    v, f = np.array(smooth.vertices), np.array(smooth.faces, dtype=np.int64)
    assert k.certified_fans(v, f, np.ones(len(v), bool), _NO_TWINS).all()
    rng = np.random.default_rng(11)
    n_crossing = 0
    for it in range(40):
        v, f = integer_shell(rng, it)
        cert = k.certified_fans(v, f, np.ones(len(v), bool), _NO_TWINS)
        for i, j in crossing_pairs(v, f):
            common = set(f[i]) & set(f[j])
            if len(common) == 1:
                n_crossing += 1
                assert not cert[common.pop()], (it, i, j)
    assert n_crossing > 100                      # the check had crossings to hide


_DETERMINISM = """
import hashlib, numpy as np, trimesh
from inertia._ext import selfcross as k
from inertia.geometry import self_crossing as sc
from inertia.geometry.intersections import winding_numbers
rng = np.random.default_rng(8)
h = hashlib.sha256()
for it in range(12):
    m = trimesh.creation.torus(1.0, 0.3, major_sections=40 + it, minor_sections=16)
    v = np.array(m.vertices) + rng.normal(0, 0.02 * (it % 3), (len(m.vertices), 3))
    f = np.ascontiguousarray(m.faces, dtype=np.int64)
    got = sc.first_crossing(v, f)
    h.update(repr(None if got is None else (got.faces, got.point.tobytes())).encode())
    h.update(k.unproved_faces(v, f, k.face_twins(f, len(v)), 0.3).tobytes())
    h.update(winding_numbers(rng.uniform(-1.5, 1.5, (50, 3)), v[f]).tobytes())
    h.update(bytes([sc.star_certificate(v, f, v.mean(axis=0))]))
print(h.hexdigest())
"""


def test_the_same_shells_give_the_same_bits_in_this_process_and_in_a_fresh_one():
    """Crossings found, faces the cell proof leaves, winding numbers and certificates: bit for
    bit the same twice in one process and in a new process."""
    import contextlib
    import io
    import subprocess
    import sys

    runs = []
    for _ in range(2):
        with contextlib.redirect_stdout(io.StringIO()) as out:
            exec(_DETERMINISM, {})
        runs.append(out.getvalue().strip())
    fresh = subprocess.run([sys.executable, "-c", _DETERMINISM], capture_output=True, text=True, check=True)
    assert runs[0] == runs[1] == fresh.stdout.strip()


def test_calls_on_threads_give_the_answers_of_calls_in_turn():
    """The kernels release the GIL and share nothing: shells searched, proved and counted on
    four threads at once give what one thread gives, bit for bit."""
    from concurrent.futures import ThreadPoolExecutor

    from inertia.geometry.intersections import winding_numbers

    rng = np.random.default_rng(9)
    shells = [integer_shell(rng, it, min_faces=k.HEIGHTFIELD_MIN_FACES) for it in range(16)]
    pts = rng.uniform(0, 500, (200, 3))

    def job(shell):
        v, f = shell
        got = sc.first_crossing(v, f)
        return (None if got is None else got.faces, winding_numbers(pts, v[f]).tobytes(),
                k.unproved_faces(v, f, k.face_twins(f, len(v)), 40.0).tobytes())

    serial = [job(shell) for shell in shells]
    with ThreadPoolExecutor(4) as pool:
        assert list(pool.map(job, shells)) == serial
    assert sum(x[0] is not None for x in serial) > 3


def test_bad_indices_and_shapes_are_refused_by_name():
    ico = trimesh.creation.icosphere(1)
    v, f = np.array(ico.vertices), np.array(ico.faces, dtype=np.int64)
    bad = f.copy()
    bad[3, 1] = len(v)
    with pytest.raises(inertia.InputError, match=r"faces\[3, 1\] = 42 names no vertex \(there are 42\)"):
        sc.first_crossing(v, bad)
    with pytest.raises(inertia.InputError, match="names no vertex"):
        sc.star_certificate(v, bad, np.zeros(3))
    twins = k.face_twins(f, len(v))
    twins[5, 2] = -1
    with pytest.raises(inertia.InputError, match=r"twins\[5, 2\] = -1 names no face \(there are 80\)"):
        sc.first_crossing(v, f, face_twins=twins)
    with pytest.raises(inertia.InputError, match="twins has length 3, expected 80"):
        sc.first_crossing(v, f, face_twins=twins[:3])
    with pytest.raises(inertia.InputError, match="center has length 2, expected 3"):
        sc.star_certificate(v, f, np.zeros(2))
    with pytest.raises(TypeError):
        sc.first_crossing(v[:, :2], f)
    nan = v.copy()
    nan[7, 1] = np.nan
    with pytest.raises(inertia.InputError, match="vertices of the faces must be finite"):
        sc.first_crossing(nan, f)
    assert np.isnan(inertia.geometry.intersections.winding_numbers(np.array([[0.0, np.nan, 0.0]]), v[f])).all()
