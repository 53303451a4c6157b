"""OpenUSD stages: each rigid body's mass properties follow UsdPhysics' precedence rules as
usd-core's ``ComputeMassProperties`` applies them, and each collider is integrated exactly.

Two independent truths: usd-core's own ``UsdPhysicsRigidBodyAPI.ComputeMassProperties`` (fed
with our per-collider values, so the precedence logic is what is compared) on OpenUSD's test
cases and on generated stages; closed forms and our mesh path for the colliders themselves.
usd-core computes in float32, so it is matched to its rounding (a few 1e-7) in general, and to
1e-9 on stages whose every number and intermediate value is exact in float32.
"""

from __future__ import annotations

import numpy as np
import pytest

from inertia import mesh_properties
from inertia.massprops import primitives
from inertia.robots.usd.mass import (
    DEFAULT_DENSITY,
    UNSET_TOLERANCE,
    body_mass,
    collider_solid,
    jacobi_principal,
    stage_mass_properties,
)
from tests.robots import usd_make as um
from tests.robots.usd_make import Gf, UsdGeom, UsdPhysics

#: usd-core's float32 arithmetic: a sum of a few parts, parallel-axis terms, a Jacobi diagonalisation
FLOAT32_RTOL = 2e-6


def _close(ours, theirs, rtol):
    """Mass, COM and tensor of our BodyMass against usd-core's ``(mass, com, I)``, relative to each
    quantity's own scale (the COM to the body's size)."""
    m, c, I = theirs[:3]
    assert abs(ours.mass - m) <= rtol * abs(m)
    size = max(np.abs(ours.com_B).max(), np.sqrt(np.abs(ours.I_B).max() / ours.mass), 1e-300)
    assert np.abs(ours.com_B - c).max() <= rtol * size, (ours.com_B, c)
    assert np.abs(ours.I_B - I).max() <= rtol * np.abs(I).max(), (ours.I_B, I)


@pytest.mark.parametrize("name", list(um.SCENARIOS))
def test_openusd_own_cases_equal_compute_mass_properties_and_their_expected_values(tmp_path, name):
    path, body_path = um.build(tmp_path, name)
    stage = um.read(path)
    i = [b.path for b in stage.bodies].index(body_path)
    ours, theirs = um.oracle(stage, i)
    _close(ours, theirs, FLOAT32_RTOL)
    _, _, mass, com, diag, axes = um.SCENARIOS[name]
    # the expectations of OpenUSD's test (its tolerance 0.01), in stage units
    assert ours.mass == pytest.approx(mass, abs=0.01)
    if com is not None:
        np.testing.assert_allclose(ours.com_B, com, atol=0.01)
    if diag is not None:
        np.testing.assert_allclose(np.linalg.eigvalsh(ours.I_B), diag, atol=0.01)
    if axes is not None:
        np.testing.assert_allclose(ours.principal_axes, axes, atol=0.01)


def _exact_stage(tmp_path, rule):
    """A stage whose every number is exact in float32, exercising one precedence rule: edges 3
    and 6 (second moments V a^2 / 12 exact), masses and offsets chosen so that the COM and every
    scale factor are exact too."""
    path = tmp_path / f"{rule}.usda"
    stage = um.new_stage(path, mpu=0.5 if rule == "units" else 1.0, kpu=2.0 if rule == "units" else 1.0)
    body_kw = {"mass": {"mass": 486000.0}, "body_density": {"density": 512.0}, "body_com": {"com": (0, 0, 3)},
               "body_inertia": {"diag": (64.0, 128.0, 160.0), "axes": (1, 0, 0, 0)},
               "collider_density": {"density": 512.0}, "material": {"density": 64.0},
               "all_authored": {"mass": 8.0, "com": (1, 2, 3), "diag": (4, 5, 6), "axes": (1, 0, 0, 0)}}
    um.body(stage, "/b", **body_kw.get(rule, {}))
    cube_mass = {"collider_density": {"density": 4096.0}, "collider_mass": {"mass": 216000.0},
                 "collider_com": {"com": (0, 0, 9)}, "collider_inertia": {"diag": (32.0, 32.0, 48.0)}}.get(rule)
    cube = um.collider(stage, "/b/c0", attrs={"size": 3.0}, mass=cube_mass, translate=(0, 0, -3))
    um.collider(stage, "/b/c1", attrs={"size": 6.0}, translate=(0, 0, 6))
    if rule == "material":
        um.material(stage, "/m", 128.0, cube)
    stage.GetRootLayer().Save()
    return path


