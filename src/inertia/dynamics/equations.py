"""Euler's second law for a rigid body, in the body frame and in the world frame, and the
attitude kinematics of a unit quaternion.

Two equivalent statements of the rotational equation of motion about the center of mass:

* **Body frame** B (rotating with the body; the inertia matrix is constant there)::

      I_B dw/dt + w x (I_B w) = tau_B          w = omega_body = w_WB_B

  The gyroscopic term ``w x (I_B w)`` is the price of differentiating in a rotating frame.
* **World frame** W (inertial; the equation is trivial but the inertia matrix turns with
  the body)::

      dL_W/dt = tau_W,    I_W = R_WB I_B R_WB^T,    omega_W = I_W^-1 L_W

Attitude kinematics (``q_world_body`` maps body to world coordinates)::

      dq/dt = 1/2 q (x) (0, omega_body) = 1/2 (0, omega_world) (x) q

Conventions: SI units (rad/s, rad/s^2, kg m^2, N m); quaternions scalar first
``(w, x, y, z)``; every function accepts leading batch dimensions, which broadcast.
``moments`` are the principal moments (..., 3) of a body whose body frame *is* its
principal frame (the fast diagonal path); ``inertia_com`` is any symmetric positive
definite (..., 3, 3) matrix about the center of mass in the body frame.

See ``docs/dynamics.md`` for which formulation is cheaper (measured in
``bench/body_vs_world.py``).
"""

from __future__ import annotations

import numpy as np

from .._core.rotations import cross3, quat_multiply_vector, quat_to_matrix, vector_multiply_quat
from .._core.validation import as_float_array, as_symmetric_matrix3
from ..massprops.validity import as_principal_moments

__all__ = [
    "angular_acceleration_principal",
    "angular_acceleration_body",
    "euler_residual",
    "quat_rate",
    "quat_rate_world",
    "inertia_world",
    "omega_world_from_momentum",
    "omega_world_principal",
    "state_rate_body",
    "state_rate_world",
]

# ---------------------------------------------------------------------------- small kernels
def _accel_principal(omega, moments, torque=None):
    """``dw/dt = (tau - w x (I w)) / I`` for diagonal I, no checks."""
    m = moments * omega
    rate = cross3(m, omega)          # = -(w x I w)
    if torque is not None:
        rate = rate + torque
    return rate / moments


def _matvec(A, v):
    return np.einsum("...ij,...j->...i", A, v)


def _solve3(A, b):
    """Solve ``A x = b`` for (..., 3, 3) matrices A and (..., 3) vectors b.

    Batches use cofactors (Cramer's rule) in elementwise NumPy: a few dozen vector
    operations instead of one LAPACK call per matrix; a single system goes to
    ``np.linalg.solve``.  Inertia matrices are positive definite and well conditioned (cond = I3/I1,
    below ~1e3 even for a needle), where Cramer's rule loses ~cond * eps, like LU.
    """
    if A.ndim == 2 and b.ndim == 1:
        return np.linalg.solve(A, b)
    rows = tuple(tuple(A[..., i, j] for j in range(3)) for i in range(3))
    return np.stack(solve3_components(rows, (b[..., 0], b[..., 1], b[..., 2])), axis=-1)


def solve3_components(a, b):
    """Solve 3x3 systems ``a x = b`` by the adjugate, with ``a`` given as rows of component
    arrays ``((a00, a01, a02), ...)`` and ``b`` as ``(b0, b1, b2)``; returns ``(x0, x1, x2)``."""
    (a00, a01, a02), (a10, a11, a12), (a20, a21, a22) = a
    b0, b1, b2 = b
    c00 = a11 * a22 - a12 * a21
    c01 = a12 * a20 - a10 * a22
    c02 = a10 * a21 - a11 * a20
    c10 = a02 * a21 - a01 * a22
    c11 = a00 * a22 - a02 * a20
    c12 = a01 * a20 - a00 * a21
    c20 = a01 * a12 - a02 * a11
    c21 = a02 * a10 - a00 * a12
    c22 = a00 * a11 - a01 * a10
    inv_det = 1.0 / (a00 * c00 + a01 * c01 + a02 * c02)
    return ((c00 * b0 + c10 * b1 + c20 * b2) * inv_det,
            (c01 * b0 + c11 * b1 + c21 * b2) * inv_det,
            (c02 * b0 + c12 * b1 + c22 * b2) * inv_det)


