"""Rollouts of the 6-DOF transition function: many steps, one body or a batch of bodies.

``rollout(x0, u, h, n_steps, body=..., method=...)`` repeats
:func:`inertia.dynamics.transition.step` with the same state layout, input layout, frames and
schemes.  A method name runs in the compiled core (:mod:`inertia._ext.dynamics`): the state is
moved to the principal frame of the body once, bodies go in chunks vectorised over the batch,
disjoint chunks on ``threads`` threads (the GIL released), and every body runs the same code, so
a body's result does not depend on the batch it is in, its place there or the thread count.  A
step function passed as ``method`` runs a Python loop over
:func:`inertia.dynamics.transition.step_principal`.
"""

from __future__ import annotations

import os

import numpy as np

from .._core.errors import InputError, IntegrationError
from .._core.validation import as_count, as_float_array, as_time_step, as_unit_quat
from .._ext import dynamics as _k
from .body import RigidBody, check_body
from .integrators import DEFAULT_METHOD
from .segments import METHOD_NAMES, NEWTON_MAX_ITER
from .state import FORCE, INPUT_SIZE, Q_WORLD_BODY, STATE_SIZE, TORQUE_BODY
from .transition import check_force_frame, resolve_method, state_from_principal, state_to_principal, step_principal

__all__ = ["rollout"]

#: From this many body-steps on, ``threads=None`` uses every core the process may run on.
_THREADS_MIN_WORK = 200_000


def rollout(x0, u, h, n_steps=None, *, body: RigidBody, method=DEFAULT_METHOD, gravity=None, force_frame: str = "world",
            save_every=1, threads: int | None = None) -> np.ndarray:
    """Roll the 6-DOF transition function forward over many steps.

    Parameters
    ----------
    x0 : (..., 13) float
        Initial states ``[p_world, v_world, q_world_body, omega_body]`` (see
        :mod:`inertia.dynamics.transition`).
    u : float array or None
        Inputs ``[force (N), torque_body (N m)]``, held over each step.

        * ``n_steps`` None: a time-major sequence (n_steps, ..., 6); step k uses ``u[k]``.
        * ``n_steps`` given: one input (..., 6) held for every step (None means zero).
    h : float, s, positive.
    n_steps : int >= 0 or None
        Number of steps when ``u`` is held constant; None takes it from ``u.shape[0]``.
    body : RigidBody
        One body, or a batch whose shape broadcasts with the state batch.
    method : str or callable
        Rotational scheme (see :func:`inertia.dynamics.transition.step`); default
        :data:`~inertia.dynamics.integrators.DEFAULT_METHOD` (splitting).
    gravity : (3,) float, m/s^2, world frame, or None.
    force_frame : {"world", "body"}
        Frame of the force.
    save_every : int >= 1 or None
        Save the state at steps 0, save_every, 2 save_every, ..., n_steps (``n_steps`` must be
        a multiple).  None saves only the final state.
    threads : int >= 1 or None
        Threads over the bodies (whole chunks each; the result is the same for any count).
        None: every core the process may use once the run has at least 200,000 body-steps,
        else one.

    Returns
    -------
    (S, ..., 13) float with S = n_steps // save_every + 1 saved states (the first is x0
    renormalised), or (..., 13) when ``save_every`` is None.  The batch shape is the broadcast
    of those of x0, u (without its time axis) and body.

    Raises
    ------
    InputError
        Bad shapes or values.
    IntegrationError
        An implicit method's Newton iteration did not converge (``h`` too large).

    Examples
    --------
    >>> from inertia.dynamics.state import pack_state
    >>> body = RigidBody(1.0, np.diag([0.0042, 0.0142, 0.0167]))
    >>> x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 10.0, 0.01])
    >>> rollout(x0, None, 1e-3, 100, body=body).shape
    (101, 13)
    >>> rollout(np.broadcast_to(x0, (5, 13)), np.zeros((100, 6)), 1e-3, body=body, save_every=None).shape
    (5, 13)
    """
    body = check_body(body)
    u, n, u_batch, held = _input_plan(u, n_steps)
    every = _save_plan(save_every, n)
    x0, hf, body_force, g, batch = _check_state(x0, h, force_frame, gravity, u, u_batch, held, body)
    rot_step = resolve_method(method)
    if threads is not None:
        threads = as_count(threads, "threads", 1)
    x0 = np.broadcast_to(x0, batch + (STATE_SIZE,))
    u_P = _inputs_to_principal(body, u, body_force)  # (..., 6) held, or (n, ..., 6)
    if isinstance(method, str):
        # the kernel moves the states to P as it loads them, and back as it stores them
        out = _rollout_compiled(x0, u_P, held, n, hf, body, g, every, method, body_force, batch, threads)
    else:
        x_P, _ = state_to_principal(body, x0, np.zeros(INPUT_SIZE), False)
        out = state_from_principal(body, _rollout_python(x_P, u_P, held, n, hf, body, g, every, rot_step,
                                                         body_force, batch))
    return out[0] if every == 0 else out


