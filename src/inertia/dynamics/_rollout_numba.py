"""Numba kernels of :mod:`inertia.dynamics.rollouts` (private; imports numba at module level).

Imported only from inside the functions of :mod:`inertia.dynamics.rollouts` that need it, so
``import inertia`` never imports numba.  Every kernel is compiled with ``cache=True``.

The rotational step is the method's scalar twin of :mod:`._steps_numba` (the NumPy kernels
transcribed), the translation transcribes :func:`inertia.dynamics.transition.step_principal`.
Everything works in the principal frame P of the body, with the body angular momentum
``m = I w`` as the rotational state (as :func:`~inertia.dynamics.integrators.integrate`; the
NumPy rollout converts ``w -> m -> w`` at every step, a difference of one rounding).

Layout: bodies are processed in chunks of ``CHUNK``; inside a chunk the state lives in a flat
structure-of-arrays buffer with fixed row offsets, allocated once per range of chunks, and
every time step is a loop over the chunk that LLVM vectorises (the explicit methods: their
sin and cos are the branch-free :func:`._steps_numba.sincos`; the implicit methods' Newton
loops stay scalar in the same layout).  Left-over bodies (all of them for a single body) run
one at a time with the state in registers.  ``error_model="numpy"`` is required: Python's
ZeroDivisionError check on every division would keep the loops scalar.

One entry point per method (``range_<method>``, for a range of bodies; it releases the GIL,
and :mod:`.rollouts` runs disjoint ranges on threads) so that a method compiles only when
first used.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from . import _steps_numba as st

#: Bodies per chunk: a multiple of the SIMD width, small enough that the chunk buffer
#: (23 x CHUNK doubles, 23.5 kB) stays in L1.
CHUNK = 128

# Buffer rows (each CHUNK long): p 0-2, v 3-5, q 6-9, m 10-12, moments I 13-15, W = 1/I
# 16-18, the acceleration F/mass + g of the held world force 19-21, torque 22-24 (I, W per
# chunk, the inputs when they change).  Fixed offsets let LLVM prove that the rows do not
# overlap, so the loop over the chunk vectorises (with runtime alias checks between separate
# arrays it does not).
_ROWS = 25
_I_ROW = 13
_W_ROW = 16
_A_ROW = 19
_T_ROW = 22


#: LLVM may fuse a multiply and an add (FMA) and divide by multiplying with a reciprocal in
#: the loops over a chunk (a rounding apart from the NumPy kernels, like the sin and cos):
#: 2x for splitting, 1.3x for rk4 on AVX-512.  The one-body path keeps IEEE order exactly.
_CHUNK_MATH = {"contract", "arcp"}


# ============================================================================ one body, one step
@njit(cache=True, inline="always", error_model="numpy")
def _rotate(qw, qx, qy, qz, v0, v1, v2):
    # R(q) v = v + w t + u x t, t = 2 u x v   (rotations.quat_rotate)
    t0 = 2.0 * (qy * v2 - qz * v1)
    t1 = 2.0 * (qz * v0 - qx * v2)
    t2 = 2.0 * (qx * v1 - qy * v0)
    return (v0 + qw * t0 + (qy * t2 - qz * t1),
            v1 + qw * t1 + (qz * t0 - qx * t2),
            v2 + qw * t2 + (qx * t1 - qy * t0))


@njit(cache=True, inline="always", error_model="numpy")
def _translate(body_force, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, hw, hx, hy, hz, nw, nx, ny, nz,
               F0, F1, F2, m, g0, g1, g2, h):
    """Position and velocity over one step   (transition.step_principal, transition._translate).

    World force: exact for the held force, ``p += v h + a h^2/2``, ``v += a h``.  Body force:
    Simpson's rule on the force turned by the attitudes q (start), qh (half step), qn (end).
    """
    if body_force:
        f0, f1, f2 = _rotate(qw, qx, qy, qz, F0, F1, F2)
        a00, a01, a02 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        f0, f1, f2 = _rotate(hw, hx, hy, hz, F0, F1, F2)
        ah0, ah1, ah2 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        f0, f1, f2 = _rotate(nw, nx, ny, nz, F0, F1, F2)
        a10, a11, a12 = f0 / m + g0, f1 / m + g1, f2 / m + g2
        hs = h * h / 6.0
        h6 = h / 6.0
        return (p0 + v0 * h + (a00 + 2.0 * ah0) * hs, p1 + v1 * h + (a01 + 2.0 * ah1) * hs,
                p2 + v2 * h + (a02 + 2.0 * ah2) * hs, v0 + (a00 + 4.0 * ah0 + a10) * h6,
                v1 + (a01 + 4.0 * ah1 + a11) * h6, v2 + (a02 + 4.0 * ah2 + a12) * h6)
    a0 = F0 / m + g0
    a1 = F1 / m + g1
    a2 = F2 / m + g2
    hh = 0.5 * h * h
    return p0 + v0 * h + a0 * hh, p1 + v1 * h + a1 * hh, p2 + v2 * h + a2 * hh, v0 + a0 * h, v1 + a1 * h, v2 + a2 * h


# ============================================================================ a chunk of bodies
# Every function below that takes a function (``step``, ``chunk``) is inlined by numba into
# an entry point that names a global one: no function value is passed at run time (numba's
# first-class functions defeat its cache and, nested, its compiler).
@njit(cache=True, inline="always", error_model="numpy")
def _chunk_step(step, b, h):
    """One time step of the CHUNK bodies of the buffer ``b`` under world forces, in place;
    returns the first failed body or CHUNK.  (Body-frame forces take the one-body path: a
    second, half step per step would double the compiled code for a rarer case.)"""
    C = CHUNK
    bad = C
    hh = 0.5 * h * h
    for i in range(C):
        nw, nx, ny, nz, n0, n1, n2, ok = step(b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i],
                                              b[10 * C + i], b[11 * C + i], b[12 * C + i],
                                              b[13 * C + i], b[14 * C + i], b[15 * C + i],
                                              b[16 * C + i], b[17 * C + i], b[18 * C + i],
                                              b[22 * C + i], b[23 * C + i], b[24 * C + i], h, True)
        # exact for the held world force: p += v h + a h^2/2, v += a h   (transition._translate)
        for k in range(3):
            a = b[(19 + k) * C + i]
            v = b[(3 + k) * C + i]
            b[k * C + i] = b[k * C + i] + v * h + a * hh
            b[(3 + k) * C + i] = v + a * h
        b[6 * C + i], b[7 * C + i], b[8 * C + i], b[9 * C + i] = nw, nx, ny, nz
        b[10 * C + i], b[11 * C + i], b[12 * C + i] = n0, n1, n2
        if not ok:
            bad = min(bad, i)
    return bad


@njit(cache=True, inline="always", error_model="numpy")
def _save(out, r, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, frame, bf):
    """Store one state as ``out[r, bi]``: omega ``m / I``, converted from P back to the body frame B.

    ``frame`` (Nf, 13) holds ``q_BP`` (0:4) and ``R_BP`` row-major (4:13) per body (row ``bf``);
    an empty ``frame`` means P = B.  ``q_WB = q_WP (x) q_BP^-1``, ``w_B = R_BP w_P``
    (transition.state_from_principal).
    """
    w0 = m0 / I0
    w1 = m1 / I1
    w2 = m2 / I2
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
              b[13 * C + i], b[14 * C + i], b[15 * C + i], frame, b0 + i if Nf > 1 else 0)


@njit(cache=True, inline="always", error_model="numpy")
def _attitude_in_P(x0, bi, frame, bf):
    """``(q_WP, w_P)`` of state ``x0[bi]`` given in the body frame B   (transition._to_principal).

    ``q_WP = q_WB (x) q_BP``, ``w_P = R_BP^T w_B``; an empty ``frame`` means P = B.
    """
    qw, qx, qy, qz = x0[bi, 6], x0[bi, 7], x0[bi, 8], x0[bi, 9]
    w0, w1, w2 = x0[bi, 10], x0[bi, 11], x0[bi, 12]
    if frame.shape[0] == 0:
        return qw, qx, qy, qz, w0, w1, w2
    cw, cx, cy, cz = frame[bf, 0], frame[bf, 1], frame[bf, 2], frame[bf, 3]
    return (qw * cw - qx * cx - qy * cy - qz * cz, qw * cx + qx * cw + qy * cz - qz * cy,
            qw * cy - qx * cz + qy * cw + qz * cx, qw * cz + qx * cy - qy * cx + qz * cw,
            frame[bf, 4] * w0 + frame[bf, 7] * w1 + frame[bf, 10] * w2,
            frame[bf, 5] * w0 + frame[bf, 8] * w1 + frame[bf, 11] * w2,
            frame[bf, 6] * w0 + frame[bf, 9] * w1 + frame[bf, 12] * w2)


@njit(cache=True, error_model="numpy")
def _load_chunk(b, b0, x0, moments, frame):
    C = CHUNK
    Nb = moments.shape[0]
    Nf = frame.shape[0]
    for i in range(C):
        bb = b0 + i if Nb > 1 else 0
        for k in range(6):
            b[k * C + i] = x0[b0 + i, k]
        r = _attitude_in_P(x0, b0 + i, frame, b0 + i if Nf > 1 else 0)
        for k in range(4):
            b[(6 + k) * C + i] = r[k]
        for k in range(3):
            b[(_I_ROW + k) * C + i] = moments[bb, k]
            b[(_W_ROW + k) * C + i] = 1.0 / moments[bb, k]
            b[(10 + k) * C + i] = moments[bb, k] * r[4 + k]


@njit(cache=True, error_model="numpy")
def _load_inputs(b, b0, u, t, mass, gravity):
    """Inputs of step t: the acceleration ``F / mass + g`` of the world force, and the torque."""
    C = CHUNK
    tt = t if u.shape[0] > 1 else 0
    Nu = u.shape[1]
    Nb = mass.shape[0]
    for i in range(C):
        bu = b0 + i if Nu > 1 else 0
        m = mass[b0 + i if Nb > 1 else 0]
        for k in range(3):
            b[(_A_ROW + k) * C + i] = u[tt, bu, k] / m + gravity[k]
            b[(_T_ROW + k) * C + i] = u[tt, bu, 3 + k]


@njit(cache=True, inline="always", error_model="numpy")
def _run_chunks(chunk, lo, hi, x0, u, moments, mass, frame, gravity, h, n_steps, save_every, out, status):
    """Bodies ``lo .. hi - 1`` (whole chunks) a chunk at a time: load, ``chunk`` n_steps times, save."""
    b = np.empty(_ROWS * CHUNK)                       # the chunk's buffer, allocated once
    for b0 in range(lo, hi, CHUNK):
        _load_chunk(b, b0, x0, moments, frame)
        if save_every > 0:
            _save_chunk(out, 0, b0, b, frame)
        for t in range(n_steps):
            if t == 0 or u.shape[0] > 1:
                _load_inputs(b, b0, u, t, mass, gravity)
            bad = chunk(b, h)
            if bad < CHUNK:
                status[b0 + bad] = t
                break
            if save_every > 0 and (t + 1) % save_every == 0:
                _save_chunk(out, (t + 1) // save_every, b0, b, frame)
        if save_every == 0:
            _save_chunk(out, 0, b0, b, frame)


@njit(cache=True, inline="always", error_model="numpy")
def _run_singles(step, lo, hi, x0, u, moments, mass, frame, gravity, h, n_steps, save_every, body_force, out,
                 status):
    """Bodies ``lo .. hi - 1`` one at a time, the state in registers (single long trajectories)."""
    g0, g1, g2 = gravity[0], gravity[1], gravity[2]
    T = u.shape[0]
    for bi in range(lo, hi):
        bb = bi if moments.shape[0] > 1 else 0
        bu = bi if u.shape[1] > 1 else 0
        bf = bi if frame.shape[0] > 1 else 0
        I0, I1, I2, m = moments[bb, 0], moments[bb, 1], moments[bb, 2], mass[bb]
        W0, W1, W2 = 1.0 / I0, 1.0 / I1, 1.0 / I2
        p0, p1, p2 = x0[bi, 0], x0[bi, 1], x0[bi, 2]
        v0, v1, v2 = x0[bi, 3], x0[bi, 4], x0[bi, 5]
        qw, qx, qy, qz, w0, w1, w2 = _attitude_in_P(x0, bi, frame, bf)
        m0, m1, m2 = I0 * w0, I1 * w1, I2 * w2
        if save_every > 0:
            _save(out, 0, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, frame, bf)
        F0, F1, F2, t0, t1, t2 = u[0, bu, 0], u[0, bu, 1], u[0, bu, 2], u[0, bu, 3], u[0, bu, 4], u[0, bu, 5]
        for t in range(n_steps):
            if T > 1:
                F0, F1, F2 = u[t, bu, 0], u[t, bu, 1], u[t, bu, 2]
                t0, t1, t2 = u[t, bu, 3], u[t, bu, 4], u[t, bu, 5]
            nw, nx, ny, nz, m0n, m1n, m2n, ok = step(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2,
                                                     h, False)
            hw, hx, hy, hz = qw, qx, qy, qz
            if body_force:
                hw, hx, hy, hz, _, _, _, ok_half = step(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2,
                                                        t0, t1, t2, 0.5 * h, False)
                ok = ok and ok_half
            p0, p1, p2, v0, v1, v2 = _translate(body_force, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, hw, hx, hy, hz,
                                                nw, nx, ny, nz, F0, F1, F2, m, g0, g1, g2, h)
            qw, qx, qy, qz, m0, m1, m2 = nw, nx, ny, nz, m0n, m1n, m2n
            if not ok:
                status[bi] = t
                break
            if save_every > 0 and (t + 1) % save_every == 0:
                _save(out, (t + 1) // save_every, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, m0, m1, m2,
                      I0, I1, I2, frame, bf)
        if save_every == 0:
            _save(out, 0, bi, p0, p1, p2, v0, v1, v2, qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, frame, bf)


# ============================================================================ rollout
# The entry points, one per method: ``range_<method>(lo, hi, x0, u, moments, mass, frame,
# gravity, h, n_steps, save_every, body_force, out, status)`` rolls bodies lo .. hi - 1 forward
# ``n_steps`` steps (world forces: whole chunks first, the rest one at a time; body forces: one
# at a time) and writes their saved states to ``out``.  They release the GIL: the caller runs
# disjoint ranges on several threads.  Each names its step directly in its chunk loop, so
# numba inlines the step there and LLVM vectorises the loop over the chunk (a step passed
# down as an argument stays an opaque call); a method compiles only when first used.
#
# x0 : (N, 13) initial states ``[p_W, v_W, q_WB, w_B]`` in the body frame (the kernel moves
#     them to the principal frame P with ``frame``).
# u : (T, Nu, 6) inputs ``[F (world, or P if body_force), tau_P]``; T is 1 (held) or n_steps,
#     Nu is 1 (shared) or N.
# moments : (Nb, 3) principal moments; mass : (Nb,); Nb is 1 or N.
# frame : (Nf, 13) ``[q_BP, R_BP row-major]`` per body (Nf is 1 or N), or (0, 13) when the
#     principal frame is the body frame; the saved states are converted back to B with it.
# gravity : (3,) world acceleration (zeros for none).
# save_every : > 0 saves steps 0, save_every, ... into out (S, N, 13); 0 saves only the final
#     state into out (1, N, 13).
# status : (N,) int64, -1 on entry; the step at which an implicit method's Newton iteration
#     failed, for the first such body of a chunk (that chunk then stops).


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_euler_explicit(b, h):
    return _chunk_step(st.step_euler_explicit, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_euler_explicit(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_euler_explicit, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_euler_explicit, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_euler_implicit(b, h):
    return _chunk_step(st.step_euler_implicit, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_euler_implicit(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_euler_implicit, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_euler_implicit, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_rk4(b, h):
    return _chunk_step(st.step_rk4, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_rk4(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_rk4, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_rk4, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_splitting(b, h):
    return _chunk_step(st.step_splitting, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_splitting(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_splitting, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_splitting, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_dmv(b, h):
    return _chunk_step(st.step_dmv, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_dmv(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_dmv, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_dmv, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_dmv4(b, h):
    return _chunk_step(st.step_dmv4, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_dmv4(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_dmv4, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_dmv4, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


@njit(cache=True, error_model="numpy", fastmath=_CHUNK_MATH)
def _chunk_midpoint(b, h):
    return _chunk_step(st.step_midpoint, b, h)


@njit(cache=True, nogil=True, error_model="numpy")
def range_midpoint(lo, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status):
    mid = lo if bf else lo + (hi - lo) // CHUNK * CHUNK
    _run_chunks(_chunk_midpoint, lo, mid, x, u, I, ms, fr, g, h, n, every, out, status)
    _run_singles(st.step_midpoint, mid, hi, x, u, I, ms, fr, g, h, n, every, bf, out, status)


#: method name -> its entry point
KERNELS = {
    "euler_explicit": range_euler_explicit,
    "euler_implicit": range_euler_implicit,
    "rk4": range_rk4,
    "splitting": range_splitting,
    "dmv": range_dmv,
    "dmv4": range_dmv4,
    "midpoint": range_midpoint,
}
