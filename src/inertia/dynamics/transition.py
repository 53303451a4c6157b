"""A 6-DOF rigid-body transition function for control: ``x_next = step(x, u, h, body=...)``.

State, a 13-vector (last axis; any leading batch dimensions)::

    x = [ p_world (0:3) | v_world (3:6) | q_world_body (6:10) | omega_body (10:13) ]

* ``p_world`` [m]: position of the center of mass in the world frame W.
* ``v_world`` [m/s]: velocity of the center of mass, expressed in W.
* ``q_world_body``: unit quaternion, scalar first ``(w, x, y, z)``, maps body coordinates to
  world coordinates (``v_W = R(q_WB) @ v_B``).  The body frame B has its origin at the center
  of mass and the axes in which ``RigidBody.inertia_com`` is expressed.
* ``omega_body`` [rad/s]: angular velocity of B in W, expressed in B (``w_WB_B``).

Input, a 6-vector: ``u = [ force (0:3) | torque_body (3:6) ]``.

* ``force`` [N], applied at the center of mass; expressed in W (``force_frame="world"``, the
  default) or in B (``force_frame="body"``).
* ``torque_body`` [N m], about the center of mass, expressed in B.
* Both are held constant over the step (zero-order hold).

Error state, a 12-vector (for Jacobians, EKFs and MPC)::

    dx = [ dp_world (0:3) | dv_world (3:6) | dtheta_body (6:9) | domega_body (9:12) ]

with the attitude perturbed on the right, in the body frame:
``q = q_nom (x) exp(dtheta/2)``, i.e. ``R = R_nom @ Exp(dtheta)`` (:func:`perturb_state`,
:func:`state_error`).  The other components are plain differences.

The rotational part is delegated to the free-body integrators of
:mod:`inertia.dynamics.integrators` (registry ``METHODS``), which work in the principal frame
P of the body; a general, non-diagonal ``inertia_com`` is rotated into P internally.  The
translational part is exact for a constant world-frame force (``v += a h``,
``p += v h + a h^2/2``) whatever the rotational method.  See ``docs/transition.md`` for which
schemes are exact for what.
"""

from __future__ import annotations

import numpy as np

from .._core.errors import InputError
from .._core.rotations import quat_conjugate, quat_multiply, quat_rotate
from .._core.validation import as_float_array, as_time_step, as_unit_quat
from .body import BodyView, RigidBody, check_body
from .integrators import DEFAULT_METHOD
from .state import (
    ERROR_STATE_SIZE,
    FORCE,
    INPUT_SIZE,
    OMEGA_BODY,
    P_WORLD,
    Q_WORLD_BODY,
    STATE_SIZE,
    TORQUE_BODY,
    V_WORLD,
    perturb_state,
    state_error,
)

__all__ = ["step", "jacobians", "resolve_method", "JACOBIAN_REL_STEP", "step_principal",
           "state_to_principal", "state_from_principal", "check_force_frame", "DEFAULT_METHOD"]

# ---------------------------------------------------------------------------- tolerances
#: Relative step of the internal 5-point central differences of :func:`jacobians`.  The
#: stencil's truncation error is O(step^4) ~ 1e-12 and its rounding error ~ eps/step ~ 1e-13,
#: relative to the natural scale of each component (see ``_jacobian_steps``).
JACOBIAN_REL_STEP = 1e-3

_FORCE_FRAMES = ("world", "body")


# ---------------------------------------------------------------------------- the step
def resolve_method(method):
    """The rotational step function ``(q_WP, omega_P, moments, h, torque_P) -> (q, omega)`` for ``method``.

    ``method`` is a name of :data:`inertia.dynamics.integrators.METHODS` or a callable with
    that uniform signature.
    """
    if callable(method):
        return method
    from .integrators import METHODS
    try:
        return METHODS[method]
    except (KeyError, TypeError):
        raise InputError(f"method must be one of {sorted(METHODS)} or a step function, got {method!r}") from None


