"""The demo's flip study: its integrator step follows the spin as well as the flip period,
and its attitude error is measured against the exact solution."""

from __future__ import annotations

import numpy as np

from inertia.dynamics.exact import exact_solution
from inertia.dynamics.flip_study import ANGLE_PER_STEP, MAX_STEPS, flip_study


def test_the_step_turns_the_body_at_most_the_stated_angle_and_rk4_follows_the_exact_attitude():
    study = flip_study([2.855e-5, 3.890e-5, 6.579e-5])          # the demo's T-handle
    turn = study.integrators["rk4"]["h"] * np.linalg.norm(study.omega0_body)
    assert turn <= ANGLE_PER_STEP * (1 + 1e-12)
    # truth: the exact solution at the recorded times (a second, independent evaluation)
    rk4 = study.integrators["rk4"]
    q_true, _ = exact_solution(study.moments, study.omega0_body, rk4["t"], [1, 0, 0, 0])
    angle = 2 * np.arccos(np.clip(np.abs(np.sum(rk4["q"] * q_true, axis=-1)), 0, 1))
    assert np.allclose(rk4["attitude_error"], angle) and angle.max() < 1e-4


def test_a_slow_flip_is_capped_in_steps_and_its_error_is_shown_not_hidden():
    # a near-sphere: the flip takes ~100 spin periods, so 0.05 rad per step needs > MAX_STEPS
    study = flip_study([1.0, 1.001, 1.002])
    h = study.integrators["rk4"]["h"]
    assert h * np.linalg.norm(study.omega0_body) > ANGLE_PER_STEP
    assert len(study.integrators["rk4"]["t"]) <= MAX_STEPS + 1
    assert study.integrators["splitting"]["attitude_error"].max() > 1e-3
