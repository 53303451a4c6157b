"""Read an OpenUSD stage's rigid bodies through usd-core: what UsdPhysics says about their mass.

usd-core is the only reader: ``Usd.Stage.Open`` composes every layer (``.usda``, ``.usdc``,
``.usdz``, references, payloads, sublayers); UsdPhysics' own parser
(``UsdPhysicsLoadStageFromPrimRange``) says which prims are rigid bodies, which collider belongs
to which body (the nearest rigid-body ancestor), the joints and the articulations; the
``PhysicsMassAPI`` attributes, the shapes' attributes and the bound physics materials are read
with their schema classes.  Nothing here computes a mass (:mod:`.mass` does).

Frames and units: every pose is the prim's world transform at the default time, in the
stage's units (``metersPerUnit``, ``kilogramsPerUnit``).  A body's frame is its world transform
without scale (physics has no scale); a collider's frame likewise, and what its transform
scales or shears relative to that frame is kept as the linear map ``L_collider`` applied to
its geometry.  Matrices are column-vector (``x_W = R_WB @ x_B + p_WB``): usd-core's row-vector
matrices are transposed once, here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..._core.errors import RobotFileError

#: file extensions read as OpenUSD stages
USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")

#: UsdPhysics shape kinds -> our collider kinds (plane, points and custom shapes carry no volume)
SHAPE_KINDS = {"CubeShape": "cube", "SphereShape": "sphere", "CapsuleShape": "capsule", "Capsule1Shape": "capsule",
               "CylinderShape": "cylinder", "Cylinder1Shape": "cylinder", "ConeShape": "cone", "MeshShape": "mesh",
               "PlaneShape": "plane", "SpherePointsShape": "points", "CustomShape": "custom"}
JOINT_KINDS = ("FixedJoint", "RevoluteJoint", "PrismaticJoint", "SphericalJoint", "DistanceJoint", "D6Joint",
               "CustomJoint")


def is_usd_path(path) -> bool:
    """Whether ``path`` names an OpenUSD layer (by its extension)."""
    return Path(str(path)).suffix.lower() in USD_EXTENSIONS


def pxr_modules():
    """``(Usd, UsdGeom, UsdPhysics, UsdShade, Sdf, Gf)``, or MissingDependencyError naming the ``usd`` extra."""
    from ..._core.optional import require

    require("pxr.UsdPhysics", "reading OpenUSD stages")
    from pxr import Gf, Sdf, Usd, UsdGeom, UsdPhysics, UsdShade

    return Usd, UsdGeom, UsdPhysics, UsdShade, Sdf, Gf


@dataclass
class MassAttrs:
    """One prim's ``PhysicsMassAPI`` as authored, in stage units (None: no opinion).

    ``applied``: the API schema is applied (without it, usd-core and PhysX ignore the values).
    ``principal_axes`` is ``(w, x, y, z)`` as written (not normalised).
    """

    applied: bool = False
    mass: float | None = None
    density: float | None = None
    center_of_mass: np.ndarray | None = None
    diagonal_inertia: np.ndarray | None = None
    principal_axes: np.ndarray | None = None

    @property
    def authored(self) -> bool:
        return any(v is not None for v in (self.mass, self.density, self.center_of_mass, self.diagonal_inertia,
                                           self.principal_axes))


@dataclass
class Collider:
    """A prim with ``PhysicsCollisionAPI``: its shape in its own coordinates (stage units) and pose.

    ``params``: cube ``size``; sphere ``radius``; capsule/cylinder/cone ``radius``, ``height``,
    ``axis`` ("X", "Y", "Z"; capsule ``height`` excludes the caps); mesh ``points`` (N, 3),
    ``faces`` (F, 3) triangles (fan-split polygons, winding made right-handed).
    """

    path: str
    kind: str
    params: dict
    body: str | None
    R_body_collider: np.ndarray
    p_body_collider: np.ndarray
    L_collider: np.ndarray          # scale/shear of the prim's transform, in the collider frame
    scale_world: np.ndarray         # GfTransform's scale of the world transform (scales an authored COM)
    mass: MassAttrs
    material_density: float | None = None   # the bound physics material's density (0: not set)
    material: str | None = None
    approximation: str | None = None        # PhysicsMeshCollisionAPI's physics:approximation
    enabled: bool = True
    problem: str | None = None               # why its shape cannot be read


@dataclass
class Body:
    """A prim with ``PhysicsRigidBodyAPI`` and its world pose (stage units)."""

    path: str
    name: str
    R_world_body: np.ndarray
    p_world_body: np.ndarray
    scale_world: np.ndarray
    mass: MassAttrs
    colliders: list = field(default_factory=list)
    dynamic: bool = True            # rigid body enabled and not kinematic
    parent: int | None = None       # index of the parent body (joints, else the prim hierarchy)
    articulation: str | None = None
    #: the prim's ``displayName``, where converters keep a name that is no valid prim name
    display_name: str | None = None

    @property
    def label(self) -> str:
        """The name reports use: the display name, else the prim's name."""
        return self.display_name or self.name


