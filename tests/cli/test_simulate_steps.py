"""``inertia simulate``: the integrator step (--step) apart from the sample spacing (--every,
--output-step), and the progress bar (terminal only, after a second)."""

from __future__ import annotations

import io
import json

import numpy as np
import pytest

from inertia._core.progress import Progress
from inertia.cli.main import main
from inertia.dynamics.exact import ExactSolution

BODY = ["--moments", "1,2,3", "--omega", "0.3,1,0.2"]


def run_json(capsys, *argv):
    assert main(["simulate", *BODY, *argv, "--format", "json"]) == 0
    out, err = capsys.readouterr()
    assert err == ""                                  # no bar: stderr is not a terminal here
    return json.loads(out)


def test_every_n_steps_samples_the_same_steps(capsys):
    full = run_json(capsys, "--duration", "2", "--step", "0.01", "--method", "rk4")
    sparse = run_json(capsys, "--duration", "2", "--step", "0.01", "--every", "20", "--method", "rk4")
    assert len(full["t"]) == 201 and sparse["t"] == pytest.approx(np.arange(11) * 0.2, abs=1e-12)
    # the same 200 steps of 0.01 s, recorded every 20th (step sizes equal to rounding)
    assert np.allclose(sparse["omega_body"], np.array(full["omega_body"])[::20], rtol=0, atol=1e-12)
    assert np.allclose(sparse["q_world_body"], np.array(full["q_world_body"])[::20], rtol=0, atol=1e-12)


def test_every_ends_at_the_duration(capsys):
    data = run_json(capsys, "--duration", "1.05", "--step", "0.1", "--every", "5", "--method", "splitting")
    assert data["t"] == pytest.approx([0.0, 0.5, 1.0, 1.05])


def test_output_step_is_independent_of_the_step(capsys):
    data = run_json(capsys, "--duration", "2", "--step", "0.1", "--output-step", "0.25", "--method", "rk4")
    assert data["t"] == pytest.approx(np.arange(9) * 0.25)
    # truth: the exact solution; RK4 with 3 steps of 1/12 s per sample
    q, w = ExactSolution([1, 2, 3], [0.3, 1, 0.2]).at(np.array(data["t"]))
    assert np.abs(np.array(data["omega_body"]) - w).max() < 1e-7
    finer = run_json(capsys, "--duration", "2", "--step", "0.05", "--output-step", "0.25", "--method", "rk4")
    err_fine = np.abs(np.array(finer["omega_body"]) - w).max()
    err_coarse = np.abs(np.array(data["omega_body"]) - w).max()
    # 5 steps of 0.05 s instead of 3 of 1/12 s per sample: order 4 gives (5/3)^4 = 7.7
    assert 6.5 < err_coarse / err_fine < 9


def test_exact_method_needs_no_step_with_output_step(capsys):
    data = run_json(capsys, "--duration", "3", "--output-step", "1.5")
    assert data["t"] == [0.0, 1.5, 3.0]


@pytest.mark.parametrize("argv, message", [
    (["--duration", "1", "--step", "0.1", "--every", "2", "--output-step", "0.5"], "either --every (2) or --output-step"),
    (["--duration", "1", "--step", "0.1", "--every", "0", "--method", "rk4"], "--every must be a positive whole number"),
    (["--times", "0,1", "--step", "0.1", "--every", "2", "--method", "rk4"], "--times lists them"),
    (["--duration", "1", "--output-step", "0.5", "--method", "rk4"], "needs --step (the time step in s)"),
    (["--duration", "1", "--step", "0.1", "--output-step", "-1", "--method", "rk4"],
     "--output-step must be a finite positive number of seconds"),
])
def test_sample_spacing_errors_are_named(capsys, argv, message):
    assert main(["simulate", *BODY, *argv]) == 1
    assert message in capsys.readouterr().err


class _Terminal(io.StringIO):
    def isatty(self):
        return True


def test_progress_bar_waits_its_delay_and_draws_on_a_terminal_only():
    quiet = _Terminal()
    bar = Progress(100, unit="steps", stream=quiet, tty_only=True, delay=60.0)
    bar.update(50)
    bar.update(50)
    assert quiet.getvalue() == ""                         # the run ended before the delay
    shown = _Terminal()
    bar = Progress(100, unit="steps", stream=shown, tty_only=True, delay=0.0)
    bar.update(100)
    assert "100/100 steps" in shown.getvalue()
    piped = io.StringIO()
    bar = Progress(100, unit="steps", stream=piped, tty_only=True)
    bar.update(100)
    assert piped.getvalue() == ""
