"""Tests of the six-point and four-point particle models (inertia.particles.models).

Truth is computed here, independently of the package: the inertia of point masses by the
definition ``sum m (|r - c|^2 1 - (r - c)(r - c)^T)``, tensors from principal moments and a
scipy rotation, and hand-derived numbers for the closed forms.
"""

from __future__ import annotations

import ast
import json
import math
import pathlib

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

import inertia
from inertia.errors import InputError, InvalidInertiaError, NoEquivalentModelError
from inertia.massprops.properties import MassProperties
from inertia.particles import ParticleModel, four_point_model, six_point_model
from inertia.particles.models import TETRAHEDRON_SIGNS

RTOL = 1e-12
MODELS = [six_point_model, four_point_model]
SETTINGS = settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])


# ---------------------------------------------------------------------------------------------- truth helpers
def point_truth(masses, positions):
    """(mass, com, central inertia) of point masses, straight from the definitions."""
    m = np.asarray(masses, float)
    r = np.asarray(positions, float)
    M = m.sum()
    c = (m[:, None] * r).sum(axis=0) / M
    I = np.zeros((3, 3))
    for mk, rk in zip(m, r - c):
        I += mk * (np.dot(rk, rk) * np.eye(3) - np.outer(rk, rk))
    return M, c, I


def assert_reproduces(model: ParticleModel, M, com, I, rtol=RTOL):
    """The model's points have mass M, COM com and central inertia I (relative tolerance)."""
    M2, c2, I2 = point_truth(model.masses, model.positions_body)
    length = math.sqrt(np.trace(I) / M)  # a body size
    assert abs(M2 - M) <= rtol * M
    assert np.abs(c2 - com).max() <= rtol * max(np.abs(com).max(), length)
    assert np.abs(I2 - I).max() <= rtol * np.abs(I).max()


def tensor_from(moments, R):
    return R @ np.diag(moments) @ R.T


# ---------------------------------------------------------------------------------------------- strategies
@st.composite
def physical_bodies(draw):
    """Random physical bodies: principal second moments s_i > 0 give moments I_i = s_j + s_k
    (triangle inequality by construction), a uniformly random rotation and a COM within
    10 body sizes of the origin."""
    s = np.array([draw(st.floats(0.01, 10.0)) for _ in range(3)])
    M = draw(st.floats(0.1, 100.0))
    moments = M * (s.sum() - s)
    R = Rotation.random(random_state=draw(st.integers(0, 2**32 - 1))).as_matrix()
    length = math.sqrt(moments.sum() / M)
    com = length * np.array([draw(st.floats(-10.0, 10.0)) for _ in range(3)])
    return MassProperties(M, com, tensor_from(moments, R))


@st.composite
def point_clouds(draw):
    """Random physical bodies built as sums of 4..10 random point masses."""
    n = draw(st.integers(4, 10))
    rng = np.random.default_rng(draw(st.integers(0, 2**32 - 1)))
    m = rng.uniform(0.1, 10.0, n)
    r = rng.uniform(-1.0, 1.0, (n, 3)) * rng.uniform(0.1, 3.0, 3) + rng.uniform(-5.0, 5.0, 3)
    M, c, I = point_truth(m, r)
    assume(np.linalg.eigvalsh(I)[0] > 1e-6 * np.trace(I))  # not (nearly) coplanar
    return MassProperties(M, c, I)


# ---------------------------------------------------------------------------------------------- reproduction
@pytest.mark.parametrize("make", MODELS)
@SETTINGS
@given(props=physical_bodies())
def test_model_reproduces_random_principal_body(make, props):
    model = make(props)
    assert_reproduces(model, props.mass, props.com, props.inertia_com)
    assert model.mass_properties().isclose(props, rtol=RTOL)


@pytest.mark.parametrize("make", MODELS)
@SETTINGS
@given(props=point_clouds())
def test_model_reproduces_point_cloud_body(make, props):
    assert_reproduces(make(props), props.mass, props.com, props.inertia_com)


@pytest.mark.parametrize("make, n", [(six_point_model, 6), (four_point_model, 4)])
def test_positions_body_is_com_plus_rotated_principal_positions(make, n):
    R = Rotation.from_euler("zyx", [0.3, -0.7, 1.1]).as_matrix()
    props = MassProperties(2.5, [1.0, -2.0, 0.5], tensor_from([0.4, 0.7, 0.9], R), frame="chassis")
    model = make(props)
    assert model.n_points == len(model) == n
    assert model.masses.shape == (n,) and model.positions_body.shape == (n, 3)
    assert np.allclose(model.masses, props.mass / n, rtol=0, atol=1e-15)
    assert model.frame == "chassis"
    expect = props.com + model.positions_principal @ model.R_body_principal.T
    assert np.allclose(model.positions_body, expect, rtol=0, atol=1e-14)
    assert np.allclose(model.positions_principal.mean(axis=0), 0.0, atol=1e-15)
    # P is the canonical principal frame of the input
    axes = props.principal().R_body_principal
    assert np.array_equal(model.R_body_principal, axes)
    assert np.array_equal(model.p_body_com, props.com)


