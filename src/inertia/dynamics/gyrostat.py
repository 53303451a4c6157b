"""Bodies with rotors (gyrostats): a rigid body carrying reaction wheels along fixed body axes.

State, a (13 + n)-vector for n wheels (last axis; any leading batch dimensions)::

    x = [ p_world (0:3) | v_world (3:6) | q_world_body (6:10) | omega_body (10:13) | h_wheels (13:13+n) ]

Input, a (6 + n)-vector: ``u = [ force_world (0:3) | torque_body (3:6) | wheel_torques (6:6+n) ]``.
Error state, (12 + n): ``[dp_world, dv_world, dtheta_body, domega_body, dh_wheels]`` with the
attitude perturbed on the right, as in :mod:`inertia.dynamics.transition`.

Model (Hughes, *Spacecraft Attitude Dynamics*, 1986, ch. 9; Wie, *Space Vehicle Dynamics and
Control*, 2nd ed., 2008, section 7.7): wheel k spins about the unit body axis ``a_k``;
``h_k = J_k (a_k . omega + Omega_k)`` is its **absolute** axial angular momentum (Omega_k its
rate relative to the body, J_k its axial moment), and the motor torque on it is ``h_k' = u_k``.
``body.inertia_com`` is the inertia of the whole gyrostat about its center of mass with the
wheels' axial moments ``J_k a_k a_k^T`` taken out (their transverse moments and masses stay in).
With ``h = sum_k h_k a_k`` (body frame)::

    I omega' + omega x (I omega + h) = tau_ext - sum_k u_k a_k,        h_k' = u_k

The total angular momentum ``m = I omega + h`` obeys ``m' = m x omega + tau_ext``: the wheel
torques are internal.  The wheels' limits (``max_torque``, ``max_momentum``) act in the plant:
a commanded torque is first limited so that ``|h_k|`` stays within ``max_momentum`` over the
hold, then to ``max_torque`` (:func:`saturate_wheel_torque`).

Methods: ``"splitting"`` (default; Strang: kick, the three exact rotor flows of
``H = sum_j (m_j - h_j)^2 / 2 I_j`` with h frozen, kick; keeps |m| and the world L to rounding,
second order) and ``"rk4"`` (classical, fourth order).  Jacobians come from the complex step
through the compiled step itself (exact to rounding, no difference taken).
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from .._core.rotations import quat_conjugate, quat_multiply
from .._core.validation import as_count, as_float_array, as_unit_quat
from .._ext import dynamics as _k
from .body import RigidBody, check_body
from .integrators import DEFAULT_METHOD
from .segments import METHOD_NAMES

__all__ = ["Gyrostat", "WheelFeedback", "GyrostatRun", "gyrostat_step", "gyrostat_jacobians", "gyrostat_rollout",
           "saturate_wheel_torque", "rollout_threads", "GYROSTAT_METHODS", "MAX_WHEELS"]

#: The gyrostat integrators; the first is the default.
GYROSTAT_METHODS = ("splitting", "rk4")
#: Most wheels a gyrostat may carry (the compiled loops are specialised for 0..MAX_WHEELS).
MAX_WHEELS = int(_k.MAX_WHEELS)
#: A wheel axis is accepted when its norm is within this of 1 (then normalised).
AXIS_NORM_TOL = 1e-6
#: From this many body-steps on, ``threads=None`` uses every core the process may run on.
THREADS_MIN_WORK = 200_000


@dataclass(frozen=True, eq=False)
class Gyrostat:
    """A rigid body with reaction wheels along fixed body axes.

    Parameters
    ----------
    body : RigidBody
        Mass and central inertia of the gyrostat, wheels' axial moments excluded (module
        docstring); a batch of bodies is allowed (Monte Carlo).
    wheel_axes : (n, 3) or (..., n, 3) float, unit vectors in the body frame, 0 <= n <= 6.
    max_torque : (n,) float, N m, positive; ``inf`` (the default) for no limit.
    max_momentum : (n,) float, N m s, positive; ``inf`` (the default) for no limit.

    Examples
    --------
    >>> g = Gyrostat(RigidBody.from_principal_moments(750.0, [600.0, 800.0, 900.0]), np.eye(3),
    ...              max_torque=[0.2] * 3, max_momentum=[50.0] * 3)
    >>> g.n_wheels, g.batch_shape
    (3, ())
    """

    body: RigidBody
    wheel_axes: np.ndarray
    max_torque: np.ndarray = None
    max_momentum: np.ndarray = None
    n_wheels: int = field(init=False)

    def __post_init__(self):
        check_body(self.body)
        axes = as_float_array(self.wheel_axes, "wheel_axes", (3,))
        if axes.ndim < 2:
            raise InputError(f"wheel_axes must have shape (n, 3) or (..., n, 3), got {axes.shape}")
        n = axes.shape[-2]
        if n > MAX_WHEELS:
            raise InputError(f"a gyrostat carries at most {MAX_WHEELS} wheels, got {n}")
        norms = np.linalg.norm(axes, axis=-1)
        if n and np.any(np.abs(norms - 1.0) > AXIS_NORM_TOL):
            k = np.unravel_index(np.argmax(np.abs(norms - 1.0)), norms.shape)
            raise InputError(f"wheel axis {k[-1]} has norm {norms[k]:.9g}, expected a unit vector "
                             f"(within {AXIS_NORM_TOL:g})")
        limits = {}
        for name in ("max_torque", "max_momentum"):
            v = getattr(self, name)
            v = np.full(n, np.inf) if v is None else as_float_array(v, name, (), allow_batch=True)
            v = np.broadcast_to(v, (n,)) if v.ndim == 0 else v
            if v.shape != (n,):
                raise InputError(f"{name} must have shape ({n},) (one per wheel), got {v.shape}")
            if np.any(~(v > 0)):
                raise InputError(f"{name} must be positive (inf for no limit), got {v.tolist()}")
            limits[name] = v
        for name, val in (("wheel_axes", axes / np.where(norms > 0, norms, 1.0)[..., None]),
                          ("max_torque", limits["max_torque"]), ("max_momentum", limits["max_momentum"])):
            val = np.array(val, dtype=np.float64, copy=True)
            val.setflags(write=False)
            object.__setattr__(self, name, val)
        object.__setattr__(self, "n_wheels", int(n))

    @property
    def batch_shape(self) -> tuple:
        """Leading (batch) shape: that of the body and of the wheel axes, broadcast."""
        try:
            return np.broadcast_shapes(self.body.batch_shape, self.wheel_axes.shape[:-2])
        except ValueError:
            raise InputError(f"body batch {self.body.batch_shape} and wheel_axes {self.wheel_axes.shape} "
                             "do not broadcast") from None

    def with_body(self, body: RigidBody) -> "Gyrostat":
        """The same wheels on another body (or a batch of bodies)."""
        return Gyrostat(body, self.wheel_axes, self.max_torque, self.max_momentum)


@dataclass(frozen=True, eq=False)
class WheelFeedback:
    """An affine wheel-torque law evaluated inside the compiled loop, once per control period.

    ``u = u_ff - gain @ [omega_body - omega_ref; h_wheels - h_ref]`` (then saturated by the plant).

    gain : (..., n, 3 + n), N m per (rad/s) and per (N m s); omega_ref : (..., 3) rad/s, body
    frame; h_ref : (..., n) N m s; u_ff : (..., n) N m (None: zero).
    """

    gain: np.ndarray
    omega_ref: np.ndarray
    h_ref: np.ndarray
    u_ff: np.ndarray = None


@dataclass(frozen=True, eq=False)
class GyrostatRun:
    """A rollout: ``states`` (S, ..., 13 + n), ``t`` (S,) s, and ``tilt`` (S, ...) rad, the largest
    angle between the monitored body axis and the total angular momentum since the previous saved
    state (row 0: at t = 0), or None when no axis was monitored."""

    t: np.ndarray
    states: np.ndarray
    tilt: np.ndarray | None


# ---------------------------------------------------------------------------- helpers
def _check_gyrostat(g) -> Gyrostat:
    if not isinstance(g, Gyrostat):
        raise InputError(f"gyrostat must be a Gyrostat (body, wheel_axes, limits), got {type(g).__name__}")
    return g


def _method_index(method) -> int:
    if method not in GYROSTAT_METHODS:
        raise InputError(f"method must be one of {list(GYROSTAT_METHODS)} for a gyrostat, got {method!r}")
    return METHOD_NAMES.index(method)


def _positive_step(h) -> float:
    h = as_float_array(h, "h", (), allow_batch=False)
    if not (np.isfinite(h) and h > 0):
        raise InputError(f"h must be a positive, finite time step in s, got {float(h)!r}")
    return float(h)


def _to_body(R_BP, v_P):
    return np.einsum("...ij,...j->...i", R_BP, v_P)


def _to_principal(R_BP, v_B):
    return np.einsum("...ji,...j->...i", R_BP, v_B)


def _state(x, n, name="x"):
    x = as_float_array(x, name, (13 + n,)).copy()
    x[..., 6:10] = as_unit_quat(x[..., 6:10], f"{name}[..., 6:10] (q_world_body)")
    return x


def _states_to_principal(body, x):
    """(..., 13 + n) body-frame states to the principal frame: q_WP = q_WB (x) q_BP, w_P = R_BP^T w_B."""
    if body.principal_is_body:
        return x
    out = np.array(np.broadcast_to(x, np.broadcast_shapes(x.shape[:-1], body.batch_shape) + x.shape[-1:]))
    out[..., 6:10] = quat_multiply(out[..., 6:10], body.q_body_principal)
    out[..., 10:13] = _to_principal(body.R_body_principal, out[..., 10:13])
    return out


def _states_from_principal(body, x_P):
    if body.principal_is_body:
        return x_P
    R, q = body.R_body_principal, body.q_body_principal
    extra = x_P.ndim - 1 - len(body.batch_shape)         # leading axes (the saved-state axis)
    R, q = R[(None,) * extra], q[(None,) * extra]
    out = np.array(x_P)
    out[..., 6:10] = quat_multiply(x_P[..., 6:10], quat_conjugate(q))
    out[..., 10:13] = _to_body(R, x_P[..., 10:13])
    return out


def _rows(a, batch, N):
    """(1, k) when ``a`` has no batch axes, else (N, k) broadcast to ``batch``."""
    a = np.asarray(a, dtype=np.float64)
    if a.ndim == 1:
        return np.ascontiguousarray(a[None])
    return np.ascontiguousarray(np.broadcast_to(a, batch + a.shape[-1:]).reshape(N, a.shape[-1]))


def _plant(g: Gyrostat, ext, batch, N):
    """Rows [mass, moments, wheel axes (P), max torque, max momentum, force (world), torque (P)]."""
    body, n = g.body, g.n_wheels
    axes_P = g.wheel_axes if body.principal_is_body else g.wheel_axes @ body.R_body_principal  # rows R_BP^T a_k
    tau_P = ext[..., 3:6] if body.principal_is_body else _to_principal(body.R_body_principal, ext[..., 3:6])
    parts = [body.mass[..., None], body.moments, axes_P.reshape(axes_P.shape[:-2] + (3 * n,)),
             g.max_torque, g.max_momentum, ext[..., 0:3], tau_P]
    shape = np.broadcast_shapes(*(p.shape[:-1] for p in parts))
    row = np.concatenate([np.broadcast_to(p, shape + p.shape[-1:]) for p in parts], axis=-1)
    return _rows(row, batch, N)


def _control(g: Gyrostat, fb: WheelFeedback | None, monitor_axis, batch, N):
    """Rows [gain (P), omega_ref (P), h_ref, u_ff, monitored axis (P)]."""
    n, body = g.n_wheels, g.body
    if fb is None:
        fb = WheelFeedback(np.zeros((n, 3 + n)), np.zeros(3), np.zeros(n))
    K = as_float_array(fb.gain, "feedback.gain", (n, 3 + n))
    w_ref = as_float_array(fb.omega_ref, "feedback.omega_ref", (3,))
    h_ref = as_float_array(fb.h_ref, "feedback.h_ref", (n,))
    u_ff = np.zeros(n) if fb.u_ff is None else as_float_array(fb.u_ff, "feedback.u_ff", (n,))
    s = np.zeros(3) if monitor_axis is None else as_float_array(monitor_axis, "monitor_axis", (3,))
    if monitor_axis is not None:
        s = s / np.linalg.norm(s, axis=-1, keepdims=True)
    if not body.principal_is_body:
        R = body.R_body_principal
        # u = -K_B [R_BP (w_P - w_ref_P); dh]: the rate columns of the gain times R_BP
        KR = K[..., :3] @ R
        K = np.concatenate([KR, np.broadcast_to(K[..., 3:], KR.shape[:-2] + (n, n))], axis=-1)
        w_ref, s = _to_principal(R, w_ref), _to_principal(R, s)
    parts = [K.reshape(K.shape[:-2] + (n * (3 + n),)), w_ref, h_ref, u_ff, s]
    shape = np.broadcast_shapes(*(p.shape[:-1] for p in parts))
    row = np.concatenate([np.broadcast_to(p, shape + p.shape[-1:]) for p in parts], axis=-1)
    return _rows(row, batch, N)


def rollout_threads(threads, work: int) -> int:
    """The threads a rollout of ``work`` body-steps runs on: ``threads``, or for None every core the
    process may use from :data:`THREADS_MIN_WORK` body-steps on, else one."""
    if threads is not None:
        return as_count(threads, "threads", 1)
    if work < THREADS_MIN_WORK:
        return 1
    return len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1


def _gravity(gravity):
    if gravity is None:
        return np.zeros(3)
    g = as_float_array(gravity, "gravity", (3,), allow_batch=False)
    return np.ascontiguousarray(g)


def _input(u, n, name="u"):
    return np.zeros(6 + n) if u is None else as_float_array(u, name, (6 + n,))


def _batch(*shapes):
    try:
        return np.broadcast_shapes(*shapes)
    except ValueError:
        raise InputError("batch shapes do not broadcast: " + ", ".join(str(s) for s in shapes)) from None


# ---------------------------------------------------------------------------- public
def saturate_wheel_torque(u, h_wheels, hold, *, max_torque, max_momentum) -> np.ndarray:
    """The torques the wheels apply: ``u`` limited by momentum over ``hold`` s, then by torque.

    ``clip(clip(u, (-hmax - h)/hold, (hmax - h)/hold), -umax, umax)``, (..., n) N m; the plant
    applies it to every commanded torque (the compiled loops do the same, per wheel).
    """
    u = np.asarray(u, float)
    h = np.asarray(h_wheels, float)
    v = np.clip(u, (-np.asarray(max_momentum) - h) / hold, (np.asarray(max_momentum) - h) / hold)
    return np.clip(v, -np.asarray(max_torque), np.asarray(max_torque))


def gyrostat_rollout(x0, h, n_steps, *, gyrostat: Gyrostat, u=None, feedback: WheelFeedback | None = None,
                     method: str = DEFAULT_METHOD, gravity=None, substeps: int = 1, save_every=1, monitor_axis=None,
                     threads: int | None = None) -> GyrostatRun:
    """Roll gyrostats forward, the wheel torques held over each control period of ``substeps * h``.

    Parameters
    ----------
    x0 : (..., 13 + n) float, initial states (module docstring), body frame.
    h : float, s, the plant step; the control period is ``substeps * h``.
    n_steps : int, control periods to run.
    gyrostat : Gyrostat, one or a batch broadcasting with x0.
    u : (..., 6 + n) float or None, held input ``[force_world, torque_body, wheel torques]``; with
        ``feedback`` its wheel part is replaced by ``feedback.u_ff``.
    feedback : WheelFeedback or None, the torque law evaluated in the loop at each control period.
    method : ``"splitting"`` (default) or ``"rk4"``.
    gravity : (3,) m/s^2, world frame, or None.
    save_every : int >= 1 or None, control periods between saved states (None: the final one only).
    monitor_axis : (..., 3) float or None, a body axis whose angle to the total angular momentum
        ``I omega + h`` is tracked at every control period (:attr:`GyrostatRun.tilt`).
    threads : int or None, threads over the batch (the result is the same for any count).

    Returns
    -------
    GyrostatRun with states (S, ..., 13 + n), S = n_steps // save_every + 1 (or 1).
    """
    g = _check_gyrostat(gyrostat)
    n = g.n_wheels
    x0 = _state(x0, n, "x0")
    hf = _positive_step(h)
    sub = as_count(substeps, "substeps", 1)
    steps = as_count(n_steps, "n_steps", 0)
    every = 0 if save_every is None else as_count(save_every, "save_every", 1)
    if every and steps % every:
        raise InputError(f"n_steps ({steps}) must be a multiple of save_every ({every})")
    u = _input(u, n)
    fb_shapes = () if feedback is None else _batch(
        np.shape(feedback.gain)[:-2], np.shape(feedback.omega_ref)[:-1], np.shape(feedback.h_ref)[:-1],
        () if feedback.u_ff is None else np.shape(feedback.u_ff)[:-1])
    mon_shape = () if monitor_axis is None else np.shape(monitor_axis)[:-1]
    batch = _batch(x0.shape[:-1], u.shape[:-1], g.batch_shape, fb_shapes, mon_shape)
    N = int(np.prod(batch, dtype=np.int64))
    if feedback is None:
        feedback = WheelFeedback(np.zeros((n, 3 + n)), np.zeros(3), np.zeros(n), u[..., 6:])
    x_P = _states_to_principal(g.body, np.broadcast_to(x0, batch + x0.shape[-1:]))
    x_k = np.ascontiguousarray(np.broadcast_to(x_P, batch + (13 + n,)).reshape(N, 13 + n))
    plant = _plant(g, u, batch, N)
    control = _control(g, feedback, monitor_axis, batch, N)
    S = steps // every + 1 if every else 1
    out = np.empty((S, N, 13 + n))
    tilt = np.empty((S, N))
    _k.gyro_rollout(_method_index(method), x_k, plant, control, _gravity(gravity), hf, sub, steps, every,
                    rollout_threads(threads, N * steps * sub), out, tilt)
    states = _states_from_principal(g.body, out.reshape((S,) + batch + (13 + n,)))
    t = np.arange(S) * (every * sub * hf) if every else np.array([steps * sub * hf])
    return GyrostatRun(t, states, None if monitor_axis is None else tilt.reshape((S,) + batch))


def gyrostat_step(x, u, h, *, gyrostat: Gyrostat, method: str = DEFAULT_METHOD, gravity=None,
                  substeps: int = 1) -> np.ndarray:
    """One control period of ``substeps`` steps of h with the input ``u`` held: ``x_next = f(x, u)``.

    x : (..., 13 + n), u : (..., 6 + n) or None (zero); see the module docstring.  The wheel
    torques are saturated by the plant's limits.  Returns (..., 13 + n).

    Examples
    --------
    >>> g = Gyrostat(RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0]), [[0.0, 1.0, 0.0]])
    >>> x = np.r_[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0.01, 1.0, 0, 0.5]
    >>> gyrostat_step(x, None, 0.01, gyrostat=g).shape
    (14,)
    """
    run = gyrostat_rollout(x, h, 1, gyrostat=gyrostat, u=u, method=method, gravity=gravity, substeps=substeps,
                           save_every=None, threads=1)
    return run.states[0]


def gyrostat_jacobians(x, u, h, *, gyrostat: Gyrostat, method: str = DEFAULT_METHOD, gravity=None,
                       substeps: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Error-state Jacobians of :func:`gyrostat_step`: ``dx_next ~ A dx + B du``.

    Returns
    -------
    A : (..., 12 + n, 12 + n) float; B : (..., 12 + n, 6 + n) float.

    Notes
    -----
    Complex step (Squire & Trapp, SIAM Rev. 40(1), 1998) through the compiled step: each column
    is one step on complex numbers, exact to rounding.  At a saturated wheel the derivative is the
    one-sided one of the clip (zero in its torque).

    Examples
    --------
    >>> g = Gyrostat(RigidBody.from_principal_moments(1.0, [1.0, 2.0, 3.0]), np.eye(3))
    >>> x = np.r_[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1.0, 0, 0, 0, 0]
    >>> [a.shape for a in gyrostat_jacobians(x, None, 0.01, gyrostat=g)]
    [(15, 15), (15, 9)]
    """
    g = _check_gyrostat(gyrostat)
    n = g.n_wheels
    x = _state(x, n)
    u = _input(u, n)
    hf = _positive_step(h)
    sub = as_count(substeps, "substeps", 1)
    batch = _batch(x.shape[:-1], u.shape[:-1], g.batch_shape)
    N = int(np.prod(batch, dtype=np.int64))
    body = g.body
    x_P = np.ascontiguousarray(np.broadcast_to(_states_to_principal(body, x), batch + (13 + n,)).reshape(N, 13 + n))
    plant = np.ascontiguousarray(np.broadcast_to(_plant(g, np.zeros(6), batch, N), (N, 10 + 5 * n)))
    u_P = u.copy()
    if not body.principal_is_body:
        u_P = np.array(np.broadcast_to(u, _batch(u.shape[:-1], body.batch_shape) + (6 + n,)))
        u_P[..., 3:6] = _to_principal(body.R_body_principal, u_P[..., 3:6])
    u_k = np.ascontiguousarray(np.broadcast_to(u_P, batch + (6 + n,)).reshape(N, 6 + n))
    A = np.empty((N, 12 + n, 12 + n))
    B = np.empty((N, 12 + n, 6 + n))
    _k.gyro_jacobians(_method_index(method), x_P, u_k, plant, _gravity(gravity), hf, sub, A, B)
    A = A.reshape(batch + A.shape[1:])
    B = B.reshape(batch + B.shape[1:])
    if body.principal_is_body:
        return A, B
    # dtheta_B = R_BP dtheta_P, domega_B = R_BP domega_P, tau_P = R_BP^T tau_B
    R = np.broadcast_to(body.R_body_principal, batch + (3, 3))
    Tx = np.broadcast_to(np.eye(12 + n), batch + (12 + n, 12 + n)).copy()
    Tx[..., 6:9, 6:9] = R
    Tx[..., 9:12, 9:12] = R
    Tu = np.broadcast_to(np.eye(6 + n), batch + (6 + n, 6 + n)).copy()
    Tu[..., 3:6, 3:6] = R
    TxT = np.swapaxes(Tx, -1, -2)
    return Tx @ A @ TxT, Tx @ B @ np.swapaxes(Tu, -1, -2)
