"""Run an integrator over segments of fixed steps: the engine of the step functions, ``integrate``
and ``inertia simulate``.

A run is a list of segments; segment k takes ``counts[k]`` steps of size ``hs[k]`` and the
state at its end is recorded.  The compiled loop (:mod:`inertia._ext.dynamics`, ``advance``)
takes one body at a time with the body angular momentum ``m = I w`` as the state; with a
progress callback the run is cut into pieces of about :data:`PROGRESS_WORK` body-steps and
reported between them (the state carries over, so the pieces change no bit).
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .._core.errors import IntegrationError
from .._ext import dynamics as _k

__all__ = ["run_segments", "METHOD_NAMES", "NEWTON_MAX_ITER", "PROGRESS_WORK"]

#: The integrators of the compiled core, in the order of its method index.
METHOD_NAMES: tuple = tuple(_k.METHODS)

#: Newton iterations allowed to the implicit methods (dmv, dmv4, midpoint) per step.
NEWTON_MAX_ITER: int = int(_k.NEWTON_MAX_ITER)

#: With a progress callback, the compiled loop returns to Python after about this many
#: body-steps (10-100 ms) to report.
PROGRESS_WORK = 1 << 20

_INDEX = {name: i for i, name in enumerate(METHOD_NAMES)}


def newton_failure(method, h, residual) -> IntegrationError:
    """The error of an implicit step whose Newton iteration did not converge."""
    return IntegrationError(f"{method}: the implicit step equation did not converge in {NEWTON_MAX_ITER} Newton "
                            f"iterations (relative residual {residual:.3g}); the time step h = {h!r} is too large "
                            f"for this angular velocity: reduce h")


def _diverged(method, step, t, h):
    return IntegrationError(f"method {method!r} diverged at step {step} (t = {t:.6g} s, h = {h:g} s): the angular "
                            f"velocity is no longer finite; reduce h or use a stable method such as 'splitting'")


def _flat(a, k):
    """A C-contiguous, writeable float64 copy with k columns (inputs are never modified)."""
    return np.array(np.reshape(a, (-1, k)), dtype=np.float64, order="C", copy=True)


def run_segments(method, q, w, I, tau, counts, hs, *, progress: Callable[[int], None] | None = None,
                 stop_if_not_finite: bool = True):
    """States at the start and after each segment: ``(qs (S+1, B..., 4), ws (S+1, B..., 3))``.

    q, w, I (and tau, or None) are already validated and broadcast to one batch shape;
    counts (S,) int >= 0 and hs (S,) float non-zero.  ``progress(n)`` is called with the
    number of steps (per body) done since its previous call.  A step whose state is no
    longer finite raises IntegrationError unless ``stop_if_not_finite`` is False (a lone step
    function returns what it computed); a Newton failure always raises.
    """
    counts = np.asarray(counts, dtype=np.int64)
    hs = np.asarray(hs, dtype=np.float64)
    batch = w.shape[:-1]
    S = len(counts)
    qf, wf, If = _flat(q, 4), _flat(w, 3), _flat(I, 3)
    tf = np.zeros((0, 3)) if tau is None else _flat(tau, 3)
    mf = If * wf
    B = qf.shape[0]
    qs = np.empty((S + 1, B, 4))
    ws = np.empty((S + 1, B, 3))
    qs[0], ws[0] = qf, wf
    done, t = 0, 0.0
    for c, h, slots in _pieces(counts, hs, progress, B):
        b, steps, kind, residual = _k.advance(_INDEX[method], qf, mf, If, tf, c, h, slots, qs, ws, stop_if_not_finite)
        if b >= 0:
            _raise_failure(method, h, c, steps, kind, residual, done, t)
        n = int(c.sum())
        done += n
        t += float(np.sum(c * h))
        if progress is not None:
            progress(n)
    return qs.reshape((S + 1,) + batch + (4,)), ws.reshape((S + 1,) + batch + (3,))


def _pieces(counts, hs, progress, bodies):
    """``(counts, hs, slots)`` per call of the compiled loop: one call, or ~PROGRESS_WORK each."""
    S = len(counts)
    slots = np.arange(1, S + 1, dtype=np.int64)
    if progress is None:
        yield counts, hs, slots
        return
    per_call = max(1, PROGRESS_WORK // max(1, bodies))
    # cut long segments into pieces of at most per_call steps; only a segment's last piece records
    reps = np.maximum(1, -(-counts // per_call))
    seg = np.repeat(np.arange(S), reps)
    last = np.cumsum(reps) - 1
    pc = np.full(len(seg), per_call, dtype=np.int64)
    pc[last] = counts - (reps - 1) * per_call
    ps = np.full(len(seg), -1, dtype=np.int64)
    ps[last] = slots
    # then group consecutive pieces into calls of about per_call steps
    call = (np.cumsum(pc) - pc) // per_call
    cuts = np.flatnonzero(np.diff(call)) + 1
    for lo, hi in zip(np.r_[0, cuts], np.r_[cuts, len(seg)]):
        yield pc[lo:hi], hs[seg[lo:hi]], ps[lo:hi]


def _raise_failure(method, hs, counts, steps, kind, residual, done, t):
    """Name the failing step: ``steps`` were done in this call before it."""
    ends = np.cumsum(counts)
    k = int(np.searchsorted(ends, steps, side="right"))
    h = float(hs[k])
    if kind == 1:
        raise newton_failure(method, h, residual)
    t += float(np.sum(counts[:k] * hs[:k])) + (steps - (ends[k - 1] if k else 0) + 1) * h
    raise _diverged(method, done + steps + 1, t, h)