def check_force_frame(force_frame) -> str:
    if force_frame not in _FORCE_FRAMES:
        raise InputError(f"force_frame must be 'world' or 'body', got {force_frame!r}")
    return force_frame


def _to_principal(body: RigidBody, q_WB, w_B, vecs_B=()):
    """Re-express the attitude, body angular velocity and body vectors in the principal frame P."""
    if body.principal_is_body:
        return (q_WB, w_B) + tuple(vecs_B)
    R_BP = body.R_body_principal
    # v_P = R_BP^T v_B ; q_WP = q_WB (x) q_BP
    to_P = lambda v: np.einsum("...ji,...j->...i", R_BP, v)  # noqa: E731
    return (quat_multiply(q_WB, body.q_body_principal), to_P(w_B)) + tuple(to_P(v) for v in vecs_B)


def _from_principal(body: RigidBody, q_WP, w_P):
    """Inverse of :func:`_to_principal` for the attitude and the angular velocity."""
    if body.principal_is_body:
        return q_WP, w_P
    # v_B = R_BP v_P ; q_WB = q_WP (x) q_BP^-1
    return (quat_multiply(q_WP, quat_conjugate(body.q_body_principal)),
            np.einsum("...ij,...j->...i", body.R_body_principal, w_P))


def _translate(p, v, a0, a_half=None, a1=None, h=0.0):
    """Advance position and velocity over h.

    Constant acceleration ``a0`` (``a_half`` None): exact, ``v + a h`` and ``p + v h + a h^2/2``.
    Otherwise Simpson's rule on the samples ``a(0), a(h/2), a(h)``:
    ``v + h (a0 + 4 a_half + a1)/6`` and ``p + h v + h^2 (a0 + 2 a_half)/6`` (the second is
    Simpson applied to ``int_0^h (h - s) a(s) ds``); both exact for constant ``a``.
    """
    if a_half is None:
        return p + v * h + a0 * (0.5 * h * h), v + a0 * h
    return (p + v * h + (a0 + 2.0 * a_half) * (h * h / 6.0),
            v + (a0 + 4.0 * a_half + a1) * (h / 6.0))


def step_principal(x_P, u_P, h, mass, moments, rot_step, gravity, body_force: bool):
    """One step of a state expressed in the principal frame: ``x_P = [p_W, v_W, q_WP, w_P]``.

    ``u_P = [F, tau_P]`` with F in the world frame, or in P when ``body_force``.  ``mass``
    (..., 1) kg, ``moments`` (..., 3).  No checks; shared by :func:`step` and the rollouts of a
    caller's step function (:mod:`inertia.dynamics.rollouts`; the compiled rollout transcribes it).
    """
    p, v, q, w = x_P[..., P_WORLD], x_P[..., V_WORLD], x_P[..., Q_WORLD_BODY], x_P[..., OMEGA_BODY]
    F, tau = u_P[..., FORCE], u_P[..., TORQUE_BODY]
    q1, w1 = rot_step(q, w, moments, h, tau)
    if not body_force:
        a0 = F / mass if gravity is None else F / mass + gravity
        p1, v1 = _translate(p, v, a0, h=h)
    else:
        # body-frame force: the world force turns with the body; sample it at 0, h/2, h.
        # The h/2 attitude costs one extra rotational half step.
        qh, _ = rot_step(q, w, moments, 0.5 * h, tau)
        g = 0.0 if gravity is None else gravity
        a0 = quat_rotate(q, F) / mass + g
        ah = quat_rotate(qh, F) / mass + g
        a1 = quat_rotate(q1, F) / mass + g
        p1, v1 = _translate(p, v, a0, ah, a1, h=h)
    shape = np.broadcast_shapes(p1.shape, v1.shape, q1.shape[:-1] + (3,), w1.shape)[:-1]
    out = np.empty(shape + (STATE_SIZE,))
    out[..., P_WORLD] = p1
    out[..., V_WORLD] = v1
    out[..., Q_WORLD_BODY] = q1
    out[..., OMEGA_BODY] = w1
    return out


