"""Stages for the OpenUSD tests, written with usd-core's API (no copied files).

``SCENARIOS`` rebuilds the cases of OpenUSD's own ``pxr/usd/usdPhysics/testenv/
testUsdPhysicsRigidBodyAPI.py`` (each with the values that test expects); ``oracle`` runs
usd-core's ``UsdPhysicsRigidBodyAPI.ComputeMassProperties`` on a body, fed with our per-collider
values, so that what is compared is the precedence logic.
"""

from __future__ import annotations

import numpy as np
import pytest

pxr = pytest.importorskip("pxr")
from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdShade  # noqa: E402

from inertia._core.rotations import matrix_to_quat  # noqa: E402
from inertia.robots.usd.mass import body_mass, principal_axes_matrix  # noqa: E402
from inertia.robots.usd.stage import read_stage  # noqa: E402


def new_stage(path, *, mpu=1.0, kpu=1.0, units=True):
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, "Z")
    if units:
        UsdGeom.SetStageMetersPerUnit(stage, mpu)
        UsdPhysics.SetStageKilogramsPerUnit(stage, kpu)
    return stage


def mass_api(prim, *, mass=None, density=None, com=None, diag=None, axes=None):
    api = UsdPhysics.MassAPI.Apply(prim)
    if mass is not None:
        api.CreateMassAttr(float(mass))
    if density is not None:
        api.CreateDensityAttr(float(density))
    if com is not None:
        api.CreateCenterOfMassAttr(Gf.Vec3f(*com))
    if diag is not None:
        api.CreateDiagonalInertiaAttr(Gf.Vec3f(*diag))
    if axes is not None:
        api.CreatePrincipalAxesAttr(Gf.Quatf(*axes))
    return api


def xform(prim, *, translate=None, rotate_xyz=None, scale=None, orient=None):
    x = UsdGeom.Xformable(prim)
    if translate is not None:
        x.AddTranslateOp().Set(Gf.Vec3d(*translate))
    if orient is not None:
        x.AddOrientOp().Set(Gf.Quatf(*orient))
    if rotate_xyz is not None:
        x.AddRotateXYZOp().Set(Gf.Vec3f(*rotate_xyz))
    if scale is not None:
        x.AddScaleOp().Set(Gf.Vec3f(*scale))
    return prim


def body(stage, path, **kw):
    prim = UsdGeom.Xform.Define(stage, path).GetPrim()
    UsdPhysics.RigidBodyAPI.Apply(prim)
    xform(prim, **{k: kw.pop(k) for k in ("translate", "rotate_xyz", "scale", "orient") if k in kw})
    if kw:
        mass_api(prim, **kw)
    return prim


def collider(stage, path, kind="Cube", *, attrs=None, mass=None, **pose):
    schema = getattr(UsdGeom, kind)
    prim = schema.Define(stage, path).GetPrim()
    for name, value in (attrs or {}).items():
        prim.GetAttribute(name).Set(value)
    UsdPhysics.CollisionAPI.Apply(prim)
    xform(prim, **pose)
    if mass:
        mass_api(prim, **mass)
    return prim


def mesh(stage, path, points, faces, **pose):
    m = UsdGeom.Mesh.Define(stage, path)
    m.CreatePointsAttr([Gf.Vec3f(*p) for p in np.asarray(points, float)])
    m.CreateFaceVertexCountsAttr([len(f) for f in faces])
    m.CreateFaceVertexIndicesAttr([int(i) for f in faces for i in f])
    UsdPhysics.CollisionAPI.Apply(m.GetPrim())
    xform(m.GetPrim(), **pose)
    return m.GetPrim()


def material(stage, path, density, bind_to):
    mat = UsdShade.Material.Define(stage, path)
    UsdPhysics.MaterialAPI.Apply(mat.GetPrim()).CreateDensityAttr(float(density))
    UsdShade.MaterialBindingAPI.Apply(bind_to).Bind(mat, UsdShade.Tokens.weakerThanDescendants, "physics")
    return mat


CUBE_POINTS = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], float)
CUBE_QUADS = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]


