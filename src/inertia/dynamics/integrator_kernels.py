"""The step kernels of the free-body integrators: momentum form, no argument checks.

Each kernel maps ``(q_world_body, m_body = I omega, moments, h, torque_body)`` to the next
``(q, m)`` for arrays that already have a common batch shape; :mod:`.integrators` checks the
arguments, documents each method and loops.  ``KERNELS`` maps the method names to them.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .._core.errors import IntegrationError
from .._core.rotations import cross3, quat_from_rotvec, quat_multiply, quat_multiply_vector, quat_normalize
from .equations import solve3_components as _solve3c

__all__ = ["KERNELS", "NEWTON_MAX_ITER", "NEWTON_RTOL", "NEWTON_FAIL_RTOL", "exp_step"] + [
    "kernel_" + n for n in ("euler_explicit", "euler_implicit", "rk4", "splitting", "dmv", "dmv4", "midpoint")]


#: Newton iterations allowed to the implicit methods (dmv, dmv4, midpoint) per step.  At
#: ``h |omega| <= 0.3`` four to five suffice; the limit only matters for huge steps.
NEWTON_MAX_ITER = 40


#: Newton stops once every correction is below ``NEWTON_RTOL * |unknown|``.  Convergence is
#: quadratic, so the error left after that correction is ~ C * 1e-20 relative (C ~ 1 for
#: h |omega| < 1): below rounding, one iteration earlier than waiting for an ulp-sized step.
NEWTON_RTOL = 1e-10

#: After NEWTON_MAX_ITER iterations, a residual above this (relative) means divergence.
NEWTON_FAIL_RTOL = 1e-10


# ============================================================================ helpers
def exp_step(q, omega, h):
    """``q (x) exp(h omega / 2)``: the exact attitude update for constant body omega, normalised."""
    return quat_normalize(quat_multiply(q, quat_from_rotvec(h * omega)))


def _solve_quadratic(chat, f, with_alpha: bool, what: str, h: float):
    """Newton solve of ``c = beta(c) chat + f * (c_k c_l)`` (j, k, l cyclic), componentwise.

    ``beta = 1 + |c|^2`` (``with_alpha``; the DMV equation) or ``beta = 1`` (implicit midpoint).
    ``chat`` and ``f`` are tuples of three arrays.  Returns the tuple ``c``.
    """
    ch0, ch1, ch2 = chat
    f0, f1, f2 = f
    # explicit first guess, exact to O(h^3)
    c0, c1, c2 = ch0 + f0 * ch1 * ch2, ch1 + f1 * ch2 * ch0, ch2 + f2 * ch0 * ch1
    for _ in range(NEWTON_MAX_ITER):
        beta = 1.0 + c0 * c0 + c1 * c1 + c2 * c2 if with_alpha else 1.0
        r = (c0 - beta * ch0 - f0 * c1 * c2,
             c1 - beta * ch1 - f1 * c2 * c0,
             c2 - beta * ch2 - f2 * c0 * c1)
        # Jacobian J_ji = delta_ji - 2 chat_j c_i [DMV only] - d(f_j c_k c_l)/dc_i
        if with_alpha:
            d0, d1, d2 = 2.0 * ch0, 2.0 * ch1, 2.0 * ch2
            J = ((1.0 - d0 * c0, -d0 * c1 - f0 * c2, -d0 * c2 - f0 * c1),
                 (-d1 * c0 - f1 * c2, 1.0 - d1 * c1, -d1 * c2 - f1 * c0),
                 (-d2 * c0 - f2 * c1, -d2 * c1 - f2 * c0, 1.0 - d2 * c2))
        else:
            one = np.ones_like(c0)
            J = ((one, -f0 * c2, -f0 * c1),
                 (-f1 * c2, one, -f1 * c0),
                 (-f2 * c1, -f2 * c0, one))
        e0, e1, e2 = _solve3c(J, r)
        c0, c1, c2 = c0 - e0, c1 - e1, c2 - e2
        size = np.maximum(np.maximum(np.abs(c0), np.abs(c1)), np.abs(c2))
        corr = np.maximum(np.maximum(np.abs(e0), np.abs(e1)), np.abs(e2))
        if np.all(corr <= NEWTON_RTOL * size + 1e-300):
            return c0, c1, c2
    beta = 1.0 + c0 * c0 + c1 * c1 + c2 * c2 if with_alpha else 1.0
    res = np.maximum(np.maximum(np.abs(c0 - beta * ch0 - f0 * c1 * c2), np.abs(c1 - beta * ch1 - f1 * c2 * c0)),
                     np.abs(c2 - beta * ch2 - f2 * c0 * c1))
    size = np.maximum(np.maximum(np.abs(c0), np.abs(c1)), np.abs(c2))
    worst = float(np.max(res / np.maximum(size, 1e-300)))
    if not np.isfinite(worst) or worst > NEWTON_FAIL_RTOL:
        raise IntegrationError(f"{what}: the implicit step equation did not converge in {NEWTON_MAX_ITER} Newton "
                         f"iterations (relative residual {worst:.3g}); the time step h = {h!r} is too large "
                         f"for this angular velocity: reduce h")
    return c0, c1, c2


def _split3(v):
    return v[..., 0], v[..., 1], v[..., 2]


# ============================================================================ kernels (no checks)
# Each kernel takes arrays already validated and broadcast to one batch shape:
# q (..., 4) unit, m = I w (..., 3) the body angular momentum, I (..., 3) > 0, h float,
# tau (..., 3) or None, and returns (q+, m+).  The state is the momentum, not omega: the
# conserving methods rotate m exactly, and converting m -> w -> m at every step would add a
# biased rounding drift (2e-13 in |m| after 1e4 steps instead of 1e-14).

def kernel_euler_explicit(q, m, I, h, tau):
    # w+ = w + h I^-1 (tau - w x I w) ; q+ = q (x) exp(h w+ / 2)   (semi-implicit Euler)
    rate = cross3(m, m / I)
    if tau is not None:
        rate = rate + tau
    m1 = m + h * rate
    return exp_step(q, m1 / I, h), m1


def kernel_euler_implicit(q, m, I, h, tau):
    # One Newton step of backward Euler on I w' = f(w) = I w x w + tau:
    #   (I - h D) dw = h f(w),  D = df/dw = [I w]x - [w]x I
    # For diagonal I, df_j/dw_k = (I_k - I_l) w_l and df_j/dw_l = (I_k - I_l) w_k  (j,k,l cyclic).
    I0, I1, I2 = _split3(I)
    w = m / I
    w0, w1, w2 = _split3(w)
    g0, g1, g2 = (I1 - I2) * h, (I2 - I0) * h, (I0 - I1) * h
    f = cross3(m, w)
    if tau is not None:
        f = f + tau
    A = ((I0, -g0 * w2, -g0 * w1),
         (-g1 * w2, I1, -g1 * w0),
         (-g2 * w1, -g2 * w0, I2))
    wn = w + np.stack(_solve3c(A, _split3(h * f)), axis=-1)
    return exp_step(q, wn, h), I * wn


def kernel_rk4(q, m, I, h, tau):
    # Classical RK4 on the 7-vector (q as 4 plain components, m); q renormalised at the end.
    def f(qs, ms):
        ws = ms / I
        dm = cross3(ms, ws)
        return 0.5 * quat_multiply_vector(qs, ws), (dm if tau is None else dm + tau)

    h2 = 0.5 * h
    k1q, k1m = f(q, m)
    k2q, k2m = f(q + h2 * k1q, m + h2 * k1m)
    k3q, k3m = f(q + h2 * k2q, m + h2 * k2m)
    k4q, k4m = f(q + h * k3q, m + h * k3m)
    h6 = h / 6.0
    q1 = q + h6 * (k1q + 2.0 * (k2q + k3q) + k4q)
    m1 = m + h6 * (k1m + 2.0 * (k2m + k3m) + k4m)
    return quat_normalize(q1), m1


def _rotate_about_axis(qc, mc, Ic, j, dt):
    """Exact flow of ``H_j = m_j^2 / (2 I_j)`` over dt, in place on component lists.

    Under H_j the body spins at the constant rate ``m_j / I_j`` about e_j:
    ``m <- Rot(e_j, -theta) m`` and ``q <- q (x) (cos(theta/2), sin(theta/2) e_j)``,
    ``theta = dt m_j / I_j``.  Both rotations are orthogonal, so |m| and ``R m`` are kept.
    """
    k, l = (j + 1) % 3, (j + 2) % 3
    half = (0.5 * dt) * mc[j] / Ic[j]
    sh, ch = np.sin(half), np.cos(half)
    s, c = 2.0 * sh * ch, 1.0 - 2.0 * sh * sh          # sin(theta), cos(theta)
    mk, ml = mc[k], mc[l]
    mc[k], mc[l] = c * mk + s * ml, c * ml - s * mk
    qw, qj, qk, ql = qc[0], qc[1 + j], qc[1 + k], qc[1 + l]
    qc[0], qc[1 + j] = qw * ch - qj * sh, qj * ch + qw * sh
    qc[1 + k], qc[1 + l] = qk * ch + ql * sh, ql * ch - qk * sh


#: Strang composition of the three planar rotations: R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2).
_SPLIT_SEQUENCE = ((0, 0.5), (1, 0.5), (2, 1.0), (1, 0.5), (0, 0.5))


def kernel_splitting(q, m, I, h, tau):
    if tau is not None:
        m = m + (0.5 * h) * tau                       # kick
    mc = [m[..., 0], m[..., 1], m[..., 2]]
    qc = [q[..., 0], q[..., 1], q[..., 2], q[..., 3]]
    Ic = _split3(I)
    for j, frac in _SPLIT_SEQUENCE:                  # drift: free-body flow, split in three
        _rotate_about_axis(qc, mc, Ic, j, frac * h)
    m = np.stack(mc, axis=-1)
    if tau is not None:
        m = m + (0.5 * h) * tau                       # kick
    return quat_normalize(np.stack(qc, axis=-1)), m


# Hairer & Vilmart (2006) order-4 modified inertia: 1/I~_j = css / I_j + cdd with
#   css = 1 + h^2 (S1 |m|^2/2 + S2 T),  cdd = h^2 (D1 |m|^2/2 + D2 T),
#   S1 = sum(I) / (6 prod(I)),  S2 = -sum(1/I) / 3,  D1 = -1 / (3 prod(I)),  D2 = S1.
def _dmv4_inverse_moments(m, I, h):
    I0, I1, I2 = _split3(I)
    prod = I0 * I1 * I2
    s1 = (I0 + I1 + I2) / (6.0 * prod)
    s2 = -(1.0 / I0 + 1.0 / I1 + 1.0 / I2) / 3.0
    d1 = -1.0 / (3.0 * prod)
    half_g2 = 0.5 * np.sum(m * m, axis=-1)
    energy = 0.5 * np.sum(m * m / I, axis=-1)
    h2 = h * h
    css = 1.0 + h2 * (s1 * half_g2 + s2 * energy)
    cdd = h2 * (d1 * half_g2 + s1 * energy)
    return css[..., None] / I + cdd[..., None]


def _dmv_core(q, m, inv_I, h, what):
    """One DMV step of the free body with inverse moments ``inv_I`` (body momentum m)."""
    Im = 1.0 / inv_I
    I0, I1, I2 = _split3(Im)
    W0, W1, W2 = _split3(inv_I)
    chat = _split3((0.5 * h) * m * inv_I)
    f = ((I1 - I2) * W0, (I2 - I0) * W1, (I0 - I1) * W2)
    c = np.stack(_solve_quadratic(chat, f, True, what, h), axis=-1)
    # body increment F = Rot((1, c)/sqrt(1 + |c|^2)) ; q+ = q (x) (1, c)/|.| ; m+ = F^T m
    s = 1.0 / np.sqrt(1.0 + np.sum(c * c, axis=-1, keepdims=True))
    p = np.concatenate([s, s * c], axis=-1)
    q1 = quat_normalize(quat_multiply(q, p))
    v = -s * c                                         # vector part of p^-1
    t = 2.0 * cross3(v, m)
    m1 = m + s * t + cross3(v, t)
    return q1, m1


def kernel_dmv(q, m, I, h, tau):
    if tau is not None:
        m = m + (0.5 * h) * tau
    q1, m1 = _dmv_core(q, m, 1.0 / I, h, "dmv")
    if tau is not None:
        m1 = m1 + (0.5 * h) * tau
    return q1, m1


def kernel_dmv4(q, m, I, h, tau):
    if tau is not None:
        m = m + (0.5 * h) * tau
    q1, m1 = _dmv_core(q, m, _dmv4_inverse_moments(m, I, h), h, "dmv4")
    if tau is not None:
        m1 = m1 + (0.5 * h) * tau
    return q1, m1


def kernel_midpoint(q, m0, I, h, tau):
    # Implicit midpoint on the body momentum (Austin, Krishnaprasad & Wang 1993):
    #   y = m_mid = m0 + h/2 (y x I^-1 y + tau),   m1 = 2 y - m0,
    # and the attitude moved by the midpoint velocity: q1 = q0 (x) exp(h w_mid / 2), w_mid = I^-1 y.
    W = 1.0 / I
    W0, W1, W2 = _split3(W)
    hh = 0.5 * h
    b = m0 if tau is None else m0 + hh * tau
    # (y x W y)_j = (W_l - W_k) y_k y_l
    f = (hh * (W2 - W1), hh * (W0 - W2), hh * (W1 - W0))
    y = np.stack(_solve_quadratic(_split3(b), f, False, "midpoint", h), axis=-1)
    m1 = 2.0 * y - m0
    return exp_step(q, W * y, h), m1


KERNELS: dict[str, Callable] = {
    "euler_explicit": kernel_euler_explicit,
    "euler_implicit": kernel_euler_implicit,
    "rk4": kernel_rk4,
    "splitting": kernel_splitting,
    "dmv": kernel_dmv,
    "dmv4": kernel_dmv4,
    "midpoint": kernel_midpoint,
}
