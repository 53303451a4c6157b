"""A closed shell that passes through itself: found (certificate, then face-pair search), named,
weighed against the solid it bounds once, and the compiled kernels equal their NumPy twins.

Truth: closed forms of the solids (a box with a column pushed through its floor), the star
property of meshes built star-shaped, and the robust path's solid for the weighing."""

from __future__ import annotations

import numpy as np
import pytest

import inertia
from inertia.errors import MeshDefectWarning
from inertia.geometry import mesh_arrays
from inertia.geometry import self_crossing as sc
from inertia.geometry.checks import check_mesh

trimesh = pytest.importorskip("trimesh")


@pytest.fixture(params=["compiled", "numpy"])
def backend(request, monkeypatch):
    if request.param == "numpy":
        monkeypatch.setattr(mesh_arrays, "_topology_state", False)
    else:
        pytest.importorskip("numba")
    return request.param


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


def test_the_certificate_proves_star_shaped_meshes_and_not_a_torus(backend):
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


def test_a_box_pushed_through_its_floor_is_refused_by_name(backend):
    v, f = _pushed_box()
    r = check_mesh(v, f)
    assert r.codes == ("self_intersecting",) and r.watertight and r.winding_consistent
    assert "cross near" in r.defects[0].message
    with pytest.raises(inertia.MeshError, match="self_intersecting") as err:
        inertia.mesh_properties(v, f, density=1.0)
    assert "robust=True" in str(err.value)
    # what the refusal protects from: the signed volume (what trimesh returns) is not the solid's
    solid, signed = _height_field_volumes(v, f)
    assert trimesh.Trimesh(v, f, process=False).volume == pytest.approx(signed, rel=1e-4)
    assert signed < 0.9 * solid
    with pytest.warns(MeshDefectWarning, match="robust solid"):
        robust = inertia.mesh_properties(v, f, density=1.0, robust=True, robust_tol=1e-3)
    assert robust.mass == pytest.approx(solid, rel=2e-3)


def test_compiled_and_numpy_searches_agree(monkeypatch):
    pytest.importorskip("numba")
    rng = np.random.default_rng(4)
    cases = [_pushed_box(), _grid_box(1)]
    for _ in range(6):                     # random tori, some with a vertex pulled through the other side
        m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=24, minor_sections=10)
        v = np.array(m.vertices)
        if rng.random() < 0.5:
            k = rng.integers(len(v))
            v[k] = -v[k] * rng.uniform(0.8, 1.2)
        cases.append((v, np.array(m.faces, dtype=np.int64)))
    for v, f in cases:
        c = v.mean(axis=0)
        compiled = (sc.star_certificate(v, f, c), sc.first_crossing(v, f) is not None)
        monkeypatch.setattr(mesh_arrays, "_topology_state", False)
        numpy = (sc.star_certificate(v, f, c), sc.first_crossing(v, f) is not None)
        monkeypatch.setattr(mesh_arrays, "_topology_state", None)
        assert compiled == numpy


def test_a_found_crossing_is_a_real_crossing():
    """The pair the search names does cross: an exact test in rational arithmetic."""
    from fractions import Fraction

    v, f = _pushed_box()
    found = sc.first_crossing(v, f)
    A, B = (v[f[i]] for i in found.faces)

    def orient(a, b, c, d):
        a, b, c, d = ([Fraction(x) for x in p] for p in (a, b, c, d))
        u = [b[i] - a[i] for i in range(3)]
        w = [c[i] - a[i] for i in range(3)]
        z = [d[i] - a[i] for i in range(3)]
        return ((u[1] * w[2] - u[2] * w[1]) * z[0] + (u[2] * w[0] - u[0] * w[2]) * z[1]
                + (u[0] * w[1] - u[1] * w[0]) * z[2])

    def edge_through(p, q, T):
        sp, sq = orient(*T, p), orient(*T, q)
        s = [orient(p, q, T[k], T[(k + 1) % 3]) for k in range(3)]
        return sp * sq < 0 and (all(x > 0 for x in s) or all(x < 0 for x in s))

    assert any(edge_through(P[k], P[(k + 1) % 3], Q) for P, Q in ((A, B), (B, A)) for k in range(3))


def test_large_unproven_shells_carry_a_note(monkeypatch):
    monkeypatch.setattr(sc, "SEARCH_MAX_FACES", 100)
    import inertia.geometry.checks as checks

    monkeypatch.setattr(checks, "SEARCH_MAX_FACES", 100)
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16)
    p = inertia.mesh_properties(np.array(torus.vertices), np.array(torus.faces), density=1.0)
    assert len(p.warnings) == 1 and "self_crossing_unchecked" in p.warnings[0]
    assert p.mass == pytest.approx(torus.volume, rel=1e-12)           # the number is unchanged


