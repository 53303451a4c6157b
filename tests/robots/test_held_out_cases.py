"""The numbered cases of issue 33 (what 795 held-out robot files showed), each with files the test
writes and checked against its oracle: MuJoCo's compiler, Pinocchio (urdfdom), the SDF specification."""

from __future__ import annotations

import json
import math
import re

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from inertia.cli.main import main
from inertia.robots import read_robot, robot_mass_properties
from tests.robots._oracles import mujoco_bodies, mujoco_compiles, pinocchio_links, worst_body_difference
from tests.robots._report import sev

#: per-body agreement with MuJoCo's compiler on primitives and declared inertials (float64 rounding)
MUJOCO_RTOL = 1e-12


def _write(folder, files: dict):
    for name, text in files.items():
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(text)
    return folder / next(iter(files))


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out = capsys.readouterr()
    return code, out.out, out.err


def _check_json(capsys, path) -> tuple[int, dict]:
    code, out, _ = _run(capsys, "check", path, "--format", "json")
    return code, json.loads(out)


def _codes(report: dict, kind: str) -> set:
    """The codes of the findings of ``kind`` ("errors", "warnings", "notes") in a check report's JSON."""
    severity = kind[:-1]
    return {f["code"] for part in [report] + report["links"] for f in part["findings"] if f["severity"] == severity}


# ---------------------------------------------------------------------------------- case 1

ARM = """<mujoco model="arm">
  <compiler angle="radian" {extra}/>
  <worldbody>
    <body name="gripper" pos="0.1 0.2 0.3" euler="0 1.57 -1.57">
      <joint name="j" axis="0 1 0"/>
      <inertial pos="0.02 0.03 0.04" euler="0.3 -1.2 0.5" mass="0.7" diaginertia="0.001 0.002 0.0025"/>
      <geom type="box" size="0.1 0.2 0.3" pos="0 0.1 0" euler="1.57 0 0"/>
      <body name="finger" pos="0 0.05 0" euler="1.57 0 0"><joint name="k"/>
        <geom type="capsule" size="0.01 0.05" euler="0 1.2 0"/></body>
    </body>
  </worldbody>
</mujoco>
"""


@pytest.mark.parametrize("extra", ["", 'inertiafromgeom="true"'])
def test_case01_an_included_models_compiler_holds_for_the_whole_scene(tmp_path, extra):
    """A scene's <compiler> before the <include> of a model with <compiler angle="radian">
    (Menagerie's aloha scene.xml): MuJoCo merges both, so the model's euler are radians (and its
    inertiafromgeom holds); before the fix its COM was off by cm and its mass was 1 vs 48."""
    scene = _write(tmp_path, {"scene.xml": '<mujoco model="scene">\n  <compiler meshdir="assets"/>\n'
                                           '  <include file="arm.xml"/>\n</mujoco>\n',
                              "arm.xml": ARM.format(extra=extra)})
    worst, n = worst_body_difference(scene)
    assert n == 2 and worst < MUJOCO_RTOL
    alone, _ = worst_body_difference(tmp_path / "arm.xml")
    assert alone < MUJOCO_RTOL


# ---------------------------------------------------------------------------------- case 2


def test_case02_geoms_outside_inertiagrouprange_carry_no_mass(tmp_path):
    path = _write(tmp_path, {"m.xml": """<mujoco>
  <compiler inertiagrouprange="0 1"/>
  <default><default class="big"><geom group="3"/></default></default>
  <worldbody><body name="b"><freejoint/>
    <geom type="box" size="0.1 0.1 0.1"/>
    <geom type="sphere" size="0.5" class="big"/>
    <geom type="box" size="0.1 0.2 0.1" pos="0.3 0 0" group="1"/>
    <geom type="box" size="0.1 0.2 0.1" pos="-0.3 0 0" group="2" mass="100"/>
  </body></worldbody>
</mujoco>
"""})
    ours = robot_mass_properties(path).link("b")
    assert ours.mass == pytest.approx(mujoco_bodies(path)["b"][0], rel=1e-14) == pytest.approx(8 + 16)
    assert worst_body_difference(path)[0] < MUJOCO_RTOL