@dataclass
class Stage:
    """What a stage says about its rigid bodies (see the module docstring)."""

    path: Path
    meters_per_unit: float
    kilograms_per_unit: float
    units_authored: tuple           # (metersPerUnit authored, kilogramsPerUnit authored)
    bodies: list
    #: prims with PhysicsMassAPI (or mass attributes) that are neither a body nor a collider
    stray_mass: list = field(default_factory=list)
    #: colliders that belong to no rigid body (static), by path
    static_colliders: list = field(default_factory=list)
    articulations: dict = field(default_factory=dict)   # root path -> [body indices]
    usd_stage: object = None

    def body(self, name: str) -> Body:
        for b in self.bodies:
            if name in (b.name, b.path, b.display_name):
                return b
        raise RobotFileError(f"{self.path}: no rigid body named {name!r}; the bodies are "
                             + ", ".join(repr(b.name) for b in self.bodies[:30]))


def open_stage(path):
    """The composed ``Usd.Stage`` of the file ``path`` (RobotFileError when usd-core cannot open it)."""
    Usd = pxr_modules()[0]
    from pxr import Tf

    try:
        _check_layers(path)
        stage = Usd.Stage.Open(str(path), Usd.Stage.LoadAll)
    except Tf.ErrorException as exc:
        text = " ".join(str(exc).split())
        raise RobotFileError(f"{path}: usd-core cannot open the stage: {text}") from None
    if stage is None:
        raise RobotFileError(f"{path}: usd-core cannot open the stage")
    return stage


def _check_layers(path) -> None:
    """Every layer the stage at ``path`` composes (sublayers, references, payloads, found layer by
    layer) checked by the input-file rule before usd-core opens it: a FIFO or a device would
    block it or be read without end.  A missing layer is left to usd-core (it composes without it)."""
    import os

    from pxr import Sdf

    from ..._core.files import MAX_MESH_FILE_BYTES, open_regular

    todo, seen = [os.path.abspath(path)], set()
    while todo:
        layer_path = todo.pop()
        if layer_path in seen or (seen and not os.path.lexists(layer_path)):
            continue
        seen.add(layer_path)
        what = f"layer {os.path.basename(path)} composes" if len(seen) > 1 else "USD file"
        fd, _ = open_regular(layer_path, what=what, limit=MAX_MESH_FILE_BYTES, error=RobotFileError)
        os.close(fd)
        layer = Sdf.Layer.FindOrOpen(layer_path)
        if layer is not None:
            todo += [layer.ComputeAbsolutePath(a) for a in layer.GetCompositionAssetDependencies()]


def _matrix(m) -> tuple[np.ndarray, np.ndarray]:
    """``(A, t)`` column-vector form ``x_W = A x + t`` of a row-vector GfMatrix4d."""
    M = np.array(m, float).reshape(4, 4)
    return M[:3, :3].T.copy(), M[3, :3].copy()


