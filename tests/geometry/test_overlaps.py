"""Overlapping closed shells are named, not summed: the divergence-theorem integrals would
count the overlap twice.

Truth: closed forms of unions of boxes (the overlap of two axis-aligned cubes is a box), and
configurations that must not be flagged (touching, nested, apart, a cavity).
"""

from __future__ import annotations

import numpy as np
import pytest

import inertia
from inertia.errors import MeshError
from inertia.geometry import check_mesh

CUBE_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
CUBE_F = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                   (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])
R_Z = np.array([[0.8, -0.6, 0.0], [0.6, 0.8, 0.0], [0.0, 0.0, 1.0]])


def two(v2, f2=None):
    return np.vstack([CUBE_V * 10, v2]), np.vstack([CUBE_F, (CUBE_F if f2 is None else f2) + 8])


@pytest.mark.parametrize("name, second", [
    ("half overlap, faces coplanar", CUBE_V * 10 + [5, 0, 0]),
    ("corner overlap", CUBE_V * 10 + [5, 5, 5]),
    ("rotated, crossing", (CUBE_V * 10 - 5) @ R_Z.T + [5, 5, 5]),
    ("poking through one face", CUBE_V * [2, 2, 20] + [4, 4, -5]),
])
def test_overlapping_closed_shells_are_named_and_refused(name, second):
    v, f = two(second)
    report = check_mesh(v, f)
    assert report.codes == ("overlapping_shells",), name
    with pytest.raises(MeshError) as ei:
        inertia.mesh_properties(v, f, density=1.0)
    assert ei.value.code == "overlapping_shells" and "count the overlap twice" in str(ei.value)
    # the sum the integrals would give is wrong: e.g. half overlap: 2000 m^3 where the union is 1500 m^3
    with pytest.warns(inertia.errors.MeshDefectWarning, match="overlapping_shells accepted"):
        summed = inertia.mesh_properties(v, f, density=1.0, on_defect="warn").volume
    assert summed == pytest.approx(2000.0 if "poking" not in name else 1080.0)


@pytest.mark.parametrize("name, second, f2", [
    ("touching along a face", CUBE_V * 10 + [10, 0, 0], None),
    ("touching at a corner", CUBE_V * 10 + [10, 10, 10], None),
    ("apart", CUBE_V * 10 + [20, 0, 0], None),
    ("cavity (inward inner shell)", CUBE_V * 2 + 4, CUBE_F[:, ::-1]),
])
def test_parts_that_touch_nest_or_stand_apart_are_not_flagged(name, second, f2):
    v, f = two(second, f2)
    assert "overlapping_shells" not in check_mesh(v, f).codes, name


def test_a_hollow_cube_keeps_its_exact_mass_properties():
    # truth: 10^3 - 2^3 = 992 m^3 for the cube with a 2 m cubic cavity
    v, f = two(CUBE_V * 2 + 4, CUBE_F[:, ::-1])
    assert inertia.mesh_properties(v, f, density=1.0).volume == pytest.approx(992.0, rel=1e-12)


def test_the_robust_path_answers_the_union_within_its_bound():
    # truth: the union of the two cubes of the half overlap is 1500 m^3 with its COM at x = 7.5
    v, f = two(CUBE_V * 10 + [5, 0, 0])
    with pytest.warns(Warning):
        p = inertia.mesh_properties(v, f, density=1.0, on_defect="robust")
    robust = next(x for x in p.findings if x.code == "robust_solid")
    bound = robust.values["bounds"]["volume"]
    assert abs(p.volume / 1500.0 - 1) <= bound and bound < 0.5
    assert robust.values["bounds"]["inertia"] <= robust.values["error_bound"] and p.precision > 0


