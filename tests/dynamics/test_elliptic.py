"""Jacobi elliptic functions and elliptic integrals against mpmath, including 1 - m down to 1e-15
at large arguments, where ``scipy.special.ellipj`` is wrong by up to 1e22."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.special as sc

from inertia.dynamics.elliptic import ellipe, ellipeinc, ellipj, ellipk, ellipkinc, ellippi, ellippiinc, jacobi_reduced
from inertia.errors import InputError

mp = pytest.importorskip("mpmath")
mp.mp.dps = 40

#: complementary parameters 1 - m of the mpmath comparison (strings: exact in mpmath)
MCS = ["0.7", "1e-4", "1e-9", "1e-12", "1e-15"]


def _mpm(mc_text):
    return 1 - mp.mpf(mc_text)


@pytest.mark.parametrize("mc_text", MCS)
def test_sn_cn_dn_am_match_mpmath_at_large_arguments(mc_text):
    mc = float(mp.mpf(mc_text))
    m = _mpm(mc_text)
    K = float(mp.ellipk(m))
    u = np.linspace(-3.7 * K, 5.3 * K, 23)
    r = jacobi_reduced(u, mc=mc)
    err = 0.0
    err_am = 0.0
    for k, uk in enumerate(u):
        ref = [mp.ellipfun(f, mp.mpf(uk), m=m) for f in ("sn", "cn", "dn")]
        err = max(err, max(abs(float(x) - y) for x, y in zip(ref, (r.sn[k], r.cn[k], r.dn[k]))))
        # am(u) = j pi + atan2(sn_r, cn_r) on the branch of the reduction
        par = -1 if int(r.j[k]) % 2 else 1
        am_ref = r.j[k] * mp.pi + mp.atan2(par * ref[0], par * ref[1])
        err_am = max(err_am, abs(float(am_ref) - r.am[k]))
    assert err < 1e-14
    assert err_am < 2e-14


def test_scipy_ellipj_is_broken_where_ours_is_not():
    """The reason for the module: raw scipy at 1 - m = 1e-12, u = 3.5 K is off by orders of magnitude."""
    mc = 1e-12
    m = _mpm("1e-12")
    u = 3.5 * float(mp.ellipk(m))
    ref = float(mp.ellipfun("dn", mp.mpf(u), m=m))
    assert abs(sc.ellipj(u, 1 - mc)[2] - ref) > 1.0
    assert abs(ellipj(u, mc=mc)[2] - ref) < 1e-14


def test_parameter_and_complementary_parameter_agree_when_m_is_exact():
    u = np.linspace(-20, 20, 41)
    for m in (0.0, 0.3, 0.9, 0.999):
        a = np.array(ellipj(u, m))
        b = np.array(ellipj(u, mc=1 - m))
        assert np.max(np.abs(a - b)) < 1e-14
        assert np.max(np.abs(a[:3] - np.array(sc.ellipj(u, m))[:3])) < 1e-13


def test_limits_m0_and_m1():
    u = np.linspace(-30, 30, 61)
    sn, cn, dn, am = ellipj(u, 0.0)
    assert np.allclose(sn, np.sin(u), atol=1e-14) and np.allclose(cn, np.cos(u), atol=1e-14)
    assert np.allclose(dn, 1.0) and np.allclose(am, u, atol=1e-13)
    sn, cn, dn, am = ellipj(u, 1.0)
    assert np.allclose(sn, np.tanh(u), atol=1e-15) and np.allclose(cn, 1 / np.cosh(u), atol=1e-15)
    assert np.allclose(dn, 1 / np.cosh(u), atol=1e-15)
    assert np.allclose(am, 2 * np.arctan(np.tanh(u / 2)), atol=1e-15)


def test_identities_and_periodicity():
    rng = np.random.default_rng(3)
    mc = 10.0 ** rng.uniform(-15, 0, 200)
    u = rng.uniform(-1e3, 1e3, 200)
    sn, cn, dn, am = ellipj(u, mc=mc)
    assert np.max(np.abs(sn ** 2 + cn ** 2 - 1)) < 4e-15
    assert np.max(np.abs(dn ** 2 + (1 - mc) * sn ** 2 - 1)) < 4e-15
    K = ellipk(mc=mc)
    sn2, cn2, dn2, am2 = ellipj(u + 4 * K, mc=mc)
    # u + 4K rounds by eps |u|; the functions are 1-Lipschitz in u
    tol = 4e-16 * (np.abs(u) + 4 * K) + 1e-15
    assert np.all(np.abs(sn2 - sn) <= tol) and np.all(np.abs(cn2 - cn) <= tol)
    assert np.all(np.abs(am2 - am - 2 * np.pi) <= 2 * tol + 1e-13)


def test_broadcasting_and_nan():
    sn, cn, dn, am = ellipj(np.zeros((4, 1)), np.array([0.1, 0.5, 0.9]))
    assert sn.shape == (4, 3)
    assert np.all(np.isnan(ellipj(np.nan, 0.5)[0]))
    assert np.ndim(ellipj(1.0, 0.5)[0]) == 0


@pytest.mark.parametrize("bad", [-0.1, 1.5, np.nan])
def test_parameter_outside_unit_interval_is_refused(bad):
    with pytest.raises(InputError, match=r"m must lie in \[0, 1\]"):
        ellipj(1.0, bad)
    with pytest.raises(InputError, match=r"mc must lie in \[0, 1\]"):
        ellipk(mc=bad)


# ---------------------------------------------------------------------------- integrals
@pytest.mark.parametrize("n, phi, m, value", [
    (-0.5, 0.7, 0.3, 0.668623630626626),
    (-2.0, 2.5, 0.9, 2.029805107551959),
    (-0.25, 7.0, 0.99, 13.31665853536122),
    (-1.5, -4.0, 0.5, -2.968936998645166),
])
def test_pi_worked_values_of_the_note(n, phi, m, value):
    assert abs(float(ellippiinc(n, phi, m)) - value) < 1e-14


def test_integrals_match_mpmath():
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(25):
        mc_text = f"{10.0 ** rng.uniform(-12, 0):.6e}"
        m = _mpm(mc_text)
        mc = float(mp.mpf(mc_text))
        phi = rng.uniform(-12, 12)
        n = -10.0 ** rng.uniform(-2, 1.5)
        pairs = [
            (ellipkinc(phi, mc=mc), mp.ellipf(phi, m)),
            (ellipeinc(phi, mc=mc), mp.ellipe(phi, m)),
            (ellippiinc(n, phi, mc=mc), mp.ellippi(n, phi, m)),
            (ellipk(mc=mc), mp.ellipk(m)),
            (ellipe(mc=mc), mp.ellipe(m)),
            (ellippi(n, mc=mc), mp.ellippi(n, m)),
        ]
        for ours, ref in pairs:
            worst = max(worst, abs(float(ours) - float(ref)) / max(1.0, abs(float(ref))))
    assert worst < 2e-14


def test_positive_characteristic_below_one():
    for n in (0.3, 0.9):
        for phi in (0.4, 1.5, 5.0):
            assert abs(float(ellippiinc(n, phi, 0.6)) - float(mp.ellippi(n, phi, 0.6))) < 1e-13


def test_characteristic_at_or_above_one_is_refused():
    with pytest.raises(InputError, match="n must be < 1"):
        ellippiinc(1.0, 0.3, 0.5)
    with pytest.raises(InputError, match="n must be < 1"):
        ellippi(2.0, 0.5)


def test_am_and_F_are_inverse():
    u = np.linspace(-40, 40, 81)
    for mc in (0.5, 1e-3, 1e-8):
        am = ellipj(u, mc=mc)[3]
        # F is ill-conditioned near am = pi/2 + j pi (slope 1/dn up to 1/sqrt(mc))
        assert np.max(np.abs(ellipkinc(am, mc=mc) - u)) < 1e-14 / np.sqrt(mc) * 40
