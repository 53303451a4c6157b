"""Fixed-step rotational integrators: measured order, invariants, torque, batches, errors.

Test body (note §2.2 / §7 TC3, the Hairer-Lubich-Wanner example relabelled): I = (2/3, 1, 2),
m0 = (sin 1.1, 0, cos 1.1), q0 = identity.  References: scipy DOP853 at rtol = atol = 1e-13 on
Euler's equations plus the quaternion kinematics (agrees with the note's exact values to
2e-12, see test_equations.py), and the figures of ../shared/notes/free-rigid-body.md.
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from inertia._core.rotations import quat_from_rotvec, quat_multiply
from inertia.dynamics import integrators as it
from inertia.dynamics.diagnostics import angular_momentum_norm, attitude_error, kinetic_energy, trajectory_invariants
from inertia.dynamics.equations import angular_acceleration_principal, state_rate_body
from inertia.errors import InputError, IntegrationError, InvalidInertiaError

I_TEST = np.array([2 / 3, 1.0, 2.0])
M0 = np.array([np.sin(1.1), 0.0, np.cos(1.1)])
W0 = M0 / I_TEST
Q0 = np.array([1.0, 0.0, 0.0, 0.0])
TORQUE = np.array([0.05, -0.1, 0.08])
NAMES = ["euler_explicit", "euler_implicit", "rk4", "splitting", "dmv", "dmv4", "midpoint"]


@lru_cache(maxsize=None)
def reference(t_end: float, torque: tuple | None = None, moments: tuple = tuple(I_TEST),
              w0: tuple = tuple(W0)):
    """(q, omega) at t_end by DOP853, rtol = atol = 1e-13."""
    I = np.array(moments)
    tau = None if torque is None else np.array(torque)

    def rhs(t, y):
        dq, dw = state_rate_body(y[:4], y[4:], I, tau)
        return np.concatenate([dq, dw])

    sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([Q0, w0]), method="DOP853", rtol=1e-13, atol=1e-13)
    q = sol.y[:4, -1]
    return q / np.linalg.norm(q), sol.y[4:, -1]


def final_errors(name, h, t_end=10.0, torque=None, moments=I_TEST, w0=W0):
    """(|m - m_ref|, attitude angle error) at t_end."""
    n = int(round(t_end / h))
    traj = it.integrate(Q0, w0, moments, h, n, method=name, torque_body=torque, record_every=n, validate=False)
    q_ref, w_ref = reference(t_end, None if torque is None else tuple(torque), tuple(moments), tuple(w0))
    return (float(np.linalg.norm(moments * (traj.omega_body[-1] - w_ref))),
            float(attitude_error(traj.q_world_body[-1], q_ref)))


def observed_order(hs, errs):
    """Least-squares slope of log(error) against log(h)."""
    return float(np.polyfit(np.log(hs), np.log(errs), 1)[0])


def test_registry():
    assert list(it.METHODS) == NAMES
    assert set(it.METHOD_ORDER) == set(NAMES)
    assert all(callable(f) for f in it.METHODS.values())


# ---------------------------------------------------------------------------- order of accuracy
# Global errors at t = 10, h = 0.1, from the note's §2.2 table (exact elliptic reference):
# err m = |m - m_exact|, err R = rotation angle.  Two significant digits there.
NOTE_ERRORS_H01 = {
    "euler_explicit": (9.7e-2, 2.8e-1),
    "euler_implicit": (7.8e-2, 2.3e-1),
    "rk4": (4.6e-7, 3.0e-6),
    "splitting": (1.10e-3, 1.7e-3),
    "dmv": (1.60e-2, 4.1e-2),
    "dmv4": (2.2e-5, 3.9e-5),
    "midpoint": (1.0e-3, 1.7e-3),
}


@pytest.mark.parametrize("name", NAMES)
def test_order_free_body(name):
    p = it.METHOD_ORDER[name]
    hs = np.array([0.1, 0.05, 0.025])
    errs = np.array([final_errors(name, h) for h in hs])
    assert observed_order(hs, errs[:, 0]) == pytest.approx(p, abs=0.12), errs
    assert observed_order(hs, errs[:, 1]) == pytest.approx(p, abs=0.12), errs
    # the note's independently implemented figures, to their printed precision
    em, eR = NOTE_ERRORS_H01[name]
    assert errs[0, 0] == pytest.approx(em, rel=0.05)
    assert errs[0, 1] == pytest.approx(eR, rel=0.05)


# Constant body torque: orders as documented (dmv4 drops to 2: kick-DMV4-kick).
TORQUE_ORDER = {"euler_explicit": 1, "euler_implicit": 1, "rk4": 4, "splitting": 2, "dmv": 2, "dmv4": 2,
                "midpoint": 2}


@pytest.mark.parametrize("name", NAMES)
def test_order_with_constant_body_torque(name):
    hs = np.array([0.1, 0.05, 0.025])
    errs = np.array([final_errors(name, h, t_end=5.0, torque=TORQUE) for h in hs])
    p = TORQUE_ORDER[name]
    assert observed_order(hs, errs[:, 0]) == pytest.approx(p, abs=0.15), errs
    assert observed_order(hs, errs[:, 1]) == pytest.approx(p, abs=0.15), errs


def _step_rk4_exp_sum(q, w, I, h):
    """RK4 on omega, attitude q (x) exp(h sum b_i w_i / 2) (MuJoCo <= 3.17 / MJX style)."""
    a = lambda x: angular_acceleration_principal(x, I)  # noqa: E731
    k1 = a(w)
    w2 = w + 0.5 * h * k1
    k2 = a(w2)
    w3 = w + 0.5 * h * k2
    k3 = a(w3)
    w4 = w + h * k3
    k4 = a(w4)
    w_bar = (w + 2 * w2 + 2 * w3 + w4) / 6
    return quat_multiply(q, quat_from_rotvec(h * w_bar)), w + h * (k1 + 2 * k2 + 2 * k3 + k4) / 6


def test_rk4_with_summed_exponential_is_only_second_order_in_attitude():
    # The pitfall documented in step_rk4: without the dexp^-1 (Magnus commutator) correction
    # the attitude is 2nd order although omega is 4th order; RK4 on q's components is 4th.
    hs = np.array([0.1, 0.05, 0.025])
    q_ref, w_ref = reference(10.0)
    errs = []
    for h in hs:
        q, w = Q0, W0
        for _ in range(int(round(10 / h))):
            q, w = _step_rk4_exp_sum(q, w, I_TEST, h)
        errs.append((np.linalg.norm(w - w_ref), attitude_error(q, q_ref)))
    errs = np.array(errs)
    assert observed_order(hs, errs[:, 0]) == pytest.approx(4.0, abs=0.12)
    assert observed_order(hs, errs[:, 1]) == pytest.approx(2.0, abs=0.12)
    assert errs[0, 1] == pytest.approx(9.6e-4, rel=0.05)          # note §2.2
    assert final_errors("rk4", 0.1)[1] < errs[0, 1] / 100


# ---------------------------------------------------------------------------- invariants, 1e4 steps
@lru_cache(maxsize=None)
def long_run(name, h=0.1, n=10_000):
    traj = it.integrate(Q0, W0, I_TEST, h, n, method=name, validate=False)
    return traj, trajectory_invariants(traj, I_TEST)


# max relative errors over 1e4 steps at h = 0.1 (note §2.2 long-run table, TC9)
@pytest.mark.parametrize("name, exact, drifting", [
    ("splitting", ("momentum_norm", "L_world"), ("energy",)),
    ("dmv", ("energy", "momentum_norm", "L_world"), ()),
    ("dmv4", ("energy", "momentum_norm", "L_world"), ()),
    ("midpoint", ("energy", "momentum_norm"), ("L_world",)),
    ("rk4", (), ("energy", "momentum_norm", "L_world")),
])
def test_invariants_over_ten_thousand_steps(name, exact, drifting):
    _, inv = long_run(name)
    errs = inv.max_relative_errors()
    for key in exact:
        assert errs[key] < 1e-13, (key, errs[key])
    for key in drifting:
        assert errs[key] > 1e-8, (key, errs[key])
    assert errs["quat_norm"] < 1e-15


def test_long_run_figures_match_note():
    e = {name: long_run(name)[1].max_relative_errors() for name in ("splitting", "rk4", "midpoint")}
    assert e["splitting"]["energy"] == pytest.approx(1.5e-4, rel=0.05)
    assert e["rk4"]["energy"] == pytest.approx(1.4e-6, rel=0.05)
    assert e["rk4"]["momentum_norm"] == pytest.approx(1.0e-6, rel=0.06)
    assert e["rk4"]["L_world"] == pytest.approx(1.2e-6, rel=0.05)
    assert e["midpoint"]["L_world"] == pytest.approx(1.2e-3, rel=0.05)


def test_splitting_energy_error_is_bounded_not_drifting():
    _, inv = long_run("splitting")
    err = np.abs(inv.energy / inv.energy[0] - 1.0)
    first, second = err[:5001].max(), err[5000:].max()
    assert second < 1.05 * first
    assert err.max() < 2e-4
    # the O(h^2) bound: halving h divides the energy error by 4
    _, inv2 = long_run("splitting", 0.05, 2000)
    err2 = np.abs(inv2.energy / inv2.energy[0] - 1.0).max()
    assert err[:1001].max() / err2 == pytest.approx(4.0, rel=0.05)


def test_rk4_invariants_drift_at_least_like_h4():
    # O(h^4 t) or better (measured: the energy error falls by 2^4.8 when h is halved)
    e1 = long_run("rk4", 0.1, 2000)[1].max_relative_errors()["energy"]
    e2 = long_run("rk4", 0.05, 4000)[1].max_relative_errors()["energy"]
    assert np.log2(e1 / e2) > 3.8


def test_euler_explicit_energy_gain_is_exactly_half_h2_a_I_a():
    # T_{n+1} - T_n = 1/2 h^2 a.I a, a = I^-1 (I w x w), and |m_{n+1}|^2 = |m_n|^2 + h^2 |m x w|^2.
    h = 0.01
    traj = it.integrate(Q0, W0, I_TEST, h, 10_000, method="euler_explicit", validate=False)
    w = traj.omega_body
    T = kinetic_energy(w, I_TEST)
    a = angular_acceleration_principal(w, I_TEST)
    gain = 0.5 * h * h * np.sum(a * I_TEST * a, axis=-1)[:-1]
    dT = np.diff(T)
    assert np.all(dT > 0)                                  # strictly increasing at every step
    assert np.abs(dT - gain).max() < 4 * np.finfo(float).eps * T.max()
    m = I_TEST * w
    G2 = np.sum(m * m, axis=-1)
    dG2 = h * h * np.sum(np.cross(m, w) ** 2, axis=-1)[:-1]
    assert np.abs(np.diff(G2) - dG2).max() < 8 * np.finfo(float).eps * G2.max()
    # the total: +8.8 % in 100 s on this body (compounding; first-order estimate h/2 int a.Ia dt)
    assert T[-1] / T[0] - 1 == pytest.approx(0.0877, abs=5e-4)


def test_euler_explicit_diverges_at_h_01():
    with pytest.raises(it.IntegrationError, match=r"'euler_explicit' diverged at step 11\d\d \(t = 11\d\.?\d* s"):
        it.integrate(Q0, W0, I_TEST, 0.1, 2000, method="euler_explicit", record_every=100, validate=False)


def test_euler_implicit_energy_never_increases():
    _, inv = long_run("euler_implicit")
    dT = np.diff(inv.energy)
    assert np.all(dT <= 4 * np.finfo(float).eps * inv.energy[0])
    assert inv.energy[-1] / inv.energy[0] - 1 == pytest.approx(-0.206, abs=0.002)   # note: 2.1e-1, decays
    assert np.all(np.diff(inv.momentum_norm) <= 4 * np.finfo(float).eps)


# Engines' figures (note §6, example A: I = (1, 2, 3), w0 = (0.01, 1, 0), 100 s, h = 10 ms):
# MuJoCo/MJX/Drake-discrete Euler +6.03e-2, MuJoCo implicit -5.5e-2, RK4 spatial-L error ~2e-10.
@pytest.mark.parametrize("name, expected", [("euler_explicit", 6.03e-2), ("euler_implicit", -5.5e-2)])
def test_engine_figures_example_a(name, expected):
    I = np.array([1.0, 2.0, 3.0])
    traj = it.integrate(Q0, [0.01, 1.0, 0.0], I, 0.01, 10_000, method=name, record_every=10_000, validate=False)
    T = kinetic_energy(traj.omega_body, I)
    assert T[-1] / T[0] - 1 == pytest.approx(expected, rel=0.01)


@pytest.mark.slow
def test_engine_figures_example_a_2ms():
    I = np.array([1.0, 2.0, 3.0])
    for name, expected in (("euler_explicit", 1.165e-2), ("euler_implicit", -1.145e-2)):
        traj = it.integrate(Q0, [0.01, 1.0, 0.0], I, 0.002, 50_000, method=name, record_every=1000, validate=False)
        inv = trajectory_invariants(traj, I)
        assert inv.energy[-1] / inv.energy[0] - 1 == pytest.approx(expected, rel=0.005)
        assert inv.max_relative_errors()["L_world"] == pytest.approx(5.9e-3, rel=0.02)


@pytest.mark.slow
def test_global_error_at_t1000_matches_note():
    # note §2.2 long run: err m(T_end), err R(T_end) at h = 0.1, T_end = 1000.  There the
    # attitude error is the matrix 2-norm |R - R_ref| = 2 sin(angle / 2) (= the angle when small).
    expected = {"splitting": (7.0e-2, 1.4e-1), "dmv": (1.07, 1.9), "dmv4": (1.6e-3, 3.6e-3),
                "rk4": (4.1e-5, 7.5e-4), "midpoint": (8.1e-2, 1.8e-1)}
    for name, (em, eR) in expected.items():
        e = final_errors(name, 0.1, t_end=1000.0)
        assert e[0] == pytest.approx(em, rel=0.06), name
        assert 2 * np.sin(e[1] / 2) == pytest.approx(eR, rel=0.06), name


# ---------------------------------------------------------------------------- structure
@pytest.mark.parametrize("name", ["splitting", "dmv", "dmv4", "midpoint"])
def test_symmetric_methods_are_reversible(name):
    q0 = np.array([0.5, 0.5, 0.5, 0.5])
    q1, w1 = it.METHODS[name](q0, W0, I_TEST, 0.1, TORQUE)
    q2, w2 = it.METHODS[name](q1, w1, I_TEST, -0.1, TORQUE)
    np.testing.assert_allclose(q2, q0, atol=1e-15)
    np.testing.assert_allclose(w2, W0, atol=1e-15)


@pytest.mark.parametrize("name", NAMES)
def test_body_at_rest_stays_at_rest(name):
    q0 = np.array([0.5, -0.5, 0.5, 0.5])
    q, w = it.METHODS[name](q0, [0.0, 0.0, 0.0], I_TEST, 0.1)
    np.testing.assert_allclose(q, q0, atol=1e-16)
    assert np.all(w == 0.0)


@pytest.mark.parametrize("name", NAMES)
def test_attitude_is_left_equivariant(name):
    # Integrating from q0 = p (x) q gives p (x) (the run from q): the world frame is arbitrary.
    p = quat_from_rotvec([0.4, -1.2, 0.7])
    a = it.integrate(Q0, W0, I_TEST, 0.1, 30, method=name, record_every=30, validate=False)
    b = it.integrate(p, W0, I_TEST, 0.1, 30, method=name, record_every=30, validate=False)
    assert attitude_error(quat_multiply(p, a.q_world_body[-1]), b.q_world_body[-1]) < 1e-13
    np.testing.assert_allclose(a.omega_body, b.omega_body, atol=1e-13)


@pytest.mark.parametrize("name", NAMES)
def test_batches_broadcast_and_match_single_runs(name):
    rng = np.random.default_rng(11)
    q = rng.normal(size=(2, 1, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    w = rng.normal(size=(5, 3))
    I = rng.uniform(0.5, 2.0, size=(2, 1, 3))
    q1, w1 = it.METHODS[name](q, w, I, 0.05, TORQUE)
    assert q1.shape == (2, 5, 4) and w1.shape == (2, 5, 3)
    traj = it.integrate(q, w, I, 0.05, 4, method=name, torque_body=TORQUE, validate=False)
    assert traj.q_world_body.shape == (5, 2, 5, 4) and traj.omega_body.shape == (5, 2, 5, 3)
    for i in range(2):
        for j in range(5):
            qs, ws = it.METHODS[name](q[i, 0], w[j], I[i, 0], 0.05, TORQUE)
            np.testing.assert_allclose(q1[i, j], qs, atol=1e-14)
            np.testing.assert_allclose(w1[i, j], ws, atol=1e-14)
            single = it.integrate(q[i, 0], w[j], I[i, 0], 0.05, 4, method=name, torque_body=TORQUE, validate=False)
            np.testing.assert_allclose(traj.omega_body[:, i, j], single.omega_body, atol=1e-13)


def test_step_function_equals_one_integrate_step():
    for name, step in it.METHODS.items():
        q, w = step(Q0, W0, I_TEST, 0.1, TORQUE)
        traj = it.integrate(Q0, W0, I_TEST, 0.1, 1, method=name, torque_body=TORQUE, validate=False)
        np.testing.assert_allclose(traj.q_world_body[-1], q, atol=1e-15)
        np.testing.assert_allclose(traj.omega_body[-1], w, atol=1e-14)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(moments=st.lists(st.floats(0.2, 5.0), min_size=3, max_size=3),
       omega=st.lists(st.floats(-2.0, 2.0), min_size=3, max_size=3),
       rotvec=st.lists(st.floats(-3.0, 3.0), min_size=3, max_size=3))
def test_conserved_quantities_for_random_bodies(moments, omega, rotvec):
    # relative invariants of an almost resting body would measure underflow, not the method
    assume(np.linalg.norm(omega) > 1e-3)
    I = np.array(moments)
    q0 = quat_from_rotvec(rotvec)
    for name, keys in (("splitting", ("momentum_norm", "L_world")),
                       ("dmv", ("energy", "momentum_norm", "L_world")),
                       ("dmv4", ("energy", "momentum_norm", "L_world")),
                       ("midpoint", ("energy", "momentum_norm"))):
        traj = it.integrate(q0, omega, I, 0.05, 60, method=name, validate=False)
        errs = trajectory_invariants(traj, I).max_relative_errors()
        for key in keys:
            assert errs[key] < 1e-13, (name, key, errs[key])


# ---------------------------------------------------------------------------- trajectories and errors
def test_integrate_records_every_and_final_state():
    traj = it.integrate(Q0, W0, I_TEST, 0.1, 25, record_every=10, validate=False)
    np.testing.assert_allclose(traj.t, [0.0, 1.0, 2.0, 2.5])
    assert len(traj) == 4
    full = it.integrate(Q0, W0, I_TEST, 0.1, 25, validate=False)
    np.testing.assert_array_equal(traj.omega_body, full.omega_body[[0, 10, 20, 25]])
    np.testing.assert_array_equal(traj.q_world_body[0], Q0)
    empty = it.integrate(Q0, W0, I_TEST, 0.1, 0, validate=False)
    assert empty.t.tolist() == [0.0]
    with pytest.raises(AttributeError):
        traj.t = None


def test_integrate_torque_changes_momentum_as_expected():
    # splitting with torque along a principal spin axis: m3 grows by h * tau3 per step exactly.
    I = np.array([1.0, 2.0, 3.0])
    traj = it.integrate(Q0, [0.0, 0.0, 1.0], I, 0.1, 10, method="splitting", torque_body=[0.0, 0.0, 0.3], validate=False)
    np.testing.assert_allclose(I[2] * traj.omega_body[-1, 2], 3.0 + 0.3, rtol=1e-14)
    assert angular_momentum_norm(traj.omega_body[-1], I) == pytest.approx(3.3)


def test_input_errors():
    with pytest.raises(InputError, match=r"method must be one of \['dmv', 'dmv4', .*\], got 'rk5'"):
        it.integrate(Q0, W0, I_TEST, 0.1, 10, method="rk5", validate=False)
    with pytest.raises(InputError, match=r"n_steps must be an integer >= 0, got -1"):
        it.integrate(Q0, W0, I_TEST, 0.1, -1, validate=False)
    with pytest.raises(InputError, match=r"n_steps must be an integer >= 0, got 2\.5"):
        it.integrate(Q0, W0, I_TEST, 0.1, 2.5, validate=False)
    with pytest.raises(InputError, match=r"record_every must be an integer >= 1, got 0"):
        it.integrate(Q0, W0, I_TEST, 0.1, 10, record_every=0, validate=False)
    with pytest.raises(InputError, match=r"h must be a finite non-zero time step in s \(negative integrates backwards\), got 0"):
        it.step_splitting(Q0, W0, I_TEST, 0)
    with pytest.raises(InputError, match=r"h must be a number"):
        it.step_rk4(Q0, W0, I_TEST, "fast")
    with pytest.raises(InputError,
                       match=r"q_world_body must be a unit quaternion .* got \|q\| = 2: \["):
        it.step_rk4([2.0, 0, 0, 0], W0, I_TEST, 0.1)
    with pytest.raises(InvalidInertiaError, match=r"moments = \(1, 1, 0\) kg m\^2 are not the principal moments of a "
                                                  r"physical body: inertia is not positive definite"):
        it.step_dmv(Q0, W0, [1.0, 1.0, 0.0], 0.1)
    with pytest.raises(InputError, match=r"batch shapes do not broadcast: q_world_body \(2, 4\), omega_body \(3, 3\)"):
        it.step_midpoint(np.tile(Q0, (2, 1)), np.ones((3, 3)), I_TEST, 0.1)
    with pytest.raises(InputError, match=r"torque_body must have shape \(\.\.\., 3\), got \(2,\)"):
        it.step_splitting(Q0, W0, I_TEST, 0.1, [1.0, 2.0])


def test_dmv_step_too_large_is_refused():
    # The DMV equation has no real solution once h |omega| exceeds about 1.
    with pytest.raises(IntegrationError, match=r"dmv: the implicit step equation did not converge .* h = 1\.0 is too large"):
        it.step_dmv(Q0, W0, I_TEST, 1.0)


# ---------------------------------------------------------------------------- failures, progress, determinism
def test_integrate_names_divergence_and_newton_failure():
    with pytest.raises(IntegrationError, match=r"'euler_explicit' diverged at step 11\d\d \(t = 11\d\.?\d* s"):
        it.integrate(Q0, W0, I_TEST, 0.1, 2000, method="euler_explicit", validate=False)
    with pytest.raises(IntegrationError, match=r"dmv: the implicit step equation did not converge in 40 Newton "
                                               r"iterations \(relative residual .*\); the time step h = 1\.0 is too large"):
        it.integrate(Q0, W0, I_TEST, 1.0, 5, method="dmv", validate=False)


def test_a_lone_step_returns_a_non_finite_state_instead_of_raising():
    q, w = it.step_euler_explicit(Q0, [1e200, 1e200, 0.0], I_TEST, 1e200)
    assert not np.isfinite(w).all()


def test_progress_reports_every_step_and_changes_nothing(monkeypatch):
    from inertia.dynamics import segments

    monkeypatch.setattr(segments, "PROGRESS_WORK", 2000)      # many pieces, segments cut in two
    seen = []
    kw = dict(method="dmv", record_every=2500, validate=False)
    a = it.integrate(Q0, W0, I_TEST, 0.01, 3000, **kw)
    b = it.integrate(Q0, W0, I_TEST, 0.01, 3000, progress=seen.append, **kw)
    assert sum(seen) == 3000 and len(seen) > 1
    assert np.array_equal(a.q_world_body, b.q_world_body) and np.array_equal(a.omega_body, b.omega_body)


@pytest.mark.parametrize("name", NAMES)
def test_a_body_gets_the_same_bits_alone_and_inside_a_batch(name):
    rng = np.random.default_rng(12)
    w = rng.normal(size=(4, 3))
    I = rng.uniform(0.5, 2.0, size=(4, 3))
    batch = it.integrate(Q0, w, I, 0.01, 300, method=name, torque_body=TORQUE, record_every=100, validate=False)
    q_b, w_b = it.METHODS[name](Q0, w, I, 0.01, TORQUE)
    for i in range(4):
        one = it.integrate(Q0, w[i], I[i], 0.01, 300, method=name, torque_body=TORQUE, record_every=100,
                           validate=False)
        assert np.array_equal(one.q_world_body, batch.q_world_body[:, i])
        assert np.array_equal(one.omega_body, batch.omega_body[:, i])
        q, w1 = it.METHODS[name](Q0, w[i], I[i], 0.01, TORQUE)
        assert np.array_equal(q, q_b[i]) and np.array_equal(w1, w_b[i])


_FRESH = """
import json, numpy as np
from inertia.dynamics import integrate
out = [integrate([1, 0, 0, 0], [0.3, 1.0, -0.2], [1, 2, 2.5], 0.01, 2000, method=m, record_every=500).omega_body
       .tobytes().hex() for m in {names!r}]
