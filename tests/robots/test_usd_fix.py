"""``inertia fix`` on OpenUSD stages and ``inertia check``'s OpenUSD findings.

A ``.usda`` layer is edited as text: only the MassAPI attribute lines (and an apiSchemas list)
differ; a binary layer is edited through Sdf; an override layer leaves the input untouched.
Truth for the written values: the source robot file, read back through usd-core and compared
body by body (``diff_robots``), and usd-core's own ``ComputeMassProperties``.
"""

from __future__ import annotations

import difflib

import pytest

from inertia.errors import InputError
from inertia.robots.diff import diff_robots
from inertia.robots.usd.check import check_stage
from inertia.robots.usd.mass import stage_mass_properties
from inertia.robots.usd.write import check_written, fix_stage
from tests.robots import usd_make as um
from tests.robots.usd_make import Gf, Sdf, Usd, UsdPhysics

URDF = """<robot name="r">
  <link name="base">
    <inertial><origin xyz="0 0 0.05"/><mass value="2.0"/>
      <inertia ixx="0.02" ixy="0" ixz="0" iyy="0.03" iyz="0" izz="0.04"/></inertial>
  </link>
  <link name="arm-1">
    <inertial><origin xyz="0.1 0 0" rpy="0.3 0 0"/><mass value="0.5"/>
      <inertia ixx="0.001" ixy="0.0001" ixz="0" iyy="0.002" iyz="0" izz="0.0025"/></inertial>
  </link>
  <joint name="j" type="revolute"><parent link="base"/><child link="arm-1"/><origin xyz="0 0 0.2"/>
    <axis xyz="0 0 1"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
</robot>
"""

# formatting a re-serialising writer would change: comments, blank lines, tabs, an attribute
# order usd-core would not choose, a body without PhysicsMassAPI, a converter-style renamed body
USDA = """#usda 1.0
(
    defaultPrim = "r"
    kilogramsPerUnit = 1
    metersPerUnit = 1
    upAxis = "Z"
)

def Xform "r"
{
    def Xform "base" (
        prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"]
    )
    {
        # hand-tuned: keep this comment
        float3 physics:diagonalInertia = (0.02, 0.03, 0.04)
        float physics:mass = 1.5   # wrong on purpose

        def Cube "col" (
            prepend apiSchemas = ["PhysicsCollisionAPI"]
        )
        {
\t\t\tdouble size = 0.1
        }

        def Xform "arm_1" (
            prepend apiSchemas = ["PhysicsRigidBodyAPI"]
        )
        {
            double3 xformOp:translate = (0, 0, 0.2)
            uniform token[] xformOpOrder = ["xformOp:translate"]

            def Sphere "s" (
                prepend apiSchemas = ["PhysicsCollisionAPI"]
            )
            {
                double radius = 0.05
            }
        }
    }
}
"""


@pytest.fixture
def files(tmp_path):
    (tmp_path / "robot.urdf").write_text(URDF)
    (tmp_path / "stage.usda").write_text(USDA)
    return tmp_path / "robot.urdf", tmp_path / "stage.usda"


def _changed_lines(before: str, after: str) -> list:
    return [line for line in difflib.ndiff(before.splitlines(), after.splitlines()) if line[:2] in ("- ", "+ ")]


def test_fix_from_a_urdf_edits_only_the_mass_api_lines_of_a_usda_and_then_agrees_with_it(files, tmp_path):
    urdf, stage = files
    assert len(diff_robots(urdf, stage).differ) == 2
    out = tmp_path / "fixed.usda"
    report = fix_stage(stage, out, source=urdf)
    assert sorted(report.changed) == ["arm_1", "base"]
    changed = _changed_lines(USDA, out.read_text())
    assert all("physics:" in line or "apiSchemas" in line for line in changed), changed
    assert "-         float physics:mass = 1.5   # wrong on purpose" in changed
    assert "+         float physics:mass = 2   # wrong on purpose" in changed        # the comment stays
    assert '+             prepend apiSchemas = ["PhysicsRigidBodyAPI", "PhysicsMassAPI"]' in changed
    assert stage.read_text() == USDA                                               # the input untouched
    assert not diff_robots(urdf, out).differ
    check_written(report, urdf)
    assert not report.remaining
    # usd-core's own reading of the written values: every attribute authored, no traversal
    s = Usd.Stage.Open(str(out))
    m, diag, com, q = UsdPhysics.RigidBodyAPI(s.GetPrimAtPath("/r/base/arm_1")).ComputeMassProperties(lambda p: None)
    assert m == pytest.approx(0.5, rel=1e-7)
    assert abs(q.GetLength() - 1) < 1e-6