def _decompose(m):
    """``(R, p, scale)`` of a world matrix: GfTransform's rotation, translation and scale."""
    Gf = pxr_modules()[5]
    tr = Gf.Transform(m)
    q = tr.GetRotation().GetQuat()
    from ..._core.rotations import quat_normalize, quat_to_matrix

    R = quat_to_matrix(quat_normalize([q.GetReal(), *q.GetImaginary()]))
    return R, np.array(tr.GetTranslation(), float), np.array(tr.GetScale(), float)


def _value(attr):
    """An attribute's value at the default time, or None when it has no authored opinion."""
    if not attr or not attr.HasAuthoredValue():
        return None
    return attr.Get()


def mass_attrs(prim) -> MassAttrs:
    """The prim's ``PhysicsMassAPI`` attributes as authored (see :class:`MassAttrs`)."""
    UsdPhysics = pxr_modules()[2]
    api = UsdPhysics.MassAPI(prim)
    out = MassAttrs(applied=prim.HasAPI(UsdPhysics.MassAPI))
    m, d = _value(api.GetMassAttr()), _value(api.GetDensityAttr())
    out.mass = None if m is None else float(m)
    out.density = None if d is None else float(d)
    c, i, q = (_value(a) for a in (api.GetCenterOfMassAttr(), api.GetDiagonalInertiaAttr(),
                                   api.GetPrincipalAxesAttr()))
    out.center_of_mass = None if c is None else np.array(c, float)
    out.diagonal_inertia = None if i is None else np.array(i, float)
    out.principal_axes = None if q is None else np.array([q.GetReal(), *q.GetImaginary()], float)
    return out


def _axis(prim) -> str:
    a = prim.GetAttribute("axis")
    return str(a.Get()) if a and a.Get() else "Z"


def _float(prim, name: str, default: float) -> float:
    a = prim.GetAttribute(name)
    v = a.Get() if a else None
    return float(default if v is None else v)


def _shape_params(prim, kind: str) -> dict:
    """The shape's own parameters (schema fallbacks where not authored), in stage units."""
    if kind == "cube":
        return {"size": _float(prim, "size", 2.0)}
    if kind == "sphere":
        return {"radius": _float(prim, "radius", 1.0)}
    if kind in ("capsule", "cylinder", "cone"):
        defaults = {"capsule": (0.5, 1.0), "cylinder": (1.0, 2.0), "cone": (1.0, 2.0)}[kind]
        radius = _float(prim, "radius", defaults[0])
        top, bottom = prim.GetAttribute("radiusTop"), prim.GetAttribute("radiusBottom")
        if top and bottom and top.Get() is not None and bottom.Get() is not None:   # Capsule_1, Cylinder_1
            if float(top.Get()) != float(bottom.Get()):
                raise RobotFileError(f"a {kind} with radiusTop {top.Get()} != radiusBottom {bottom.Get()} "
                                     "is not supported")
            radius = float(top.Get())
        return {"radius": radius, "height": _float(prim, "height", defaults[1]), "axis": _axis(prim)}
    if kind == "mesh":
        return _mesh_params(prim)
    return {}


