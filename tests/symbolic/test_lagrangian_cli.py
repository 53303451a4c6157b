"""``inertia lagrangian``: every format is usable as what it claims to be."""

from __future__ import annotations

import json

import numpy as np
import pytest

pytest.importorskip("sympy")

from inertia.cli.main import main  # noqa: E402
from inertia.symbolic import derive  # noqa: E402


def _run(capsys, *argv):
    code = main(["lagrangian", *argv])
    out = capsys.readouterr()
    return code, out.out, out.err


def test_default_is_zyx_readable_latex(capsys):
    code, out, _ = _run(capsys)
    assert code == 0
    assert out.startswith("% Equations of motion in Euler angles") and r"R = R_{Z}(\psi)\,R_{Y}(\theta)\,R_{X}(\phi)" in out
    assert out.count("\\begin{align*}") == out.count("\\end{align*}") == 6


def test_json_describes_the_model(capsys):
    code, out, _ = _run(capsys, "--sequence", "zxz", "--gravity", "--format", "json")
    d = json.loads(out)
    assert code == 0
    assert d["sequence"] == "ZXZ" and d["gravity"] is True and d["translation"] is False
    assert d["singularity"]["det_E"].endswith("sin(theta)")
    assert d["parameters"][-3:] == ["g_x", "g_y", "g_z"]
    assert d["count_ops"] == derive("ZXZ", gravity=True).count_ops


def test_python_output_is_a_working_module(capsys):
    code, out, _ = _run(capsys, "--format", "python", "--inertia", "diagonal")
    ns: dict = {}
    exec(compile(out, "<cli>", "exec"), ns)  # noqa: S102 - our own generated code
    fn = ns["inertia_eom_zyx"]
    q, qd, J, tau = [0.3, -0.2, 0.1], [0.4, -0.1, 0.7], [1.0, 2.0, 3.0], [0.0, 0.5, 0.0]
    expected = derive("ZYX", inertia="diagonal").numeric()(q, qd, inertia=J, torque_body=tau)
    np.testing.assert_allclose(fn(*q, *qd, *J, *tau), expected, rtol=1e-13)


def test_output_file_is_written_whole(tmp_path, capsys):
    target = tmp_path / "eom.c"
    code, out, _ = _run(capsys, "--translation", "--format", "c", "-o", str(target))
    assert code == 0 and out == ""
    text = target.read_text()
    assert "int inertia_eom_zyx_6dof(" in text and text.rstrip().endswith("}")
    assert [p.name for p in tmp_path.iterdir()] == ["eom.c"]  # no temporary file left behind


def test_bad_sequence_is_a_clear_error(capsys):
    code, out, err = _run(capsys, "--sequence", "XXY")
    assert code == 1 and out == ""
    assert "unknown Euler sequence 'XXY'" in err and "Traceback" not in err
