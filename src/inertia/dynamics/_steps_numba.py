"""Scalar numba twins of the integrator kernels (private; imports numba at module level).

Imported only from inside the functions of :mod:`.integrators` and :mod:`.rollouts` that use
the compiled backend (through :mod:`._integrate_numba` and :mod:`._rollout_numba`), so
``import inertia`` never imports numba.  Every function is compiled with ``cache=True``.

Each ``step_<method>`` is a line-by-line transcription of ``kernel_<method>`` in
:mod:`.integrator_kernels` on scalars: the body angular momentum ``m = I w`` is the state,
``(q, m, I, W = 1/I, tau, h, vec) -> (q+, m+, ok)``, the same formulas in the same order of operations, so
the compiled and NumPy paths agree to a few ulps per step.  ``ok`` is False when an implicit
method's Newton iteration did not converge (the NumPy kernel raises there).  Two deliberate
differences, both at the level of one rounding:

* in the loops over a chunk of bodies (``vec=True``), sin and cos come from :func:`sincos`,
  a branch-free evaluation that LLVM vectorises (numba has no vector libm without Intel's
  SVML), accurate to about one ulp; one body at a time they come from libm;
* a zero torque is added rather than skipped (only the sign of a zero can differ).

numba's cache does not follow imports: the kernels of :mod:`._integrate_numba` and
:mod:`._rollout_numba` are cached with the code of these steps inside and are only
recompiled when their own file changes.  After editing this file, delete the ``*.nbi``/``*.nbc``
files of ``__pycache__`` (an installed package rewrites every file, which refreshes them all).

Repetition here is deliberate: the kernels are flat scalar arithmetic (numba compiles it to
registers; a helper returning tuples or a loop over the three coordinates costs measurably
in the inner loops), so a few lines of the same shape recur between kernels.
"""

from __future__ import annotations

import math

from numba import njit

from .equations import solve3_components
from .integrator_kernels import NEWTON_FAIL_RTOL, NEWTON_MAX_ITER, NEWTON_RTOL


def _in_chunk_loops(expr, caller, callee) -> bool:
    """numba's inline cost model for the steps and their helpers: inline them (numba IR) into
    the loops over a chunk of bodies only (functions named ``_chunk*``), where LLVM must see
    the whole step to vectorise; elsewhere a step is one compiled function, called."""
    return caller.func_id.func_name.startswith("_chunk")


_OPTS = dict(cache=True, error_model="numpy", inline=_in_chunk_loops)


# ============================================================================ sin and cos
# x = n pi/2 + r, |r| <= pi/4: n = floor(x 2/pi + 1/2); pi/2 = _PIO2_HI + _PIO2_LO with
# _PIO2_HI holding 33 bits, so n _PIO2_HI is exact for |n| < 2^20 and r carries an absolute
# error below 1e-20 there; beyond, the error is about ulp(x), the uncertainty of x itself.
# Then Taylor polynomials to degree 17 (sin) and 16 (cos): truncation below 1e-19 on |r| <= pi/4.
_TWO_OVER_PI = 0.63661977236758134308
_PIO2_HI = 1.57079632673412561417e+00        # first 33 bits of pi/2
_PIO2_LO = 6.07710050650619224932e-11        # pi/2 - _PIO2_HI
#: beyond this |x| the rounding of x exceeds pi/4: the angle carries no digit, r is set to 0
_SINCOS_NOISE = 2.0 ** 50
_S3, _S5, _S7, _S9, _S11, _S13, _S15, _S17 = (
    (-1.0) ** k / math.factorial(2 * k + 1) for k in range(1, 9))
_C2, _C4, _C6, _C8, _C10, _C12, _C14, _C16 = (
    (-1.0) ** k / math.factorial(2 * k) for k in range(1, 9))


