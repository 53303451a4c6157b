"""MJCF ``<replicate>`` and ``<attach>`` read as MuJoCo's compiler builds them.

Truth: MuJoCo itself on the same files (every body's mass, world COM and world inertia, link
poses, subtree totals; at qpos0 and at random joint values, the joints named as MuJoCo names
them), through the helpers of test_whole.  The refusals (cycles, expansion bombs, missing
models) name the element and its file and line.
"""

from __future__ import annotations

import numpy as np
import pytest

from inertia.cli.main import main
from inertia.robots import read_robot, robot_mass_properties
from inertia.robots.xmlsafe import RobotFileError
from tests.robots.test_whole import INERTIA_RTOL, KINEMATICS_RTOL, _mujoco_model, _random_values, compare_with_mujoco

#: a cube of side 0.1 around (0.02, 0, 0.01), as an OBJ file
CUBE_OBJ = "\n".join(
    [f"v {0.02 + x * 0.05} {y * 0.05} {0.01 + z * 0.05}" for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)]
    + ["f 1 3 4 2", "f 5 6 8 7", "f 1 2 6 5", "f 3 7 8 4", "f 1 5 7 3", "f 2 4 8 6"]) + "\n"

#: a model's defaults, in a file it includes (relative to its own folder)
CHILD_DEFAULTS = """<mujoco>
  <default>
    <geom density="700" type="box" size="0.02 0.03 0.04"/>
    <default class="heavy"><geom density="3000"/></default>
  </default>
</mujoco>
"""

#: a model meant to be attached: its own defaults, degrees (MuJoCo's default unit), fixed-axis
#: euler sequence, mesh folder, mass bound and world geom
CHILD = """<mujoco model="kid">
  <compiler meshdir="parts" eulerseq="XYZ" boundmass="0.05"/>
  <include file="defaults.xml"/>
  <asset><mesh name="cube" file="cube.obj" scale="1 1 2"/></asset>
  <worldbody>
    <geom name="world_ball" type="sphere" size="0.05" pos="0 0 0.3"/>
    <body name="arm" pos="0.1 0 0" euler="0 90 30" childclass="heavy">
      <joint name="j1" axis="1 0 0"/>
      <geom/>
      <geom type="mesh" mesh="cube" euler="45 0 0"/>
      <body name="hand" pos="0 0.2 0"><joint name="j2"/><geom class="main" type="capsule" size="0.01 0.05"/>
        <body name="tip"/>
      </body>
    </body>
    <frame name="F" pos="0 0 1" euler="0 0 90" childclass="heavy">
      <body name="fb" pos="0.1 0 0"><joint name="jf" type="slide"/><geom/></body>
    </frame>
  </worldbody>
</mujoco>
"""

PARENT = """<mujoco model="parent">
  <compiler angle="radian"/>
  <default><geom density="9000"/></default>
  <asset><model name="kid" file="sub/child.xml"/></asset>
  <worldbody>
    <body name="base" pos="0 0 1" euler="0 0 0.5">
      <joint name="s" type="slide"/>
      <geom size="0.1"/>
      <frame pos="0.3 0 0" euler="0.2 0 0">
        <attach model="kid" body="arm" prefix="a_"/>
      </frame>
      <attach model="kid" prefix="w_"/>
      <attach model="kid" frame="F" prefix="f_"/>
    </body>
    <attach model="kid" body="hand" prefix="h_"/>
    <attach model="kid" body="fb" prefix="b_"/>
  </worldbody>
</mujoco>
"""


def _write(folder, files: dict):
    for name, text in files.items():
        path = folder / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text)
    return folder / next(iter(files))


def _agrees_with_mujoco(path, n_bodies: int, seeds=(0, 1)):
    """Our bodies equal MuJoCo's at qpos0 and at random values of MuJoCo's joints."""
    kin, body, total, n = compare_with_mujoco(path)
    assert n == n_bodies
    assert kin < KINEMATICS_RTOL and body < INERTIA_RTOL and total < INERTIA_RTOL
    for seed in seeds:
        values = _random_values(_mujoco_model(path), np.random.default_rng(seed))
        kin, body, total, _ = compare_with_mujoco(path, values)
        assert kin < KINEMATICS_RTOL and body < INERTIA_RTOL and total < INERTIA_RTOL
    return read_robot(path)