def test_model_arrays_are_read_only():
    model = six_point_model(MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.5])))
    for a in (model.masses, model.positions_body, model.positions_principal, model.R_body_principal):
        with pytest.raises(ValueError):
            a[0] = 1.0


def test_models_are_deterministic():
    R = Rotation.from_rotvec([0.2, 0.5, -0.4]).as_matrix()
    props = MassProperties(3.0, [0.1, 0.2, 0.3], tensor_from([1.0, 1.5, 2.0], R))
    for make in MODELS:
        a, b = make(props), make(props)
        assert np.array_equal(a.positions_body, b.positions_body)


# ---------------------------------------------------------------------------------------------- six-point closed form
def test_six_point_distances_match_the_closed_form():
    # M = 6, I = diag(2, 3, 4): d_i^2 = 3/(2M) (I_j + I_k - I_i) = (5/4, 3/4, 1/4)
    model = six_point_model(MassProperties(6.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0])))
    d = np.sqrt([1.25, 0.75, 0.25])
    expect = np.array([[d[0], 0, 0], [-d[0], 0, 0], [0, d[1], 0], [0, -d[1], 0], [0, 0, d[2]], [0, 0, -d[2]]])
    assert np.allclose(model.positions_principal, expect, rtol=0, atol=1e-15)
    assert np.array_equal(model.R_body_principal, np.eye(3))
    assert np.allclose(model.positions_body, expect, rtol=0, atol=1e-15)
    assert model.kind == "six_point" and model.findings == ()


# ---------------------------------------------------------------------------------------------- four-point geometry
def test_tetrahedron_directions_are_regular():
    t = TETRAHEDRON_SIGNS / math.sqrt(3.0)
    assert np.allclose(np.linalg.norm(t, axis=1), 1.0)
    assert np.array_equal(t.sum(axis=0), np.zeros(3))
    assert np.allclose(t.T @ t, 4.0 / 3.0 * np.eye(3), rtol=0, atol=1e-15)
    dots = t @ t.T
    assert np.allclose(dots[~np.eye(4, dtype=bool)], -1.0 / 3.0)  # regular: all angles arccos(-1/3)


def test_four_point_model_of_a_sphere_is_a_regular_tetrahedron():
    M, radius = 4.0, 0.5
    sphere = MassProperties(M, [1.0, 2.0, 3.0], 0.4 * M * radius**2 * np.eye(3))
    model = four_point_model(sphere)
    assert_reproduces(model, M, sphere.com, sphere.inertia_com)
    rel = model.positions_body - sphere.com
    # s = M r^2 / 5 on every axis, so every point is at sqrt(3 s / M) = sqrt(3/5) r from the centre
    assert np.allclose(np.linalg.norm(rel, axis=1), math.sqrt(3.0 / 5.0) * radius, rtol=1e-14)
    dist = np.linalg.norm(rel[:, None, :] - rel[None, :, :], axis=-1)[~np.eye(4, dtype=bool)]
    assert np.allclose(dist, dist[0], rtol=1e-14)
    assert np.allclose(model.masses, M / 4)


def test_four_point_positions_are_scaled_cube_corners():
    # M = 2, moments (2, 3, 4): s = (5/2, 3/2, 1/2), c_i = sqrt(s_i / M)
    model = four_point_model(MassProperties(2.0, [0, 0, 0], np.diag([2.0, 3.0, 4.0])))
    c = np.sqrt(np.array([2.5, 1.5, 0.5]) / 2.0)
    assert np.allclose(model.positions_principal, TETRAHEDRON_SIGNS * c, rtol=0, atol=1e-15)
    assert model.kind == "four_point"


@SETTINGS
@given(seed=st.integers(0, 2**32 - 1))
def test_three_points_are_always_flat(seed):
    """Independent check of the minimality argument: three point masses always give I1 + I2 = I3."""
    rng = np.random.default_rng(seed)
    _, _, I = point_truth(rng.uniform(0.1, 5.0, 3), rng.normal(size=(3, 3)))
    I1, I2, I3 = np.linalg.eigvalsh(I)
    assert abs(I1 + I2 - I3) <= 1e-12 * I3


