"""``inertia simulate`` estimates its work before taking a step and refuses unbounded runs."""

from __future__ import annotations

import time

import pytest

from inertia.cli.main import main

BODY = ["--moments", "1,2,3", "--omega", "0.01,1,0"]


def test_a_run_of_1e13_steps_is_refused_at_once(capsys):
    t0 = time.perf_counter()
    code = main(["simulate", *BODY, "--times", "0,1e12", "--method", "rk4", "--step", "0.1"])
    elapsed = time.perf_counter() - t0
    err = capsys.readouterr().err
    assert code == 1
    assert "1e+13 steps" in err and "--max-steps 1,000,000" in err and "--method exact" in err
    assert elapsed < 5.0        # refused before stepping: 1e13 steps would take years


@pytest.mark.parametrize("max_steps, ok", [(99, False), (100, True)])
def test_the_estimate_is_the_number_of_steps_taken(max_steps, ok, capsys):
    # 0 -> 10 s with steps of at most 0.1 s: exactly 100 steps
    code = main(["simulate", *BODY, "--times", "0,10", "--method", "rk4", "--step", "0.1",
                 "--max-steps", str(max_steps), "--format", "csv"])
    out, err = capsys.readouterr()
    assert (code == 0) is ok
    if not ok:
        assert "about 100 steps" in err


def test_the_exact_solution_needs_no_step_budget(capsys):
    assert main(["simulate", *BODY, "--times", "0,1e12", "--format", "csv"]) == 0
    assert capsys.readouterr().out.strip().splitlines()[-1].startswith("1000000000000")


def test_max_steps_must_be_positive(capsys):
    assert main(["simulate", *BODY, "--times", "0,1", "--method", "rk4", "--step", "0.1", "--max-steps", "0"]) == 1
    assert "--max-steps must be a positive whole number" in capsys.readouterr().err


@pytest.mark.parametrize("moments, omega, what", [
    ("1,2,3", "0,1e154,0", "angular momentum I w of this spin is about 1e154"),       # energy was inf
    ("1e-200,2e-200,3e-200", "0.1,1,0", "angular momentum I w of this spin is about 1e-200"),  # "rest"
    ("1e100,2e100,3e100", "0,1e100,0", "angular momentum I w of this spin is about 1e200"),
])
def test_spins_beyond_double_precision_are_refused_by_name(moments, omega, what, capsys):
    for argv in (["simulate", "--moments", moments, "--omega", omega, "--times", "0,1"],
                 ["flip", "--moments", moments, "--omega", omega]):   # flip: overflow warnings, NaN before
        assert main(argv) == 1
        err = capsys.readouterr().err
        assert what in err and "express the body in other units" in err and "Warning" not in err


def test_a_small_body_inside_the_range_is_simulated_like_a_scaled_one(capsys):
    # the same spin with moments scaled by 1e-20: omega and q identical, energy scaled (exact solution)
    rows = []
    for scale in ("1", "1e-20"):
        m = ",".join(f"{k}{'' if scale == '1' else 'e-20'}" for k in (1, 2, 3))
        assert main(["simulate", "--moments", m, "--omega", "0.1,1,0", "--times", "0,7.5", "--format", "csv"]) == 0
        rows.append([float(x) for x in capsys.readouterr().out.strip().splitlines()[-1].split(",")])
    import numpy as np
    np.testing.assert_allclose(rows[1][:8], rows[0][:8], rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(rows[1][8:], np.array(rows[0][8:]) * 1e-20, rtol=1e-12)


def test_a_diverging_integrator_is_an_integration_error_not_a_null(capsys):
    code = main(["simulate", "--moments", "1,2,3", "--omega", "0,10,100", "--times", "0,1000",
                 "--method", "euler_explicit", "--step", "1", "--format", "json"])
    err = capsys.readouterr().err
    assert code == 1 and "diverged" in err
