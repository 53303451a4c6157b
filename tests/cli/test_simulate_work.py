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