# ---------------------------------------------------------------------------- body frame
def angular_acceleration_principal(omega_body, moments, torque_body=None) -> np.ndarray:
    """Angular acceleration from Euler's law in the principal body frame (the fast path).

    Solves ``I dw/dt + w x (I w) = tau`` with ``I = diag(moments)``, componentwise::

        I1 dw1/dt = (I2 - I3) w2 w3 + tau1     (and cyclic)

    Parameters
    ----------
    omega_body : (..., 3) float, rad/s
        Angular velocity of the body in the world, expressed in the principal body frame.
    moments : (..., 3) float, kg m^2
        Principal moments of inertia about the center of mass (any order, all > 0).
    torque_body : (..., 3) float, N m, or None
        Torque about the center of mass, expressed in the body frame.  None means zero.

    Returns
    -------
    (...) + (3,) float, rad/s^2, ``dw/dt`` in the body frame; the batch shapes broadcast.

    Examples
    --------
    >>> angular_acceleration_principal([0.0, 1.0, 1.0], [1.0, 2.0, 3.0]).tolist()
    [-1.0, 0.0, 0.0]
    >>> angular_acceleration_principal(np.ones((5, 3)), [1.0, 2.0, 3.0]).shape
    (5, 3)
    """
    w = as_float_array(omega_body, "omega_body", (3,))
    I = as_principal_moments(moments, validate=False)
    tau = None if torque_body is None else as_float_array(torque_body, "torque_body", (3,))
    return _accel_principal(w, I, tau)


def angular_acceleration_body(omega_body, inertia_com, torque_body=None) -> np.ndarray:
    """Angular acceleration from Euler's law in the body frame, any symmetric inertia.

    Solves ``I_B dw/dt = tau_B - w x (I_B w)`` for dw/dt by a 3x3 solve (cofactors).  For a
    body frame that is principal, :func:`angular_acceleration_principal` is the cheaper path
    (no solve; ``I_B^-1`` could also be computed once, since I_B is constant in B).

    Parameters
    ----------
    omega_body : (..., 3) float, rad/s, in the body frame.
    inertia_com : (..., 3, 3) float, kg m^2
        Symmetric positive definite inertia about the center of mass, in the body frame.
    torque_body : (..., 3) float, N m, in the body frame, or None (zero).

    Returns
    -------
    (..., 3) float, rad/s^2, in the body frame.

    Examples
    --------
    >>> angular_acceleration_body([0.0, 1.0, 1.0], np.diag([1.0, 2.0, 3.0])).tolist()
    [-1.0, 0.0, 0.0]
    """
    w = as_float_array(omega_body, "omega_body", (3,))
    J = as_symmetric_matrix3(inertia_com, "inertia_com")
    rhs = cross3(_matvec(J, w), w)
    if torque_body is not None:
        rhs = rhs + as_float_array(torque_body, "torque_body", (3,))
    return _solve3(J, rhs)


def euler_residual(omega_body, omega_dot_body, inertia_com, torque_body=None) -> np.ndarray:
    """Residual of Euler's law in the body frame, ``I w' + w x (I w) - tau`` [N m], (..., 3).

    ``inertia_com`` is a (..., 3, 3) matrix.  Zero (to rounding) for a consistent triple;
    meant for checks and tests.
    """
    w = as_float_array(omega_body, "omega_body", (3,))
    wd = as_float_array(omega_dot_body, "omega_dot_body", (3,))
    J = as_symmetric_matrix3(inertia_com, "inertia_com")
    r = _matvec(J, wd) + cross3(w, _matvec(J, w))
    if torque_body is not None:
        r = r - as_float_array(torque_body, "torque_body", (3,))
    return r


# ---------------------------------------------------------------------------- kinematics
def quat_rate(q_world_body, omega_body) -> np.ndarray:
    """Attitude kinematics with body angular velocity: ``dq/dt = 1/2 q (x) (0, w_B)`` (..., 4).

    Parameters
    ----------
    q_world_body : (..., 4) float, unit quaternion (w, x, y, z), body -> world.
        Not renormalised: the formula is linear in q, which integrators that treat q as
        a 4-vector rely on.
    omega_body : (..., 3) float, rad/s, expressed in the body frame.

    Returns
    -------
    (..., 4) float, 1/s.

    Examples
    --------
    >>> quat_rate([1.0, 0.0, 0.0, 0.0], [0.0, 0.0, 2.0])[1:].tolist()   # spin about z at 2 rad/s
    [0.0, 0.0, 1.0]
    >>> quat_rate(np.tile([1.0, 0.0, 0.0, 0.0], (5, 1)), [0.0, 0.0, 2.0]).shape
    (5, 4)
    """
    q = as_float_array(q_world_body, "q_world_body", (4,))
    w = as_float_array(omega_body, "omega_body", (3,))
    return 0.5 * quat_multiply_vector(q, w)


def quat_rate_world(q_world_body, omega_world) -> np.ndarray:
    """Attitude kinematics with world angular velocity: ``dq/dt = 1/2 (0, w_W) (x) q`` (..., 4).

    Same shapes and units as :func:`quat_rate`; ``omega_world = R_WB omega_body``.
    """
    q = as_float_array(q_world_body, "q_world_body", (4,))
    w = as_float_array(omega_world, "omega_world", (3,))
    return 0.5 * vector_multiply_quat(w, q)


