"""``inertia props ROBOT_FILE``: the whole robot, each link, a subtree, joint values, and the
errors a user meets, checked against MuJoCo's numbers for the same file."""

from __future__ import annotations

import json

import numpy as np
import pytest

from inertia.cli.main import main
from inertia.errors import InputError
from inertia.robots.io import read_robot
from tests.robots.test_whole import MADE_MJCF, _mujoco_at


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out = capsys.readouterr()
    return code, out.out, out.err


@pytest.fixture
def made(tmp_path):
    path = tmp_path / "made.xml"
    path.write_text(MADE_MJCF)
    return path


def test_json_gives_the_whole_robot_and_each_link_as_mujoco_does(capsys, made):
    code, out, _ = _run(capsys, "props", made, "--joint", "h2=0.3", "--joint", "s1=-0.02", "--format", "json")
    assert code == 0
    data = json.loads(out)
    m, d = _mujoco_at(made, {"h2": 0.3, "s1": -0.02})
    assert data["frame"] == "world" and data["configuration"]["h2"] == 0.3
    assert data["configuration"]["h1"] == pytest.approx(np.radians(15), abs=1e-15)  # qpos0: the ref, in rad
    assert data["mass"] == pytest.approx(m.body_subtreemass[0], rel=1e-14)
    np.testing.assert_allclose(data["com"], d.subtree_com[0], rtol=0, atol=1e-14)
    rows = {r["name"]: r for r in data["links"]}
    assert list(rows) == [m.body(i).name for i in range(1, m.nbody)]
    assert set(rows["base"]) == {"name", "mass", "com", "inertia_com", "source"}
    assert {n: r["source"] for n, r in rows.items()} == {
        "base": "declared", "arm": "geometry", "hand": "declared", "finger": "geometry", "static": "geometry",
        "free": "geometry", "massless_frame": "none"}
    for i in range(1, m.nbody):
        if m.body_mass[i] > 0:  # a massless body has no center of mass (we give its origin)
            np.testing.assert_allclose(rows[m.body(i).name]["com"], d.xipos[i], rtol=0, atol=1e-14)


def test_a_subtree_is_mujocos_subtree_and_its_inertial_block_is_in_the_links_frame(capsys, made, tmp_path):
    m, d = _mujoco_at(made)
    arm = m.body("arm").id
    code, out, _ = _run(capsys, "props", made, "--subtree", "arm", "--format", "json")
    data = json.loads(out)
    assert code == 0 and data["subtree"] == "arm" and [r["name"] for r in data["links"]] == ["arm", "hand", "finger"]
    assert data["mass"] == pytest.approx(m.body_subtreemass[arm], rel=1e-14)
    np.testing.assert_allclose(data["com"], d.subtree_com[arm], rtol=0, atol=1e-14)
    # the block lumps the subtree onto the link: read back, moved by the link's pose, the same to
    # the 6 significant digits each number is written with (half a unit in the 6th digit: 5e-6)
    code, block, _ = _run(capsys, "props", made, "--subtree", "arm", "--format", "urdf")
    urdf = tmp_path / "lumped.urdf"
    urdf.write_text(f'<robot name="r"><link name="arm">{block}</link></robot>')
    back = read_robot(urdf).link("arm").inertial
    R, p = d.xmat[arm].reshape(3, 3), d.xpos[arm]
    assert back.mass == pytest.approx(data["mass"], rel=5e-6)
    np.testing.assert_allclose(R @ back.com_link + p, data["com"], rtol=0, atol=5e-6 * np.abs(back.com_link).sum())
    I = np.array(data["inertia_com"])
    np.testing.assert_allclose(R @ back.inertia_com @ R.T, I, rtol=0, atol=5e-6 * 9 * np.abs(I).max())


def test_the_table_lists_every_link_with_its_source(capsys, made):
    code, out, _ = _run(capsys, "props", made)
    assert code == 0 and "Mass properties of the whole robot" in out and "frame           world" in out
    table = out[out.index("\nLinks\n"):]
    for name, source in (("base", "declared"), ("arm", "geometry"), ("massless_frame", "none")):
        assert any(line.split()[0] == name and line.split()[-1] == source for line in table.splitlines()[3:] if line)
    assert "geometry: MuJoCo's inertia from the body's geoms" in table


