"""Control of rotating bodies over :mod:`inertia.dynamics`: LQR on the gyrostat's error-state
Jacobians, reaction-wheel limits, the dual-spin stability threshold, and the studies of the
intermediate-axis spin (passive wheel sweep, active hold, Monte Carlo with a wrong model).

Names are imported lazily (PEP 562): ``import inertia.control`` loads no NumPy until a name is used.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_MODULES = ("dual_spin", "lqr", "studies")

_EXPORTS = {
    "dual_spin_threshold": "dual_spin", "dual_spin_exponent": "dual_spin", "DualSpinThreshold": "dual_spin",
    "dlqr": "lqr", "design_spin_hold": "lqr", "SpinHold": "lqr",
    "SpinSetup": "studies", "t_handle_setup": "studies", "basilisk_setup": "studies", "initial_state": "studies",
    "passive_sweep": "studies", "PassiveSweep": "studies", "active_run": "studies", "ActiveRun": "studies",
    "monte_carlo": "studies", "MonteCarlo": "studies", "perturbed_models": "studies",
    "Showcase": "studies", "showcase": "studies", "saturate_wheel_torque": "inertia.dynamics.gyrostat",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
