"""Rotational dynamics: Euler's equations, integrators, the exact solution, the flip, 6-DOF transitions.

Conventions: ``omega_body`` is the angular velocity in body axes [rad/s]; quaternions
``q_world_body`` are scalar-first and map body to world coordinates; ``moments`` are the
principal moments [kg m^2] when the body frame is the principal frame.

Names are imported lazily (PEP 562): ``import inertia.dynamics`` loads no NumPy until a
name is used.
"""

from __future__ import annotations

import importlib

_MODULES = ("equations", "integrators", "exact", "elliptic", "flip", "diagnostics", "transition", "rollout",
            "quaternion")

# public name -> submodule that defines it
_EXPORTS = {
    # equations
    "angular_acceleration_body": "equations", "angular_acceleration_principal": "equations",
    "state_rate_body": "equations", "state_rate_world": "equations", "inertia_world": "equations",
    # integrators
    "integrate": "integrators", "Trajectory": "integrators", "METHODS": "integrators",
    "IntegrationError": "integrators",
    # exact solution and flip
    "exact_solution": "exact", "ExactSolution": "exact",
    "flip_interval": "flip", "flip_times": "flip", "detect_flips": "flip", "axis_stability": "flip",
    "unstable_axis": "flip", "intermediate_axis": "flip",
    # diagnostics
    "kinetic_energy": "diagnostics", "angular_momentum_norm": "diagnostics",
    "angular_momentum_world": "diagnostics", "trajectory_invariants": "diagnostics",
    # 6-DOF transition function
    "RigidBody": "transition", "step": "transition", "jacobians": "transition",
    "pack_state": "transition", "unpack_state": "transition", "pack_input": "transition",
    "perturb_state": "transition", "state_error": "transition", "rollout": "rollout",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    if name in _MODULES:
        return importlib.import_module(f"{__name__}.{name}")
    mod = _EXPORTS.get(name)
    if mod is None:
        raise AttributeError(f"module 'inertia.dynamics' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{mod}"), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(__all__) | set(_MODULES))
