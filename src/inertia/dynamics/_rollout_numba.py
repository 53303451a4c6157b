"""Numba kernels of :mod:`inertia.dynamics.rollouts` (private; imports numba at module level).

This module is imported only from inside the functions of :mod:`inertia.dynamics.rollouts`
that need it, so ``import inertia`` never imports numba.  Every kernel is compiled with
``cache=True`` (the machine code is stored next to this file in ``__pycache__``).

The rotational steps are line-by-line transcriptions of the NumPy kernels in
:mod:`inertia.dynamics.integrators` (``_k_euler_explicit``, ``_k_rk4``, ``_k_splitting``):
same formulas, same order of operations, so the two paths agree to a few ulps per step.
Everything works in the principal frame P of the body (moments on the diagonal), on scalars.

Layout: bodies are processed in chunks of ``CHUNK`` (parallel over chunks with ``prange``);
inside a chunk the state lives in a flat structure-of-arrays buffer with fixed row offsets and
every time step is a loop over the chunk, which LLVM vectorises for the trig-free method
(rk4).  Left-over bodies (all of them for a single body) run one at a time with the state in
registers.  ``error_model="numpy"`` is required: Python's ZeroDivisionError check on every
division would keep the loops scalar.

Repetition here is deliberate: the kernels are written as flat scalar arithmetic (numba
compiles it to registers; a helper returning tuples, or a loop over the three coordinates,
costs measurably in the inner loops), so a few lines of the same shape recur between kernels
that differ in what they accumulate.  ``duplicates`` lists them; they stay.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit, prange

#: Method ids (the kernel dispatches on them outside the loop over bodies).
EULER_EXPLICIT = 0
RK4 = 1
SPLITTING = 2
METHOD_IDS = {"euler_explicit": EULER_EXPLICIT, "rk4": RK4, "splitting": SPLITTING}

#: Bodies per chunk: a multiple of the SIMD width, small enough that the chunk buffer
#: (23 x CHUNK doubles, 23.5 kB) stays in L1.
CHUNK = 128


# ============================================================================ small kernels
@njit(cache=True, error_model="numpy")
def _accel(w0, w1, w2, I0, I1, I2, t0, t1, t2):
    # dw/dt = ((I w) x w + tau) / I   (integrators._accel_principal)
    m0 = I0 * w0
    m1 = I1 * w1
    m2 = I2 * w2
    return ((m1 * w2 - m2 * w1 + t0) / I0,
            (m2 * w0 - m0 * w2 + t1) / I1,
            (m0 * w1 - m1 * w0 + t2) / I2)


@njit(cache=True, error_model="numpy")
def _qdot(qw, qx, qy, qz, a, b, c):
    # 1/2 q (x) (0, w)   (equations._qmul_pure_right)
    return (0.5 * (-qx * a - qy * b - qz * c),
            0.5 * (qw * a + qy * c - qz * b),
            0.5 * (qw * b - qx * c + qz * a),
            0.5 * (qw * c + qx * b - qy * a))


@njit(cache=True, error_model="numpy")
def _normalize(qw, qx, qy, qz):
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return qw / n, qx / n, qy / n, qz / n


@njit(cache=True, error_model="numpy")
def _exp_step(qw, qx, qy, qz, w0, w1, w2, h):
    # q (x) exp(h w / 2), normalised   (integrators._exp_step, quaternion.quat_from_rotvec)
    v0 = h * w0
    v1 = h * w1
    v2 = h * w2
    theta = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    half = 0.5 * theta
    if theta < 1e-4:
        t2 = theta * theta
        k = 0.5 - t2 / 48.0 + t2 * t2 / 3840.0
    else:
        k = math.sin(half) / theta
    pw = math.cos(half)
    px = k * v0
    py = k * v1
    pz = k * v2
    rw = qw * pw - qx * px - qy * py - qz * pz
    rx = qw * px + qx * pw + qy * pz - qz * py
    ry = qw * py - qx * pz + qy * pw + qz * px
    rz = qw * pz + qx * py - qy * px + qz * pw
    return _normalize(rw, rx, ry, rz)


# ============================================================================ rotational steps
@njit(cache=True, inline="always", error_model="numpy")
def _rot_euler_explicit(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h):
    a0, a1, a2 = _accel(w0, w1, w2, I0, I1, I2, t0, t1, t2)
    n0 = w0 + h * a0
    n1 = w1 + h * a1
    n2 = w2 + h * a2
    rw, rx, ry, rz = _exp_step(qw, qx, qy, qz, n0, n1, n2, h)
    return rw, rx, ry, rz, n0, n1, n2


@njit(cache=True, inline="always", error_model="numpy")
def _rot_rk4(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h):
    h2 = 0.5 * h
    k1w, k1x, k1y, k1z = _qdot(qw, qx, qy, qz, w0, w1, w2)
    k1a, k1b, k1c = _accel(w0, w1, w2, I0, I1, I2, t0, t1, t2)
    sw, sx, sy, sz = qw + h2 * k1w, qx + h2 * k1x, qy + h2 * k1y, qz + h2 * k1z
    s0, s1, s2 = w0 + h2 * k1a, w1 + h2 * k1b, w2 + h2 * k1c
    k2w, k2x, k2y, k2z = _qdot(sw, sx, sy, sz, s0, s1, s2)
    k2a, k2b, k2c = _accel(s0, s1, s2, I0, I1, I2, t0, t1, t2)
    sw, sx, sy, sz = qw + h2 * k2w, qx + h2 * k2x, qy + h2 * k2y, qz + h2 * k2z
    s0, s1, s2 = w0 + h2 * k2a, w1 + h2 * k2b, w2 + h2 * k2c
    k3w, k3x, k3y, k3z = _qdot(sw, sx, sy, sz, s0, s1, s2)
    k3a, k3b, k3c = _accel(s0, s1, s2, I0, I1, I2, t0, t1, t2)
    sw, sx, sy, sz = qw + h * k3w, qx + h * k3x, qy + h * k3y, qz + h * k3z
    s0, s1, s2 = w0 + h * k3a, w1 + h * k3b, w2 + h * k3c
    k4w, k4x, k4y, k4z = _qdot(sw, sx, sy, sz, s0, s1, s2)
    k4a, k4b, k4c = _accel(s0, s1, s2, I0, I1, I2, t0, t1, t2)
    h6 = h / 6.0
    rw, rx, ry, rz = _normalize(qw + h6 * (k1w + 2.0 * (k2w + k3w) + k4w),
                                qx + h6 * (k1x + 2.0 * (k2x + k3x) + k4x),
                                qy + h6 * (k1y + 2.0 * (k2y + k3y) + k4y),
                                qz + h6 * (k1z + 2.0 * (k2z + k3z) + k4z))
    return (rw, rx, ry, rz,
            w0 + h6 * (k1a + 2.0 * (k2a + k3a) + k4a),
            w1 + h6 * (k1b + 2.0 * (k2b + k3b) + k4b),
            w2 + h6 * (k1c + 2.0 * (k2c + k3c) + k4c))


@njit(cache=True, error_model="numpy")
def _rotor(q0, qj, qk, ql, mj, mk, ml, Ij, dt):
    # exact flow of H_j = m_j^2 / (2 I_j) over dt  (integrators._rotate_about_axis)
    half = (0.5 * dt) * mj / Ij
    sh = math.sin(half)
    ch = math.cos(half)
    s = 2.0 * sh * ch
    c = 1.0 - 2.0 * sh * sh
    nk = c * mk + s * ml
    nl = c * ml - s * mk
    return (q0 * ch - qj * sh, qj * ch + q0 * sh, qk * ch + ql * sh, ql * ch - qk * sh, nk, nl)


@njit(cache=True, inline="always", error_model="numpy")
def _rot_splitting(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h):
    rw, rx, ry, rz, m0, m1, m2 = _rot_splitting_m(qw, qx, qy, qz, I0 * w0, I1 * w1, I2 * w2, I0, I1, I2,
                                                  t0, t1, t2, h)
    return rw, rx, ry, rz, m0 / I0, m1 / I1, m2 / I2


@njit(cache=True, inline="always", error_model="numpy")
def _rot_splitting_m(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, t0, t1, t2, h):
    # the splitting step on the body momentum m = I w (the state of the NumPy kernel: |m| is
    # kept to rounding, which a w state divided and re-multiplied each step would not be)
    # kick, R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2), kick
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    dt = 0.5 * h
    # axis 0: (j, k, l) = (0, 1, 2); q components (w, x | y, z)
    qw, qx, qy, qz, m1, m2 = _rotor(qw, qx, qy, qz, m0, m1, m2, I0, dt)
    # axis 1: (1, 2, 0); q components (w, y | z, x)
    qw, qy, qz, qx, m2, m0 = _rotor(qw, qy, qz, qx, m1, m2, m0, I1, dt)
    # axis 2: (2, 0, 1); q components (w, z | x, y)
    qw, qz, qx, qy, m0, m1 = _rotor(qw, qz, qx, qy, m2, m0, m1, I2, 1.0 * h)
    qw, qy, qz, qx, m2, m0 = _rotor(qw, qy, qz, qx, m1, m2, m0, I1, dt)
    qw, qx, qy, qz, m1, m2 = _rotor(qw, qx, qy, qz, m0, m1, m2, I0, dt)
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    rw, rx, ry, rz = _normalize(qw, qx, qy, qz)
    return rw, rx, ry, rz, m0, m1, m2


@njit(cache=True, error_model="numpy")
def _rot(method, qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h):
    if method == RK4:
        return _rot_rk4(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h)
    if method == SPLITTING:
        return _rot_splitting(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h)
    return _rot_euler_explicit(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h)


@njit(cache=True, error_model="numpy")
def _rotate(qw, qx, qy, qz, v0, v1, v2):
    # R(q) v = v + w t + u x t, t = 2 u x v   (quaternion.quat_rotate)
    t0 = 2.0 * (qy * v2 - qz * v1)
    t1 = 2.0 * (qz * v0 - qx * v2)
    t2 = 2.0 * (qx * v1 - qy * v0)
    return (v0 + qw * t0 + (qy * t2 - qz * t1),
            v1 + qw * t1 + (qz * t0 - qx * t2),
            v2 + qw * t2 + (qx * t1 - qy * t0))


# ============================================================================ one body, one step
@njit(cache=True, inline="always", error_model="numpy")
def _translate_world(p0, p1, p2, v0, v1, v2, F0, F1, F2, m, g0, g1, g2, h):
    # exact for the held world force: p += v h + a h^2/2, v += a h   (transition._translate)
    a0 = F0 / m + g0
    a1 = F1 / m + g1
    a2 = F2 / m + g2
    hh = 0.5 * h * h
    return (p0 + v0 * h + a0 * hh, p1 + v1 * h + a1 * hh, p2 + v2 * h + a2 * hh,
            v0 + a0 * h, v1 + a1 * h, v2 + a2 * h)


@njit(cache=True, error_model="numpy")
def _body_step(method, body_force, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2,
               I0, I1, I2, F0, F1, F2, t0, t1, t2, m, g0, g1, g2, h):
    """One step of one body in the principal frame   (transition.step_principal)."""
    nw, nx, ny, nz, n0, n1, n2 = _rot(method, qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h)
    if body_force:
        # Simpson on the rotating force: samples at 0, h/2, h   (transition._translate)
        hw, hx, hy, hz, _, _, _ = _rot(method, qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, 0.5 * h)
        f0, f1, f2 = _rotate(qw, qx, qy, qz, F0, F1, F2)
        a00, a01, a02 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        f0, f1, f2 = _rotate(hw, hx, hy, hz, F0, F1, F2)
        ah0, ah1, ah2 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        f0, f1, f2 = _rotate(nw, nx, ny, nz, F0, F1, F2)
        a10, a11, a12 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        hs = h * h / 6.0
        h6 = h / 6.0
        return (p0 + v0 * h + (a00 + 2.0 * ah0) * hs,
                p1 + v1 * h + (a01 + 2.0 * ah1) * hs,
                p2 + v2 * h + (a02 + 2.0 * ah2) * hs,
                v0 + (a00 + 4.0 * ah0 + a10) * h6,
                v1 + (a01 + 4.0 * ah1 + a11) * h6,
                v2 + (a02 + 4.0 * ah2 + a12) * h6,
                nw, nx, ny, nz, n0, n1, n2)
    p0, p1, p2, v0, v1, v2 = _translate_world(p0, p1, p2, v0, v1, v2, F0, F1, F2, m, g0, g1, g2, h)
    return p0, p1, p2, v0, v1, v2, nw, nx, ny, nz, n0, n1, n2


# ============================================================================ a chunk of bodies
# Buffer rows (each CHUNK long) of the flat chunk buffer: state 0-12, moments 13-15,
# input 16-21, mass 22.  Fixed offsets let LLVM prove that the rows do not overlap, so the
# loop over the chunk vectorises (with runtime alias checks between separate arrays it does not).
_ROWS = 23
_I_ROW = 13
_U_ROW = 16
_M_ROW = 22


# The three world-force chunk loops are written out, one per method, each calling its rotation
# step directly (inlined): no branch is left in the loop body, so LLVM vectorises it.  (A
# shared loop with a method argument keeps the branch and stays scalar.)
@njit(cache=True, error_model="numpy")
def _chunk_rk4(b, g0, g1, g2, h):
    C = CHUNK
    for i in range(C):
        qw, qx, qy, qz, w0, w1, w2 = _rot_rk4(b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i],
                                              b[10 * C + i], b[11 * C + i], b[12 * C + i],
                                              b[13 * C + i], b[14 * C + i], b[15 * C + i],
                                              b[19 * C + i], b[20 * C + i], b[21 * C + i], h)
        p0, p1, p2, v0, v1, v2 = _translate_world(b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i],
                                                  b[5 * C + i], b[16 * C + i], b[17 * C + i], b[18 * C + i],
                                                  b[22 * C + i], g0, g1, g2, h)
        b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i], b[5 * C + i] = p0, p1, p2, v0, v1, v2
        b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i] = qw, qx, qy, qz
        b[10 * C + i], b[11 * C + i], b[12 * C + i] = w0, w1, w2


@njit(cache=True, error_model="numpy")
def _chunk_splitting(b, g0, g1, g2, h):
    C = CHUNK
    for i in range(C):
        qw, qx, qy, qz, w0, w1, w2 = _rot_splitting(b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i],
                                                    b[10 * C + i], b[11 * C + i], b[12 * C + i],
                                                    b[13 * C + i], b[14 * C + i], b[15 * C + i],
                                                    b[19 * C + i], b[20 * C + i], b[21 * C + i], h)
        p0, p1, p2, v0, v1, v2 = _translate_world(b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i],
                                                  b[5 * C + i], b[16 * C + i], b[17 * C + i], b[18 * C + i],
                                                  b[22 * C + i], g0, g1, g2, h)
        b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i], b[5 * C + i] = p0, p1, p2, v0, v1, v2
        b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i] = qw, qx, qy, qz
        b[10 * C + i], b[11 * C + i], b[12 * C + i] = w0, w1, w2


@njit(cache=True, error_model="numpy")
def _chunk_euler_explicit(b, g0, g1, g2, h):
    C = CHUNK
    for i in range(C):
        qw, qx, qy, qz, w0, w1, w2 = _rot_euler_explicit(b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i],
                                                         b[10 * C + i], b[11 * C + i], b[12 * C + i],
                                                         b[13 * C + i], b[14 * C + i], b[15 * C + i],
                                                         b[19 * C + i], b[20 * C + i], b[21 * C + i], h)
        p0, p1, p2, v0, v1, v2 = _translate_world(b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i],
                                                  b[5 * C + i], b[16 * C + i], b[17 * C + i], b[18 * C + i],
                                                  b[22 * C + i], g0, g1, g2, h)
        b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i], b[5 * C + i] = p0, p1, p2, v0, v1, v2
        b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i] = qw, qx, qy, qz
        b[10 * C + i], b[11 * C + i], b[12 * C + i] = w0, w1, w2


@njit(cache=True, error_model="numpy")
def _chunk_generic(method, body_force, b, g0, g1, g2, h):
    """Any (method, body_force), through :func:`_body_step` (scalar; used for body forces)."""
    C = CHUNK
    for i in range(C):
        r = _body_step(method, body_force,
                       b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i], b[5 * C + i],
                       b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i],
                       b[10 * C + i], b[11 * C + i], b[12 * C + i],
                       b[13 * C + i], b[14 * C + i], b[15 * C + i],
                       b[16 * C + i], b[17 * C + i], b[18 * C + i], b[19 * C + i], b[20 * C + i], b[21 * C + i],
                       b[22 * C + i], g0, g1, g2, h)
        for k in range(13):
            b[k * C + i] = r[k]


@njit(cache=True, error_model="numpy")
def _advance_chunk(method, body_force, b, g0, g1, g2, h):
    """One time step of the CHUNK bodies of the flat buffer ``b`` (23 * CHUNK,), in place."""
    if body_force:
        _chunk_generic(method, body_force, b, g0, g1, g2, h)
    elif method == RK4:
        _chunk_rk4(b, g0, g1, g2, h)
    elif method == SPLITTING:
        _chunk_splitting(b, g0, g1, g2, h)
    else:
        _chunk_euler_explicit(b, g0, g1, g2, h)


@njit(cache=True, inline="always", error_model="numpy")
def _save(out, r, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2, frame, bf):
    """Store one state as ``out[r, bi]``, converted from P back to the body frame B.

    ``frame`` (Nf, 13) holds ``q_BP`` (0:4) and ``R_BP`` row-major (4:13) per body (row ``bf``);
    an empty ``frame`` means P = B.  ``q_WB = q_WP (x) q_BP^-1``, ``w_B = R_BP w_P``
    (transition.state_from_principal).
    """
    out[r, bi, 0] = p0
    out[r, bi, 1] = p1
    out[r, bi, 2] = p2
    out[r, bi, 3] = v0
    out[r, bi, 4] = v1
    out[r, bi, 5] = v2
    if frame.shape[0] == 0:
        out[r, bi, 6] = qw
        out[r, bi, 7] = qx
        out[r, bi, 8] = qy
        out[r, bi, 9] = qz
        out[r, bi, 10] = w0
        out[r, bi, 11] = w1
        out[r, bi, 12] = w2
        return
    cw, cx, cy, cz = frame[bf, 0], -frame[bf, 1], -frame[bf, 2], -frame[bf, 3]
    out[r, bi, 6] = qw * cw - qx * cx - qy * cy - qz * cz
    out[r, bi, 7] = qw * cx + qx * cw + qy * cz - qz * cy
    out[r, bi, 8] = qw * cy - qx * cz + qy * cw + qz * cx
    out[r, bi, 9] = qw * cz + qx * cy - qy * cx + qz * cw
    out[r, bi, 10] = frame[bf, 4] * w0 + frame[bf, 5] * w1 + frame[bf, 6] * w2
    out[r, bi, 11] = frame[bf, 7] * w0 + frame[bf, 8] * w1 + frame[bf, 9] * w2
    out[r, bi, 12] = frame[bf, 10] * w0 + frame[bf, 11] * w1 + frame[bf, 12] * w2


@njit(cache=True, error_model="numpy")
def _save_chunk(out, r, b0, b, frame):
    C = CHUNK
    Nf = frame.shape[0]
    for i in range(C):
        _save(out, r, b0 + i, b[i], b[C + i], b[2 * C + i], b[3 * C + i], b[4 * C + i], b[5 * C + i],
              b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i], b[10 * C + i], b[11 * C + i], b[12 * C + i],
              frame, b0 + i if Nf > 1 else 0)


@njit(cache=True, error_model="numpy")
def _run_chunk(b0, x0, u, moments, mass, frame, g0, g1, g2, h, n_steps, save_every, method, body_force, out):
    """Bodies ``b0 .. b0 + CHUNK - 1``: load, step ``n_steps`` times, save."""
    C = CHUNK
    T = u.shape[0]
    Nu = u.shape[1]
    Nb = moments.shape[0]
    b = np.empty(_ROWS * C)
    for i in range(C):
        for k in range(13):
            b[k * C + i] = x0[b0 + i, k]
        bb = b0 + i if Nb > 1 else 0
        for k in range(3):
            b[(_I_ROW + k) * C + i] = moments[bb, k]
        b[_M_ROW * C + i] = mass[bb]
    if save_every > 0:
        _save_chunk(out, 0, b0, b, frame)
    for t in range(n_steps):
        if t == 0 or T > 1:
            tt = t if T > 1 else 0
            for i in range(C):
                bu = b0 + i if Nu > 1 else 0
                for k in range(6):
                    b[(_U_ROW + k) * C + i] = u[tt, bu, k]
        _advance_chunk(method, body_force, b, g0, g1, g2, h)
        if save_every > 0 and (t + 1) % save_every == 0:
            _save_chunk(out, (t + 1) // save_every, b0, b, frame)
    if save_every == 0:
        _save_chunk(out, 0, b0, b, frame)


@njit(cache=True, error_model="numpy")
def _run_single(bi, x0, u, moments, mass, frame, g0, g1, g2, h, n_steps, save_every, method, body_force, out):
    """Body ``bi`` alone, its state in registers: the path of single long trajectories."""
    T = u.shape[0]
    Nu = u.shape[1]
    bb = bi if moments.shape[0] > 1 else 0
    bu = bi if Nu > 1 else 0
    bf = bi if frame.shape[0] > 1 else 0
    I0, I1, I2, m = moments[bb, 0], moments[bb, 1], moments[bb, 2], mass[bb]
    p0, p1, p2 = x0[bi, 0], x0[bi, 1], x0[bi, 2]
    v0, v1, v2 = x0[bi, 3], x0[bi, 4], x0[bi, 5]
    qw, qx, qy, qz = x0[bi, 6], x0[bi, 7], x0[bi, 8], x0[bi, 9]
    w0, w1, w2 = x0[bi, 10], x0[bi, 11], x0[bi, 12]
    if save_every > 0:
        _save(out, 0, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2, frame, bf)
    F0, F1, F2, t0, t1, t2 = u[0, bu, 0], u[0, bu, 1], u[0, bu, 2], u[0, bu, 3], u[0, bu, 4], u[0, bu, 5]
    for t in range(n_steps):
        if T > 1:
            F0, F1, F2, t0, t1, t2 = u[t, bu, 0], u[t, bu, 1], u[t, bu, 2], u[t, bu, 3], u[t, bu, 4], u[t, bu, 5]
        p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2 = _body_step(
            method, body_force, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2,
            I0, I1, I2, F0, F1, F2, t0, t1, t2, m, g0, g1, g2, h)
        if save_every > 0 and (t + 1) % save_every == 0:
            _save(out, (t + 1) // save_every, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2, frame, bf)
    if save_every == 0:
        _save(out, 0, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, w0, w1, w2, frame, bf)


# ============================================================================ rollout
@njit(cache=True, parallel=True, error_model="numpy")
def rollout_kernel(x0, u, moments, mass, frame, gravity, h, n_steps, save_every, method, body_force, out):
    """Roll N bodies forward ``n_steps`` steps; write the saved states to ``out``.

    Parameters (all float64, C-contiguous)
    ----------
    x0 : (N, 13) initial states in the principal frame, ``[p_W, v_W, q_WP, w_P]``.
    u : (T, Nu, 6) inputs ``[F (world, or P if body_force), tau_P]``; T is 1 (held) or
        n_steps, Nu is 1 (shared) or N.
    moments : (Nb, 3) principal moments; mass : (Nb,); Nb is 1 or N.
    frame : (Nf, 13) ``[q_BP, R_BP row-major]`` per body (Nf is 1 or N), or (0, 13) when the
        principal frame is the body frame; the saved states are converted back to B with it.
    gravity : (3,) world acceleration (zeros for none).
    save_every : int; > 0 saves steps 0, save_every, ... into out (S, N, 13), 0 saves only the
        final state into out (1, N, 13).

    Full chunks of CHUNK bodies take the vectorised path; the remaining bodies (all of them
    when N < CHUNK) take the one-body path.  Both evaluate the same IEEE operations.
    """
    N = x0.shape[0]
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    n_full = N // CHUNK
    for c in prange(n_full):
        _run_chunk(c * CHUNK, x0, u, moments, mass, frame, g0, g1, g2, h, n_steps, save_every, method,
                   body_force, out)
    for bi in prange(n_full * CHUNK, N):
        _run_single(bi, x0, u, moments, mass, frame, g0, g1, g2, h, n_steps, save_every, method, body_force, out)


@njit(cache=True, nogil=True, error_model="numpy")
def rollout_kernel_serial(x0, u, moments, mass, frame, gravity, h, n_steps, save_every, method, body_force, out):
    """:func:`rollout_kernel` for a few bodies: one at a time on the calling thread (no pool)."""
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    for bi in range(x0.shape[0]):
        _run_single(bi, x0, u, moments, mass, frame, g0, g1, g2, h, n_steps, save_every, method, body_force, out)


# ============================================================================ integrate
@njit(cache=True, nogil=True, error_model="numpy")
def integrate_kernel(method, q, w, moments, torque, h, recorded, qs, ws):
    """The compiled path of :func:`inertia.dynamics.integrators.integrate` (rotation only).

    q (B, 4), w (B, 3), moments (B, 3), torque (B, 3) (zeros for none), all in the principal
    frame; ``recorded`` (R,) ascending step numbers, starting at 0; the states at those
    steps go to qs (R, B, 4) and ws (R, B, 3).  Returns -1, or the first step at which a
    body's angular velocity stopped being finite (the caller raises).
    """
    n = recorded[recorded.shape[0] - 1]
    for b in range(q.shape[0]):
        qw, qx, qy, qz = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
        w0, w1, w2 = w[b, 0], w[b, 1], w[b, 2]
        I0, I1, I2 = moments[b, 0], moments[b, 1], moments[b, 2]
        t0, t1, t2 = torque[b, 0], torque[b, 1], torque[b, 2]
        qs[0, b, 0], qs[0, b, 1], qs[0, b, 2], qs[0, b, 3] = qw, qx, qy, qz
        ws[0, b, 0], ws[0, b, 1], ws[0, b, 2] = w0, w1, w2
        r = 1
        if method == SPLITTING:  # momentum state, as the NumPy kernel
            w0, w1, w2 = I0 * w0, I1 * w1, I2 * w2
        for i in range(1, n + 1):
            if method == SPLITTING:
                qw, qx, qy, qz, w0, w1, w2 = _rot_splitting_m(qw, qx, qy, qz, w0, w1, w2, I0, I1, I2,
                                                              t0, t1, t2, h)
            else:
                qw, qx, qy, qz, w0, w1, w2 = _rot(method, qw, qx, qy, qz, w0, w1, w2, I0, I1, I2, t0, t1, t2, h)
            if not (math.isfinite(w0) and math.isfinite(w1) and math.isfinite(w2)):
                return i
            if r < recorded.shape[0] and recorded[r] == i:
                qs[r, b, 0], qs[r, b, 1], qs[r, b, 2], qs[r, b, 3] = qw, qx, qy, qz
                if method == SPLITTING:
                    ws[r, b, 0], ws[r, b, 1], ws[r, b, 2] = w0 / I0, w1 / I1, w2 / I2
                else:
                    ws[r, b, 0], ws[r, b, 1], ws[r, b, 2] = w0, w1, w2
                r += 1
    return -1