# ---------------------------------------------------------------------------------------------- poses
@pytest.mark.parametrize("make", MODELS)
@SETTINGS
@given(props=physical_bodies(), seed=st.integers(0, 2**32 - 1))
def test_moved_model_has_the_moved_body_properties(make, props, seed):
    rng = np.random.default_rng(seed)
    R_WB = Rotation.random(random_state=rng).as_matrix()
    p_WB = rng.uniform(-3.0, 3.0, 3)
    r_W = make(props).positions_world(R_WB, p_WB)
    # the body moved by the pose: com_W = R com + p, I_W = R I R^T
    com_W = R_WB @ props.com + p_WB
    I_W = R_WB @ props.inertia_com @ R_WB.T
    length = math.sqrt(np.trace(props.inertia_com) / props.mass)
    M2, c2, I2 = point_truth(make(props).masses, r_W)
    assert np.abs(c2 - com_W).max() <= RTOL * max(np.abs(com_W).max(), length)
    assert np.abs(I2 - I_W).max() <= RTOL * np.abs(I_W).max()
    # and the same as moving the MassProperties with the package's own transform
    moved = props.transformed(R_WB, p_WB)
    assert MassProperties.from_point_masses(make(props).masses, r_W, validate=False).isclose(moved, rtol=RTOL)


def test_positions_world_batches_broadcast():
    props = MassProperties(1.0, [0.1, 0.2, 0.3], np.diag([1.0, 2.0, 2.5]))
    model = six_point_model(props)
    R = Rotation.random(6, random_state=1).as_matrix().reshape(2, 3, 3, 3)
    p = np.random.default_rng(2).normal(size=(3, 3))
    out = model.positions_world(R, p)  # (2, 3) batch of rotations with (3,) batch of offsets
    assert out.shape == (2, 3, 6, 3)
    for a in range(2):
        for b in range(3):
            single = model.positions_world(R[a, b], p[b])
            assert single.shape == (6, 3)
            assert np.allclose(out[a, b], single, rtol=0, atol=1e-14)
            assert np.allclose(single, model.positions_body @ R[a, b].T + p[b], rtol=0, atol=1e-14)
    # one rotation, several offsets; default offset is zero
    assert model.positions_world(np.eye(3), np.zeros((5, 3))).shape == (5, 6, 3)
    assert np.array_equal(model.positions_world(np.eye(3)), model.positions_body)


def test_positions_world_rejects_bad_poses():
    model = four_point_model(MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.5])))
    with pytest.raises(InputError, match="R_world_body is a reflection"):
        model.positions_world(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InputError, match="R_world_body is not orthonormal"):
        model.positions_world(2 * np.eye(3))
    with pytest.raises(InputError, match=r"p_world_body must have shape \(\.\.\., 3\), got \(2,\)"):
        model.positions_world(np.eye(3), [1.0, 2.0])


# ---------------------------------------------------------------------------------------------- export
def test_to_dict_is_json_ready():
    props = MassProperties(2.0, [1.0, 0.0, 0.0], np.diag([1.0, 2.0, 2.5]), frame="base")
    model = six_point_model(props)
    d = json.loads(json.dumps(model.to_dict()))
    assert d["kind"] == "six_point" and d["frame"] == "base"
    assert np.allclose(d["masses"], model.masses)
    assert np.allclose(d["positions_body"], model.positions_body)
    assert np.allclose(d["positions_principal"], model.positions_principal)
    assert np.array(d["R_body_principal"]).shape == (3, 3)
    assert d["p_body_com"] == [1.0, 0.0, 0.0]
    assert d["findings"] == []


def test_mass_properties_keeps_the_frame_name():
    props = MassProperties(2.0, [1.0, 0.0, 0.0], np.diag([1.0, 2.0, 2.5]), frame="base")
    mp = four_point_model(props).mass_properties()
    assert mp.frame == "base" and mp.isclose(props)


# ---------------------------------------------------------------------------------------------- unphysical input
def unphysical(moments, mass=1.0):
    return MassProperties(mass, [0.0, 0.0, 0.0], np.diag(moments), validate=False)


