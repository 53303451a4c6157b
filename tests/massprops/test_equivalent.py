"""Tests of the equivalent uniform box and ellipsoid (inertia.massprops.equivalent).

Truth is built by hand here: box and ellipsoid tensors from their textbook formulas
(``M/12 (b^2 + c^2)``, ``M/5 (b^2 + c^2)``), rotated with scipy, and point-mass tensors from
the definition.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import inertia
from inertia.errors import InputError, NoEquivalentModelError
from inertia.massprops.equivalent import (
    EquivalentBox,
    EquivalentEllipsoid,
    equivalent_box,
    equivalent_ellipsoid,
    principal_second_moments,
)
from inertia.massprops.properties import MassProperties

RTOL = 1e-12
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


def box_tensor(M, dims):
    a, b, c = dims
    return M / 12.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def ellipsoid_tensor(M, semi):
    a, b, c = semi
    return M / 5.0 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])


def assert_same_props(got: MassProperties, M, com, I, rtol=RTOL):
    length = math.sqrt(np.trace(I) / M)
    assert abs(got.mass - M) <= rtol * M
    assert np.abs(got.com - com).max() <= rtol * max(np.abs(com).max(), length)
    assert np.abs(got.inertia_com - I).max() <= rtol * np.abs(I).max()


@st.composite
def posed_solids(draw):
    """(M, dims (3,), R (3, 3), com (3,)): a random solid's size and a random pose."""
    dims = np.array([draw(st.floats(0.05, 5.0)) for _ in range(3)])
    M = draw(st.floats(0.1, 100.0))
    R = Rotation.random(random_state=draw(st.integers(0, 2**32 - 1))).as_matrix()
    com = np.array([draw(st.floats(-10.0, 10.0)) for _ in range(3)])
    return M, dims, R, com


@st.composite
def physical_bodies(draw):
    s = np.array([draw(st.floats(0.01, 10.0)) for _ in range(3)])
    M = draw(st.floats(0.1, 100.0))
    R = Rotation.random(random_state=draw(st.integers(0, 2**32 - 1))).as_matrix()
    moments = M * (s.sum() - s)
    com = math.sqrt(moments.sum() / M) * np.array([draw(st.floats(-10.0, 10.0)) for _ in range(3)])
    return MassProperties(M, com, R @ np.diag(moments) @ R.T)


def matched_axes(dims_true, dims_got, R_true, R_got):
    """Columns of R_got that match (up to sign) the columns of R_true with the same length."""
    order = np.argsort(-dims_true)  # the model lists dimensions in descending order
    return np.abs(np.einsum("ik,ik->k", R_true[:, order], R_got))


# ---------------------------------------------------------------------------------------------- box
def test_box_primitive_by_hand_returns_its_dimensions():
    M, dims = 2.0, np.array([0.1, 0.3, 0.2])
    R = Rotation.from_euler("xyz", [0.2, 0.4, -0.3]).as_matrix()
    com = np.array([1.0, -2.0, 3.0])
    props = MassProperties(M, com, R @ box_tensor(M, dims) @ R.T, frame="link")
    box = equivalent_box(props)
    assert isinstance(box, EquivalentBox)
    assert np.allclose(box.size, [0.3, 0.2, 0.1], rtol=1e-13, atol=0)  # descending with ascending moments
    assert np.array_equal(box.size, box.dims)
    assert np.allclose(matched_axes(dims, box.size, R, box.R_body_principal), 1.0, rtol=0, atol=1e-12)
    assert np.array_equal(box.p_body_com, com)
    assert box.frame == "link" and box.findings == ()
    assert math.isclose(box.volume, 0.006, rel_tol=1e-13)
    assert math.isclose(box.density, M / 0.006, rel_tol=1e-13)
    assert_same_props(box.mass_properties(), M, com, props.inertia_com)
    assert box.mass_properties().frame == "link"


@SETTINGS
@given(solid=posed_solids())
def test_equivalent_box_of_random_posed_box(solid):
    M, dims, R, com = solid
    props = MassProperties(M, com, R @ box_tensor(M, dims) @ R.T)
    box = equivalent_box(props)
    assert np.allclose(box.size, np.sort(dims)[::-1], rtol=1e-9, atol=0)
    assert_same_props(box.mass_properties(), M, com, props.inertia_com)