def test_a_second_fix_writes_nothing(files, tmp_path):
    urdf, stage = files
    fix_stage(stage, source=urdf, in_place=True)
    text = stage.read_text()
    report = fix_stage(stage, source=urdf, in_place=True)
    assert report.identical and not report.changed and stage.read_text() == text


def test_values_go_to_the_layer_that_holds_them_and_the_root_layer_is_left_alone(files, tmp_path):
    urdf, _ = files
    root, physics = tmp_path / "robot.usda", tmp_path / "physics.usda"
    geo = Sdf.Layer.CreateNew(str(tmp_path / "geometry.usda"))
    geo.ImportFromString(USDA.replace('float physics:mass = 1.5   # wrong on purpose', ''))
    geo.Save()
    phys = Sdf.Layer.CreateNew(str(physics))
    phys.ImportFromString('#usda 1.0\nover "r"\n{\n    over "base"\n    {\n        float physics:mass = 1.5\n    }\n}\n')
    phys.Save()
    top = Sdf.Layer.CreateNew(str(root))
    top.subLayerPaths.append("physics.usda")
    top.subLayerPaths.append("geometry.usda")
    top.pseudoRoot.SetInfo("metersPerUnit", 1.0)
    top.pseudoRoot.SetInfo("kilogramsPerUnit", 1.0)
    top.Save()
    before = root.read_bytes()
    with pytest.raises(InputError, match="physics.usda, not in the file itself"):
        fix_stage(root, tmp_path / "copy.usda", source=urdf)
    report = fix_stage(root, source=urdf, in_place=True)
    assert root.read_bytes() == before
    assert "float physics:mass = 2" in physics.read_text()
    assert str(physics) in report.layers
    assert not diff_robots(urdf, root).differ


def test_a_binary_layer_is_edited_in_place_through_sdf(files, tmp_path):
    urdf, stage = files
    crate = tmp_path / "stage.usdc"
    Sdf.Layer.FindOrOpen(str(stage)).Export(str(crate))
    fix_stage(crate, source=urdf, in_place=True)
    assert crate.read_bytes()[:8] == b"PXR-USDC"
    assert not diff_robots(urdf, crate).differ


def test_an_override_layer_sublayers_the_input_and_carries_its_units(files, tmp_path):
    urdf, stage = files
    text = stage.read_text().replace("metersPerUnit = 1", "metersPerUnit = 0.5")
    stage.write_text(text.replace("double size = 0.1", "double size = 0.2").replace("(0, 0, 0.2)", "(0, 0, 0.4)"))
    before = stage.read_bytes()
    over = tmp_path / "over.usda"
    fix_stage(stage, source=urdf, layer=over)
    assert stage.read_bytes() == before
    layer = Sdf.Layer.FindOrOpen(str(over))
    assert list(layer.subLayerPaths) == ["stage.usda"] and layer.pseudoRoot.GetInfo("metersPerUnit") == 0.5
    assert not diff_robots(urdf, over).differ
    # a stage in half-metres: the written numbers are in stage units
    s = Usd.Stage.Open(str(over))
    assert UsdPhysics.MassAPI(s.GetPrimAtPath("/r/base")).GetCenterOfMassAttr().Get()[2] == pytest.approx(0.1)


def test_fix_without_a_source_normalises_principal_axes_and_repairs_a_non_physical_inertia(tmp_path):
    path = tmp_path / "bad.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b", mass=2.0, com=(0, 0, 0), diag=(0.1, 0.1, 0.5), axes=(2, 0, 0, 0))
    um.collider(stage, "/b/c", attrs={"size": 0.5})
    stage.GetRootLayer().Save()
    codes = {f.code for lk in check_stage(path).links for f in lk.errors}
    assert codes == {"non_unit_principal_axes", "triangle_inequality"}
    report = fix_stage(path, in_place=True)
    assert "principalAxes normalised (norm 2)" in report.changed["b"]
    assert not any(lk.errors for lk in check_stage(path).links)
    fixed = Usd.Stage.Open(str(path))
    q = UsdPhysics.MassAPI(fixed.GetPrimAtPath("/b")).GetPrincipalAxesAttr().Get()
    assert q == Gf.Quatf(1, 0, 0, 0)


def test_fix_needs_exactly_one_destination(files, tmp_path):
    urdf, stage = files
    with pytest.raises(InputError, match="exactly one of"):
        fix_stage(stage, source=urdf)
    with pytest.raises(InputError, match="is the input"):
        fix_stage(stage, stage, source=urdf)