def test_certificate_mode_notes_what_it_does_not_prove():
    """self_crossing='certificate' (bulk work): a shell the one-pass proof does not cover is not
    searched; the result carries the note self_crossing_unchecked (never silence), a proved
    shell carries nothing, and an unknown mode is refused by name."""
    torus = trimesh.creation.torus(1.0, 0.3, major_sections=40, minor_sections=16)
    p = inertia.mesh_properties(np.array(torus.vertices), np.array(torus.faces), density=1.0,
                                self_crossing="certificate")
    assert len(p.warnings) == 1 and "self_crossing_unchecked" in p.warnings[0]
    assert p.mass == pytest.approx(torus.volume, rel=1e-12)
    v, f = _pushed_box()                   # unproven and unsearched: here its tensor gives it away
    with pytest.raises(inertia.InvalidInertiaError):
        inertia.mesh_properties(v, f, density=1.0, self_crossing="certificate")
    sphere = trimesh.creation.icosphere(subdivisions=2)
    q = inertia.mesh_properties(np.array(sphere.vertices), np.array(sphere.faces), density=1.0,
                                self_crossing="certificate")
    assert q.warnings == () and q.mass == pytest.approx(sphere.volume, rel=1e-12)
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
    """certified_fans_around (each fan walked across the matched edges) agrees with
    certified_fans_of (every face sorted by vertex) on smooth and jittered closed shells, and
    refuses a vertex where two cones of faces touch, though the cone it walks is flat alone."""
    pytest.importorskip("numba")
    from inertia.geometry import _heightfield_numba as hf
    from inertia.geometry import _selfcross_numba as k

    rng = np.random.default_rng(3)
    n_cert = 0
    for it in range(40):
        m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=int(rng.integers(6, 30)),
                                   minor_sections=int(rng.integers(4, 16))) if it % 2 else \
            trimesh.creation.icosphere(int(rng.integers(1, 4)))
        f = np.ascontiguousarray(m.faces, dtype=np.int64)
        v = np.array(m.vertices, float)
        v = np.ascontiguousarray(v + rng.normal(0, rng.choice([0.0, 0.01, 0.05, 0.1]) * np.ptp(v), v.shape))
        N = k.face_frames(v, f)[0]
        adj, closed = hf.face_twins(f, len(v))
        assert closed
        wanted = rng.random(len(v)) < 0.5
        sorted_ = k.certified_fans_of(v, f, N, wanted)
        np.testing.assert_array_equal(k.certified_fans_around(v, f, N, adj, wanted), sorted_)
        n_cert += int(sorted_.sum())
    assert n_cert > 1000

    # two icosahedra touching at one vertex (index 0 of both): the edges all match, vertex 0
    # has two cones of five faces; one cone alone is flat and would be certified (jittered: a
    # regular one puts the first sector's bisector on another's edge, which is not certified)
    ico = trimesh.creation.icosphere(0)
    a, fa = np.array(ico.vertices), np.array(ico.faces, dtype=np.int64)
    a = a + np.random.default_rng(1).normal(0, 0.02, a.shape)
    b = 2.0 * a[0] - a                                  # point-mirrored through vertex 0
    v = np.vstack([a, b[1:]])
    fb = np.where(fa == 0, 0, fa + len(a) - 1)[:, ::-1]  # outward again after the mirror
    f = np.ascontiguousarray(np.vstack([fa, fb]))
    N = k.face_frames(v, f)[0]
    adj, closed = hf.face_twins(f, len(v))
    assert closed
    wanted = np.ones(len(v), dtype=bool)
    around = k.certified_fans_around(v, f, N, adj, wanted)
    assert not around[0] and around[1:].sum() >= 10
    np.testing.assert_array_equal(around, k.certified_fans_of(v, f, N, wanted))
    cone = np.flatnonzero((fa == 0).any(axis=1))
    turned = [np.roll(fa[t], -list(fa[t]).index(0)) for t in cone]
    order = [0]                                         # the cone's faces in turn around vertex 0
    while len(order) < len(cone):
        order.append(next(i for i in range(len(cone)) if turned[i][1] == turned[order[-1]][2]))
    ts = cone[order]
    A = np.array([turned[i][1] for i in order])
    B = np.array([turned[i][2] for i in order])
    assert k._fan_certified(v, N, 0, ts, A, B, len(ts))


def test_a_certified_fan_never_hides_a_crossing():
    """The search skips pairs of faces around a vertex whose fan is certified flat
    (``certified_fans``): on jittered meshes, where thousands of such pairs do cross, no crossing
    pair (the exact NumPy test) has its common vertex certified, while a smooth mesh has every
    vertex certified."""
    pytest.importorskip("numba")
    from inertia.geometry import _selfcross_numba as k
    from inertia.geometry.intersections import crossing

    smooth = trimesh.creation.torus(1.0, 0.3, major_sections=30, minor_sections=12)
    v, f = np.array(smooth.vertices), np.array(smooth.faces, dtype=np.int64)
    assert k.certified_fans(v, f, k.face_frames(v, f)[0]).all()
    rng = np.random.default_rng(11)
    n_crossing = 0
    for it in range(60):
        m = trimesh.creation.torus(1.0, rng.uniform(0.2, 0.5), major_sections=int(rng.integers(6, 20)),
                                   minor_sections=int(rng.integers(4, 10))) if it % 2 else trimesh.creation.icosphere(2)
        v = np.array(m.vertices, float)
        f = np.ascontiguousarray(m.faces, dtype=np.int64)
        v = np.ascontiguousarray(v + rng.normal(0, rng.choice([0.05, 0.1, 0.2]) * np.ptp(v), v.shape))
        cert = k.certified_fans(v, f, k.face_frames(v, f)[0])
        for x in range(len(v)):
            around = np.flatnonzero((f == x).any(axis=1))
            pairs = np.array([(a, b) for i, a in enumerate(around) for b in around[i + 1:]
                              if len(set(f[a]) & set(f[b])) == 1])
            if len(pairs) == 0:
                continue
            hit = crossing(v[f[pairs[:, 0]]], v[f[pairs[:, 1]]])
            n_crossing += int(hit.sum())
            assert not (hit.any() and cert[x]), (it, x)
    assert n_crossing > 1000                     # the check had crossings to hide
