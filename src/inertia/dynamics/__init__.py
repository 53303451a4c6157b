"""Rotational dynamics: Euler's equations, integrators, the exact solution, the flip, 6-DOF transitions,
bodies with rotors (gyrostats).

Conventions: ``omega_body`` is the angular velocity in body axes [rad/s]; quaternions
``q_world_body`` are scalar-first and map body to world coordinates; ``moments`` are the
principal moments [kg m^2] when the body frame is the principal frame.

Names are imported lazily (PEP 562): ``import inertia.dynamics`` loads no NumPy until a
name is used.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_MODULES = ("equations", "integrators", "exact", "elliptic", "flip", "flip_study", "diagnostics", "state", "body",
            "transition", "rollouts", "gyrostat")

# public name -> submodule that defines it
_EXPORTS = {
    # equations
    "angular_acceleration_body": "equations", "angular_acceleration_principal": "equations",
    "state_rate_body": "equations", "state_rate_world": "equations", "inertia_world": "equations",
    # integrators
    "integrate": "integrators", "integrate_segments": "integrators", "Trajectory": "integrators",
    "METHODS": "integrators",
    "IntegrationError": "integrators",
    # exact solution and flip
    "exact_solution": "exact", "ExactSolution": "exact",
    "flip_interval": "flip", "flip_times": "flip", "detect_flips": "flip", "axis_stability": "flip",
    "unstable_axis": "flip", "intermediate_axis": "flip",
    # diagnostics
    "kinetic_energy": "diagnostics", "angular_momentum_norm": "diagnostics",
    "angular_momentum_world": "diagnostics", "trajectory_invariants": "diagnostics",
    # 6-DOF transition function
    "RigidBody": "body", "step": "transition", "jacobians": "transition",
    "pack_state": "state", "unpack_state": "state", "pack_input": "state", "RigidState": "state",
    "perturb_state": "state", "state_error": "state", "rollout": "rollouts", "DEFAULT_METHOD": "integrators",
    # bodies with rotors
    "Gyrostat": "gyrostat", "WheelFeedback": "gyrostat", "GyrostatRun": "gyrostat", "gyrostat_step": "gyrostat",
    "gyrostat_jacobians": "gyrostat", "gyrostat_rollout": "gyrostat", "saturate_wheel_torque": "gyrostat",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
