"""Body frame or world frame: which form of Euler's law costs less for the same accuracy?

The question: integrate

* **body**  ``I w' + w x (I w) = tau_B`` (constant inertia, extra gyroscopic term), or
* **world** ``dL/dt = tau_W`` with ``I_W = R I R^T`` and ``w_W = I_W^-1 L`` at every
  evaluation (trivial equation, inertia that turns with the body)?

Usage::

    python bench/body_vs_world.py [--t-end 10] [--repeat 5] [--quick]

Problem: the free asymmetric test body of the notes, ``I = (2/3, 1, 2)`` kg m^2,
``m0 = (sin 1.1, 0, cos 1.1)``, a generic initial attitude, integrated to ``--t-end``.
Reference: scipy DOP853, rtol = atol = 1e-13, on the body equations (the two formulations
have the same exact solution).

Formulations (all with quaternion attitude; "principal" = the body frame is principal):

* ``body/diag``     ``w' = I^-1 ((I w) x w)`` componentwise, ``q' = 1/2 q (x) (0, w)``.
* ``body/full``     general 3x3 body inertia: ``w' = J^-1 ((J w) x w)`` with ``J^-1`` computed
  once (it is constant in the body frame).
* ``world/literal`` ``R(q)``, ``I_W = R J R^T`` (two 3x3 products), ``w_W = I_W^-1 L`` by a
  3x3 solve (cofactors), ``q' = 1/2 (0, w_W) (x) q``, ``L' = 0``.
* ``world/R-Iinv-RT`` the cheapest world form: ``w_W = R (I^-1 (R^T L))`` (no inverse).

Integrators, identical for every formulation: classical **RK4** on the 7 components (q as
a 4-vector, renormalised at the end of the step) and first-order **Euler** with the exact
exponential map for the attitude (body: semi-implicit, ``w+ = w + h w'``,
``q+ = q exp(h w+/2)``; world: ``L+ = L``, ``q+ = exp(h w_W(q)/2) q``).

Costs:

* **flops/step**: every +, -, *, / executed by one step, counted by running the scalar
  kernel once on a float subclass that counts (sqrt, sin, cos counted separately);
* **ns/step**: the same scalar kernels compiled with numba (``njit``, no fastmath), a loop
  of steps inside numba; minimum over ``--repeat`` timings;
* **NumPy**: the library's own vectorised right-hand sides
  (:func:`inertia.dynamics.equations.state_rate_body` / ``state_rate_world``) under one
  generic NumPy RK4, per step for 1 body and per body-step for a batch of 10 000.

Accuracy: the attitude error (rotation angle, rad) and ``|w - w_ref|`` at ``t_end`` for
step counts on a geometric grid; *steps to target* interpolates log(error) against
log(steps) at the attitude targets (1e-8 rad for RK4, 1e-3 rad for Euler); *time to
target* = steps x ns/step; the *ratio* is world / body for the same integrator.

Everything printed is measured in this run.  The machine may be shared: compare ratios
within one run, not absolute times across runs.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from collections import Counter

import numpy as np
from scipy.integrate import solve_ivp

from inertia._core.rotations import quat_from_rotvec, quat_to_matrix
from inertia.dynamics import equations as eq
from inertia.dynamics.diagnostics import attitude_error

# Module-level aliases, so the flop counter can swap in counting versions.
sqrt = math.sqrt
sin = math.sin
cos = math.cos

MOMENTS = np.array([2 / 3, 1.0, 2.0])
M0 = np.array([math.sin(1.1), 0.0, math.cos(1.1)])
W0 = M0 / MOMENTS
Q0 = quat_from_rotvec([0.3, -0.5, 0.8])

_PURE: dict[str, object] = {}


def kernel(f):
    """Register a scalar kernel (compiled later by :func:`jit_all`)."""
    _PURE[f.__name__] = f
    return f


# ============================================================================ scalar kernels
@kernel
def qdot_body(q, w):
    # 1/2 q (x) (0, w)
    return (-0.5 * (q[1] * w[0] + q[2] * w[1] + q[3] * w[2]),
            0.5 * (q[0] * w[0] + q[2] * w[2] - q[3] * w[1]),
            0.5 * (q[0] * w[1] - q[1] * w[2] + q[3] * w[0]),
            0.5 * (q[0] * w[2] + q[1] * w[1] - q[2] * w[0]))


@kernel
def qdot_world(q, v):
    # 1/2 (0, v) (x) q
    return (-0.5 * (v[0] * q[1] + v[1] * q[2] + v[2] * q[3]),
            0.5 * (v[0] * q[0] + v[1] * q[3] - v[2] * q[2]),
            0.5 * (v[1] * q[0] + v[2] * q[1] - v[0] * q[3]),
            0.5 * (v[2] * q[0] + v[0] * q[2] - v[1] * q[1]))


@kernel
def matvec(A, v):
    return (A[0] * v[0] + A[1] * v[1] + A[2] * v[2],
            A[3] * v[0] + A[4] * v[1] + A[5] * v[2],
            A[6] * v[0] + A[7] * v[1] + A[8] * v[2])


@kernel
def matTvec(A, v):
    return (A[0] * v[0] + A[3] * v[1] + A[6] * v[2],
            A[1] * v[0] + A[4] * v[1] + A[7] * v[2],
            A[2] * v[0] + A[5] * v[1] + A[8] * v[2])


@kernel
def matmul(A, B):
    return (A[0] * B[0] + A[1] * B[3] + A[2] * B[6], A[0] * B[1] + A[1] * B[4] + A[2] * B[7],
            A[0] * B[2] + A[1] * B[5] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[3] + A[5] * B[6], A[3] * B[1] + A[4] * B[4] + A[5] * B[7],
            A[3] * B[2] + A[4] * B[5] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[3] + A[8] * B[6], A[6] * B[1] + A[7] * B[4] + A[8] * B[7],
            A[6] * B[2] + A[7] * B[5] + A[8] * B[8])


@kernel
def matmul_bt(A, B):
    # A B^T
    return (A[0] * B[0] + A[1] * B[1] + A[2] * B[2], A[0] * B[3] + A[1] * B[4] + A[2] * B[5],
            A[0] * B[6] + A[1] * B[7] + A[2] * B[8],
            A[3] * B[0] + A[4] * B[1] + A[5] * B[2], A[3] * B[3] + A[4] * B[4] + A[5] * B[5],
            A[3] * B[6] + A[4] * B[7] + A[5] * B[8],
            A[6] * B[0] + A[7] * B[1] + A[8] * B[2], A[6] * B[3] + A[7] * B[4] + A[8] * B[5],
            A[6] * B[6] + A[7] * B[7] + A[8] * B[8])


@kernel
def solve3(A, b):
    # Cramer / cofactors: x = C^T b / det
    c00 = A[4] * A[8] - A[5] * A[7]
    c01 = A[5] * A[6] - A[3] * A[8]
    c02 = A[3] * A[7] - A[4] * A[6]
    c10 = A[2] * A[7] - A[1] * A[8]
    c11 = A[0] * A[8] - A[2] * A[6]
    c12 = A[1] * A[6] - A[0] * A[7]
    c20 = A[1] * A[5] - A[2] * A[4]
    c21 = A[2] * A[3] - A[0] * A[5]
    c22 = A[0] * A[4] - A[1] * A[3]
    inv_det = 1.0 / (A[0] * c00 + A[1] * c01 + A[2] * c02)
    return ((c00 * b[0] + c10 * b[1] + c20 * b[2]) * inv_det,
            (c01 * b[0] + c11 * b[1] + c21 * b[2]) * inv_det,
            (c02 * b[0] + c12 * b[1] + c22 * b[2]) * inv_det)


@kernel
def rot_matrix(q):
    # R(q / |q|) without normalising q first (RK4 stage quaternions are not unit)
    w, x, y, z = q[0], q[1], q[2], q[3]
    s = 2.0 / (w * w + x * x + y * y + z * z)
    xs, ys, zs = x * s, y * s, z * s
    wx, wy, wz = w * xs, w * ys, w * zs
    xx, xy, xz = x * xs, x * ys, x * zs
    yy, yz, zz = y * ys, y * zs, z * zs
    return (1.0 - (yy + zz), xy - wz, xz + wy,
            xy + wz, 1.0 - (xx + zz), yz - wx,
            xz - wy, yz + wx, 1.0 - (xx + yy))


@kernel
def accel_diag(w, I, invI):
    m0, m1, m2 = I[0] * w[0], I[1] * w[1], I[2] * w[2]
    return (invI[0] * (m1 * w[2] - m2 * w[1]),
            invI[1] * (m2 * w[0] - m0 * w[2]),
            invI[2] * (m0 * w[1] - m1 * w[0]))


@kernel
def accel_full(w, J, Jinv):
    m = matvec(J, w)
    return matvec(Jinv, (m[1] * w[2] - m[2] * w[1], m[2] * w[0] - m[0] * w[2], m[0] * w[1] - m[1] * w[0]))


@kernel
def omega_world_literal(q, L, J):
    R = rot_matrix(q)
    I_W = matmul_bt(matmul(R, J), R)
    return solve3(I_W, L)


@kernel
def omega_world_fast(q, L, invI):
    R = rot_matrix(q)
    lb = matTvec(R, L)
    return matvec(R, (invI[0] * lb[0], invI[1] * lb[1], invI[2] * lb[2]))


@kernel
def add4(a, k, s):
    return (a[0] + s * k[0], a[1] + s * k[1], a[2] + s * k[2], a[3] + s * k[3])


@kernel
def add3(a, k, s):
    return (a[0] + s * k[0], a[1] + s * k[1], a[2] + s * k[2])


@kernel
def rk4_sum4(a, k1, k2, k3, k4, h6):
    return (a[0] + h6 * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]),
            a[1] + h6 * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]),
            a[2] + h6 * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2]),
            a[3] + h6 * (k1[3] + 2.0 * (k2[3] + k3[3]) + k4[3]))


@kernel
def rk4_sum3(a, k1, k2, k3, k4, h6):
    return (a[0] + h6 * (k1[0] + 2.0 * (k2[0] + k3[0]) + k4[0]),
            a[1] + h6 * (k1[1] + 2.0 * (k2[1] + k3[1]) + k4[1]),
            a[2] + h6 * (k1[2] + 2.0 * (k2[2] + k3[2]) + k4[2]))


@kernel
def normalize4(q):
    s = 1.0 / sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
    return (q[0] * s, q[1] * s, q[2] * s, q[3] * s)


@kernel
def qmul(p, q):
    return (p[0] * q[0] - p[1] * q[1] - p[2] * q[2] - p[3] * q[3],
            p[0] * q[1] + p[1] * q[0] + p[2] * q[3] - p[3] * q[2],
            p[0] * q[2] - p[1] * q[3] + p[2] * q[0] + p[3] * q[1],
            p[0] * q[3] + p[1] * q[2] - p[2] * q[1] + p[3] * q[0])


@kernel
def quat_exp(v):
    # unit quaternion of the rotation vector v (angle |v|)
    th = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if th < 1e-8:
        k = 0.5
    else:
        k = sin(0.5 * th) / th
    return (cos(0.5 * th), k * v[0], k * v[1], k * v[2])


# ---- RK4 steps: (q, x, h, p1, p2) -> (q, x);  x = omega_body (body) or L_world (world)
@kernel
def rk4_body_diag(q, w, h, I, invI):
    hh = 0.5 * h
    k1q, k1w = qdot_body(q, w), accel_diag(w, I, invI)
    q2, w2 = add4(q, k1q, hh), add3(w, k1w, hh)
    k2q, k2w = qdot_body(q2, w2), accel_diag(w2, I, invI)
    q3, w3 = add4(q, k2q, hh), add3(w, k2w, hh)
    k3q, k3w = qdot_body(q3, w3), accel_diag(w3, I, invI)
    q4, w4 = add4(q, k3q, h), add3(w, k3w, h)
    k4q, k4w = qdot_body(q4, w4), accel_diag(w4, I, invI)
    h6 = h / 6.0
    return normalize4(rk4_sum4(q, k1q, k2q, k3q, k4q, h6)), rk4_sum3(w, k1w, k2w, k3w, k4w, h6)


@kernel
def rk4_body_full(q, w, h, J, Jinv):
    hh = 0.5 * h
    k1q, k1w = qdot_body(q, w), accel_full(w, J, Jinv)
    q2, w2 = add4(q, k1q, hh), add3(w, k1w, hh)
    k2q, k2w = qdot_body(q2, w2), accel_full(w2, J, Jinv)
    q3, w3 = add4(q, k2q, hh), add3(w, k2w, hh)
    k3q, k3w = qdot_body(q3, w3), accel_full(w3, J, Jinv)
    q4, w4 = add4(q, k3q, h), add3(w, k3w, h)
    k4q, k4w = qdot_body(q4, w4), accel_full(w4, J, Jinv)
    h6 = h / 6.0
    return normalize4(rk4_sum4(q, k1q, k2q, k3q, k4q, h6)), rk4_sum3(w, k1w, k2w, k3w, k4w, h6)


@kernel
def rk4_world_literal(q, L, h, J, unused):
    # free body: dL/dt = 0, so the L stages are L itself
    hh = 0.5 * h
    k1 = qdot_world(q, omega_world_literal(q, L, J))
    q2 = add4(q, k1, hh)
    k2 = qdot_world(q2, omega_world_literal(q2, L, J))
    q3 = add4(q, k2, hh)
    k3 = qdot_world(q3, omega_world_literal(q3, L, J))
    q4 = add4(q, k3, h)
    k4 = qdot_world(q4, omega_world_literal(q4, L, J))
    return normalize4(rk4_sum4(q, k1, k2, k3, k4, h / 6.0)), L


@kernel
def rk4_world_fast(q, L, h, invI, unused):
    hh = 0.5 * h
    k1 = qdot_world(q, omega_world_fast(q, L, invI))
    q2 = add4(q, k1, hh)
    k2 = qdot_world(q2, omega_world_fast(q2, L, invI))
    q3 = add4(q, k2, hh)
    k3 = qdot_world(q3, omega_world_fast(q3, L, invI))
    q4 = add4(q, k3, h)
    k4 = qdot_world(q4, omega_world_fast(q4, L, invI))
    return normalize4(rk4_sum4(q, k1, k2, k3, k4, h / 6.0)), L


# ---- Euler steps (first order; exact exponential map for the attitude)
@kernel
def euler_body_diag(q, w, h, I, invI):
    a = accel_diag(w, I, invI)
    wn = add3(w, a, h)
    return normalize4(qmul(q, quat_exp((h * wn[0], h * wn[1], h * wn[2])))), wn


@kernel
def euler_body_full(q, w, h, J, Jinv):
    a = accel_full(w, J, Jinv)
    wn = add3(w, a, h)
    return normalize4(qmul(q, quat_exp((h * wn[0], h * wn[1], h * wn[2])))), wn


@kernel
def euler_world_literal(q, L, h, J, unused):
    v = omega_world_literal(q, L, J)
    return normalize4(qmul(quat_exp((h * v[0], h * v[1], h * v[2])), q)), L


@kernel
def euler_world_fast(q, L, h, invI, unused):
    v = omega_world_fast(q, L, invI)
    return normalize4(qmul(quat_exp((h * v[0], h * v[1], h * v[2])), q)), L


# ---- RK4 with a constant torque given in the other formulation's frame
@kernel
def rhs_body_torque_world(q, w, I, invI, tau_W):
    # body form, torque known in the world frame: tau_B = R^T tau_W at every evaluation
    tb = matTvec(rot_matrix(q), tau_W)
    m0, m1, m2 = I[0] * w[0], I[1] * w[1], I[2] * w[2]
    return qdot_body(q, w), (invI[0] * (m1 * w[2] - m2 * w[1] + tb[0]),
                             invI[1] * (m2 * w[0] - m0 * w[2] + tb[1]),
                             invI[2] * (m0 * w[1] - m1 * w[0] + tb[2]))


@kernel
def rhs_body_torque_body(q, w, I, invI, tau_B):
    m0, m1, m2 = I[0] * w[0], I[1] * w[1], I[2] * w[2]
    return qdot_body(q, w), (invI[0] * (m1 * w[2] - m2 * w[1] + tau_B[0]),
                             invI[1] * (m2 * w[0] - m0 * w[2] + tau_B[1]),
                             invI[2] * (m0 * w[1] - m1 * w[0] + tau_B[2]))


@kernel
def rhs_world_torque_world(q, L, I, invI, tau_W):
    return qdot_world(q, omega_world_fast(q, L, invI)), tau_W


@kernel
def rhs_world_torque_body(q, L, I, invI, tau_B):
    # world form, torque known in the body frame: dL/dt = R tau_B at every evaluation
    R = rot_matrix(q)
    lb = matTvec(R, L)
    return (qdot_world(q, matvec(R, (invI[0] * lb[0], invI[1] * lb[1], invI[2] * lb[2]))),
            matvec(R, tau_B))


@kernel
def rk4_generic(rhs, q, x, h, I, invI, tau):
    hh = 0.5 * h
    k1q, k1x = rhs(q, x, I, invI, tau)
    k2q, k2x = rhs(add4(q, k1q, hh), add3(x, k1x, hh), I, invI, tau)
    k3q, k3x = rhs(add4(q, k2q, hh), add3(x, k2x, hh), I, invI, tau)
    k4q, k4x = rhs(add4(q, k3q, h), add3(x, k3x, h), I, invI, tau)
    h6 = h / 6.0
    return normalize4(rk4_sum4(q, k1q, k2q, k3q, k4q, h6)), rk4_sum3(x, k1x, k2x, k3x, k4x, h6)


@kernel
def rk4_body_torque_world(q, w, h, I, p2):
    return rk4_generic(rhs_body_torque_world, q, w, h, I, (p2[0], p2[1], p2[2]), (p2[3], p2[4], p2[5]))


@kernel
def rk4_body_torque_body(q, w, h, I, p2):
    return rk4_generic(rhs_body_torque_body, q, w, h, I, (p2[0], p2[1], p2[2]), (p2[3], p2[4], p2[5]))


@kernel
def rk4_world_torque_world(q, L, h, I, p2):
    return rk4_generic(rhs_world_torque_world, q, L, h, I, (p2[0], p2[1], p2[2]), (p2[3], p2[4], p2[5]))


@kernel
def rk4_world_torque_body(q, L, h, I, p2):
    return rk4_generic(rhs_world_torque_body, q, L, h, I, (p2[0], p2[1], p2[2]), (p2[3], p2[4], p2[5]))


@kernel
def run(step, n, h, q, x, p1, p2):
    for _ in range(n):
        q, x = step(q, x, h, p1, p2)
    return q, x


# ============================================================================ set-up
def _tuple(a):
    return tuple(float(v) for v in np.ravel(a))


J_BODY = np.diag(MOMENTS)
TAU = np.array([0.05, -0.1, 0.08])        # N m, constant, in the frame the scenario names
_INV = _tuple(1.0 / MOMENTS)
PARAMS = {
    "body/diag": (_tuple(MOMENTS), _INV),
    "body/full": (_tuple(J_BODY), _tuple(np.linalg.inv(J_BODY))),
    "world/literal": (_tuple(J_BODY), _tuple(J_BODY)),
    "world/R-Iinv-RT": (_INV, _INV),
}
_TORQUED = (_tuple(MOMENTS), _INV + _tuple(TAU))
#: (scenario, integrator, formulation) -> (kernel, p1, p2).  Scenario "free": no torque;
#: "tau_W": constant torque given in the world frame; "tau_B": constant torque in the body frame.
STEPS = {
    ("free", "RK4", "body/diag"): ("rk4_body_diag",) + PARAMS["body/diag"],
    ("free", "RK4", "body/full"): ("rk4_body_full",) + PARAMS["body/full"],
    ("free", "RK4", "world/literal"): ("rk4_world_literal",) + PARAMS["world/literal"],
    ("free", "RK4", "world/R-Iinv-RT"): ("rk4_world_fast",) + PARAMS["world/R-Iinv-RT"],
    ("free", "Euler", "body/diag"): ("euler_body_diag",) + PARAMS["body/diag"],
    ("free", "Euler", "body/full"): ("euler_body_full",) + PARAMS["body/full"],
    ("free", "Euler", "world/literal"): ("euler_world_literal",) + PARAMS["world/literal"],
    ("free", "Euler", "world/R-Iinv-RT"): ("euler_world_fast",) + PARAMS["world/R-Iinv-RT"],
    ("tau_W", "RK4", "body/diag"): ("rk4_body_torque_world",) + _TORQUED,
    ("tau_W", "RK4", "world/R-Iinv-RT"): ("rk4_world_torque_world",) + _TORQUED,
    ("tau_B", "RK4", "body/diag"): ("rk4_body_torque_body",) + _TORQUED,
    ("tau_B", "RK4", "world/R-Iinv-RT"): ("rk4_world_torque_body",) + _TORQUED,
}
TARGET = {"RK4": 1e-8, "Euler": 1e-3}


def initial_state(form):
    if form.startswith("body"):
        return _tuple(Q0), _tuple(W0)
    return _tuple(Q0), _tuple(quat_to_matrix(Q0) @ M0)


def omega_body_of(form, q, x):
    if form.startswith("body"):
        return np.array(x)
    R = quat_to_matrix(np.array(q))
    return (R.T @ np.array(x)) / MOMENTS


# ============================================================================ flop counting
_COUNTS: Counter = Counter()


class _Counted(float):
    """A float that counts the arithmetic done on it (results stay counted)."""

    __slots__ = ()


def _binop(kind, fn):
    def op(a, b):
        _COUNTS[kind] += 1
        return _Counted(fn(float(a), float(b)))
    return op


for _name, _kind, _fn in [
    ("__add__", "add", lambda a, b: a + b), ("__radd__", "add", lambda a, b: b + a),
    ("__sub__", "add", lambda a, b: a - b), ("__rsub__", "add", lambda a, b: b - a),
    ("__mul__", "mul", lambda a, b: a * b), ("__rmul__", "mul", lambda a, b: b * a),
    ("__truediv__", "div", lambda a, b: a / b), ("__rtruediv__", "div", lambda a, b: b / a),
]:
    setattr(_Counted, _name, _binop(_kind, _fn))
_Counted.__neg__ = lambda a: _Counted(-float(a))


def _counting_unary(kind, fn):
    def op(a):
        _COUNTS[kind] += 1
        return _Counted(fn(float(a)))
    return op


def count_flops(step_name, form, p1, p2):
    """Operation counts of one step, by running the pure-Python kernel on counting floats."""
    g = globals()
    saved = {k: g[k] for k in ("sqrt", "sin", "cos")}
    g.update(sqrt=_counting_unary("sqrt", math.sqrt), sin=_counting_unary("trig", math.sin),
             cos=_counting_unary("trig", math.cos))
    try:
        q, x = initial_state(form)
        cf = lambda t: tuple(_Counted(v) for v in t)  # noqa: E731
        _COUNTS.clear()
        g[step_name](cf(q), cf(x), _Counted(0.01), cf(p1), cf(p2))
        return dict(_COUNTS)
    finally:
        g.update(saved)


def jit_all():
    import numba
    g = globals()
    for name, f in _PURE.items():
        g[name] = numba.njit(f)


# ============================================================================ accuracy and time
def reference(t_end, scenario="free"):
    def rhs(t, y):
        if scenario == "free":
            tau_B = None
        elif scenario == "tau_B":
            tau_B = TAU
        else:
            tau_B = quat_to_matrix(y[:4] / np.linalg.norm(y[:4])).T @ TAU
        dq, dw = eq.state_rate_body(y[:4], y[4:], MOMENTS, tau_B)
        return np.concatenate([dq, dw])
    sol = solve_ivp(rhs, (0.0, t_end), np.concatenate([Q0, W0]), method="DOP853", rtol=1e-13, atol=1e-13)
    q = sol.y[:4, -1]
    return q / np.linalg.norm(q), sol.y[4:, -1]


def errors(step, form, p1, p2, n, t_end, ref):
    q, x = initial_state(form)
    qn, xn = run(step, n, t_end / n, q, x, p1, p2)
    w = omega_body_of(form, qn, xn)
    return float(attitude_error(np.array(qn), ref[0])), float(np.linalg.norm(w - ref[1])), qn, xn


def steps_to_target(ns, errs, target):
    """Interpolate log(err) against log(n) at the target; None if never reached."""
    ns, errs = np.asarray(ns, float), np.asarray(errs, float)
    for i in range(len(ns) - 1):
        if errs[i] > target >= errs[i + 1]:
            t = (math.log(target) - math.log(errs[i])) / (math.log(errs[i + 1]) - math.log(errs[i]))
            return math.exp(math.log(ns[i]) + t * (math.log(ns[i + 1]) - math.log(ns[i])))
    return None if errs[-1] > target else float(ns[0])


def _calibrate(step, form, p1, p2, min_time):
    """Steps per timing so that one timing lasts about ``min_time`` seconds."""
    q, x = initial_state(form)
    n = 1000
    while True:
        t = time.perf_counter()
        run(step, n, 1e-3, q, x, p1, p2)
        if time.perf_counter() - t > min_time:
            return n
        n *= 4


def time_per_step(cases, repeat, min_time=0.1):
    """ns/step of each (step, form, p1, p2), min over ``repeat`` rounds.

    Every round times every case once, so slow phases of a shared machine hit all cases
    alike instead of whichever case happened to run then.
    """
    ns = [_calibrate(*c, min_time) for c in cases]
    best = [math.inf] * len(cases)
    for _ in range(repeat):
        for i, (step, form, p1, p2) in enumerate(cases):
            q, x = initial_state(form)
            t = time.perf_counter()
            run(step, ns[i], 1e-3, q, x, p1, p2)
            best[i] = min(best[i], (time.perf_counter() - t) / ns[i] * 1e9)
    return best


def _numpy_case(form, batch):
    rng = np.random.default_rng(0)
    q = rng.normal(size=(batch, 4))
    q /= np.linalg.norm(q, axis=-1, keepdims=True)
    if form.startswith("body"):
        x = np.broadcast_to(W0, (batch, 3)).copy()
        inertia = MOMENTS if form == "body/diag" else J_BODY
        rhs = lambda q_, x_: eq.state_rate_body(q_, x_, inertia)  # noqa: E731
    else:
        x = np.einsum("nij,j->ni", quat_to_matrix(q), M0)
        inertia = MOMENTS if form == "world/R-Iinv-RT" else J_BODY
        rhs = lambda q_, x_: eq.state_rate_world(q_, x_, inertia)  # noqa: E731
    return rhs, q, x


def _numpy_rk4(rhs, q, x, h, n_steps):
    for _ in range(n_steps):
        k1 = rhs(q, x)
        k2 = rhs(q + 0.5 * h * k1[0], x + 0.5 * h * k1[1])
        k3 = rhs(q + 0.5 * h * k2[0], x + 0.5 * h * k2[1])
        k4 = rhs(q + h * k3[0], x + h * k3[1])
        q = q + h / 6 * (k1[0] + 2 * k2[0] + 2 * k3[0] + k4[0])
        x = x + h / 6 * (k1[1] + 2 * k2[1] + 2 * k3[1] + k4[1])
        q = q / np.linalg.norm(q, axis=-1, keepdims=True)
    return q, x


def numpy_rk4_per_step(forms, batch, repeat, n_steps):
    """Seconds per step of a generic NumPy RK4 over the library's right-hand sides (rounds as above)."""
    cases = [_numpy_case(f, batch) for f in forms]
    best = [math.inf] * len(cases)
    for _ in range(repeat):
        for i, (rhs, q, x) in enumerate(cases):
            t = time.perf_counter()
            _numpy_rk4(rhs, q, x, 1e-3, n_steps)
            best[i] = min(best[i], (time.perf_counter() - t) / n_steps)
    return best


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--t-end", type=float, default=10.0)
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--quick", action="store_true", help="fewer step sizes and repeats")
    args = ap.parse_args(argv)
    t_end = args.t_end
    repeat = 2 if args.quick else args.repeat

    flops = {key: count_flops(name, key[2], p1, p2) for key, (name, p1, p2) in STEPS.items()}
    jit_all()
    refs = {sc: reference(t_end, sc) for sc in ("free", "tau_W", "tau_B")}
    grids = {"RK4": np.unique(np.geomspace(10, 3000 if args.quick else 20000, 16 if args.quick else 28).astype(int)),
             "Euler": np.unique(np.geomspace(100, 1e6 if args.quick else 1e7, 12 if args.quick else 21).astype(int))}

    rows = []
    for (scenario, integ, form), (name, p1, p2) in STEPS.items():
        step = globals()[name]
        ref = refs[scenario]
        ns = grids[integ]
        e_att = [errors(step, form, p1, p2, int(n), t_end, ref)[0] for n in ns]
        # order from the asymptotic part (errors well above rounding, below 1e-2)
        sel = [(n, e) for n, e in zip(ns, e_att) if 1e-10 < e < 1e-2]
        order = float("nan")
        if len(sel) > 2:
            order = -np.polyfit(np.log([s[0] for s in sel]), np.log([s[1] for s in sel]), 1)[0]
        a01, w01, qn, xn = errors(step, form, p1, p2, int(round(t_end / 0.01)), t_end, ref)
        # invariants at t_end for h = 0.01 (free body only): spatial L and energy
        dL = dT = float("nan")
        if scenario == "free":
            wb = omega_body_of(form, qn, xn)
            L_end = quat_to_matrix(np.array(qn)) @ (MOMENTS * wb)
            L0 = quat_to_matrix(Q0) @ M0
            dL = np.linalg.norm(L_end - L0) / np.linalg.norm(L0)
            dT = 0.5 * np.sum(MOMENTS * wb * wb) / (0.5 * np.sum(M0 * W0)) - 1
        nt = steps_to_target(ns, e_att, TARGET[integ])
        rows.append(dict(scenario=scenario, integ=integ, form=form, flops=flops[(scenario, integ, form)],
                         order=order, att01=a01, w01=w01, dL=dL, dT=dT, n_target=nt))
    timings = time_per_step([(globals()[name], key[2], p1, p2) for key, (name, p1, p2) in STEPS.items()], repeat)
    for r, ns_step in zip(rows, timings):
        r["ns_step"] = ns_step
        r["us_target"] = None if r["n_target"] is None else r["n_target"] * ns_step / 1e3

    forms = list(PARAMS)
    one = numpy_rk4_per_step(forms, 1, repeat, 200 if args.quick else 1000)
    many = numpy_rk4_per_step(forms, 10_000, repeat, 5 if args.quick else 20)
    np_rows = {f: (a, b / 10_000) for f, a, b in zip(forms, one, many)}

    print(f"Body frame vs world frame, free body I = {MOMENTS.round(4).tolist()}, t_end = {t_end:g} s, "
          f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    print("flops = + - * / per step (sqrt, sin/cos and divisions also listed); ns/step: numba scalar loop, "
          f"min of {repeat}")
    print()
    hdr = (f"{'torque':<6} {'integ':<5} {'formulation':<16} {'flops':>5} {'sqrt,trig,div':>13} {'ns/step':>8} "
           f"{'order':>5} {'att.err h=.01':>13} {'|dw| h=.01':>10} {'|dL|/L':>8} {'dT/T':>9} {'steps->tgt':>10} "
           f"{'us->tgt':>9} {'ratio':>6}")
    print(hdr)
    print("-" * len(hdr))
    base = {}
    for r in rows:
        c = r["flops"]
        total = c.get("add", 0) + c.get("mul", 0) + c.get("div", 0)
        special = f"{c.get('sqrt', 0)},{c.get('trig', 0)},{c.get('div', 0)}"
        key = (r["scenario"], r["integ"])
        if r["form"] == "body/diag":
            base[key] = r["us_target"]
        b = base.get(key)
        ratio = "" if (b is None or r["us_target"] is None) else f"{r['us_target'] / b:.2f}"
        nt = "n/a" if r["n_target"] is None else f"{r['n_target']:.0f}"
        ut = "n/a" if r["us_target"] is None else f"{r['us_target']:.1f}"
        inv = "" if r["scenario"] != "free" else f"{r['dL']:>8.1e} {r['dT']:>9.1e}"
        print(f"{r['scenario']:<6} {r['integ']:<5} {r['form']:<16} {total:>5} {special:>13} {r['ns_step']:>8.1f} "
              f"{r['order']:>5.2f} {r['att01']:>13.3e} {r['w01']:>10.2e} {inv:>18} {nt:>10} {ut:>9} {ratio:>6}")
    print(f"\ntargets: attitude error at t_end <= {TARGET['RK4']:g} rad (RK4), <= {TARGET['Euler']:g} rad (Euler); "
          "ratio = time to target / body/diag's (same torque case and integrator)")
    print(f"torque cases: free; tau_W = {TAU.tolist()} N m constant in the world frame (the body form rotates it "
          "with R^T at every evaluation); tau_B = the same vector constant in the body frame (the world form "
          "rotates it with R)")
    print("\nNumPy, the library's vectorised right-hand sides under one generic RK4:")
    print(f"{'formulation':<16} {'us/step, 1 body':>16} {'ns/body-step, 10k':>18} {'ratio (1 body)':>15} "
          f"{'ratio (10k)':>12}")
    b1, b2 = np_rows["body/diag"]
    for form, (t1, t2) in np_rows.items():
        print(f"{form:<16} {t1 * 1e6:>16.1f} {t2 * 1e9:>18.1f} {t1 / b1:>15.2f} {t2 / b2:>12.2f}")
    return rows, np_rows


if __name__ == "__main__":
    main()