# ---------------------------------------------------------------------------------- case 3


def _polygon_obj(n: int, flipped: bool = False) -> str:
    """A prism whose two caps are n-gons (one polygon face each) and whose sides are quads;
    ``flipped``: the bottom cap wound as the top one (against its neighbours)."""
    angles = [2 * math.pi * k / n + 0.1 * math.sin(3 * k) for k in range(n)]
    lines = [f"v {math.cos(a):.9f} {0.7 * math.sin(a):.9f} {z}" for z in (-0.2, 0.3) for a in angles]
    lines.append("f " + " ".join(str(k + 1) for k in (range(n) if flipped else reversed(range(n)))))
    lines.append("f " + " ".join(str(n + k + 1) for k in range(n)))
    lines += [f"f {k + 1} {(k + 1) % n + 1} {n + (k + 1) % n + 1} {n + k + 1}" for k in range(n)]
    return "\n".join(lines) + "\n"


def _polygon_model(tmp_path, n: int, mode: str, flipped: bool = False, inertial: str = ""):
    return _write(tmp_path, {"m.xml": f"""<mujoco>
  <asset><mesh name="p" file="p.obj" inertia="{mode}"/></asset>
  <worldbody><body name="b"><freejoint/>{inertial}<geom type="mesh" mesh="p"/></body></worldbody>
</mujoco>
""", "p.obj": _polygon_obj(n, flipped)})


@pytest.mark.parametrize("n", [5, 49, 415])
@pytest.mark.parametrize("mode", ["legacy", "convex", "exact", "shell"])
def test_case03_obj_polygons_are_triangulated_as_mujoco_does(tmp_path, n, mode):
    """Self-crossing n-gon caps (Menagerie's stretch gripper has faces of 49 to 415 vertices):
    MuJoCo's reader ear-clips faces of 5 to 100 vertices its own way and drops larger ones; before
    the fix (fans) legacy and shell differed by 0.16 and 0.35 at n = 49, by 0.50 to 1.6 at 415."""
    assert worst_body_difference(_polygon_model(tmp_path, n, mode))[0] < 1e-7


@pytest.mark.parametrize("n", [5, 49, 415])
@pytest.mark.parametrize("inertial", ["", '<inertial pos="0 0 0" mass="1" diaginertia="1 1 1"/>'])
def test_case03_exact_mode_refuses_inconsistent_winding_as_mujoco_does(tmp_path, capsys, n, inertial):
    """A cap wound against its neighbours: MuJoCo refuses the mesh in inertia="exact" (whatever the
    body's inertial), naming the first edge two faces run along; at n = 415 its reader drops the
    caps and compiles the rest.  check gives the same verdict (mujoco_refuses_mesh, exit 1), the same
    edge, and no massless-link error beside it; before the fix it reported a mass."""
    path = _polygon_model(tmp_path, n, "exact", flipped=True, inertial=inertial)
    theirs = mujoco_compiles(path)
    code, report = _check_json(capsys, path)
    errors = [e for lk in report["links"] for e in lk["findings"] if e["severity"] == "error"]
    if theirs is None:
        assert n == 415 and code == 0 and "mujoco_refuses_mesh" not in _codes(report, "errors")
        return
    pair = re.search(r"vertices (\d+) and (\d+)", theirs).groups()
    assert code == 1 and [e["code"] for e in errors] == ["mujoco_refuses_mesh"]
    assert re.search(r"from vertex (\d+) to vertex (\d+)", errors[0]["message"]).groups() == pair
    assert report["massless_frames"] == []


# ---------------------------------------------------------------------------------- case 4


