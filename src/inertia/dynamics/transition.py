"""A 6-DOF rigid-body transition function for control: ``x_next = step(x, u, h, body=...)``.

State, a 13-vector (last axis; any leading batch dimensions)::

    x = [ p_world (0:3) | v_world (3:6) | q_world_body (6:10) | omega_body (10:13) ]

* ``p_world`` [m]: position of the center of mass in the world frame W.
* ``v_world`` [m/s]: velocity of the center of mass, expressed in W.
* ``q_world_body``: unit quaternion, scalar first ``(w, x, y, z)``, maps body coordinates to
  world coordinates (``v_W = R(q_WB) @ v_B``).  The body frame B has its origin at the center
  of mass and the axes in which ``RigidBody.inertia_body`` is expressed.
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
P of the body; a general, non-diagonal ``inertia_body`` is rotated into P internally.  The
translational part is exact for a constant world-frame force (``v += a h``,
``p += v h + a h^2/2``) whatever the rotational method.  See ``docs/transition.md`` for which
schemes are exact for what.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np
from scipy.spatial.transform import Rotation

from .._core.errors import InputError, InvalidInertiaError
from .._core.tolerances import PHYSICAL_RTOL, SYMMETRY_RTOL
from ..massprops.validity import check_inertia
from .._core.rotations import (quat_conjugate, quat_from_rotvec, quat_multiply, quat_rotate,
                         quat_to_rotvec)

__all__ = [
    "STATE_SIZE", "ERROR_STATE_SIZE", "INPUT_SIZE",
    "P_WORLD", "V_WORLD", "Q_WORLD_BODY", "OMEGA_BODY", "FORCE", "TORQUE_BODY",
    "DP_WORLD", "DV_WORLD", "DTHETA_BODY", "DOMEGA_BODY",
    "RigidBody", "RigidState", "pack_state", "unpack_state", "pack_input",
    "perturb_state", "state_error", "step", "jacobians", "resolve_method",
    "QUAT_NORM_TOL", "JACOBIAN_REL_STEP",
]

# ---------------------------------------------------------------------------- layout
STATE_SIZE = 13
ERROR_STATE_SIZE = 12
INPUT_SIZE = 6

#: Slices of the 13-vector state.
P_WORLD = slice(0, 3)
V_WORLD = slice(3, 6)
Q_WORLD_BODY = slice(6, 10)
OMEGA_BODY = slice(10, 13)

#: Slices of the 6-vector input.
FORCE = slice(0, 3)
TORQUE_BODY = slice(3, 6)

#: Slices of the 12-vector error state.
DP_WORLD = slice(0, 3)
DV_WORLD = slice(3, 6)
DTHETA_BODY = slice(6, 9)
DOMEGA_BODY = slice(9, 12)

# ---------------------------------------------------------------------------- tolerances
#: An input quaternion may deviate from unit norm by at most this much; within it, the
#: quaternion is renormalised silently (a solver's or filter's drift), beyond it the state is
#: refused (a zero or garbage quaternion is a bug, not drift).
QUAT_NORM_TOL = 1e-6

#: Relative step of the internal 5-point central differences of :func:`jacobians`.  The
#: stencil's truncation error is O(step^4) ~ 1e-12 and its rounding error ~ eps/step ~ 1e-13,
#: relative to the natural scale of each component (see ``_jacobian_steps``).
JACOBIAN_REL_STEP = 1e-3

_FORCE_FRAMES = ("world", "body")


# ---------------------------------------------------------------------------- the body
def _principal_axes_batch(I_B: np.ndarray) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(moments (..., 3), R_BP (..., 3, 3), is_identity)`` of inertia matrices (..., 3, 3).

    The moments are always ascending, so that a body and any rotated copy of it are integrated
    with the same axis order (the splitting methods depend on it).

    * Diagonal input (every product exactly zero) with ascending diagonal: P = B, no frame
      change, nothing rounded.
    * Diagonal input otherwise: ``R_BP`` is the signed permutation that sorts the diagonal
      (exact in the matrix; its quaternion has entries 0, 1/2, sqrt(1/2) or 1).
    * General input: the eigenvectors of ``numpy.linalg.eigh`` as columns, the third negated
      where needed to make ``det R_BP = +1``.  Any proper principal frame gives the same motion
      (the integrators are equivariant under the sign changes), so the choice only moves rounding.
    """
    off = I_B[..., [0, 0, 1], [1, 2, 2]]
    if not np.any(off):
        diag = np.diagonal(I_B, axis1=-2, axis2=-1)
        if np.all(np.diff(diag, axis=-1) >= 0):
            return diag.copy(), np.broadcast_to(np.eye(3), I_B.shape).copy(), True
        order = np.argsort(diag, axis=-1, kind="stable")
        moments = np.take_along_axis(diag, order, axis=-1)
        R = (np.arange(3)[..., :, None] == order[..., None, :]).astype(float)  # R[i, k] = [i == order[k]]
    else:
        moments, R = np.linalg.eigh(I_B)
    det = np.linalg.det(R)
    R[..., :, 2] *= np.where(det < 0, -1.0, 1.0)[..., None]
    return moments, R, False