# ---------------------------------------------------------------------------- OpenUSD's cases

def _cube_body(stage):                        # test_mass_rigid_body_cube
    prim = collider(stage, "/cube", attrs={"size": 1.0})
    UsdPhysics.RigidBodyAPI.Apply(prim)
    return "/cube"


def _xform_cube(stage, body_kw=None, cube_mass=None):
    body(stage, "/xform", **(body_kw or {}))
    collider(stage, "/xform/cube", attrs={"size": 1.0}, mass=cube_mass)
    return "/xform"


def _material_case(stage, body_density=None, cube_density=None, material_density=500.0):
    body(stage, "/xform", **({"density": body_density} if body_density else {}))
    cube = collider(stage, "/xform/cube", attrs={"size": 1.0}, mass={"density": cube_density} if cube_density else None)
    material(stage, "/basePhysicsMaterial", material_density, cube)
    return "/xform"


def _compound_scaled(stage):                  # test_mass_rigid_body_cube_rigid_body_compound
    body(stage, "/xform")
    collider(stage, "/xform/cube0", attrs={"size": 1.0}, translate=(100, 20, 10), rotate_xyz=(0, 0, 45),
             scale=(3, 2, 3))
    collider(stage, "/xform/cube1", attrs={"size": 1.0}, translate=(-100, 20, 10), rotate_xyz=(0, 0, 45),
             scale=(3, 2, 3))
    return "/xform"


def _compound(stage):                         # test_mass_rigid_body_cube_compound
    body(stage, "/xform")
    collider(stage, "/xform/cube0", attrs={"size": 1.0}, translate=(0, 0, -2))
    collider(stage, "/xform/cube1", attrs={"size": 1.0}, translate=(0, 0, 2))
    return "/xform"


#: name -> (builder, stage units (mpu, kpu), expected mass, expected COM, expected diagonal, expected axes)
SCENARIOS = {
    "cube": (_cube_body, (1, 1), 1000.0, (0, 0, 0), 166.667, None),
    "rigid_body_density": (lambda s: _xform_cube(s, {"density": 500.0}), (1, 1), 500.0, (0, 0, 0), 83.3335, None),
    "collider_density": (lambda s: _xform_cube(s, cube_mass={"density": 500.0}), (1, 1), 500.0, (0, 0, 0), 83.3335,
                         None),
    "material_density": (lambda s: _material_case(s), (1, 1), 500.0, (0, 0, 0), 83.3335, None),
    "density_precedence": (lambda s: _material_case(s, 5000.0, 500.0, 2000.0), (1, 1), 500.0, (0, 0, 0), 83.3335,
                           None),
    "rigid_body_mass": (lambda s: _xform_cube(s, {"mass": 2000.0}), (1, 1), 2000.0, (0, 0, 0), 333.334, None),
    "collider_mass": (lambda s: _xform_cube(s, cube_mass={"mass": 2000.0}), (1, 1), 2000.0, (0, 0, 0), 333.334, None),
    "mass_precedence": (lambda s: _xform_cube(s, {"mass": 2000.0}, {"mass": 500.0}), (1, 1), 2000.0, (0, 0, 0),
                        333.334, None),
    "rigid_body_com": (lambda s: _xform_cube(s, {"com": (2, 2, 2)}), (1, 1), 1000.0, (2, 2, 2), None, None),
    "collider_com": (lambda s: _xform_cube(s, cube_mass={"com": (2, 2, 2)}), (1, 1), 1000.0, (2, 2, 2), None, None),
    "com_precedence": (lambda s: _xform_cube(s, {"com": (2, 2, 2)}, {"com": (1, 1, 1)}), (1, 1), 1000.0, (2, 2, 2),
                       None, None),
    "rigid_body_inertia": (lambda s: _xform_cube(s, {"diag": (2, 2, 2)}), (1, 1), 1000.0, None, 2.0, None),
    "collider_inertia": (lambda s: _xform_cube(s, cube_mass={"diag": (2, 2, 2)}), (1, 1), 1000.0, None, 2.0, None),
    "inertia_precedence": (lambda s: _xform_cube(s, {"diag": (2, 2, 2)}, {"diag": (1, 1, 1)}), (1, 1), 1000.0, None,
                           2.0, None),
    "principal_axes": (lambda s: _xform_cube(s, {"axes": (0.707, 0, 0.707, 0)}), (1, 1), 1000.0, None, None,
                       (0.707, 0, 0.707, 0)),
    "cm_units": (_cube_body, (0.01, 1), 1000.0 * 1e-6, (0, 0, 0), 166.667 * 1e-6, None),
    "decagram_units": (_cube_body, (1, 0.1), 1000.0 / 0.1, (0, 0, 0), 166.667 / 0.1, None),
    "compound": (_compound, (1, 1), 2000.0, (0, 0, 0), None, None),
    "compound_scaled": (_compound_scaled, (1, 1), 2000.0 * 18, None, None, None),
}