@pytest.fixture(params=["named", "by its model name"])
def attached(tmp_path, request):
    parent = PARENT if request.param == "named" else PARENT.replace('<model name="kid"', "<model")
    return _write(tmp_path, {"parent.xml": parent, "sub/child.xml": CHILD, "sub/defaults.xml": CHILD_DEFAULTS,
                             "sub/parts/cube.obj": CUBE_OBJ})


def test_attached_bodies_keep_their_models_meaning(attached):
    """Child defaults (from a file it includes) and classes (inherited from a frame around the
    attached body), degrees against the parent's radians, XYZ euler, meshdir under the
    child's folder, the child's boundmass (not the parent's density default), the world
    body's geoms joining the attaching body, a frame attached at its own pose."""
    model = _agrees_with_mujoco(attached, 12)
    assert [lk.name for lk in model.links] == ["base", "a_arm", "a_hand", "a_tip", "w_arm", "w_hand", "w_tip",
                                               "w_fb", "f_fb", "h_hand", "h_tip", "b_fb"]
    joints = {j.name for lk in model.links for j in lk.joints}
    assert {"s", "a_j1", "a_j2", "w_j1", "w_jf", "f_jf", "h_j2"} <= joints
    base = model.link("base")
    assert len(base.geometries) == 2  # its sphere and the child's world ball
    bounded = robot_mass_properties(model).link("a_tip")
    assert bounded.mass == pytest.approx(0.05) and bounded.source == "bound"


def test_messages_in_attached_models_point_into_their_file(attached):
    child = attached.parent / "sub" / "child.xml"
    child.write_text(CHILD.replace('<geom class="main"', '<geom class="nope"'))
    with pytest.raises(RobotFileError) as ei:
        read_robot(attached)
    assert f"{child}:11: <geom> uses undefined default class 'nope'" in str(ei.value)
    child.write_text(CHILD)
    model = read_robot(attached)
    assert model.document.where(model.link("a_hand").element) == f"{child}:11"


REPLICATED = """<mujoco>
  <compiler angle="degree" eulerseq="zyx"/>
  <default><default class="dense"><geom density="5000"/></default></default>
  <worldbody>
    <frame pos="0.5 0 0" euler="0 0 30">
      <replicate count="3" offset="0.1 0.2 0.3" euler="10 20 30" sep="_">
        <replicate count="2" offset="0 0 0.05" euler="0 0 90" childclass="dense">
          <body name="b" pos="0.05 0 0">
            <joint name="hb" axis="0 1 0"/>
            <geom type="box" size="0.01 0.02 0.03"/>
            <body name="c"><joint name="hc" type="slide"/><geom type="capsule" size="0.01 0.02"/></body>
          </body>
        </replicate>
      </replicate>
    </frame>
    <body name="arm" pos="0 1 0">
      <joint name="shoulder" axis="1 0 0"/>
      <geom type="box" size="0.1 0.01 0.01"/>
      <replicate count="12" offset="0.02 0 0" euler="0 15 0" sep="-">
        <geom type="sphere" size="0.01" pos="0 0.01 0"/>
        <body name="fin" pos="0 0.02 0">
          <joint name="bend" axis="0 0 1"/><geom type="box" size="0.005 0.01 0.002"/>
        </body>
      </replicate>
    </body>
  </worldbody>
</mujoco>
"""


def test_replicated_bodies_equal_mujocos(tmp_path):
    """Nested replicates with a multi-axis euler (MuJoCo's order of offset and rotation), a
    childclass, name suffixes (innermost first), and a replicate of geoms, joints and bodies
    inside a body with a joint."""
    path = _write(tmp_path, {"r.xml": REPLICATED})
    model = _agrees_with_mujoco(path, 6 * 2 + 1 + 12)
    names = [lk.name for lk in model.links]
    assert names[:4] == ["b0_0", "c0_0", "b1_0", "c1_0"] and names[-1] == "fin-11"
    assert len(model.link("arm").geometries) == 13 and [j.name for j in model.link("fin-07").joints] == ["bend-07"]


