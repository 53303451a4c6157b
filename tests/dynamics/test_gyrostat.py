"""Gyrostats (bodies with reaction wheels): against MuJoCo (a free body carrying hinge-joint rotors),
the free-body integrators, conservation laws and central differences; the limits, the feedback law
inside the compiled loop, frames, determinism and the checks of every input."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from inertia._core.rotations import quat_to_matrix
from inertia.dynamics import RigidBody, rollout
from inertia.dynamics.gyrostat import (
    Gyrostat,
    WheelFeedback,
    gyrostat_jacobians,
    gyrostat_rollout,
    gyrostat_step,
    saturate_wheel_torque,
)
from inertia.dynamics.state import perturb_state, state_error
from inertia.errors import InputError
from tests.scipy_quat import as_wxyz

AXES = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.6, 0.8]])


def general_gyrostat(rng, **limits):
    R = Rotation.random(random_state=rng).as_matrix()
    return Gyrostat(RigidBody(1.3, R @ np.diag([0.02, 0.03, 0.04]) @ R.T), AXES, **limits)


def state(w, h, q=(1.0, 0, 0, 0)):
    return np.r_[np.zeros(6), q, w, h]


# ------------------------------------------------------------------------------ MuJoCo
def _mujoco_gyrostat(I_base, J, Jt, mass_rotor, axes):
    """MJCF: a free base carrying one symmetric rotor per axis on a hinge (no contact, no damping),
    every centre of mass at the base origin; motors on the hinges."""
    rotors = "".join(
        f'<body name="r{k}" zaxis="{a[0]} {a[1]} {a[2]}"><joint name="j{k}" type="hinge" axis="0 0 1"/>'
        f'<inertial pos="0 0 0" mass="{mass_rotor}" diaginertia="{Jt} {Jt} {J}"/></body>' for k, a in enumerate(axes))
    I = I_base
    full = f"{I[0, 0]} {I[1, 1]} {I[2, 2]} {I[0, 1]} {I[0, 2]} {I[1, 2]}"
    motors = "".join(f'<motor joint="j{k}" gear="1"/>' for k in range(len(axes)))
    return (f'<mujoco><option timestep="2e-4" integrator="RK4" gravity="0 0 0"><flag contact="disable"/></option>'
            f'<worldbody><body name="base"><freejoint/><inertial pos="0 0 0" mass="1.0" fullinertia="{full}"/>'
            f"{rotors}</body></worldbody><actuator>{motors}</actuator></mujoco>")


def test_a_gyrostat_agrees_with_mujoco_rotors_on_hinges_over_10_s():
    """A general base with three motor-driven rotors (one oblique), 10 s: rk4 within 1e-8 of MuJoCo's
    RK4 (both at 0.2 ms; the gyrostat's inertia is the composite one less the rotors' axial moments,
    the wheel momentum J (a . omega + hinge rate)); splitting converges to it at order 2."""
    mujoco = pytest.importorskip("mujoco")
    I_base = np.array([[2.0, 0.1, -0.05], [0.1, 3.0, 0.2], [-0.05, 0.2, 4.0]]) * 1e-2
    J, Jt, mr = 2e-3, 1.2e-3, 0.05
    model = mujoco.MjModel.from_xml_string(_mujoco_gyrostat(I_base, J, Jt, mr, AXES))
    data = mujoco.MjData(model)
    w0, rates, u = np.array([0.3, 5.0, -0.2]), np.array([20.0, -10.0, 5.0]), np.array([1e-3, -2e-3, 5e-4])
    data.qvel[3:6], data.qvel[6:9], data.ctrl[:] = w0, rates, u
    per, every = 2e-4, 500                                      # a sample every 0.1 s
    q_mj, w_mj, h_mj = [], [], []
    for k in range(100 * every + 1):
        if k % every == 0:
            q_mj.append(data.qpos[3:7].copy())
            w_mj.append(data.qvel[3:6].copy())
            h_mj.append(J * (AXES @ data.qvel[3:6] + data.qvel[6:9]))
        if k < 100 * every:
            mujoco.mj_step(model, data)
    q_mj, w_mj, h_mj = np.array(q_mj), np.array(w_mj), np.array(h_mj)
    I_s = I_base + sum(Jt * (np.eye(3) - np.outer(a, a)) for a in AXES)
    g = Gyrostat(RigidBody(1.0 + 3 * mr, I_s), AXES)
    x0 = state(w0, J * (AXES @ w0 + rates))
    u_in = np.r_[np.zeros(6), u]

    def errors(method, h):
        run = gyrostat_rollout(x0, h, 100, gyrostat=g, u=u_in, method=method, substeps=int(round(0.1 / h)))
        S = run.states
        dq = np.minimum(np.abs(S[:, 6:10] - q_mj).max(1), np.abs(S[:, 6:10] + q_mj).max(1)).max()
        return dq, np.abs(S[:, 10:13] - w_mj).max() / np.abs(w_mj).max(), np.abs(S[:, 13:] - h_mj).max() / \
            np.abs(h_mj).max()

    assert max(errors("rk4", per)) < 1e-8
    coarse, fine = errors("splitting", 4 * per)[0], errors("splitting", 2 * per)[0]
    assert 3.5 < coarse / fine < 4.5 and fine < 1e-5


# ------------------------------------------------------------------------------ independent truth
@pytest.mark.parametrize("method", ["splitting", "rk4"])
def test_without_wheels_a_gyrostat_is_the_free_body(method):
    """In its principal frame the same bits as the free-body rollout (the same rotor flows and RK4 stages;
    omega differs by the rounding of m W against m / I); a general body to rounding (frame changes)."""
    rng = np.random.default_rng(1)
    x0 = np.r_[rng.normal(size=6), as_wxyz(Rotation.random(random_state=rng)), rng.normal(size=3)]
    for body, bitwise in ((RigidBody.from_principal_moments(1.3, [0.02, 0.03, 0.04]), True),
                          (general_gyrostat(rng).body, False)):
        got = gyrostat_rollout(x0, 1e-3, 300, gyrostat=Gyrostat(body, np.zeros((0, 3))), method=method).states
        ref = rollout(x0, None, 1e-3, 300, body=body, method=method)
        if bitwise:
            assert np.array_equal(got[:, :10], ref[:, :10])
        assert np.abs(got - ref).max() <= 1e-14 * np.abs(ref).max()


def test_the_wheels_exchange_momentum_with_the_body_and_the_total_is_kept():
    """Splitting with wheel torques: world L = R (I w + h) and |I w + h| to rounding; each wheel's
    momentum grows by its torque times the time (to the rounding of the sums); gravity and force move only p and v."""
    rng = np.random.default_rng(2)
    g = general_gyrostat(rng)
    x0 = np.r_[np.zeros(6), as_wxyz(Rotation.random(random_state=rng)), [0.5, 3.0, -0.2], [0.01, -0.02, 0.005]]
    u = np.r_[0.2, 0, 0, 0, 0, 0, 2e-3, -1e-3, 3e-3]
    run = gyrostat_rollout(x0, 1e-3, 2000, gyrostat=g, u=u, gravity=[0, 0, -9.81])
    S = run.states
    m = S[:, 10:13] @ g.body.inertia_com.T + S[:, 13:] @ AXES
    L = np.einsum("sij,sj->si", quat_to_matrix(S[:, 6:10]), m)
    assert np.abs(L - L[0]).max() < 2e-14 * np.linalg.norm(L[0])
    assert np.abs(S[-1, 13:] - x0[13:] - 2.0 * u[6:]).max() < 1e-14     # 2000 sums of h u
    a = np.array([0.2 / 1.3, 0, -9.81])
    assert np.abs(S[-1, 0:3] - 0.5 * a * 2.0 ** 2).max() < 1e-12 and np.abs(S[-1, 3:6] - a * 2.0).max() < 1e-12


@pytest.mark.parametrize("method, substeps", [("splitting", 1), ("rk4", 3)])
def test_jacobians_match_central_differences_of_the_step(method, substeps):
    """Complex-step A and B against 4th-order central differences of gyrostat_step on the error state,
    for a non-principal body, oblique wheels, a force and torques, over substeps."""
    rng = np.random.default_rng(3)
    g = general_gyrostat(rng)
    x = np.r_[rng.normal(size=6), as_wxyz(Rotation.random(random_state=rng)), [0.4, 3.0, -0.7], [0.01, 0.02, -0.01]]
    u = np.r_[0.3, -0.1, 0.2, 0.01, -0.02, 0.005, 1e-3, -2e-3, 5e-4]
    kw = dict(gyrostat=g, method=method, gravity=[0, 0, -9.81], substeps=substeps)
    A, B = gyrostat_jacobians(x, u, 0.01, **kw)
    x1 = gyrostat_step(x, u, 0.01, **kw)

    def err(y):
        return np.r_[state_error(y[:13], x1[:13]), y[13:] - x1[13:]]

    def moved(d):
        return np.r_[perturb_state(x[:13], d[:12]), x[13:] + d[12:]]

    e, w = 1e-4, np.array([1.0, -8.0, 8.0, -1.0]) / 12.0
    An = np.stack([sum(c * err(gyrostat_step(moved(o * e * np.eye(15)[k]), u, 0.01, **kw)) for o, c in
                       zip((-2, -1, 1, 2), w)) / e for k in range(15)], axis=1)
    Bn = np.stack([sum(c * err(gyrostat_step(x, u + o * e * np.eye(9)[k], 0.01, **kw)) for o, c in
                       zip((-2, -1, 1, 2), w)) / e for k in range(9)], axis=1)
    assert np.abs(A - An).max() < 1e-9 * np.abs(A).max()
    assert np.abs(B - Bn).max() < 1e-9 * np.abs(B).max()


def test_a_rotated_gyrostat_moves_as_the_rotated_motion():
    """Body, wheels and state turned by R: the same motion seen in the turned frame (the principal-frame
    conversions of states, torques, wheel axes, gains and the monitored axis)."""
    rng = np.random.default_rng(4)
    g = Gyrostat(RigidBody(1.0, np.diag([0.02, 0.03, 0.04])), AXES)
    R = Rotation.random(random_state=rng)
    gr = Gyrostat(RigidBody(1.0, R.as_matrix() @ g.body.inertia_com @ R.as_matrix().T), R.apply(AXES))
    x = state([0.3, 4.0, -0.5], [0.01, 0.02, 0.0])
    xr = x.copy()
    xr[6:10] = as_wxyz(Rotation.from_quat([0, 0, 0, 1]) * R.inv())     # q_WB' = q_WB R^T: same world pose
    xr[10:13] = R.apply(x[10:13])
    K = rng.normal(size=(3, 6)) * 1e-3
    Kr = np.c_[K[:, :3] @ R.as_matrix().T, K[:, 3:]]
    fb, fbr = WheelFeedback(K, [0, 4.0, 0], np.zeros(3)), WheelFeedback(Kr, R.apply([0, 4.0, 0]), np.zeros(3))
    a = gyrostat_rollout(x, 1e-3, 50, gyrostat=g, feedback=fb, substeps=4, monitor_axis=[0, 1, 0])
    b = gyrostat_rollout(xr, 1e-3, 50, gyrostat=gr, feedback=fbr, substeps=4, monitor_axis=R.apply([0, 1, 0]))
    assert np.abs(b.states[:, 10:13] - R.apply(a.states[:, 10:13])).max() < 1e-12
    assert np.abs(b.states[:, 13:] - a.states[:, 13:]).max() < 1e-15
    assert np.abs(b.tilt - a.tilt).max() < 1e-12


# ------------------------------------------------------------------------------ limits and feedback
def test_the_plant_keeps_each_wheel_within_its_torque_and_momentum():
    g = Gyrostat(RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0]), np.eye(3), max_torque=[0.1, 0.2, 0.3],
                 max_momentum=[0.05, 1.0, 0.02])
    x = state([0.1, 1.0, 0.0], [0.04, 0.0, -0.02])
    y = gyrostat_step(x, np.r_[np.zeros(6), 5.0, -5.0, 5.0], 0.1, gyrostat=g)
    # wheel 1 stops at its momentum limit, wheel 2 at its torque limit, wheel 3 at the torque limit
    assert np.allclose(y[13:], [0.05, -0.02, 0.01], rtol=0, atol=1e-15)
    assert np.allclose(saturate_wheel_torque([5.0, -5.0, 5.0], x[13:], 0.1, max_torque=g.max_torque,
                                             max_momentum=g.max_momentum) * 0.1 + x[13:], y[13:], atol=1e-15)
    # a wheel beyond its limit is brought back as fast as its torque allows
    over = gyrostat_step(state([0, 1.0, 0], [0.0, 0.0, 0.5]), None, 0.1, gyrostat=g)
    assert over[15] == pytest.approx(0.5 - 0.03, abs=1e-15)


def test_the_feedback_law_runs_in_the_loop_once_per_period():
    """One control period of the compiled law = a step with the torque computed by hand."""
    g = Gyrostat(RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0]), np.eye(3), max_torque=[0.05] * 3)
    x = state([0.1, 1.2, -0.1], [0.01, 0.02, 0.03])
    K = np.arange(18.0).reshape(3, 6) * 1e-2
    fb = WheelFeedback(K, [0, 1.0, 0], [0, 0.01, 0], u_ff=[0.001, 0.0, -0.001])
    got = gyrostat_rollout(x, 0.01, 1, gyrostat=g, feedback=fb, substeps=5, save_every=None).states[0]
    z = np.r_[x[10:13] - [0, 1.0, 0], x[13:] - [0, 0.01, 0]]
    u = np.clip(fb.u_ff - K @ z, -0.05, 0.05)
    assert np.array_equal(got, gyrostat_step(x, np.r_[np.zeros(6), u], 0.01, gyrostat=g, substeps=5))


# ------------------------------------------------------------------------------ determinism
def _batch(n=70):
    rng = np.random.default_rng(5)
    x0 = np.stack([state(rng.normal(size=3) + [0, 5, 0], rng.normal(size=3) * 1e-2,
                         as_wxyz(Rotation.random(random_state=rng))) for _ in range(n)])
    R = Rotation.random(n, random_state=rng).as_matrix()
    g = Gyrostat(RigidBody(np.ones(n), R @ np.diag([0.02, 0.03, 0.04]) @ np.swapaxes(R, 1, 2)), AXES,
                 max_torque=[0.02] * 3, max_momentum=[0.05] * 3)
    fb = WheelFeedback(rng.normal(size=(n, 3, 6)) * 1e-2, [0, 5.0, 0], np.zeros(3))
    return x0, g, fb


def test_a_run_gets_the_same_bits_alone_anywhere_in_a_batch_and_on_any_thread_count():
    x0, g, fb = _batch()
    kw = dict(substeps=2, save_every=5, monitor_axis=[0, 1, 0])
    runs = [gyrostat_rollout(x0, 1e-3, 20, gyrostat=g, feedback=fb, threads=t, **kw) for t in (1, 2, 3)]
    for r in runs[1:]:
        assert np.array_equal(r.states, runs[0].states) and np.array_equal(r.tilt, runs[0].tilt)
    for i in (0, 15, 16, 47, 69):
        one = g.with_body(RigidBody(g.body.mass[i], g.body.inertia_com[i]))
        alone = gyrostat_rollout(x0[i], 1e-3, 20, gyrostat=one, feedback=WheelFeedback(fb.gain[i], fb.omega_ref,
                                                                                       fb.h_ref), **kw)
        assert np.array_equal(alone.states, runs[0].states[:, i]) and np.array_equal(alone.tilt, runs[0].tilt[:, i])


_FRESH = """
import json, sys
sys.path.insert(0, {root!r})
from tests.dynamics.test_gyrostat import _batch
from inertia.dynamics.gyrostat import gyrostat_rollout
x0, g, fb = _batch()
r = gyrostat_rollout(x0, 1e-3, 20, gyrostat=g, feedback=fb, substeps=2, save_every=None, threads=2)
print(json.dumps(r.states.tobytes().hex()))
"""


def test_the_same_call_gives_the_same_bits_in_a_fresh_process():
    root = str(Path(__file__).resolve().parents[2])
    x0, g, fb = _batch()
    mine = gyrostat_rollout(x0, 1e-3, 20, gyrostat=g, feedback=fb, substeps=2, save_every=None, threads=1)
    got = subprocess.run([sys.executable, "-c", _FRESH.format(root=root)], capture_output=True, text=True, check=True)
    assert json.loads(got.stdout) == mine.states.tobytes().hex()


# ------------------------------------------------------------------------------ shapes and errors
def test_shapes_of_steps_jacobians_and_rollouts():
    g = Gyrostat(RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0]), [[0, 1.0, 0]])
    x = state([0.01, 1.0, 0.0], [0.5])
    assert gyrostat_step(np.broadcast_to(x, (2, 3, 14)), None, 0.01, gyrostat=g).shape == (2, 3, 14)
    A, B = gyrostat_jacobians(np.broadcast_to(x, (4, 14)), None, 0.01, gyrostat=g)
    assert A.shape == (4, 13, 13) and B.shape == (4, 13, 7)
    run = gyrostat_rollout(x, 0.01, 10, gyrostat=g, save_every=5, substeps=2)
    assert run.states.shape == (3, 14) and run.tilt is None and np.allclose(run.t, [0, 0.1, 0.2])
    last = gyrostat_rollout(x, 0.01, 10, gyrostat=g, save_every=None, substeps=2, monitor_axis=[0, 1, 0])
    assert np.array_equal(last.states[0], run.states[-1]) and last.tilt.shape == (1,)


def test_input_errors_say_what_was_expected():
    body = RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0])
    with pytest.raises(InputError, match=r"^wheel axis 1 has norm 2, expected a unit vector"):
        Gyrostat(body, [[1.0, 0, 0], [0, 2.0, 0]])
    with pytest.raises(InputError, match=r"^a gyrostat carries at most 6 wheels, got 7$"):
        Gyrostat(body, np.ones((7, 3)) / np.sqrt(3))
    with pytest.raises(InputError, match=r"^max_torque must be positive \(inf for no limit\), got \[0\.0\]$"):
        Gyrostat(body, [[1.0, 0, 0]], max_torque=[0.0])
    with pytest.raises(InputError, match=r"^max_momentum must have shape \(1,\) \(one per wheel\), got \(2,\)$"):
        Gyrostat(body, [[1.0, 0, 0]], max_momentum=[1.0, 2.0])
    g = Gyrostat(body, [[1.0, 0, 0]])
    x = state([0, 1.0, 0], [0.0])
    with pytest.raises(InputError, match=r"^method must be one of \['splitting', 'rk4'\] for a gyrostat, got 'dmv'$"):
        gyrostat_step(x, None, 0.01, gyrostat=g, method="dmv")
    with pytest.raises(InputError, match=r"^h must be a positive, finite time step in s, got -0\.01$"):
        gyrostat_step(x, None, -0.01, gyrostat=g)
    with pytest.raises(InputError, match=r"^n_steps \(10\) must be a multiple of save_every \(3\)$"):
        gyrostat_rollout(x, 0.01, 10, gyrostat=g, save_every=3)
    with pytest.raises(InputError, match=r"^gyrostat must be a Gyrostat"):
        gyrostat_step(x, None, 0.01, gyrostat=body)


def test_the_kernels_check_every_size_they_are_given():
    from inertia._ext import dynamics as kernels

    x0 = state([0, 1.0, 0], [0.0])[None]
    plant = np.r_[1.0, 1.0, 2.0, 3.0, 1.0, 0, 0, np.inf, np.inf, 0, 0, 0, 0, 0, 0][None]
    control = np.zeros((1, 4 + 8))
    args = dict(x0=x0, plant=plant, control=control, gravity=np.zeros(3), h=0.01, substeps=1, n_steps=4,
                save_every=2, threads=1, out=np.empty((3, 1, 14)), tilt=np.empty((3, 1)))
    kernels.gyro_rollout(3, **args)
    for key, bad, message in (
            ("x0", np.zeros((1, 20)), r"^a gyrostat state has 13 \+ n columns \(0 <= n <= 6 wheels\), got 20$"),
            ("plant", np.ones((2, 15)), r"^plant has 2 rows, expected 1 or 1$"),
            ("plant", plant * np.r_[1, -1, np.ones(13)], r"^plant row 0: mass and moments must be positive"),
            ("control", np.zeros((1, 3)), r"^control \(axis 1\) has length 3, expected 12$"),
            ("out", np.empty((2, 1, 14)), r"^out has length 2, expected 3$"),
            ("h", np.nan, r"^h must be positive and finite, got nan$"),
            ("substeps", 0, r"^substeps must be >= 1, got 0$"),
            ("save_every", 3, r"^n_steps must be a multiple of save_every$")):
        with pytest.raises(InputError, match=message):
            kernels.gyro_rollout(3, **{**args, key: bad})
    with pytest.raises(InputError, match=r"^method index 4: the gyrostat steps are splitting \(3\) and rk4 \(2\)$"):
        kernels.gyro_rollout(4, **args)
    with pytest.raises(InputError, match=r"^u \(axis 1\) has length 6, expected 7$"):
        kernels.gyro_jacobians(3, x0, np.zeros((1, 6)), plant, np.zeros(3), 0.01, 1, np.empty((1, 13, 13)),
                               np.empty((1, 13, 7)))
