"""Invariants of rigid-body rotation along a trajectory: kinetic energy, |L|, spatial L, |q|.

For the torque-free body the kinetic energy ``T = 1/2 w . I w``, the norm of the angular
momentum ``|L| = |I w|`` (the same in every frame) and the world-frame angular momentum
``L_W = R_WB I w`` are constant; a unit quaternion keeps ``|q| = 1``.  These functions
measure how well an integrator keeps them.  All accept leading batch dimensions
(for a :class:`~inertia.dynamics.integrators.Trajectory`: time first, then the bodies).

The inertia is given either as principal moments ``moments`` (..., 3) (body frame =
principal frame, the convention of :mod:`inertia.dynamics.integrators`) or as a full body
inertia matrix ``inertia_com=`` (..., 3, 3); exactly one of the two.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.rotations import quat_to_matrix
from .._core.validation import as_float_array, as_symmetric_matrix3
from ..massprops.validity import as_principal_moments

__all__ = [
    "angular_momentum_body",
    "kinetic_energy",
    "angular_momentum_norm",
    "angular_momentum_world",
    "quat_norm",
    "attitude_error",
    "InvariantHistory",
    "trajectory_invariants",
]


def angular_momentum_body(omega_body, moments=None, *, inertia_com=None) -> np.ndarray:
    """Body-frame angular momentum ``m = I w`` (..., 3) [kg m^2/s].

    Parameters
    ----------
    omega_body : (..., 3) float, rad/s, body frame.
    moments : (..., 3) float, kg m^2, principal moments (body frame = principal frame).
    inertia_com : (..., 3, 3) float, kg m^2, keyword-only alternative to ``moments``.
    """
    w = as_float_array(omega_body, "omega_body", (3,), finite=False)
    if (moments is None) == (inertia_com is None):
        raise InputError("give exactly one of moments= (principal, (..., 3)) or inertia_com= ((..., 3, 3)), got "
                         + ("both" if moments is not None else "neither"))
    if moments is not None:
        return as_principal_moments(moments, validate=False) * w
    return np.einsum("...ij,...j->...i", as_symmetric_matrix3(inertia_com, "inertia_com"), w)


def kinetic_energy(omega_body, moments=None, *, inertia_com=None) -> np.ndarray:
    """Rotational kinetic energy ``T = 1/2 w . I w`` (...) [J].

    Examples
    --------
    >>> float(kinetic_energy([1.0, 0.0, 2.0], [1.0, 2.0, 3.0]))
    6.5
    >>> kinetic_energy(np.ones((4, 3)), [1.0, 2.0, 3.0]).shape
    (4,)
    """
    w = as_float_array(omega_body, "omega_body", (3,), finite=False)
    m = angular_momentum_body(w, moments, inertia_com=inertia_com)
    return 0.5 * np.sum(m * w, axis=-1)


def angular_momentum_norm(omega_body, moments=None, *, inertia_com=None) -> np.ndarray:
    """``|L| = |I w|`` (...) [kg m^2/s], frame independent (the Casimir of Euler's equations)."""
    return np.linalg.norm(angular_momentum_body(omega_body, moments, inertia_com=inertia_com), axis=-1)


def angular_momentum_world(q_world_body, omega_body, moments=None, *, inertia_com=None) -> np.ndarray:
    """Spatial (world-frame) angular momentum ``L_W = R_WB (I w)`` (..., 3) [kg m^2/s].

    ``q_world_body`` (..., 4) is normalised before use, so this measures the drift of the
    momentum and the attitude, not of ``|q|`` (see :func:`quat_norm` for that).
    """
    q = as_float_array(q_world_body, "q_world_body", (4,), finite=False)
    m = angular_momentum_body(omega_body, moments, inertia_com=inertia_com)
    R = quat_to_matrix(q / np.linalg.norm(q, axis=-1, keepdims=True))
    return np.einsum("...ij,...j->...i", R, m)


def quat_norm(q_world_body) -> np.ndarray:
    """Euclidean norm ``|q|`` (...) of quaternions (..., 4)."""
    return np.linalg.norm(as_float_array(q_world_body, "q_world_body", (4,), finite=False), axis=-1)


def attitude_error(q_a, q_b) -> np.ndarray:
    """Angle [rad] in [0, pi] of the rotation between two attitudes (...): ``|log(q_a^-1 q_b)|``.

    Insensitive to the sign of either quaternion; accurate for small angles
    (``2 atan2(|v|, |w|)`` of the relative quaternion, no arccos).

    Examples
    --------
    >>> round(float(attitude_error([1, 0, 0, 0], [np.cos(0.05), np.sin(0.05), 0, 0])), 12)
    0.1
    """
    a = as_float_array(q_a, "q_a", (4,), finite=False)
    b = as_float_array(q_b, "q_b", (4,), finite=False)
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    # relative quaternion a^-1 (x) b: scalar part a.b, vector part aw bv - bw av - av x bv
    w = np.sum(a * b, axis=-1)
    v = a[..., :1] * b[..., 1:] - b[..., :1] * a[..., 1:] - np.cross(a[..., 1:], b[..., 1:])
    return 2.0 * np.arctan2(np.linalg.norm(v, axis=-1), np.abs(w))


@dataclass(frozen=True)
class InvariantHistory:
    """Invariants along a trajectory (time first, then the batch).

    Attributes
    ----------
    energy : (N, ...) float, J
    momentum_norm : (N, ...) float, kg m^2/s
    L_world : (N, ..., 3) float, kg m^2/s
    quat_norm : (N, ...) float
    """

    energy: np.ndarray
    momentum_norm: np.ndarray
    L_world: np.ndarray
    quat_norm: np.ndarray

    def max_relative_errors(self) -> dict[str, np.ndarray]:
        """Largest deviation from the initial value over the run, per body (...).

        ``energy`` and ``momentum_norm``: ``max_t |x(t) - x(0)| / |x(0)|``;
        ``L_world``: ``max_t |L(t) - L(0)| / |L(0)|`` (vector difference);
        ``quat_norm``: ``max_t ||q(t)| - 1|``.  Where the initial value is zero (a body at
        rest) the deviation is absolute.
        """
        def rel(num, den):
            return num / np.where(den > 0, den, 1.0)

        e0, g0, L0 = self.energy[0], self.momentum_norm[0], self.L_world[0]
        return {
            "energy": rel(np.max(np.abs(self.energy - e0), axis=0), np.abs(e0)),
            "momentum_norm": rel(np.max(np.abs(self.momentum_norm - g0), axis=0), g0),
            "L_world": rel(np.max(np.linalg.norm(self.L_world - L0, axis=-1), axis=0), np.linalg.norm(L0, axis=-1)),
            "quat_norm": np.max(np.abs(self.quat_norm - 1.0), axis=0),
        }


def trajectory_invariants(trajectory, moments=None, *, inertia_com=None) -> InvariantHistory:
    """Energy, |L|, spatial L and |q| at every record of a trajectory.

    Parameters
    ----------
    trajectory : Trajectory (or any object with ``q_world_body`` (N, ..., 4) and
        ``omega_body`` (N, ..., 3))
    moments : (..., 3) float, kg m^2, principal moments (broadcast against the batch).
    inertia_com : (..., 3, 3) float, keyword-only alternative to ``moments``.

    Examples
    --------
    >>> from .integrators import integrate
    >>> traj = integrate([1, 0, 0, 0], [1.3, 0.0, 0.2], [2/3, 1, 2], 0.1, 50, validate=False)
    >>> inv = trajectory_invariants(traj, [2/3, 1, 2])
    >>> inv.energy.shape, inv.L_world.shape
    ((51,), (51, 3))
    >>> bool(inv.max_relative_errors()["momentum_norm"] < 1e-14)
    True
    """
    q = trajectory.q_world_body
    w = trajectory.omega_body
    return InvariantHistory(
        energy=kinetic_energy(w, moments, inertia_com=inertia_com),
        momentum_norm=angular_momentum_norm(w, moments, inertia_com=inertia_com),
        L_world=angular_momentum_world(q, w, moments, inertia_com=inertia_com),
        quat_norm=quat_norm(q),
    )
