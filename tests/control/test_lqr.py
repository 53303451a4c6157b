"""Discrete LQR (scipy's solver, the batched doubling against it) and the spin-hold design: its
set-aside directions, its frame covariance and its closed loop."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import solve_discrete_are
from scipy.spatial.transform import Rotation

from inertia.control.lqr import design_spin_hold, dlqr
from inertia.dynamics import RigidBody
from inertia.dynamics.gyrostat import Gyrostat, gyrostat_jacobians
from inertia.errors import InputError


def random_systems(rng, k, n=5, m=3):
    A = np.eye(n) + 0.3 * rng.normal(size=(k, n, n))
    B = rng.normal(size=(k, n, m))
    M = rng.normal(size=(k, n, n))
    return A, B, M @ np.swapaxes(M, 1, 2) + np.eye(n), np.eye(m) * rng.uniform(0.1, 10.0, (k, 1, 1))


def test_dlqr_of_one_system_is_scipys_and_a_batch_by_doubling_agrees():
    rng = np.random.default_rng(0)
    A, B, Q, R = random_systems(rng, 40)
    K, P = dlqr(A, B, Q, R)
    for k in range(40):
        Ps = solve_discrete_are(A[k], B[k], Q[k], R[k])
        assert np.abs(P[k] - Ps).max() < 1e-9 * np.abs(Ps).max()
        K1, P1 = dlqr(A[k], B[k], Q[k], R[k])
        assert np.array_equal(P1, Ps) and np.abs(K[k] - K1).max() < 1e-9 * np.abs(K1).max()
        assert np.abs(np.linalg.eigvals(A[k] - B[k] @ K[k])).max() < 1
    # each system of a batch stops on its own: the same bits in another batch
    assert np.array_equal(dlqr(A[7:9], B[7:9], Q[7:9], R[7:9])[1], P[7:9])


def test_dlqr_refuses_an_unstabilisable_system():
    A = np.diag([1.2, 0.5])
    B = np.array([[0.0], [1.0]])                      # the unstable mode is not reached
    with pytest.raises(InputError, match=r"^no stabilising LQR solution"):
        dlqr(A, B, np.eye(2), np.eye(1))
    with pytest.raises(InputError, match=r"^no stabilising LQR solution for system \(1,\)"):
        dlqr(np.stack([np.diag([0.5, 0.5]), A]), B, np.eye(2), np.eye(1))


def basilisk(body_inertia=np.diag([900.0, 800.0, 600.0]), axes=np.eye(3)):
    return Gyrostat(RigidBody(750.0, body_inertia), axes, max_torque=[0.2] * 3, max_momentum=[50.0] * 3)


def test_the_set_aside_directions_are_those_the_wheels_cannot_move():
    """c = [L^T I, L^T G] is kept by the step and untouched by the torques (c A = c, c B = 0): the
    design's momentum direction; and the gain ignores the spin phase and reads a momentum error as
    a spin-rate error (zero gain on the spin-rate error)."""
    g = basilisk()
    s = np.array([0.0, 1.0, 0.0])
    x = np.r_[np.zeros(6), 1.0, 0, 0, 0, 0.1 * s, np.zeros(3)]
    A, B = gyrostat_jacobians(x, None, 0.1, gyrostat=g)
    L = g.body.inertia_com @ (0.1 * s)
    c = np.r_[g.body.inertia_com @ L, L] / np.linalg.norm(L)
    assert np.abs(c @ A[9:, 9:] - c).max() < 1e-12 * np.abs(c).max()
    assert np.abs(c @ B[9:, 6:]).max() < 1e-12 * np.abs(c).max()
    hold = design_spin_hold(g, s, 0.1, 0.1)
    assert np.abs(hold.gain @ np.r_[s, 0, 0, 0]).max() < 1e-12 * np.abs(hold.gain).max()
    assert hold.open_loop_radius > 1.0 > hold.closed_loop_radius


def test_the_design_turns_with_the_body():
    """Body, wheels and spin axis turned by R: the gain's rate columns turn with them."""
    R = Rotation.from_rotvec([0.3, -0.5, 0.2]).as_matrix()
    s = np.array([0.0, 1.0, 0.0])
    a = design_spin_hold(basilisk(), s, 0.1, 0.1)
    b = design_spin_hold(basilisk(R @ np.diag([900.0, 800.0, 600.0]) @ R.T, np.eye(3) @ R.T), R @ s, 0.1, 0.1)
    assert np.abs(b.gain[:, :3] @ R - a.gain[:, :3]).max() < 1e-8 * np.abs(a.gain).max()
    assert np.abs(b.gain[:, 3:] - a.gain[:, 3:]).max() < 1e-8 * np.abs(a.gain).max()


def test_a_batch_of_models_gives_each_its_own_design():
    rng = np.random.default_rng(1)
    I = np.diag([900.0, 800.0, 600.0]) * rng.uniform(0.9, 1.1, (6, 3))[:, None, :]
    batch = design_spin_hold(basilisk(I), [0, 1, 0], 0.1, 0.1)
    for k in (0, 5):
        one = design_spin_hold(basilisk(I[k]), [0, 1, 0], 0.1, 0.1)
        assert np.abs(batch.gain[k] - one.gain).max() < 1e-9 * np.abs(one.gain).max()
    assert batch.gain.shape == (6, 3, 6) and np.all(batch.closed_loop_radius < 1)


def test_design_input_errors():
    g = basilisk()
    with pytest.raises(InputError, match=r"^spin_rate must be finite and non-zero, got 0$"):
        design_spin_hold(g, [0, 1, 0], 0, 0.1)
    with pytest.raises(InputError, match=r"^a spin hold needs at least one wheel$"):
        design_spin_hold(Gyrostat(g.body, np.zeros((0, 3))), [0, 1, 0], 0.1, 0.1)
    with pytest.raises(InputError, match=r"^the wheels cannot hold a momentum of 5 N m s along the spin axis"):
        design_spin_hold(Gyrostat(g.body, [[1.0, 0, 0]]), [0, 1, 0], 0.1, 0.1, h_bias=5.0)
