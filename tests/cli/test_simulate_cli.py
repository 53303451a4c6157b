"""``inertia simulate`` and ``inertia flip``: output keys and values, formats, SOURCE bodies,
integrator methods, and clear errors (never a traceback) for bad input."""

from __future__ import annotations

import csv
import io
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from inertia.dynamics.exact import ExactSolution
from tests.cli._run import run

REFERENCE_INTERVAL = 20.7546097647


def run_json(capsys, *argv) -> dict:
    rc, out, err = run(capsys, *argv, "--format", "json")
    assert rc == 0, err
    return json.loads(out)


def integrator_methods():
    # our own module: an ImportError here is a failure, never a skip
    from inertia.dynamics.integrators import METHODS

    return list(METHODS)


# ---------------------------------------------------------------------------- simulate
def test_simulate_json_keys_shapes_and_values(capsys):
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0", "--duration", "41.5",
                    "--step", "0.5")
    for key in ("t", "omega_body", "q_world_body", "energy", "angular_momentum_norm"):
        assert key in data
    n = len(data["t"])
    assert n == 84 and data["t"][0] == 0 and data["t"][-1] == 41.5
    assert np.shape(data["omega_body"]) == (n, 3) and np.shape(data["q_world_body"]) == (n, 4)
    assert np.shape(data["energy"]) == (n,) and np.shape(data["angular_momentum_norm"]) == (n,)
    assert data["method"] == "exact" and data["regime"] == "minor_axis"
    assert data["period"] == pytest.approx(2 * REFERENCE_INTERVAL, abs=1e-9)
    assert np.allclose(data["energy"], 0.5 * 2.0001, rtol=1e-15)
    assert np.allclose(data["angular_momentum_norm"], math.sqrt(4.0001), rtol=1e-15)
    q, w = ExactSolution([1, 2, 3], [0.01, 1, 0]).at(np.array(data["t"]))
    assert np.allclose(data["omega_body"], w, atol=1e-15) and np.allclose(data["q_world_body"], q, atol=1e-15)


def test_simulate_times_any_value_including_1e6(capsys):
    T2 = ExactSolution([1, 2, 3], [0.01, 1, 0]).flip_interval
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0",
                    "--times", f"0,{T2!r},1e6,-5")
    w = np.array(data["omega_body"])
    assert np.allclose(w[1], [0.01, -1, 0], atol=1e-12)
    assert np.all(np.isfinite(w)) and len(data["t"]) == 4


def test_simulate_duration_not_a_multiple_of_step_ends_at_duration(capsys):
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.1,1,0", "--duration", "1",
                    "--step", "0.3")
    assert data["t"][:4] == pytest.approx([0, 0.3, 0.6, 0.9]) and data["t"][-1] == 1.0


def test_simulate_negative_components_and_initial_attitude(capsys):
    q0 = np.array([0.5, 0.5, -0.5, 0.5])
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "-0.4,0.3,-0.7",
                    "--q0", ",".join(map(str, q0)), "--times", "0,2.5")
    q, w = ExactSolution([1, 2, 3], [-0.4, 0.3, -0.7], q0).at([0, 2.5])
    assert np.allclose(data["q_world_body"], q, atol=1e-15) and np.allclose(data["omega_body"], w, atol=1e-15)


def test_simulate_csv_and_table(capsys):
    rc, out, err = run(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0", "--duration", "2",
                       "--step", "1", "--format", "csv")
    assert rc == 0, err
    rows = list(csv.reader(io.StringIO(out)))
    assert rows[0] == ["t", "omega_x", "omega_y", "omega_z", "q_w", "q_x", "q_y", "q_z", "energy",
                       "angular_momentum_norm"]
    assert len(rows) == 4 and float(rows[2][0]) == 1.0
    assert float(rows[2][1]) == pytest.approx(0.011713459529, abs=1e-12)
    rc, out, err = run(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0", "--duration", "2",
                       "--step", "1")
    assert rc == 0 and "minor_axis" in out and "energy" in out and "0.0117135" in out


