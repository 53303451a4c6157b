"""Route (b): the Lagrange equations of a rigid body in Euler angles, in rigid-body form.

With ``omega_body = E(q) q'`` the rotational Lagrangian is ``1/2 q'^T E^T J E q'``, and its
Euler-Lagrange operator equals ``E^T`` times Euler's equation (the Boltzmann-Hamel /
Euler-Poincare identity)::

    E^T [ J (E q'' + E' q') + omega x J omega ] = E^T tau          (M = E^T J E)

Away from gimbal lock ``E`` is invertible, so the accelerations follow without solving a
linear system or simplifying anything::

    omega' = J^-1 (tau - omega x J omega)
    q''    = E^-1 (omega' - E' q')        (E^-1 = adj E / det E, det E in closed form)

With gravity and a fixed pivot, ``J`` is the inertia about the pivot (parallel axis) and
``tau`` gains ``c x R^T (m g + F)``.  With translation the center of mass obeys
``m r_com'' = F + m g`` and the body origin follows from ``r_com = p + R c``.
"""

from __future__ import annotations

from ._sympy import require_sympy
from .rotations import kinematic_matrix_inverse
from .system import EulerAngleSystem


def _inverse_sym3(A):
    """Inverse of a symmetric 3x3 sympy matrix by its adjugate (no simplification)."""
    return A.adjugate() / A.det(method="berkowitz")


def pivot_inertia(system: EulerAngleSystem):
    """The inertia the rotation sees: about the COM with translation, about the pivot without."""
    sp = require_sympy()
    if system.has_com and not system.translation:
        c = system.com
        return system.J + system.mass * ((c.T * c)[0, 0] * sp.eye(3) - c * c.T)
    return system.J


def lagrangian(system: EulerAngleSystem):
    """``L = T - V`` in the coordinates and rates (rigid-body form)."""
    sp = require_sympy()
    w = system.omega_body
    if system.translation:
        v_com = sp.Matrix(system.rates[:3]) + system.R * w.cross(system.com)
        T = (w.T * system.J * w)[0, 0] / 2 + system.mass * (v_com.T * v_com)[0, 0] / 2
    else:
        T = (w.T * pivot_inertia(system) * w)[0, 0] / 2
    V = -system.mass * (system.g.T * system.com_world())[0, 0] if system.gravity else sp.S.Zero
    return T - V


def mass_matrix(system: EulerAngleSystem):
    """``M = d^2 T / dq'^2`` (``E^T J E`` for rotation only)."""
    sp = require_sympy()
    return sp.hessian(lagrangian(system), system.rates)


def body_torque(system: EulerAngleSystem):
    """Total torque in body axes about the point the rotation is written about."""
    tau = system.torque_body
    if system.has_com and not system.translation:
        load = system.force_world + system.mass * system.g   # g is zero without gravity
        tau = tau + system.com.cross(system.R.T * load)
    return tau


def euler_residual(system: EulerAngleSystem):
    """``E^T [J (E q'' + E' q') + omega x J omega - tau]`` for the angles (zero on solutions).

    With translation the first three entries are ``m r_com'' - F - m g`` instead.
    """
    sp = require_sympy()
    nt = len(system.position)
    J = pivot_inertia(system)
    w = system.omega_body
    Edot = system.rate_of(system.E)
    w_dot = system.E * sp.Matrix(system.accelerations[nt:]) + Edot * sp.Matrix(system.rates[nt:])
    rot = system.E.T * (J * w_dot + w.cross(J * w) - body_torque(system))
    if not system.translation:
        return rot
    r_dd = system.time_derivative(system.time_derivative(system.com_world()))  # uses q'' symbols
    trans = system.mass * r_dd - system.force_world - system.mass * system.g
    return sp.Matrix.vstack(trans, rot)


def accelerations(system: EulerAngleSystem):
    """``q''`` as a column of sympy expressions in the coordinates, rates, parameters and inputs."""
    sp = require_sympy()
    nt = len(system.position)
    J = pivot_inertia(system)
    w = system.omega_body
    w_dot = _inverse_sym3(J) * (body_torque(system) - w.cross(J * w))
    Edot = system.rate_of(system.E)
    angle_acc = kinematic_matrix_inverse(system.sequence, system.angles) * (
        w_dot - Edot * sp.Matrix(system.rates[nt:]))
    if not system.translation:
        return angle_acc
    a_com = system.force_world / system.mass + system.g
    c = system.com
    p_dd = a_com - system.R * (w_dot.cross(c) + w.cross(w.cross(c)))
    return sp.Matrix.vstack(p_dd, angle_acc)
