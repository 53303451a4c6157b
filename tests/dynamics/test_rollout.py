"""Rollouts: against closed forms (the exact elliptic solution, the held-force translation), DOP853,
conservation laws and a loop of single steps; determinism over runs, processes, threads and batches."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.spatial.transform import Rotation

from inertia.dynamics import RigidBody, exact_solution, pack_state, step
from inertia.dynamics.integrators import METHODS, step_dmv
from inertia.dynamics.rollouts import rollout
from inertia.dynamics.state import OMEGA_BODY, P_WORLD, Q_WORLD_BODY, V_WORLD
from inertia.errors import InputError, IntegrationError
from tests.scipy_quat import as_wxyz, from_wxyz

BOX_MOMENTS = np.array([0.1 ** 2 + 0.2 ** 2, 0.1 ** 2 + 0.4 ** 2, 0.2 ** 2 + 0.4 ** 2]) / 12.0  # kg m^2, 1 kg
NAMES = list(METHODS)
G = np.array([0.0, 0.0, -9.81])


def random_states(rng, n, spin=3.0):
    q = as_wxyz(Rotation.random(n, random_state=rng))
    return np.concatenate([rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), q, spin * rng.normal(size=(n, 3))], -1)


def general_body(rng, mass=1.0):
    R = Rotation.random(random_state=rng).as_matrix()
    return RigidBody(mass, R @ np.diag(BOX_MOMENTS) @ R.T)


def random_bodies(rng, n):
    return RigidBody(rng.uniform(0.5, 2.0, n), np.stack([general_body(rng).inertia_com for _ in range(n)]))


# ------------------------------------------------------------------------------ independent truth
@pytest.mark.parametrize("method, tol", [("rk4", 1e-9), ("dmv4", 1e-8), ("splitting", 2e-5), ("midpoint", 2e-5)])
def test_torque_free_rollout_follows_the_exact_elliptic_solution(method, tol):
    """A general (non-principal) body: rotation against exact_solution in the principal frame."""
    rng = np.random.default_rng(7)
    body = general_body(rng)
    x0 = random_states(rng, 1, spin=2.0)[0]
    traj = rollout(x0, None, 1e-3, 2000, body=body, method=method, save_every=500)
    R_BP = np.array(body.R_body_principal)  # writable: scipy 1.11's from_matrix refuses read-only arrays
    q_WP0 = (from_wxyz(x0[Q_WORLD_BODY]) * Rotation.from_matrix(R_BP))
    q_ex, w_ex = exact_solution(body.moments, R_BP.T @ x0[OMEGA_BODY], np.arange(5) * 0.5, as_wxyz(q_WP0))
    w_B = w_ex @ R_BP.T
    R_WB = from_wxyz(q_ex) * Rotation.from_matrix(R_BP).inv()
    assert np.abs(traj[:, OMEGA_BODY] - w_B).max() < tol * np.abs(w_B).max()
    assert (from_wxyz(traj[:, Q_WORLD_BODY]) * R_WB.inv()).magnitude().max() < tol


def test_translation_under_a_held_world_force_is_the_closed_form():
    rng = np.random.default_rng(8)
    x0 = random_states(rng, 3)
    F = np.array([0.3, -0.2, 1.5])
    body = RigidBody(np.array([0.5, 1.0, 2.0]), np.broadcast_to(np.diag(BOX_MOMENTS), (3, 3, 3)))
    traj = rollout(x0, np.r_[F, 0, 0, 0], 1e-2, 100, body=body, method="rk4", gravity=G, save_every=100)
    a = F / body.mass[:, None] + G
    t = 1.0
    assert np.allclose(traj[-1, :, P_WORLD], x0[:, P_WORLD] + x0[:, V_WORLD] * t + 0.5 * a * t * t, rtol=0, atol=1e-12)
    assert np.allclose(traj[-1, :, V_WORLD], x0[:, V_WORLD] + a * t, rtol=0, atol=1e-13)


def _dop853(body, x0, u, g, body_force, t_end):
    """The 13-state ODE in the body frame of a general body, DOP853 at rtol = atol = 1e-12."""
    I, m = body.inertia_com, float(body.mass)
    F, tau = u[:3], u[3:]

    def rhs(_, y):
        R = from_wxyz(y[6:10]).as_matrix()
        w = y[10:]
        q = y[6:10]
        dq = 0.5 * np.array([-q[1:] @ w, *(q[0] * w + np.cross(q[1:], w))])
        a = (R @ F if body_force else F) / m + g
        return np.r_[y[3:6], a, dq, np.linalg.solve(I, tau - np.cross(w, I @ w))]

    y = solve_ivp(rhs, (0.0, t_end), x0, method="DOP853", rtol=1e-12, atol=1e-12).y[:, -1]
    y[6:10] /= np.linalg.norm(y[6:10])
    return y


@pytest.mark.parametrize("force_frame", ["world", "body"])
def test_general_body_with_torque_and_force_matches_dop853(force_frame):
    rng = np.random.default_rng(9)
    body = general_body(rng, mass=1.3)
    x0 = random_states(rng, 1, spin=2.0)[0]
    u = np.r_[0.4, -0.3, 0.2, 0.002, -0.001, 0.003]
    ref = _dop853(body, x0, u, G, force_frame == "body", 1.0)
    got = rollout(x0, u, 1e-3, 1000, body=body, method="rk4", gravity=G, force_frame=force_frame, save_every=None)
    assert np.abs(got[:6] - ref[:6]).max() < 1e-9
    assert (from_wxyz(got[Q_WORLD_BODY]) * from_wxyz(ref[6:10]).inv()).magnitude() < 1e-9
    assert np.abs(got[OMEGA_BODY] - ref[10:]).max() < 1e-9


@pytest.mark.parametrize("method", NAMES)
def test_rollout_of_a_general_body_equals_a_loop_of_steps(method):
    """The compiled 6-DOF bookkeeping (frames, inputs, gravity, Simpson for body forces) against
    transition.step in NumPy, a time-varying input: to rounding (step() re-forms m = I w each step)."""
    rng = np.random.default_rng(2)
    body = general_body(rng, mass=1.3)
    x0 = random_states(rng, 1, spin=5.0)[0]
    us = np.concatenate([rng.normal(size=(200, 3)), 0.005 * rng.normal(size=(200, 3))], -1)
    for frame in ("world", "body"):
        traj = rollout(x0, us, 1e-3, body=body, method=method, gravity=G, force_frame=frame)
        x = x0
        for k in range(200):
            x = step(x, us[k], 1e-3, body=body, method=method, gravity=G, force_frame=frame)
        assert np.abs(traj[-1] - x).max() < 1e-12, frame


def test_splitting_keeps_the_momentum_invariants_over_a_long_run():
    """1e5 steps of the torque-free box near its intermediate axis: |L| and L_world to rounding."""
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.01])
    traj = rollout(x0, None, 1e-3, 100_000, body=body, method="splitting", save_every=1000)
    L_body = traj[:, OMEGA_BODY] * BOX_MOMENTS
    L_world = from_wxyz(traj[:, Q_WORLD_BODY]).apply(L_body)
    G0 = np.linalg.norm(L_body[0])
    assert np.abs(np.linalg.norm(L_body, axis=1) - G0).max() / G0 < 1e-12
    assert np.abs(L_world - L_world[0]).max() / G0 < 1e-11


@pytest.mark.parametrize("method", ["dmv", "dmv4", "midpoint"])
def test_conserving_methods_keep_energy_in_a_batch(method):
    rng = np.random.default_rng(10)
    bodies = random_bodies(rng, 70)
    x0 = random_states(rng, 70)
    traj = rollout(x0, None, 1e-2, 500, body=bodies, method=method, save_every=500)
    w_P = np.einsum("nji,snj->sni", bodies.R_body_principal, traj[..., OMEGA_BODY])
    T = 0.5 * np.sum(bodies.moments * w_P ** 2, axis=-1)
    assert np.abs(T[1] / T[0] - 1).max() < 1e-12


def test_a_step_function_runs_in_python_and_agrees_with_its_name():
    rng = np.random.default_rng(11)
    body = general_body(rng)
    x0 = random_states(rng, 3)
    a = rollout(x0, np.r_[0.1, 0, 0, 0.001, 0, 0], 0.01, 30, body=body, method=step_dmv, save_every=None)
    b = rollout(x0, np.r_[0.1, 0, 0, 0.001, 0, 0], 0.01, 30, body=body, method="dmv", save_every=None)
    assert a.shape == (3, 13)
    assert np.abs(a - b).max() < 1e-12


# ------------------------------------------------------------------------------ determinism
def _batch(n=300, seed=3):
    rng = np.random.default_rng(seed)
    return random_states(rng, n), random_bodies(rng, n), np.concatenate(
        [rng.normal(size=(n, 3)), 0.01 * rng.normal(size=(n, 3))], -1)


@pytest.mark.parametrize("force_frame", ["world", "body"])
@pytest.mark.parametrize("method", NAMES)
def test_a_body_gets_the_same_bits_alone_anywhere_in_a_batch_and_on_any_thread_count(method, force_frame):
    """300 bodies (chunks of 64 and a padded tail): one thread = 2 = 3 threads = each body alone."""
    x0, bodies, u = _batch()
    kw = dict(method=method, force_frame=force_frame, gravity=G, save_every=20)
    runs = [rollout(x0, u, 1e-3, 40, body=bodies, threads=t, **kw) for t in (1, 2, 3)]
    assert np.array_equal(runs[0], runs[1]) and np.array_equal(runs[0], runs[2])
    for i in (0, 1, 63, 64, 127, 290, 299):
        one = RigidBody(bodies.mass[i], bodies.inertia_com[i])
        alone = rollout(x0[i], u[i], 1e-3, 40, body=one, **kw)
        assert np.array_equal(alone, runs[0][:, i]), i
    sub = slice(5, 77)                                  # another batch size, other positions
    part = RigidBody(bodies.mass[sub], bodies.inertia_com[sub])
    assert np.array_equal(rollout(x0[sub], u[sub], 1e-3, 40, body=part, **kw), runs[0][:, sub])


_FRESH = """
import json, sys, numpy as np
sys.path.insert(0, {root!r})
from tests.dynamics.test_rollout import _batch, G
from inertia.dynamics.rollouts import rollout
x0, bodies, u = _batch()
out = [rollout(x0, u, 1e-3, 30, body=bodies, method=m, gravity=G, save_every=None, threads=2).tobytes().hex()
       for m in ("rk4", "splitting", "dmv")]
