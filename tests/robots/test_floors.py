"""The checks that need the kinematic tree, against MuJoCo's compiler as the oracle: what it
refuses (a moving body below mjMINVAL = 1e-15, a massless link that moves alone) is an error,
what it accepts (massless frames on fixed joints, or welded to a body with mass) is an idiom
listed in one line, and a radius of gyration far below the link's size is a warning."""

from __future__ import annotations

import json

import numpy as np
import pytest

from inertia.cli.main import main
from tests.robots._report import sev

INERTIA = '<inertia ixx="{0}" iyy="{0}" izz="{0}" ixy="0" ixz="0" iyz="0"/>'


def _link(name, mass=None, moment=None, geometry='<box size="0.3 0.3 0.3"/>'):
    inertial = "" if mass is None else f'<inertial><mass value="{mass}"/>{INERTIA.format(moment)}</inertial>'
    return f'<link name="{name}">{inertial}<collision><geometry>{geometry}</geometry></collision></link>\n'


def _joint(name, parent, child, kind="revolute", xyz="0 0 0.2"):
    limit = '<limit lower="-1" upper="1" effort="1" velocity="1"/>' if kind == "revolute" else ""
    return (f'<joint name="{name}" type="{kind}"><parent link="{parent}"/><child link="{child}"/>'
            f'<origin xyz="{xyz}"/><axis xyz="0 0 1"/>{limit}</joint>\n')


def _urdf(tmp_path, *parts, name="r.urdf"):
    path = tmp_path / name
    path.write_text('<robot name="r">\n' + "".join(parts) + "</robot>\n")
    return path


def _check(capsys, path):
    code = main(["check", str(path), "--format", "json"])
    report = json.loads(capsys.readouterr().out)
    found = {(lk["name"], f["code"]) for lk in report["links"] for f in sev(lk, "error") + sev(lk, "warning")}
    return code, report, found


def _mujoco_loads(path) -> bool:
    mujoco = pytest.importorskip("mujoco")
    try:
        mujoco.MjModel.from_xml_path(str(path))
        return True
    except ValueError:
        return False


def test_massless_frames_are_an_idiom_mujoco_accepts(tmp_path, capsys):
    """base_footprint (no inertial) and tool0 (mass 0, tensor 0) on fixed joints, and a moving
    'wrist' with no mass of its own whose welded child carries the mass: all accepted."""
    path = _urdf(tmp_path, _link("base_footprint"), _link("base", 2.0, 0.03), _link("wrist"), _link("hand", 0.5, 1e-3),
                 '<link name="tool0"><inertial><mass value="0"/>' + INERTIA.format(0) + "</inertial></link>\n",
                 _joint("fp", "base_footprint", "base", "fixed"), _joint("j", "base", "wrist"),
                 _joint("h", "wrist", "hand", "fixed"), _joint("t", "hand", "tool0", "fixed"))
    code, report, found = _check(capsys, path)
    assert code == 0 and not any(c in ("massless_moving_link", "below_simulator_floor", "non_positive_mass")
                                 for _, c in found)
    assert sorted(report["massless_frames"]) == ["base_footprint", "tool0", "wrist"]
    assert _mujoco_loads(path)
    main(["check", str(path)])
    table = capsys.readouterr().out.splitlines()
    assert "3 massless frames" in table[1] and "tool0" in table[1]


def test_a_massless_link_that_moves_alone_is_an_error_mujoco_agrees(tmp_path, capsys):
    path = _urdf(tmp_path, _link("base", 2.0, 0.03), '<link name="finger"/>\n', _joint("j", "base", "finger"))
    code, report, found = _check(capsys, path)
    assert code == 1 and ("finger", "massless_moving_link") in found
    assert "finger" not in report["massless_frames"]
    assert not _mujoco_loads(path)
    # with a collision shape MuJoCo's URDF import infers a mass (Pinocchio and Gazebo do not): still
    # an error, and the message says so
    path = _urdf(tmp_path, _link("base", 2.0, 0.03), _link("finger"), _joint("j", "base", "finger"), name="g.urdf")
    code, report, found = _check(capsys, path)
    message = [f["message"] for lk in report["links"] for f in sev(lk, "error")][0]
    assert code == 1 and "MuJoCo's URDF import infers" in message and _mujoco_loads(path)


@pytest.mark.parametrize("tensor", ["0 0 0 0 0 0", "2.4e-35 0 0 0 0 0", "1e-41 1e-41 1e-41 0 0 0",
                                    "1e-16 1e-16 1e-16 0 0 0"])