def test_triangle_violation_message_six_point():
    with pytest.raises(NoEquivalentModelError) as exc:
        six_point_model(unphysical([1.0, 1.0, 3.0]))
    assert str(exc.value) == (
        "no six-point model: I1 + I2 - I3 = -1 < 0 (needs d3^2 = 3/(2M) (I1 + I2 - I3) = -1.5 m^2 >= 0; "
        "principal moments (1, 1, 3) kg m^2 about the COM, tolerance 5e-12), whereas every real mass "
        "distribution has I_j + I_k - I_i = 2 sum m x_i^2 >= 0")
    assert [v.code for v in exc.value.findings] == ["triangle_inequality"]
    assert exc.value.findings[0].values["margin"] == -1.0
    assert isinstance(exc.value, InvalidInertiaError) and isinstance(exc.value, ValueError)


def test_triangle_violation_message_four_point():
    with pytest.raises(NoEquivalentModelError,
                       match=r"^no four-point model: I1 \+ I2 - I3 = -1 < 0 \(needs c3\^2 = 1/\(2M\) \(I1 \+ I2 - I3\) "
                             r"= -0\.5 m\^2 >= 0;"):
        four_point_model(unphysical([1.0, 1.0, 3.0]))


def test_negative_moment_reports_each_violated_inequality():
    with pytest.raises(NoEquivalentModelError) as exc:
        six_point_model(unphysical([-0.5, 1.0, 1.0]))
    msg = str(exc.value)
    assert msg.startswith("no six-point model: I1 + I3 - I2 = -0.5 < 0 (needs d2^2 = 3/(2M) (I1 + I3 - I2) = -0.75 m^2")
    assert "; I1 + I2 - I3 = -0.5 < 0 (needs d3^2 = 3/(2M) (I1 + I2 - I3) = -0.75 m^2 >= 0" in msg
    assert msg.endswith("; inertia is not positive definite: principal moments (-0.5, 1, 1) kg m^2, "
                        "smallest -0.5 <= tolerance 1.5e-12")
    assert [v.code for v in exc.value.findings] == ["triangle_inequality", "triangle_inequality",
                                                      "not_positive_definite"]


def test_rod_is_not_positive_definite():
    # a thin rod: I1 = 0, I2 = I3; the triangle inequality holds but the tensor is singular
    with pytest.raises(NoEquivalentModelError) as exc:
        four_point_model(unphysical([0.0, 1.0, 1.0]))
    assert str(exc.value) == ("no four-point model: inertia is not positive definite: principal moments "
                              "(0, 1, 1) kg m^2, smallest 0 <= tolerance 2e-12")


def test_non_positive_mass_is_refused():
    with pytest.raises(NoEquivalentModelError) as exc:
        six_point_model(unphysical([1.0, 1.0, 1.0], mass=-2.0))
    assert str(exc.value) == "no six-point model: mass must be positive and finite, got -2 kg"


def test_asymmetric_tensor_is_refused():
    props = MassProperties(1.0, [0, 0, 0], [[1.0, 0.5, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]], validate=False)
    with pytest.raises(NoEquivalentModelError, match=r"^no six-point model: inertia is not symmetric: "
                                                     r"I\[0,1\] = 0\.5 but I\[1,0\] = 0"):
        six_point_model(props)


def test_rotated_unphysical_tensor_is_refused():
    R = Rotation.from_rotvec([0.3, 0.2, 0.1]).as_matrix()
    props = MassProperties(1.0, [5.0, 0.0, 0.0], tensor_from([1.0, 2.0, 3.01], R), validate=False)
    with pytest.raises(NoEquivalentModelError, match=r"no six-point model: I1 \+ I2 - I3 = -0\.01 < 0"):
        six_point_model(props)


def test_not_mass_properties_is_an_input_error():
    with pytest.raises(InputError, match="six-point model: expected a MassProperties, got ndarray"):
        six_point_model(np.eye(3))


# ---------------------------------------------------------------------------------------------- flat bodies
def test_exact_flat_plate_six_point_has_two_points_at_the_com():
    # moments (1, 2, 3): I1 + I2 = I3 exactly (a lamina normal to principal axis 3)
    props = MassProperties(1.0, [0.5, 0.5, 0.5], np.diag([1.0, 2.0, 3.0]))
    model = six_point_model(props)
    assert model.positions_principal[4].tolist() == [0.0, 0.0, 0.0]
    assert model.positions_principal[5].tolist() == [0.0, 0.0, 0.0]
    assert np.array_equal(model.positions_body[4], props.com)
    assert [f.code for f in model.findings] == ["flat_body"]
    assert model.findings[0].message.startswith("I1 + I2 - I3 = 0 kg m^2 is zero within 6e-12; d3 = 0 m, so "
                                                "points 4 and 5 (+-d3 on principal axis 3) coincide at the COM")
    assert_reproduces(model, 1.0, props.com, props.inertia_com)
    json.dumps(model.to_dict())  # no -0.0 / NaN trouble


