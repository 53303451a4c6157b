"""The numbers behind the pictures: a spin about the intermediate axis, solved three ways.

:func:`flip_study` takes principal moments, spins the body about its intermediate axis
with a small wobble, and returns the exact (elliptic-function) solution, two integrators'
trajectories with their energy and |L| errors, and the predicted flip times.  Everything
is in the principal frame: ``omega_body`` components are about the principal axes
(moments ascending), ``q_world_body`` maps principal axes to world axes, and at t = 0 the
body frame and the world frame coincide.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: default spin rate about the intermediate axis [rad/s] and relative wobble about the minor one
SPIN_RATE = 10.0
WOBBLE = 0.01
#: the integrators' step: at most this rotation per step [rad] (h |omega| <= 0.05), and at
#: most T_flip / 400; never more than MAX_STEPS steps (the attitude error then shows it)
ANGLE_PER_STEP = 0.05
MAX_STEPS = 50_000


@dataclass
class FlipStudy:
    moments: np.ndarray            # (3,) ascending, kg m^2
    omega0_body: np.ndarray        # (3,) rad/s, principal axes
    flip_interval: float           # s between flips (predicted, 2K(m)/lambda)
    flip_times: np.ndarray         # predicted flip times in [0, t_end], s
    t: np.ndarray                  # (N,) s
    q_exact: np.ndarray            # (N, 4) exact attitude, world <- body
    omega_exact: np.ndarray        # (N, 3)
    integrators: dict              # name -> {"h", "q", "omega", "energy_error", "momentum_error",
                                   #          "attitude_error" (rad, against the exact solution)}
    L_world: np.ndarray            # (3,) angular momentum in world axes (constant), kg m^2/s
    detected_flips: np.ndarray     # flip times found in the exact omega (s)


def flip_study(moments, *, spin_rate: float = SPIN_RATE, wobble: float = WOBBLE, n_flips: float = 3.0,
               samples: int = 1201, steps_per_flip: int = 400, methods=("splitting", "rk4")) -> FlipStudy:
    """Spin about the intermediate axis with ``wobble`` x ``spin_rate`` about the minor axis."""
    from . import diagnostics, exact, flip, integrators

    I = np.sort(np.asarray(moments, float))
    w0 = np.array([wobble * spin_rate, spin_rate, 0.0])
    T = flip.flip_interval(I, w0)
    t_end = n_flips * T + 0.5 * T
    t = np.linspace(0.0, t_end, samples)
    q0 = np.array([1.0, 0.0, 0.0, 0.0])
    q_ex, w_ex = exact.exact_solution(I, w0, t, q0)
    out = {}
    h = min(T / steps_per_flip, ANGLE_PER_STEP / float(np.linalg.norm(w0)))
    n_steps = int(np.ceil(t_end / h))
    if n_steps > MAX_STEPS:
        n_steps, h = MAX_STEPS, t_end / MAX_STEPS
    every = max(1, n_steps // (samples - 1))
    E0 = float(diagnostics.kinetic_energy(w0, I))
    G0 = float(diagnostics.angular_momentum_norm(w0, I))
    for name in methods:
        tr = integrators.integrate(q0, w0, I, h, n_steps, method=name, record_every=every)
        E = diagnostics.kinetic_energy(tr.omega_body, I)
        G = diagnostics.angular_momentum_norm(tr.omega_body, I)
        q_true, _ = exact.exact_solution(I, w0, tr.t, q0)
        dot = np.clip(np.abs(np.sum(tr.q_world_body * q_true, axis=-1)), 0.0, 1.0)
        out[name] = {"h": h, "t": tr.t, "q": tr.q_world_body, "omega": tr.omega_body,
                     "energy_error": np.abs(E / E0 - 1), "momentum_error": np.abs(G / G0 - 1),
                     "attitude_error": 2.0 * np.arccos(dot)}
    L_world = I * w0  # body = world at t = 0
    detected = flip.detect_flips(t, w_ex, I).times
    return FlipStudy(I, w0, T, flip.flip_times(I, w0, t_end), t, q_ex, w_ex, out, L_world, np.asarray(detected))