def build(tmp_path, name):
    """Write scenario ``name`` to a .usda file; ``(path, body path)``."""
    builder, (mpu, kpu), *_ = SCENARIOS[name]
    path = tmp_path / f"{name}.usda"
    stage = new_stage(path, mpu=mpu, kpu=kpu)
    body_path = builder(stage)
    stage.GetRootLayer().Save()
    return path, body_path


def collider_information(parts):
    """usd-core's ``MassInformation`` callback that gives our value for each collider of ``parts``
    (a body's colliders, by prim path), and volume 0 for any other prim (it then adds nothing)."""
    by_path = {p.path: p for p in parts}

    def info(prim):
        mi = UsdPhysics.RigidBodyAPI.MassInformation()
        p = by_path.get(str(prim.GetPath()))
        if p is None:
            mi.volume, mi.inertia, mi.centerOfMass = 0.0, Gf.Matrix3f(0.0), Gf.Vec3f(0.0)
            mi.localPos, mi.localRot = Gf.Vec3f(0.0), Gf.Quatf(1.0)
            return mi
        mi.volume = float(p.volume)
        mi.inertia = Gf.Matrix3f(*[float(x) for x in p.J_C.ravel()])
        mi.centerOfMass = Gf.Vec3f(*p.com_C)
        mi.localPos = Gf.Vec3f(*p.p_body_collider)
        w, x, y, z = matrix_to_quat(p.R_body_collider)
        mi.localRot = Gf.Quatf(float(w), float(x), float(y), float(z))
        return mi

    return info


def extruded(stage, path, outline, scale: float = 1.0, **pose):
    """A collider mesh: the polygon ``outline`` ((x, y) corners, counter-clockwise) extruded from
    z = 0 to z = 1, all times ``scale``; bottom, top and side faces wound outward."""
    n = len(outline)
    v = [(x, y, z) for z in (0, 1) for (x, y) in outline]
    faces = [tuple(range(n - 1, -1, -1)), tuple(range(n, 2 * n))] + [
        (i, (i + 1) % n, (i + 1) % n + n, i + n) for i in range(n)]
    return mesh(stage, path, np.array(v, float) * scale, faces, **pose)


def oracle(stage, index: int, **kw):
    """usd-core's ``ComputeMassProperties`` of body ``index`` of our read stage, each collider
    given as our value for it (a collider of another body: volume 0, so it adds nothing);
    ``(mass, com_B, I_B)`` in stage units and body frame, with the I_B built from its diagonal
    and principal axes."""
    ours = body_mass(stage, index, **kw)
    info = collider_information(ours.parts)
    prim = stage.usd_stage.GetPrimAtPath(stage.bodies[index].path)
    mass, diag, com, q = UsdPhysics.RigidBodyAPI(prim).ComputeMassProperties(info)
    R = principal_axes_matrix([q.GetReal(), *q.GetImaginary()])
    return ours, (mass, np.array(com, float), R @ np.diag(np.array(diag, float)) @ R.T,
                  np.array(diag, float), np.array([q.GetReal(), *q.GetImaginary()]))


def read(path):
    return read_stage(path)


__all__ = ["Sdf", "Usd", "UsdGeom", "UsdPhysics", "Gf"]