def _sdf(version: str, inertial_pose: str, collision_pose: str) -> str:
    return f"""<sdf version="{version}"><model name="m"><link name="l">
  <inertial>{inertial_pose}<mass>2</mass>
    <inertia><ixx>0.1</ixx><iyy>0.2</iyy><izz>0.25</izz><ixy>0</ixy><ixz>0</ixz><iyz>0</iyz></inertia></inertial>
  <collision name="c">{collision_pose}<geometry><box><size>0.1 0.2 0.3</size></box></geometry></collision>
</link></model></sdf>
"""


@pytest.mark.parametrize("form", ["degrees", "quat_xyzw"])
def test_case04_sdf_pose_forms_hold_in_inertials_and_shapes(tmp_path, form):
    """SDF 1.9's <pose degrees="true"> and rotation_format="quat_xyzw" inside <inertial> and
    <collision> (read as radians, or refused, before the fix), against the specification:
    the same rotation from scipy."""
    rpy_deg = [30.0, -50.0, 120.0]
    R = Rotation.from_euler("xyz", rpy_deg, degrees=True)  # SDF rpy: fixed axes x, y, z
    if form == "degrees":
        pose = '<pose degrees="true">0.1 0.2 0.3 ' + " ".join(map(str, rpy_deg)) + "</pose>"
    else:
        pose = '<pose rotation_format="quat_xyzw">0.1 0.2 0.3 ' + " ".join(repr(float(q)) for q in R.as_quat()) + "</pose>"
    path = _write(tmp_path, {"m.sdf": _sdf("1.9", pose, pose)})
    link = read_robot(path).link("l")
    Rm = R.as_matrix()
    np.testing.assert_allclose(link.inertial.com_link, [0.1, 0.2, 0.3], atol=1e-15)
    np.testing.assert_allclose(link.inertial.inertia_com, Rm @ np.diag([0.1, 0.2, 0.25]) @ Rm.T, atol=1e-15)
    np.testing.assert_allclose(link.geometries[0].R_link_geom, Rm, atol=1e-15)
    np.testing.assert_allclose(link.geometries[0].p_link_geom, [0.1, 0.2, 0.3], atol=1e-15)


# ---------------------------------------------------------------------------------- case 5

SDF_INERTIAL = ("<inertial><mass>1</mass><inertia><ixx>0.01</ixx><iyy>0.01</iyy><izz>0.01</izz><ixy>0</ixy>"
                "<ixz>0</ixz><iyz>0</iyz></inertia></inertial>")

URDF_INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>'


def test_case05_a_link_inside_a_gazebo_plugin_is_no_link(tmp_path, capsys):
    """unitree and PR2 files: a <link> inside <gazebo><plugin> ("2 root links" before the fix;
    "<inertial> without <mass>" in the xacro'd PR2): urdfdom, hence Pinocchio, reads <robot>'s
    own <link> children only."""
    path = _write(tmp_path, {"r.urdf": f"""<robot name="r">
  <link name="base">{URDF_INERTIAL}</link>
  <link name="arm">{URDF_INERTIAL}</link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm"/>
    <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <gazebo><plugin name="p" filename="libp.so"><link name="imu_link"><inertial><origin xyz="0 0 0"/></inertial></link>
    <bodyName>base</bodyName></plugin></gazebo>
</robot>
"""})
    names, total = pinocchio_links(path)
    assert {lk.name for lk in read_robot(path).links} == names - {"universe"} == {"base", "arm"}
    assert robot_mass_properties(path).total.mass == pytest.approx(total) == 2.0
    assert _run(capsys, "check", path)[0] == 0


# ---------------------------------------------------------------------------------- case 6


