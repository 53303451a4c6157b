"""MJCF ``<frame>`` is read as MuJoCo reads it; what this reader does not expand
(``<composite>``, ``<flexcomp>``, SDF ``<include>``), and an ``<attach>`` of a model that is not
there, is an error naming the element and line, never a silent "0 links, 0 errors".

Truth: MuJoCo's own compiler (body mass, COM and inertia) on the same file.
"""

from __future__ import annotations

import numpy as np
import pytest

from inertia._core.rotations import quat_to_matrix
from inertia.cli.main import main
from inertia.robots import read_robot
from inertia.robots.geometry import link_geometry_properties
from inertia.robots.xmlsafe import RobotFileError

FRAMES = """<mujoco>
  <compiler angle="radian"/>
  <default><default class="heavy"><geom density="7800"/></default></default>
  <worldbody>
    <frame pos="1 0 0" euler="0 0 0.3">
      <body name="a">
        <geom type="sphere" size="0.05"/>
        <frame pos="0 0.1 0.5" euler="0.4 -0.2 0.7" childclass="heavy">
          <geom type="box" size="0.1 0.2 0.3" pos="0.05 0 0"/>
          <frame quat="0.9 0.1 0.3 0.2"><geom type="capsule" size="0.02 0.1" pos="0 0 0.2"/></frame>
        </frame>
        <body name="b" pos="0 0 1">
          <frame euler="0.5 0 0"><geom type="cylinder" size="0.03 0.2" pos="0 0.1 0"/></frame>
        </body>
      </body>
    </frame>
  </worldbody>
</mujoco>
"""


def test_geoms_in_nested_frames_give_mujocos_body_inertia(tmp_path):
    mujoco = pytest.importorskip("mujoco")
    path = tmp_path / "frames.xml"
    path.write_text(FRAMES)
    m = mujoco.MjModel.from_xml_path(str(path))
    model = read_robot(path)
    assert [lk.name for lk in model.links] == ["a", "b"]
    for i, name in ((1, "a"), (2, "b")):
        ours, _, problems = link_geometry_properties(model.link(name))
        assert not problems
        R = quat_to_matrix(m.body_iquat[i])
        I_mj = R @ np.diag(m.body_inertia[i]) @ R.T
        assert abs(m.body_mass[i] / ours.mass - 1) < 1e-9
        assert np.abs(m.body_ipos[i] - ours.com).max() < 1e-9
        assert np.abs(I_mj - ours.inertia_com).max() < 1e-9 * np.abs(I_mj).max()


@pytest.mark.parametrize("element", [
    '<attach model="other" body="b" prefix="x_"/>',
    '<composite type="particle" count="2 2 2" spacing="0.1"><geom size="0.01"/></composite>',
    '<flexcomp name="f" type="grid" count="2 2 1" spacing="0.1 0.1 0.1"/>',
])
@pytest.mark.parametrize("inside", ["worldbody", "body", "frame"])
def test_elements_not_expanded_are_errors_naming_them(tmp_path, capsys, element, inside):
    tag = element[1:].split(" ")[0]
    wrap = {"worldbody": "{}", "body": '<body name="p">{}</body>', "frame": '<frame pos="1 0 0">{}</frame>'}
    path = tmp_path / "m.xml"
    path.write_text("<mujoco>\n  <worldbody>\n    " + wrap[inside].format(element) + "\n  </worldbody>\n</mujoco>\n")
    with pytest.raises(RobotFileError) as ei:
        read_robot(path)
    assert f"m.xml:3: <{tag}>" in str(ei.value)
    assert main(["check", str(path)]) == 2
    assert "0 errors" not in capsys.readouterr().out


def test_an_sdf_include_is_an_error_not_an_empty_model(tmp_path, capsys):
    path = tmp_path / "w.sdf"
    path.write_text('<?xml version="1.0"?>\n<sdf version="1.7">\n  <world name="w">\n'
                    '    <include><uri>model://robot</uri></include>\n  </world>\n</sdf>\n')
    with pytest.raises(RobotFileError) as ei:
        read_robot(path)
    assert "w.sdf:4: <include>" in str(ei.value) and "model://robot" in str(ei.value)
    assert main(["check", str(path)]) == 2
