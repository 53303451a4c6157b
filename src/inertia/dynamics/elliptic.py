"""Jacobi elliptic functions and elliptic integrals that stay accurate next to ``m = 1``.

Everything uses the **parameter** ``m = k^2`` (as scipy and mpmath do), accepts arrays
and broadcasts them.  Every function also takes the complementary parameter
``mc = 1 - m`` as an optional keyword: near the separatrix of the free rigid body ``1 - m``
is known to full relative precision from a ratio of invariants while ``m`` itself, as a
double, has lost it (``m = 1 - 1e-12`` keeps only four significant digits of ``1 - m``).
When ``mc`` is given it is used for every ``1 - m`` quantity and ``m`` is taken as
``1 - mc``.

Why this module exists
----------------------
``scipy.special.ellipj(u, m)`` switches to an ``m -> 1`` asymptotic expansion when
``1 - m < 1e-9`` which is only valid for small ``|u|``: against mpmath its error reaches
1e22 at ``1 - m = 1e-12`` over a few periods (see ``docs/exact-solution.md``).  Here the
argument is reduced first, ``u = 2 K j + r`` with ``|r| <= K`` and, when ``|r| > K/2``,
``v = K - |r|``, and scipy is called only on ``|v| <= K/2`` where every branch of its
algorithm is accurate.  The quarter-period shift uses::

    sn(K - v) = cd(v),   cn(K - v) = k' sd(v),   dn(K - v) = k' nd(v),
    am(K - v) = atan2(cn v, k' sn v)

and the half-period shift ``sn, cn -> (-1)^j sn, (-1)^j cn``, ``am -> am + j pi``.

The integrals are Carlson's symmetric forms (``scipy.special.elliprf/elliprd/elliprj``)
with the same reduction of the amplitude, ``phi = j pi + r`` with ``|r| <= pi/2``::

    F(phi|m)    = s R_F(c^2, d^2, 1)                              + 2 j K(m)
    E(phi|m)    = s R_F(c^2, d^2, 1) - (m/3) s^3 R_D(c^2, d^2, 1)   + 2 j E(m)
    Pi(n;phi|m) = s R_F(c^2, d^2, 1) + (n/3) s^3 R_J(c^2, d^2, 1, 1 - n s^2) + 2 j Pi(n|m)

with ``s = sin r``, ``c = cos r`` and ``d^2 = 1 - m s^2`` computed as ``c^2 + mc s^2``
(no cancellation).  ``Pi(n; phi|m) = int_0^phi dt / ((1 - n sin^2 t) sqrt(1 - m sin^2 t))``,
the convention of ``mpmath.ellippi(n, phi, m)``; only ``n < 1`` is supported (no Cauchy
principal value).

References: Carlson, "Numerical computation of real or complex elliptic integrals",
Numer. Algorithms 10 (1995); DLMF 19.25 (Carlson forms), 22.4 and 22.6 (periods and
quarter-period shifts of sn, cn, dn).  The reduction follows ``shared/notes/free-rigid-body.md``
§1.6.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import scipy.special as sc

from .._core.errors import InputError

__all__ = [
    "ellipj",
    "jacobi_reduced",
    "JacobiReduced",
    "ellipk",
    "ellipkinc",
    "ellipe",
    "ellipeinc",
    "ellippi",
    "ellippiinc",
]


# ---------------------------------------------------------------------------- parameters
def _parameters(m, mc):
    """``(m, mc)`` as float arrays in [0, 1], consistent with each other (``mc`` wins)."""
    if mc is None:
        m = np.asarray(m, dtype=float)
        _check_unit_interval(m, "m")
        mc = 1.0 - m
    else:
        mc = np.asarray(mc, dtype=float)
        _check_unit_interval(mc, "mc")
        m = 1.0 - mc
    return m, mc


def _check_unit_interval(x: np.ndarray, name: str) -> None:
    bad = ~((x >= 0.0) & (x <= 1.0))  # also catches NaN
    if np.any(bad):
        value = x[bad].ravel()[0] if x.ndim else float(x)
        raise InputError(f"{name} must lie in [0, 1] (the elliptic parameter m = k^2 and mc = 1 - m), "
                         f"got {value!r}")


def _complete_k(m, mc):
    """K(m), taken from ``ellipkm1(mc)`` so that small ``mc`` keeps full precision (inf at mc = 0)."""
    with np.errstate(divide="ignore"):
        return sc.ellipkm1(mc)


# ---------------------------------------------------------------------------- Jacobi functions
class JacobiReduced(NamedTuple):
    """Jacobi functions at ``u`` together with the reduction ``u = 2 K j + r``, ``|r| <= K``.

    ``sn, cn, dn, am`` are the values at ``u``.  ``j`` (float holding an integer) counts half
    periods, so ``am(u) = j pi + am_r`` with ``am_r = am(r)`` in ``[-pi/2, pi/2]``, and
    ``sn_r = sin(am_r) = (-1)^j sn(u)``, ``cn_r = cos(am_r) = (-1)^j cn(u) >= 0``.
    """

    sn: np.ndarray
    cn: np.ndarray
    dn: np.ndarray
    am: np.ndarray
    j: np.ndarray
    sn_r: np.ndarray
    cn_r: np.ndarray
    am_r: np.ndarray


def jacobi_reduced(u, m=None, *, mc=None) -> JacobiReduced:
    """sn, cn, dn, am of ``(u | m)`` with the period reduction that keeps them accurate.

    Parameters
    ----------
    u : (...) float
        Argument (any real; NaN gives NaN).
    m : (...) float in [0, 1]
        Parameter ``k^2``.  Ignored when ``mc`` is given.
    mc : (...) float in [0, 1], optional
        Complementary parameter ``1 - m``; give it when it is known more accurately than ``m``.

    Returns
    -------
    JacobiReduced
        Arrays of the broadcast shape of ``u`` and ``m``.
    """
    m, mc = _parameters(m, mc)
    u = np.asarray(u, dtype=float)
    u, m, mc = np.broadcast_arrays(u, m, mc)
    K = _complete_k(m, mc)
    sep = mc == 0.0                       # m = 1: sn = tanh, cn = dn = sech, no period
    K_safe = np.where(sep, 1.0, K)
    # u = 2 K j + r, |r| <= K
    j = np.rint(u / (2.0 * K_safe))
    j = np.where(sep | ~np.isfinite(j), 0.0, j)
    r = np.where(sep, u, u - 2.0 * K_safe * j)
    r_abs = np.abs(r)
    sign_r = np.where(r < 0, -1.0, 1.0)
    # beyond K/2 evaluate at the complement v = K - |r| (where scipy is accurate)
    far = (r_abs > 0.5 * K_safe) & ~sep
    v = np.where(far, K_safe - r_abs, r_abs)
    sn_v, cn_v, dn_v, am_v = sc.ellipj(v, m)
    kp = np.sqrt(mc)
    with np.errstate(divide="ignore", invalid="ignore"):
        # quarter-period shift: sn(K - v) = cd v, cn(K - v) = k' sd v, dn(K - v) = k' nd v.
        # cd v = 1 - mc sn^2 / (dn (dn + cn)) (from dn^2 - cn^2 = mc sn^2): the ratio cn/dn
        # would inherit the relative error of m as a double in 1 - cd ~ mc, this form does not.
        sn_a = np.where(far, 1.0 - mc * sn_v * sn_v / (dn_v * (dn_v + cn_v)), sn_v)
        cn_a = np.where(far, kp * sn_v / dn_v, cn_v)
        dn_a = np.where(far, kp / dn_v, dn_v)
    am_a = np.where(far, np.arctan2(cn_v, kp * sn_v), am_v)
    # m = 1 exactly: the separatrix functions (scipy's m = 1 branch is exact, but keep it explicit)
    if np.any(sep):
        ra = np.where(sep, r_abs, 0.0)
        sn_a = np.where(sep, np.tanh(ra), sn_a)
        sech = 1.0 / np.cosh(np.minimum(ra, 710.0))
        cn_a = np.where(sep, sech, cn_a)
        dn_a = np.where(sep, sech, dn_a)
        am_a = np.where(sep, 2.0 * np.arctan(np.tanh(0.5 * ra)), am_a)
    parity = 1.0 - 2.0 * np.mod(j, 2.0)
    sn_r = sign_r * sn_a
    am_r = sign_r * am_a
    return JacobiReduced(sn=parity * sn_r, cn=parity * cn_a, dn=dn_a, am=j * np.pi + am_r,
                         j=j, sn_r=sn_r, cn_r=cn_a, am_r=am_r)


def ellipj(u, m=None, *, mc=None):
    """Jacobi elliptic functions ``(sn, cn, dn, am)`` of ``(u | m)``, accurate for any ``u``.

    A drop-in replacement for :func:`scipy.special.ellipj` that stays accurate when
    ``1 - m`` is tiny and ``|u|`` is large (scipy is wrong by up to 1e22 there).

    Parameters
    ----------
    u : (...) float
        Argument.
    m : (...) float in [0, 1]
        Parameter ``k^2`` (ignored when ``mc`` is given).
    mc : (...) float in [0, 1], optional
        Complementary parameter ``1 - m``.

    Returns
    -------
    sn, cn, dn, am : (...) float
        ``am`` is the continuous, unbounded amplitude (``am(u + 2K) = am(u) + pi``).

    Examples
    --------
    >>> sn, cn, dn, am = ellipj([0.5, 80.0], mc=1e-12)
    >>> sn.shape
    (2,)
    >>> bool(abs(sn[0] - np.tanh(0.5)) < 1e-11)
    True
    """
    r = jacobi_reduced(u, m, mc=mc)
    return r.sn, r.cn, r.dn, r.am


# ---------------------------------------------------------------------------- integrals
def ellipk(m=None, *, mc=None):
    """Complete elliptic integral of the first kind ``K(m)`` (inf at ``m = 1``)."""
    m, mc = _parameters(m, mc)
    return _complete_k(m, mc)


def ellipe(m=None, *, mc=None):
    """Complete elliptic integral of the second kind ``E(m)``.

    ``E = R_F(0, mc, 1) - (m/3) R_D(0, mc, 1)`` (DLMF 19.25.1); ``E(1) = 1``.
    """
    m, mc = _parameters(m, mc)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = sc.elliprf(0.0, mc, 1.0) - m / 3.0 * sc.elliprd(0.0, mc, 1.0)
    return np.where(mc == 0.0, 1.0, out)


def _check_characteristic(n: np.ndarray) -> None:
    bad = ~(n < 1.0)
    if np.any(bad):
        value = n[bad].ravel()[0] if n.ndim else float(n)
        raise InputError(f"n must be < 1 (the characteristic of Pi(n; phi|m); n >= 1 needs a Cauchy "
                         f"principal value, which is not implemented), got {value!r}")


def ellippi(n, m=None, *, mc=None):
    """Complete elliptic integral of the third kind ``Pi(n | m)``, for ``n < 1``.

    ``Pi(n|m) = R_F(0, mc, 1) + (n/3) R_J(0, mc, 1, 1 - n)`` (DLMF 19.25.2).  Diverges
    (inf) at ``m = 1``.
    """
    m, mc = _parameters(m, mc)
    n = np.asarray(n, dtype=float)
    _check_characteristic(n)
    with np.errstate(divide="ignore", invalid="ignore"):
        out = sc.elliprf(0.0, mc, 1.0) + n / 3.0 * sc.elliprj(0.0, mc, 1.0, 1.0 - n)
    return np.where(mc == 0.0, np.inf, out)


def _amplitude_reduction(phi):
    """``phi = j pi + r`` with ``|r| <= pi/2``: returns ``(j, sin r, cos r)`` (cos r >= 0)."""
    phi = np.asarray(phi, dtype=float)
    j = np.rint(phi / np.pi)
    r = phi - j * np.pi
    return j, np.sin(r), np.abs(np.cos(r))


def _carlson_first(s, c, mc):
    """``s R_F(c^2, d^2, 1)`` with ``d^2 = c^2 + mc s^2`` = ``F(r|m)`` for ``s = sin r, c = cos r``."""
    c2 = c * c
    d2 = c2 + mc * s * s
    return s * sc.elliprf(c2, d2, 1.0)


def ellipkinc(phi, m=None, *, mc=None):
    """Incomplete elliptic integral of the first kind ``F(phi | m)`` for any real ``phi``.

    At ``m = 1`` (``mc = 0``) this is ``asinh(tan phi)`` for ``|phi| < pi/2`` and inf beyond.
    """
    m, mc = _parameters(m, mc)
    j, s, c = _amplitude_reduction(phi)
    j, s, c, m, mc = np.broadcast_arrays(j, s, c, m, mc)
    with np.errstate(divide="ignore", invalid="ignore"):
        local = _carlson_first(s, c, mc)
        total = local + np.where(j != 0, 2.0 * j * _complete_k(m, mc), 0.0)
    return total


def ellipeinc(phi, m=None, *, mc=None):
    """Incomplete elliptic integral of the second kind ``E(phi | m)`` for any real ``phi``."""
    m, mc = _parameters(m, mc)
    j, s, c = _amplitude_reduction(phi)
    j, s, c, m, mc = np.broadcast_arrays(j, s, c, m, mc)
    c2 = c * c
    d2 = c2 + mc * s * s
    with np.errstate(divide="ignore", invalid="ignore"):
        local = s * sc.elliprf(c2, d2, 1.0) - m / 3.0 * s ** 3 * sc.elliprd(c2, d2, 1.0)
    return local + np.where(j != 0, 2.0 * j * ellipe(mc=mc), 0.0)


def ellippiinc(n, phi, m=None, *, mc=None):
    """Incomplete elliptic integral of the third kind ``Pi(n; phi | m)``, ``n < 1``, any real ``phi``.

    Same argument order and convention as ``mpmath.ellippi(n, phi, m)``:
    ``int_0^phi dt / ((1 - n sin^2 t) sqrt(1 - m sin^2 t))``.

    Examples
    --------
    >>> round(float(ellippiinc(-0.5, 0.7, 0.3)), 12)
    0.668623630627
    >>> ellippiinc(-2.0, np.linspace(0, 10, 5), 0.9).shape
    (5,)
    """
    m, mc = _parameters(m, mc)
    n = np.asarray(n, dtype=float)
    _check_characteristic(n)
    j, s, c = _amplitude_reduction(phi)
    j, s, c, n, m, mc = np.broadcast_arrays(j, s, c, n, m, mc)
    return incomplete_pi_local(n, s, c, c * c + mc * s * s) + np.where(j != 0, 2.0 * j * ellippi(n, mc=mc), 0.0)


def incomplete_pi_local(n, s, c, d2):
    """``Pi(n; r | m)`` for ``|r| <= pi/2`` from ``s = sin r``, ``c = cos r``, ``d2 = 1 - m s^2``."""
    c2 = c * c
    with np.errstate(divide="ignore", invalid="ignore"):
        return s * sc.elliprf(c2, d2, 1.0) + n / 3.0 * s ** 3 * sc.elliprj(c2, d2, 1.0, 1.0 - n * s * s)