@pytest.mark.parametrize("version", ["1.4", "1.5", "1.6"])
def test_case06_a_joint_may_share_a_links_name_before_sdf_1_7(tmp_path, capsys, version):
    """gazebo_models' create, simple_gripper, demo_joint_types (SDF 1.4-1.6): a link and a joint
    with one name ("poses' relative_to form a cycle" before the fix): joints had a namespace of
    their own then; from SDF 1.7 on the names are one namespace and libsdformat refuses it."""
    text = f"""<sdf version="{version}"><model name="m">
  <link name="base"><pose>0 0 0.5 0 0 0</pose>{SDF_INERTIAL}</link>
  <link name="wheel"><pose>0.2 0 0.5 0 0 1.5707963267948966</pose>{SDF_INERTIAL}</link>
  <joint name="wheel" type="revolute"><pose>0.01 0 0 0 0 0</pose><parent>base</parent><child>wheel</child>
    <axis><xyz>1 0 0</xyz></axis></joint>
</model></sdf>
"""
    path = _write(tmp_path, {"m.sdf": text})
    ours = robot_mass_properties(path, {"wheel": 0.0})
    np.testing.assert_allclose(ours.link("wheel").com, [0.2, 0, 0.5], atol=1e-15)
    assert _run(capsys, "check", path)[0] == 0
    (tmp_path / "n.sdf").write_text(text.replace(f'version="{version}"', 'version="1.7"'))
    code, out, _ = _run(capsys, "check", tmp_path / "n.sdf")
    assert code == 1 and "joint 'wheel': a link, joint or frame of this model already has that name" in out


# ---------------------------------------------------------------------------------- case 7


def test_case07_kinematic_loops_are_named_not_refused(tmp_path, capsys):
    """cassie, polaris, PR2's gripper screws: a link that is the child of two joints ("already the
    child of" before the fix).  The links keep their declared poses; the loop joint is named."""
    path = _write(tmp_path, {"m.sdf": f"""<sdf version="1.6"><model name="m">
  <link name="a"><pose>0 0 0 0 0 0</pose>{SDF_INERTIAL}</link>
  <link name="b"><pose>1 0 0 0 0 0</pose>{SDF_INERTIAL}</link>
  <link name="c"><pose>1 1 0 0 0 0</pose>{SDF_INERTIAL}</link>
  <joint name="ab" type="revolute"><parent>a</parent><child>b</child><axis><xyz>0 0 1</xyz></axis></joint>
  <joint name="bc" type="revolute"><parent>b</parent><child>c</child><axis><xyz>0 0 1</xyz></axis></joint>
  <joint name="ac_screw" type="screw"><parent>a</parent><child>c</child><axis><xyz>0 0 1</xyz></axis></joint>
</model></sdf>
"""})
    code, report = _check_json(capsys, path)
    assert code == 0 and "kinematic_loop" in _codes(report, "notes")
    assert "joint 'ac_screw' (its child link 'c' already has a parent)" in sev(report, "note")[0]["message"]
    total = robot_mass_properties(path).total
    assert total.mass == 3.0
    np.testing.assert_allclose(total.com, [2 / 3, 1 / 3, 0], atol=1e-15)


# ---------------------------------------------------------------------------------- case 8


@pytest.mark.parametrize("tiny", ["1e-12", "1e-14"])
def test_case08_a_small_positive_moment_is_positive(tmp_path, capsys, tiny):
    """diaginertia="1e-12 1 1": MuJoCo compiles it and it is physical (not_positive_definite
    before the fix, a fixed fraction of the largest moment)."""
    path = _write(tmp_path, {"m.xml": f"""<mujoco><worldbody><body name="b"><joint/>
  <inertial pos="0 0 0" mass="1" diaginertia="{tiny} 1 1"/></body></worldbody></mujoco>
"""})
    assert mujoco_compiles(path) is None
    assert _run(capsys, "check", path)[0] == 0


# ---------------------------------------------------------------------------------- case 9