def _validate_bodies(mass: np.ndarray, inertia: np.ndarray) -> None:
    """Raise InvalidInertiaError for the first non-physical body of a batch.

    A vectorised screen (symmetry, positive definiteness, triangle inequality with the
    tolerances of :mod:`inertia.massprops.validity`) finds the suspects; the per-body
    :func:`~inertia.massprops.validity.check_inertia` then words the message.
    """
    flat_I = inertia.reshape(-1, 3, 3)
    scale = np.abs(flat_I).max(axis=(-2, -1))
    asym = np.abs(flat_I - np.swapaxes(flat_I, -1, -2)).max(axis=(-2, -1))
    moments = np.linalg.eigvalsh(0.5 * (flat_I + np.swapaxes(flat_I, -1, -2)))
    tol = PHYSICAL_RTOL * np.maximum(np.abs(moments.sum(axis=-1)), np.finfo(float).tiny)
    suspect = ((asym > SYMMETRY_RTOL * np.maximum(scale, np.finfo(float).tiny)) | (moments[:, 0] <= tol)
               | (moments[:, 0] + moments[:, 1] - moments[:, 2] < -tol))
    for k in np.flatnonzero(suspect):
        violations = check_inertia(flat_I[k])
        if violations:
            index = tuple(int(i) for i in np.unravel_index(k, inertia.shape[:-2]))
            where = "" if inertia.ndim == 2 else f" (body {index})"
            raise InvalidInertiaError(f"inertia_body is not physical{where}: "
                                      + "; ".join(v.message for v in violations), violations)