def test_exact_flat_plate_four_point_is_a_rectangle():
    props = MassProperties(1.0, [0.0, 0.0, 0.0], np.diag([1.0, 2.0, 3.0]))
    model = four_point_model(props)
    assert np.array_equal(model.positions_principal[:, 2], np.zeros(4))
    assert "the four points lie in the plane normal to principal axis 3" in model.findings[0].message
    assert_reproduces(model, 1.0, props.com, props.inertia_com)


@pytest.mark.parametrize("make", MODELS)
@SETTINGS
@given(seed=st.integers(0, 2**32 - 1))
def test_rotated_point_lamina(make, seed):
    """Coplanar point masses in a random plane: an exact lamina up to rounding."""
    rng = np.random.default_rng(seed)
    R = Rotation.random(random_state=rng).as_matrix()
    r_local = np.column_stack([rng.uniform(-1, 1, (8, 2)), np.zeros(8)])
    r = r_local @ R.T + rng.uniform(-2, 2, 3)
    M, c, I = point_truth(rng.uniform(0.5, 2.0, 8), r)
    model = make(MassProperties(M, c, I))
    assert_reproduces(model, M, c, I)
    assert model.findings and model.findings[0].code == "flat_body"
    assert model.findings[0].message.startswith("I1 + I2 - I3 = ")
    # the flat axis has (near) zero extent
    assert np.abs(model.positions_principal[:, 2]).max() <= 1e-6 * np.abs(model.positions_principal).max()


def test_margin_negative_within_tolerance_is_clipped_to_flat():
    I3 = 3.0 * (1.0 + 1e-13)  # margin -3e-13, tolerance 6e-12
    model = six_point_model(unphysical([1.0, 2.0, I3]))
    assert model.positions_principal[4, 2] == 0.0 and model.positions_principal[5, 2] == 0.0
    assert model.findings


def test_margin_negative_beyond_tolerance_is_refused():
    with pytest.raises(NoEquivalentModelError, match=r"I1 \+ I2 - I3 = -3e-11 < 0"):
        six_point_model(unphysical([1.0, 2.0, 3.0 + 3e-11]))


def test_rtol_keyword_loosens_the_check():
    model = four_point_model(unphysical([1.0, 2.0, 3.0 + 3e-11]), rtol=1e-9)
    assert np.array_equal(model.positions_principal[:, 2], np.zeros(4))


# ---------------------------------------------------------------------------------------------- repeated moments
@pytest.mark.parametrize("make", MODELS)
@pytest.mark.parametrize("moments", [[1.0, 1.0, 1.5], [1.0, 1.8, 1.8], [2.0, 2.0, 2.0]])
def test_repeated_moments(make, moments):
    R = Rotation.from_rotvec([0.4, -1.0, 0.7]).as_matrix()
    props = MassProperties(1.5, [0.0, 1.0, 0.0], tensor_from(moments, R))
    assert_reproduces(make(props), props.mass, props.com, props.inertia_com)


# ---------------------------------------------------------------------------------------------- package wiring
def test_lazy_exports():
    assert inertia.six_point_model is six_point_model
    assert inertia.four_point_model is four_point_model
    assert inertia.particles.ParticleModel is ParticleModel


def test_massprops_never_imports_particles():
    root = pathlib.Path(inertia.__file__).parent / "massprops"
    for path in root.glob("*.py"):
        tree = ast.parse(path.read_text())
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                name = ("." * node.level) + (node.module or "")
                assert "particles" not in name, f"{path.name} imports {name}"
            elif isinstance(node, ast.Import):
                assert not any("particles" in a.name for a in node.names), f"{path.name} imports particles"


def test_particle_model_constructor_checks():
    with pytest.raises(InputError, match=r"expected masses \(n,\) with n >= 1 and positions_principal \(n, 3\), "
                                         r"got \(2,\) and \(3, 3\)"):
        ParticleModel("x", [1.0, 1.0], np.zeros((3, 3)), np.eye(3), np.zeros(3))
    with pytest.raises(InputError, match="point mass 1 must be positive, got 0 kg"):
        ParticleModel("x", [1.0, 0.0], np.zeros((2, 3)), np.eye(3), np.zeros(3))
    m = ParticleModel("pair", [1.0, 1.0], [[1.0, 0, 0], [-1.0, 0, 0]], np.eye(3), [0.0, 0.0, 2.0])
    assert m.positions_body.tolist() == [[1.0, 0.0, 2.0], [-1.0, 0.0, 2.0]]
    assert m.mass == 2.0
