"""Rollouts: the NumPy reference path, the compiled numba path, and their agreement."""

from __future__ import annotations

import sys

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from inertia.dynamics import RigidBody, pack_state, step
from inertia.dynamics.integrators import step_dmv
from inertia.dynamics.rollouts import COMPILED_METHODS, numba_available, rollout
from inertia.dynamics.state import OMEGA_BODY, Q_WORLD_BODY
from inertia.errors import InputError, MissingDependencyError
from tests.scipy_quat import as_wxyz, from_wxyz

HAVE_NUMBA = numba_available()
needs_numba = pytest.mark.skipif(not HAVE_NUMBA, reason="numba not installed")

BOX_MOMENTS = np.array([0.1 ** 2 + 0.2 ** 2, 0.1 ** 2 + 0.4 ** 2, 0.2 ** 2 + 0.4 ** 2]) / 12.0  # kg m^2, 1 kg


def random_states(rng, n, spin=3.0):
    q = as_wxyz(Rotation.random(n, random_state=rng))
    return np.concatenate([rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), q, spin * rng.normal(size=(n, 3))], -1)


def general_body(rng, mass=1.0):
    R = Rotation.random(random_state=rng).as_matrix()
    return RigidBody(mass, R @ np.diag(BOX_MOMENTS) @ R.T)


# ------------------------------------------------------------------------------ NumPy path
def test_numpy_rollout_equals_a_loop_of_steps():
    rng = np.random.default_rng(0)
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = random_states(rng, 1)[0]
    us = 0.01 * rng.normal(size=(50, 6))
    traj = rollout(x0, us, 0.01, body=body, method="rk4", gravity=[0, 0, -9.81], backend="numpy")
    assert traj.shape == (51, 13)
    x = x0
    for k in range(50):
        x = step(x, us[k], 0.01, body=body, method="rk4", gravity=[0, 0, -9.81])
        # the same operations, except that step() renormalises its input quaternion (ulps)
        assert np.allclose(traj[k + 1], x, rtol=0, atol=1e-14)


def test_numpy_rollout_of_a_general_body_matches_steps_to_rounding():
    rng = np.random.default_rng(1)
    body = general_body(rng)
    x0 = random_states(rng, 4)
    traj = rollout(x0, np.r_[0.1, 0, 0, 0.001, 0, 0], 0.01, 30, body=body, method="splitting", backend="numpy",
                   save_every=None)
    x = x0
    for _ in range(30):
        x = step(x, np.r_[0.1, 0, 0, 0.001, 0, 0], 0.01, body=body, method="splitting")
    assert traj.shape == (4, 13)
    assert np.allclose(traj, x, rtol=0, atol=1e-13)


def test_rollout_shapes_and_saving():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.01])
    assert rollout(x0, None, 1e-3, 20, body=body, backend="numpy").shape == (21, 13)
    assert rollout(x0, None, 1e-3, 20, body=body, backend="numpy", save_every=5).shape == (5, 13)
    assert rollout(x0, None, 1e-3, 20, body=body, backend="numpy", save_every=None).shape == (13,)
    assert rollout(x0, None, 1e-3, 0, body=body, backend="numpy").shape == (1, 13)
    xb = np.broadcast_to(x0, (2, 3, 13))
    assert rollout(xb, np.zeros((7, 3, 6)), 1e-3, body=body, backend="numpy").shape == (8, 2, 3, 13)
    traj = rollout(x0, None, 1e-3, 20, body=body, backend="numpy", save_every=5)
    full = rollout(x0, None, 1e-3, 20, body=body, backend="numpy")
    assert np.array_equal(traj, full[::5])


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
    with pytest.raises(InputError, match=r"^backend must be one of \('auto', 'numpy', 'numba'\), got 'cuda'$"):
        rollout(x0, None, 0.01, 3, body=body, backend="cuda")


@needs_numba
def test_numba_backend_refuses_an_uncompiled_method():
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 1.0])
    with pytest.raises(InputError, match=r"^backend='numba' compiles the methods .* got method=<function step_dmv"):
        rollout(x0, None, 0.01, 3, body=body, method=step_dmv, backend="numba")
    # "auto" falls back to NumPy for it
    assert rollout(x0, None, 0.01, 3, body=body, method="dmv").shape == (4, 13)


def test_missing_numba_raises_or_falls_back(monkeypatch):
    monkeypatch.setitem(sys.modules, "numba", None)              # `import numba` now fails
    monkeypatch.delitem(sys.modules, "inertia.dynamics._rollout_numba", raising=False)
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 1.0])
    with pytest.raises(MissingDependencyError, match=r"^backend='numba' needs numba, which is not installed"):
        rollout(x0, None, 0.01, 3, body=body, backend="numba")
    assert rollout(x0, None, 0.01, 3, body=body, backend="auto").shape == (4, 13)