@dataclass(frozen=True, eq=False)
class RigidBody:
    """Mass and central inertia of a rigid body, as the transition function needs them.

    Parameters
    ----------
    mass : float or (...,) float, kg, positive.
    inertia_body : (3, 3) or (..., 3, 3) float, kg m^2, about the center of mass, in the body
        frame B (negated products, ``L_B = I @ omega_body``).  A general symmetric positive
        definite matrix; it need not be diagonal.
    validate : bool, keyword-only
        Check every body with :func:`inertia.massprops.validity.check_inertia` (positive mass,
        symmetric, positive definite, triangle inequality) and raise
        :class:`inertia.errors.InvalidInertiaError` listing the violations.  ``validate=False`` skips the
        check and silently accepts non-physical bodies.

    Attributes (derived)
    --------------------
    moments : (..., 3) float, kg m^2, principal moments, ascending.
    R_body_principal : (..., 3, 3) float, columns are the principal axes in B (proper rotation).
    q_body_principal : (..., 4) float, the same rotation as a quaternion.
    principal_is_body : bool, True when P = B (diagonal inertia with an ascending diagonal):
        no frame change at all, so nothing is rounded by one.

    Leading dimensions describe a batch of bodies; they broadcast against the batch dimensions
    of the state.

    Examples
    --------
    >>> body = RigidBody(1.0, np.diag([0.0042, 0.0142, 0.0167]))
    >>> body.moments.shape, body.principal_is_body
    ((3,), True)
    >>> RigidBody(1.0, np.diag([0.0167, 0.0142, 0.0042])).moments.tolist()   # sorted ascending
    [0.0042, 0.0142, 0.0167]
    >>> RigidBody(np.ones(5), np.broadcast_to(np.eye(3), (5, 3, 3))).moments.shape
    (5, 3)
    """

    mass: np.ndarray
    inertia_body: np.ndarray
    validate: bool = field(default=True, repr=False, kw_only=True)
    moments: np.ndarray = field(init=False, repr=False)
    R_body_principal: np.ndarray = field(init=False, repr=False)
    q_body_principal: np.ndarray = field(init=False, repr=False)
    principal_is_body: bool = field(init=False, repr=False)

    def __post_init__(self):
        mass = _as_array(self.mass, "mass", ())
        inertia = _as_array(self.inertia_body, "inertia_body", (3, 3))
        if np.any(mass <= 0):
            bad = mass[mass <= 0].ravel()[0] if mass.ndim else float(mass)
            raise InputError(f"mass must be positive, got {bad!r} kg")
        try:
            np.broadcast_shapes(mass.shape, inertia.shape[:-2])
        except ValueError:
            raise InputError(f"mass {mass.shape} and inertia_body {inertia.shape} batch shapes do not "
                             f"broadcast") from None
        if self.validate:
            _validate_bodies(mass, inertia)
        moments, R_BP, identity = _principal_axes_batch(inertia)
        if identity:
            q_BP = np.broadcast_to(np.array([1.0, 0.0, 0.0, 0.0]), moments.shape[:-1] + (4,)).copy()
        else:  # vectorised (quaternion.matrix_to_quat loops in Python, slow for 1e5 bodies)
            q_BP = Rotation.from_matrix(R_BP.reshape(-1, 3, 3)).as_quat(scalar_first=True)
            q_BP = q_BP.reshape(R_BP.shape[:-2] + (4,))
        for name, val in (("mass", mass), ("inertia_body", inertia), ("moments", moments),
                          ("R_body_principal", R_BP), ("q_body_principal", q_BP)):
            val = np.array(val, dtype=np.float64, copy=True)
            val.setflags(write=False)
            object.__setattr__(self, name, val)
        object.__setattr__(self, "principal_is_body", bool(identity))

    @classmethod
    def from_mass_properties(cls, props, *, validate: bool = True) -> "RigidBody":
        """The body of a :class:`inertia.massprops.MassProperties` value.

        Uses ``props.mass`` and ``props.inertia_com``: the body frame B of the state is the
        frame of ``props`` translated to the center of mass (same axes).  The frame origin of
        ``props`` sits at ``p_world - R_WB @ props.com`` in the world.
        """
        return cls(props.mass, props.inertia_com, validate=validate)

    @classmethod
    def from_principal_moments(cls, mass, moments, *, validate: bool = True) -> "RigidBody":
        """A body whose frame is principal: ``inertia_body = diag(moments)`` (..., 3) kg m^2."""
        moments = _as_array(moments, "moments", (3,))
        return cls(mass, moments[..., :, None] * np.eye(3), validate=validate)

    @property
    def batch_shape(self) -> tuple:
        """Leading (batch) shape of the body: ``()`` for one body."""
        return np.broadcast_shapes(self.mass.shape, self.inertia_body.shape[:-2])


