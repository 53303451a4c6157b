"""The families behind issue 33's cases, swept, each case with files the test writes:

* every MJCF ``<compiler>`` attribute that changes inertia, set in every place an ``<include>``
  allows (the main file before or after the include, the included file before or after its
  bodies) and overridden in both orders, against MuJoCo's compiler body by body;
* every SDF pose form (radians, degrees, quat_xyzw, relative_to) in every place (link,
  inertial, collision) by version (1.4 to 1.11), against the specification's transform;
* every URDF element that can hold a ``<link>`` that is not one, against urdfdom (Pinocchio);
* validity tolerances over 30 orders of magnitude, against MuJoCo's acceptance.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from inertia.cli.main import main
from inertia.robots import read_robot, robot_mass_properties
from tests.robots._oracles import mujoco_compiles, pinocchio_links, worst_body_difference
from tests.robots._report import sev

#: per-body agreement with MuJoCo on primitives and declared inertials
MUJOCO_RTOL = 1e-12
#: fitted primitives: MuJoCo's eigen-solver stops at about 1e-6 rad (see mujoco_inertia)
FITTED_RTOL = 1e-9

# ------------------------------------------------------------------------ compiler x includes

#: a model whose bodies' mass properties depend on every <compiler> mass option
MODEL = """<mujoco model="arm">
  {inner_before}
  <asset><mesh name="tet" vertex="0 0 0  0.3 0 0  0 0.2 0  0 0 0.1  0.1 0.1 0.2" inertia="convex"/></asset>
  <worldbody>
    <body name="a" pos="0.1 0.2 0.3" euler="10 20 30">
      <joint name="ja" axis="0 1 0"/>
      <inertial pos="0.01 0.02 0.03" euler="0.3 -1.2 0.5" mass="0.7" diaginertia="0.001 0.002 0.0025"/>
      <geom type="box" size="0.1 0.05 0.02" euler="0 0 0.4"/>
      <geom type="sphere" size="0.2" group="3" pos="0 0.1 0"/>
      <geom type="capsule" size="0.02 0.1" contype="0" conaffinity="0" euler="1 0 0"/>
      <body name="static" pos="0 0.3 0" euler="0 30 0"><geom type="cylinder" size="0.03 0.1"/></body>
      <body name="massless" pos="0 0 0.2"><site name="s"/></body>
      {balance}
    </body>
    <body name="free" pos="1 0 0"><freejoint/>
      <inertial pos="0.1 0.05 0" quat="0.9 0.1 0.3 0.2" mass="2" diaginertia="0.02 0.03 0.04"/></body>
    <body name="fitted" pos="0 1 0"><joint name="jf"/><geom type="box" mesh="tet"/><geom type="ellipsoid" mesh="tet"/>
      <geom type="sphere" size="0.1" group="3" pos="0.3 0 0"/></body>
  </worldbody>
  {inner_after}