@njit(**_OPTS)
def sincos(x):
    """``(sin x, cos x)`` without a branch or a call (vectorisable); about one ulp."""
    fn = math.floor(x * _TWO_OVER_PI + 0.5)
    r = (x - fn * _PIO2_HI) - fn * _PIO2_LO
    if abs(x) > _SINCOS_NOISE:
        r = 0.0 * r
    z = r * r
    z2 = z * z
    z4 = z2 * z2
    # degree-8 polynomials in z by Estrin's scheme (short dependency chains)
    ps = ((_S3 + z * _S5) + z2 * (_S7 + z * _S9)) + z4 * ((_S11 + z * _S13) + z2 * (_S15 + z * _S17))
    pc = ((_C2 + z * _C4) + z2 * (_C6 + z * _C8)) + z4 * ((_C10 + z * _C12) + z2 * (_C14 + z * _C16))
    s = r + (r * z) * ps
    c = 1.0 + z * pc
    half = fn * 0.5
    quarter = fn * 0.25
    odd = half - math.floor(half) != 0.0            # n odd: sin and cos swap
    k4 = quarter - math.floor(quarter)             # n mod 4, over 4
    sn = c if odd else s
    cs = s if odd else c
    if k4 >= 0.5:                                  # n = 2, 3: sin negative
        sn = -sn
    if 0.125 < k4 < 0.625:                         # n = 1, 2: cos negative
        cs = -cs
    return sn, cs


@njit(**_OPTS)
def trig(x, vec):
    """``(sin x, cos x)``: :func:`sincos` when ``vec`` (a constant of the caller), else libm.

    libm is faster for one body (shorter dependency chain); :func:`sincos` lets the loops over
    a chunk of bodies vectorise.
    """
    if vec:
        return sincos(x)
    return math.sin(x), math.cos(x)


# ============================================================================ helpers
@njit(**_OPTS)
def over(m, I, W, vec):
    """``m / I``: the NumPy kernels' division on one body; ``m * W`` (``W = 1 / I``, held by
    the caller) in the loops over a chunk, where divisions would bound the speed."""
    if vec:
        return m * W
    return m / I


@njit(**_OPTS)
def normalize(qw, qx, qy, qz):
    n = math.sqrt(qw * qw + qx * qx + qy * qy + qz * qz)
    return qw / n, qx / n, qy / n, qz / n


@njit(**_OPTS)
def exp_step(qw, qx, qy, qz, w0, w1, w2, h, vec):
    """``q (x) exp(h w / 2)``, normalised   (integrator_kernels.exp_step)."""
    v0 = h * w0
    v1 = h * w1
    v2 = h * w2
    theta = math.sqrt(v0 * v0 + v1 * v1 + v2 * v2)
    sh, pw = trig(0.5 * theta, vec)
    t2 = theta * theta
    # sin(t/2)/t = 1/2 - t^2/48 + t^4/3840 below 1e-4 (a select, not a branch)
    k = 0.5 - t2 / 48.0 + t2 * t2 / 3840.0 if theta < 1e-4 else sh / theta
    px = k * v0
    py = k * v1
    pz = k * v2
    rw = qw * pw - qx * px - qy * py - qz * pz
    rx = qw * px + qx * pw + qy * pz - qz * py
    ry = qw * py - qx * pz + qy * pw + qz * px
    rz = qw * pz + qx * py - qy * px + qz * pw
    return normalize(rw, rx, ry, rz)


#: ``a x = b`` by the adjugate: the NumPy kernels' own function, compiled (a: rows of three)
solve3 = njit(**_OPTS)(solve3_components)


