"""Mesh defect checks and the mesh_properties defect policy, on synthetic meshes.

Truth: a box of size (a, b, c) and density rho has m = rho a b c and central inertia
m/12 diag(b^2 + c^2, a^2 + c^2, a^2 + b^2); each defect is built by hand so its code,
count and location are known exactly.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import inertia
from inertia.errors import Finding, InertiaError, InputError, MeshDefectWarning, MeshError
from inertia.geometry.checks import check_mesh
from inertia.geometry.mesh_arrays import validate_inputs, weld_vertices
from inertia.geometry.orient import orient_faces
from inertia.geometry.report import MeshReport
from inertia.massprops.mesh import mesh_properties

SIZE = np.array([1.0, 2.0, 3.0])
CENTER = np.array([10.0, -20.0, 30.0])


def box_mesh(size=SIZE, center=CENTER):
    """Closed, outward-wound box: vertex 4x + 2y + z is the corner (x, y, z) in {0, 1}^3."""
    corners = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
    v = (corners - 0.5) * np.asarray(size, float) + np.asarray(center, float)
    f = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                  [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
    return v, f


def box_truth(rho=1.0, size=SIZE):
    a, b, c = size
    m = rho * a * b * c
    return m, m / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def assert_is_box(props, rho=1.0, size=SIZE, center=CENTER):
    m, I = box_truth(rho, size)
    assert props.mass == pytest.approx(m, rel=1e-13)
    np.testing.assert_allclose(props.com, center, rtol=0, atol=1e-12 * np.abs(center).max())
    np.testing.assert_allclose(props.inertia_com, I, rtol=0, atol=1e-12 * np.abs(I).max())


def edge_faces(f, i, j):
    """Indices of faces having the undirected edge (i, j)."""
    return sorted(k for k, t in enumerate(f.tolist()) if {i, j} <= set(t))


# ---------------------------------------------------------------- clean meshes
def test_clean_box_reports_ok_and_gives_the_exact_box():
    v, f = box_mesh()
    r = check_mesh(v, f)
    assert isinstance(r, MeshReport)
    assert r.ok and r.watertight and r.winding_consistent
    assert r.codes == () and r.findings == ()
    assert (r.n_vertices, r.n_faces, r.n_welded, r.n_components) == (8, 12, 0, 1)
    assert r.volume == pytest.approx(6.0, rel=1e-14)
    assert r.area == pytest.approx(2 * (2 + 3 + 6), rel=1e-14)
    assert "no defects" in r.summary()
    p = mesh_properties(v, f, density=2.5)
    assert_is_box(p, rho=2.5)
    assert p.volume == pytest.approx(6.0, rel=1e-14)
    assert p.findings == ()
    assert_is_box(mesh_properties(v, f, mass=15.0), rho=2.5)


def test_public_names_are_exported_lazily():
    assert inertia.geometry.check_mesh is check_mesh
    assert inertia.geometry.MeshReport is MeshReport
    assert inertia.mesh_properties is mesh_properties


def test_split_vertices_are_welded_and_report_the_callers_indices():
    """An STL-like box (3 vertices per face) is watertight once exactly equal vertices are welded."""
    v, f = box_mesh()
    vs = v[f.ravel()]
    fs = np.arange(36).reshape(12, 3)
    r = check_mesh(vs, fs)
    assert r.ok and r.watertight and r.n_welded == 36 - 8
    assert_is_box(mesh_properties(vs, fs, density=1.0))
    wv, wf = weld_vertices(vs, fs)
    assert wv.shape == (8, 3) and wf.shape == (12, 3)
    # an open-edge report names original indices: drop face 0 = split vertices 0, 1, 2
    r = check_mesh(vs, fs[1:])
    d = r.get("open_edges")
    assert d.values["count"] == 3
    assert set(d.values["example"]["edge"]) <= set(range(36))
    assert np.array_equal(np.array(d.values["example"]["coords"]), vs[list(d.values["example"]["edge"])])


def test_negative_zero_welds_with_zero():
    v, f = box_mesh(size=(2, 2, 2), center=(1, 1, 1))  # corners at 0 and 2
    vs = v[f.ravel()].copy()
    vs[vs == 0.0] = -0.0
    vs[0] = [0.0, 0.0, 0.0]
    assert check_mesh(vs, np.arange(36).reshape(12, 3)).watertight


# ---------------------------------------------------------------- winding and orientation
def test_one_flipped_face_is_inconsistent_winding_and_repair_orient_repairs_it():
    v, f = box_mesh()
    f[3] = f[3][[0, 2, 1]]  # face 3 = (4, 5, 7) now
    r = check_mesh(v, f)
    assert r.codes == ("inconsistent_winding",)
    assert r.watertight and not r.winding_consistent and not r.ok
    d = r.get("inconsistent_winding")
    assert d.values["count"] == 3  # the three edges of the flipped face
    assert 3 in d.values["example"]["faces"] and len(d.values["example"]["faces"]) == 2
    i, j = d.values["example"]["edge"]
    assert {i, j} <= {4, 5, 7}
    assert f"edge ({i}, {j}) from " in d.message and "in faces" in d.message
    np.testing.assert_array_equal(d.values["example"]["coords"], v[[i, j]])

    with pytest.raises(MeshError) as exc:
        mesh_properties(v, f, density=1.0)
    msg = str(exc.value)
    assert "inconsistent_winding: 3 edges with inconsistent winding" in msg
    assert f"edge ({i}, {j})" in msg and "repair='orient'" in msg and "on_defect='warn'" in msg
    assert exc.value.remedies == (("repair", "orient"), ("on_defect", "robust"), ("on_defect", "warn"))
    assert "\n" not in msg
    assert exc.value.report.codes == ("inconsistent_winding",)

    p = mesh_properties(v, f, density=1.0, repair="orient")
    assert_is_box(p)
    assert [(x.code, x.severity, x.message) for x in p.findings] == [
        ("orientation_repaired", "note", "repair='orient' flipped 1 of 12 faces")]
    fixed, n = orient_faces(v, f)
    assert n == 1 and check_mesh(v, fixed).ok


def test_all_faces_flipped_is_inverted_and_repair_orient_repairs_it():
    v, f = box_mesh()
    f = f[:, ::-1].copy()
    r = check_mesh(v, f)
    assert r.codes == ("inverted",)
    assert r.watertight and r.winding_consistent
    d = r.get("inverted")
    assert d.values["count"] == 1 and d.values["example"]["component"] == 0 and d.values["example"]["volume"] == pytest.approx(-6.0)
    assert "wound inward" in d.message and "signed volume -6" in d.message
    with pytest.raises(MeshError, match=r"inverted: the closed surface is wound inward.*repair='orient'"):
        mesh_properties(v, f, density=1.0)
    # refused with on_defect="warn" as well: the volume is negative
    with pytest.raises(MeshError, match=r"signed volume -6 <= 0"), pytest.warns(MeshDefectWarning):
        mesh_properties(v, f, density=1.0, on_defect="warn")
    p = mesh_properties(v, f, density=1.0, repair="orient")
    assert_is_box(p)
    assert [x.message for x in p.findings] == ["repair='orient' flipped 12 of 12 faces"]


def test_cavity_wound_inward_is_not_inverted_and_gives_the_hollow_box():
    v, f = box_mesh(size=(4, 4, 4), center=(0, 0, 0))
    vi, fi = box_mesh(size=(2, 2, 2), center=(0.5, 0, 0))
    V = np.vstack([v, vi])
    hollow = np.vstack([f, fi[:, ::-1] + 8])
    r = check_mesh(V, hollow)
    assert r.ok and r.n_components == 2 and r.volume == pytest.approx(64 - 8)
    p = mesh_properties(V, hollow, density=1.0)
    m_o, I_o = box_truth(1.0, (4, 4, 4))
    m_i, I_i = box_truth(1.0, (2, 2, 2))
    m = m_o - m_i
    com = (m_o * np.zeros(3) - m_i * np.array([0.5, 0, 0])) / m
    d_o, d_i = -com, np.array([0.5, 0, 0]) - com
    par = lambda mm, d: mm * (d @ d * np.eye(3) - np.outer(d, d))  # noqa: E731
    I = I_o + par(m_o, d_o) - I_i - par(m_i, d_i)
    assert p.mass == pytest.approx(m, rel=1e-13)
    np.testing.assert_allclose(p.com, com, atol=1e-13)
    np.testing.assert_allclose(p.inertia_com, I, atol=1e-12 * np.abs(I).max())

    # the cavity wound outward is inverted (nested, so it should be negative); fix restores it
    wrong = np.vstack([f, fi + 8])
    r = check_mesh(V, wrong)
    d = r.get("inverted")
    assert r.codes == ("inverted",) and d.values["count"] == 1 and d.values["example"]["component"] == 1
    assert "1 component of 2 is wound inward" in d.message and "nested inside another component" in d.message
    fixed = mesh_properties(V, wrong, density=1.0, repair="orient")
    assert fixed.isclose(p, rtol=1e-12)


def test_one_of_two_disjoint_bodies_inverted():
    v1, f1 = box_mesh(center=(0, 0, 0))
    v2, f2 = box_mesh(center=(5, 0, 0))
    V = np.vstack([v1, v2])
    F = np.vstack([f1, f2[:, ::-1] + 8])
    r = check_mesh(V, F)
    assert r.codes == ("inverted",) and r.count("inverted") == 1
    assert r.get("inverted").values["example"]["face"] == 12
    p = mesh_properties(V, F, density=1.0, repair="orient")
    assert p.mass == pytest.approx(12.0) and p.com == pytest.approx([2.5, 0, 0])


def test_moebius_strip_cannot_be_oriented():
    n = 12
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    top = np.stack([(2 + 0.5 * np.cos(t / 2)) * np.cos(t), (2 + 0.5 * np.cos(t / 2)) * np.sin(t),
                    0.5 * np.sin(t / 2)], axis=1)
    bot = np.stack([(2 - 0.5 * np.cos(t / 2)) * np.cos(t), (2 - 0.5 * np.cos(t / 2)) * np.sin(t),
                    -0.5 * np.sin(t / 2)], axis=1)
    v = np.vstack([top, bot])  # top i, bottom n + i; after a full turn top and bottom swap
    faces = []
    for i in range(n):
        a, b = i, n + i
        c, d = ((i + 1, n + i + 1) if i < n - 1 else (n, 0))
        faces += [[a, b, d], [a, d, c]]
    f = np.array(faces)
    r = check_mesh(v, f)
    assert "open_edges" in r.codes and "inconsistent_winding" in r.codes
    with pytest.raises(MeshError, match="cannot be oriented consistently"):
        mesh_properties(v, f, density=1.0, repair="orient", on_defect="warn")
    with pytest.raises(MeshError, match="non-orientable"):
        orient_faces(v, f)


# ---------------------------------------------------------------- hard defects
def test_nan_vertex_is_always_refused():
    v, f = box_mesh()
    v[5, 1] = np.nan
    v[6, 2] = np.inf
    r = check_mesh(v, f)
    d = r.get("non_finite")
    assert d.values["count"] == 2 and d.values["example"]["vertex"] == 5
    assert "2 vertices with NaN or infinite coordinates, e.g. vertex 5 at (10.5, nan, 31.5)" in d.message
    assert not r.ok and not r.watertight
    for kw in ({}, {"on_defect": "warn"}, {"kind": "shell"}, {"repair": "orient"}, {"on_defect": "robust"}):
        with pytest.raises(MeshError, match=r"non_finite: 2 vertices .* vertex 5 .*NaN/inf"):
            mesh_properties(v, f, density=1.0, **kw)


def test_bad_indices_are_always_refused():
    v, f = box_mesh()
    f[2, 1] = -1  # negative: must not wrap around
    f[7, 0] = 8
    r = check_mesh(v, f)
    d = r.get("bad_index")
    assert d.values["count"] == 2 and d.values["example"]["face"] == 2 and d.values["example"]["vertices"] == (4, -1, 7)
    assert "2 faces with a vertex index outside 0..7, e.g. face 2 = (4, -1, 7)" in d.message
    for kw in ({}, {"on_defect": "warn"}, {"kind": "shell"}):
        with pytest.raises(MeshError, match=r"bad_index: 2 faces .*negative indices are not wrapped"):
            mesh_properties(v, f, density=1.0, **kw)


@pytest.mark.parametrize("vertices, faces", [
    (np.zeros((0, 3)), np.zeros((0, 3), int)),
    ([], []),
    (box_mesh()[0], np.zeros((0, 3), int)),
    (np.zeros((0, 3)), [[0, 1, 2]]),
])
def test_empty_mesh(vertices, faces):
    r = check_mesh(vertices, faces)
    assert r.codes == ("empty",) and r.count("empty") == 1 and not r.ok and not r.watertight
    n_v, n_f = len(np.asarray(vertices).reshape(-1, 3)), len(np.asarray(faces).reshape(-1, 3))
    assert r.get("empty").message == f"empty mesh: {n_v} vertices, {n_f} faces"
    for kw in ({}, {"on_defect": "warn"}, {"kind": "shell"}):
        with pytest.raises(MeshError, match=r"empty: empty mesh.*at least one triangle"):
            mesh_properties(vertices, faces, density=1.0, **kw)


def test_mesh_of_only_degenerate_faces_is_empty():
    v = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0]], float)
    r = check_mesh(v, [[0, 1, 2], [0, 1, 1]])
    assert r.codes == ("empty", "degenerate_faces", "open_edges") and not r.ok
    assert r.get("empty").message == "empty mesh: all 2 valid faces are degenerate (zero area)"
    with pytest.raises(MeshError, match="empty: empty mesh: all 2 valid faces are degenerate"):
        mesh_properties(v, [[0, 1, 2], [0, 1, 1]], density=1.0, kind="shell")


# ---------------------------------------------------------------- topology defects
def test_duplicate_face():
    v, f = box_mesh()
    f2 = np.vstack([f, f[4][::-1]])  # face 12 repeats face 4 (0, 4, 5), reversed
    r = check_mesh(v, f2)
    d = r.get("duplicate_faces")
    assert d.values["count"] == 1 and d.values["example"]["faces"] == (4, 12) and d.values["example"]["vertices"] == (0, 4, 5)
    assert "1 duplicate face (same three vertices as another face), e.g. faces 4 and 12" in d.message
    assert r.count("non_manifold_edges") == 3  # its edges are now used by three faces
    with pytest.raises(MeshError, match=r"duplicate_faces: 1 duplicate face .* faces 4 and 12"):
        mesh_properties(v, f2, density=1.0)
    with pytest.raises(MeshError, match=r"duplicate_faces.*count their area twice"):
        mesh_properties(v, f2, density=1.0, kind="shell")
    with pytest.warns(MeshDefectWarning) as rec:
        p = mesh_properties(v, f2, density=1.0, on_defect="warn")
    assert [str(w.message).split(":")[1].split()[0] for w in rec] == ["duplicate_faces", "non_manifold_edges"]
    assert [(x.code, x.severity) for x in p.findings] == [("duplicate_faces", "warning"),
                                                          ("non_manifold_edges", "warning")]
    # why it is an error: the reversed copy cancels face 4's tetrahedron (volume 1/2 about the center)
    assert p.mass == pytest.approx(5.5, rel=1e-14)


def test_non_manifold_edge_three_faces():
    v, f = box_mesh()
    v2 = np.vstack([v, CENTER + [0, -5, 0]])  # vertex 8 outside, a fin on edge (0, 4)
    f2 = np.vstack([f, [[0, 4, 8]]])
    r = check_mesh(v2, f2)
    d = r.get("non_manifold_edges")
    assert d.values["count"] == 1 and set(d.values["example"]["edge"]) == {0, 4}
    assert d.values["example"]["faces"] == tuple(edge_faces(f2, 0, 4)) == (4, 9, 12)
    assert d.values["example"]["balanced"] == 0
    assert "1 non-manifold edge (used by more than two faces), e.g. edge (" in d.message
    assert "shared by 3 faces (4, 9, 12)" in d.message
    assert r.count("open_edges") == 2  # the fin's free edges
    with pytest.raises(MeshError, match=r"non_manifold_edges: 1 non-manifold edge.*kind=.shell."):
        mesh_properties(v2, f2, density=1.0)
    # a thin shell may have fins
    p = mesh_properties(v2, f2, density=1.0, kind="shell")
    fin_area = 0.5 * np.linalg.norm(np.cross(v2[4] - v2[0], v2[8] - v2[0]))
    assert p.mass == pytest.approx(22.0 + fin_area, rel=1e-14)


def test_two_closed_bodies_sharing_an_edge_are_balanced_non_manifold():
    v1, f1 = box_mesh(size=(1, 1, 1), center=(0, 0, 0))
    v2, f2 = box_mesh(size=(1, 1, 1), center=(1, 1, 0))
    V = np.vstack([v1, v2])
    F = np.vstack([f1, f2 + 8])
    r = check_mesh(V, F)  # welded: the boxes share the edge x = y = 0.5
    d = r.get("non_manifold_edges")
    assert r.codes == ("non_manifold_edges",) and d.values["count"] == 1 and d.values["example"]["balanced"] == 1
    assert "all 1 balanced" in d.message
    with pytest.warns(MeshDefectWarning):
        p = mesh_properties(V, F, density=1.0, on_defect="warn")
    assert p.mass == pytest.approx(2.0, rel=1e-14)


def test_open_mesh_raise_warn_and_shell():
    v, f = box_mesh()
    f_open = np.delete(f, [2, 3], axis=0)  # remove the x = +1/2 side
    r = check_mesh(v, f_open)
    d = r.get("open_edges")
    assert r.codes == ("open_edges",) and d.values["count"] == 4 and not r.watertight and r.winding_consistent
    i, j = d.values["example"]["edge"]
    assert {i, j} <= {4, 5, 6, 7} and d.values["example"]["faces"][0] in range(10)
    fmt = lambda p: "(" + ", ".join(f"{x:g}" for x in p) + ")"  # noqa: E731
    assert f"e.g. edge ({i}, {j}) from {fmt(v[i])} to {fmt(v[j])} in face {d.values['example']['faces'][0]}" in d.message
    with pytest.raises(MeshError) as exc:
        mesh_properties(v, f_open, density=1.0)
    msg = str(exc.value)
    assert msg.startswith("mesh cannot be used as a solid: open_edges: 4 open edges (used by only one face")
    assert "kind='shell'" in msg and "on_defect='warn'" in msg and "repair" not in msg.split("Options")[1][:20]
    assert exc.value.remedies == (("kind", "shell"), ("on_defect", "robust"), ("on_defect", "warn"))

    with pytest.warns(MeshDefectWarning, match=r"open_edges accepted \(on_defect='warn'\): 4 open edges") as rec:
        p = mesh_properties(v, f_open, density=1.0, on_defect="warn")
    assert rec[0].filename == __file__  # points at the caller
    assert len(p.findings) == 1 and "4 open edges" in p.findings[0].message and p.findings[0].severity == "warning"
    assert np.isfinite(p.mass)

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        s = mesh_properties(v, f_open, density=2.0, kind="shell")
    area = 2 * (2 + 3 + 6) - 6
    assert s.mass == pytest.approx(2.0 * area) and s.findings == () and np.isnan(s.volume)
    # orientation is irrelevant to a shell
    assert mesh_properties(v, f_open[:, ::-1], density=2.0, kind="shell").isclose(s, rtol=1e-13)


def test_open_mesh_with_negative_volume_is_refused_even_with_warn():
    v, f = box_mesh()
    f_open = np.delete(f, [2, 3], axis=0)[:, ::-1]
    with pytest.raises(MeshError, match=r"signed volume -?[0-9.e+-]+ <= 0"), pytest.warns(MeshDefectWarning):
        mesh_properties(v, f_open, density=1.0, on_defect="warn")


def test_degenerate_faces_are_a_note_not_an_error():
    v, f = box_mesh()
    v2 = np.vstack([v, 0.5 * (v[0] + v[1])])  # vertex 8: midpoint of edge (0, 1)
    # split face 0 = (0, 1, 3) at vertex 8 and close the T-junction with the sliver (0, 1, 8)
    f2 = np.vstack([[[0, 8, 3], [8, 1, 3]], f[1:], [[0, 1, 8]], [[2, 7, 7]]])
    r = check_mesh(v2, f2)
    d = r.get("degenerate_faces")
    assert r.codes == ("degenerate_faces",) and d.values["count"] == 2 and d.severity == "note"
    assert d.values["example"]["face"] == 13 and d.values["example"]["vertices"] == (0, 1, 8)
    assert "2 faces of zero area (1 repeating a vertex after welding" in d.message
    assert "e.g. face 13 = (0, 1, 8) has area 0" in d.message
    assert r.ok and r.watertight and r.winding_consistent and r.errors == ()
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        p = mesh_properties(v2, f2, density=1.0)
    assert_is_box(p)
    assert [(x.code, x.severity) for x in p.findings] == [("degenerate_faces", "note")]
    assert "face 13" in p.findings[0].message


# ---------------------------------------------------------------- inputs and options
@pytest.mark.parametrize("vertices, faces, pattern", [
    (np.zeros((4, 2)), [[0, 1, 2]], r"vertices must have shape \(V, 3\), got \(4, 2\)"),
    ("abc", [[0, 1, 2]], r"vertices must be a numeric \(V, 3\) array"),
    (np.zeros((4, 3)), [[0, 1, 2, 3]], r"faces must have shape \(F, 3\) \(triangulate polygons first\), got \(1, 4\)"),
    (np.zeros((4, 3)), [0, 1, 2], r"faces must have shape \(F, 3\), got \(3,\)"),
    (np.zeros((4, 3)), [[0, 1.5, 2]], r"faces must hold integer vertex indices; faces\[0, 1\] = 1.5"),
    (np.zeros((4, 3)), [[0, np.nan, 2]], r"faces must hold integer vertex indices"),
    (np.zeros((4, 3)), [["a", "b", "c"]], r"faces must be an integer \(F, 3\) array"),
    (np.zeros((4, 3)), np.ones((1, 3), bool), r"faces must be an integer"),
])
def test_validate_inputs_errors(vertices, faces, pattern):
    with pytest.raises(InputError, match=pattern):
        validate_inputs(vertices, faces)
    with pytest.raises(InputError, match=pattern):
        check_mesh(vertices, faces)
    with pytest.raises(InputError, match=pattern):
        mesh_properties(vertices, faces, density=1.0)


def test_integral_float_faces_are_accepted():
    v, f = box_mesh()
    vv, ff = validate_inputs(v.tolist(), f.astype(float))
    assert vv.dtype == np.float64 and ff.dtype == np.int64 and np.array_equal(ff, f)
    assert_is_box(mesh_properties(v, f.astype(np.float32), density=1.0))
    assert_is_box(mesh_properties(v, f.astype(np.uint16), density=1.0))


def test_option_errors():
    v, f = box_mesh()
    with pytest.raises(InputError, match=r"on_defect must be one of \('raise', 'warn', 'robust'\), got 'ignore'"):
        mesh_properties(v, f, density=1.0, on_defect="ignore")
    with pytest.raises(InputError, match=r"kind must be one of \('solid', 'shell'\), got True"):
        mesh_properties(v, f, density=1.0, kind=True)
    with pytest.raises(InputError, match=r"repair must be one of \(None, 'orient'\), got 'weld'"):
        mesh_properties(v, f, density=1.0, repair="weld")
    # combinations that mean nothing are refused, never ignored
    with pytest.raises(InputError, match=r"on_defect='robust' integrates a solid"):
        mesh_properties(v, f, density=1.0, kind="shell", on_defect="robust")
    with pytest.raises(InputError, match=r"a thin shell's orientation does not matter"):
        mesh_properties(v, f, density=1.0, kind="shell", repair="orient")
    with pytest.raises(InputError, match="exactly one of density= or mass=, got both"):
        mesh_properties(v, f, density=1.0, mass=1.0)
    with pytest.raises(InputError, match="got neither"):
        mesh_properties(v, f)
    with pytest.raises(InputError, match="density must be finite and positive"):
        mesh_properties(v, f, density=-1.0)


def test_errors_share_the_base_class_and_carry_the_report():
    v, f = box_mesh()
    with pytest.raises(InertiaError) as exc:
        mesh_properties(v, f[:-1], density=1.0)
    assert isinstance(exc.value, MeshError) and isinstance(exc.value, ValueError)
    assert exc.value.report.count("open_edges") == 3


def test_frame_and_name_are_used():
    v, f = box_mesh()
    assert mesh_properties(v, f, density=1.0, frame="link1").frame == "link1"
    with pytest.raises(MeshError, match=r"^mesh part\.stl cannot be used as a solid"):
        mesh_properties(v, f[:-1], density=1.0, name="part.stl")


def test_report_accessors_and_summary():
    v, f = box_mesh()
    f2 = np.vstack([f[:-1], [[0, 0, 1]]])
    r = check_mesh(v, f2)
    assert r.codes == ("degenerate_faces", "open_edges")
    assert [d.severity for d in r.findings] == ["note", "error"]
    assert r.count("open_edges") == 3 and r.count("inverted") == 0 and r.get("inverted") is None
    assert all(isinstance(d, Finding) for d in r.findings)
    text = r.summary()
    assert text.splitlines()[0] == "mesh: 8 vertices (0 welded duplicates), 12 faces, 1 components"
    assert "- open_edges (error): 3 open edges" in text and "- degenerate_faces (note): 1 face" in text
    assert str(r) == text
    with pytest.raises(Exception):
        r.n_faces = 3  # frozen


def test_check_mesh_on_100k_faces_of_a_torus():
    """A closed torus grid of 100,000 faces: not star-shaped, so the face-pair search runs."""
    nu, nv = 250, 200
    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, nu, endpoint=False),
                       np.linspace(0, 2 * np.pi, nv, endpoint=False), indexing="ij")
    v = np.stack([(3 + np.cos(w)) * np.cos(u), (3 + np.cos(w)) * np.sin(u), np.sin(w)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(nu), np.arange(nv), indexing="ij")
    a = i * nv + j
    b = ((i + 1) % nu) * nv + j
    c = ((i + 1) % nu) * nv + (j + 1) % nv
    d = i * nv + (j + 1) % nv
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    assert len(f) == 100_000
    r = check_mesh(v, f)         # its time is measured in bench/mesh_mass_properties.py, not asserted
    assert r.ok and r.n_components == 1 and r.codes == ()       # the search found no crossing
    # torus volume 2 pi^2 R r^2, to the discretisation error
    assert r.volume == pytest.approx(2 * np.pi**2 * 3, rel=1e-3)
