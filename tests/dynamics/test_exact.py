"""The exact torque-free solution against a tight DOP853 run, the worked values of the notes,
invariants, periodicity at t = 1e6 s, every regime, and bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import solve_ivp

from inertia._core.rotations import quat_from_rotvec, quat_multiply, quat_to_matrix
from inertia.dynamics.exact import REGIMES, ExactSolution, FreeBody, exact_solution
from inertia.errors import InputError, InvalidInertiaError


# ---------------------------------------------------------------------------- reference
def dop853(moments, omega0, q0, times, rtol=1e-13, atol=1e-13):
    """Euler's equations + quaternion kinematics by DOP853: ``(q (N, 4), omega (N, 3))``."""
    I = np.asarray(moments, float)

    def rhs(_t, y):
        w, q = y[:3], y[3:]
        return np.concatenate([np.cross(I * w, w) / I, 0.5 * quat_multiply(q, np.r_[0.0, w])])

    times = np.asarray(times, float)
    sol = solve_ivp(rhs, (times[0], times[-1]), np.r_[omega0, q0], method="DOP853", rtol=rtol, atol=atol,
                    t_eval=times)
    assert sol.success
    return sol.y[3:].T, sol.y[:3].T


def random_quat(rng):
    q = rng.normal(size=4)
    return q / np.linalg.norm(q)


def compare(moments, omega0, times, seed=0, **kw):
    """Max |d omega| / |omega0| and max |d q| between the exact solution and DOP853."""
    q0 = random_quat(np.random.default_rng(seed))
    body = ExactSolution(moments, omega0, q0, **kw)
    q, w = body.at(times)
    qr, wr = dop853(moments, omega0, q0, times)
    scale = max(np.linalg.norm(omega0), 1e-300)
    return body, np.abs(w - wr).max() / scale, np.abs(q - qr).max()


# ---------------------------------------------------------------------------- worked values (§7)
class TestWorkedExampleTC1:
    """I = (1, 2, 3), w0 = (0.01, 1, 0): the canonical Dzhanibekov body (minor-axis case)."""

    body = ExactSolution([1, 2, 3], [0.01, 1, 0])

    def test_constants(self):
        b = self.body
        assert b.regime == "minor_axis"
        assert b.parameter == pytest.approx(0.999900009999000, abs=1e-15)
        assert b.complementary_parameter == pytest.approx(9.99900009999e-05, rel=1e-12)
        assert b.rate == pytest.approx(0.577379135981, abs=1e-12)
        assert b._motion.K == pytest.approx(5.991639326778, abs=1e-12)
        assert b.period == pytest.approx(41.509219529338, abs=1e-11)
        assert b.flip_interval == pytest.approx(20.7546097647, abs=1e-10)
        assert b.rotation_per_period == pytest.approx(45.6990041521, abs=1e-10)
        assert math.remainder(b.rotation_per_period - 1.7167070019, 2 * math.pi) == pytest.approx(0, abs=1e-10)

    @pytest.mark.parametrize("t, w", [
        ("T/4", (1.000049998750, 0.0, -0.577350269190)),
        ("T/2", (0.01, -1.0, 0.0)),
        ("T", (0.01, 1.0, 0.0)),
        (1.0, (0.011713459529, 0.99998139726, -0.003521606363)),
        (5.0, (0.089780601692, 0.996011768786, -0.051512317104)),
        (10.0, (0.976782616339, 0.214466128837, -0.563916152036)),
    ])
    def test_omega(self, t, w):
        T = self.body.period
        t = {"T/4": T / 4, "T/2": T / 2, "T": T}.get(t, t)
        assert np.allclose(self.body.omega_body(t), w, atol=2e-11, rtol=0)

    def test_attitude_at_5(self):
        assert float(self.body.psi(5.0)) == pytest.approx(5.075808334632, abs=1e-11)
        R5 = [[0.282050200242, -0.081848833532, -0.955901905528],
              [0.043480049845, 0.996421012953, -0.072488966128],
              [0.958413882312, -0.021117135087, 0.284599537591]]
        assert np.allclose(self.body.R_world_body(5.0), R5, atol=2e-12, rtol=0)