@njit(cache=True, error_model="numpy")
def solve_quadratic(ch0, ch1, ch2, f0, f1, f2, with_alpha):
    """Newton on ``c = beta(c) chat + f (c_k c_l)``   (integrator_kernels._solve_quadratic).

    Returns ``(c0, c1, c2, ok)``; ``ok`` False: no convergence in NEWTON_MAX_ITER iterations.
    """
    c0 = ch0 + f0 * ch1 * ch2
    c1 = ch1 + f1 * ch2 * ch0
    c2 = ch2 + f2 * ch0 * ch1
    d0 = 2.0 * ch0
    d1 = 2.0 * ch1
    d2 = 2.0 * ch2
    for _ in range(NEWTON_MAX_ITER):
        beta = 1.0 + c0 * c0 + c1 * c1 + c2 * c2 if with_alpha else 1.0
        r0 = c0 - beta * ch0 - f0 * c1 * c2
        r1 = c1 - beta * ch1 - f1 * c2 * c0
        r2 = c2 - beta * ch2 - f2 * c0 * c1
        if with_alpha:
            e0, e1, e2 = solve3(((1.0 - d0 * c0, -d0 * c1 - f0 * c2, -d0 * c2 - f0 * c1),
                                 (-d1 * c0 - f1 * c2, 1.0 - d1 * c1, -d1 * c2 - f1 * c0),
                                 (-d2 * c0 - f2 * c1, -d2 * c1 - f2 * c0, 1.0 - d2 * c2)), (r0, r1, r2))
        else:
            e0, e1, e2 = solve3(((1.0, -f0 * c2, -f0 * c1), (-f1 * c2, 1.0, -f1 * c0), (-f2 * c1, -f2 * c0, 1.0)),
                                (r0, r1, r2))
        c0 = c0 - e0
        c1 = c1 - e1
        c2 = c2 - e2
        size = max(max(abs(c0), abs(c1)), abs(c2))
        corr = max(max(abs(e0), abs(e1)), abs(e2))
        if corr <= NEWTON_RTOL * size + 1e-300:
            return c0, c1, c2, True
    beta = 1.0 + c0 * c0 + c1 * c1 + c2 * c2 if with_alpha else 1.0
    res = max(max(abs(c0 - beta * ch0 - f0 * c1 * c2), abs(c1 - beta * ch1 - f1 * c2 * c0)),
              abs(c2 - beta * ch2 - f2 * c0 * c1))
    size = max(max(abs(c0), abs(c1)), abs(c2))
    worst = res / max(size, 1e-300)
    return c0, c1, c2, math.isfinite(worst) and worst <= NEWTON_FAIL_RTOL