def _mesh_params(prim) -> dict:
    """Points and fan-triangulated faces of a UsdGeomMesh (left-handed winding reversed)."""
    points = prim.GetAttribute("points").Get()
    counts = prim.GetAttribute("faceVertexCounts").Get()
    indices = prim.GetAttribute("faceVertexIndices").Get()
    if points is None or counts is None or indices is None or len(points) == 0:
        raise RobotFileError("the mesh has no points or faces")
    v = np.array(points, float).reshape(-1, 3)
    n = np.array(counts, np.int64)
    idx = np.array(indices, np.int64)
    if n.sum() != idx.size or np.any(n < 0):
        raise RobotFileError(f"faceVertexCounts sum to {int(n.sum())} but there are {idx.size} faceVertexIndices")
    if idx.size and (idx.min() < 0 or idx.max() >= len(v)):
        raise RobotFileError(f"a face vertex index is outside the {len(v)} points")
    start = np.concatenate([[0], np.cumsum(n)[:-1]])
    tri_per_face = np.maximum(n - 2, 0)
    face_of = np.repeat(np.arange(n.size), tri_per_face)
    k = np.arange(face_of.size) - np.repeat(np.cumsum(tri_per_face) - tri_per_face, tri_per_face) + 1
    s = start[face_of]
    faces = np.stack([idx[s], idx[s + k], idx[s + k + 1]], axis=1)
    orientation = prim.GetAttribute("orientation").Get() if prim.GetAttribute("orientation") else None
    if str(orientation) == "leftHanded":
        faces = faces[:, ::-1]
    # converters write a vertex per face corner (STL has no shared vertices): equal points are one
    # vertex, so that a closed surface is closed in its indices too
    v, inverse = np.unique(v, axis=0, return_inverse=True)
    return {"points": v, "faces": inverse.reshape(-1)[faces]}


def _load_physics(stage, root: str):
    UsdPhysics = pxr_modules()[2]
    load = getattr(UsdPhysics, "UsdPhysicsLoadStageFromPrimRange", None) or UsdPhysics.LoadUsdPhysicsFromRange
    parsed = load(stage, [root])
    return {str(k).rsplit(".", 1)[-1]: list(zip(*v)) for k, v in parsed.items()}


def read_stage(path, *, root: str = "/") -> Stage:
    """Every rigid body of the stage at ``path`` with its colliders, mass attributes and pose.

    ``root``: the prim path below which bodies are read (default the whole stage).
    """
    Usd, UsdGeom, UsdPhysics, UsdShade, Sdf, Gf = pxr_modules()
    path = Path(path)
    stage = open_stage(path)
    if not stage.GetPrimAtPath(root):
        raise RobotFileError(f"{path}: no prim at {root!r}")
    parsed = _load_physics(stage, root)
    cache = UsdGeom.XformCache(Usd.TimeCode.Default())
    bodies, index = [], {}
    for p, desc in parsed.get("RigidBody", []):
        prim = stage.GetPrimAtPath(p)
        R, t, s = _decompose(cache.GetLocalToWorldTransform(prim))
        index[str(p)] = len(bodies)
        bodies.append(Body(str(p), prim.GetName(), R, t, s, mass_attrs(prim),
                           dynamic=bool(desc.rigidBodyEnabled) and not bool(desc.kinematicBody),
                           display_name=prim.GetMetadata("displayName") or None))
    out = Stage(path, UsdGeom.GetStageMetersPerUnit(stage), UsdPhysics.GetStageKilogramsPerUnit(stage),
                (UsdGeom.StageHasAuthoredMetersPerUnit(stage), UsdPhysics.StageHasAuthoredKilogramsPerUnit(stage)),
                bodies, usd_stage=stage)
    colliders = []
    for shape, kind in SHAPE_KINDS.items():
        for p, desc in parsed.get(shape, []):
            colliders.append(_collider(stage, cache, str(p), kind, desc, bodies, index))
    _bind_materials(stage, colliders)
    for c in colliders:
        (bodies[index[c.body]].colliders if c.body in index else out.static_colliders).append(c)
    _stray_mass(stage, root, out, {c.path for c in colliders})
    _tree(parsed, bodies, index, out)
    return out


