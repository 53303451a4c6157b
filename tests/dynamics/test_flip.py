"""Dzhanibekov flip: predicted interval, detection in simulated trajectories (exact and DOP853),
and the linear stability of steady spin about each principal axis."""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from inertia.dynamics.exact import ExactSolution, exact_solution
from inertia.dynamics.flip import (
    axis_stability,
    detect_flips,
    euler_jacobian,
    flip_interval,
    flip_interval_approx,
    flip_times,
    intermediate_axis,
    unstable_axis,
)
from inertia.errors import InputError, InvalidInertiaError

REFERENCE_INTERVAL = 20.7546097647      # I = (1, 2, 3), w0 = (0.01, 1, 0): shared/notes §3


def dop853_omega(moments, omega0, times, atol=1e-13):
    I = np.asarray(moments, float)
    sol = solve_ivp(lambda _t, w: np.cross(I * w, w) / I, (times[0], times[-1]), omega0, method="DOP853",
                    rtol=1e-13, atol=atol, t_eval=times)
    return sol.y.T


# ---------------------------------------------------------------------------- prediction
def test_reference_flip_interval():
    assert flip_interval([1, 2, 3], [0.01, 1, 0]) == pytest.approx(REFERENCE_INTERVAL, abs=1e-10)
    # the same body with its axes relabelled (unsorted moments) flips at the same rate
    assert flip_interval([2, 3, 1], [1, 0, 0.01]) == pytest.approx(REFERENCE_INTERVAL, abs=1e-10)


def test_near_separatrix_approximation():
    assert flip_interval_approx([1, 2, 3], [0.01, 1, 0]) == pytest.approx(20.7541775282, abs=1e-10)
    assert flip_interval_approx([1, 2, 3], [0.01, 1, 0], order=1) == pytest.approx(REFERENCE_INTERVAL, abs=1e-7)
    # the relative error of the log formula is ~ (1 - m)/4 and vanishes at the separatrix
    for eps in (1e-2, 1e-4, 1e-6):
        sol = ExactSolution([1, 2, 3], [eps, 1, 0])
        rel = 1 - flip_interval_approx([1, 2, 3], [eps, 1, 0]) / sol.flip_interval
        assert 0 < rel < 0.3 * sol.complementary_parameter
    with pytest.raises(InputError, match="order must be 0 or 1"):
        flip_interval_approx([1, 2, 3], [0.01, 1, 0], order=2)


def test_flip_interval_grows_logarithmically_as_the_wobble_shrinks():
    T = [flip_interval([1, 2, 3], [eps, 1, 0]) for eps in (1e-2, 1e-4, 1e-6, 1e-8)]
    steps = np.diff(T)
    # each factor 100 in the wobble adds (2 / lam) ln(100) with lam -> sqrt(1/3) (G = 2, Omega = 1)
    assert np.allclose(steps, 2 / math.sqrt(1 / 3) * math.log(100), rtol=1e-3)


def test_flip_interval_in_other_regimes():
    assert flip_interval([1, 2, 3], [0, 1, 0]) == math.inf           # steady (unstable) spin
    assert flip_interval([3, 4, 6], [0.25, 0.5, 0.125]) == math.inf  # separatrix: one flip, infinitely slow
    assert math.isnan(flip_interval([1, 1, 2], [0.1, 1, 0.2]))       # no unique intermediate axis
    assert math.isnan(flip_interval_approx([1, 1, 2], [0.1, 1, 0.2]))


def test_flip_times_of_the_reference_body():
    ft = flip_times([1, 2, 3], [0.01, 1, 0], 100.0)
    assert ft[0] == pytest.approx(10.3773048823, abs=1e-9)          # T/4 (u0 = K)
    assert np.allclose(np.diff(ft), REFERENCE_INTERVAL, atol=1e-9)
    assert flip_times([1, 2, 3], [0.01, 1, 0], 40.0, t_start=20.0) == pytest.approx([31.1319146470], abs=1e-9)