@pytest.mark.parametrize("argv,message", [
    (["--joint", "elbow=1"], "no joint named 'elbow'; the joints that take a value are: h1, s1, h2, h3, s2"),
    (["--joint", "b1=0.1"], "joint 'b1' is a ball joint: only its default configuration is supported"),
    (["--joint", "f=0"], "joint 'f' is a free joint"),
    (["--joint", "h1"], "--joint 'h1' must read NAME=VALUE"),
    (["--joint", "h1=abc"], "--joint 'h1=abc' must read NAME=VALUE"),
    (["--joint", "h1=nan"], "joint 'h1': the value must be finite"),
    (["--subtree", "elbow"], "no link named 'elbow'"),
    (["--density", "100"], "--density applies to mesh files and primitives only"),
])
def test_bad_options_are_one_message_naming_them(capsys, made, argv, message):
    code, out, err = _run(capsys, "props", made, *argv)
    assert code == 1 and not out and message in err and "Traceback" not in err


def test_robot_options_on_a_mesh_or_primitive_are_refused(capsys):
    code, _, err = _run(capsys, "props", "box:0.1,0.2,0.3", "--joint", "a=1")
    assert code == 1 and "--joint applies to robot files" in err


def test_fixed_and_mimic_joints_take_no_value(capsys, tmp_path):
    path = tmp_path / "r.urdf"
    inertial = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'
    path.write_text(f"""<robot name="r"><link name="a">{inertial}</link><link name="b">{inertial}</link>
<link name="c">{inertial}</link>
<joint name="weld" type="fixed"><parent link="a"/><child link="b"/></joint>
<joint name="follow" type="continuous"><parent link="b"/><child link="c"/><mimic joint="lead"/></joint>
</robot>""")
    for joint, message in (("weld", "joint 'weld' is fixed: it has no value"),
                           ("follow", "joint 'follow' mimics joint 'lead'")):
        code, _, err = _run(capsys, "props", path, "--joint", f"{joint}=1")
        assert code == 1 and message in err
    code, _, err = _run(capsys, "props", path)  # its master is no joint of the file
    assert code == 1 and "joint 'follow' mimics 'lead', which is no joint of this file" in err


def test_sdf_links_without_inertial_count_with_sdfs_default(capsys, tmp_path):
    """Gazebo simulates a link without <inertial> with SDF's default: 1 kg, 1 kg m^2 per axis."""
    path = tmp_path / "m.sdf"
    path.write_text("""<sdf version="1.9"><model name="m">
<link name="body"><inertial><mass>2</mass><inertia><ixx>0.1</ixx><iyy>0.1</iyy><izz>0.1</izz></inertia></inertial>
</link><link name="sensor"><pose>0 0 1 0 0 0</pose></link>
<joint name="mount" type="fixed"><parent>body</parent><child>sensor</child></joint></model></sdf>""")
    code, out, _ = _run(capsys, "props", path, "--format", "json")
    data = json.loads(out)
    assert code == 0 and [r["source"] for r in data["links"]] == ["declared", "sdf_default"]
    assert data["mass"] == 3.0 and data["com"] == pytest.approx([0, 0, 1 / 3], abs=1e-15)
    # parallel axes: 0.1 + 1 about x and y, plus 2 * (1/3)^2 + 1 * (2/3)^2 = 2/3
    np.testing.assert_allclose(np.diag(data["inertia_com"]), [1.1 + 2 / 3, 1.1 + 2 / 3, 1.1], rtol=1e-14)
    assert "SDF's default inertial" in data["notes"][0] and "sensor" in data["notes"][0]
    path.write_text(path.read_text().replace("<inertial>", '<inertial auto="true">'))
    code, out, _ = _run(capsys, "props", path, "--format", "json")
    assert code == 0 and "Gazebo computes these from the collision shapes" in json.loads(out)["notes"][1]