def _collider(stage, cache, path: str, kind: str, desc, bodies, index) -> Collider:
    prim = stage.GetPrimAtPath(path)
    A, _ = _matrix(cache.GetLocalToWorldTransform(prim))
    R_WC, p_WC, scale = _decompose(cache.GetLocalToWorldTransform(prim))
    body = str(desc.rigidBody) if desc.rigidBody and not desc.rigidBody.isEmpty else None
    if body in index:
        b = bodies[index[body]]
        R_BC, p_BC = b.R_world_body.T @ R_WC, b.R_world_body.T @ (p_WC - b.p_world_body)
    else:
        R_BC, p_BC = R_WC, p_WC
    problem, params = None, {}
    try:
        params = _shape_params(prim, kind)
    except ValueError as exc:
        problem = str(exc)
    approximation = None
    if kind == "mesh":
        a = prim.GetAttribute("physics:approximation")
        approximation = str(a.Get()) if a and a.Get() is not None else "none"
    return Collider(path, kind, params, body, R_BC, p_BC, R_WC.T @ A, scale, mass_attrs(prim),
                    approximation=approximation, enabled=bool(desc.collisionEnabled), problem=problem)


def _bind_materials(stage, colliders) -> None:
    """Each collider's bound physics material and its density, as usd-core's ComputeMassProperties
    finds it (``ComputeBoundMaterials`` with purpose ``physics``; only materials with
    ``PhysicsMaterialAPI`` count)."""
    _, _, UsdPhysics, UsdShade, _, _ = pxr_modules()
    if not colliders:
        return
    prims = [stage.GetPrimAtPath(c.path) for c in colliders]
    materials, _ = UsdShade.MaterialBindingAPI.ComputeBoundMaterials(prims, "physics")
    for c, mat in zip(colliders, materials):
        if mat and mat.GetPrim().HasAPI(UsdPhysics.MaterialAPI):
            c.material = str(mat.GetPrim().GetPath())
            d = UsdPhysics.MaterialAPI(mat.GetPrim()).GetDensityAttr().Get()
            c.material_density = float(d) if d is not None else 0.0


def _stray_mass(stage, root: str, out: Stage, collider_paths: set) -> None:
    """Prims with mass opinions that neither a body nor a collider carries: physics ignores them."""
    Usd, _, UsdPhysics = pxr_modules()[:3]
    bodies = {b.path for b in out.bodies}
    for prim in Usd.PrimRange(stage.GetPrimAtPath(root), Usd.TraverseInstanceProxies()):
        p = str(prim.GetPath())
        if p in bodies or p in collider_paths:
            continue
        attrs = mass_attrs(prim)
        if prim.HasAPI(UsdPhysics.MaterialAPI) and not attrs.applied:
            continue            # a physics material's own physics:density
        if attrs.applied or attrs.authored:
            out.stray_mass.append((p, attrs))


def _tree(parsed, bodies, index, out: Stage) -> None:
    """Parents from the joints (body0 -> body1, loop closures excluded), else the nearest
    rigid-body ancestor prim; articulation membership from UsdPhysics' articulations."""
    for kind in JOINT_KINDS:
        for _, j in parsed.get(kind, []):
            b0, b1 = str(j.body0), str(j.body1)
            if j.excludeFromArticulation or b1 not in index or b0 not in index:
                continue
            child = bodies[index[b1]]
            if child.parent is None and not _is_ancestor(bodies, index[b1], index[b0]):
                child.parent = index[b0]
    for i, b in enumerate(bodies):
        if b.parent is not None:
            continue
        up = b.path.rsplit("/", 1)[0]
        while up and up not in index:
            up = up.rsplit("/", 1)[0]
        if up in index and not _is_ancestor(bodies, i, index[up]):
            b.parent = index[up]
    for p, art in parsed.get("Articulation", []):
        members = [index[str(x)] for x in art.articulatedBodies if str(x) in index]
        out.articulations[str(p)] = members
        for i in members:
            bodies[i].articulation = str(p)


def _is_ancestor(bodies, i: int, j: int) -> bool:
    """Whether body ``i`` is ``j`` or one of ``j``'s ancestors (a joint that would close a loop)."""
    seen = set()
    while j is not None and j not in seen:
        if j == i:
            return True
        seen.add(j)
        j = bodies[j].parent
    return False


def finite_vector(v) -> bool:
    return v is not None and all(math.isfinite(x) for x in v)