def state_to_principal(body, x, u, body_force: bool):
    """``(x_P, u_P)``: attitude, angular velocity and torque (and a body-frame force) in P.

    A body-frame force is re-expressed in P (``R_WB F_B = R_WP F_P``); a world force is kept.
    """
    if body.principal_is_body:
        return x, u
    vecs = (u[..., TORQUE_BODY], u[..., FORCE]) if body_force else (u[..., TORQUE_BODY],)
    q_WP, w_P, tau_P, *F_P = _to_principal(body, x[..., Q_WORLD_BODY], x[..., OMEGA_BODY], vecs)
    F = F_P[0] if body_force else u[..., FORCE]
    shape = np.broadcast_shapes(x.shape[:-1], q_WP.shape[:-1], w_P.shape[:-1])
    x_P = np.concatenate([np.broadcast_to(a, shape + a.shape[-1:]) for a in (x[..., :6], q_WP, w_P)], axis=-1)
    shape = np.broadcast_shapes(F.shape[:-1], tau_P.shape[:-1])
    u_P = np.concatenate([np.broadcast_to(a, shape + (3,)) for a in (F, tau_P)], axis=-1)
    return x_P, u_P


def state_from_principal(body, x_P):
    """Inverse of :func:`_state_to_principal` for states (..., 13)."""
    if body.principal_is_body:
        return x_P
    q_WB, w_B = _from_principal(body, x_P[..., Q_WORLD_BODY], x_P[..., OMEGA_BODY])
    out = np.empty(np.broadcast_shapes(x_P.shape[:-1], q_WB.shape[:-1]) + (STATE_SIZE,))
    out[..., :6] = x_P[..., :6]
    out[..., Q_WORLD_BODY] = q_WB
    out[..., OMEGA_BODY] = w_B
    return out


def _step_core(x, u, h, body, rot_step, gravity, force_frame):
    """One step of validated arrays (broadcast batch); see :func:`step`."""
    body_force = force_frame == "body"
    x_P, u_P = state_to_principal(body, x, u, body_force)
    x_P1 = step_principal(x_P, u_P, h, body.mass[..., None], body.moments, rot_step, gravity, body_force)
    return state_from_principal(body, x_P1)


def _prepare(x, u, h, body, method, gravity, force_frame):
    """Validate and broadcast the arguments of :func:`step` and :func:`jacobians`."""
    body = check_body(body)
    x = as_float_array(x, "x", (STATE_SIZE,)).copy()
    u = np.zeros(INPUT_SIZE) if u is None else as_float_array(u, "u", (INPUT_SIZE,))
    h = as_time_step(h)
    rot_step = resolve_method(method)
    force_frame = check_force_frame(force_frame)
    g = None if gravity is None else as_float_array(gravity, "gravity", (3,))
    x[..., Q_WORLD_BODY] = as_unit_quat(x[..., Q_WORLD_BODY], "x[..., 6:10] (q_world_body)")
    try:
        shape = np.broadcast_shapes(x.shape[:-1], u.shape[:-1], body.batch_shape,
                                    () if g is None else g.shape[:-1])
    except ValueError:
        raise InputError(f"batch shapes do not broadcast: x {x.shape}, u {u.shape}, body {body.batch_shape}"
                         + ("" if g is None else f", gravity {g.shape}")) from None
    return x, u, h, body, rot_step, g, force_frame, shape