def test_noise_tensors_of_moving_bodies_are_below_the_floor(tmp_path, capsys, tensor):
    """A 1.34 kg moving body whose tensor is zero or rounding noise: the relative checks pass
    some of these (2.4e-35 is 'positive definite'), MuJoCo refuses every one."""
    path = tmp_path / "m.xml"
    path.write_text('<mujoco><worldbody><body name="link"><joint type="hinge"/>'
                    f'<inertial pos="0 0 0" mass="1.34" fullinertia="{tensor}"/></body></worldbody></mujoco>')
    code, _, found = _check(capsys, path)
    assert code == 1 and found & {("link", "below_simulator_floor"), ("link", "not_positive_definite")}
    assert not _mujoco_loads(path)


def test_a_body_just_above_the_floor_passes_as_mujoco_does(tmp_path, capsys):
    path = tmp_path / "m.xml"
    path.write_text('<mujoco><worldbody><body name="link"><joint type="hinge"/><geom type="sphere" size="1e-5" '
                    'mass="1e-6"/></body></worldbody></mujoco>')   # moments 4e-17: below the floor
    code, _, found = _check(capsys, path)
    assert code == 1 and ("link", "below_simulator_floor") in found and not _mujoco_loads(path)
    path.write_text('<mujoco><worldbody><body name="link"><joint type="hinge"/><geom type="sphere" size="1e-4" '
                    'mass="1e-6"/></body></worldbody></mujoco>')   # moments 4e-15: above
    code, _, found = _check(capsys, path)
    assert code == 0 and _mujoco_loads(path)


def test_radius_of_gyration_far_below_the_link_is_implausible(tmp_path, capsys):
    """A 2 kg link 0.3 m across with the placeholder 1e-6 kg m^2 (radius of gyration 0.7 mm): a
    warning; its real tensor (a solid box: 0.03 kg m^2) is not."""
    base = _link("base", 5.0, 0.1)
    placeholder = _urdf(tmp_path, base, _link("arm", 2.0, 1e-6), _joint("j", "base", "arm"), name="p.urdf")
    code, _, found = _check(capsys, placeholder)
    assert code == 0 and ("arm", "implausible_inertia") in found
    box = 2.0 * (0.3**2 + 0.3**2) / 12
    real = _urdf(tmp_path, base, _link("arm", 2.0, box), _joint("j", "base", "arm"), name="q.urdf")
    code, _, found = _check(capsys, real)
    assert code == 0 and not any(c == "implausible_inertia" for _, c in found)


def test_sdf_links_without_inertial_are_gazebos_default_not_massless(tmp_path, capsys):
    path = tmp_path / "m.sdf"
    path.write_text('<sdf version="1.7"><model name="m"><link name="plain"/></model></sdf>')
    code, report, _ = _check(capsys, path)
    notes = [n["code"] for lk in report["links"] for n in sev(lk, "note")]
    assert code == 0 and notes == ["sdf_default_inertial"] and report["massless_frames"] == []


def test_empty_robot_and_dangling_joint_are_errors_not_zero_errors(tmp_path, capsys):
    empty = _urdf(tmp_path, "<!-- nothing -->\n", name="empty.urdf")
    code, report, _ = _check(capsys, empty)
    assert code == 1 and [e["code"] for e in sev(report, "error")] == ["no_links"]
    dangling = _urdf(tmp_path, _link("base", 1.0, 0.1), _joint("j", "base", "ghost"), name="d.urdf")
    code, report, _ = _check(capsys, dangling)
    assert code == 1 and [e["code"] for e in sev(report, "error")] == ["joints_unreadable"]
    assert "ghost" in sev(report, "error")[0]["message"]


def test_group_mass_is_the_composite_of_the_welded_links():
    """The welded group's moments against a closed form: two point-like 1 kg spheres 2 d apart."""
    from inertia.robots.floors import group_mass
    from inertia.robots.model import Inertial, Link, RobotModel

    d, r = 0.5, 1e-3
    tiny = 2 / 5 * r * r
    links = [Link("a", 1, Inertial(1.0, np.zeros(3), np.eye(3), tiny * np.eye(3))),
             Link("b", 2, Inertial(1.0, np.zeros(3), np.eye(3), tiny * np.eye(3)), parent=0,
                  p_parent_link=np.array([2 * d, 0, 0]))]
    model = RobotModel("x", "urdf", links)
    members = [(0, np.eye(3), np.zeros(3)), (1, np.eye(3), np.array([2 * d, 0, 0]))]

    def props_of(link):
        from inertia import MassProperties

        i = link.inertial
        return MassProperties(i.mass, i.com_link, i.inertia_com)

    mass, moments = group_mass(model, members, props_of)
    assert mass == 2.0
    np.testing.assert_allclose(moments, [2 * tiny, 2 * tiny + 2 * d * d, 2 * tiny + 2 * d * d], rtol=1e-12)
