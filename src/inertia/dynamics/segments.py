"""Run an integrator over segments of fixed steps: the engine of ``integrate`` and ``inertia simulate``.

A run is a list of segments; segment k takes ``counts[k]`` steps of size ``hs[k]`` and the
state at its end is recorded.  :func:`run_segments` does it on the NumPy kernels
(:mod:`.integrator_kernels`, the reference) or in one compiled loop
(:mod:`._integrate_numba`), with the body angular momentum ``m = I w`` as the state in both,
and reports progress between pieces of the run when asked.
"""

from __future__ import annotations

from typing import Callable

import numpy as np

from .._core.errors import IntegrationError
from .compiled import use_compiled
from .integrator_kernels import KERNELS

__all__ = ["run_segments", "COMPILED_METHODS", "PROGRESS_WORK"]

#: methods with a compiled loop (all of them)
COMPILED_METHODS = tuple(KERNELS)

#: With a progress callback, the compiled loop returns to Python after about this many
#: body-steps (10-100 ms) to report; the NumPy loop reports every PROGRESS_WORK / 1000.
PROGRESS_WORK = 1 << 20


def _compiled_kernel(method):
    def load():
        from . import _integrate_numba
        return _integrate_numba.SEGMENTS[method]
    return load


def run_segments(method, q, w, I, tau, counts, hs, *, backend="auto", progress: Callable[[int], None] | None = None):
    """States at the start and after each segment: ``(qs (S+1, B..., 4), ws (S+1, B..., 3))``.

    q, w, I (and tau, or None) are already validated and broadcast to one batch shape;
    counts (S,) int >= 0 and hs (S,) float non-zero.  ``progress(n)`` is called with the
    number of steps (per body) done since its previous call.
    """
    counts = np.asarray(counts, dtype=np.int64)
    hs = np.asarray(hs, dtype=float)
    batch = w.shape[:-1]
    bodies = int(np.prod(batch, dtype=np.int64))
    if use_compiled(backend, method, COMPILED_METHODS, int(counts.sum()), bodies, _compiled_kernel(method)):
        return _run_compiled(method, q, w, I, tau, counts, hs, progress)
    return _run_numpy(method, q, w, I, tau, counts, hs, progress)


def _diverged(method, step, t, h):
    return IntegrationError(f"method {method!r} diverged at step {step} (t = {t:.6g} s, h = {h:g} s): the angular "
                            f"velocity is no longer finite; reduce h or use a stable method such as 'splitting'")


def _run_numpy(method, q, w, I, tau, counts, hs, progress):
    kernel = KERNELS[method]
    batch = w.shape[:-1]
    S = len(counts)
    qs = np.empty((S + 1,) + batch + (4,))
    ws = np.empty((S + 1,) + batch + (3,))
    qs[0], ws[0] = q, w
    m = I * w
    every = max(1, PROGRESS_WORK // 1000 // max(1, int(np.prod(batch, dtype=np.int64))))
    done = pending = 0
    t = 0.0
    with np.errstate(over="ignore", invalid="ignore"):
        for k in range(S):
            h = float(hs[k])
            for j in range(int(counts[k])):
                q, m = kernel(q, m, I, h, tau)
                done += 1
                if not np.isfinite(m).all():
                    raise _diverged(method, done, t + (j + 1) * h, h)
                pending += 1
                if progress is not None and pending >= every:
                    progress(pending)
                    pending = 0
            qs[k + 1], ws[k + 1] = q, m / I
            t += counts[k] * h
    if progress is not None and pending:
        progress(pending)
    return qs, ws


def _flat(a, k):
    """A C-contiguous, writeable float64 copy (k columns): one numba type, inputs never modified."""
    return np.array(np.reshape(a, (-1, k)), dtype=np.float64, order="C", copy=True)


def _run_compiled(method, q, w, I, tau, counts, hs, progress):
    from . import _integrate_numba as nb

    batch = w.shape[:-1]
    S = len(counts)
    qf, wf, If = _flat(q, 4), _flat(w, 3), _flat(I, 3)
    tf = np.zeros_like(wf) if tau is None else _flat(tau, 3)
    mf = If * wf
    B = qf.shape[0]
    qs = np.empty((S + 1, B, 4))
    ws = np.empty((S + 1, B, 3))
    qs[0], ws[0] = qf, wf
    failure = np.zeros(2, dtype=np.int64)
    kernel = nb.SEGMENTS[method]
    done, t = 0, 0.0
    for c, h, slots in _pieces(counts, hs, progress, B):
        b = kernel(qf, mf, If, tf, c, h, slots, qs, ws, failure)
        if b >= 0:
            _raise_failure(method, qf[b], mf[b], If[b], None if tau is None else tf[b], h, c, done, t, failure)
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


def _raise_failure(method, q, m, I, tau, hs, counts, done, t, failure):
    """Name the failing step; the NumPy kernel, re-run on it, words a Newton failure itself."""
    steps = int(failure[0])                         # steps done in this call before the failure
    ends = np.cumsum(counts)
    k = int(np.searchsorted(ends, steps, side="right"))
    h = float(hs[k])
    t += float(np.sum(counts[:k] * hs[:k])) + (steps - (ends[k - 1] if k else 0) + 1) * h
    if failure[1] == 1:
        KERNELS[method](q[None], m[None], I[None], h, None if tau is None else tau[None])
    raise _diverged(method, done + steps + 1, t, h)
