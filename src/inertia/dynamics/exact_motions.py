"""The motions of the torque-free rigid body in its principal frame P, one class per regime.

Used by :class:`inertia.dynamics.exact.ExactSolution`, which picks the regime and maps the
motion to the body and world frames: :class:`ConstantMotion` (rest, sphere, steady spin),
:class:`SymmetricTopMotion`, :class:`EllipticMotion` (minor- and major-axis regimes, Jacobi
elliptic functions) and :class:`SeparatrixMotion` (the heteroclinic orbit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.special as sc

from .._core.rotations import quat_multiply
from .elliptic import ellipk, ellippi, incomplete_pi_local, jacobi_reduced

__all__ = ["ConstantMotion", "SymmetricTopMotion", "EllipticMotion", "SeparatrixMotion", "deltas",
           "axis_angle_quat", "minimal_rotation_quat"]


# ============================================================================ small helpers
def axis_angle_quat(axis, angle) -> np.ndarray:
    """Quaternion (..., 4) of the rotation by ``angle`` (...) about the unit ``axis`` (3,) or (..., 3)."""
    angle = np.asarray(angle, dtype=float)
    half = 0.5 * angle
    axis = np.asarray(axis, dtype=float)
    return np.concatenate([np.cos(half)[..., None], np.sin(half)[..., None] * axis], axis=-1)


def minimal_rotation_quat(n_hat, d) -> np.ndarray:
    """Quaternion (..., 4) of the smallest rotation taking the unit vectors n_hat (..., 3) onto d (3,).

    ``p = (1 + c, n x d) / sqrt(2 (1 + c))`` with ``c = n.d``; callers guarantee ``c > -1``
    (here ``c > 0`` always).
    """
    c = n_hat @ d
    v = np.cross(n_hat, d)
    return np.concatenate([(1.0 + c)[..., None], v], axis=-1) / np.sqrt(2.0 * (1.0 + c))[..., None]


def deltas(I, m):
    """``D_j = |m|^2 - 2T I_j`` without cancellation (Celledoni et al.'s invariants).

    Called with the unit vector ``m / G`` (so ``D_j / G^2``): no underflow or overflow of
    ``m^2`` whatever the scale of the angular momentum.
    """
    I1, I2, I3 = I
    m1s, m2s, m3s = m * m
    D1 = m2s * (I2 - I1) / I2 + m3s * (I3 - I1) / I3
    D2 = m1s * (I1 - I2) / I1 + m3s * (I3 - I2) / I3
    D3 = m1s * (I1 - I3) / I1 + m2s * (I2 - I3) / I2
    return D1, D2, D3


# ============================================================================ motions (frame P)
class ConstantMotion:
    """Rest, sphere, steady spin: constant omega, rotation about it at |omega|."""

    def __init__(self, w0):
        self.w0 = w0
        rate = float(np.linalg.norm(w0))
        self.rate = rate
        self.axis = w0 / rate if rate > 0 else np.array([1.0, 0.0, 0.0])

    def omega(self, t):
        return np.broadcast_to(self.w0, t.shape + (3,)).copy()

    def quat_from_start(self, t):
        """``q_P0_P(t)``: rotation from the initial principal frame to the current one."""
        return axis_angle_quat(self.axis, self.rate * t)


class SymmetricTopMotion:
    """Two equal moments: regular precession.

    With ``s`` the symmetry axis, ``I_t`` the transverse moment and
    ``Omega = (I_s - I_t) w_s / I_t``: ``w(t) = Rot(e_s, Omega t) w0`` and
    ``R(t) = R0 Rot(m0/G, G t / I_t) Rot(e_s, -Omega t)``.
    """

    def __init__(self, I, w0, s_axis: int, I_t: float):
        self.s = s_axis
        self.e_s = np.eye(3)[s_axis]
        self.w0 = w0
        self.Omega = (I[s_axis] - I_t) * w0[s_axis] / I_t
        m0 = I * w0
        self.G = float(np.linalg.norm(m0))
        self.L_hat = m0 / self.G
        self.I_t = I_t

    def omega(self, t):
        ang = self.Omega * t
        c, s = np.cos(ang), np.sin(ang)
        k = self.s
        i, j = (k + 1) % 3, (k + 2) % 3
        w = np.empty(t.shape + (3,))
        # rotation about e_k (right-handed cyclic order i -> j -> k)
        w[..., i] = c * self.w0[i] - s * self.w0[j]
        w[..., j] = s * self.w0[i] + c * self.w0[j]
        w[..., k] = self.w0[k]
        return w

    def quat_from_start(self, t):
        a = axis_angle_quat(self.L_hat, self.G / self.I_t * t)
        b = axis_angle_quat(self.e_s, -self.Omega * t)
        return quat_multiply(a, b)


@dataclass
class _AsymmetricMotion:
    """Moments ``I`` (ascending), initial ``w0``, ``G = |I w0|`` and ``D_j / G^2`` of an
    asymmetric body; subclasses precompute their constants in ``_setup``."""

    I: np.ndarray
    w0: np.ndarray
    G: float
    D: tuple

    def __post_init__(self):
        self._setup(*self.I, *self.D, self.G)


@dataclass
class EllipticMotion(_AsymmetricMotion):
    """Asymmetric body off the separatrix: Jacobi elliptic functions (constants precomputed)."""

    major: bool = False

    def _setup(self, I1, I2, I3, D1, D2, D3, G):
        if self.major:
            # circulation about e3: cn on axis 1, sn on 2, dn on 3
            self.cn_axis, self.dn_axis = 0, 2
            self.A = G * math.sqrt(-D3 / (I1 * (I3 - I1)))
            self.B = G * math.sqrt(-D3 / (I2 * (I3 - I2)))
            self.C = G * math.sqrt(D1 / (I3 * (I3 - I1)))
            self.lam = G * math.sqrt((I3 - I2) * D1 / (I1 * I2 * I3))
            self.m = (I2 - I1) * (-D3) / ((I3 - I2) * D1)
            self.mc = D2 * (I3 - I1) / ((I3 - I2) * D1)
            self.n = -I3 * (I2 - I1) / (I1 * (I3 - I2))
            self.sqrt_1mn = math.sqrt(I2 * (I3 - I1) / (I1 * (I3 - I2)))
            self.s_c = 1.0
            I_d = I3
        else:
            # circulation about e1: cn on axis 3, sn on 2, dn on 1
            self.cn_axis, self.dn_axis = 2, 0
            self.A = G * math.sqrt(D1 / (I3 * (I3 - I1)))
            self.B = G * math.sqrt(D1 / (I2 * (I2 - I1)))
            self.C = G * math.sqrt(-D3 / (I1 * (I3 - I1)))
            self.lam = G * math.sqrt((I2 - I1) * (-D3) / (I1 * I2 * I3))
            self.m = (I3 - I2) * D1 / ((I2 - I1) * (-D3))
            self.mc = (-D2) * (I3 - I1) / ((I2 - I1) * (-D3))
            self.n = -I1 * (I3 - I2) / (I3 * (I2 - I1))
            self.sqrt_1mn = math.sqrt(I2 * (I3 - I1) / (I3 * (I2 - I1)))
            self.s_c = -1.0
            I_d = I1
        self.mc = min(max(self.mc, 0.0), 1.0)
        self.m = min(max(self.m, 0.0), 1.0)
        self.I_d = I_d
        self.sigma = 1.0 if self.w0[self.dn_axis] > 0 else -1.0
        self.d = self.sigma * np.eye(3)[self.dn_axis]
        self.a = I_d * self.C / G
        self.K = float(ellipk(mc=self.mc))
        self.period = 4.0 * self.K / self.lam
        self.u0 = self._initial_phase()
        self.coef = self.s_c * G * (I3 - I1) / (self.lam * I1 * I3)
        self.Pi_c = float(ellippi(self.n, mc=self.mc))
        # J(u) gains this much per half period of am (am -> am + pi)
        self.J_half = 2.0 * self.Pi_c - self.a * math.pi / self.sqrt_1mn
        self.J0 = float(self._J(jacobi_reduced(self.u0, mc=self.mc)))
        self.rotation_per_period = G / I_d * self.period + self.coef * 2.0 * self.J_half

    # ---------------------------------------------------------------- phase
    def _initial_phase(self) -> float:
        """``u0`` with ``sn(u0) = s w_sn/B``, ``cn(u0) = w_cn/A``, in (-2K, 2K].

        Near ``am = +-pi/2`` (the slow passage by the saddle), ``F(phi|m)`` is computed as
        ``K - F(phi'|m)`` with ``sn(phi') = |cn|/dn``, ``cn(phi') = k' |sn|/dn``, which keeps
        full precision when ``1 - m`` is tiny.
        """
        sn0 = self.sigma * self.w0[1] / self.B
        cn0 = self.w0[self.cn_axis] / self.A
        h = math.hypot(sn0, cn0)
        s, c = abs(sn0) / h, abs(cn0) / h
        mc = self.mc
        if s <= c:
            F = s * float(sc.elliprf(c * c, c * c + mc * s * s, 1.0))
        else:
            dn0 = math.sqrt(c * c + mc * s * s)
            sv, cv = c / dn0, s * math.sqrt(mc) / dn0
            v = sv * float(sc.elliprf(cv * cv, mc / (dn0 * dn0), 1.0))
            F = self.K - v
        u_abs = F if cn0 >= 0 else 2.0 * self.K - F
        return u_abs if sn0 >= 0 else -u_abs

    # ---------------------------------------------------------------- evaluation
    def _J(self, jr):
        """``J(u) = Pi(n; am u|m) - a/sqrt(1-n) atan(sqrt(1-n) tan am u)`` (continuous branch)."""
        local = incomplete_pi_local(self.n, jr.sn_r, jr.cn_r, jr.dn * jr.dn)
        theta = np.arctan2(self.sqrt_1mn * jr.sn_r, jr.cn_r)
        return jr.j * self.J_half + local - self.a / self.sqrt_1mn * theta

    def _at(self, t):
        jr = jacobi_reduced(self.lam * t + self.u0, mc=self.mc)
        w = np.empty(t.shape + (3,))
        w[..., self.cn_axis] = self.A * jr.cn
        w[..., 1] = self.sigma * self.B * jr.sn
        w[..., self.dn_axis] = self.sigma * self.C * jr.dn
        psi = self.G / self.I_d * t + self.coef * (self._J(jr) - self.J0)
        return w, psi

    def omega(self, t):
        return self._at(t)[0]

    def psi(self, t):
        return self._at(t)[1]

    def omega_psi(self, t):
        return self._at(t)


@dataclass
class SeparatrixMotion(_AsymmetricMotion):
    """``D2 = 0``: heteroclinic motion towards +-G e2 (hyperbolic functions).

    ``m(t) = (s1 B13 sech x, G tanh x, s3 B31 sech x)`` with ``x = lam t - nu``; the
    attitude angle about ``d = s3 e3`` integrates ``int dx / (1 + b sech x)`` in closed form.
    """

    def _setup(self, I1, I2, I3, D1, D2, D3, G):
        m0 = self.I * self.w0
        self.s1 = 1.0 if m0[0] > 0 else -1.0
        self.s3 = 1.0 if m0[2] > 0 else -1.0
        self.B13 = G * math.sqrt(I1 * (-D3) / (I3 - I1))
        self.B31 = G * math.sqrt(I3 * D1 / (I3 - I1))
        self.lam = self.s1 * self.s3 * G * math.sqrt(-D1 * D3 / (I1 * I3))
        # nu = -atanh(m2/G), with 1 -+ m2/G from m1^2 + m3^2 (no cancellation)
        perp = math.hypot(m0[0], m0[2])
        at = math.log((G + abs(m0[1])) / perp)
        self.nu = -math.copysign(at, m0[1])
        self.d = self.s3 * np.array([0.0, 0.0, 1.0])
        self.I_d = I3
        self.D3 = D3 * G * G
        self.c_half = self.B13 / (G + self.B31)       # sqrt((1 - b)/(1 + b)), b = B31/G
        self.ratio = 2.0 * self.B31 / self.B13         # 2 b / sqrt(1 - b^2)
        self.x0 = -self.nu
        self.atan0 = math.atan(self.c_half * math.tanh(0.5 * self.x0))

    def omega_psi(self, t):
        x = self.lam * t - self.nu
        sech = 1.0 / np.cosh(np.clip(x, -700.0, 700.0))
        m = np.empty(t.shape + (3,))
        m[..., 0] = self.s1 * self.B13 * sech
        m[..., 1] = self.G * np.tanh(x)
        m[..., 2] = self.s3 * self.B31 * sech
        w = m / self.I
        bracket = (x - self.x0) - self.ratio * (np.arctan(self.c_half * np.tanh(0.5 * x)) - self.atan0)
        psi = self.G / self.I_d * t - self.D3 / (self.G * self.I_d * self.lam) * bracket
        return w, psi

    def omega(self, t):
        return self.omega_psi(t)[0]

    def psi(self, t):
        return self.omega_psi(t)[1]
