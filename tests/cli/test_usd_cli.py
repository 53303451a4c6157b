"""The OpenUSD side of ``inertia props``, ``check`` and ``fix``, and ``inertia diff`` across formats."""

from __future__ import annotations

import json
import subprocess
import sys

import numpy as np
import pytest

from inertia.cli.main import main
from tests.robots import usd_make as um
from tests.robots.test_usd_fix import URDF, USDA

# the same two-link robot as MJCF (the URDF's inertial frames written as MuJoCo's <inertial>)
MJCF = """<mujoco model="r">
  <compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <inertial pos="0 0 0.05" mass="2" diaginertia="0.02 0.03 0.04"/>
      <body name="arm-1" pos="0 0 0.2">
        <joint name="j" axis="0 0 1"/>
        <inertial pos="0.1 0 0" euler="0.3 0 0" mass="0.5" fullinertia="0.001 0.002 0.0025 0.0001 0 0"/>
      </body>
    </body>
  </worldbody>
</mujoco>
"""


def _run(capsys, *argv):
    code = main([str(a) for a in argv])
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def robot(tmp_path):
    (tmp_path / "robot.urdf").write_text(URDF)
    (tmp_path / "robot.xml").write_text(MJCF)
    (tmp_path / "stage.usda").write_text(USDA)
    return tmp_path


def test_help_and_robot_commands_do_not_import_usd_core():
    code = ("import sys\nfrom inertia.cli.main import main\n"
            "for argv in (['--help'], ['props', '--help'], ['diff', '--help']):\n"
            "    try:\n        main(argv)\n    except SystemExit:\n        pass\n"
            "print('pxr' in sys.modules)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip().splitlines()[-1] == "False"


def test_a_stage_without_usd_core_names_the_usd_extra(monkeypatch, robot, capsys):
    for key in [k for k in sys.modules if k == "pxr" or k.startswith("pxr.")]:
        monkeypatch.setitem(sys.modules, key, None)
    monkeypatch.setitem(sys.modules, "pxr", None)
    code, _, err = _run(capsys, "props", robot / "stage.usda")
    assert code == 1
    assert "reading OpenUSD stages needs pxr, which is not installed: pip install 'inertia[usd]'" in err


def test_props_json_has_the_robot_shape_and_the_stages_numbers(robot, capsys):
    from inertia.robots.usd.mass import stage_mass_properties

    code, out, _ = _run(capsys, "props", robot / "stage.usda", "--format", "json")
    assert code == 0
    data = json.loads(out)
    truth = stage_mass_properties(robot / "stage.usda")
    assert data["format"] == "usd" and data["frame"] == "world"
    assert data["mass"] == pytest.approx(truth.total.mass, rel=1e-15)
    assert [r["name"] for r in data["links"]] == ["base", "arm_1"]
    assert data["links"][1]["source"] == "default_density"            # the sphere at 1000 kg/m^3
    assert data["links"][1]["mass"] == pytest.approx(1000 * 4 / 3 * np.pi * 0.05 ** 3, rel=1e-14)
    code, out, _ = _run(capsys, "props", robot / "stage.usda", "--subtree", "arm_1", "--format", "json")
    assert json.loads(out)["mass"] == pytest.approx(data["links"][1]["mass"], rel=1e-15)


def test_props_table_and_options_that_do_not_apply(robot, capsys):
    code, out, _ = _run(capsys, "props", robot / "stage.usda")
    assert code == 0 and "OpenUSD (UsdPhysics), 2 rigid bodies" in out and "default_density: its colliders" in out
    code, _, err = _run(capsys, "props", robot / "stage.usda", "--joint", "j=1")
    assert code == 1 and "--joint does not apply to an OpenUSD stage" in err
    code, _, err = _run(capsys, "props", robot / "robot.urdf", "--as-physx")
    assert code == 1 and "--as-physx applies to OpenUSD stages only" in err


def test_check_a_stage_exits_1_on_errors_and_lists_usd_findings(tmp_path, capsys):
    path = tmp_path / "c.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b", mass=1.0, com=(0, 0, 0), diag=(0.1, 0.1, 0.1), axes=(0.5, 0, 0, 0))
    stage.GetRootLayer().Save()
    code, out, _ = _run(capsys, "check", path)
    assert code == 1
    assert out.splitlines()[0] == f"{path} (OpenUSD, 1 rigid body): 1 error, 0 warnings"
    assert "error non_unit_principal_axes: physics:principalAxes [0.5, 0.0, 0.0, 0.0] has norm 0.5, not 1" in out
    code, out, _ = _run(capsys, "check", path, "--format", "json")
    data = json.loads(out)
    found = data["links"][0]["findings"]
    assert [(f["code"], f["severity"]) for f in found] == [("non_unit_principal_axes", "error")]
    assert not [f for f in data["findings"] if f["severity"] == "warning"]


def test_fix_from_then_diff_reports_nothing(robot, capsys):
    code, out, _ = _run(capsys, "diff", robot / "robot.urdf", robot / "stage.usda")
    assert code == 1
    lines = out.splitlines()
    assert lines[0].endswith("2 bodies differ beyond 1e-06, 0 bodies agree (total mass 2.5 vs 2.0236 kg)")
    assert lines[1].startswith("  arm-1 -> arm_1: inertia 0.787")    # worst first, renamed as a USD identifier
    assert lines[2] == "    A: 0.5 kg, COM [0.1, 0, 0.2] m, moments [0.000990098, 0.0020099, 0.0025] kg m^2"
    code, _, err = _run(capsys, "fix", robot / "stage.usda", "--from", robot / "robot.urdf", "-o", robot / "f.usda")
    assert code == 0 and "2 bodies changed" in err
    code, out, _ = _run(capsys, "diff", robot / "robot.urdf", robot / "f.usda")
    assert code == 0 and "0 bodies differ" in out


def test_diff_across_urdf_and_mjcf_agrees_and_json_lists_every_body(robot, capsys):
    code, out, _ = _run(capsys, "diff", robot / "robot.urdf", robot / "robot.xml", "--format", "json")
    data = json.loads(out)
    assert code == 0 and data["n_differ"] == 0 and data["n_same"] == 2
    code, out, _ = _run(capsys, "diff", robot / "robot.xml", robot / "stage.usda", "--map", "arm-1=arm_1",
                        "--tol", "1e-3", "--format", "json")
    data = json.loads(out)
    assert code == 1 and [d["name_b"] for d in data["differ"]] == ["arm_1", "base"]
    assert data["differ"][1]["errors"]["mass"] == pytest.approx(0.25, rel=1e-7)


def test_diff_refuses_a_bad_map_and_a_negative_tolerance(robot, capsys):
    assert _run(capsys, "diff", robot / "robot.urdf", robot / "stage.usda", "--map", "nope")[0] == 1
    code, _, err = _run(capsys, "diff", robot / "robot.urdf", robot / "stage.usda", "--tol", "-1")
    assert code == 1 and "--tol must be a non-negative number" in err