@pytest.mark.parametrize("method", integrator_methods())
def test_simulate_with_every_integrator(capsys, method):
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.3,1,0.2", "--duration", "2",
                    "--step", "0.001", "--method", method)
    q, w = ExactSolution([1, 2, 3], [0.3, 1, 0.2]).at(np.array(data["t"]))
    assert len(data["t"]) == 2001 and data["method"] == method
    err = np.abs(np.array(data["omega_body"]) - w).max()
    assert err < 5e-3, f"{method}: {err}"
    # the integrator path does not record the exact solution's regime
    assert "regime" not in data


def test_simulate_integrator_at_listed_times(capsys):
    data = run_json(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.3,1,0.2", "--times", "0.5,1.25,3",
                    "--step", "0.01", "--method", "rk4")
    q, w = ExactSolution([1, 2, 3], [0.3, 1, 0.2]).at(np.array([0.5, 1.25, 3.0]))
    assert np.abs(np.array(data["omega_body"]) - w).max() < 1e-8
    assert np.abs(np.array(data["q_world_body"]) - q).max() < 1e-8


def test_simulate_source_body_in_its_own_axes(capsys):
    data = run_json(capsys, "simulate", "box:0.1,0.2,0.4", "--mass", "2", "--omega", "0.05,5,0.05",
                    "--times", "0,0.7,3")
    # box inertia about its COM in its own axes: m/12 (b^2 + c^2), ...
    I_box = 2 / 12 * np.array([0.2 ** 2 + 0.4 ** 2, 0.1 ** 2 + 0.4 ** 2, 0.1 ** 2 + 0.2 ** 2])
    assert sorted(data["moments"]) == pytest.approx(sorted(I_box), rel=1e-12)
    # the motion reported in the box axes is the exact solution with diag(I_box) in those axes
    q, w = ExactSolution(I_box, [0.05, 5, 0.05]).at([0, 0.7, 3])
    assert np.allclose(data["omega_body"], w, atol=1e-12)
    R = [np.array(x) for x in data["q_world_body"]]
    from inertia._core.rotations import quat_to_matrix
    assert np.allclose(quat_to_matrix(np.array(R)), quat_to_matrix(q), atol=1e-12)
    assert data["source"] == "box:0.1,0.2,0.4"


# ---------------------------------------------------------------------------- flip
def test_flip_json(capsys):
    data = run_json(capsys, "flip", "--moments", "1,2,3", "--omega", "0.01,1,0")
    for key in ("flip_interval", "period", "unstable_axis", "eigenvalues"):
        assert key in data
    assert data["flip_interval"] == pytest.approx(REFERENCE_INTERVAL, abs=1e-10)
    assert data["period"] == pytest.approx(2 * REFERENCE_INTERVAL, abs=1e-9)
    assert data["flip_interval_approx"] == pytest.approx(20.7541775282, abs=1e-10)
    assert data["unstable_axis"] == 1
    eig = np.array(data["eigenvalues"])
    assert eig.shape == (3, 3, 2)
    spin = math.hypot(0.01, 1.0)
    r = spin * math.sqrt(1 / 3)
    assert eig[1, 1] == pytest.approx([r, 0], abs=1e-14)         # real pair: unstable
    assert eig[0, 1] == pytest.approx([0, r], abs=1e-14)         # imaginary pairs: stable
    assert eig[2, 1] == pytest.approx([0, spin], abs=1e-14)
    assert data["stability"] == ["stable", "unstable", "stable"]


def test_flip_unsorted_moments_and_no_flip_cases(capsys):
    data = run_json(capsys, "flip", "--moments", "2,3,1", "--omega", "1,0,0.01")
    assert data["unstable_axis"] == 0
    assert data["flip_interval"] == pytest.approx(REFERENCE_INTERVAL, abs=1e-10)
    data = run_json(capsys, "flip", "--moments", "1,2,3", "--omega", "0,1,0")     # steady: never flips
    assert data["flip_interval"] is None and data["regime"] == "steady_spin"
    data = run_json(capsys, "flip", "--moments", "1,1,2", "--omega", "0.1,1,0")   # symmetric
    assert data["unstable_axis"] is None and data["flip_interval"] is None
    rc, out, _ = run(capsys, "flip", "--moments", "1,2,3", "--omega", "0,1,0")
    assert rc == 0 and "never" in out


