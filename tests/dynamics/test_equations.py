"""Euler's law in the body and world frames, quaternion kinematics, diagnostics.

Reference values: ../shared/notes/free-rigid-body.md §7 (TC1, TC3), computed there from
the exact elliptic solution and checked against DOP853.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from inertia._core.rotations import quat_from_rotvec, quat_multiply, quat_to_matrix
from inertia.dynamics import diagnostics, integrators
from inertia.dynamics.diagnostics import (
    angular_momentum_norm,
    angular_momentum_world,
    attitude_error,
    kinetic_energy,
    quat_norm,
)
from inertia.dynamics.equations import (
    angular_acceleration_body,
    angular_acceleration_principal,
    euler_residual,
    inertia_world,
    omega_world_from_momentum,
    omega_world_principal,
    quat_rate,
    quat_rate_world,
    state_rate_body,
    state_rate_world,
)
from inertia.errors import InputError, InvalidInertiaError


def random_quat(rng, shape=()):
    q = rng.normal(size=shape + (4,))
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def random_spd_inertia(rng):
    """A physical inertia (triangle inequality holds) in a random orientation, and its parts."""
    moments = np.sort(rng.uniform(0.5, 2.0, size=3))
    moments[2] = min(moments[2], moments[0] + moments[1])
    R = quat_to_matrix(random_quat(rng))
    return R @ np.diag(moments) @ R.T, moments, R


# ---------------------------------------------------------------------------- body frame
def test_principal_path_matches_general_matrix_path():
    rng = np.random.default_rng(1)
    w = rng.normal(size=(20, 3))
    I = rng.uniform(0.3, 3.0, size=(20, 3))
    tau = rng.normal(size=(20, 3))
    a_fast = angular_acceleration_principal(w, I, tau)
    a_gen = angular_acceleration_body(w, I[..., :, None] * np.eye(3), tau)
    np.testing.assert_allclose(a_fast, a_gen, rtol=1e-13, atol=1e-13)
    # componentwise form I1 w1' = (I2 - I3) w2 w3 + tau1
    np.testing.assert_allclose(a_fast[:, 0], ((I[:, 1] - I[:, 2]) * w[:, 1] * w[:, 2] + tau[:, 0]) / I[:, 0],
                               rtol=1e-13)


def test_general_inertia_is_covariant_under_change_of_body_axes():
    # Re-expressing the body frame (I_B = R I_P R^T, w_B = R w_P, tau_B = R tau_P) rotates the result.
    rng = np.random.default_rng(2)
    for _ in range(10):
        I_B, moments, R_BP = random_spd_inertia(rng)
        w_P, tau_P = rng.normal(size=3), rng.normal(size=3)
        a_P = angular_acceleration_principal(w_P, moments, tau_P)
        a_B = angular_acceleration_body(R_BP @ w_P, I_B, R_BP @ tau_P)
        np.testing.assert_allclose(a_B, R_BP @ a_P, rtol=1e-12, atol=1e-12)
        assert np.abs(euler_residual(R_BP @ w_P, a_B, I_B, R_BP @ tau_P)).max() < 1e-12


def test_euler_residual_zero_for_computed_acceleration_and_nonzero_otherwise():
    I = np.diag([1.0, 2.0, 3.0])
    w = np.array([0.3, -0.2, 0.5])
    a = angular_acceleration_body(w, I, [0.1, 0.0, 0.0])
    np.testing.assert_allclose(euler_residual(w, a, I, [0.1, 0.0, 0.0]), 0.0, atol=1e-15)
    assert np.abs(euler_residual(w, a, I)).max() == pytest.approx(0.1)


def test_linear_stability_eigenvalues_tc6():
    # Jacobian of w' = f(w) at w = e_j for I = (1, 2, 3): {0, ±0.57735i}, {0, ±0.57735}, {0, ±1i}.
    I = np.array([1.0, 2.0, 3.0])
    expected = [(0.5773502691896, True), (0.5773502691896, False), (1.0, True)]
    for j, (rate, oscillatory) in enumerate(expected):
        w = np.eye(3)[j]
        eps = 1e-6
        J = np.stack([(angular_acceleration_principal(w + eps * e, I) - angular_acceleration_principal(w - eps * e, I))
                      / (2 * eps) for e in np.eye(3)], axis=1)
        ev = np.linalg.eigvals(J)
        ev = ev[np.argsort(np.abs(ev))]
        assert abs(ev[0]) < 1e-9
        if oscillatory:
            np.testing.assert_allclose(np.sort(ev[1:].imag), [-rate, rate], atol=1e-9)
            np.testing.assert_allclose(ev[1:].real, 0.0, atol=1e-9)
        else:
            np.testing.assert_allclose(np.sort(ev[1:].real), [-rate, rate], atol=1e-9)


# ---------------------------------------------------------------------------- kinematics
def test_quat_rate_body_and_world_forms_agree():
    rng = np.random.default_rng(3)
    q = random_quat(rng, (30,))
    w_B = rng.normal(size=(30, 3))
    w_W = np.einsum("...ij,...j->...i", quat_to_matrix(q), w_B)
    np.testing.assert_allclose(quat_rate(q, w_B), quat_rate_world(q, w_W), atol=1e-15)


def test_quat_rate_is_the_derivative_of_q_exp():
    # d/dt [q (x) exp(t w / 2)] at t = 0 is 1/2 q (x) (0, w), and dR/dt = R [w]x.
    rng = np.random.default_rng(4)
    q, w = random_quat(rng), rng.normal(size=3)
    eps = 1e-6
    fd = (quat_multiply(q, quat_from_rotvec(eps * w)) - quat_multiply(q, quat_from_rotvec(-eps * w))) / (2 * eps)
    np.testing.assert_allclose(quat_rate(q, w), fd, atol=1e-9)
    dq = quat_rate(q, w)
    dR = (quat_to_matrix(q + eps * dq) - quat_to_matrix(q - eps * dq)) / (2 * eps)
    wx = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    np.testing.assert_allclose(dR, quat_to_matrix(q) @ wx, atol=1e-8)


# ---------------------------------------------------------------------------- world frame
def test_world_inertia_and_world_omega_paths_agree():
    rng = np.random.default_rng(5)
    I_B, moments, R_BP = random_spd_inertia(rng)
    R_WB = quat_to_matrix(random_quat(rng, (8,)))
    L_W = rng.normal(size=(8, 3))
    I_W = inertia_world(R_WB, I_B)
    np.testing.assert_allclose(I_W, np.swapaxes(I_W, -1, -2), atol=1e-14)
    np.testing.assert_allclose(np.linalg.eigvalsh(I_W), np.broadcast_to(moments, (8, 3)), rtol=1e-12)
    w_lit = omega_world_from_momentum(L_W, R_WB, I_B)
    np.testing.assert_allclose(np.einsum("...ij,...j->...i", I_W, w_lit), L_W, atol=1e-12)
    # principal path with the principal frame P: R_WP = R_WB R_BP
    w_fast = omega_world_principal(L_W, R_WB @ R_BP, moments)
    np.testing.assert_allclose(w_fast, w_lit, rtol=1e-11, atol=1e-12)


def test_body_law_implies_world_law_pointwise():
    # d/dt (R I w) = R ([w]x I w + I w') = R tau_B  for the body-frame acceleration.
    rng = np.random.default_rng(6)
    for _ in range(5):
        I_B, _, _ = random_spd_inertia(rng)
        q, w, tau_B = random_quat(rng), rng.normal(size=3), rng.normal(size=3)
        dq, dw = state_rate_body(q, w, I_B, tau_B)
        R = quat_to_matrix(q)
        dR = 2 * (quat_to_matrix(q + 1e-6 * dq) - quat_to_matrix(q - 1e-6 * dq)) / (2 * 2e-6)
        dL = dR @ I_B @ w + R @ I_B @ dw
        np.testing.assert_allclose(dL, R @ tau_B, atol=1e-8)


def _integrate_body(q0, w0, inertia, tau_B, t_eval):
    def rhs(t, y):
        dq, dw = state_rate_body(y[:4], y[4:], inertia, tau_B)
        return np.concatenate([dq, dw])
    sol = solve_ivp(rhs, (0, t_eval[-1]), np.concatenate([q0, w0]), method="DOP853", rtol=1e-13, atol=1e-13,
                    t_eval=t_eval)
    q = sol.y[:4].T
    return q / np.linalg.norm(q, axis=-1, keepdims=True), sol.y[4:].T


def _integrate_world(q0, w0, I_B, tau_B, t_eval):
    R0 = quat_to_matrix(q0)
    L0 = R0 @ I_B @ w0

    def rhs(t, y):
        q = y[:4] / np.linalg.norm(y[:4])
        tau_W = None if tau_B is None else quat_to_matrix(q) @ tau_B
        dq, dL = state_rate_world(y[:4], y[4:], I_B, tau_W)
        return np.concatenate([dq, dL])
    sol = solve_ivp(rhs, (0, t_eval[-1]), np.concatenate([q0, L0]), method="DOP853", rtol=1e-13, atol=1e-13,
                    t_eval=t_eval)
    q = sol.y[:4].T
    q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    R = quat_to_matrix(q)
    # w_B = I_B^-1 R^T L_W
    w = np.linalg.solve(I_B, np.einsum("nji,nj->ni", R, sol.y[4:].T).T).T
    return q, w


@pytest.mark.parametrize("with_torque", [False, True])
def test_body_frame_and_world_frame_give_the_same_trajectory(with_torque):
    rng = np.random.default_rng(7)
    I_B, _, _ = random_spd_inertia(rng)          # non-diagonal body inertia
    q0, w0 = random_quat(rng), np.array([0.7, -1.1, 0.4])
    tau_B = np.array([0.05, -0.02, 0.03]) if with_torque else None
    t = np.linspace(0, 8, 5)
    qb, wb = _integrate_body(q0, w0, I_B, tau_B, t)
    qw, ww = _integrate_world(q0, w0, I_B, tau_B, t)
    assert attitude_error(qb, qw).max() < 1e-10
    np.testing.assert_allclose(wb, ww, atol=1e-10)


def test_world_frame_principal_path_trajectory():
    # state_rate_world with principal moments (no I_W inverse) = the matrix path.
    rng = np.random.default_rng(8)
    moments = np.array([2 / 3, 1.0, 2.0])
    q, L = random_quat(rng), rng.normal(size=3)
    a = state_rate_world(q, L, moments)
    b = state_rate_world(q, L, np.diag(moments))
    np.testing.assert_allclose(a[0], b[0], atol=1e-14)
    np.testing.assert_allclose(a[1], 0.0)


# ---------------------------------------------------------------------------- reference values
TC3_I = np.array([2 / 3, 1.0, 2.0])
TC3_W0 = np.array([np.sin(1.1), 0.0, np.cos(1.1)]) / TC3_I


def test_tc3_initial_condition_and_exact_values():
    np.testing.assert_allclose(TC3_W0, [1.336811040092, 0.0, 0.226798060713], atol=1e-12)
    _, w = _integrate_body(np.array([1.0, 0, 0, 0]), TC3_W0, TC3_I, None, np.array([0.0, 1.0, 5.0, 10.0]))
    np.testing.assert_allclose(w[1], [1.276977909105, 0.372846321121, 0.184555040425], atol=2e-12)
    np.testing.assert_allclose(w[2], [1.327784854342, 0.146214872301, -0.220828013922], atol=2e-12)
    np.testing.assert_allclose(w[3], [1.302673751492, -0.283007426813, 0.203533068294], atol=2e-12)


def test_tc1_dzhanibekov_omega_and_attitude():
    # I = (1, 2, 3), w0 = (0.01, 1, 0), R0 = identity (note §7, TC1): checks the kinematics convention.
    I = np.array([1.0, 2.0, 3.0])
    T = 41.509219529338
    q, w = _integrate_body(np.array([1.0, 0, 0, 0]), np.array([0.01, 1.0, 0.0]), I, None,
                           np.array([0.0, 1.0, 5.0, 10.0, T / 2]))
    np.testing.assert_allclose(w[1], [0.011713459529, 0.99998139726, -0.003521606363], atol=1e-10)
    np.testing.assert_allclose(w[2], [0.089780601692, 0.996011768786, -0.051512317104], atol=1e-10)
    np.testing.assert_allclose(w[3], [0.976782616339, 0.214466128837, -0.563916152036], atol=1e-10)
    np.testing.assert_allclose(w[4], [0.01, -1.0, 0.0], atol=1e-9)
    R5 = np.array([[0.282050200242, -0.081848833532, -0.955901905528],
                   [0.043480049845, 0.996421012953, -0.072488966128],
                   [0.958413882312, -0.021117135087, 0.284599537591]])
    np.testing.assert_allclose(quat_to_matrix(q[2]), R5, atol=1e-10)


# ---------------------------------------------------------------------------- diagnostics
def test_diagnostics_values_and_batch_shapes():
    I = np.array([1.0, 2.0, 3.0])
    w = np.array([1.0, 0.0, 2.0])
    assert kinetic_energy(w, I) == pytest.approx(6.5)
    assert kinetic_energy(w, inertia_com=np.diag(I)) == pytest.approx(6.5)
    assert angular_momentum_norm(w, I) == pytest.approx(np.sqrt(37.0))
    q = quat_from_rotvec([0.0, 0.0, np.pi / 2])
    np.testing.assert_allclose(angular_momentum_world(q, w, I), [0.0, 1.0, 6.0], atol=1e-15)
    assert kinetic_energy(np.ones((7, 2, 3)), I).shape == (7, 2)
    assert angular_momentum_world(np.tile([1.0, 0, 0, 0], (7, 1)), np.ones((7, 3)), I).shape == (7, 3)
    assert quat_norm(np.full((3, 4), 0.5)).tolist() == [1.0, 1.0, 1.0]


def test_attitude_error_small_angles_and_sign():
    q = quat_from_rotvec([0.3, -0.2, 0.1])
    for angle in (1e-12, 1e-6, 0.5, 3.0):
        p = quat_multiply(q, quat_from_rotvec([angle, 0.0, 0.0]))
        assert attitude_error(q, p) == pytest.approx(angle, rel=1e-9)
        assert attitude_error(q, -p) == pytest.approx(angle, rel=1e-9)


def test_diagnostics_pass_nonfinite_through():
    assert np.isinf(kinetic_energy([np.inf, 0.0, 0.0], [1.0, 1.0, 1.0]))


def test_trajectory_invariants_relative_errors():
    traj = integrators.integrate([1, 0, 0, 0], TC3_W0, TC3_I, 0.1, 100, method="dmv", validate=False)
    inv = diagnostics.trajectory_invariants(traj, TC3_I)
    assert inv.energy.shape == (101,) and inv.L_world.shape == (101, 3)
    errs = inv.max_relative_errors()
    assert set(errs) == {"energy", "momentum_norm", "L_world", "quat_norm"}
    assert all(float(v) < 1e-14 for v in errs.values())
    # a body at rest: absolute deviations, no division by zero
    rest = integrators.integrate([1, 0, 0, 0], [0.0, 0.0, 0.0], TC3_I, 0.1, 3, validate=False)
    assert all(float(v) == 0.0 for v in diagnostics.trajectory_invariants(rest, TC3_I).max_relative_errors().values())


# ---------------------------------------------------------------------------- input errors
def test_input_errors_name_the_argument():
    with pytest.raises(InvalidInertiaError, match=r"moments = \(1, -1, 2\) kg m\^2 are not the principal moments of a "
                                                  r"physical body: inertia is not positive definite"):
        angular_acceleration_principal([1, 2, 3], [1.0, -1.0, 2.0])
    with pytest.raises(InputError, match=r"omega_body must have shape \(\.\.\., 3\), got \(2,\)"):
        angular_acceleration_principal([1, 2], [1.0, 1.0, 2.0])
    with pytest.raises(InputError, match=r"inertia_com must be symmetric, got max \|I - I\^T\| = 1"):
        angular_acceleration_body([1, 2, 3], [[1, 1, 0], [0, 1, 0], [0, 0, 1]])
    with pytest.raises(InputError, match="torque_body holds a non-finite value"):
        angular_acceleration_principal([1, 2, 3], [1, 2, 3], [np.nan, 0, 0])
    with pytest.raises(InputError, match="give exactly one of moments= .* got both"):
        kinetic_energy([1, 2, 3], [1, 2, 3], inertia_com=np.eye(3))
    with pytest.raises(InputError, match=r"q_world_body must have shape \(\.\.\., 4\)"):
        quat_rate([1, 0, 0], [1, 2, 3])