def test_case09_an_include_fragment_compiles_and_a_moving_plane_does_not(tmp_path, capsys):
    fragment = _write(tmp_path, {"defaults.xml": '<mujoco>\n  <default><geom rgba="1 0 0 1"/></default>\n'
                                                 '  <keyframe><key name="home"/></keyframe>\n</mujoco>\n'})
    assert mujoco_compiles(fragment) is None
    code, report = _check_json(capsys, fragment)
    assert code == 0 and _codes(report, "errors") == set() and _codes(report, "notes") == {"no_bodies"}
    plane = _write(tmp_path, {"plane.xml": """<mujoco><worldbody>
  <body name="b"><joint/><geom type="sphere" size="0.1"/>
    <body name="c"><geom type="plane" size="1 1 0.1"/></body></body>
</worldbody></mujoco>
"""})
    assert mujoco_compiles(plane) == "Error: plane only allowed in static bodies"
    code, report = _check_json(capsys, plane)
    assert code == 1 and _codes(report, "errors") == {"plane_in_moving_body"}
    static = tmp_path / "static.xml"
    static.write_text(plane.read_text().replace("<joint/>", ""))
    assert mujoco_compiles(static) is None and _run(capsys, "check", static)[0] == 0


# ---------------------------------------------------------------------------------- case 10

MASSLESS_MOVING = f"""<robot name="r">
  <link name="base">{URDF_INERTIAL}</link>
  <link name="wheel"/>
  <joint name="j" type="continuous"><parent link="base"/><child link="wheel"/></joint>
</robot>
"""
UNREADABLE_JOINTS = f'<robot name="r"><link name="a">{URDF_INERTIAL}</link><link name="b">{URDF_INERTIAL}</link></robot>'


@pytest.mark.parametrize("name, text", [("massless.urdf", MASSLESS_MOVING), ("two_roots.urdf", UNREADABLE_JOINTS),
                                        ("fragment.xml", "<mujoco><default/></mujoco>")])
def test_case10_fix_and_check_agree_on_the_written_copy(tmp_path, capsys, name, text):
    """fix said "written and valid" (exit 0) where check of its output said 1: one judgement now."""
    path = _write(tmp_path, {name: text})
    out = tmp_path / f"fixed_{name}"
    for mode in ([], ["--flip-products"], ["--from-geometry"]):
        fixed = _run(capsys, "fix", path, "-o", out, *mode)[0]
        assert fixed == _run(capsys, "check", out)[0]


def test_case10_a_scene_with_nothing_to_fix_says_so(tmp_path, capsys):
    scene = _write(tmp_path, {"scene.xml": '<mujoco><include file="arm.xml"/></mujoco>\n',
                              "arm.xml": ARM.format(extra="")})
    code, _, err = _run(capsys, "fix", scene, "-o", tmp_path / "out.xml")
    assert code == 0 and "nothing to fix" in err and (tmp_path / "out.xml").read_bytes() == scene.read_bytes()


# ---------------------------------------------------------------------------------- case 11


def test_case11_a_stray_end_tag_is_read_as_mujoco_reads_it(tmp_path, capsys):
    """unitree g1's scene.xml: a second </mujoco> (MuJoCo's tinyxml2 stops at the root's end)."""
    path = _write(tmp_path, {"scene.xml": '<mujoco>\n  <worldbody><body name="b"><joint/><geom size="0.1"/></body>'
                                          '</worldbody>\n</mujoco>\n</mujoco>\n'})
    assert mujoco_compiles(path) is None
    assert worst_body_difference(path)[0] < MUJOCO_RTOL
    code, out, _ = _run(capsys, "check", path, "--format", "json")
    (found,) = json.loads(out)["findings"]
    assert code == 0 and (found["code"], found["severity"], found["where"]) == ("content_after_root", "warning",
                                                                                f"{path}:4")
    assert found["message"].startswith("markup after the end of the root element")
    path.write_text(path.read_text() + "text after the stray end tag: tinyxml2 stopped before it\n")
    assert mujoco_compiles(path) is None and _run(capsys, "check", path)[0] == 0
    path.write_text(path.read_text().split("</mujoco>")[0] + "</mujoco>\n junk")
    assert mujoco_compiles(path) is not None and _run(capsys, "check", path)[0] == 2