def _check_state(x0, h, force_frame, gravity, u, u_batch, held, body):
    """``(x0, h, body_force, gravity, batch shape)`` checked and broadcast for :func:`rollout`."""
    x0 = as_float_array(x0, "x0", (STATE_SIZE,)).copy()
    x0[..., Q_WORLD_BODY] = as_unit_quat(x0[..., Q_WORLD_BODY], "x0[..., 6:10] (q_world_body)")
    hf = as_time_step(h)
    force_frame = check_force_frame(force_frame)
    body_force = force_frame == "body"
    g = None if gravity is None else as_float_array(gravity, "gravity", (3,))
    if g is not None and g.shape != (3,):
        raise InputError(f"gravity must have shape (3,), got {g.shape}")
    try:
        batch = np.broadcast_shapes(x0.shape[:-1], u_batch, body.batch_shape)
    except ValueError:
        raise InputError(f"batch shapes do not broadcast: x0 {x0.shape}, u {u.shape} "
                         f"({'held' if held else 'time-major'}), body {body.batch_shape}") from None
    return x0, hf, body_force, g, batch


def _input_plan(u, n_steps):
    """``(u, n, u_batch, held)``: a held input for ``n_steps`` steps, or a time-major sequence."""
    if n_steps is None:
        if u is None:
            raise InputError("give n_steps when u is None (zero input held for n_steps steps)")
        u = as_float_array(u, "u", (INPUT_SIZE,))
        if u.ndim < 2:
            raise InputError(f"u must be a time-major sequence (n_steps, ..., 6) when n_steps is None, "
                             f"got shape {u.shape}; pass n_steps to hold one input")
        return u, u.shape[0], u.shape[1:-1], False
    n = as_count(n_steps, "n_steps", 0)
    u = np.zeros(INPUT_SIZE) if u is None else as_float_array(u, "u", (INPUT_SIZE,))
    return u, n, u.shape[:-1], True


def _save_plan(save_every, n: int) -> int:
    """Steps between saved states (0: only the final state)."""
    if save_every is None:
        return 0
    every = as_count(save_every, "save_every", 1)
    if n % every:
        raise InputError(f"n_steps ({n}) must be a multiple of save_every ({every})")
    return every


def _inputs_to_principal(body, u, body_force):
    """Torque (and a body-frame force) in the principal frame; u is (..., 6) or (n, ..., 6)."""
    if body.principal_is_body:
        return u
    R = body.R_body_principal
    to_P = lambda v: np.einsum("...ji,...j->...i", R, v)  # noqa: E731
    tau_P = to_P(u[..., TORQUE_BODY])
    F = to_P(u[..., FORCE]) if body_force else u[..., FORCE]
    shape = np.broadcast_shapes(F.shape[:-1], tau_P.shape[:-1])
    return np.concatenate([np.broadcast_to(F, shape + (3,)), np.broadcast_to(tau_P, shape + (3,))], axis=-1)