# ---------------------------------------------------------------------------- state helpers
def _as_array(value, name: str, tail: tuple) -> np.ndarray:
    """Float64 array with trailing shape ``tail``, finite; InputError naming ``name`` otherwise."""
    try:
        a = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric, got {type(value).__name__}: {exc}") from None
    k = len(tail)
    if a.ndim < k or a.shape[a.ndim - k:] != tail:
        want = "(..., " + ", ".join(str(s) for s in tail) + ")" if k else "(...)"
        raise InputError(f"{name} must have shape {want}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        bad = tuple(int(i) for i in np.argwhere(~np.isfinite(a))[0])
        raise InputError(f"{name} holds a non-finite value ({a[bad]}) at index {bad}")
    return a


def _as_unit_quat(q: np.ndarray, name: str) -> np.ndarray:
    """Renormalise quaternions within ``QUAT_NORM_TOL`` of unit norm; refuse the others."""
    norm = np.linalg.norm(q, axis=-1, keepdims=True)
    dev = np.abs(norm - 1.0)
    if np.any(dev > QUAT_NORM_TOL):
        k = tuple(int(i) for i in np.unravel_index(np.argmax(dev), dev.shape)[:-1])
        raise InputError(f"{name} must be a unit quaternion (|q| - 1 within {QUAT_NORM_TOL:g}), got |q| = "
                         f"{float(norm[k][0]):.12g} at batch index {k}: {q[k].tolist()}")
    return q / norm


def _as_step(h) -> float:
    try:
        hf = float(h)
    except (TypeError, ValueError):
        raise InputError(f"h must be a number (the time step in s), got {h!r}") from None
    if not (math.isfinite(hf) and hf > 0):
        raise InputError(f"h must be a positive finite time step in s, got {h!r}")
    return hf


def pack_state(p_world, v_world, q_world_body, omega_body) -> np.ndarray:
    """The 13-vector state (..., 13) from its parts (each broadcast to a common batch shape).

    >>> pack_state([0, 0, 1], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0]).shape
    (13,)
    """
    parts = [_as_array(p_world, "p_world", (3,)), _as_array(v_world, "v_world", (3,)),
             _as_array(q_world_body, "q_world_body", (4,)), _as_array(omega_body, "omega_body", (3,))]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in parts))
    return np.concatenate([np.broadcast_to(a, shape + a.shape[-1:]) for a in parts], axis=-1)


def unpack_state(x) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(p_world, v_world, q_world_body, omega_body)`` views of a state (..., 13)."""
    x = np.asarray(x, dtype=np.float64)
    return x[..., P_WORLD], x[..., V_WORLD], x[..., Q_WORLD_BODY], x[..., OMEGA_BODY]


def pack_input(force=(0.0, 0.0, 0.0), torque_body=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The 6-vector input (..., 6) from ``force`` (..., 3) N and ``torque_body`` (..., 3) N m."""
    F = _as_array(force, "force", (3,))
    tau = _as_array(torque_body, "torque_body", (3,))
    shape = np.broadcast_shapes(F.shape[:-1], tau.shape[:-1])
    return np.concatenate([np.broadcast_to(F, shape + (3,)), np.broadcast_to(tau, shape + (3,))], axis=-1)


@dataclass(frozen=True, eq=False)
class RigidState:
    """The state as named fields (each with leading batch dimensions); see the module docstring.

    >>> s = RigidState.from_vector(np.r_[0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0.5])
    >>> s.omega_body, s.to_vector().shape
    (array([0. , 0. , 0.5]), (13,))
    """

    p_world: np.ndarray
    v_world: np.ndarray
    q_world_body: np.ndarray
    omega_body: np.ndarray

    @classmethod
    def from_vector(cls, x) -> "RigidState":
        x = _as_array(x, "x", (STATE_SIZE,))
        return cls(*(a.copy() for a in unpack_state(x)))

    def to_vector(self) -> np.ndarray:
        return pack_state(self.p_world, self.v_world, self.q_world_body, self.omega_body)