EXACT_RULES = ["default", "mass", "body_density", "collider_density", "collider_mass", "material", "body_com",
               "collider_com", "body_inertia", "collider_inertia", "all_authored", "units"]


@pytest.mark.parametrize("rule", EXACT_RULES)
def test_every_precedence_rule_equals_compute_mass_properties_to_1e9_where_float32_is_exact(tmp_path, rule):
    stage = um.read(_exact_stage(tmp_path, rule))
    ours, theirs = um.oracle(stage, 0)
    _close(ours, theirs, 1e-9)


def test_the_precedence_rules_give_the_numbers_the_schema_text_states(tmp_path):
    # truth: hand arithmetic on the rules of overview.dox (3 m and 6 m cubes, 27 and 216 m^3)
    mass = {rule: body_mass(um.read(_exact_stage(tmp_path, rule)), 0).mass for rule in EXACT_RULES}
    assert mass["default"] == DEFAULT_DENSITY * (27 + 216)
    assert mass["mass"] == 486000.0                               # a body's mass beats everything below
    assert mass["body_density"] == 512.0 * 243                    # density times volume
    assert mass["collider_density"] == 4096.0 * 27 + 512.0 * 216  # a child's density beats its parent's
    assert mass["collider_mass"] == 216000.0 + 1000.0 * 216       # mass beats density
    assert mass["material"] == 64.0 * 243                         # a MassAPI density beats a material's
    assert mass["units"] == DEFAULT_DENSITY * 0.5 ** 3 / 2.0 * 243  # 1000 kg/m^3 in stage units


def _general_stage(tmp_path, seed):
    """Every shape, scaled, rotated and nested in xforms, with mass opinions drawn at random."""
    rng = np.random.default_rng(seed)
    path = tmp_path / f"general{seed}.usda"
    stage = um.new_stage(path, mpu=float(rng.choice([1.0, 0.01, 0.3])), kpu=float(rng.choice([1.0, 0.001, 3.0])))
    opts = [None, {"density": 700.0}, {"mass": 3.0}, {"com": tuple(rng.normal(size=3))},
            {"density": 2000.0, "com": (0.1, 0, 0)}]
    body_opts = [{}, {"density": 300.0}, {"mass": 5.0}, {"com": (0.2, 0.1, 0)}, {"mass": 2.0, "com": (0, 0, 0.3)}]
    um.body(stage, "/b", translate=tuple(rng.normal(size=3)), rotate_xyz=tuple(rng.uniform(-90, 90, 3)),
            **body_opts[seed % len(body_opts)])
    UsdGeom.Xform.Define(stage, "/b/mid")
    um.xform(stage.GetPrimAtPath("/b/mid"), translate=tuple(rng.normal(size=3)), rotate_xyz=(10, 20, 30),
             scale=(1.5, 1.5, 1.5))
    kinds = [("Cube", {"size": 0.7}), ("Sphere", {"radius": 0.4}), ("Capsule", {"radius": 0.2, "height": 0.5}),
             ("Cylinder", {"radius": 0.3, "height": 0.6, "axis": "X"}), ("Cone", {"radius": 0.3, "height": 0.9,
                                                                                  "axis": "Y"})]
    for k, (kind, attrs) in enumerate(kinds):
        um.collider(stage, f"/b/mid/{kind.lower()}", kind, attrs=attrs, mass=opts[(seed + k) % len(opts)],
                    translate=tuple(rng.normal(size=3)), rotate_xyz=tuple(rng.uniform(-180, 180, 3)),
                    scale=tuple(rng.uniform(0.5, 2.0, 3)) if k % 2 else None)
    um.mesh(stage, "/b/mesh", um.CUBE_POINTS * 0.3, um.CUBE_QUADS, translate=(0, 1, 0), rotate_xyz=(0, 45, 0))
    stage.GetRootLayer().Save()
    return path


@pytest.mark.parametrize("seed", range(6))
def test_generated_stages_with_every_shape_equal_compute_mass_properties_to_float32_rounding(tmp_path, seed):
    stage = um.read(_general_stage(tmp_path, seed))
    ours, theirs = um.oracle(stage, 0)
    _close(ours, theirs, FLOAT32_RTOL)


# ---------------------------------------------------------------------------- colliders, exactly

def _one(tmp_path, kind, attrs, **pose):
    path = tmp_path / f"{kind}.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b")
    um.collider(stage, "/b/c", kind, attrs=attrs, **pose)
    stage.GetRootLayer().Save()
    return um.read(path).bodies[0].colliders[0]