# ------------------------------------------------------------------------------ numba = NumPy
@needs_numba
@pytest.mark.parametrize("method", COMPILED_METHODS)
def test_numba_single_long_rollout_equals_numpy(method):
    """One body, 1000 steps with a time-varying input, general inertia, gravity."""
    rng = np.random.default_rng(2)
    body = general_body(rng, mass=1.3)
    x0 = random_states(rng, 1, spin=5.0)[0]
    us = np.concatenate([rng.normal(size=(1000, 3)), 0.005 * rng.normal(size=(1000, 3))], -1)
    kw = dict(body=body, method=method, gravity=[0, 0, -9.81])
    a = rollout(x0, us, 1e-3, backend="numpy", **kw)
    b = rollout(x0, us, 1e-3, backend="numba", **kw)
    assert b.shape == a.shape == (1001, 13)
    assert np.abs(a - b).max() < 1e-12


@needs_numba
@pytest.mark.parametrize("force_frame", ["world", "body"])
@pytest.mark.parametrize("method", COMPILED_METHODS)
def test_numba_batch_equals_numpy(method, force_frame):
    """300 bodies: two full vectorised chunks plus left-overs on the one-body path."""
    rng = np.random.default_rng(3)
    n = 300
    x0 = random_states(rng, n)
    bodies = RigidBody(rng.uniform(0.5, 2.0, n), np.stack([general_body(rng).inertia_body for _ in range(n)]))
    u = np.concatenate([rng.normal(size=(n, 3)), 0.01 * rng.normal(size=(n, 3))], -1)
    kw = dict(body=bodies, method=method, force_frame=force_frame, gravity=[0, 0, -9.81], save_every=50)
    a = rollout(x0, u, 1e-3, 200, backend="numpy", **kw)
    b = rollout(x0, u, 1e-3, 200, backend="numba", **kw)
    assert b.shape == a.shape == (5, n, 13)
    assert np.abs(a - b).max() < 1e-12


@needs_numba
def test_numba_shared_body_and_held_input_final_state_only():
    rng = np.random.default_rng(4)
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = random_states(rng, 260).reshape(2, 130, 13)
    u = np.r_[0.0, 0.0, 9.81, 0.0, 0.001, 0.0]
    a = rollout(x0, u, 1e-3, 300, body=body, method="rk4", backend="numpy", save_every=None)
    b = rollout(x0, u, 1e-3, 300, body=body, method="rk4", backend="numba", save_every=None)
    assert b.shape == (2, 130, 13)
    assert np.abs(a - b).max() < 1e-12


@needs_numba
def test_numba_splitting_keeps_the_momentum_invariants_over_a_long_run():
    """1e5 steps of the torque-free box near its intermediate axis: |L| and L_world to rounding."""
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.01])
    traj = rollout(x0, None, 1e-3, 100_000, body=body, method="splitting", backend="numba", save_every=1000)
    L_body = traj[:, OMEGA_BODY] * BOX_MOMENTS
    q = traj[:, Q_WORLD_BODY]
    L_world = from_wxyz(q).apply(L_body)
    G = np.linalg.norm(L_body[0])
    assert np.abs(np.linalg.norm(L_body, axis=1) - G).max() / G < 1e-12
    assert np.abs(L_world - L_world[0]).max() / G < 1e-11


@needs_numba
def test_numba_threads_split_the_bodies_and_change_nothing(monkeypatch):
    """Two threads over 300 bodies (a chunk each side, left-overs on the one-body path) = one thread = NumPy."""
    import numba

    from inertia.dynamics import rollouts

    if numba.config.NUMBA_NUM_THREADS < 2:
        pytest.skip("numba is limited to one thread")
    monkeypatch.setattr(rollouts, "_THREADS_MIN_WORK", 1)
    rng = np.random.default_rng(5)
    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = random_states(rng, 300)
    kw = dict(body=body, method="splitting", gravity=[0, 0, -9.81], save_every=None)
    before = numba.get_num_threads()
    try:
        runs = []
        for threads in (1, 2):
            numba.set_num_threads(threads)
            runs.append(rollout(x0, None, 1e-3, 50, backend="numba", **kw))
    finally:
        numba.set_num_threads(before)
    assert np.array_equal(runs[0], runs[1])
    assert np.abs(runs[0] - rollout(x0, None, 1e-3, 50, backend="numpy", **kw)).max() < 1e-12


@needs_numba
@pytest.mark.parametrize("n_bodies", [1, 200])
def test_numba_newton_failure_is_named_like_numpy(n_bodies):
    """A step too large for the DMV equation: both backends refuse, the compiled one names step and body."""
    from inertia.errors import IntegrationError

    body = RigidBody.from_principal_moments(1.0, BOX_MOMENTS)
    x0 = np.broadcast_to(pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.0]), (n_bodies, 13))
    with pytest.raises(IntegrationError, match="dmv: the implicit step equation did not converge"):
        rollout(x0, None, 0.5, 3, body=body, method="dmv", backend="numpy")
    with pytest.raises(IntegrationError, match=r"dmv: .* did not converge .* at step 0 of body 0 "):
        rollout(x0, None, 0.5, 3, body=body, method="dmv", backend="numba")