@pytest.mark.parametrize("attribute, value", [("mass", "2.5\n"), ("mass", "2.5 "), ("xyz", "0 0\n0.1")])
def test_case11_numbers_urdfdom_refuses_are_warned_of(tmp_path, capsys, attribute, value):
    """A line break after or inside a number reads as XML, but urdfdom says "not a float" and
    Pinocchio then drops the inertial: a warning naming the element."""
    mass, xyz = ("2.5", "0 0 0.1")
    mass, xyz = (value, xyz) if attribute == "mass" else (mass, value)
    path = _write(tmp_path, {"r.urdf": f"""<robot name="r"><link name="base"/><link name="b"><inertial>
  <origin xyz="{xyz}"/><mass value="{mass}"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j" type="fixed"><parent link="base"/><child link="b"/></joint></robot>
"""})
    assert pinocchio_links(path)[1] == 0.0  # urdfdom refused the inertial: Pinocchio has no mass
    assert robot_mass_properties(path).total.mass == 2.5
    code, report = _check_json(capsys, path)
    assert code == 0 and _codes(report, "warnings") == {"ros_unreadable_number"}
    clean = tmp_path / "clean.urdf"
    clean.write_text(re.sub(r'="([^"]*)"', lambda m: '="' + " ".join(m.group(1).split()) + '"', path.read_text()))
    code, report = _check_json(capsys, clean)
    assert pinocchio_links(clean)[1] == 2.5 and code == 0 and _codes(report, "warnings") == set()


# ---------------------------------------------------------------------------------- case 12


def _collada_with_missing_texture(folder):
    """A COLLADA box whose emission texture lies outside the mesh folder (trimesh logs a traceback)."""
    trimesh = pytest.importorskip("trimesh")
    pytest.importorskip("collada")
    from trimesh.exchange.dae import export_collada

    text = export_collada(trimesh.creation.box((0.1, 0.2, 0.3))).decode()
    text = text.replace("<library_effects>", '<library_images><image id="img"><init_from>../elsewhere/t.png'
                        "</init_from></image></library_images><library_effects>")
    text = text.replace('<technique sid="common">', '<newparam sid="surf"><surface type="2D"><init_from>img'
                        '</init_from></surface></newparam><newparam sid="samp"><sampler2D><source>surf</source>'
                        '</sampler2D></newparam><technique sid="common">', 1)
    text = re.sub(r"<emission>\s*<color>[^<]*</color>\s*</emission>",
                  '<emission><texture texture="samp" texcoord="UVSET0"/></emission>', text)
    (folder / "meshes").mkdir()
    (folder / "meshes" / "box.dae").write_text(text)


def test_case12_a_dependencys_noise_is_one_line_not_a_traceback(tmp_path, capfd):
    _collada_with_missing_texture(tmp_path)
    path = _write(tmp_path, {"m.sdf": f"""<sdf version="1.6"><model name="m"><link name="l">{SDF_INERTIAL}
  <visual name="v"><geometry><mesh><uri>meshes/box.dae</uri></mesh></geometry></visual></link></model></sdf>
"""})
    assert main(["check", str(path), "-v"]) == 0
    out, err = capfd.readouterr()
    assert "Traceback" not in err and err == ""
    assert "its reader said: unable to load emissive texture (" in out and out.count("\n") < 8


def test_case11_a_comment_holding_dashes_is_read_as_tinyxml2_reads_it(tmp_path, capsys):
    """gazebo_models' src_doorway: a comment opened inside a comment (XML forbids '--' there;
    tinyxml2, hence MuJoCo, urdfdom and libsdformat, ends the comment at the first '-->')."""
    path = _write(tmp_path, {"m.xml": '<mujoco>\n  <!-- mass from aluminium\n  <!-- divided by 4 -- hollow --->\n'
                                      '  <worldbody><body name="b"><joint/><geom size="0.1"/></body></worldbody>\n'
                                      "</mujoco>\n"})
    assert mujoco_compiles(path) is None
    assert worst_body_difference(path)[0] < MUJOCO_RTOL
    code, report = _check_json(capsys, path)
    assert code == 0 and _codes(report, "warnings") == {"comment_with_dashes"}
    out = tmp_path / "out.xml"
    assert main(["fix", str(path), "-o", str(out)]) == 0 and out.read_bytes() == path.read_bytes()