print(json.dumps(out))
"""


def test_integrate_gives_the_same_bits_twice_and_in_a_fresh_process():
    import json
    import subprocess
    import sys

    run = lambda m: it.integrate([1, 0, 0, 0], [0.3, 1.0, -0.2], [1, 2, 2.5], 0.01, 2000, method=m,  # noqa: E731
                                 record_every=500).omega_body.tobytes().hex()
    mine = [run(m) for m in NAMES]
    assert mine == [run(m) for m in NAMES]
    got = subprocess.run([sys.executable, "-c", _FRESH.format(names=NAMES)], capture_output=True, text=True,
                         check=True)
    assert json.loads(got.stdout) == mine


def test_integrate_segments_records_each_segment_end():
    q0 = Q0.copy()
    traj = it.integrate_segments(q0, W0, I_TEST, [30, 0, 7], [0.1, 0.2, 0.05], method="rk4", validate=False)
    assert traj.t.tolist() == pytest.approx([0.0, 3.0, 3.0, 3.35], abs=1e-15) and len(traj) == 4
    one = it.integrate(Q0, W0, I_TEST, 0.1, 30, method="rk4", validate=False)
    assert np.array_equal(traj.omega_body[1], one.omega_body[-1]) and np.array_equal(traj.omega_body[2], traj.omega_body[1])
    assert np.array_equal(q0, Q0)                                  # input untouched
    with pytest.raises(InputError, match="steps must be a 1-D sequence of integers >= 0"):
        it.integrate_segments(Q0, W0, I_TEST, [3, -1], 0.1, validate=False)
    with pytest.raises(InputError, match="h must be a finite non-zero step"):
        it.integrate_segments(Q0, W0, I_TEST, [3, 1], [0.1, 0.0], validate=False)
