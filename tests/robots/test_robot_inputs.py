"""Inputs real robot repositories hold: ``.urdf.xacro`` files, COLLADA and glTF meshes, old
Gazebo 1.x files, a blank line before ``<?xml``.  Every file is written here."""

from __future__ import annotations

import json
import sys

import numpy as np
import pytest

from inertia.cli.main import main
from inertia.errors import MissingDependencyError, RobotFileError
from inertia.robots.check import check_model
from inertia.robots.io import read_robot
from inertia.robots.whole import robot_mass_properties
from tests.robots._report import sev


def _run(capsys, *argv):
    code = main(list(map(str, argv)))
    out = capsys.readouterr()
    return code, out.out, out.err


def _hide(monkeypatch, name):
    for key in [k for k in sys.modules if k == name or k.startswith(name + ".")]:
        monkeypatch.setitem(sys.modules, key, None)
    monkeypatch.setitem(sys.modules, name, None)


def _box_inertia(m, x, y, z):
    return m * (y * y + z * z) / 12, m * (x * x + z * z) / 12, m * (x * x + y * y) / 12


# ----------------------------------------------------------------------------- xacro

PARTS = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:macro name="box_link" params="name mass x y z">
    <link name="${name}">
      <inertial><mass value="${mass}"/>
        <inertia ixx="${mass*(y*y+z*z)/12}" iyy="${mass*(x*x+z*z)/12}" izz="${mass*(x*x+y*y)/12}"
                 ixy="0" ixz="0" iyz="0"/></inertial>
    </link>
  </xacro:macro>
</robot>
"""

ROBOT = """<?xml version="1.0"?>
<robot name="r" xmlns:xacro="http://www.ros.org/wiki/xacro">
  <xacro:arg name="arm_mass" default="2"/>
  <xacro:arg name="prefix" default=""/>
  <xacro:property name="prefix" value="$(arg prefix)"/>
  <xacro:include filename="$(find {package})/urdf/parts.xacro"/>
  <xacro:box_link name="${{prefix}}base" mass="5" x="0.4" y="0.3" z="0.1"/>
  <xacro:box_link name="${{prefix}}arm" mass="$(arg arm_mass)" x="0.5" y="0.05" z="0.05"/>
  <joint name="${{prefix}}shoulder" type="revolute"><parent link="${{prefix}}base"/><child link="${{prefix}}arm"/>
    <origin xyz="0 0 0.1"/><axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""


@pytest.fixture
def workspace(tmp_path):
    """A ROS-like workspace: ``src/mypkg`` (package.xml) with ``urdf/robot.urdf.xacro``
    including ``$(find parts_pkg)/urdf/parts.xacro`` from ``src/parts_pkg``."""
    pytest.importorskip("xacro")
    src = tmp_path / "ws" / "src"
    for pkg in ("mypkg", "parts_pkg"):
        (src / pkg / "urdf").mkdir(parents=True)
        (src / pkg / "package.xml").write_text(f'<?xml version="1.0"?>\n<package format="3"><name>{pkg}</name>'
                                                "</package>\n")
    (src / "parts_pkg" / "urdf" / "parts.xacro").write_text(PARTS)
    (src / "mypkg" / "urdf" / "robot.urdf.xacro").write_text(ROBOT.format(package="parts_pkg"))
    return src


def test_a_xacro_file_is_expanded_with_its_arguments_and_packages(capsys, workspace):
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    code, out, err = _run(capsys, "props", path, "--package-path", workspace, "--xacro-arg", "prefix:=left_",
                          "--xacro-arg", "arm_mass:=3", "--joint", "left_shoulder=0.5", "--format", "json")
    assert code == 0, err
    data = json.loads(out)
    assert data["format"] == "urdf" and data["frame"] == "root link 'left_base'"
    assert [(r["name"], r["mass"]) for r in data["links"]] == [("left_base", 5.0), ("left_arm", 3.0)]
    # the arm's COM at the origin of its frame: 0.1 up, turned about y (which does not move it)
    assert data["com"] == pytest.approx([0, 0, 3 * 0.1 / 8], abs=1e-15)
    arm = np.array(_box_inertia(3.0, 0.5, 0.05, 0.05))
    c, s = np.cos(0.5), np.sin(0.5)
    R = np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    I = np.diag(_box_inertia(5.0, 0.4, 0.3, 0.1)) + R @ np.diag(arm) @ R.T
    I += (5 * 3 / 8) * 0.1 ** 2 * np.diag([1, 1, 0])  # parallel axes of the two COMs, 0.1 apart on z
    np.testing.assert_allclose(data["inertia_com"], I, rtol=0, atol=1e-15)
    assert check_model(read_robot(path, search_paths=[workspace])).n_errors == 0