def step(x, u, h, *, body: RigidBody, method=DEFAULT_METHOD, gravity=None, force_frame: str = "world") -> np.ndarray:
    """Advance the 6-DOF state by one time step: ``x_next = f_h(x, u)``.

    Parameters
    ----------
    x : (..., 13) float
        State ``[p_world (m), v_world (m/s), q_world_body (unit, w first), omega_body (rad/s)]``;
        a quaternion within ``QUAT_NORM_TOL`` (:mod:`inertia._core.tolerances`) of unit norm is
        renormalised.
    u : (..., 6) float or None
        Input ``[force (N), torque_body (N m)]``, constant over the step; None means zero.
    h : float, s, finite and non-zero (negative steps backwards, as every integrator does).
    body : RigidBody
        Mass and central inertia in the body frame (any symmetric positive definite matrix).
    method : str or callable
        Rotational scheme, a name of :data:`inertia.dynamics.integrators.METHODS`
        (:data:`~inertia.dynamics.integrators.DEFAULT_METHOD`, the splitting method, by
        default) or a function with the uniform step signature.
    gravity : (3,) float, m/s^2, world frame, or None (no gravity).
    force_frame : {"world", "body"}
        Frame of ``u[..., 0:3]``.  ``"body"`` samples the rotating world force at 0, h/2 and h
        (Simpson), which costs one extra rotational half step.

    Returns
    -------
    (...,13) float, the next state; the batch shape is the broadcast of those of x, u and body.

    Notes
    -----
    Translation, world-frame force: exact for the held force (``v1 = v + a h``,
    ``p1 = p + v h + a h^2/2``, ``a = F/m + g``).  Rotation: the chosen integrator in the
    principal frame P, ``q_WP = q_WB (x) q_BP``, ``omega_P = R_BP^T omega_B``,
    ``tau_P = R_BP^T tau_B``, then back.

    Examples
    --------
    >>> import numpy as np
    >>> from inertia.dynamics import RigidBody, jacobians, pack_state, step
    >>> body = RigidBody(1.0, np.diag([0.0167, 0.0142, 0.0042]))
    >>> x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0, 0, 1.0])
    >>> step(x0, np.zeros(6), 1e-3, body=body).shape
    (13,)
    >>> step(np.broadcast_to(x0, (5, 13)), np.zeros(6), 1e-3, body=body).shape
    (5, 13)
    """
    x, u, h, body, rot_step, g, force_frame, _ = _prepare(x, u, h, body, method, gravity, force_frame)
    return _step_core(x, u, h, body, rot_step, g, force_frame)


# ---------------------------------------------------------------------------- Jacobians
# 5-point central-difference stencil: f'(0) ~ sum_k c_k f(o_k e) / e, error O(e^4)
_STENCIL_OFFSETS = np.array([-2.0, -1.0, 1.0, 2.0])
_STENCIL_WEIGHTS = np.array([1.0, -8.0, 8.0, -1.0]) / 12.0


def _jacobian_steps(x, u, h, body):
    """Per-component difference steps (..., 12) for dx and (..., 6) for u.

    Each step is ``JACOBIAN_REL_STEP`` times the natural scale of its component: max(1, |p|) m,
    max(1, |v|) m/s, 1 rad, max(|omega|, 1/h) rad/s (the map depends on h omega), max(|F|, m (1 +
    |v|/h)) N, and max(|tau|, I_min max(|omega|, 1/h)/1) N m with I_min the smallest principal
    moment (so that the torque step changes omega by at most ~ the omega step).
    """
    c = JACOBIAN_REL_STEP
    shape = x.shape[:-1]
    p, v, w = x[..., P_WORLD], x[..., V_WORLD], x[..., OMEGA_BODY]
    F, tau = u[..., FORCE], u[..., TORQUE_BODY]
    nrm = lambda a: np.linalg.norm(a, axis=-1, keepdims=True)  # noqa: E731
    w_scale = np.maximum(nrm(w), 1.0 / h)
    m = body.mass[..., None]
    I_min = np.min(body.moments, axis=-1, keepdims=True)
    dx_steps = np.concatenate(np.broadcast_arrays(
        c * np.maximum(1.0, nrm(p)) * np.ones(3), c * np.maximum(1.0, nrm(v)) * np.ones(3),
        np.full(shape + (3,), c), c * w_scale * np.ones(3)), axis=-1)
    du_steps = np.concatenate(np.broadcast_arrays(
        c * np.maximum(nrm(F), m * (1.0 + nrm(v) / h)) * np.ones(3),
        c * np.maximum(nrm(tau), I_min * w_scale) * np.ones(3)), axis=-1)
    return dx_steps, du_steps