# ---------------------------------------------------------------------------- world frame
def inertia_world(R_world_body, inertia_com) -> np.ndarray:
    """Inertia re-expressed in the world frame: ``I_W = R_WB I_B R_WB^T`` (..., 3, 3) [kg m^2].

    Parameters
    ----------
    R_world_body : (..., 3, 3) float, rotation matrix, body -> world.
    inertia_com : (..., 3, 3) float, kg m^2, about the center of mass, in the body frame.
    """
    R = as_float_array(R_world_body, "R_world_body", (3, 3))
    J = as_symmetric_matrix3(inertia_com, "inertia_com")
    return R @ J @ np.swapaxes(R, -1, -2)


def omega_world_from_momentum(L_world, R_world_body, inertia_com) -> np.ndarray:
    """World angular velocity from world angular momentum, ``w_W = I_W^-1 L_W`` (..., 3) [rad/s].

    The literal world-frame evaluation: forms ``I_W = R I_B R^T`` and solves with it
    (cofactors).
    For principal moments, :func:`omega_world_principal` is cheaper.

    Parameters
    ----------
    L_world : (..., 3) float, kg m^2/s, about the center of mass, in the world frame.
    R_world_body : (..., 3, 3) float, body -> world.
    inertia_com : (..., 3, 3) float, kg m^2, in the body frame.
    """
    L = as_float_array(L_world, "L_world", (3,))
    I_W = inertia_world(R_world_body, inertia_com)
    return _solve3(I_W, L)


def omega_world_principal(L_world, R_world_body, moments) -> np.ndarray:
    """``w_W = R diag(1/I) R^T L_W`` (..., 3) [rad/s] for a principal body frame.

    Equivalent to :func:`omega_world_from_momentum` with ``inertia_com = diag(moments)``,
    without forming or inverting ``I_W``.
    """
    L = as_float_array(L_world, "L_world", (3,))
    R = as_float_array(R_world_body, "R_world_body", (3, 3))
    I = as_principal_moments(moments, validate=False)
    # L_B = R^T L_W ; w_B = L_B / I ; w_W = R w_B
    L_B = np.einsum("...ji,...j->...i", R, L)
    return _matvec(R, L_B / I)


# ---------------------------------------------------------------------------- full state rates
def state_rate_body(q_world_body, omega_body, inertia, torque_body=None):
    """Time derivative of the body-frame state ``(q_world_body, omega_body)``.

    ``dq/dt = 1/2 q (x) (0, w)`` and ``I dw/dt = tau_B - w x (I w)``.

    Parameters
    ----------
    q_world_body : (..., 4) float, quaternion (used as a 4-vector, not renormalised).
    omega_body : (..., 3) float, rad/s, body frame.
    inertia : (..., 3) principal moments **or** (..., 3, 3) body inertia matrix, kg m^2.
        A trailing shape (3, 3) is read as a matrix, so pass a batch of 3 bodies' moments
        as shape (3, 1, 3) or call :func:`angular_acceleration_principal` directly.
    torque_body : (..., 3) float, N m, body frame, or None.

    Returns
    -------
    (dq_dt (..., 4), domega_dt (..., 3))
    """
    a = np.asarray(inertia, dtype=float)
    if a.ndim >= 2 and a.shape[-2:] == (3, 3):
        dw = angular_acceleration_body(omega_body, a, torque_body)
    else:
        dw = angular_acceleration_principal(omega_body, a, torque_body)
    return quat_rate(q_world_body, omega_body), dw


def state_rate_world(q_world_body, L_world, inertia_com, torque_world=None):
    """Time derivative of the world-frame state ``(q_world_body, L_world)``.

    ``dL_W/dt = tau_W``, ``w_W = (R I_B R^T)^-1 L_W``, ``dq/dt = 1/2 (0, w_W) (x) q``.
    ``R`` is computed from the quaternion normalised to unit length (the stage values of
    an integrator that treats q as a 4-vector drift off the unit sphere), while the
    kinematic rate uses q itself, so it stays linear in q.

    Parameters
    ----------
    q_world_body : (..., 4) float.
    L_world : (..., 3) float, kg m^2/s, angular momentum about the center of mass, world frame.
    inertia_com : (..., 3) principal moments or (..., 3, 3) body inertia, kg m^2 (as in
        :func:`state_rate_body`).  The matrix path forms and solves with ``I_W``.
    torque_world : (..., 3) float, N m, world frame, or None.

    Returns
    -------
    (dq_dt (..., 4), dL_dt (..., 3))
    """
    q = as_float_array(q_world_body, "q_world_body", (4,))
    L = as_float_array(L_world, "L_world", (3,))
    R = quat_to_matrix(q / np.linalg.norm(q, axis=-1, keepdims=True))
    a = np.asarray(inertia_com, dtype=float)
    if a.ndim >= 2 and a.shape[-2:] == (3, 3):
        w_W = omega_world_from_momentum(L, R, a)
    else:
        w_W = omega_world_principal(L, R, a)
    dL = np.zeros(np.broadcast_shapes(L.shape, w_W.shape)) if torque_world is None else \
        np.broadcast_to(as_float_array(torque_world, "torque_world", (3,)),
                        np.broadcast_shapes(L.shape, w_W.shape)).copy()
    return 0.5 * vector_multiply_quat(w_W, q), dL
