"""The compiled loop of :func:`inertia.dynamics.integrators.integrate` (private; imports numba).

One body at a time, its state in registers, the steps of :mod:`._steps_numba` on the body
angular momentum (the state of the NumPy kernels).  The run is a list of segments (a count
of steps, a step size, and the record slot the state goes to at the segment's end, or -1);
the caller may cut a long run into several calls (the state is updated in place) to draw a
progress bar between them.
"""

from __future__ import annotations

import math

from numba import njit

from . import _steps_numba as st


@njit(cache=True, nogil=True, error_model="numpy")
def _segments(step, q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    """Advance every body over the segments with ``step``; returns -1, or the body that failed.

    q (B, 4) and m (B, 3) (``m = I w``, principal frame) hold the state and are updated in
    place; moments and torque (B, 3); counts (S,) int64 steps of size hs (S,) per segment;
    slots (S,) int64: the row of qs (R, B, 4) and ws (R, B, 3) that receives the state at
    the segment's end (omega ``m / I``), or -1.  On failure (an implicit method's Newton
    iteration did not converge, or the state stopped being finite) q[b] and m[b] hold the
    state before the failing step, ``failure[0]`` the number of steps done before it and
    ``failure[1]`` 1 for Newton, 2 for a non-finite state.
    """
    for b in range(q.shape[0]):
        qw, qx, qy, qz = q[b, 0], q[b, 1], q[b, 2], q[b, 3]
        m0, m1, m2 = m[b, 0], m[b, 1], m[b, 2]
        I0, I1, I2 = moments[b, 0], moments[b, 1], moments[b, 2]
        W0, W1, W2 = 1.0 / I0, 1.0 / I1, 1.0 / I2
        t0, t1, t2 = torque[b, 0], torque[b, 1], torque[b, 2]
        done = 0
        for k in range(counts.shape[0]):
            h = hs[k]
            for _ in range(counts[k]):
                nw, nx, ny, nz, n0, n1, n2, ok = step(qw, qx, qy, qz, m0, m1, m2, I0, I1, I2, W0, W1, W2,
                                                      t0, t1, t2, h, False)
                if not (ok and math.isfinite(n0) and math.isfinite(n1) and math.isfinite(n2)):
                    q[b, 0], q[b, 1], q[b, 2], q[b, 3] = qw, qx, qy, qz
                    m[b, 0], m[b, 1], m[b, 2] = m0, m1, m2
                    failure[0] = done
                    failure[1] = 2 if ok else 1
                    return b
                qw, qx, qy, qz, m0, m1, m2 = nw, nx, ny, nz, n0, n1, n2
                done += 1
            r = slots[k]
            if r >= 0:
                qs[r, b, 0], qs[r, b, 1], qs[r, b, 2], qs[r, b, 3] = qw, qx, qy, qz
                ws[r, b, 0], ws[r, b, 1], ws[r, b, 2] = m0 / I0, m1 / I1, m2 / I2
        q[b, 0], q[b, 1], q[b, 2], q[b, 3] = qw, qx, qy, qz
        m[b, 0], m[b, 1], m[b, 2] = m0, m1, m2
    return -1


# One entry point per method, so that a method compiles (about a second) only when first used:
# numba caches a function whose arguments are arrays, not one that takes a function.
@njit(cache=True, nogil=True, error_model="numpy")
def segments_euler_explicit(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_euler_explicit, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_euler_implicit(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_euler_implicit, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_rk4(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_rk4, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_splitting(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_splitting, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_dmv(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_dmv, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_dmv4(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_dmv4, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


@njit(cache=True, nogil=True, error_model="numpy")
def segments_midpoint(q, m, moments, torque, counts, hs, slots, qs, ws, failure):
    return _segments(st.step_midpoint, q, m, moments, torque, counts, hs, slots, qs, ws, failure)


#: method name -> its compiled loop
SEGMENTS = {"euler_explicit": segments_euler_explicit, "euler_implicit": segments_euler_implicit,
            "rk4": segments_rk4, "splitting": segments_splitting, "dmv": segments_dmv, "dmv4": segments_dmv4,
            "midpoint": segments_midpoint}