def test_worked_example_TC3_hlw_body():
    """Hairer-Lubich-Wanner's test body: it violates the triangle inequality, so validate=False."""
    w0 = np.array([math.sin(1.1) / (2 / 3), 0.0, math.cos(1.1) / 2])
    assert np.allclose(w0, [1.336811040092, 0, 0.226798060713], atol=1e-12)
    with pytest.raises(InvalidInertiaError, match="triangle inequality"):
        ExactSolution([2 / 3, 1, 2], w0)
    b = ExactSolution([2 / 3, 1, 2], w0, validate=False)
    assert b.regime == "minor_axis"
    assert b.parameter == pytest.approx(0.259048532150643, abs=1e-14)
    assert b.rate == pytest.approx(0.630178767743, abs=1e-12)
    assert b._motion.u0 == pytest.approx(0.0, abs=1e-15)
    assert b._motion.n == pytest.approx(-1.0, abs=1e-15)
    assert b.period == pytest.approx(10.731465234883, abs=1e-11)
    assert np.allclose(b.omega_body([1, 5, 10]), [[1.276977909105, 0.372846321121, 0.184555040425],
                                                  [1.327784854342, 0.146214872301, -0.220828013922],
                                                  [1.302673751492, -0.283007426813, 0.203533068294]],
                       atol=2e-12, rtol=0)
    assert b.psi([1.0, 10.0]) == pytest.approx([1.390387771427, 13.871347522008], abs=1e-11)
    assert b.rotation_per_period == pytest.approx(14.8886359733, abs=1e-9)


# ---------------------------------------------------------------------------- against DOP853
CASES = [
    # (moments, omega0, regime) -- both circulation cases, every sign, unsorted moments
    ([1, 2, 3], [0.1, 1, 0], "minor_axis"),
    ([1, 2, 3], [0.01, 1, 0.01], "major_axis"),
    ([2, 3, 4], [1, 0.2, -0.3], "minor_axis"),
    ([1, 2, 3], [-0.4, 0.3, -0.7], "major_axis"),
    ([0.5, 0.9, 1.3], [0.3, -1.2, 0.5], "major_axis"),
    ([1, 2, 3], [0.02, -1, -0.01], "minor_axis"),
    ([3, 1, 2], [0.3, -0.2, 0.5], "major_axis"),
    ([2.5, 2, 1], [-0.2, 0.1, 0.9], "minor_axis"),
    ([1, 3, 2], [0.7, -0.4, 0.6], "minor_axis"),
]


@pytest.mark.parametrize("moments, omega0, regime", CASES)
def test_matches_dop853_over_three_periods(moments, omega0, regime):
    b = ExactSolution(moments, omega0)
    times = np.linspace(0, 3 * b.period, 241)
    b, dw, dq = compare(moments, omega0, times, seed=len(CASES))
    assert b.regime == regime
    assert dw < 1e-10 and dq < 1e-10


@pytest.mark.parametrize("omega0, one_minus_m", [([0.01, 1, 0], 1e-4), ([0.003, -1, 0.0], 9e-6)])
def test_near_separatrix_matches_dop853(omega0, one_minus_m):
    b = ExactSolution([1, 2, 3], omega0)
    assert b.complementary_parameter == pytest.approx(one_minus_m, rel=0.3)
    times = np.linspace(0, 2 * b.period, 201)
    _, dw, dq = compare([1, 2, 3], omega0, times, seed=5)
    # ill-conditioned: DOP853's own error is amplified by ~1/k' at every passage by the saddle
    assert dw < 1e-9 and dq < 1e-9