def perturb_state(x_nom, dx) -> np.ndarray:
    """Apply an error state: ``x = x_nom [+] dx`` (the retraction of the error-state manifold).

    Parameters
    ----------
    x_nom : (..., 13) float, nominal state.
    dx : (..., 12) float, error state ``[dp_world, dv_world, dtheta_body, domega_body]``.

    Returns
    -------
    (..., 13) float with ``p = p_nom + dp``, ``v = v_nom + dv``, ``omega = omega_nom + domega``
    and ``q = q_nom (x) exp(dtheta/2)`` (a rotation by ``|dtheta|`` rad about ``dtheta``, in the
    body frame, applied on the right).
    """
    x_nom = np.asarray(x_nom, dtype=np.float64)
    dx = np.asarray(dx, dtype=np.float64)
    shape = np.broadcast_shapes(x_nom.shape[:-1], dx.shape[:-1])
    x_nom = np.broadcast_to(x_nom, shape + (STATE_SIZE,))
    dx = np.broadcast_to(dx, shape + (ERROR_STATE_SIZE,))
    out = np.empty(shape + (STATE_SIZE,))
    out[..., P_WORLD] = x_nom[..., P_WORLD] + dx[..., DP_WORLD]
    out[..., V_WORLD] = x_nom[..., V_WORLD] + dx[..., DV_WORLD]
    out[..., Q_WORLD_BODY] = quat_multiply(x_nom[..., Q_WORLD_BODY], quat_from_rotvec(dx[..., DTHETA_BODY]))
    out[..., OMEGA_BODY] = x_nom[..., OMEGA_BODY] + dx[..., DOMEGA_BODY]
    return out


def state_error(x, x_nom) -> np.ndarray:
    """The error state (..., 12) taking ``x_nom`` to ``x``: the inverse of :func:`perturb_state`.

    ``dtheta_body = Log(q_nom^-1 (x) q)`` as a rotation vector in (-pi, pi] (q and -q are the
    same attitude); the other components are plain differences ``x - x_nom``.
    """
    x = np.asarray(x, dtype=np.float64)
    x_nom = np.asarray(x_nom, dtype=np.float64)
    shape = np.broadcast_shapes(x_nom.shape[:-1], x.shape[:-1])
    out = np.empty(shape + (ERROR_STATE_SIZE,))
    out[..., DP_WORLD] = x[..., P_WORLD] - x_nom[..., P_WORLD]
    out[..., DV_WORLD] = x[..., V_WORLD] - x_nom[..., V_WORLD]
    out[..., DTHETA_BODY] = quat_to_rotvec(quat_multiply(quat_conjugate(x_nom[..., Q_WORLD_BODY]),
                                                         x[..., Q_WORLD_BODY]))
    out[..., DOMEGA_BODY] = x[..., OMEGA_BODY] - x_nom[..., OMEGA_BODY]
    return out


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


def _check_force_frame(force_frame) -> str:
    if force_frame not in _FORCE_FRAMES:
        raise InputError(f"force_frame must be 'world' or 'body', got {force_frame!r}")
    return force_frame


def _check_body(body) -> RigidBody:
    if not isinstance(body, RigidBody):
        raise InputError(f"body must be a RigidBody (mass, inertia_body), got {type(body).__name__}")
    return body


class _BodyView:
    """The arrays of a RigidBody with ``extra_axes`` unit axes inserted after its batch axes.

    Lets a batch of bodies broadcast against states that carry extra trailing batch axes
    (the perturbation axes of :func:`jacobians`).
    """

    def __init__(self, body: RigidBody, extra_axes: int = 0):
        ins = (None,) * extra_axes
        self.mass = body.mass[(..., *ins)]
        self.moments = body.moments[(..., *ins, slice(None))]
        self.R_body_principal = body.R_body_principal[(..., *ins, slice(None), slice(None))]
        self.q_body_principal = body.q_body_principal[(..., *ins, slice(None))]
        self.principal_is_body = body.principal_is_body


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