# ---------------------------------------------------------------------------- detection
def test_detects_flips_of_the_exact_solution_at_the_predicted_times():
    ts = np.arange(0.0, 150.0, 0.05)
    _, w = exact_solution([1, 2, 3], [0.01, 1, 0], ts)
    flips = detect_flips(ts, w, [1, 2, 3])
    expected = flip_times([1, 2, 3], [0.01, 1, 0], 150.0)
    assert len(flips) == len(expected) == 7
    assert np.abs(flips.times - expected).max() < 1e-8        # cubic location, h = 0.05
    assert np.allclose(flips.intervals, REFERENCE_INTERVAL, atol=1e-8)
    assert flips.directions.tolist() == [-1, 1, -1, 1, -1, 1, -1]
    assert flips.axis == 1


def test_detects_flips_in_a_dop853_trajectory():
    ts = np.arange(0.0, 110.0, 0.02)
    w = dop853_omega([1, 2, 3], np.array([0.01, 1.0, 0.0]), ts)
    flips = detect_flips(ts, w, [1, 2, 3])
    assert len(flips) == 5
    assert np.abs(flips.intervals - REFERENCE_INTERVAL).max() < 1e-8
    assert flips.times[0] == pytest.approx(10.3773048823, abs=1e-8)


def test_detects_flips_in_the_major_axis_regime_and_with_unsorted_moments():
    # relabel axes: moments (3, 1, 2) -> intermediate axis is z (index 2)
    w0 = np.array([0.01, 0.01, 1.0])
    sol = ExactSolution([3, 1, 2], w0)
    assert sol.regime == "major_axis"
    ts = np.arange(0.0, 3 * sol.period, 0.05)
    flips = detect_flips(ts, sol.omega_body(ts), [3, 1, 2])
    assert flips.axis == 2
    assert np.allclose(flips.intervals, sol.flip_interval, atol=1e-7)


def test_wobble_about_a_stable_axis_is_not_a_flip():
    ts = np.arange(0.0, 60.0, 0.05)
    _, w = exact_solution([1, 2, 3], [1.0, 0.1, 0.1], ts)        # small cone about the minor axis
    assert len(detect_flips(ts, w, [1, 2, 3])) == 0
    sign_changes = detect_flips(ts, w, [1, 2, 3], threshold=0.0)   # but w2 does change sign
    period = ExactSolution([1, 2, 3], [1.0, 0.1, 0.1]).period
    assert len(sign_changes) >= 2 and np.allclose(sign_changes.intervals, period / 2, atol=1e-4)


def test_hysteresis_counts_a_jittery_crossing_once():
    t = np.linspace(0, 10, 1001)
    n2 = np.cos(np.pi * t / 10)                     # from +1 to -1, crossing at t = 5
    n2[(t > 4.9) & (t < 5.1)] = 1e-3 * np.sin(40 * t[(t > 4.9) & (t < 5.1)])   # jitter near zero
    w = np.stack([np.sqrt(1 - n2 ** 2), n2, np.zeros_like(t)], axis=-1) / np.array([1.0, 2.0, 3.0])
    flips = detect_flips(t, w, [1, 2, 3])
    assert len(flips) == 1 and flips.directions.tolist() == [-1]
    assert 4.9 <= flips.times[0] <= 5.1
    assert len(detect_flips(t, w, [1, 2, 3], threshold=0.0)) > 1


@pytest.mark.parametrize("args, match", [
    (([0, 2, 1], np.zeros((3, 3)), [1, 2, 3]), "t must be strictly increasing"),
    (([0, 1, 2], np.zeros((2, 3)), [1, 2, 3]), r"omega_body must have shape \(N, 3\) = \(3, 3\)"),
    (([0, 1, 2], np.zeros((3, 3)), [1, 1, 2]), "no unique intermediate axis"),
    (([0, 1, 2], np.zeros((3, 3)), [1, 2, np.nan]), "moments holds a non-finite value"),
])
def test_detect_flips_refuses_bad_input(args, match):
    with pytest.raises(InputError, match=match):
        detect_flips(*args)


def test_detect_flips_threshold_range():
    with pytest.raises(InputError, match=r"threshold must lie in \[0, 1\)"):
        detect_flips([0, 1], np.ones((2, 3)), [1, 2, 3], threshold=1.0)


def test_intermediate_axis():
    assert intermediate_axis([1, 2, 3]) == 1
    assert intermediate_axis([3, 1, 2]) == 2
    assert intermediate_axis([2, 3, 1]) == 0