def test_a_rod_through_a_cube_whose_samples_all_miss_is_found_by_its_crossing_faces():
    """A thin rod through the cube: no sample point of either surface lies inside the other (the
    rod's long faces have their centroids and corner points far out, the cube's points miss the
    rod), so only faces crossing faces show the overlap; the point named is on the cube's
    surface.  Truth: the rod's volume inside the cube, 10 x 0.02^2 / 2, counted twice."""
    s = 0.02
    tri_ = np.array([[0.0, 0.5, 0.5], [0.0, 0.5 + s, 0.5], [0.0, 0.5, 0.5 + s]])
    rod_v = np.vstack([tri_ + [-10, 0, 0], tri_ + [10, 0, 0]])                # a prism along x
    rod_f = np.array([(0, 2, 1), (3, 4, 5), (0, 1, 4), (0, 4, 3), (1, 2, 5), (1, 5, 4), (2, 0, 3), (2, 3, 5)])
    v, f = two(rod_v, rod_f)
    v = v.copy()
    v[:8] /= 10.0                                                          # the unit cube
    report = check_mesh(v, f)
    assert report.codes == ("overlapping_shells",)
    point = np.array(report.findings[0].values["example"]["point"])
    assert np.isclose(point, 0.0).any() or np.isclose(point, 1.0).any()   # on a face of the cube
    with pytest.warns(inertia.errors.MeshDefectWarning, match="overlapping_shells accepted"):
        summed = inertia.mesh_properties(v, f, density=1.0, on_defect="warn").volume
    assert summed == pytest.approx(1.0 + 20 * s * s / 2, rel=1e-12)


def test_winding_numbers_are_one_inside_zero_outside_and_the_solid_angle_on_the_surface():
    """Closed surfaces (counted by rays): 1 inside a cylinder, 0 outside, and equal to a sum of
    solid angles written here (Van Oosterom & Strackee) at random points and at points 1e-7 off
    a cube's faces; an open one (summed): the square face of a cube seen from its center, 4 pi / 6."""
    from inertia.geometry.intersections import winding_numbers
    from inertia.geometry.shapes import cylinder_mesh

    def solid_angles(points, tri):
        r = tri[None] - points[:, None, None, :]
        a, b, c = r[..., 0, :], r[..., 1, :], r[..., 2, :]
        la, lb, lc = (np.linalg.norm(x, axis=-1) for x in (a, b, c))
        num = np.einsum("ptk,ptk->pt", a, np.cross(b, c))
        den = la * lb * lc + (a * b).sum(-1) * lc + (a * c).sum(-1) * lb + (b * c).sum(-1) * la
        return (2.0 * np.arctan2(num, den)).sum(axis=1) / (4.0 * np.pi)

    v, f = cylinder_mesh(0.5, 1.0, sides=12)
    tri = v[f]
    pts = np.random.default_rng(5).uniform(-0.7, 0.7, size=(1000, 3))
    w = winding_numbers(pts, tri)
    np.testing.assert_allclose(w, solid_angles(pts, tri), rtol=0, atol=1e-12)
    inside = (np.hypot(pts[:, 0], pts[:, 1]) < 0.4) & (np.abs(pts[:, 2]) < 0.45)
    outside = (np.hypot(pts[:, 0], pts[:, 1]) > 0.55) | (np.abs(pts[:, 2]) > 0.55)
    assert inside.sum() > 50 and outside.sum() > 100
    np.testing.assert_array_equal(w[inside], 1.0)
    np.testing.assert_array_equal(w[outside], 0.0)
    cube = CUBE_V[CUBE_F]
    off = np.array([[0.5, 0.25, 1e-7], [0.5, 0.25, -1e-7], [0.3, 1 + 1e-7, 0.6], [0.3, 1 - 1e-7, 0.6]])
    np.testing.assert_array_equal(winding_numbers(off, cube), [1.0, 0.0, 0.0, 1.0])
    np.testing.assert_allclose(solid_angles(off, cube), [1.0, 0.0, 0.0, 1.0], atol=1e-9)
    square = np.array([[[1, -1, -1], [1, 1, -1], [1, 1, 1]], [[1, -1, -1], [1, 1, 1], [1, -1, 1]]], float)
    assert winding_numbers(np.zeros((1, 3)), square)[0] == pytest.approx(1 / 6, abs=1e-14)