def test_a_non_uniformly_scaled_sphere_is_the_ellipsoid(tmp_path):
    c = _one(tmp_path, "Sphere", {"radius": 0.5}, scale=(1, 2, 3))
    V, com, J, shape, _ = collider_solid(c)
    truth = primitives.ellipsoid((0.5, 1.0, 1.5), density=1.0)     # closed form
    assert V == pytest.approx(truth.mass, rel=1e-14)
    np.testing.assert_allclose(J, truth.inertia_com, rtol=1e-13, atol=1e-16)


def test_a_rotated_then_scaled_cube_is_the_mesh_of_its_transformed_corners(tmp_path):
    # scale applied after a rotation shears the cube; truth: our mesh path on the moved corners
    c = _one(tmp_path, "Cube", {"size": 2.0}, rotate_xyz=(30, 0, 0), scale=(1, 3, 0.5))
    V, com, J, _, _ = collider_solid(c)
    v = um.CUBE_POINTS @ c.L_collider.T
    faces = np.array([[q[0], q[1], q[2]] for q in um.CUBE_QUADS] + [[q[0], q[2], q[3]] for q in um.CUBE_QUADS])
    truth = mesh_properties(v, faces, density=1.0)
    assert V == pytest.approx(truth.mass, rel=1e-13)
    np.testing.assert_allclose(J, truth.inertia_com, rtol=0, atol=1e-12 * np.abs(J).max())


def test_a_mesh_collider_of_a_cube_equals_the_cube_primitive(tmp_path):
    path = tmp_path / "m.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b")
    um.mesh(stage, "/b/m", um.CUBE_POINTS, um.CUBE_QUADS)
    stage.GetRootLayer().Save()
    V, com, J, shape, _ = collider_solid(um.read(path).bodies[0].colliders[0])
    assert shape == "exact" and V == pytest.approx(8.0, rel=1e-14)
    np.testing.assert_allclose(J, np.eye(3) * 8 * (4 + 4) / 12, rtol=1e-13)


def test_a_cone_has_its_base_at_minus_half_height_on_its_axis(tmp_path):
    # truth: UsdGeomCone's apex points along +axis; a fine faceted cone from our mesh path
    c = _one(tmp_path, "Cone", {"radius": 0.5, "height": 2.0, "axis": "X"})
    V, com, J, _, _ = collider_solid(c)
    n = 720
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.stack([np.full(n, -1.0), 0.5 * np.cos(t), 0.5 * np.sin(t)], axis=1)
    v = np.vstack([ring, [[1.0, 0, 0], [-1.0, 0, 0]]])
    faces = [[i, (i + 1) % n, n] for i in range(n)] + [[(i + 1) % n, i, n + 1] for i in range(n)]
    truth = mesh_properties(v, np.array(faces), density=1.0)
    np.testing.assert_allclose(com, [-0.5, 0, 0], atol=1e-15)
    np.testing.assert_allclose(com, truth.com, atol=1e-4)
    np.testing.assert_allclose(J, truth.inertia_com, rtol=1e-4, atol=1e-4 * np.abs(J).max())


