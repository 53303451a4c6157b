"""The 6-DOF transition function: layout, exact cases, frames, batching, Jacobians, errors."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.spatial.transform import Rotation

from inertia._core.rotations import quat_multiply, quat_to_matrix
from inertia.dynamics import RigidBody, jacobians, pack_input, pack_state, step, unpack_state
from inertia.dynamics.integrators import METHODS
from inertia.dynamics.state import (
    DTHETA_BODY,
    OMEGA_BODY,
    P_WORLD,
    Q_WORLD_BODY,
    V_WORLD,
    RigidState,
    perturb_state,
    state_error,
)
from inertia.errors import InputError, InvalidInertiaError
from tests.scipy_quat import as_wxyz, from_wxyz

# box 0.1 x 0.2 x 0.4 m, 1 kg: principal moments (kg m^2), ascending
BOX_MOMENTS = np.array([0.2 ** 2 + 0.4 ** 2, 0.1 ** 2 + 0.4 ** 2, 0.1 ** 2 + 0.2 ** 2])[::-1] / 12.0
ALL_METHODS = sorted(METHODS)
#: schemes that reproduce a constant torque about a principal axis from rest exactly
#: (the attitude as well as omega): see docs/transition.md
EXACT_TORQUE_METHODS = ["splitting", "midpoint"]


def random_rotation(rng) -> np.ndarray:
    return Rotation.random(random_state=rng).as_matrix()


def random_state(rng, shape=(), spin=3.0) -> np.ndarray:
    n = int(np.prod(shape, dtype=int))
    q = as_wxyz(Rotation.random(max(n, 1), random_state=rng))
    x = np.concatenate([rng.normal(size=(max(n, 1), 3)), rng.normal(size=(max(n, 1), 3)), q,
                        spin * rng.normal(size=(max(n, 1), 3))], axis=-1)
    return x.reshape(shape + (13,)) if shape else x[0]


def general_body(rng, mass=1.3):
    """A box-like body whose body frame is a random rotation of its principal frame."""
    R_BP = random_rotation(rng)
    return RigidBody(mass, R_BP @ np.diag(BOX_MOMENTS) @ R_BP.T), R_BP


def quat_same(q1, q2) -> float:
    """Distance between two attitudes as quaternions, sign-blind."""
    return min(np.abs(q1 - q2).max(), np.abs(q1 + q2).max())


# ------------------------------------------------------------------------------ layout
def test_state_layout_and_round_trips():
    x = pack_state([1, 2, 3], [4, 5, 6], [1, 0, 0, 0], [7, 8, 9])
    assert x.shape == (13,)
    assert x[P_WORLD].tolist() == [1, 2, 3] and x[V_WORLD].tolist() == [4, 5, 6]
    assert x[Q_WORLD_BODY].tolist() == [1, 0, 0, 0] and x[OMEGA_BODY].tolist() == [7, 8, 9]
    p, v, q, w = unpack_state(x)
    assert np.array_equal(np.concatenate([p, v, q, w]), x)
    s = RigidState.from_vector(x)
    assert np.array_equal(s.to_vector(), x) and s.omega_body.tolist() == [7, 8, 9]
    xb = pack_state(np.zeros((4, 3)), [0, 0, 0], [1, 0, 0, 0], [0, 0, 1])     # broadcasting
    assert xb.shape == (4, 13)
    assert pack_input([1, 2, 3], [4, 5, 6]).tolist() == [1, 2, 3, 4, 5, 6]


def test_perturb_state_is_a_right_body_frame_perturbation_and_state_error_inverts_it():
    rng = np.random.default_rng(1)
    x = random_state(rng, (5,))
    dx = 0.3 * rng.normal(size=(5, 12))
    y = perturb_state(x, dx)
    # R = R_nom Exp(dtheta): the rotation vector is applied in the body frame, on the right
    R_expected = quat_to_matrix(x[:, 6:10]) @ Rotation.from_rotvec(dx[:, DTHETA_BODY]).as_matrix()
    assert np.allclose(quat_to_matrix(y[:, 6:10]), R_expected, atol=1e-14)
    assert np.allclose(y[:, 0:6], x[:, 0:6] + dx[:, 0:6], rtol=0, atol=1e-15)
    assert np.allclose(y[:, 10:13], x[:, 10:13] + dx[:, 9:12], rtol=0, atol=1e-15)
    assert np.allclose(state_error(y, x), dx, rtol=0, atol=1e-14)


@settings(max_examples=60, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), size=st.floats(1e-9, 3.0))
def test_state_error_inverts_perturb_state_property(seed, size):
    """Round trip for perturbations from 1e-9 up to rotations of ~3 rad (below pi)."""
    rng = np.random.default_rng(seed)
    x = random_state(rng)
    dx = rng.normal(size=12)
    dx[6:9] *= min(size, 3.0) / np.linalg.norm(dx[6:9])
    dx *= np.r_[np.full(6, size), np.ones(3), np.full(3, size)]
    assert np.allclose(state_error(perturb_state(x, dx), x), dx, rtol=1e-9, atol=1e-14)


# ------------------------------------------------------------------------------ exact cases
@pytest.mark.parametrize("axis", [0, 1, 2])
@pytest.mark.parametrize("method", ALL_METHODS)
def test_constant_principal_torque_from_rest(method, axis):
    """omega = tau/I t for every method; the angle tau/(2I) t^2 exactly for splitting and midpoint."""
    body = RigidBody.from_principal_moments(2.0, BOX_MOMENTS)
    tau = np.zeros(3)
    tau[axis] = 0.01
    h, n = 0.01, 300
    t = n * h
    x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0])
    u = pack_input([0, 0, 0], tau)
    for _ in range(n):
        x = step(x, u, h, body=body, method=method)
    omega_exact = tau / BOX_MOMENTS * t
    assert np.allclose(x[OMEGA_BODY], omega_exact, rtol=1e-13, atol=0)
    angle = tau[axis] / (2 * BOX_MOMENTS[axis]) * t * t        # 2.7 to 10.8 rad
    q_exact = np.zeros(4)
    q_exact[0], q_exact[1 + axis] = np.cos(angle / 2), np.sin(angle / 2)
    err = quat_same(x[Q_WORLD_BODY], q_exact)
    if method in EXACT_TORQUE_METHODS:
        assert err < 1e-13
    else:
        assert err > 1e-13                                     # these schemes are not exact here


@pytest.mark.parametrize("method", EXACT_TORQUE_METHODS)
def test_constant_principal_torque_exact_with_unsorted_diagonal_inertia(method):
    """A diagonal inertia in non-ascending order goes through an exact permutation frame."""
    moments_B = BOX_MOMENTS[[2, 0, 1]]
    body = RigidBody(2.0, np.diag(moments_B))
    assert not body.principal_is_body
    tau = np.array([0.0, 0.0, 0.01])
    h, n = 0.01, 300
    x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0])
    for _ in range(n):
        x = step(x, pack_input([0, 0, 0], tau), h, body=body, method=method)
    t = n * h
    assert np.allclose(x[OMEGA_BODY], tau / moments_B * t, rtol=1e-13, atol=1e-18)
    angle = tau[2] / (2 * moments_B[2]) * t * t
    assert quat_same(x[Q_WORLD_BODY], [np.cos(angle / 2), 0, 0, np.sin(angle / 2)]) < 1e-13


@pytest.mark.parametrize("method", ALL_METHODS)
def test_constant_world_force_and_gravity_exact(method):
    """p = p0 + v0 t + a t^2/2 and v = v0 + a t with a = F/m + g, whatever the rotation does."""
    rng = np.random.default_rng(2)
    body, _ = general_body(rng, mass=1.7)
    F = np.array([3.0, -1.0, 2.0])
    g = np.array([0.0, 0.0, -9.81])
    p0, v0 = np.array([1.0, -2.0, 0.5]), np.array([0.3, 0.1, 4.0])
    x = pack_state(p0, v0, as_wxyz(Rotation.random(random_state=rng)), [0.5, 3.0, 0.2])
    u = pack_input(F, [0.01, -0.02, 0.005])
    h, n = 0.005, 400
    for _ in range(n):
        x = step(x, u, h, body=body, method=method, gravity=g)
    t = n * h
    a = F / 1.7 + g
    assert np.allclose(x[V_WORLD], v0 + a * t, rtol=1e-13, atol=1e-13)
    assert np.allclose(x[P_WORLD], p0 + v0 * t + 0.5 * a * t * t, rtol=1e-13, atol=1e-13)


def test_free_fall():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = pack_state([0, 0, 10.0], [1.0, 0, 0], [1, 0, 0, 0], [0, 0, 0])
    for _ in range(100):
        x = step(x, None, 0.01, body=body, gravity=[0, 0, -9.81])
    assert np.allclose(x[P_WORLD], [1.0, 0.0, 10.0 - 0.5 * 9.81], rtol=1e-14, atol=1e-14)
    assert np.allclose(x[V_WORLD], [1.0, 0.0, -9.81], rtol=1e-14, atol=1e-14)
    assert np.array_equal(x[Q_WORLD_BODY], [1, 0, 0, 0])


def test_body_frame_force_without_rotation_is_exact_and_turns_with_the_attitude():
    body = RigidBody.from_principal_moments(2.0, BOX_MOMENTS)
    R = Rotation.from_rotvec([0.3, -0.4, 1.1])
    x0 = pack_state([0, 0, 0], [0, 0, 0], as_wxyz(R), [0, 0, 0])
    F_B = np.array([1.0, 2.0, -0.5])
    x = x0
    for _ in range(50):
        x = step(x, pack_input(F_B, [0, 0, 0]), 0.02, body=body, force_frame="body", method="rk4")
    a = R.apply(F_B) / 2.0
    assert np.allclose(x[V_WORLD], a * 1.0, rtol=1e-13, atol=1e-15)
    assert np.allclose(x[P_WORLD], 0.5 * a, rtol=1e-13, atol=1e-15)


def test_body_frame_force_on_a_spinning_body_is_fourth_order_with_rk4():
    """Thrust along body x on a body spinning about its z axis at w: closed form
    v = F/(m w) (sin wt, 1 - cos wt, 0); Simpson sampling gives O(h^4)."""
    m, w = 1.5, 2.0
    body = RigidBody.from_principal_moments(m, BOX_MOMENTS)
    F = 0.9
    T = 2.0
    errs = []
    for n in (20, 40):
        x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, w])
        for _ in range(n):
            x = step(x, pack_input([F, 0, 0], [0, 0, 0]), T / n, body=body, force_frame="body", method="rk4")
        v_exact = F / (m * w) * np.array([np.sin(w * T), 1 - np.cos(w * T), 0])
        p_exact = F / (m * w) * np.array([(1 - np.cos(w * T)) / w, T - np.sin(w * T) / w, 0])
        errs.append(max(np.abs(x[V_WORLD] - v_exact).max(), np.abs(x[P_WORLD] - p_exact).max()))
    order = np.log2(errs[0] / errs[1])
    assert 3.7 < order < 4.3, (errs, order)


# ------------------------------------------------------------------------------ frames and batches
@pytest.mark.parametrize("method", ALL_METHODS)
def test_general_inertia_moves_like_its_principal_counterpart(method):
    rng = np.random.default_rng(3)
    body_B, R_BP = general_body(rng)
    body_P = RigidBody.from_principal_moments(1.3, BOX_MOMENTS)
    q_BP = as_wxyz(Rotation.from_matrix(R_BP))
    x_P = random_state(rng, spin=2.0)
    # same physical state described with the body frame B: q_WB = q_WP q_BP^-1, w_B = R_BP w_P
    x_B = x_P.copy()
    x_B[Q_WORLD_BODY] = quat_multiply(x_P[Q_WORLD_BODY], q_BP * [1, -1, -1, -1])
    x_B[OMEGA_BODY] = R_BP @ x_P[OMEGA_BODY]
    tau_P = np.array([0.002, -0.001, 0.003])
    F_P = np.array([0.5, 0.2, -0.1])
    for force_frame, F_B in (("world", F_P), ("body", R_BP @ F_P)):
        xp, xb = x_P, x_B
        for _ in range(100):
            xp = step(xp, pack_input(F_P, tau_P), 0.01, body=body_P, method=method, force_frame=force_frame)
            xb = step(xb, pack_input(F_B, R_BP @ tau_P), 0.01, body=body_B, method=method,
                      force_frame=force_frame)
        assert np.allclose(xb[:6], xp[:6], rtol=0, atol=1e-12)
        assert np.allclose(xb[OMEGA_BODY], R_BP @ xp[OMEGA_BODY], rtol=0, atol=1e-11)
        R_WB = quat_to_matrix(xb[Q_WORLD_BODY])
        assert np.allclose(R_WB @ R_BP, quat_to_matrix(xp[Q_WORLD_BODY]), rtol=0, atol=1e-12)


@pytest.mark.parametrize("method", ["rk4", "splitting", "dmv"])
def test_batched_equals_looped(method):
    rng = np.random.default_rng(4)
    x = random_state(rng, (2, 3))
    u = 0.01 * rng.normal(size=(2, 3, 6))
    body, _ = general_body(rng)
    xb = step(x, u, 0.01, body=body, method=method, gravity=[0, 0, -9.81])
    assert xb.shape == (2, 3, 13)
    for i in range(2):
        for j in range(3):
            xl = step(x[i, j], u[i, j], 0.01, body=body, method=method, gravity=[0, 0, -9.81])
            assert np.allclose(xb[i, j], xl, rtol=0, atol=1e-15)
    # a batch of different bodies against the same state
    bodies = [general_body(rng)[0] for _ in range(3)]
    batch = RigidBody(np.array([b.mass for b in bodies]), np.stack([b.inertia_com for b in bodies]))
    xs = step(x[0], u[0], 0.01, body=batch, method=method)
    for j, b in enumerate(bodies):
        assert np.allclose(xs[j], step(x[0, j], u[0, j], 0.01, body=b, method=method), rtol=0, atol=1e-14)


def test_single_state_with_shared_input_broadcasts():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.1, 1.0, 0.0])
    out = step(np.broadcast_to(x, (4, 13)), np.zeros(6), 0.01, body=body)
    assert out.shape == (4, 13) and np.allclose(out, out[0])


# ------------------------------------------------------------------------------ Jacobians
def fd_jacobians(x, u, h, eps_x=1e-6, eps_u=1e-6, **kw):
    """Independent 2-point central differences on the error-state manifold (scipy rotations)."""
    def plus(x0, dx):
        y = x0.copy()
        y[0:6] += dx[0:6]
        R = from_wxyz(x0[6:10]) * Rotation.from_rotvec(dx[6:9])
        y[6:10] = as_wxyz(R)
        y[10:13] += dx[9:12]
        return y

    def minus(y, x0):
        d = np.empty(12)
        d[0:6] = y[0:6] - x0[0:6]
        d[6:9] = (from_wxyz(x0[6:10]).inv()
                  * from_wxyz(y[6:10])).as_rotvec()
        d[9:12] = y[10:13] - x0[10:13]
        return d

    x_next = step(x, u, h, **kw)
    A = np.empty((12, 12))
    B = np.empty((12, 6))
    for k in range(12):
        e = np.zeros(12)
        e[k] = eps_x
        A[:, k] = (minus(step(plus(x, e), u, h, **kw), x_next)
                   - minus(step(plus(x, -e), u, h, **kw), x_next)) / (2 * eps_x)
    for k in range(6):
        e = np.zeros(6)
        e[k] = eps_u
        B[:, k] = (minus(step(x, u + e, h, **kw), x_next) - minus(step(x, u - e, h, **kw), x_next)) / (2 * eps_u)
    return A, B


def rel_err(J, J_ref) -> float:
    return np.abs(J - J_ref).max() / np.abs(J_ref).max()


@pytest.mark.parametrize("force_frame", ["world", "body"])
@pytest.mark.parametrize("method", ALL_METHODS)
def test_jacobians_match_independent_finite_differences(method, force_frame):
    rng = np.random.default_rng(5)
    body, _ = general_body(rng, mass=1.3)
    x = random_state(rng, spin=2.0)
    u = np.r_[rng.normal(size=3), 0.01 * rng.normal(size=3)]
    kw = dict(body=body, method=method, gravity=[0, 0, -9.81], force_frame=force_frame)
    h = 0.02
    A, B = jacobians(x, u, h, **kw)
    # scales: state steps 1e-6 (dimensionless / SI), torque step 1e-8 N m (moments ~0.01 kg m^2)
    A_fd, B_fd = fd_jacobians(x, u, h, eps_x=1e-6, eps_u=1e-6, **kw)
    _, B_fd_tau = fd_jacobians(x, u, h, eps_x=1e-6, eps_u=1e-8, **kw)
    B_fd[:, 3:] = B_fd_tau[:, 3:]
    assert rel_err(A, A_fd) < 1e-6
    assert rel_err(B[:, :3], B_fd[:, :3]) < 1e-6
    assert rel_err(B[:, 3:], B_fd[:, 3:]) < 1e-6


def test_jacobians_have_the_analytic_translational_blocks():
    rng = np.random.default_rng(6)
    body, _ = general_body(rng, mass=2.5)
    x = random_state(rng)
    h = 0.01
    A, B = jacobians(x, np.r_[1.0, 2.0, 3.0, 0.01, 0.0, 0.0], h, body=body, method="rk4", gravity=[0, 0, -9.81])
    I3 = np.eye(3)
    assert np.allclose(A[0:3, 0:3], I3, atol=1e-12) and np.allclose(A[0:3, 3:6], h * I3, atol=1e-12)
    assert np.allclose(A[3:6, 3:6], I3, atol=1e-12)
    assert np.allclose(A[0:6, 6:12], 0, atol=1e-12) and np.allclose(A[6:12, 0:6], 0, atol=1e-12)
    assert np.allclose(B[0:3, 0:3], h * h / (2 * 2.5) * I3, rtol=1e-9, atol=1e-16)
    assert np.allclose(B[3:6, 0:3], h / 2.5 * I3, rtol=1e-9, atol=1e-14)
    assert np.allclose(B[0:6, 3:6], 0, atol=1e-12) and np.allclose(B[6:12, 0:3], 0, atol=1e-12)


def test_jacobians_torque_free_attitude_block_is_the_inverse_step_rotation():
    """Torque-free: q+ = q Phi(omega), so dtheta+ = Phi^T dtheta (right perturbations)."""
    rng = np.random.default_rng(7)
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = random_state(rng, spin=3.0)
    h = 0.02
    for method in ("rk4", "splitting"):
        A, _ = jacobians(x, np.zeros(6), h, body=body, method=method)
        x1 = step(x, np.zeros(6), h, body=body, method=method)
        Phi = quat_to_matrix(x[Q_WORLD_BODY]).T @ quat_to_matrix(x1[Q_WORLD_BODY])
        assert np.allclose(A[6:9, 6:9], Phi.T, rtol=0, atol=1e-10)


def test_jacobians_at_rest():
    """From rest: dtheta+ = h domega (+ h^2/2 I^-1 dtau), domega+ = domega + h I^-1 dtau."""
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0])
    h = 0.01
    A, B = jacobians(x, np.zeros(6), h, body=body, method="splitting")
    assert np.allclose(A[6:9, 9:12], h * np.eye(3), rtol=1e-9, atol=1e-14)
    assert np.allclose(A[9:12, 9:12], np.eye(3), rtol=1e-9, atol=1e-12)
    assert np.allclose(B[9:12, 3:6], h * np.diag(1 / BOX_MOMENTS), rtol=1e-9)
    assert np.allclose(B[6:9, 3:6], h * h / 2 * np.diag(1 / BOX_MOMENTS), rtol=1e-9)


def test_jacobians_batched_equal_looped():
    rng = np.random.default_rng(8)
    body, _ = general_body(rng)
    x = random_state(rng, (3,))
    u = 0.01 * rng.normal(size=(3, 6))
    A, B = jacobians(x, u, 0.01, body=body, method="rk4")
    assert A.shape == (3, 12, 12) and B.shape == (3, 12, 6)
    for i in range(3):
        Ai, Bi = jacobians(x[i], u[i], 0.01, body=body, method="rk4")
        assert np.allclose(A[i], Ai, rtol=0, atol=1e-12) and np.allclose(B[i], Bi, rtol=0, atol=1e-12)
    bodies = RigidBody(np.ones(3), np.stack([general_body(rng)[0].inertia_com for _ in range(3)]))
    A, B = jacobians(x, u, 0.01, body=bodies, method="splitting")
    assert A.shape == (3, 12, 12)


def test_jacobians_predict_a_finite_perturbation_to_second_order():
    rng = np.random.default_rng(9)
    body, _ = general_body(rng)
    x = random_state(rng, spin=2.0)
    u = np.r_[1.0, 0.0, 0.0, 0.002, 0.0, -0.001]
    A, B = jacobians(x, u, 0.01, body=body)
    x1 = step(x, u, 0.01, body=body)
    for s in (1e-3, 1e-4):
        dx = s * rng.normal(size=12)
        du = s * np.r_[rng.normal(size=3), 0.01 * rng.normal(size=3)]
        err = state_error(step(perturb_state(x, dx), u + du, 0.01, body=body), x1) - (A @ dx + B @ du)
        assert np.abs(err).max() < 50 * s * s


# ------------------------------------------------------------------------------ input errors
def test_errors_name_the_argument_and_value():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0])
    with pytest.raises(InputError, match=r"^x must have shape \(\.\.\., 13\), got \(12,\)$"):
        step(x[:12], None, 0.01, body=body)
    with pytest.raises(InputError, match=r"^u must have shape \(\.\.\., 6\), got \(3,\)$"):
        step(x, np.zeros(3), 0.01, body=body)
    with pytest.raises(InputError, match=r"^h must be a finite non-zero time step in s \(negative integrates "
                                         r"backwards\), got 0\.0$"):
        step(x, None, 0.0, body=body)
    bad = x.copy()
    bad[6] = 1.1
    with pytest.raises(InputError,
                       match=r"^x\[\.\.\., 6:10\] \(q_world_body\) must be a unit quaternion.*got \|q\| = 1\.1: \[1\.1, "):
        step(bad, None, 0.01, body=body)
    with pytest.raises(InputError, match=r"^method must be one of \[.*'rk4'.*\] or a step function, got 'rk5'$"):
        step(x, None, 0.01, body=body, method="rk5")
    with pytest.raises(InputError, match=r"^force_frame must be 'world' or 'body', got 'inertial'$"):
        step(x, None, 0.01, body=body, force_frame="inertial")
    with pytest.raises(InputError, match=r"^body must be a RigidBody \(mass, inertia_com\), got dict$"):
        step(x, None, 0.01, body={"mass": 1.0})
    x_nan = x.copy()
    x_nan[0] = np.nan
    with pytest.raises(InputError, match=r"^x holds a non-finite value \(nan\) at index \(0,\)$"):
        step(x_nan, None, 0.01, body=body)
    with pytest.raises(InputError, match=r"^batch shapes do not broadcast"):
        step(np.broadcast_to(x, (3, 13)), np.zeros((2, 6)), 0.01, body=body)


def test_a_nearly_unit_quaternion_is_renormalised():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x = pack_state([0, 0, 0], [0, 0, 0], [1 + 5e-7, 0, 0, 0], [0, 0, 1.0])
    x1 = step(x, None, 0.01, body=body)
    assert abs(np.linalg.norm(x1[Q_WORLD_BODY]) - 1) < 1e-15


def test_body_validation():
    with pytest.raises(InvalidInertiaError, match=r"^inertia_com is not physical: inertia fails the triangle"):
        RigidBody(1.0, np.diag([1.0, 1.0, 3.0]))
    with pytest.raises(InputError, match=r"^mass must be positive, got -1\.0 kg$"):
        RigidBody(-1.0, np.diag(BOX_MOMENTS))
    with pytest.raises(InputError, match=r"^inertia_com must have shape \(\.\.\., 3, 3\), got \(3,\)$"):
        RigidBody(1.0, BOX_MOMENTS)
    RigidBody(1.0, np.diag([1.0, 1.0, 3.0]), validate=False)       # opt-out


def test_body_from_mass_properties():
    from inertia.massprops.properties import MassProperties
    rng = np.random.default_rng(10)
    R = random_rotation(rng)
    props = MassProperties(2.0, [0.1, 0.0, 0.0], R @ np.diag(BOX_MOMENTS) @ R.T)
    body = RigidBody.from_mass_properties(props)
    assert body.mass == 2.0 and np.allclose(body.moments, BOX_MOMENTS, rtol=1e-12)
    R_BP = body.R_body_principal
    assert np.isclose(np.linalg.det(R_BP), 1.0)
    assert np.allclose(R_BP @ np.diag(body.moments) @ R_BP.T, props.inertia_com, atol=1e-15)