</mujoco>
"""
BALANCE = ('<body name="unbalanced" pos="0.1 0 0"><joint name="ju"/>'
           '<inertial pos="0 0 0" mass="1" diaginertia="0.01 0.01 0.05"/></body>')

#: attribute -> (value swept, the value it overrides or is overridden by)
COMPILER = {"angle": ("radian", "degree"), "eulerseq": ("ZYX", "xyz"), "inertiagrouprange": ("0 1", "0 5"),
            "boundmass": ("0.5", "0"), "boundinertia": ("0.01", "0"), "balanceinertia": ("true", "false"),
            "inertiafromgeom": ("true", "auto"), "settotalmass": ("5", "-1"), "fitaabb": ("true", "false"),
            "alignfree": ("true", "false"), "discardvisual": ("true", "false"), "fusestatic": ("true", "false")}

#: where the attribute is set: (main before the include, main after it, included before its
#: bodies, included after them); two entries set it twice, the second value in document order wins
PLACES = {"main, before the include": ("main_before",), "main, after the include": ("main_after",),
          "included, before its bodies": ("inner_before",), "included, after its bodies": ("inner_after",),
          "main then included (included wins)": ("main_before:other", "inner_before"),
          "included then main (main wins)": ("inner_before:other", "main_after")}


def write_compiler_case(folder, attribute: str, place: str):
    """The two files of one sweep case; returns the main file."""
    value, other = COMPILER[attribute]
    slots = dict.fromkeys(("main_before", "main_after", "inner_before", "inner_after"), "")
    for slot in PLACES[place]:
        name, _, which = slot.partition(":")
        slots[name] = f'<compiler {attribute}="{other if which else value}"/>'
    (folder / "arm.xml").write_text(MODEL.format(inner_before=slots["inner_before"], inner_after=slots["inner_after"],
                                                 balance=BALANCE if attribute == "balanceinertia" else ""))
    main = folder / "scene.xml"
    main.write_text(f'<mujoco model="scene">\n  {slots["main_before"]}\n  <include file="arm.xml"/>\n'
                    f'  {slots["main_after"]}\n</mujoco>\n')
    return main


def compiler_sweep_row(folder, attribute: str, place: str) -> tuple:
    """``(MuJoCo's refusal or None, our check's exit status, worst per-body difference or None)``."""
    main = write_compiler_case(folder, attribute, place)
    refusal = mujoco_compiles(main)
    code = main_quiet(["check", str(main), "-q"])
    worst = None if refusal else worst_body_difference(main, fusestatic=None)[0]
    return refusal, code, worst


def main_quiet(argv) -> int:
    import contextlib
    import io

    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        return main(argv)


@pytest.mark.filterwarnings("ignore:compiler attribute 'settotalmass' is deprecated")
@pytest.mark.parametrize("place", list(PLACES))
@pytest.mark.parametrize("attribute", list(COMPILER))
def test_every_compiler_mass_option_holds_across_includes_as_in_mujoco(tmp_path, attribute, place):
    refusal, code, worst = compiler_sweep_row(tmp_path, attribute, place)
    if refusal:  # balanceinertia="false" last: MuJoCo refuses the unbalanced body, and so does check
        assert attribute == "balanceinertia" and "A + B >= C" in refusal and code == 1
        return
    assert code == 0
    assert worst < FITTED_RTOL


def test_a_removed_compiler_attribute_is_refused_as_mujoco_refuses_it(tmp_path, capsys):
    path = tmp_path / "m.xml"
    path.write_text('<mujoco><compiler exactmeshinertia="true"/><worldbody><body><freejoint/><geom size="1"/>'
                    "</body></worldbody></mujoco>")
    assert "unrecognized attribute: 'exactmeshinertia'" in (mujoco_compiles(path) or "")
    assert main(["check", str(path)]) == 2
    assert "exactmeshinertia=...> is not MJCF any more" in capsys.readouterr().err


# ------------------------------------------------------------------------ SDF pose forms

VERSIONS = ["1.4", "1.5", "1.6", "1.7", "1.8", "1.9", "1.10", "1.11"]
FORMS = ["radians", "degrees", "quat_xyzw", "relative_to"]
PLACE_ELEMENTS = ["link", "inertial", "collision"]
RPY = [0.3, -0.7, 2.1]
XYZ = [0.1, -0.2, 0.3]


def _pose(form: str, rel: str = "") -> str:
    R = Rotation.from_euler("xyz", RPY)
    xyz = " ".join(map(repr, XYZ))
    if form == "degrees":
        return f'<pose degrees="true">{xyz} ' + " ".join(repr(float(np.degrees(a))) for a in RPY) + "</pose>"
    if form == "quat_xyzw":
        return f'<pose rotation_format="quat_xyzw">{xyz} ' + " ".join(repr(float(q)) for q in R.as_quat()) + "</pose>"
    attr = f' relative_to="{rel}"' if form == "relative_to" else ""
    return f"<pose{attr}>{xyz} " + " ".join(map(repr, RPY)) + "</pose>"


def _sdf_pose_case(version: str, form: str, place: str) -> str:
    """A model with a reference link ``ref`` at a known pose and link ``l`` whose ``place`` has
    the pose in ``form`` (relative_to ``ref`` for the link; to ``l`` itself inside it)."""
    pose = _pose(form, "ref" if place == "link" else "l")
    inertia = "<inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.25</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia>"
    return f"""<sdf version="{version}"><model name="m">
  <link name="ref"><pose>1 2 3 0 0 1.5707963267948966</pose></link>
  <link name="l">{pose if place == "link" else ""}
    <inertial>{pose if place == "inertial" else ""}<mass>2</mass>{inertia}</inertial>
    <collision name="c">{pose if place == "collision" else ""}<geometry><box><size>0.1 0.2 0.3</size></box>
    </geometry></collision></link>
</model></sdf>
"""


def _expected_pose(version: str, form: str, place: str):
    """The specification's pose of ``place`` in the model frame: ``(R, p)``."""
    R, p = Rotation.from_euler("xyz", RPY).as_matrix(), np.array(XYZ)
    if place == "link" and form == "relative_to" and float(version[2:]) >= 7:
        R_ref, p_ref = Rotation.from_euler("z", np.pi / 2).as_matrix(), np.array([1.0, 2, 3])
        return R_ref @ R, R_ref @ p + p_ref  # relative_to is SDF 1.7's: before it, no such attribute
    return R, p


