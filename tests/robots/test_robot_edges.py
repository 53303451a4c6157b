"""Bad robot files: every one is a named error (file, line, element), never a crash or a silent number.

Each case writes a minimal file to ``tmp_path`` and asserts the error's type, its stable
``code`` and that the message says where the problem is.
"""

from __future__ import annotations

import math

import pytest

from inertia.cli.main import main
from inertia.errors import InertiaError
from inertia.robots import check_model, read_robot
from inertia.robots.geometry import link_geometry_properties
from inertia.robots.xmlsafe import RobotFileError


def _mjcf(body_xml: str, head: str = "") -> str:
    return f'<mujoco>\n{head}  <worldbody>\n{body_xml}  </worldbody>\n</mujoco>\n'


def _refused(path, *fragments, named=None):
    """Read (and check) ``path``; the RobotFileError it raises, after checking its message
    (which names ``named``, by default ``path``: the file where the problem is)."""
    with pytest.raises(RobotFileError) as info:
        check_model(read_robot(path))
    err = info.value
    assert err.code == "robot_file"
    msg = str(err)
    assert str(named or path) in msg, msg
    for f in fragments:
        assert f in msg, f"{f!r} not in {msg!r}"
    return err


# ----------------------------------------------------------------------------- the cases, one file each

CASES = {
    # 1. a URDF <geometry> with only a comment in it: no shape
    "comment_geometry.urdf": (
        '<robot name="r">\n  <link name="arm">\n    <visual>\n      <geometry><!-- todo --></geometry>\n'
        '    </visual>\n  </link>\n</robot>\n', (":4", "'arm'", "<geometry>")),
    # 2. an MJCF geom given by fromto without its radius
    "fromto.xml": (_mjcf('    <body name="b">\n      <geom type="capsule" fromto="0 0 0 0 0 1"/>\n'
                         '    </body>\n'), (":4", "'b'", "size")),
    # 3. an unknown encoding in the XML declaration
    "encoding.urdf": ('<?xml version="1.0" encoding="utfa"?>\n<robot name="r"/>\n', (":1", "utfa")),
    # 7. the angle unit misspelt
    "angle.xml": (_mjcf('    <body name="b"><inertial mass="1" diaginertia="1 1 1" euler="90 0 0"/></body>\n',
                        '  <compiler angle="degrees"/>\n'), (":2", "angle", "'degrees'", "degree", "radian")),
    # 8. an SDF mass written empty (read as the 1 kg default before)
    "empty_mass.sdf": (
        '<sdf version="1.7">\n<model name="m">\n  <link name="l">\n    <inertial>\n      <mass></mass>\n'
        '    </inertial>\n  </link>\n</model>\n</sdf>\n', (":5", "mass", "'l'")),
    "empty_ixx.sdf": (
        '<sdf version="1.7">\n<model name="m">\n  <link name="l">\n    <inertial>\n      <mass>2</mass>\n'
        '      <inertia>\n        <ixx>  </ixx>\n      </inertia>\n    </inertial>\n  </link>\n</model>\n</sdf>\n',
        (":7", "ixx", "'l'")),
    "text_mass.sdf": (
        '<sdf version="1.7">\n<model name="m">\n  <link name="l">\n    <inertial>\n      <mass>heavy</mass>\n'
        '    </inertial>\n  </link>\n</model>\n</sdf>\n', (":5", "mass", "'heavy'")),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_bad_file_is_a_named_error(tmp_path, name):
    text, fragments = CASES[name]
    path = tmp_path / name
    path.write_text(text)
    _refused(path, *fragments)


def test_urdf_geometry_without_a_shape_is_refused_like_urdfdom(tmp_path):
    path = tmp_path / "empty_geometry.urdf"
    path.write_text('<robot name="r">\n  <link name="arm">\n    <collision>\n      <geometry/>\n'
                    '    </collision>\n  </link>\n</robot>\n')
    _refused(path, ":4", "'arm'")


def test_mesh_file_name_too_long_for_the_file_system(tmp_path):
    long_name = "m" * 300 + ".stl"
    path = tmp_path / "long.urdf"
    path.write_text(f'<robot name="r">\n  <link name="arm">\n    <visual>\n      <geometry>\n'
                    f'        <mesh filename="{long_name}"/>\n      </geometry>\n    </visual>\n  </link>\n</robot>\n')
    _refused(path, ":5", "'arm'", long_name[:20])
    mj = tmp_path / "long.xml"
    mj.write_text(_mjcf('    <body name="b"><geom type="mesh" mesh="m"/></body>\n',
                        f'  <asset>\n    <mesh name="m" file="{long_name}"/>\n  </asset>\n'))
    _refused(mj, ":3", long_name[:20])


# ----------------------------------------------------------------------------- 5. deep nesting


def test_thousands_of_nested_bodies_are_read_without_recursion(tmp_path, capsys):
    n, r, rho = 3000, 0.1, 500.0
    # odd bodies declare 1 kg; even ones take their mass from a sphere geom (4/3 pi r^3 rho)
    parts = []
    for i in range(n):
        inside = ('<inertial mass="1" diaginertia="0.1 0.1 0.1"/>' if i % 2
                  else f'<geom type="sphere" size="{r}" density="{rho}"/>')
        parts.append(f'<body name="b{i}" pos="0 0 0.1">{inside}')
    path = tmp_path / "deep.xml"
    path.write_text(_mjcf("".join(parts) + "</body>" * n + "\n"))
    model = read_robot(path)
    assert [lk.name for lk in model.links] == [f"b{i}" for i in range(n)]
    total = 0.0
    for lk in model.links:
        if lk.inertial is not None:
            total += lk.inertial.mass
        else:
            total += link_geometry_properties(lk)[0].mass
    expected = n // 2 * 1.0 + (n - n // 2) * 4 / 3 * math.pi * r**3 * rho
    assert total == pytest.approx(expected, rel=1e-12)
    assert check_model(model).n_errors == 0
    out = tmp_path / "fixed.xml"
    assert main(["fix", str(path), "-o", str(out), "--nearest-valid"]) == 0
    assert len(read_robot(out).links) == n
    capsys.readouterr()


def test_deeply_nested_defaults_are_read(tmp_path):
    n = 2000
    defaults = "".join(f'<default class="c{i}">' for i in range(n)) + '<geom size="0.2"/>' + "</default>" * n
    path = tmp_path / "defaults.xml"
    path.write_text(_mjcf(f'    <body name="b"><geom class="c{n - 1}" type="sphere" mass="2"/></body>\n',
                          f"  <default>{defaults}</default>\n"))
    (geom,) = read_robot(path).links[0].geometries
    assert geom.params["radius"] == 0.2


# ----------------------------------------------------------------------------- 6. zero-norm orientations


@pytest.mark.parametrize("attr, value", [("quat", "0 0 0 0"), ("axisangle", "0 0 0 1"),
                                         ("xyaxes", "1 0 0 2 0 0"), ("xyaxes", "1 1 0 -3 -3 0"),
                                         ("xyaxes", "0 0 0 0 1 0"), ("zaxis", "0 0 0")])
@pytest.mark.parametrize("element", ["body", "geom", "inertial"])
def test_zero_norm_orientation_is_refused(tmp_path, attr, value, element):
    o = f'{attr}="{value}"'
    body = {"body": f'    <body name="b" {o}>\n      <inertial mass="1" diaginertia="1 1 1"/>\n    </body>\n',
            "geom": f'    <body name="b">\n      <geom type="sphere" size="0.1" {o}/>\n    </body>\n',
            "inertial": f'    <body name="b">\n      <inertial mass="1" diaginertia="1 1 1" {o}/>\n    </body>\n'}
    path = tmp_path / "zero.xml"
    path.write_text(_mjcf(body[element]))
    line = ":3" if element == "body" else ":4"
    _refused(path, line, f"<{element}>", attr, "'b'")


def test_zero_length_fromto_is_refused(tmp_path):
    path = tmp_path / "fromto0.xml"
    path.write_text(_mjcf('    <body name="b">\n      <geom type="capsule" size="0.1" fromto="1 2 3 1 2 3"/>\n'
                          '    </body>\n'))
    _refused(path, ":4", "fromto", "'b'")


# ----------------------------------------------------------------------------- 9. include fan-out


def test_include_of_the_same_file_twice_is_refused(tmp_path):
    depth = 24
    for k in range(depth):
        inner = (f'  <include file="f{k + 1}.xml"/>\n' * 2) if k + 1 < depth else \
            '  <worldbody><body name="leaf"><inertial mass="1" diaginertia="1 1 1"/></body></worldbody>\n'
        (tmp_path / f"f{k}.xml").write_text(f"<mujoco>\n{inner}</mujoco>\n")
    # expanded depth first, in document order (as MuJoCo does): f22 includes f23 a second time
    _refused(tmp_path / "f0.xml", f"{tmp_path / 'f22.xml'}:3", f"{tmp_path / 'f23.xml'} was already included at "
             f"{tmp_path / 'f22.xml'}:2", "only once", named=tmp_path / "f22.xml")
    (tmp_path / "g.xml").write_text('<mujoco>\n  <include file="f23.xml"/>\n  <worldbody/>\n'
                                    '  <include file="f23.xml"/>\n</mujoco>\n')
    _refused(tmp_path / "g.xml", ":4", "f23.xml", ":2")


def test_include_cycle_is_refused(tmp_path):
    (tmp_path / "a.xml").write_text('<mujoco>\n  <include file="b.xml"/>\n</mujoco>\n')
    (tmp_path / "b.xml").write_text('<mujoco>\n  <include file="a.xml"/>\n</mujoco>\n')
    _refused(tmp_path / "a.xml", f"{tmp_path / 'b.xml'}:2", f"{tmp_path / 'a.xml'} is the file being read",
             named=tmp_path / "b.xml")


def test_expanded_model_size_is_bounded(tmp_path, monkeypatch):
    from inertia.robots import mjcf

    monkeypatch.setattr(mjcf, "MAX_ELEMENTS", 50)
    (tmp_path / "part.xml").write_text("<mujoco><worldbody>" + "<body/>" * 40 + "</worldbody></mujoco>")
    (tmp_path / "part2.xml").write_text("<mujoco><worldbody>" + "<body/>" * 40 + "</worldbody></mujoco>")
    path = tmp_path / "main.xml"
    path.write_text('<mujoco>\n  <include file="part.xml"/>\n  <include file="part2.xml"/>\n</mujoco>\n')
    _refused(path, ":3", "part2.xml", "more than 50 elements")


def test_distinct_nested_includes_still_expand(tmp_path):
    (tmp_path / "c.xml").write_text('<mujoco><worldbody><body name="c"/></worldbody></mujoco>')
    (tmp_path / "b.xml").write_text('<mujoco><include file="c.xml"/>'
                                    '<worldbody><body name="b"/></worldbody></mujoco>')
    path = tmp_path / "a.xml"
    path.write_text('<mujoco><include file="b.xml"/><worldbody><body name="a"/></worldbody></mujoco>')
    model = read_robot(path)
    assert [lk.name for lk in model.links] == ["c", "b", "a"]  # every <worldbody>, in order
    assert [p.name for p in model.document.included] == ["b.xml", "c.xml"]


# ----------------------------------------------------------------------------- the command line


def _all_files(tmp_path):
    files = []
    for name, (text, _) in CASES.items():
        (tmp_path / name).write_text(text)
        files.append(tmp_path / name)
    zero = tmp_path / "zero.xml"
    zero.write_text(_mjcf('    <body name="b" quat="0 0 0 0"/>\n'))
    long = tmp_path / "long.urdf"
    long.write_text(f'<robot name="r"><link name="a"><visual><geometry><mesh filename="{"m" * 300}.stl"/>'
                    '</geometry></visual></link></robot>')
    (tmp_path / "g.xml").write_text('<mujoco><include file="h.xml"/><include file="h.xml"/></mujoco>')
    (tmp_path / "h.xml").write_text("<mujoco/>")
    return files + [zero, long, tmp_path / "g.xml"]


@pytest.mark.parametrize("command", ["check", "fix"])
@pytest.mark.parametrize("case", range(len(CASES) + 3))
def test_cli_reports_each_bad_file_as_an_error_not_a_crash(tmp_path, capsys, command, case):
    path = _all_files(tmp_path)[case]
    argv = [command, str(path)] + (["-o", str(tmp_path / "out.xml")] if command == "fix" else [])
    code = main(argv)
    err = capsys.readouterr().err
    assert code in (1, 2), (path.name, code, err)
    assert "Traceback" not in err and "internal error" not in err, err
    assert str(path) in err, err


def test_robot_file_error_is_an_inertia_error():
    assert issubclass(RobotFileError, InertiaError)


@pytest.mark.parametrize("encoding", ["utfa", "rot13", "idna", "utf-7", "undefined"])
def test_unusable_declared_encoding_is_named(tmp_path, encoding):
    path = tmp_path / "enc.sdf"
    path.write_text(f'<?xml version="1.0" encoding="{encoding}"?>\n<sdf version="1.7"/>\n')
    _refused(path, ":1", repr(encoding))


def test_urdf_inertia_without_all_six_attributes_is_refused(tmp_path):
    path = tmp_path / "five.urdf"
    path.write_text('<robot name="r">\n  <link name="a">\n    <inertial>\n      <mass value="1"/>\n'
                    '      <inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0"/>\n    </inertial>\n  </link>\n</robot>\n')
    _refused(path, ":5", "iyz")


def test_sdf_absent_fields_keep_sdf_defaults(tmp_path):
    path = tmp_path / "defaults.sdf"
    path.write_text('<sdf version="1.7"><model name="m"><link name="l"><inertial><inertia><ixy>0.5</ixy>'
                    '</inertia></inertial></link></model></sdf>')
    inertial = read_robot(path).links[0].inertial
    assert inertial.mass == 1.0
    assert inertial.inertia_com_inertial.tolist() == [[1.0, 0.5, 0.0], [0.5, 1.0, 0.0], [0.0, 0.0, 1.0]]


def test_a_second_top_level_default_adds_to_the_first(tmp_path):
    (tmp_path / "robot.xml").write_text('<mujoco><default><geom type="box" size="0.1 0.2 0.3"/></default>'
                                        '<worldbody><body name="b"><geom mass="1"/></body></worldbody></mujoco>')
    path = tmp_path / "scene.xml"
    path.write_text('<mujoco><include file="robot.xml"/><default><default class="x"><geom rgba="1 0 0 1"/>'
                    '</default></default></mujoco>')
    (geom,) = read_robot(path).links[0].geometries
    assert geom.kind == "box" and geom.params["size"] == pytest.approx([0.2, 0.4, 0.6])


@pytest.mark.parametrize("fmt, text", [
    ("urdf", '<robot name="r"><link name="a">\n<visual><origin xyz="0 0 0"/></visual></link></robot>\n'),
    ("sdf", '<sdf version="1.7"><model name="m"><link name="a">\n<collision name="c"></collision>'
            '</link></model></sdf>\n'),
])
def test_a_shape_element_without_geometry_is_refused_not_skipped(tmp_path, fmt, text):
    # urdfdom and the SDF specification require <geometry> in <visual> and <collision>
    path = tmp_path / f"m.{fmt}"
    path.write_text(text)
    with pytest.raises(RobotFileError, match=r"m\.\w+:2: link 'a': <(visual|collision)> has no <geometry>"):
        read_robot(path)


def test_a_massless_body_on_an_unnamed_free_joint_is_named_by_its_kind(tmp_path):
    # MuJoCo refuses it ("mass and inertia of moving bodies must be larger than mjMINVAL"): inertia
    # from a mesh geom whose file is missing leaves the body without mass
    f = tmp_path / "m.xml"
    f.write_text('<mujoco><asset><mesh name="p" file="missing.obj"/></asset><worldbody><body name="b">'
                 '<freejoint/><geom type="mesh" mesh="p"/></body></worldbody></mujoco>')
    report = check_model(read_robot(f))
    (error,) = [e for e in report.links[0].errors if e.code == "massless_moving_link"]
    assert "an unnamed free joint" in error.message and "None" not in error.message