def test_cube_has_identity_axes():
    box = equivalent_box(MassProperties(6.0, [0, 0, 0], box_tensor(6.0, [0.5, 0.5, 0.5])))
    assert np.allclose(box.size, 0.5, rtol=1e-14)
    assert np.array_equal(box.R_body_principal, np.eye(3))


# ---------------------------------------------------------------------------------------------- ellipsoid
def test_ellipsoid_primitive_by_hand_returns_its_semi_axes():
    M, semi = 3.0, np.array([0.2, 0.5, 0.1])
    R = Rotation.from_rotvec([0.1, -0.8, 0.5]).as_matrix()
    com = np.array([0.0, 0.5, -1.5])
    props = MassProperties(M, com, R @ ellipsoid_tensor(M, semi) @ R.T)
    ell = equivalent_ellipsoid(props)
    assert isinstance(ell, EquivalentEllipsoid)
    assert np.allclose(ell.semi_axes, [0.5, 0.2, 0.1], rtol=1e-13, atol=0)
    assert np.allclose(matched_axes(semi, ell.semi_axes, R, ell.R_body_principal), 1.0, rtol=0, atol=1e-12)
    assert math.isclose(ell.volume, 4.0 / 3.0 * math.pi * 0.01, rel_tol=1e-13)
    assert_same_props(ell.mass_properties(), M, com, props.inertia_com)


@SETTINGS
@given(solid=posed_solids())
def test_equivalent_ellipsoid_of_random_posed_ellipsoid(solid):
    M, semi, R, com = solid
    props = MassProperties(M, com, R @ ellipsoid_tensor(M, semi) @ R.T)
    ell = equivalent_ellipsoid(props)
    assert np.allclose(ell.semi_axes, np.sort(semi)[::-1], rtol=1e-9, atol=0)
    assert_same_props(ell.mass_properties(), M, com, props.inertia_com)


def test_sphere_is_its_own_equivalent_ellipsoid():
    M, r = 5.0, 0.3
    ell = equivalent_ellipsoid(MassProperties(M, [1.0, 1.0, 1.0], 0.4 * M * r * r * np.eye(3)))
    assert np.allclose(ell.semi_axes, r, rtol=1e-14)


def test_box_and_ellipsoid_of_the_same_body_differ_by_the_known_ratio():
    # b_i^2 / a_i^2 = (12 s_i / M) / (5 s_i / M) = 12 / 5
    props = MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.5, 2.0]))
    assert np.allclose(equivalent_box(props).size / equivalent_ellipsoid(props).semi_axes,
                       math.sqrt(12.0 / 5.0), rtol=1e-14)


# ---------------------------------------------------------------------------------------------- any body
@pytest.mark.parametrize("make", [equivalent_box, equivalent_ellipsoid])
@SETTINGS
@given(props=physical_bodies())
def test_equivalent_solid_reproduces_random_body(make, props):
    solid = make(props)
    assert_same_props(solid.mass_properties(), props.mass, props.com, props.inertia_com)
    # independent recomputation from the returned dimensions and axes
    k = 12.0 if make is equivalent_box else 5.0
    d2 = solid.dims ** 2
    I_P = props.mass / k * (d2.sum() - d2)
    R = solid.R_body_principal
    assert np.abs(R @ np.diag(I_P) @ R.T - props.inertia_com).max() <= RTOL * np.abs(props.inertia_com).max()


def test_principal_second_moments_are_sums_of_squares():
    rng = np.random.default_rng(7)
    m = rng.uniform(0.5, 2.0, 9)
    r = rng.normal(size=(9, 3)) * [2.0, 1.0, 0.3] + [1.0, 2.0, 3.0]
    props = MassProperties.from_point_masses(m, r)
    sm = principal_second_moments(props)
    rel_P = (r - props.com) @ sm.principal.R_body_principal  # rows: R_body_principal^T (r - com)
    s_true = np.einsum("k,ki->i", m, rel_P ** 2)  # s_i = sum m x_i^2 along principal axis i
    assert np.allclose(sm.second_moments, s_true, rtol=1e-12, atol=0)
    assert sm.flat_axes == ()


