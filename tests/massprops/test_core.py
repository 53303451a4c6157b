"""Value type, tensor functions, transforms, validity, canonical form, assembly.

Truth: the defining sum I = sum m (|r|^2 1 - r r^T) evaluated directly on point clouds,
the parallel-axis theorem derived independently (direct sums about another point),
and hand-computed closed forms.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import inertia
from inertia.errors import InertiaError, InputError, InvalidInertiaError
from inertia.massprops import principal_axes
from inertia.massprops.tensor import point_mass_inertia
from inertia.massprops.validity import is_physical

from ..conftest import random_point_cloud, random_rotation


def direct_inertia(m, r, about=np.zeros(3)):
    """The definition, one particle at a time (independent of the vectorised code)."""
    I = np.zeros((3, 3))
    for mk, rk in zip(m, r):
        d = rk - about
        I += mk * (d @ d * np.eye(3) - np.outer(d, d))
    return I


seeds = st.integers(min_value=0, max_value=2**32 - 1)


# ---------------------------------------------------------------- point masses
def test_point_mass_inertia_matches_definition_and_batches():
    rng = np.random.default_rng(0)
    m = rng.uniform(0.1, 1, size=(4, 5))
    r = rng.normal(size=(4, 5, 3))
    I = point_mass_inertia(m, r)
    assert I.shape == (4, 3, 3)
    for k in range(4):
        np.testing.assert_allclose(I[k], direct_inertia(m[k], r[k]), rtol=1e-14, atol=1e-14)


def test_single_particle_off_diagonal_is_negated_product():
    I = point_mass_inertia([2.0], [[1.0, 2.0, 3.0]])
    assert I[0, 1] == -2.0 * 1 * 2 and I[0, 2] == -2.0 * 1 * 3 and I[1, 2] == -2.0 * 2 * 3
    assert I[0, 0] == 2.0 * (4 + 9)


def test_point_masses_value_about_com():
    rng = np.random.default_rng(1)
    m, r = random_point_cloud(rng)
    p = inertia.point_masses(m, r)
    com = (m @ r) / m.sum()
    np.testing.assert_allclose(p.com, com, rtol=1e-14)
    np.testing.assert_allclose(p.inertia_com, direct_inertia(m, r, com), rtol=1e-13, atol=1e-13)
    assert p.mass == pytest.approx(m.sum(), rel=1e-15)


def test_point_masses_bad_input_messages():
    with pytest.raises(InputError, match=r"positions must have shape \(\.\.\., 3\), got \(2, 2\)"):
        inertia.point_masses([1, 1], [[0, 0], [1, 1]])
    with pytest.raises(InputError, match="point mass 1 is negative"):
        inertia.point_masses([1, -1, 1], np.eye(3))
    with pytest.raises(InputError, match="non-finite"):
        inertia.point_masses([1, 1, 1], [[0, 0, np.nan], [1, 0, 0], [0, 1, 0]])
    # two points: zero moment about the joining line -> not positive definite
    with pytest.raises(InvalidInertiaError, match="not positive definite"):
        inertia.point_masses([1, 1], [[0, 0, 0], [1, 0, 0]])
    # ... unless asked to accept degenerate values
    rod = inertia.point_masses([1, 1], [[0, 0, 0], [1, 0, 0]], validate=False)
    assert rod.inertia_com[1, 1] == pytest.approx(0.5)


# ---------------------------------------------------------------- parallel axis, rotation, lines
@settings(max_examples=40, deadline=None)
@given(seeds)
def test_parallel_axis_both_ways_match_direct_sums(seed):
    rng = np.random.default_rng(seed)
    m, r = random_point_cloud(rng)
    p = inertia.point_masses(m, r)
    P = rng.normal(size=3) * 3
    np.testing.assert_allclose(p.about(P), direct_inertia(m, r, P), rtol=1e-11, atol=1e-11)
    back = inertia.MassProperties.from_inertia_about(p.mass, p.com, direct_inertia(m, r, P), P)
    np.testing.assert_allclose(back.inertia_com, p.inertia_com, rtol=1e-10, atol=1e-10)


@settings(max_examples=40, deadline=None)
@given(seeds)
def test_rotating_a_body_gives_R_I_RT(seed):
    rng = np.random.default_rng(seed)
    m, r = random_point_cloud(rng)
    R = random_rotation(rng)
    t = rng.normal(size=3)
    p = inertia.point_masses(m, r)
    moved = inertia.point_masses(m, r @ R.T + t)  # truth: recompute from moved particles
    q = p.transformed(R, t)
    np.testing.assert_allclose(q.com, moved.com, atol=1e-12)
    np.testing.assert_allclose(q.inertia_com, R @ p.inertia_com @ R.T, atol=1e-12)
    np.testing.assert_allclose(q.inertia_com, moved.inertia_com, atol=1e-11)
    # translating alone leaves the central tensor unchanged
    np.testing.assert_array_equal(p.translated(t).inertia_com, p.inertia_com)


def test_expressed_in_another_frame_keeps_the_physics():
    rng = np.random.default_rng(3)
    m, r = random_point_cloud(rng)
    body = inertia.point_masses(m, r, frame="model")
    R_WM, p_WM = random_rotation(rng), np.array([1.0, -2.0, 0.5])
    world = body.expressed_in("world", R_WM, p_WM)
    assert world.frame == "world"
    # kinetic energy 1/2 w.I w of a rotation is frame-independent
    w_M = rng.normal(size=3)
    assert w_M @ body.inertia_com @ w_M == pytest.approx((R_WM @ w_M) @ world.inertia_com @ (R_WM @ w_M), rel=1e-12)
    np.testing.assert_allclose(world.com, R_WM @ body.com + p_WM, atol=1e-14)


def test_moment_about_line_is_DT_I_D_plus_offset():
    rng = np.random.default_rng(4)
    m, r = random_point_cloud(rng)
    p = inertia.point_masses(m, r)
    D = rng.normal(size=3)
    P = rng.normal(size=3)
    u = D / np.linalg.norm(D)
    # truth: sum of m * squared distance of each particle to the line
    dist2 = [np.sum((x - P - ((x - P) @ u) * u) ** 2) for x in r]
    assert p.moment_about_axis(D, P) == pytest.approx(float(m @ dist2), rel=1e-12)
    assert p.moment_about_axis(D) == pytest.approx(u @ p.inertia_com @ u, rel=1e-14)
    with pytest.raises(InputError, match="non-zero"):
        p.moment_about_axis([0, 0, 0])


def test_rotation_must_be_proper():
    p = inertia.point_masses(*random_point_cloud(np.random.default_rng(5)))
    with pytest.raises(InputError, match="reflection"):
        p.rotated(np.diag([1.0, 1.0, -1.0]))
    with pytest.raises(InputError, match="not orthonormal"):
        p.rotated(np.diag([1.0, 2.0, 1.0]))


def test_rotate_inertia_batched():
    rng = np.random.default_rng(6)
    Rs = np.stack([random_rotation(rng) for _ in range(5)])
    I = np.diag([1.0, 2.0, 3.0])
    out = inertia.massprops.rotate_inertia(I, Rs)
    assert out.shape == (5, 3, 3)
    np.testing.assert_allclose(out[2], Rs[2] @ I @ Rs[2].T, atol=1e-15)


# ---------------------------------------------------------------- product conventions
def test_product_conventions_round_trip_and_sign():
    I = inertia.massprops.inertia_from_elements(2.0, 3.0, 4.0, 0.1, -0.2, 0.3, convention="tensor")
    assert I[0, 1] == 0.1 and I[0, 2] == -0.2 and I[1, 2] == 0.3
    J = inertia.massprops.inertia_from_elements(2.0, 3.0, 4.0, 0.1, -0.2, 0.3, convention="cad")
    assert J[0, 1] == -0.1 and J[0, 2] == 0.2 and J[1, 2] == -0.3
    e = inertia.massprops.elements_from_inertia(J, convention="cad")
    assert (e["ixy"], e["ixz"], e["iyz"]) == (0.1, -0.2, 0.3)
    # a particle at (1, 1, 0): the CAD product +sum m x y is positive, the tensor entry negative
    p = inertia.MassProperties.from_inertia_about(1.0, [0, 0, 0], point_mass_inertia([1.0], [[1, 1, 0]]) + np.eye(3),
                                                  [0, 0, 0], validate=False)
    assert p.elements(convention="cad")["ixy"] == 1.0
    assert p.elements(convention="tensor")["ixy"] == -1.0
    with pytest.raises(InputError, match="'tensor'.*'cad'"):
        inertia.massprops.inertia_from_elements(1, 1, 1, convention="positive")


# ---------------------------------------------------------------- validity
def test_validity_reports_every_violation_with_numbers():
    bad = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 3.0]])
    v = inertia.check_inertia(bad, mass=-1.0)
    codes = [x.code for x in v]
    assert codes == ["non_positive_mass", "triangle_inequality"]
    assert {x.severity for x in v} == {"error"}
    assert "I1 + I2 = 2 < I3 = 3" in v[1].message
    assert v[1].values["margin"] == pytest.approx(-1.0)
    v = inertia.check_inertia(np.diag([0.0, 2.0, 2.0]))  # a rod: on the triangle boundary, not PD
    assert [x.code for x in v] == ["not_positive_definite"]
    assert "smallest 0 <=" in v[0].message
    v = inertia.check_inertia(np.diag([-1.0, 2.0, 2.0]))
    assert [x.code for x in v] == ["not_positive_definite", "triangle_inequality"]
    v = inertia.check_inertia(np.array([[1.0, 0.2, 0], [0.1, 1, 0], [0, 0, 1]]))
    assert v[0].code == "not_symmetric" and "I[0,1] = 0.2 but I[1,0] = 0.1" in v[0].message
    v = inertia.check_inertia(np.array([[np.nan, 0, 0], [0, 1, 0], [0, 0, 1]]))
    assert [x.code for x in v] == ["non_finite"]


def test_flat_plate_is_on_the_triangle_boundary_and_valid():
    # square plate in the xy-plane: I_z = I_x + I_y exactly
    a = 0.3
    m = 2.0
    plate = np.diag([m * a * a / 12, m * a * a / 12, m * a * a / 6])
    assert inertia.check_inertia(plate, m) == []
    assert not is_physical(plate * np.array([1, 1, 1 + 1e-6]), m)


def test_strict_constructor_raises_our_error_with_all_reasons():
    with pytest.raises(InvalidInertiaError) as exc:
        inertia.MassProperties(0.0, [0, 0, 0], np.diag([1.0, 1.0, 3.0]))
    assert [v.code for v in exc.value.findings] == ["non_positive_mass", "triangle_inequality"]
    assert isinstance(exc.value, InertiaError)
    with pytest.raises(InputError, match=r"inertia_com must have shape \(3, 3\), got \(3,\)"):
        inertia.MassProperties(1.0, [0, 0, 0], [1, 2, 3])


def test_value_is_immutable():
    p = inertia.point_masses(*random_point_cloud(np.random.default_rng(7)))
    with pytest.raises(ValueError):
        p.inertia_com[0, 0] = 5.0
    with pytest.raises(AttributeError):
        p.mass = 3.0


# ---------------------------------------------------------------- canonical form
@settings(max_examples=60, deadline=None)
@given(seeds)
def test_principal_axes_reconstruct_and_follow_the_sign_rule(seed):
    rng = np.random.default_rng(seed)
    m, r = random_point_cloud(rng)
    I = inertia.point_masses(m, r).inertia_com
    moments, R = principal_axes(I)
    assert np.all(np.diff(moments) >= 0)
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(R @ np.diag(moments) @ R.T, I, atol=1e-12 * np.trace(I))
    for k in (0, 1):
        col = R[:, k]
        assert col[np.argmax(np.abs(col))] > 0
    np.testing.assert_allclose(R[:, 2], np.cross(R[:, 0], R[:, 1]), atol=1e-14)


def test_principal_axes_do_not_depend_on_eigensolver_signs():
    # Whatever signs the eigensolver gives its vectors, the canonical axes are those the sign
    # rule makes of the true axes: each of the first two flipped to its largest-magnitude entry
    # positive, the third their cross product (built here from R0, whose columns are the axes).
    rng = np.random.default_rng(8)
    for _ in range(20):
        R0 = random_rotation(rng)
        e1, e2 = (R0[:, k] * np.sign(R0[np.argmax(np.abs(R0[:, k])), k]) for k in (0, 1))
        expected = np.column_stack([e1, e2, np.cross(e1, e2)])
        for signs in ([1, 1, 1], [-1, 1, 1], [1, -1, -1]):
            Rs = R0 * np.array(signs)
            _, R = principal_axes(Rs @ np.diag([1.0, 2.0, 3.0]) @ Rs.T)
            np.testing.assert_allclose(R, expected, atol=1e-14)


def _principal(I):
    return inertia.MassProperties(1.0, np.zeros(3), I, validate=False).principal()


def test_repeated_moments_are_reported_and_fixed_deterministically():
    rng = np.random.default_rng(9)
    R0 = random_rotation(rng)
    # symmetric top: I1 = I2 < I3
    I = R0 @ np.diag([1.0, 1.0, 3.0]) @ R0.T
    pf = _principal(I)
    assert pf.degenerate == ((0, 1),)
    assert np.linalg.det(pf.R_body_principal) == pytest.approx(1.0)
    assert abs(pf.R_body_principal[:, 2] @ R0[:, 2]) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(pf.R_body_principal @ np.diag(pf.moments) @ pf.R_body_principal.T, I, atol=1e-13)
    # a perturbation below the tolerance does not change the chosen axes (beyond its own size)
    pf2 = _principal(I + 1e-13 * np.diag([1, 0, 0]))
    np.testing.assert_allclose(pf2.R_body_principal, pf.R_body_principal, atol=1e-8)
    # prolate: I1 < I2 = I3
    pf = _principal(np.diag([1.0, 4.0, 4.0]))
    assert pf.degenerate == ((1, 2),)
    np.testing.assert_allclose(pf.R_body_principal, np.eye(3), atol=0)
    # sphere: identity
    pf = _principal(R0 @ np.diag([2.0, 2.0, 2.0]) @ R0.T)
    assert pf.degenerate == ((0, 1, 2),)
    np.testing.assert_array_equal(pf.R_body_principal, np.eye(3))


def test_the_principal_frame_diagonalises_the_inertia_about_the_com():
    rng = np.random.default_rng(10)
    p = inertia.point_masses(*random_point_cloud(rng))
    pf = p.principal()
    assert np.all(np.diff(pf.moments) >= 0)
    np.testing.assert_array_equal(pf.p_body_com, p.com)
    R = pf.R_body_principal
    np.testing.assert_allclose(R.T @ p.inertia_com @ R, np.diag(pf.moments), atol=1e-12 * pf.moments.sum())
    assert p.principal() is pf                                  # computed once per value


def test_principal_axes_batched_equal_looped_for_every_clause():
    rng = np.random.default_rng(11)
    R0 = random_rotation(rng)
    Is = [inertia.point_masses(*random_point_cloud(rng)).inertia_com for _ in range(3)]
    Is += [R0 @ np.diag(m) @ R0.T for m in ([1.0, 1.0, 3.0], [1.0, 4.0, 4.0], [2.0, 2.0, 2.0])]
    Is = np.stack(Is).reshape(2, 3, 3, 3)
    moments, R = principal_axes(Is)
    assert moments.shape == (2, 3, 3) and R.shape == (2, 3, 3, 3)
    for i in range(2):
        for j in range(3):
            m1, R1 = principal_axes(Is[i, j])
            np.testing.assert_allclose(moments[i, j], m1, rtol=1e-14)
            np.testing.assert_allclose(R[i, j], R1, atol=1e-13)
            np.testing.assert_allclose(R1, _principal(Is[i, j]).R_body_principal, atol=1e-13)
    # a rigid body's principal frame is the canonical one
    from inertia.dynamics import RigidBody

    body = RigidBody(np.ones((2, 3)), Is, validate=False)
    np.testing.assert_allclose(body.R_body_principal, R, atol=1e-13)


# ---------------------------------------------------------------- assemblies
@settings(max_examples=30, deadline=None)
@given(seeds)
def test_splitting_a_body_into_parts_and_assembling_gives_the_whole(seed):
    rng = np.random.default_rng(seed)
    m, r = random_point_cloud(rng, n=12)
    whole = inertia.point_masses(m, r)
    parts = []
    for idx in (slice(0, 4), slice(4, 8), slice(8, 12)):
        sub = inertia.point_masses(m[idx], r[idx])
        # give each part its own frame: pose (R, p) such that the particles are R x + p
        R = random_rotation(rng)
        p = rng.normal(size=3)
        local = inertia.point_masses(m[idx], (r[idx] - p) @ R)  # x_local = R^T (x - p)
        assert local.transformed(R, p).isclose(sub, rtol=1e-10)
        parts.append(inertia.Part(local, R, p))
    total = inertia.assemble(parts, frame="body")
    assert total.isclose(whole, rtol=1e-10)
    # the + operator is the same combination
    assert (parts[0].in_assembly() + parts[1].in_assembly() + parts[2].in_assembly())._replace(frame="body").isclose(whole, rtol=1e-10)


def test_removing_a_part_needs_explicit_request():
    rng = np.random.default_rng(12)
    m, r = random_point_cloud(rng, n=10)
    whole = inertia.point_masses(m, r)
    keep = inertia.point_masses(m[:7], r[:7])
    hole = inertia.point_masses(m[7:], r[7:])
    with pytest.raises(InputError, match="allow_negative=True"):
        inertia.assemble([inertia.Part(whole), inertia.Part(hole, subtract=True)])
    rest = inertia.assemble([inertia.Part(whole), inertia.Part(hole, subtract=True)], allow_negative=True, frame="body")
    assert rest.isclose(keep, rtol=1e-9)
    with pytest.raises(InputError, match="assembly mass must be positive"):
        inertia.assemble([inertia.Part(hole), inertia.Part(whole, subtract=True)], allow_negative=True)


def test_combining_different_frames_is_refused():
    a = inertia.point_masses(*random_point_cloud(np.random.default_rng(13)), frame="a")
    b = inertia.point_masses(*random_point_cloud(np.random.default_rng(14)), frame="b")
    with pytest.raises(InputError, match="different frames"):
        a + b


def test_with_mass_scales_inertia_and_to_dict_is_json_ready():
    import json

    p = inertia.point_masses(*random_point_cloud(np.random.default_rng(15)))
    q = p.with_mass(2 * p.mass)
    np.testing.assert_allclose(q.inertia_com, 2 * p.inertia_com)
    d = json.loads(json.dumps(q.to_dict()))
    assert d["mass"] == q.mass and len(d["R_body_principal"]) == 3
    assert np.linalg.det(np.array(d["R_body_principal"])) == pytest.approx(1.0)
    assert math.isnan(q.volume) and d["volume"] is None


def test_principal_axes_match_lapack_to_rounding_at_every_scale():
    # The compiled Jacobi eigensolver against LAPACK (numpy.linalg.eigh), an independent method:
    # moments to a few ulps of the largest, axes that rebuild the matrix, orthonormal to rounding
    # (LAPACK's own errors here reach 2e-15 relative); over 60 orders of magnitude, nearly
    # repeated moments and tiny products.
    rng = np.random.default_rng(31)
    for scale in (1e-30, 1e-6, 1.0, 1e7, 1e30):
        for gap in (1.0, 1e-3, 1e-8):
            for _ in range(20):
                R0 = random_rotation(rng)
                m = np.sort(rng.uniform(1.0, 2.0, 3))
                m[1] = m[0] + gap * (m[1] - m[0])
                I = scale * (R0 @ np.diag(m) @ R0.T)
                I = 0.5 * (I + I.T)
                moments, R = principal_axes(I)
                np.testing.assert_allclose(moments, np.linalg.eigvalsh(I), rtol=0, atol=4e-15 * scale * m[2])
                np.testing.assert_allclose(R.T @ R, np.eye(3), rtol=0, atol=4e-15)
                assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-14)
                np.testing.assert_allclose(R @ np.diag(moments) @ R.T, I, rtol=0, atol=4e-15 * scale * m[2])
    # entries near the largest double: no overflow on the way (LAPACK scales; so must we)
    I = np.array([[1.0, 1e308, 0.0], [1e308, 1.0, 0.0], [0.0, 0.0, 1.0]])
    moments, R = principal_axes(I)
    np.testing.assert_allclose(moments, np.linalg.eigvalsh(I), rtol=4e-15)
    # a diagonal matrix: its moments exactly, its axes a permutation
    moments, R = principal_axes(np.diag([3.0, 1.0, 2.0]))
    assert moments.tolist() == [1.0, 2.0, 3.0]
    assert R.tolist() == [[0.0, 0.0, 1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