def test_a_package_is_found_by_its_folder_without_a_search_path(workspace):
    """``$(find mypkg)`` from a file inside mypkg: the folder whose package.xml names it."""
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    path.write_text(ROBOT.format(package="mypkg"))
    (workspace / "mypkg" / "urdf" / "parts.xacro").write_text(PARTS)
    assert robot_mass_properties(path).total.mass == 7.0


@pytest.mark.parametrize("change,message", [
    (("parts_pkg", "no_such_pkg"), "$(find no_such_pkg): package 'no_such_pkg' not found; give the folder"),
    (('mass="5"', 'mass="$(arg base_mass)"'), "Undefined substitution argument base_mass (give it with "
                                              "--xacro-arg base_mass:=VALUE)"),
    (("</robot>", "<robot>"), "xacro could not expand the file"),
])
def test_xacro_errors_are_one_message_naming_the_file(capsys, workspace, change, message):
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    path.write_text(ROBOT.format(package="parts_pkg").replace(*change))
    code, out, err = _run(capsys, "props", path, "--package-path", workspace)
    assert code == 1 and not out and message in err and str(path) in err and "Traceback" not in err


@pytest.mark.parametrize("how", [["-o", "out.urdf"], ["--in-place"]])
def test_fix_refuses_a_xacro_file_and_writes_nothing(capsys, workspace, how):
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    before = path.read_bytes()
    out = workspace / "out.urdf"
    code, _, err = _run(capsys, "fix", path, "--package-path", workspace,
                        *[str(out) if a == "out.urdf" else a for a in how])
    assert code != 0 and "is a xacro file" in err
    assert path.read_bytes() == before and not out.exists()


def test_xacro_arguments_need_name_and_value(capsys, workspace):
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    code, _, err = _run(capsys, "props", path, "--xacro-arg", "prefix=left_")
    assert code == 1 and "xacro argument 'prefix=left_' must read NAME:=VALUE" in err


def test_without_xacro_the_message_names_the_extra(monkeypatch, tmp_path):
    path = tmp_path / "r.urdf.xacro"
    path.write_text('<robot name="r"><link name="a"/></robot>')
    _hide(monkeypatch, "xacro")
    with pytest.raises(MissingDependencyError) as ei:
        read_robot(path)
    assert ei.value.code == "missing_dependency" and "inertia[xacro]" in str(ei.value)


# ----------------------------------------------------------------------------- COLLADA and glTF meshes


def collada_box(size, center, *, unit: float = 1.0, translate=(0.0, 0.0, 0.0)) -> str:
    """A COLLADA box of ``size`` [m] centred at ``center`` [m], written in units of ``unit`` m,
    its node moved by ``translate`` [file units]."""
    import trimesh

    box = trimesh.creation.box(extents=np.asarray(size, float) / unit)
    v, f = box.vertices + np.asarray(center, float) / unit, box.faces
    pos = " ".join(repr(float(x)) for x in v.ravel())
    idx = " ".join(str(int(i)) for i in f.ravel())
    matrix = np.eye(4)
    matrix[:3, 3] = translate
    return f"""<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit meter="{unit!r}" name="unit"/><up_axis>Z_UP</up_axis></asset>
  <library_geometries><geometry id="g"><mesh>
    <source id="p"><float_array id="pa" count="{v.size}">{pos}</float_array><technique_common>
      <accessor source="#pa" count="{len(v)}" stride="3"><param name="X" type="float"/><param name="Y" type="float"/>
      <param name="Z" type="float"/></accessor></technique_common></source>
    <vertices id="v"><input semantic="POSITION" source="#p"/></vertices>
    <triangles count="{len(f)}"><input semantic="VERTEX" source="#v" offset="0"/><p>{idx}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="s"><node id="n">
    <matrix>{" ".join(repr(float(x)) for x in matrix.ravel())}</matrix><instance_geometry url="#g"/>
  </node></visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#s"/></scene>
</COLLADA>
"""


def test_a_collada_mesh_is_read_in_its_declared_unit(tmp_path):
    """Written in centimetres (<unit meter="0.01">) with a node transform: the box's closed form."""
    pytest.importorskip("collada")
    from inertia import load_mesh
    from inertia.massprops.mesh import mesh_properties

    path = tmp_path / "box.dae"
    path.write_text(collada_box((0.1, 0.2, 0.3), (0.01, 0.02, 0.03), unit=0.01, translate=(5.0, 0.0, 0.0)))
    props = mesh_properties(*load_mesh(path), density=1000.0)
    assert props.mass == pytest.approx(1000 * 0.1 * 0.2 * 0.3, rel=1e-12)
    np.testing.assert_allclose(props.com, [0.06, 0.02, 0.03], rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.diag(props.inertia_com), _box_inertia(6.0, 0.1, 0.2, 0.3), rtol=1e-12)