def test_attach_inside_replicate_and_self_attach(attached):
    path = attached.parent / "p.xml"
    path.write_text("""<mujoco>
  <asset><model name="kid" file="sub/child.xml"/></asset>
  <worldbody>
    <body name="a" pos="1 0 0"><joint name="ja"/><geom size="0.1"/>
      <body name="a2" pos="0 1 0"><geom size="0.05"/></body></body>
    <body name="b" pos="0 0 1"><attach body="a" prefix="s_"/></body>
    <replicate count="2" offset="0 0 3" euler="0 0 45"><attach model="kid" body="arm" prefix="r_"/></replicate>
  </worldbody>
</mujoco>
""")
    model = _agrees_with_mujoco(path, 11)
    assert [lk.name for lk in model.links][3:7] == ["s_a", "s_a2", "r_arm0", "r_hand0"]


def test_a_replicate_inside_an_attached_frame_uses_the_attached_models_units(tmp_path):
    """A frame inside a body of the child (its geoms join the attaching body), holding a
    replicate whose euler is in the child's degrees and zyx sequence, under a parent in radians."""
    child = """<mujoco model="c3">
  <compiler eulerseq="zyx"/>
  <worldbody>
    <body name="holder" pos="0 0 1" euler="0 0 20">
      <geom size="0.01"/>
      <frame name="G" pos="0.1 0.2 0" euler="30 0 10">
        <geom type="box" size="0.1 0.02 0.03" pos="0.1 0 0"/>
        <replicate count="4" euler="0 0 30" offset="0.1 0 0">
          <body name="r" pos="0 0.05 0"><joint name="rj"/><geom type="capsule" size="0.01 0.04"/></body>
        </replicate>
      </frame>
    </body>
  </worldbody>
</mujoco>
"""
    parent = """<mujoco>
  <compiler angle="radian"/>
  <asset><model name="c" file="c3.xml"/></asset>
  <worldbody>
    <body name="top" pos="0 0 1" euler="0.1 0.2 0.3">
      <joint name="tj"/>
      <geom size="0.02"/>
      <attach model="c" frame="G" prefix="g_"/>
      <frame euler="0.5 0 0"><attach model="c" body="holder" prefix="h_"/></frame>
    </body>
  </worldbody>
</mujoco>
"""
    model = _agrees_with_mujoco(_write(tmp_path, {"p.xml": parent, "c3.xml": child}), 10)
    assert len(model.link("top").geometries) == 2 and model.link("g_r3").joints[0].name == "g_rj3"


@pytest.mark.parametrize("body, message", [
    ('<body name="a"><geom size="0.1"/><body name="a2"><attach body="a" prefix="s_"/></body></body>',
     "body 'a' (FILE:3) holds this <attach>"),
    ('<body name="b"><attach body="a" prefix="s_"/></body><body name="a"><geom size="0.1"/></body>',
     "body 'a' (FILE:3) comes after the <attach>"),
    ('<body name="b"><attach body="nope" prefix="s_"/></body>', "no body named 'nope'"),
    ('<body name="b"><attach body="b" frame="f" prefix="s_"/></body>', "give body or frame, not both"),
    ('<body name="b"><attach model="m" body="b"/></body>', "needs a prefix"),
    ('<body name="b"><attach model="m" body="b" prefix="x"/></body>', "model 'm' is not a model asset"),
    ('<replicate count="0"><body/></replicate>', "count='0' must be positive"),
    ('<replicate count="two"><body/></replicate>', "count='two' must be a positive whole number"),
    ('<body><replicate count="2"><frame><joint/></frame></replicate></body>',
     "<joint> inside a <replicate> must be inside a body there"),
])
def test_attach_and_replicate_mistakes_are_named(tmp_path, capsys, body, message):
    path = tmp_path / "m.xml"
    path.write_text(f"<mujoco>\n  <worldbody>\n    {body}\n  </worldbody>\n</mujoco>\n")
    with pytest.raises(RobotFileError) as ei:
        read_robot(path)
    assert f"{path}:3: <" in str(ei.value) and message.replace("FILE", str(path)) in str(ei.value)
    assert main(["check", str(path)]) == 2


