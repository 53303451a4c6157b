"""The 6-DOF state, input and error-state layouts, and the error-state algebra.

State, a 13-vector (last axis; any leading batch dimensions)::

    x = [ p_world (0:3) | v_world (3:6) | q_world_body (6:10) | omega_body (10:13) ]

Input, a 6-vector: ``u = [ force (0:3) | torque_body (3:6) ]``.  Error state, a 12-vector::

    dx = [ dp_world (0:3) | dv_world (3:6) | dtheta_body (6:9) | domega_body (9:12) ]

with the attitude perturbed on the right, in the body frame: ``q = q_nom (x) exp(dtheta/2)``.
See :mod:`inertia.dynamics.transition` for the meaning of each part.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.rotations import quat_conjugate, quat_from_rotvec, quat_multiply, quat_to_rotvec
from .._core.validation import as_float_array

__all__ = [
    "STATE_SIZE", "ERROR_STATE_SIZE", "INPUT_SIZE",
    "P_WORLD", "V_WORLD", "Q_WORLD_BODY", "OMEGA_BODY", "FORCE", "TORQUE_BODY",
    "DP_WORLD", "DV_WORLD", "DTHETA_BODY", "DOMEGA_BODY",
    "RigidState", "pack_state", "unpack_state", "pack_input", "perturb_state", "state_error",
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


def pack_state(p_world, v_world, q_world_body, omega_body) -> np.ndarray:
    """The 13-vector state (..., 13) from its parts (each broadcast to a common batch shape).

    >>> pack_state([0, 0, 1], [0, 0, 0], [1, 0, 0, 0], [0, 0, 0]).shape
    (13,)
    """
    parts = [as_float_array(p_world, "p_world", (3,)), as_float_array(v_world, "v_world", (3,)),
             as_float_array(q_world_body, "q_world_body", (4,)), as_float_array(omega_body, "omega_body", (3,))]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in parts))
    return np.concatenate([np.broadcast_to(a, shape + a.shape[-1:]) for a in parts], axis=-1)


def unpack_state(x) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(p_world, v_world, q_world_body, omega_body)`` views of a state (..., 13)."""
    x = np.asarray(x, dtype=np.float64)
    return x[..., P_WORLD], x[..., V_WORLD], x[..., Q_WORLD_BODY], x[..., OMEGA_BODY]


def pack_input(force=(0.0, 0.0, 0.0), torque_body=(0.0, 0.0, 0.0)) -> np.ndarray:
    """The 6-vector input (..., 6) from ``force`` (..., 3) N and ``torque_body`` (..., 3) N m."""
    F = as_float_array(force, "force", (3,))
    tau = as_float_array(torque_body, "torque_body", (3,))
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
        x = as_float_array(x, "x", (STATE_SIZE,))
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