def test_a_body_the_source_gives_no_mass_is_kept_and_said_why(tmp_path):
    (tmp_path / "r.urdf").write_text('<robot name="r"><link name="base"/><link name="arm"><inertial><mass value="1"/>'
                                     '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>'
                                     '<joint name="j" type="fixed"><parent link="base"/><child link="arm"/></joint>'
                                     '</robot>')
    path = tmp_path / "s.usda"
    stage = um.new_stage(path)
    um.body(stage, "/base")
    um.collider(stage, "/base/c", attrs={"size": 0.1})
    stage.GetRootLayer().Save()
    report = fix_stage(path, source=tmp_path / "r.urdf", in_place=True)
    assert "UsdPhysics cannot say \"massless\"" in report.skipped["base"]
    assert report.identical


# ---------------------------------------------------------------------------- check's findings

def _findings(path):
    rep = check_stage(path)
    return ({f.code for lk in rep.links for f in lk.errors}, {f.code for lk in rep.links for f in lk.warnings},
            {f.code for f in rep.warnings})   # the stage's own


def test_check_names_each_openusd_problem(tmp_path):
    path = tmp_path / "c.usda"
    stage = um.new_stage(path, units=False)
    um.body(stage, "/default")                                        # colliders at 1000 kg/m^3, nothing authored
    um.collider(stage, "/default/c", attrs={"size": 0.1})
    um.body(stage, "/empty")                                          # no mass, no collider
    um.body(stage, "/tiny", mass=0.01, diag=(1e-7, 1e-7, 1e-7), com=(0, 0, 0))   # below usd-core's 1e-5
    um.collider(stage, "/tiny/c", attrs={"size": 0.01})
    um.body(stage, "/massonly", mass=1.0)                             # mass without inertia, no collider
    um.body(stage, "/negative", mass=-1.0)
    um.collider(stage, "/negative/c", attrs={"size": 0.1})
    visual = stage.DefinePrim("/visual", "Mesh")
    um.mass_api(visual, mass=3.0)                                     # mass on a prim physics ignores
    loose = um.body(stage, "/loose")
    loose.CreateAttribute("physics:mass", Sdf.ValueTypeNames.Float).Set(2.0)   # no PhysicsMassAPI applied
    um.collider(stage, "/loose/c", attrs={"size": 0.1})
    stage.GetRootLayer().Save()
    errors, warnings, stage_warnings = _findings(path)
    assert errors == {"mass_fallback", "negative_mass"}
    assert warnings == {"default_density", "inertia_below_usd_tolerance", "mass_without_inertia",
                        "mass_api_not_applied"}
    assert stage_warnings == {"missing_units", "mass_on_non_physics_prim"}
    rep = check_stage(path)
    tiny = next(lk for lk in rep.links if lk.name == "tiny")
    assert ("physics:diagonalInertia [1.e-07 1.e-07 1.e-07] has norm 1.73e-07, at most 1e-05 (stage units): "
            "usd-core's ComputeMassProperties reads it as not set") in tiny.warnings[0].message


def test_check_warns_when_physx_would_simulate_a_concave_mesh_as_a_much_heavier_hull(tmp_path):
    path = tmp_path / "h.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b")
    # a thin L: its hull is about 1.8 times its volume
    um.extruded(stage, "/b/m", [(0, 0), (4, 0), (4, 1), (1, 1), (1, 4), (0, 4)], scale=0.1)
    stage.GetRootLayer().Save()
    _, warnings, _ = _findings(path)
    assert "hull_differs" in warnings
    exact, physx = stage_mass_properties(path), stage_mass_properties(path, physx=True)
    assert physx.links[0].mass / exact.links[0].mass == pytest.approx(11.5 / 7.0, rel=1e-12)   # hull area / L area (shoelace)


def test_a_usdz_package_is_read_and_fixed_through_an_override_layer_only(files, tmp_path):
    from pxr import UsdUtils

    urdf, stage = files
    package = tmp_path / "robot.usdz"
    assert UsdUtils.CreateNewUsdzPackage(Sdf.AssetPath(str(stage)), str(package))
    assert len(diff_robots(urdf, package).differ) == 2
    with pytest.raises(InputError, match="cannot be edited in place .* --layer OUT.usda"):
        fix_stage(package, source=urdf, in_place=True)
    over = tmp_path / "over.usda"
    fix_stage(package, source=urdf, layer=over)
    assert not diff_robots(urdf, over).differ