print(json.dumps(out))
"""


def test_the_same_call_gives_the_same_bits_twice_and_in_a_fresh_process():
    import pathlib

    root = str(pathlib.Path(__file__).resolve().parents[2])
    x0, bodies, u = _batch()
    mine = []
    for m in ("rk4", "splitting", "dmv"):
        a = rollout(x0, u, 1e-3, 30, body=bodies, method=m, gravity=G, save_every=None, threads=2)
        b = rollout(x0, u, 1e-3, 30, body=bodies, method=m, gravity=G, save_every=None, threads=1)
        assert np.array_equal(a, b)
        mine.append(a.tobytes().hex())
    got = subprocess.run([sys.executable, "-c", _FRESH.format(root=root)], capture_output=True, text=True, check=True)
    assert json.loads(got.stdout) == mine


# ------------------------------------------------------------------------------ shapes and errors
def test_rollout_shapes_and_saving():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.01])
    assert rollout(x0, None, 1e-3, 20, body=body).shape == (21, 13)
    assert rollout(x0, None, 1e-3, 20, body=body, save_every=5).shape == (5, 13)
    assert rollout(x0, None, 1e-3, 20, body=body, save_every=None).shape == (13,)
    assert rollout(x0, None, 1e-3, 0, body=body).shape == (1, 13)
    xb = np.broadcast_to(x0, (2, 3, 13))
    assert rollout(xb, np.zeros((7, 3, 6)), 1e-3, body=body).shape == (8, 2, 3, 13)
    assert rollout(xb, np.zeros((0, 3, 6)), 1e-3, body=body).shape == (1, 2, 3, 13)
    traj = rollout(x0, None, 1e-3, 20, body=body, save_every=5)
    full = rollout(x0, None, 1e-3, 20, body=body)
    assert np.array_equal(traj, full[::5])
    assert np.array_equal(full[-1], rollout(x0, None, 1e-3, 20, body=body, save_every=None))


def test_rollout_input_errors():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 1.0])
    with pytest.raises(InputError, match=r"^n_steps \(10\) must be a multiple of save_every \(3\)$"):
        rollout(x0, None, 0.01, 10, body=body, save_every=3)
    with pytest.raises(InputError, match=r"^give n_steps when u is None"):
        rollout(x0, None, 0.01, body=body)
    with pytest.raises(InputError,
                       match=r"^u must be a time-major sequence \(n_steps, \.\.\., 6\) when n_steps is None"):
        rollout(x0, np.zeros(6), 0.01, body=body)
    with pytest.raises(InputError, match=r"^n_steps must be an integer >= 0, got 2\.5$"):
        rollout(x0, None, 0.01, 2.5, body=body)
    with pytest.raises(InputError, match=r"^threads must be an integer >= 1, got 0$"):
        rollout(x0, None, 0.01, 3, body=body, threads=0)
    with pytest.raises(InputError, match=r"^method must be one of \['dmv', .*\] or a step function, got 'rk5'$"):
        rollout(x0, None, 0.01, 3, body=body, method="rk5")


@pytest.mark.parametrize("n_bodies", [1, 200])
def test_newton_failure_names_step_and_body(n_bodies):
    """A step too large for the DMV equation: refused, with the step and the (flat) body."""
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = np.broadcast_to(pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.0]), (n_bodies, 13))
    with pytest.raises(IntegrationError, match=r"dmv: .* did not converge .* at step 0 of body 0 "):
        rollout(x0, None, 0.5, 3, body=body, method="dmv")
    with pytest.raises(IntegrationError, match=r"dmv: the implicit step equation did not converge"):
        rollout(x0, None, 0.5, 3, body=body, method=step_dmv)


def test_the_kernels_check_every_size_and_index_they_are_given():
    """The compiled core's own guards (the Python layer never sends these): InputError, no crash."""
    from inertia._ext import dynamics as kernels

    q, m, I = np.array([[1.0, 0, 0, 0]]), np.ones((1, 3)), np.ones((1, 3))
    qs, ws = np.empty((1, 1, 4)), np.empty((1, 1, 3))
    one = np.array([1], dtype=np.int64)
    with pytest.raises(InputError, match=r"^slots\[0\] = 1 names no row of qs \(1\)$"):
        kernels.advance(2, q, m, I, np.zeros((0, 3)), one, np.array([0.1]), one, qs, ws, True)
    with pytest.raises(InputError, match=r"^counts\[0\] = -1 < 0$"):
        kernels.advance(2, q, m, I, np.zeros((0, 3)), -one, np.array([0.1]), 0 * one, qs, ws, True)
    with pytest.raises(InputError, match=r"^method index 7 names no integrator \(0\.\.6\)$"):
        kernels.advance(7, q, m, I, np.zeros((0, 3)), one, np.array([0.1]), 0 * one, qs, ws, True)
    x0 = np.zeros((3, 13))
    x0[:, 6] = 1.0
    args = dict(u=np.zeros((1, 1, 6)), moments=np.ones((1, 3)), mass=np.ones(1), frame=np.zeros((0, 13)),
                gravity=np.zeros(3), h=0.01, n_steps=4, save_every=2, body_force=False, threads=1,
                out=np.empty((3, 3, 13)), status=np.empty(3, dtype=np.int64))
    kernels.rollout(3, x0, **args)
    for key, bad, message in (("moments", np.ones((2, 3)), r"^moments has 2 rows, expected 1 or 3$"),
                              ("u", np.zeros((3, 1, 6)), r"^u must hold 1 or n_steps inputs$"),
                              ("out", np.empty((2, 3, 13)), r"^out has length 2, expected 3$"),
                              ("save_every", 3, r"^n_steps must be a multiple of save_every$"),
                              ("threads", 0, r"^threads must be >= 1, got 0$")):
        with pytest.raises(InputError, match=message):
            kernels.rollout(3, x0, **{**args, key: bad})