def test_as_physx_a_non_convex_mesh_on_a_dynamic_body_weighs_its_convex_hull(tmp_path):
    path = tmp_path / "l.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b")
    # an L-shaped prism: 3 unit cubes; its hull adds half a cube
    um.extruded(stage, "/b/m", [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    stage.GetRootLayer().Save()
    exact = stage_mass_properties(path)
    physx = stage_mass_properties(path, physx=True)
    assert exact.links[0].mass == pytest.approx(3000.0, rel=1e-14)
    assert physx.links[0].mass == pytest.approx(3500.0, rel=1e-14)
    assert physx.links[0].exact_mass == pytest.approx(3000.0, rel=1e-14)


def test_a_collider_belongs_to_its_nearest_body_not_to_an_enclosing_one(tmp_path):
    # UsdPhysics' parser gives each collider its nearest rigid-body ancestor; usd-core's
    # ComputeMassProperties would count the inner body's cube in the outer one too
    path = tmp_path / "n.usda"
    stage = um.new_stage(path)
    um.body(stage, "/a")
    um.collider(stage, "/a/c", attrs={"size": 1.0})
    um.body(stage, "/a/b", translate=(3, 0, 0))
    um.collider(stage, "/a/b/c", attrs={"size": 2.0})
    stage.GetRootLayer().Save()
    r = stage_mass_properties(path)
    assert [lk.mass for lk in r.links] == [1000.0, 8000.0]
    assert r.links[1].parent == 0
    np.testing.assert_allclose(r.links[1].com, [3, 0, 0])


def test_usd_cores_diagonalisation_is_reproduced_in_double():
    # truth: numpy's eigendecomposition; the order follows the start axes (no sorting)
    rng = np.random.default_rng(3)
    for _ in range(20):
        A = rng.normal(size=(3, 3))
        I = A @ A.T + np.eye(3)
        d, q = jacobi_principal(I)
        np.testing.assert_allclose(np.sort(d), np.linalg.eigvalsh(I), rtol=1e-6)
        from inertia.robots.usd.mass import principal_axes_matrix

        R = principal_axes_matrix(q)
        np.testing.assert_allclose(R @ np.diag(d) @ R.T, I, atol=1e-6 * np.abs(I).max())


def test_an_inertia_below_usd_cores_tolerance_reads_as_not_set_unless_asked(tmp_path):
    path = tmp_path / "t.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b", mass=1.0, diag=(4e-6, 4e-6, 4e-6), com=(0, 0, 0), axes=(1, 0, 0, 0))
    um.collider(stage, "/b/c", attrs={"size": 2.0})
    stage.GetRootLayer().Save()
    s = um.read(path)
    ours, theirs = um.oracle(s, 0)
    _close(ours, theirs, FLOAT32_RTOL)                     # usd-core: the cube's inertia at 1 kg
    np.testing.assert_allclose(ours.I_B, np.eye(3) * 2 / 3, rtol=1e-14)
    strict = body_mass(s, 0, tol=0.0)                     # the schema's text: only 0 means "not set"
    np.testing.assert_allclose(strict.I_B, np.eye(3) * 4e-6, rtol=1e-6)
    assert UNSET_TOLERANCE == 1e-5


def test_a_body_without_mass_or_colliders_gets_one_kilogram_where_usd_core_says_minus_one(tmp_path):
    path = tmp_path / "e.usda"
    stage = um.new_stage(path)
    um.body(stage, "/b")
    um.body(stage, "/c", mass=2.0)
    stage.GetRootLayer().Save()
    s = um.read(path)
    assert body_mass(s, 0).mass == 1.0 and body_mass(s, 0).source == "fallback"
    prim = s.usd_stage.GetPrimAtPath("/b")
    assert UsdPhysics.RigidBodyAPI(prim).ComputeMassProperties(lambda p: None)[0] == -1.0
    # an authored mass without colliders: usd-core's sphere of radius 0.1 m
    c = body_mass(s, 1)
    np.testing.assert_allclose(c.I_B, np.eye(3) * 0.4 * 2.0 * 0.01, rtol=1e-14)
    theirs = UsdPhysics.RigidBodyAPI(s.usd_stage.GetPrimAtPath("/c")).ComputeMassProperties(lambda p: None)
    np.testing.assert_allclose(np.array(theirs[1]), np.diag(c.I_B), rtol=1e-6)


def test_world_values_follow_the_bodys_pose_and_the_stage_units(tmp_path):
    path = tmp_path / "w.usda"
    stage = um.new_stage(path, mpu=0.01, kpu=0.001)       # centimetres and grams
    um.body(stage, "/b", translate=(100, 0, 0), rotate_xyz=(0, 0, 90))
    um.collider(stage, "/b/c", attrs={"size": 10.0}, translate=(0, 20, 0))   # a 10 cm cube 20 cm along body y
    stage.GetRootLayer().Save()
    r = stage_mass_properties(path)
    lk = r.links[0]
    assert lk.mass == pytest.approx(1.0, rel=1e-12)        # 1000 kg/m^3 x 1e-3 m^3
    np.testing.assert_allclose(lk.com, [1.0 - 0.2, 0, 0], atol=1e-12)   # body y is world x after 90 deg about z
    np.testing.assert_allclose(lk.inertia_com, np.eye(3) * 1.0 * 0.02 / 12, rtol=1e-12)
    assert r.frame == "world" and r.format == "usd"


def test_gf_helpers_are_the_column_vector_convention():
    # truth: usd-core's own row-vector matrix of a rotation, transposed once
    q = Gf.Quatd(np.cos(0.3), 0, 0, np.sin(0.3))
    M = np.array(Gf.Matrix4d().SetRotate(q), float)[:3, :3]
    from inertia._core.rotations import quat_to_matrix

    np.testing.assert_allclose(M.T, quat_to_matrix([np.cos(0.3), 0, 0, np.sin(0.3)]), atol=1e-15)