@pytest.mark.parametrize("moments, omega0, regime", [
    ([1.5, 1.5, 2.5], [0.3, -0.4, 1.1], "symmetric_top"),      # oblate, I1 = I2
    ([2, 1, 2], [0.3, 0.5, -0.2], "symmetric_top"),            # prolate, unsorted (I2 = I3)
    ([1, 1, 1], [0.3, 0.2, 0.1], "sphere"),
    ([1, 2, 3], [0, 1.3, 0], "steady_spin"),                   # unstable axis, exactly on it
    ([1, 2, 3], [0, 0, -0.8], "steady_spin"),
    ([1.5, 1.5, 2.5], [0, 0, 2.0], "steady_spin"),
    ([1, 2, 3], [0, 0, 0], "rest"),
])
def test_special_regimes_match_dop853(moments, omega0, regime):
    times = np.linspace(0, 20, 81)
    b, dw, dq = compare(moments, omega0, times, seed=2)
    assert b.regime == regime
    assert dw < 1e-11 and dq < 1e-11


@pytest.mark.parametrize("gap", [1e-6, 1e-12, 1e-15])
def test_nearly_symmetric_moments_use_stable_formulas(gap):
    for omega0 in ([0.3, 0.2, 1.0], [1.0, 0.02, 0.03]):
        times = np.linspace(0, 20, 41)
        b, dw, dq = compare([1, 1 + gap, 1.5], omega0, times)
        assert dw < 1e-12 and dq < 1e-11, b.regime


@pytest.mark.parametrize("s1, s3", [(1, 1), (-1, 1), (1, -1), (-1, -1)])
def test_separatrix_matches_dop853(s1, s3):
    # I = (3, 4, 6): D2 = (m3^2 - m1^2)/3, exactly zero for |m1| = |m3| = 0.75
    omega0 = [s1 * 0.25, 0.5, s3 * 0.125]
    times = np.linspace(0, 15, 61)
    b, dw, dq = compare([3, 4, 6], omega0, times, seed=3)
    assert b.regime == "separatrix" and b.period == math.inf and b.flip_interval == math.inf
    assert dw < 1e-12 and dq < 1e-11
    # and it tends to spin about +-e2 without overflow at huge times
    q, w = b.at(1e6)
    assert np.all(np.isfinite(q)) and np.all(np.isfinite(w))
    assert abs(abs(w[1]) * 4 - b.angular_momentum_norm) < 1e-12


def test_local_consistency_very_near_separatrix_and_at_large_times():
    """1 - m = 2e-12: a DOP853 run over the whole motion is meaningless (its error is amplified
    by 1/k' = 7e5 per passage), so restart it from the exact state at many times and
    integrate 3 s."""
    b = ExactSolution([1, 2, 3], [1e-6, 1, 1e-6], random_quat(np.random.default_rng(11)))
    assert b.complementary_parameter < 3e-12
    worst = {}
    for t0 in (0.0, 23.0, 51.4, b.period / 2, 0.9 * b.period, 1e3, 1e6):
        times = t0 + np.linspace(0, 3, 7)
        q, w = b.at(times)
        qr, wr = dop853([1, 2, 3], w[0], q[0], times - t0)
        worst[t0] = max(np.abs(w - wr).max(), np.abs(q - qr).max())
    # t0 <= 1e3: rounding of u = lam t + u0 is ~1e-13; at 1e6 it is eps * 6e5 = 1e-10
    assert max(v for k, v in worst.items() if k < 1e4) < 1e-11
    assert worst[1e6] < 1e-9


