"""Lagrangian mechanics of a rigid body in Euler angles, derived symbolically (sympy, lazily).

Two routes to the same equations:

* (a) particles: the body as six (or four) constrained point masses,
  ``L = sum 1/2 m_k |v_k|^2 - V``, Euler-Lagrange term by term (:class:`ParticleRoute`);
* (b) the rigid-body form ``E^T [J (E q'' + E' q') + omega x J omega] = E^T tau``, solved for
  ``q''`` with the closed-form ``E^-1`` (:func:`derive`, :class:`EquationsOfMotion`).

Any of the twelve intrinsic sequences, a general symmetric inertia, optional translation
(6-DOF), uniform gravity with an offset center of mass, a body torque and a world force.
See ``docs/symbolic.md``.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_EXPORTS = {
    "derive": "equations", "EquationsOfMotion": "equations", "GimbalLockError": "equations",
    "GimbalLockWarning": "equations", "GIMBAL_LOCK_TOL": "equations", "GIMBAL_WARN_TOL": "equations",
    "EulerAngleSystem": "system", "ParticleRoute": "particles",
    "SEQUENCES": "rotations", "rotation_matrix": "rotations", "kinematic_matrix": "rotations",
    "kinematic_matrix_inverse": "rotations", "det_kinematic": "rotations",
    "lagrangian": "rigid", "mass_matrix": "rigid", "euler_residual": "rigid", "accelerations": "rigid",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ())
