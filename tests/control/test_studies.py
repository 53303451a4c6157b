"""The showcase: the active hold of both bodies beside the free flip, the Monte Carlo with wrong
models, and the models' errors staying within their bounds."""

from __future__ import annotations

import numpy as np
import pytest

from inertia.control.studies import active_run, basilisk_setup, monte_carlo, perturbed_models, t_handle_setup


@pytest.mark.parametrize("setup", [t_handle_setup, basilisk_setup])
def test_the_lqr_holds_the_spin_within_a_degree_and_the_free_body_flips(setup):
    st = setup()
    run = active_run(st)
    assert run.tilt_held[0] == pytest.approx(st.initial_tilt, rel=1e-12)
    assert run.max_tilt_after_settle < st.max_tilt and run.capture_time < st.settle
    assert run.tilt_free.max() > np.radians(90)                  # without its wheels it turns over
    g = st.gyrostat
    assert np.all(np.abs(run.torque) <= g.max_torque * (1 + 1e-9))
    assert np.all(np.abs(run.held[:, 13:]) <= g.max_momentum)
    assert np.abs(run.torque).max() == pytest.approx(g.max_torque[0], rel=1e-9)   # the limit is met


@pytest.mark.parametrize("setup", [t_handle_setup, basilisk_setup])
def test_a_monte_carlo_with_wrong_models_succeeds_in_99_percent_and_repeats(setup):
    st = setup()
    a = monte_carlo(st, 64, seed=3)
    assert a.success_rate >= 0.99 and a.max_tilt.shape == (64,)
    b = monte_carlo(st, 64, seed=3, threads=1)
    assert np.array_equal(a.max_tilt, b.max_tilt)
    # the settled spin rate is the one the body's momentum allows (here its nominal rate)
    assert np.abs(a.final_spin_rate - st.spin_rate).max() < 1e-3 * st.spin_rate


def test_the_models_errors_stay_within_their_bounds():
    st = t_handle_setup()
    body = st.gyrostat.body
    models, scale, angle = perturbed_models(body, 500, np.random.default_rng(0), moment_error=0.2,
                                            axis_error=np.radians(5))
    assert np.all(np.abs(scale - 1) <= 0.2) and np.all((angle >= 0) & (angle <= np.radians(5)))
    # the model's inertia, seen in the true principal frame, is turned by exactly `angle`
    R_true = body.R_body_principal
    for k in (0, 1, 499):
        w, V = np.linalg.eigh(R_true.T @ models.inertia_com[k] @ R_true)
        assert np.allclose(w, np.sort(body.moments * scale[k]), rtol=1e-12)
        turn = np.linalg.det(V) * V                            # columns: the model's axes in the true frame
        order = np.argsort(body.moments * scale[k])
        cos = np.abs(np.diag(turn[:, np.argsort(order)]))
        assert np.degrees(np.arccos(np.clip(cos.min(), -1, 1))) <= 5 + 1e-6