# ============================================================================ the steps
@njit(**_OPTS)
def step_euler_explicit(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    w0 = over(m0, I0, W0, vec)
    w1 = over(m1, I1, W1, vec)
    w2 = over(m2, I2, W2, vec)
    n0 = m0 + h * ((m1 * w2 - m2 * w1) + t0)
    n1 = m1 + h * ((m2 * w0 - m0 * w2) + t1)
    n2 = m2 + h * ((m0 * w1 - m1 * w0) + t2)
    rw, rx, ry, rz = exp_step(qw, qx, qy, qz, over(n0, I0, W0, vec), over(n1, I1, W1, vec),
                              over(n2, I2, W2, vec), h, vec)
    return rw, rx, ry, rz, n0, n1, n2, True


@njit(**_OPTS)
def step_euler_implicit(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    w0 = over(m0, I0, W0, vec)
    w1 = over(m1, I1, W1, vec)
    w2 = over(m2, I2, W2, vec)
    g0 = (I1 - I2) * h
    g1 = (I2 - I0) * h
    g2 = (I0 - I1) * h
    f0 = (m1 * w2 - m2 * w1) + t0
    f1 = (m2 * w0 - m0 * w2) + t1
    f2 = (m0 * w1 - m1 * w0) + t2
    d0, d1, d2 = solve3(((I0, -g0 * w2, -g0 * w1), (-g1 * w2, I1, -g1 * w0), (-g2 * w1, -g2 * w0, I2)),
                        (h * f0, h * f1, h * f2))
    n0 = w0 + d0
    n1 = w1 + d1
    n2 = w2 + d2
    rw, rx, ry, rz = exp_step(qw, qx, qy, qz, n0, n1, n2, h, vec)
    return rw, rx, ry, rz, I0 * n0, I1 * n1, I2 * n2, True


@njit(**_OPTS)
def _rk4_rate(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, vec):
    # (dq/dt, dm/dt) = (1/2 q (x) (0, w), m x w + tau), w = m / I
    a = over(m0, I0, W0, vec)
    b = over(m1, I1, W1, vec)
    c = over(m2, I2, W2, vec)
    return (0.5 * (-qx * a - qy * b - qz * c),
            0.5 * (qw * a + qy * c - qz * b),
            0.5 * (qw * b - qx * c + qz * a),
            0.5 * (qw * c + qx * b - qy * a),
            (m1 * c - m2 * b) + t0,
            (m2 * a - m0 * c) + t1,
            (m0 * b - m1 * a) + t2)


@njit(**_OPTS)
def step_rk4(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    h2 = 0.5 * h
    aw, ax, ay, az, a0, a1, a2 = _rk4_rate(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, vec)
    bw, bx, by, bz, b0, b1, b2 = _rk4_rate(qw + h2 * aw, qx + h2 * ax, qy + h2 * ay, qz + h2 * az,
                                           m0 + h2 * a0, m1 + h2 * a1, m2 + h2 * a2,
                                           I0, I1, I2, W0, W1, W2, t0, t1, t2, vec)
    cw, cx, cy, cz, c0, c1, c2 = _rk4_rate(qw + h2 * bw, qx + h2 * bx, qy + h2 * by, qz + h2 * bz,
                                           m0 + h2 * b0, m1 + h2 * b1, m2 + h2 * b2,
                                           I0, I1, I2, W0, W1, W2, t0, t1, t2, vec)
    dw, dx, dy, dz, d0, d1, d2 = _rk4_rate(qw + h * cw, qx + h * cx, qy + h * cy, qz + h * cz,
                                           m0 + h * c0, m1 + h * c1, m2 + h * c2,
                                           I0, I1, I2, W0, W1, W2, t0, t1, t2, vec)
    h6 = h / 6.0
    rw, rx, ry, rz = normalize(qw + h6 * (aw + 2.0 * (bw + cw) + dw), qx + h6 * (ax + 2.0 * (bx + cx) + dx),
                               qy + h6 * (ay + 2.0 * (by + cy) + dy), qz + h6 * (az + 2.0 * (bz + cz) + dz))
    return (rw, rx, ry, rz, m0 + h6 * (a0 + 2.0 * (b0 + c0) + d0), m1 + h6 * (a1 + 2.0 * (b1 + c1) + d1),
            m2 + h6 * (a2 + 2.0 * (b2 + c2) + d2), True)


@njit(**_OPTS)
def _rotor(q0, qj, qk, ql, mj, mk, ml, Ij, Wj, dt, vec):
    # exact flow of H_j = m_j^2 / (2 I_j) over dt   (integrator_kernels._rotate_about_axis)
    sh, ch = trig(over((0.5 * dt) * mj, Ij, Wj, vec), vec)
    s = 2.0 * sh * ch
    c = 1.0 - 2.0 * sh * sh
    return (q0 * ch - qj * sh, qj * ch + q0 * sh, qk * ch + ql * sh, ql * ch - qk * sh,
            c * mk + s * ml, c * ml - s * mk)


@njit(**_OPTS)
def step_splitting(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    # kick, R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2), kick
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    dt = 0.5 * h
    # axis 0: (j, k, l) = (0, 1, 2), q components (w, x | y, z); axis 1: (1, 2, 0); axis 2: (2, 0, 1)
    qw, qx, qy, qz, m1, m2 = _rotor(qw, qx, qy, qz, m0, m1, m2, I0, W0, dt, vec)
    qw, qy, qz, qx, m2, m0 = _rotor(qw, qy, qz, qx, m1, m2, m0, I1, W1, dt, vec)
    qw, qz, qx, qy, m0, m1 = _rotor(qw, qz, qx, qy, m2, m0, m1, I2, W2, 1.0 * h, vec)
    qw, qy, qz, qx, m2, m0 = _rotor(qw, qy, qz, qx, m1, m2, m0, I1, W1, dt, vec)
    qw, qx, qy, qz, m1, m2 = _rotor(qw, qx, qy, qz, m0, m1, m2, I0, W0, dt, vec)
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    rw, rx, ry, rz = normalize(qw, qx, qy, qz)
    return rw, rx, ry, rz, m0, m1, m2, True


@njit(cache=True, error_model="numpy")
def _dmv_core(qw, qx, qy, qz, m0, m1, m2, W0, W1, W2, h):
    """One free DMV step with inverse moments W   (integrator_kernels._dmv_core)."""
    I0 = 1.0 / W0
    I1 = 1.0 / W1
    I2 = 1.0 / W2
    hh = 0.5 * h
    c0, c1, c2, ok = solve_quadratic(hh * m0 * W0, hh * m1 * W1, hh * m2 * W2,
                                     (I1 - I2) * W0, (I2 - I0) * W1, (I0 - I1) * W2, True)
    s = 1.0 / math.sqrt(1.0 + (c0 * c0 + c1 * c1 + c2 * c2))
    pw, px, py, pz = s, s * c0, s * c1, s * c2
    rw, rx, ry, rz = normalize(qw * pw - qx * px - qy * py - qz * pz, qw * px + qx * pw + qy * pz - qz * py,
                               qw * py - qx * pz + qy * pw + qz * px, qw * pz + qx * py - qy * px + qz * pw)
    v0 = -s * c0
    v1 = -s * c1
    v2 = -s * c2
    u0 = 2.0 * (v1 * m2 - v2 * m1)
    u1 = 2.0 * (v2 * m0 - v0 * m2)
    u2 = 2.0 * (v0 * m1 - v1 * m0)
    return (rw, rx, ry, rz, m0 + s * u0 + (v1 * u2 - v2 * u1), m1 + s * u1 + (v2 * u0 - v0 * u2),
            m2 + s * u2 + (v0 * u1 - v1 * u0), ok)


@njit(cache=True, error_model="numpy")
def step_dmv(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    qw, qx, qy, qz, m0, m1, m2, ok = _dmv_core(qw, qx, qy, qz, m0, m1, m2, W0, W1, W2, h)
    return qw, qx, qy, qz, m0 + (0.5 * h) * t0, m1 + (0.5 * h) * t1, m2 + (0.5 * h) * t2, ok


@njit(cache=True, error_model="numpy")
def step_dmv4(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    m0 = m0 + (0.5 * h) * t0
    m1 = m1 + (0.5 * h) * t1
    m2 = m2 + (0.5 * h) * t2
    # Hairer & Vilmart's modified inverse moments   (integrator_kernels._dmv4_inverse_moments)
    prod = I0 * I1 * I2
    s1 = (I0 + I1 + I2) / (6.0 * prod)
    s2 = -(W0 + W1 + W2) / 3.0
    d1 = -1.0 / (3.0 * prod)
    half_g2 = 0.5 * (m0 * m0 + m1 * m1 + m2 * m2)
    energy = 0.5 * (m0 * m0 / I0 + m1 * m1 / I1 + m2 * m2 / I2)
    h2 = h * h
    css = 1.0 + h2 * (s1 * half_g2 + s2 * energy)
    cdd = h2 * (d1 * half_g2 + s1 * energy)
    qw, qx, qy, qz, m0, m1, m2, ok = _dmv_core(qw, qx, qy, qz, m0, m1, m2, css / I0 + cdd, css / I1 + cdd,
                                               css / I2 + cdd, h)
    return qw, qx, qy, qz, m0 + (0.5 * h) * t0, m1 + (0.5 * h) * t1, m2 + (0.5 * h) * t2, ok


@njit(cache=True, error_model="numpy")
def step_midpoint(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2, t0, t1, t2, h, vec):
    # y = m_mid = m + h/2 (y x W y + tau), m+ = 2 y - m, q+ = q (x) exp(h W y / 2)
    hh = 0.5 * h
    y0, y1, y2, ok = solve_quadratic(m0 + hh * t0, m1 + hh * t1, m2 + hh * t2,
                                     hh * (W2 - W1), hh * (W0 - W2), hh * (W1 - W0), False)
    rw, rx, ry, rz = exp_step(qw, qx, qy, qz, W0 * y0, W1 * y1, W2 * y2, h, vec)
    return rw, rx, ry, rz, 2.0 * y0 - m0, 2.0 * y1 - m1, 2.0 * y2 - m2, ok