def _step_principal(x_P, u_P, h, mass, moments, rot_step, gravity, body_force: bool):
    """One step of a state expressed in the principal frame: ``x_P = [p_W, v_W, q_WP, w_P]``.

    ``u_P = [F, tau_P]`` with F in the world frame, or in P when ``body_force``.  ``mass``
    (..., 1) kg, ``moments`` (..., 3).  No checks; shared by :func:`step` and the NumPy path
    of :mod:`inertia.dynamics.rollout` (whose numba kernels transcribe it).
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


def _state_to_principal(body, x, u, body_force: bool):
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


def _state_from_principal(body, x_P):
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
    x_P, u_P = _state_to_principal(body, x, u, body_force)
    x_P1 = _step_principal(x_P, u_P, h, body.mass[..., None], body.moments, rot_step, gravity, body_force)
    return _state_from_principal(body, x_P1)


def _prepare(x, u, h, body, method, gravity, force_frame):
    """Validate and broadcast the arguments of :func:`step` and :func:`jacobians`."""
    body = _check_body(body)
    x = _as_array(x, "x", (STATE_SIZE,)).copy()
    u = np.zeros(INPUT_SIZE) if u is None else _as_array(u, "u", (INPUT_SIZE,))
    h = _as_step(h)
    rot_step = resolve_method(method)
    force_frame = _check_force_frame(force_frame)
    g = None if gravity is None else _as_array(gravity, "gravity", (3,))
    x[..., Q_WORLD_BODY] = _as_unit_quat(x[..., Q_WORLD_BODY], "x[..., 6:10] (q_world_body)")
    try:
        shape = np.broadcast_shapes(x.shape[:-1], u.shape[:-1], body.batch_shape,
                                    () if g is None else g.shape[:-1])
    except ValueError:
        raise InputError(f"batch shapes do not broadcast: x {x.shape}, u {u.shape}, body {body.batch_shape}"
                         + ("" if g is None else f", gravity {g.shape}")) from None
    return x, u, h, body, rot_step, g, force_frame, shape


def step(x, u, h, *, body: RigidBody, method="rk4", gravity=None, force_frame: str = "world") -> np.ndarray:
    """Advance the 6-DOF state by one time step: ``x_next = f_h(x, u)``.

    Parameters
    ----------
    x : (..., 13) float
        State ``[p_world (m), v_world (m/s), q_world_body (unit, w first), omega_body (rad/s)]``;
        a quaternion within ``QUAT_NORM_TOL`` of unit norm is renormalised.
    u : (..., 6) float or None
        Input ``[force (N), torque_body (N m)]``, constant over the step; None means zero.
    h : float, s, positive.
    body : RigidBody
        Mass and central inertia in the body frame (any symmetric positive definite matrix).
    method : str or callable
        Rotational scheme, a name of :data:`inertia.dynamics.integrators.METHODS`
        (``"rk4"`` by default) or a function with the uniform step signature.
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


def jacobians(x, u, h, *, body: RigidBody, method="rk4", gravity=None,
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
    >>> body = RigidBody(1.0, np.diag([0.0167, 0.0142, 0.0042]))
    >>> x0 = pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.1, 2.0, 0.0])
    >>> A, B = jacobians(x0, np.zeros(6), 1e-2, body=body)
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
    x_pert = _step_core(xb, ub, h, _BodyView(body, extra_axes=2), rot_step, g_b, force_frame)
    d = state_error(x_pert, x_next[..., None, None, :])  # (..., nx+nu, n_off, 12)
    J = np.einsum("...kon,o->...nk", d, _STENCIL_WEIGHTS)  # (..., 12, nx+nu), before / step
    steps = np.concatenate([dx_steps, du_steps], axis=-1)
    J = J / steps[..., None, :]
    return J[..., :nx], J[..., nx:]