def test_flip_table(capsys):
    rc, out, err = run(capsys, "flip", "--moments", "1,2,3", "--omega", "0.01,1,0")
    assert rc == 0, err
    assert "20.75460976" in out and "unstable" in out


# ---------------------------------------------------------------------------- bad input
@pytest.mark.parametrize("argv, message", [
    (["--moments", "1,2,4"], "--moments = (1, 2, 4) kg m^2 are not the principal moments of a physical body: "
                             "inertia fails the triangle inequality: I1 + I2 = 3 < I3 = 4"),
    (["--moments", "0,2,2"], "inertia is not positive definite"),
    (["--moments", "1,nan,3"], "--moments: item 2 = 'nan' must be finite"),
    (["--moments", "1,x,3"], "--moments: item 2 = 'x' is not a number"),
    (["--moments", "1,2"], "--moments takes 3 comma-separated moments (kg m^2), got 2"),
    (["--moments", "1,2,3", "--omega", "1,nan,0"], "--omega: item 2 = 'nan' must be finite"),
    (["--moments", "1,2,3", "--step", "-0.1"], "--step must be a finite positive number of seconds, got -0.1"),
    (["--moments", "1,2,3", "--step", "0"], "--step must be a finite positive number of seconds, got 0.0"),
    (["--moments", "1,2,3", "--duration", "-1"], "--duration must be a finite non-negative number of seconds"),
    (["--moments", "1,2,3", "--method", "nope"], "--method must be one of exact"),
    (["--moments", "1,2,3", "--q0", "1,1,0,0"], "--q0 must be a unit quaternion"),
    (["--moments", "1,2,3", "--density", "7"], "--density applies to a SOURCE only"),
    (["box:0.1,0.2,0.4", "--moments", "1,2,3"], "give either SOURCE ('box:0.1,0.2,0.4') or --moments"),
    ([], "give the body: --moments I1,I2,I3"),
])
def test_simulate_bad_input_is_a_clear_error(capsys, argv, message):
    base = {"--omega": "0.1,1,0", "--duration": "1", "--step": "0.1"}
    for i, a in enumerate(argv):
        if a in base:
            base[a] = argv[i + 1]
    rest = [a for i, a in enumerate(argv) if a not in base and (i == 0 or argv[i - 1] not in base)]
    full = rest + [x for kv in base.items() for x in kv]
    rc, out, err = run(capsys, "simulate", *full)
    assert rc == 1, (out, err)
    assert err.startswith("inertia simulate: error: ")
    assert message in err
    assert "Traceback" not in err


def test_integrator_with_times_needs_step_and_order(capsys):
    rc, _, err = run(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.1,1,0", "--times", "1,2",
                     "--method", "rk4")
    assert rc == 1 and "give --step" in err
    rc, _, err = run(capsys, "simulate", "--moments", "1,2,3", "--omega", "0.1,1,0", "--times", "2,1",
                     "--step", "0.1", "--method", "rk4")
    assert rc == 1 and "increasing order" in err


@pytest.mark.parametrize("argv, message", [
    (["--moments", "1,2,4", "--omega", "0,1,0"], "triangle inequality"),
    (["--moments", "1,2,3", "--omega", "0,inf,0"], "--omega: item 2 = 'inf' must be finite"),
    (["--moments", "0,0,0", "--omega", "0,1,0"], "not positive definite"),
])
def test_flip_bad_input_is_a_clear_error(capsys, argv, message):
    rc, out, err = run(capsys, "flip", *argv)
    assert rc == 1 and message in err and err.startswith("inertia flip: error: ") and "Traceback" not in err


def test_console_script_with_negative_values():
    """The real command (argparse would take ``-0.4,...`` for an option without the fix)."""
    cmd = [sys.executable, "-c", "import sys; from inertia.cli.main import main; sys.exit(main())"]
    res = subprocess.run(cmd + ["simulate", "--moments", "1,2,3", "--omega", "-0.4,0.3,-0.7", "--times", "-1,0",
                                "--format", "json"], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    assert json.loads(res.stdout)["omega_body"][1] == pytest.approx([-0.4, 0.3, -0.7], abs=1e-15)