@pytest.mark.parametrize("place", PLACE_ELEMENTS)
@pytest.mark.parametrize("form", FORMS)
@pytest.mark.parametrize("version", VERSIONS)
def test_every_sdf_pose_form_by_version_follows_the_specification(tmp_path, version, form, place):
    path = tmp_path / "m.sdf"
    path.write_text(_sdf_pose_case(version, form, place))
    R, p = _expected_pose(version, form, place)
    ours = robot_mass_properties(path).link("l")
    link = read_robot(path).link("l")
    I_declared = np.diag([0.1, 0.2, 0.25])
    if place == "collision":
        np.testing.assert_allclose(link.geometries[0].R_link_geom, R, atol=1e-14)
        np.testing.assert_allclose(link.geometries[0].p_link_geom, p, atol=1e-14)
        np.testing.assert_allclose(ours.inertia_com, I_declared, atol=1e-14)
    else:
        np.testing.assert_allclose(ours.com, p, atol=1e-14)
        np.testing.assert_allclose(ours.inertia_com, R @ I_declared @ R.T, atol=1e-14)
    assert main_quiet(["check", str(path)]) == 0


# ------------------------------------------------------------------------ URDF <link> holders

HOLDERS = {
    "gazebo": "<gazebo>{link}</gazebo>",
    "gazebo plugin": '<gazebo><plugin name="p" filename="libp.so">{link}</plugin></gazebo>',
    "gazebo reference sensor": '<gazebo reference="base"><sensor name="s" type="imu">{link}</sensor></gazebo>',
    "transmission": '<transmission name="t"><type>SimpleTransmission</type>{link}'
                    '<joint name="j"><hardwareInterface>E</hardwareInterface></joint></transmission>',
    "ros2_control": '<ros2_control name="rc" type="system"><hardware>{link}</hardware></ros2_control>',
    "an unknown element": "<anything><nested>{link}</nested></anything>",
    "a link's own child": None,  # the stray <link> inside the arm link
}
STRAY = '<link name="stray"><inertial><mass value="5"/></inertial></link>'
INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'


@pytest.mark.parametrize("holder", list(HOLDERS))
def test_a_link_held_by_any_other_element_is_no_link_as_in_urdfdom(tmp_path, holder):
    arm = f'<link name="arm">{INERTIAL}{STRAY if HOLDERS[holder] is None else ""}</link>'
    extra = HOLDERS[holder].format(link=STRAY) if HOLDERS[holder] else ""
    path = tmp_path / "r.urdf"
    path.write_text(f'<robot name="r"><link name="base">{INERTIAL}</link>{arm}<joint name="j" type="revolute">'
                    '<parent link="base"/><child link="arm"/><limit lower="-1" upper="1" effort="1" velocity="1"/>'
                    f"</joint>{extra}</robot>")
    names, total = pinocchio_links(path)
    assert {lk.name for lk in read_robot(path).links} == names - {"universe"} == {"base", "arm"}
    assert robot_mass_properties(path).total.mass == total == 2.0
    assert main_quiet(["check", str(path)]) == 0


# ------------------------------------------------------------------------ tolerances


#: 16 scales over 30 orders of magnitude; odd powers keep the smallest moments off MuJoCo's
#: floor (1e-15) exactly, where rounding would decide
SCALES = [10.0 ** k for k in range(-15, 16, 2)]
TENSORS = {
    "a moment 1e-12 of the others": "diaginertia=\"{a} {s} {s}\"",
    "a flat plate (I1 + I2 = I3)": "diaginertia=\"{s} {s} {s2}\"",
    "I1 + I2 short of I3 by 1e-9": "diaginertia=\"{s} {s} {s2b}\"",
    "I1 + I2 short of I3 by 1e-13": "diaginertia=\"{s} {s} {s2c}\"",
    "a zero moment": "diaginertia=\"0 {s} {s}\"",
    "a rotated tensor": "fullinertia=\"{f}\"",
}


