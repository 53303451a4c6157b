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
        p = inertia.mesh_properties(v, f, density=1.0, robust=True)
    text = p.warnings[-1]
    bound = float(text.split("relative error bounds: volume ")[1].split(",")[0])
    assert abs(p.volume / 1500.0 - 1) <= bound and bound < 0.5