# ---------------------------------------------------------------------------- invariants
@pytest.mark.parametrize("moments, omega0", [
    ([1, 2, 3], [0.01, 1, 0]), ([1, 2, 3], [-0.4, 0.3, -0.7]), ([1, 2, 3], [1e-6, 1, 1e-6]),
    ([3, 4, 6], [0.25, 0.5, 0.125]), ([1.5, 1.5, 2.5], [0.3, -0.4, 1.1]), ([2, 3, 4], [1, 0.2, -0.3]),
])
def test_invariants_to_rounding_up_to_1e6(moments, omega0):
    rng = np.random.default_rng(1)
    b = ExactSolution(moments, omega0, random_quat(rng))
    t = np.concatenate([np.linspace(0, 100, 2001), rng.uniform(0, 1e6, 2000)])
    q, w = b.at(t)
    I = np.asarray(moments, float)
    E = 0.5 * np.sum(I * w * w, axis=-1)
    G = np.linalg.norm(I * w, axis=-1)
    L = np.einsum("...ij,...j->...i", quat_to_matrix(q), I * w)
    assert np.abs(E / b.energy - 1).max() < 2e-15
    assert np.abs(G / b.angular_momentum_norm - 1).max() < 2e-15
    assert np.abs(L - b.angular_momentum_world).max() / b.angular_momentum_norm < 4e-15
    assert np.abs(np.linalg.norm(q, axis=-1) - 1).max() < 1e-15


def test_quaternion_is_continuous_and_starts_at_q0():
    q0 = random_quat(np.random.default_rng(4))
    b = ExactSolution([1, 2, 3], [0.01, 1, 0], q0)
    q = b.q_world_body(np.linspace(0, 200, 20001))
    assert np.allclose(q[0], q0, atol=1e-15)
    assert np.min(np.sum(q[1:] * q[:-1], axis=-1)) > 0.99


@pytest.mark.parametrize("moments, omega0", [([1, 2, 3], [0.01, 1, 0]), ([1, 2, 3], [-0.4, 0.3, -0.7]),
                                             ([1, 2, 3], [1e-6, 1, 1e-6]), ([3, 1, 2], [0.3, -0.2, 0.5])])
def test_periodicity_at_1e6(moments, omega0):
    """omega(t + T) = omega(t) and R(t + T) = Rot(L, DeltaPsi) R(t), at t = 1e6 s in one call each."""
    b = ExactSolution(moments, omega0, random_quat(np.random.default_rng(9)))
    T = b.period
    for t in (0.0, 1e6):
        (qa, wa), (qb, wb) = b.at(t), b.at(t + T)
        L_hat = b.angular_momentum_world / b.angular_momentum_norm
        q_expected = quat_multiply(quat_from_rotvec(L_hat * b.rotation_per_period), qa)
        tol = 1e-12 if t == 0 else 2e-10     # eps * lam * t rounding of the phase
        assert np.abs(wa - wb).max() < tol
        assert min(np.abs(q_expected - qb).max(), np.abs(q_expected + qb).max()) < tol


def test_rotation_per_period_against_dop853():
    q0 = random_quat(np.random.default_rng(8))
    for moments, omega0 in (([1, 2, 3], [0.01, 1, 0]), ([1, 2, 3], [-0.4, 0.3, -0.7])):
        b = ExactSolution(moments, omega0, q0)
        qr, _ = dop853(moments, omega0, q0, [0.0, b.period])
        L_hat = b.angular_momentum_world / b.angular_momentum_norm
        q_expected = quat_multiply(quat_from_rotvec(L_hat * b.rotation_per_period), q0)
        R_diff = quat_to_matrix(q_expected) - quat_to_matrix(qr[-1])
        assert np.abs(R_diff).max() < 1e-11


@settings(max_examples=25, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1))
def test_random_bodies_match_dop853(seed):
    rng = np.random.default_rng(seed)
    I1 = rng.uniform(0.2, 2.0)
    I2 = rng.uniform(I1, 2.0)
    I = rng.permutation([I1, I2, rng.uniform(I2, I1 + I2)])   # physical: I1 + I2 >= I3
    w0 = rng.normal(size=3) * rng.uniform(0.1, 3.0)
    times = np.linspace(0, 4, 9)
    body, dw, dq = compare(I, w0, times, seed=seed)
    assert body.regime in REGIMES
    assert dw < 1e-10 and dq < 1e-10