def test_an_attach_cycle_through_two_models_is_refused(tmp_path):
    a = _write(tmp_path, {
        "a.xml": '<mujoco>\n  <asset><model name="b" file="b.xml"/></asset>\n  <worldbody>\n'
                 '    <body name="x"><attach model="b" body="y" prefix="b_"/></body>\n  </worldbody>\n</mujoco>\n',
        "b.xml": '<mujoco>\n  <asset><model name="a" file="a.xml"/></asset>\n  <worldbody>\n'
                 '    <body name="y"><attach model="a" body="x" prefix="a_"/></body>\n  </worldbody>\n</mujoco>\n'})
    with pytest.raises(RobotFileError) as ei:
        read_robot(a)
    assert f"{a}:4: <attach>: attaching body 'y' of {tmp_path / 'b.xml'} here puts it inside itself" in str(ei.value)
    assert f"attached at {a}:4: <attach>: an attach cycle" in str(ei.value)


def _refusal(path, text: str) -> str:
    path.write_text(text)
    with pytest.raises(RobotFileError) as ei:
        read_robot(path)
    return str(ei.value)


def test_a_replicate_bomb_is_refused_before_it_is_expanded(tmp_path):
    path = tmp_path / "bomb.xml"
    message = _refusal(path, '<mujoco>\n  <worldbody>\n    <replicate count="1000">\n      <replicate count="1000">\n'
                             '        <replicate count="1000"><body><geom size="1"/></body></replicate>\n'
                             '      </replicate>\n    </replicate>\n  </worldbody>\n</mujoco>\n')
    assert f"{path}:3: <replicate> (count=1000): the expanded model would hold more than" in message


def test_an_attach_bomb_is_refused(tmp_path, monkeypatch):
    from inertia.robots import mjcf

    monkeypatch.setattr(mjcf, "MAX_ELEMENTS", 200)
    _write(tmp_path, {"kid.xml": "<mujoco><worldbody><body name='k'>" + "<geom size='1'/>" * 60
                      + "</body></worldbody></mujoco>"})
    path = tmp_path / "m.xml"
    message = _refusal(path, '<mujoco>\n  <asset><model name="kid" file="kid.xml"/></asset>\n  <worldbody>\n'
                             '    <replicate count="10">\n      <attach model="kid" body="k" prefix="k"/>\n'
                             '    </replicate>\n  </worldbody>\n</mujoco>\n')
    assert f"{path}:5: <attach> (body 'k'): the expanded model would hold more than 200 elements" in message


def test_a_missing_model_file_is_named(tmp_path):
    path = tmp_path / "m.xml"
    message = _refusal(path, '<mujoco>\n  <asset><model name="kid" file="gone.xml"/></asset>\n  <worldbody>\n'
                             '    <attach model="kid" prefix="k"/>\n  </worldbody>\n</mujoco>\n')
    assert f"{path}:2: <model file='gone.xml'>: model file not found" in message


def test_fix_of_a_model_with_attachments_refuses_changes_in_their_files(attached, tmp_path, capsys):
    """Nothing to fix: the copy, exit 0 (issue 33, case 10); a change in the attached file: refused."""
    out = tmp_path / "fixed.xml"
    assert main(["fix", str(attached), "-o", str(out)]) == 0
    assert out.read_bytes() == attached.read_bytes() and "nothing to fix" in capsys.readouterr().err
    out.unlink()
    child = attached.parent / "sub" / "child.xml"
    child.write_text(CHILD.replace('<body name="tip"/>', '<body name="tip"><inertial pos="0 0 0" mass="1" '
                                   'diaginertia="1 1 3"/></body>'))
    assert main(["fix", str(attached), "-o", str(out)]) != 0
    assert not out.exists() and "in files it includes or attaches: 'a_tip'" in capsys.readouterr().err