def test_a_urdf_with_two_roots_is_named_and_a_second_parent_is_a_loop(capsys, tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text('<robot name="r"><link name="a"/><link name="b"/><link name="c"/>'
                    '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint></robot>')
    code, _, err = _run(capsys, "props", path)
    assert code == 1 and "one root link" in err and "'a', 'c'" in err
    inertial = '<inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>'
    path.write_text(f'<robot name="r"><link name="a">{inertial}</link><link name="b">{inertial}</link>'
                    '<joint name="j" type="fixed"><parent link="a"/><child link="b"/></joint>'
                    '<joint name="k" type="fixed"><parent link="a"/><child link="b"/></joint></robot>')
    code, out, _ = _run(capsys, "props", path)
    assert code == 0 and "2 kg" in out  # urdfdom reads the loop too; the mass needs no tree
    code, out, _ = _run(capsys, "check", path)
    assert code == 0 and "kinematic_loop" in out and "joint 'k'" in out and "link 'b' already has a parent" in out


def test_an_sdf_world_places_its_models_and_nested_models(tmp_path):
    """Two copies of a model at their world poses, a nested model, a <frame> and a joint named
    by its scope: the closed form of three spheres."""
    from inertia.robots.whole import robot_mass_properties

    def ball(name, mass, pose="0 0 0 0 0 0", extra=""):
        i = 0.4 * mass * 0.1 ** 2
        return (f'<link name="{name}"><pose {extra}>{pose}</pose><inertial><mass>{mass}</mass><inertia>'
                f"<ixx>{i}</ixx><iyy>{i}</iyy><izz>{i}</izz></inertia></inertial></link>")

    model = ('<model name="{name}"><pose>{pose}</pose>' + ball("body", 2.0)
             + '<frame name="tip"><pose relative_to="body">0 0 1 0 0 0</pose></frame>'
             + ball("end", 1.0, "0 0 0 0 0 0", 'relative_to="tip"')
             + '<joint name="j" type="revolute"><parent>body</parent><child>end</child><pose>0 0 -1 0 0 0</pose>'
             + "<axis><xyz>1 0 0</xyz></axis></joint>{nested}</model>")
    nested = '<model name="inner"><pose>0 5 0 0 0 0</pose>' + ball("pod", 3.0) + "</model>"
    path = tmp_path / "w.world"
    path.write_text('<sdf version="1.8"><world name="w">'
                    + model.format(name="a", pose="1 0 0 0 0 0", nested=nested)
                    + model.format(name="b", pose="0 0 2 0 0 1.5707963267948966", nested="") + "</world></sdf>")
    robot = robot_mass_properties(path, {"a::j": np.pi / 2})
    assert robot.frame == "world" and set(robot.configuration) == {"a::j", "b::j"}
    # a: body (1,0,0); end 1 above it, turned about x through the body by 90 deg: (1,-1,0);
    # a::inner::pod (1,5,0); b: body (0,0,2), end (0,0,3)
    points = {"a::body": [1, 0, 0], "a::end": [1, -1, 0], "a::inner::pod": [1, 5, 0], "b::end": [0, 0, 3]}
    for name, point in points.items():
        np.testing.assert_allclose(robot.link(name).com, point, atol=1e-15)
    np.testing.assert_allclose(robot.subtree("a::body").com, [1, -1 / 3, 0], atol=1e-15)
    masses, coms = np.array([2, 1, 3, 2, 1.0]), np.array([[1, 0, 0], [1, -1, 0], [1, 5, 0], [0, 0, 2], [0, 0, 3.0]])
    assert robot.total.mass == 9.0
    np.testing.assert_allclose(robot.total.com, masses @ coms / 9, atol=1e-15)
    r = coms - masses @ coms / 9
    I = sum(0.4 * m * 0.01 * np.eye(3) + m * (x @ x * np.eye(3) - np.outer(x, x)) for m, x in zip(masses, r))
    np.testing.assert_allclose(robot.total.inertia_com, I, atol=1e-14)


def test_a_chain_of_mimic_joints_follows_the_first(tmp_path):
    from inertia.robots.kinematics import configuration

    path = tmp_path / "r.urdf"
    links = "".join(f'<link name="l{i}"/>' for i in range(4))
    joints = "".join(f'<joint name="j{i}" type="revolute"><parent link="l{i - 1}"/><child link="l{i}"/>'
                     f'<limit lower="-1" upper="1" effort="1" velocity="1"/>{mimic}</joint>'
                     for i, mimic in ((1, ""), (2, '<mimic joint="j1" multiplier="2" offset="0.1"/>'),
                                      (3, '<mimic joint="j2" multiplier="-1" offset="0.5"/>')))
    path.write_text(f'<robot name="r">{links}{joints}</robot>')
    values = configuration(read_robot(path), {"j1": 0.3})
    assert values == pytest.approx({"j1": 0.3, "j2": 0.7, "j3": -0.2}, abs=1e-15)
    path.write_text(path.read_text().replace('joint="j1" multiplier="2"', 'joint="j3" multiplier="2"'))
    with pytest.raises(InputError, match="mimic each other in a cycle"):
        configuration(read_robot(path))