def _tolerance_case(tmp_path, scale: float, tensor: str, moving: bool):
    R = Rotation.from_euler("xyz", [0.3, 0.5, -0.4]).as_matrix()
    I = R @ np.diag([0.5, 0.7, 0.9]) @ R.T * scale
    values = {"a": repr(1e-12 * scale), "s": repr(scale), "s2": repr(2 * scale), "s2b": repr(2 * scale * (1 + 1e-9)),
              "s2c": repr(2 * scale * (1 + 1e-13)),
              "f": " ".join(repr(float(x)) for x in (I[0, 0], I[1, 1], I[2, 2], I[0, 1], I[0, 2], I[1, 2]))}
    path = tmp_path / "m.xml"
    path.write_text(f'<mujoco><worldbody><body name="b">{"<joint/>" if moving else ""}<inertial pos="0 0 0" '
                    f'mass="1" {TENSORS[tensor].format(**values)}/></body></worldbody></mujoco>')
    return path


def tolerance_row(tmp_path, scale: float, tensor: str, moving: bool) -> tuple[bool, bool]:
    """``(MuJoCo compiles it, check finds no error)``."""
    path = _tolerance_case(tmp_path, scale, tensor, moving)
    return mujoco_compiles(path) is None, main_quiet(["check", str(path), "-q"]) == 0


@pytest.mark.parametrize("moving", [True, False], ids=["moving", "static"])
@pytest.mark.parametrize("tensor", list(TENSORS))
def test_validity_follows_mujocos_acceptance_over_30_orders_of_magnitude(tmp_path, tensor, moving):
    verdicts = {scale: tolerance_row(tmp_path, scale, tensor, moving) for scale in SCALES}
    assert [s for s, (theirs, ours) in verdicts.items() if theirs != ours] == []


def test_check_json_of_a_tolerance_case_names_mujocos_floor(tmp_path, capsys):
    path = _tolerance_case(tmp_path, 1e-9, "a moment 1e-12 of the others", True)
    assert main(["check", str(path), "--format", "json"]) == 1
    report = json.loads(capsys.readouterr().out)
    assert [e["code"] for lk in report["links"] for e in sev(lk, "error")] == ["below_simulator_floor"]


# ------------------------------------------------------------------------ SDF <include>


def test_an_sdf_world_of_included_models_equals_the_world_written_out(tmp_path):
    """libsdformat's <include>: model://NAME is a model folder (model.config names the SDF of each
    version, the newest read), <name>, <pose> and <static> replace the model's own."""
    body = ("<link name='l'><pose>0.1 0 0 0 0 0</pose><inertial><pose>0 0.2 0 0 0 0</pose><mass>2</mass><inertia>"
            "<ixx>0.1</ixx><iyy>0.2</iyy><izz>0.25</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>"
            "</link>")
    (tmp_path / "models" / "cart").mkdir(parents=True)
    (tmp_path / "models" / "cart" / "model.config").write_text(
        "<model><sdf version='1.5'>old.sdf</sdf><sdf version='1.6'>model.sdf</sdf></model>")
    (tmp_path / "models" / "cart" / "old.sdf").write_text("<sdf version='1.5'><model name='cart'/></sdf>")
    (tmp_path / "models" / "cart" / "model.sdf").write_text(
        f"<sdf version='1.6'><model name='cart'><pose>5 5 5 0 0 0</pose>{body}</model></sdf>")
    (tmp_path / "world").mkdir()
    world = tmp_path / "world" / "w.sdf"
    world.write_text("<sdf version='1.6'><world name='w'>"
                     "<include><uri>model://cart</uri><name>c1</name><pose>1 0 0 0 0 1.5707963267948966</pose></include>"
                     "<include><uri>model://cart</uri><name>c2</name></include>"
                     "<include><uri>model://sun_is_not_here</uri></include></world></sdf>")
    with pytest.raises(Exception, match="model://sun_is_not_here'.*not found"):
        read_robot(world, search_paths=[tmp_path / "models"])
    world.write_text(world.read_text().replace("<include><uri>model://sun_is_not_here</uri></include>", ""))
    written = tmp_path / "world" / "out.sdf"
    written.write_text("<sdf version='1.6'><world name='w'>"
                       f"<model name='c1'><pose>1 0 0 0 0 1.5707963267948966</pose>{body}</model>"
                       f"<model name='c2'><pose>5 5 5 0 0 0</pose>{body}</model></world></sdf>")
    ours = robot_mass_properties(read_robot(world, search_paths=[tmp_path / "models"]))
    expected = robot_mass_properties(written)
    assert [lk.name for lk in ours.links] == ["c1::l", "c2::l"] == [lk.name for lk in expected.links]
    for a, b in zip(ours.links, expected.links):
        np.testing.assert_allclose(a.com, b.com, atol=1e-15)
        np.testing.assert_allclose(a.inertia_com, b.inertia_com, atol=1e-15)
    assert main_quiet(["check", str(world), "--package-path", str(tmp_path / "models")]) == 0
