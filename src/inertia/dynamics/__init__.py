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

# public name -> submodule that defines it.  The rest is in the submodules: the equations in
# :mod:`.equations`, the state layout in :mod:`.state`, bodies with rotors in :mod:`.gyrostat`,
# the invariants in :mod:`.diagnostics`, the flip in :mod:`.flip` and :mod:`.flip_study`.
_EXPORTS = {
    # the 6-DOF transition function (for control) and its state
    "RigidBody": "body", "pack_state": "state", "unpack_state": "state", "pack_input": "state",
    "step": "transition", "jacobians": "transition", "rollout": "rollouts",
    # free rotation: integrators, the exact solution, the flip
    "integrate": "integrators", "METHODS": "integrators", "DEFAULT_METHOD": "integrators",
    "exact_solution": "exact", "flip_interval": "flip", "axis_stability": "flip",
    # invariants
    "kinetic_energy": "diagnostics", "angular_momentum_world": "diagnostics",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