# ---------------------------------------------------------------------------- stability
def test_stability_worked_values_TC6():
    s = axis_stability([1, 2, 3], 1.0)
    r = 0.5773502691896
    assert np.allclose(s[0].eigenvalues, [0, 1j * r, -1j * r], atol=1e-12)
    assert np.allclose(s[1].eigenvalues, [0, r, -r], atol=1e-12)
    assert np.allclose(s[2].eigenvalues, [0, 1j, -1j], atol=1e-12)
    assert [x.classification for x in s] == ["stable", "unstable", "stable"]
    assert s[1].growth_rate == pytest.approx(r, abs=1e-12) and s[0].frequency == pytest.approx(r, abs=1e-12)
    assert unstable_axis([1, 2, 3]) == 1 and unstable_axis([2, 3, 1]) == 0


@pytest.mark.parametrize("seed", range(6))
def test_eigenvalues_formula_and_jacobian(seed):
    rng = np.random.default_rng(seed)
    I1 = rng.uniform(0.3, 2)
    I2 = rng.uniform(I1 * 1.05, 2.5)
    I3 = rng.uniform(I2 * 1.05, I1 + I2)
    order = rng.permutation(3)
    I = np.array([I1, I2, I3])[order]
    Omega = rng.uniform(0.1, 5) * rng.choice([-1, 1])
    stab = axis_stability(I, Omega)
    for s in stab:
        w = np.zeros(3)
        w[s.axis] = Omega
        J = euler_jacobian(I, w)
        # finite-difference Jacobian of the Euler equations (checks euler_jacobian too)
        f = lambda v: np.cross(I * v, v) / I                      # noqa: E731
        h = 1e-6
        J_fd = np.stack([(f(w + h * e) - f(w - h * e)) / (2 * h) for e in np.eye(3)], axis=-1)
        assert np.allclose(J, J_fd, atol=1e-8)
        num = np.sort_complex(np.linalg.eigvals(J))
        assert np.allclose(num, np.sort_complex(s.eigenvalues), atol=1e-10)
    inter = int(np.flatnonzero(order == 1)[0])              # body index of the intermediate moment
    expected = abs(Omega) * math.sqrt((I2 - I1) * (I3 - I2) / (I1 * I3))
    assert stab[inter].classification == "unstable"
    assert stab[inter].growth_rate == pytest.approx(expected, rel=1e-13)
    for s in stab:
        if s.axis != inter:
            assert s.classification == "stable" and np.all(np.abs(s.eigenvalues.real) == 0)


def test_separatrix_rate_equals_linear_growth_rate():
    """On the separatrix lam = (G/I2) sqrt((I3-I2)(I2-I1)/(I1 I3)): the axis-2 exponent at Omega = G/I2."""
    sol = ExactSolution([3, 4, 6], [0.25, 0.5, 0.125])
    growth = axis_stability([3, 4, 6], sol.angular_momentum_norm / 4)[1].growth_rate
    assert sol.rate == pytest.approx(growth, rel=1e-14)


def test_small_perturbation_grows_at_the_predicted_rate():
    eps = 1e-9
    ts = np.linspace(0, 12, 7)
    w = dop853_omega([1, 2, 3], np.array([eps, 1.0, 0.0]), ts, atol=1e-24)
    lam = axis_stability([1, 2, 3], 1.0)[1].growth_rate
    # linearised: dw1' = -dw3, dw3' = -dw1/3, so dw1 = eps cosh(lam t), dw3 = -eps lam sinh(lam t)
    assert np.allclose(w[:, 0], eps * np.cosh(lam * ts), rtol=1e-6, atol=0)
    assert np.allclose(w[:, 2], -eps * lam * np.sinh(lam * ts), rtol=1e-6, atol=1e-24)


def test_degenerate_and_invalid_moments():
    s = axis_stability([1, 1, 2], 1.0)
    assert [x.classification for x in s] == ["marginal", "marginal", "stable"]
    assert unstable_axis([1, 1, 2]) is None
    assert [x.classification for x in axis_stability([1, 2, 3], 0.0)] == ["marginal"] * 3
    with pytest.raises(InvalidInertiaError, match="triangle inequality"):
        axis_stability([1, 2, 4])
    with pytest.raises(InputError, match="rate must be finite"):
        axis_stability([1, 2, 3], math.nan)