def test_without_pycollada_a_collada_mesh_names_the_mesh_extra(monkeypatch, tmp_path):
    from inertia import load_mesh

    path = tmp_path / "box.dae"
    path.write_text(collada_box((0.1, 0.2, 0.3), (0, 0, 0)))
    _hide(monkeypatch, "collada")
    with pytest.raises(MissingDependencyError) as ei:
        load_mesh(path)
    assert "inertia[mesh]" in str(ei.value) and "COLLADA" in str(ei.value)


@pytest.mark.parametrize("ext", ["dae", "glb"])
def test_a_robots_collada_or_gltf_mesh_is_compared_with_its_inertial(tmp_path, ext):
    """A URDF link whose visual is a .dae or .glb box: its declared inertial agrees, and a
    tensor 10 times too large is caught against the mesh (so the mesh was read)."""
    pytest.importorskip("collada" if ext == "dae" else "trimesh")
    size, center, mass = (0.1, 0.2, 0.3), (0.0, 0.0, 0.15), 2.0
    mesh = tmp_path / f"box.{ext}"
    if ext == "dae":
        mesh.write_text(collada_box(size, center))
    else:
        import trimesh

        mesh.write_bytes(trimesh.Scene(trimesh.creation.box(extents=size).apply_translation(center))
                         .export(file_type="glb"))
    for factor, warnings in ((1.0, []), (10.0, ["geometry_mismatch"])):
        ixx, iyy, izz = (factor * x for x in _box_inertia(mass, *size))
        path = tmp_path / "r.urdf"
        path.write_text(f"""<robot name="r"><link name="a"><inertial><origin xyz="0 0 0.15"/><mass value="{mass}"/>
<inertia ixx="{ixx!r}" iyy="{iyy!r}" izz="{izz!r}" ixy="0" ixz="0" iyz="0"/></inertial>
<visual><geometry><mesh filename="box.{ext}"/></geometry></visual></link></robot>""")
        link = check_model(read_robot(path)).links[0]
        assert [w.code for w in link.warnings] == warnings and not link.notes


# ----------------------------------------------------------------------------- old Gazebo, blank lines


@pytest.mark.parametrize("name", ["model-1_2.sdf", "model.xml"])
def test_an_old_gazebo_file_is_named_as_such(capsys, tmp_path, name):
    path = tmp_path / name
    path.write_text('<?xml version="1.0" ?>\n<!-- a model -->\n<gazebo version="1.2">\n  <model name="m">\n'
                    '    <link name="a"/>\n  </model>\n</gazebo>\n')
    with pytest.raises(RobotFileError, match=r"old Gazebo 1\.2 format .*not SDF"):
        read_robot(path)
    code, _, err = _run(capsys, "check", path)
    assert code == 2 and "old Gazebo 1.2 format" in err and "model.config" in err


def test_blank_lines_before_the_xml_declaration_are_tolerated(capsys, tmp_path):
    path = tmp_path / "r.urdf"
    path.write_text('\n\n<?xml version="1.0"?>\n<robot name="r"><link name="a"><inertial><mass value="2"/>'
                    '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>\n')
    model = read_robot(path)
    assert model.link("a").line == 4 and "blank lines" in model.document.notes[0][1]
    code, out, _ = _run(capsys, "props", path, "--format", "json")
    assert code == 0 and json.loads(out)["mass"] == 2.0
    assert _run(capsys, "check", path)[0] == 0


def test_check_reads_a_xacro_file_with_its_arguments(capsys, workspace):
    """The check sees the expanded links: a negative arm mass given as an argument is named."""
    path = workspace / "mypkg" / "urdf" / "robot.urdf.xacro"
    code, out, _ = _run(capsys, "check", path, "--package-path", workspace, "--xacro-arg", "arm_mass:=2",
                        "--format", "json")
    assert code == 0 and [lk["name"] for lk in json.loads(out)["links"]] == ["base", "arm"]
    code, out, _ = _run(capsys, "check", path, "--package-path", workspace, "--xacro-arg", "arm_mass:=-2",
                        "--format", "json")
    errors = [(lk["name"], e["code"]) for lk in json.loads(out)["links"] for e in sev(lk, "error")]
    assert code == 1 and ("arm", "non_positive_mass") in errors