# ---------------------------------------------------------------------------------------------- flat bodies
def test_thin_plate_gives_a_lamina_box():
    # rectangular plate a x b, zero thickness: I = M/12 diag(b^2, a^2, a^2 + b^2)
    M, a, b = 2.0, 0.6, 0.4
    props = MassProperties(M, [0.0, 0.0, 1.0], M / 12.0 * np.diag([b * b, a * a, a * a + b * b]))
    box = equivalent_box(props)
    assert np.allclose(box.size[:2], [a, b], rtol=1e-14) and box.size[2] == 0.0
    assert box.volume == 0.0 and math.isnan(box.density)
    assert [(f.code, f.message) for f in box.findings] == [(
        "flat_body", "I1 + I2 - I3 = 0 kg m^2 is zero within 1.73e-13; the equivalent box is flat along "
        "principal axis 3 (b3 = 0 m)")]
    assert_same_props(box.mass_properties(), M, props.com, props.inertia_com)
    assert box.mass_properties().volume == 0.0
    json.dumps(box.to_dict())


def test_thin_plate_gives_a_flat_disc_ellipsoid():
    M = 1.0
    props = MassProperties(M, [0, 0, 0], np.diag([1.0, 2.0, 3.0]))
    ell = equivalent_ellipsoid(props)
    assert ell.semi_axes[2] == 0.0 and ell.volume == 0.0
    assert "equivalent ellipsoid is flat along principal axis 3 (a3 = 0 m)" in ell.findings[0].message
    assert_same_props(ell.mass_properties(), M, props.com, props.inertia_com)


# ---------------------------------------------------------------------------------------------- refusals
def test_unphysical_tensor_has_no_box():
    props = MassProperties(1.0, [0, 0, 0], np.diag([1.0, 1.0, 3.0]), validate=False)
    with pytest.raises(NoEquivalentModelError) as exc:
        equivalent_box(props)
    assert str(exc.value) == (
        "no equivalent box: I1 + I2 - I3 = -1 < 0 (needs b3^2 = 6/M (I1 + I2 - I3) = -6 m^2 >= 0; "
        "principal moments (1, 1, 3) kg m^2 about the COM, tolerance 5e-12), whereas every real mass "
        "distribution has I_j + I_k - I_i = 2 sum m x_i^2 >= 0")


def test_unphysical_tensor_has_no_ellipsoid():
    props = MassProperties(2.0, [0, 0, 0], np.diag([1.0, 1.0, 3.0]), validate=False)
    with pytest.raises(NoEquivalentModelError,
                       match=r"^no equivalent ellipsoid: I1 \+ I2 - I3 = -1 < 0 \(needs a3\^2 = 5/\(2M\) "
                             r"\(I1 \+ I2 - I3\) = -1\.25 m\^2 >= 0;"):
        equivalent_ellipsoid(props)


def test_non_positive_definite_has_no_solid():
    props = MassProperties(1.0, [0, 0, 0], np.diag([0.0, 1.0, 1.0]), validate=False)
    with pytest.raises(NoEquivalentModelError, match=r"^no equivalent box: inertia is not positive definite"):
        equivalent_box(props)


def test_zero_mass_has_no_solid():
    props = MassProperties(0.0, [0, 0, 0], np.diag([1.0, 1.0, 1.0]), validate=False)
    with pytest.raises(NoEquivalentModelError,
                       match=r"^no equivalent ellipsoid: mass must be positive and finite, got 0 kg$"):
        equivalent_ellipsoid(props)


def test_solid_constructor_checks():
    with pytest.raises(InputError, match=r"box: size must be >= 0, got \[1\.0, -1\.0, 1\.0\]"):
        EquivalentBox(1.0, [1.0, -1.0, 1.0], np.eye(3), np.zeros(3))
    with pytest.raises(InputError, match="ellipsoid: mass must be positive and finite, got 0"):
        EquivalentEllipsoid(0, [1.0, 1.0, 1.0], np.eye(3), np.zeros(3))


def test_to_dict_and_exports():
    props = MassProperties(1.0, [0, 0, 0], box_tensor(1.0, [0.3, 0.2, 0.1]))
    d = json.loads(json.dumps(equivalent_box(props).to_dict()))
    assert d["kind"] == "box" and np.allclose(d["size"], [0.3, 0.2, 0.1]) and d["frame"] == "body"
    e = json.loads(json.dumps(equivalent_ellipsoid(props).to_dict()))
    assert e["kind"] == "ellipsoid" and len(e["semi_axes"]) == 3
    assert inertia.equivalent_box is equivalent_box
    assert inertia.equivalent_ellipsoid is equivalent_ellipsoid