@pytest.mark.parametrize("scale", [1e-150, 1e-20, 1e20, 1e150])
def test_scaling_symmetry(scale):
    """omega -> s omega, t -> t / s maps solutions onto solutions; no under/overflow at any scale."""
    ref = ExactSolution([1, 2, 3], [0.01, 1, 0])
    b = ExactSolution([1, 2, 3], np.array([0.01, 1, 0]) * scale)
    assert b.regime == ref.regime and b.period * scale == pytest.approx(ref.period, rel=1e-14)
    t = np.array([1.0, 10.0, 33.3])
    q, w = b.at(t / scale)
    qr, wr = ref.at(t)
    assert np.allclose(w / scale, wr, atol=1e-13) and np.allclose(q, qr, atol=1e-13)


# ---------------------------------------------------------------------------- API and input
def test_shapes_and_aliases():
    q, w = exact_solution([1, 2, 3], [0.01, 1, 0], 2.0)
    assert q.shape == (4,) and w.shape == (3,)
    q, w = exact_solution([1, 2, 3], [0.01, 1, 0], np.zeros((2, 5)))
    assert q.shape == (2, 5, 4) and w.shape == (2, 5, 3)
    assert FreeBody is ExactSolution
    b = FreeBody([1, 2, 3], [0.01, 1, 0])
    assert np.allclose(b(3.0)[1], b.at(3.0)[1])
    assert b.R_world_body([0.0, 1.0]).shape == (2, 3, 3)
    assert "minor_axis" in repr(b)


def test_period_and_flip_interval_by_regime():
    assert math.isnan(ExactSolution([1, 1, 1], [1, 2, 3]).period)
    assert math.isnan(ExactSolution([1, 1, 1], [1, 2, 3]).flip_interval)
    assert math.isnan(ExactSolution([1, 2, 3], [0, 0, 0]).flip_interval)
    assert ExactSolution([1, 2, 3], [0, 1, 0]).flip_interval == math.inf
    top = ExactSolution([1.5, 1.5, 2.5], [0.3, -0.4, 1.1])
    assert top.period == pytest.approx(2 * math.pi / abs((2.5 - 1.5) * 1.1 / 1.5))
    assert math.isnan(top.flip_interval)


def test_flip_times_are_zeros_of_the_intermediate_component():
    b = ExactSolution([1, 2, 3], [0.01, 1, 0])
    ft = b.flip_times(0, 100)
    assert np.allclose(ft, [10.3773048823, 31.1319146470, 51.8865244, 72.6411342, 93.3957440], atol=1e-6)
    assert np.abs(b.omega_body(ft)[:, 1]).max() < 1e-13


@pytest.mark.parametrize("moments, match", [
    ([1, 2, 4], r"moments = \(1, 2, 4\) kg m\^2 are not the principal moments of a physical body: "
                r"inertia fails the triangle inequality: I1 \+ I2 = 3 < I3 = 4"),
    ([0, 2, 2], "not positive definite"),
    ([-1, 2, 2], "not positive definite"),
])
def test_non_physical_moments_are_refused(moments, match):
    with pytest.raises(InvalidInertiaError, match=match):
        ExactSolution(moments, [1, 0, 0])


@pytest.mark.parametrize("kwargs, match", [
    ({"moments": [1, np.nan, 2]}, "moments holds a non-finite value"),
    ({"moments": [1, 2]}, r"moments must have shape \(3,?\), got \(2,\)"),
    ({"omega0_body": [1, np.inf, 0]}, "omega0_body holds a non-finite value"),
    ({"q0_world_body": [1, 1, 0, 0]}, r"q0_world_body must be a unit quaternion .* \|q\| = 1.41421356237"),
    ({"t": [0, np.nan]}, "t must hold finite times"),
])
def test_bad_input_is_refused_with_the_argument_named(kwargs, match):
    args = {"moments": [1, 2, 3], "omega0_body": [0.1, 1, 0], "t": 1.0, "q0_world_body": (1, 0, 0, 0)}
    args.update(kwargs)
    with pytest.raises(InputError, match=match):
        exact_solution(**args)