def jacobians(x, u, h, *, body: RigidBody, method=DEFAULT_METHOD, gravity=None,
              force_frame: str = "world") -> tuple[np.ndarray, np.ndarray]:
    """Jacobians of :func:`step` in the 12-dimensional error state: ``(A, B)``.

    ``dx_next ~ A @ dx + B @ du`` where ``dx`` is the error state of the module docstring
    (``q = q_nom (x) exp(dtheta/2)``, body-frame right perturbation, for the input and for the
    output state alike) and ``du`` a plain perturbation of ``u``.

    Parameters
    ----------
    x, u, h, body, method, gravity, force_frame
        As for :func:`step`.

    Returns
    -------
    A : (..., 12, 12) float, ``d dx_next / d dx``.
    B : (..., 12, 6) float, ``d dx_next / d u``.

    Notes
    -----
    Computed by 5-point central differences (error O(step^4)) on the error-state manifold, all
    72 perturbed steps in one batched call; steps per component from ``JACOBIAN_REL_STEP`` and
    the natural scales (``_jacobian_steps``).  Accuracy is ~1e-10 relative for the smooth
    schemes; it works for any registered method, including implicit ones (their fixed-point
    tolerance then bounds the accuracy).

    Examples
    --------
    >>> import numpy as np
    >>> from inertia.dynamics import RigidBody, jacobians
    >>> x0 = np.r_[0, 0, 0, 0, 0, 0, 1, 0, 0, 0, 0.1, 2.0, 0.0]   # p, v, q_world_body, omega_body
    >>> A, B = jacobians(x0, np.zeros(6), 1e-2, body=RigidBody(1.0, np.diag([0.0167, 0.0142, 0.0042])))
    >>> A.shape, B.shape
    ((12, 12), (12, 6))
    """
    x, u, h, body, rot_step, g, force_frame, shape = _prepare(x, u, h, body, method, gravity, force_frame)
    x = np.broadcast_to(x, shape + (STATE_SIZE,))
    u = np.broadcast_to(u, shape + (INPUT_SIZE,))
    dx_steps, du_steps = _jacobian_steps(x, u, h, body)
    n_off = _STENCIL_OFFSETS.size
    nx, nu = ERROR_STATE_SIZE, INPUT_SIZE
    # perturbed states: (..., nx, n_off, 13); inputs unchanged
    eye_x = np.eye(nx)
    dX = dx_steps[..., :, None, None] * _STENCIL_OFFSETS[:, None] * eye_x[:, None, :]
    xs = perturb_state(x[..., None, None, :], dX)
    # perturbed inputs: (..., nu, n_off, 6); state unchanged
    dU = du_steps[..., :, None, None] * _STENCIL_OFFSETS[:, None] * np.eye(nu)[:, None, :]
    us = u[..., None, None, :] + dU
    # one batched step over all (nx + nu) * n_off perturbations
    xb = np.concatenate([xs, np.broadcast_to(x[..., None, None, :], shape + (nu, n_off, STATE_SIZE))], axis=-3)
    ub = np.concatenate([np.broadcast_to(u[..., None, None, :], shape + (nx, n_off, INPUT_SIZE)), us], axis=-3)
    g_b = None if g is None else g[..., None, None, :]
    x_next = _step_core(x, u, h, body, rot_step, g, force_frame)
    x_pert = _step_core(xb, ub, h, BodyView(body, extra_axes=2), rot_step, g_b, force_frame)
    d = state_error(x_pert, x_next[..., None, None, :])  # (..., nx+nu, n_off, 12)
    J = np.einsum("...kon,o->...nk", d, _STENCIL_WEIGHTS)  # (..., 12, nx+nu), before / step
    steps = np.concatenate([dx_steps, du_steps], axis=-1)
    J = J / steps[..., None, :]
    return J[..., :nx], J[..., nx:]