def _rollout_python(x_P, u_P, held, n, h, body, g, every, rot_step, body_force, batch):
    """A step function of the caller's: a Python loop over :func:`inertia.dynamics.transition.step_principal`."""
    S = 1 if every == 0 else n // every + 1
    out = np.empty((S,) + batch + (STATE_SIZE,))
    mass = body.mass[..., None]
    x = x_P
    if every:
        out[0] = x
    for k in range(n):
        uk = u_P if held else u_P[k]
        x = step_principal(x, uk, h, mass, body.moments, rot_step, g, body_force)
        if every and (k + 1) % every == 0:
            out[(k + 1) // every] = x
    if every == 0:
        out[0] = x
    return out


def _kernel_array(a) -> np.ndarray:
    return np.ascontiguousarray(a, dtype=np.float64)


def _threads(threads, N: int, n: int) -> int:
    if threads is not None:
        return threads
    if N * n < _THREADS_MIN_WORK:
        return 1
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def _rollout_compiled(x0, u_P, held, n, h, body, g, every, method, body_force, batch, threads):
    """Flatten the batch, call the kernel, restore the batch shape."""
    N = int(np.prod(batch, dtype=np.int64))
    x_flat = _kernel_array(np.broadcast_to(x0, batch + (STATE_SIZE,)).reshape(N, STATE_SIZE))
    # inputs: (T, Nu, 6) with T in {1, n} and Nu in {1, N}
    u_batch = u_P.shape[:-1] if held else u_P.shape[1:-1]
    shared = all(s == 1 for s in u_batch)
    if held:
        u_k = u_P.reshape(1, 1, INPUT_SIZE) if shared else \
            np.broadcast_to(u_P, batch + (INPUT_SIZE,)).reshape(1, N, INPUT_SIZE)
    else:
        u_P = u_P.reshape((u_P.shape[0],) + (1,) * (len(batch) - len(u_batch)) + u_P.shape[1:])  # batch right-aligned
        u_k = u_P.reshape(n, 1, INPUT_SIZE) if shared else \
            np.broadcast_to(u_P, (n,) + batch + (INPUT_SIZE,)).reshape(n, N, INPUT_SIZE)
    u_k = _kernel_array(u_k) if u_k.shape[0] else np.zeros((1, 1, INPUT_SIZE))
    # bodies: (Nb, 3) and (Nb,) with Nb in {1, N}
    if body.batch_shape:
        moments = _kernel_array(np.broadcast_to(body.moments, batch + (3,)).reshape(N, 3))
        mass = _kernel_array(np.broadcast_to(body.mass, batch).reshape(N))
    else:
        moments = _kernel_array(body.moments.reshape(1, 3))
        mass = _kernel_array(body.mass.reshape(1))
    gravity = np.zeros(3) if g is None else _kernel_array(g)
    # body <-> principal frame of the states: [q_BP, R_BP row-major] per body, none if P = B
    if body.principal_is_body:
        frame = np.zeros((0, 13))
    else:
        R = body.R_body_principal
        fr = np.concatenate([body.q_body_principal, R.reshape(R.shape[:-2] + (9,))], axis=-1)
        frame = _kernel_array(fr.reshape(1, 13) if not body.batch_shape else
                              np.broadcast_to(fr, batch + (13,)).reshape(N, 13))
    S = 1 if every == 0 else n // every + 1
    out = np.empty((S, N, STATE_SIZE))
    status = np.empty(N, dtype=np.int64)
    _k.rollout(METHOD_NAMES.index(method), x_flat, u_k, moments, mass, frame, gravity, float(h), int(n), int(every),
               bool(body_force), _threads(threads, N, n), out, status)
    failed = np.flatnonzero(status >= 0)
    if failed.size:
        b = int(failed[0])
        raise IntegrationError(f"{method}: the implicit step equation did not converge in {NEWTON_MAX_ITER} Newton "
                               f"iterations at step {int(status[b])} of body {b} (flat batch index); the time step "
                               f"h = {h!r} is too large for this angular velocity: reduce h")
    return out.reshape((S,) + batch + (STATE_SIZE,))
