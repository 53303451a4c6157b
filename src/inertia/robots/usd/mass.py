"""Each rigid body's mass properties as UsdPhysics defines them, and the whole stage's.

The rules (OpenUSD ``usdPhysics/overview.dox``; the reference implementation is usd-core's
``UsdPhysicsRigidBodyAPI::ComputeMassProperties`` in ``rigidBodyAPI.cpp``, which this module
follows step by step, in double precision where it computes in float):

* a collider's mass: its own authored ``physics:mass``; else its volume times the first
  density set among its own ``physics:density``, its body's ``physics:density``, its bound
  physics material's density, and the default ``1000 kg/m^3`` in stage units
  (``1000 metersPerUnit^3 / kilogramsPerUnit``);
* a collider's ``diagonalInertia`` replaces its computed tensor, its ``principalAxes`` rotate the
  tensor, its ``centerOfMass`` moves the COM (without an authored inertia, the computed tensor
  is carried to that point by the parallel-axis rule, as usd-core does);
* the body: with ``physics:mass``, ``diagonalInertia`` and ``centerOfMass`` all authored, they
  are the answer; otherwise its colliders are summed, the sum is scaled to the body's authored
  mass, moved to its authored COM, and authored diagonal or principal axes replace the sum's;
* a body without colliders: its authored mass with the inertia of a solid sphere of radius
  0.1 m (usd-core's stand-in for a point), or, with no mass either, UsdPhysics' default of
  1 kg (usd-core returns -1 there) and usd-core's default inertia diag(1, 1, 1).

"Not set" follows usd-core: mass and density ``<= 0``, a non-finite ``centerOfMass``, a
``diagonalInertia`` or ``principalAxes`` within :data:`UNSET_TOLERANCE` of zero (Euclidean
norm, stage units).  ``unset_tolerance=0`` reads only exact zeros as not set (the schema's text).

Colliders are integrated exactly: Cube, Sphere, Capsule, Cylinder, Cone in closed form, Mesh
through :func:`inertia.mesh_properties`; the prim's scale and shear map the solid exactly
(``V' = |det L| V``, second moments ``S' = |det L| L S L^T``).  ``physx=True`` gives what PhysX
simulates where it differs: a triangle mesh on a dynamic body becomes its convex hull
(``physics:approximation`` none, convexHull, convexDecomposition), ``boundingCube`` the box
of its points, ``boundingSphere`` the sphere about their box's centre through the farthest one.
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

from ..._core.errors import InertiaError, MeshError
from ..._core.rotations import quat_to_matrix
from ...massprops.properties import MassProperties, combine
from ..geometry import summed_solid
from ..whole import LinkMass, RobotMassProperties
from .stage import finite_vector, is_usd_path, read_stage

#: usd-core's ``COMPARE_TOLERANCE``: a diagonalInertia or principalAxes whose norm is within it
#: of zero (stage units) reads as not set
UNSET_TOLERANCE = 1e-5
#: UsdPhysics' default density [kg/m^3], scaled to stage units where used
DEFAULT_DENSITY = 1000.0
#: usd-core's inertia for an authored mass without colliders: a solid sphere of this radius [m]
POINT_RADIUS = 0.1

#: where a body's mass properties come from (``source`` in the reports)
SOURCES = {"authored": "mass, inertia and COM authored on the body",
           "partly_authored": "mass authored on the body, the rest from its colliders",
           "colliders": "its colliders' volumes at an authored density (or authored collider masses)",
           "default_density": "its colliders at the default density 1000 kg/m^3 (nothing authored)",
           "sphere": "authored mass, no collider: usd-core's 0.1 m sphere inertia",
           "fallback": "nothing authored and no collider: UsdPhysics' default 1 kg"}

_AXIS = {"Z": np.eye(3), "X": np.array([[0.0, 0.0, 1.0], [0.0, 1.0, 0.0], [-1.0, 0.0, 0.0]]),
         "Y": np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])}


@dataclass
class ColliderMass:
    """One collider's part, stage units: the unit-density solid (``volume``, ``com_C``,
    ``J_C`` about its COM, collider frame) and the part after the precedence rules
    (``mass``, ``com_C_final``, ``I_C_final``)."""

    path: str
    volume: float
    com_C: np.ndarray
    J_C: np.ndarray
    density: float
    density_from: str             # collider, body, material, default
    mass: float
    com_C_final: np.ndarray
    I_C_final: np.ndarray
    R_body_collider: np.ndarray
    p_body_collider: np.ndarray
    shape: str                    # exact, hull, ...: what solid the volume is
    exact_volume: float = math.nan


@dataclass
class BodyMass:
    """One body's result in stage units and body frame, with its parts and notes."""

    index: int
    mass: float
    com_B: np.ndarray
    I_B: np.ndarray
    source: str
    parts: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    diagonal: np.ndarray | None = None
    principal_axes: np.ndarray | None = None   # (w, x, y, z), as usd-core would report it


# ------------------------------------------------------------------------------ primitives


def _second_moments_mapped(volume: float, com, inertia, L) -> tuple[float, np.ndarray, np.ndarray]:
    """A unit-density solid ``(volume, com, inertia about com)`` mapped by ``x -> L x``.

    With ``S = tr(I)/2 E - I`` the second moments about the COM, the image has
    ``V' = |det L| V``, ``c' = L c``, ``S' = |det L| L S L^T`` and ``I' = tr(S') E - S'``.
    """
    det = abs(float(np.linalg.det(L)))
    S = 0.5 * np.trace(inertia) * np.eye(3) - inertia
    S2 = det * L @ S @ L.T
    return det * volume, L @ np.asarray(com, float), np.trace(S2) * np.eye(3) - S2


def _primitive(kind: str, p: dict):
    """``(volume, com, inertia)`` at unit density of a UsdGeom primitive in its own coordinates."""
    from ...massprops import primitives

    if kind == "cube":
        s = abs(p["size"])
        props = primitives.box((s, s, s), density=1.0)
    elif kind == "sphere":
        props = primitives.sphere(abs(p["radius"]), density=1.0)
    elif kind == "cylinder":
        props = primitives.cylinder(abs(p["radius"]), abs(p["height"]), density=1.0)
    elif kind == "capsule":
        props = primitives.capsule(abs(p["radius"]), abs(p["height"]), density=1.0)
    else:   # cone: base at -height/2, apex at +height/2 (UsdGeomCone)
        props = primitives.cone(abs(p["radius"]), abs(p["height"]), density=1.0)
        props = props.translated([0.0, 0.0, -0.5 * abs(p["height"])])
    R = _AXIS[p.get("axis", "Z")]
    return props.mass, R @ props.com, R @ props.inertia_com @ R.T


_MESH_CACHE: dict = {}


def _mesh_solid(points, faces, what: str, approximation: str | None):
    """``(volume, com, inertia, shape)`` at unit density of a mesh (points already mapped),
    as the exact solid or as PhysX's approximation ``approximation``."""
    from ...massprops.mesh import mesh_properties
    from ..mujoco_inertia import hull_faces

    key = (hashlib.blake2b(points.tobytes() + faces.tobytes(), digest_size=16).digest(), approximation)
    if key in _MESH_CACHE:
        return _MESH_CACHE[key]
    if approximation in (None, "meshSimplification", "sdf"):
        props, shape = summed_solid(points, faces, density=1.0, name=what), "exact"
        if any(f.severity == "warning" for f in props.findings):   # defects accepted: overlapping parts
            shape = "exact (closed parts that overlap, summed as a simulator sums them)"
    elif approximation == "boundingCube":
        from ...massprops import primitives

        lo, hi = points.min(axis=0), points.max(axis=0)
        props, shape = primitives.box(tuple(hi - lo), density=1.0).translated(0.5 * (lo + hi)), "bounding box"
    elif approximation == "boundingSphere":
        from ...massprops import primitives

        centre = 0.5 * (points.min(axis=0) + points.max(axis=0))
        radius = float(np.max(np.linalg.norm(points - centre, axis=1)))
        props, shape = primitives.sphere(radius, density=1.0).translated(centre), "bounding sphere"
    else:
        props, shape = mesh_properties(points, hull_faces(points), density=1.0, name=f"{what} (convex hull)"), "hull"
    if len(_MESH_CACHE) > 256:
        _MESH_CACHE.pop(next(iter(_MESH_CACHE)))
    _MESH_CACHE[key] = out = (props.mass, np.array(props.com), np.array(props.inertia_com), shape)
    return out


#: PhysX's view of ``physics:approximation`` on a dynamic body's mesh (None: the mesh itself)
_PHYSX_MESH = {"none": "convexHull", "convexHull": "convexHull", "convexDecomposition": "convexHull",
               "boundingCube": "boundingCube", "boundingSphere": "boundingSphere", "meshSimplification": None,
               "sdf": None}


def collider_solid(c, *, physx: bool = False, dynamic: bool = True):
    """``(volume, com_C, J_C, shape, exact_volume)`` of a collider at unit density in its frame.

    ``shape``: "exact" or the approximation PhysX simulates (``physx=True``).  An open or
    otherwise unusable mesh is taken as its convex hull (what PhysX cooks for a dynamic body),
    with ``shape`` "hull (mesh not closed)".  InertiaError when nothing can be computed.
    """
    if c.problem:
        raise InertiaError(f"{c.path}: {c.kind}: {c.problem}")
    if c.kind in ("plane", "points", "custom"):
        raise InertiaError(f"{c.path}: a {c.kind} collider has no volume to integrate")
    L = c.L_collider
    if c.kind != "mesh":
        V, com, J = _second_moments_mapped(*_primitive(c.kind, c.params), L)
        return V, com, J, "exact", V
    points = c.params["points"] @ L.T
    faces = c.params["faces"] if np.linalg.det(L) > 0 else c.params["faces"][:, ::-1]
    try:
        exact = _mesh_solid(points, faces, c.path, None)
    except MeshError as exc:
        hull = _mesh_solid(points, faces, c.path, "convexHull")
        codes = ", ".join(dict.fromkeys(d.code for d in exc.report.errors)) if exc.report is not None else exc.code
        return (*hull[:3], f"hull (the mesh is not a closed solid: {codes})", math.nan)
    if physx and dynamic:
        approx = _PHYSX_MESH.get(c.approximation or "none", "convexHull")
        if approx is not None:
            return (*_mesh_solid(points, faces, c.path, approx), exact[0])
    return (*exact, exact[0])


# ------------------------------------------------------------------------------ precedence


def is_set(vec, tol: float) -> bool:
    """usd-core's "authored and not the sentinel": norm above ``tol`` (above 0 when tol is 0)."""
    return vec is not None and float(np.linalg.norm(vec)) > tol


def principal_axes_matrix(q) -> np.ndarray:
    """The rotation of a ``principalAxes`` quaternion ``(w, x, y, z)`` (normalised):
    ``I_body = R D R^T``, the principal frame's axes as columns in the body frame."""
    q = np.asarray(q, float)
    return quat_to_matrix(q / np.linalg.norm(q))


def _translate_inertia(I, mass: float, t) -> np.ndarray:
    """usd-core's ``TranslateInertia``: ``I + m (|t|^2 E - t t^T)``."""
    t = np.asarray(t, float)
    return I + mass * (float(t @ t) * np.eye(3) - np.outer(t, t))


def jacobi_principal(I) -> tuple[np.ndarray, np.ndarray]:
    """``(diagonal, q)`` as usd-core's ``UsdPhysicsDiagonalize`` (``massProperties.h``) finds
    them, in double: cyclic Jacobi rotations on the largest off-diagonal entry, at most 24,
    stopping when it is below ``|d_ii - d_jj| / 4e6``.  The order of the moments follows the
    body axes the rotations start from (no sorting), which decides what an authored
    ``principalAxes`` or ``diagonalInertia`` is paired with."""
    from ..._core.rotations import quat_multiply

    q = np.array([1.0, 0.0, 0.0, 0.0])
    d = np.asarray(I, float)
    nxt = (1, 2, 0)
    for _ in range(24):
        R = quat_to_matrix(q)
        d = R.T @ I @ R
        off = (abs(d[1, 2]), abs(d[0, 2]), abs(d[0, 1]))
        a = 0 if off[0] > off[1] and off[0] > off[2] else 1 if off[1] > off[2] else 2
        a1, a2 = nxt[a], nxt[nxt[a]]
        if d[a1, a2] == 0.0 or abs(d[a1, a1] - d[a2, a2]) > 2e6 * abs(2.0 * d[a1, a2]):
            break
        w = (d[a1, a1] - d[a2, a2]) / (2.0 * d[a1, a2])
        r = np.zeros(4)
        if abs(w) > 1000:                      # small angle: h is nearly 1
            r[0], r[1 + a] = 1.0, 1.0 / (4.0 * w)
        else:
            t = 1.0 / (abs(w) + math.sqrt(w * w + 1.0))
            h = 1.0 / math.sqrt(t * t + 1.0)
            r[0], r[1 + a] = math.sqrt((1.0 + h) / 2.0), math.sqrt((1.0 - h) / 2.0) * (1.0 if w >= 0 else -1.0)
        q = quat_multiply(q, r)
        q = q / np.linalg.norm(q)
    return np.diag(d).copy(), q


def collider_part(c, body, solid, *, meters_per_unit: float, kilograms_per_unit: float,
                  tol: float = UNSET_TOLERANCE) -> ColliderMass:
    """One collider's mass part by the precedence rules (usd-core's ``_ParseCollisionShapeForMass``)."""
    V, com, J, shape, exact_volume = solid
    a, b = c.mass if c.mass.applied else None, body.mass if body.mass.applied else None
    density, source = (a.density if a else None), "collider"
    if not (density and density > 0):
        density, source = (b.density if b else None), "body"
    if not (density and density > 0):
        density, source = c.material_density, "material"
    if not (density and density > 0):
        density, source = DEFAULT_DENSITY * meters_per_unit ** 3 / kilograms_per_unit, "default"
    if a and a.mass is not None and a.mass > 0:
        mass, I, source = a.mass, J * (a.mass / V), "mass"
    else:
        mass, I = V * density, J * density
    if a and is_set(a.diagonal_inertia, tol):
        I = np.diag(a.diagonal_inertia)
    if a and is_set(a.principal_axes, tol):
        R = principal_axes_matrix(a.principal_axes)
        I = R @ I @ R.T
    com_final = com
    if a and finite_vector(a.center_of_mass):
        com_final = a.center_of_mass * c.scale_world
        if not is_set(a.diagonal_inertia, tol):
            I = _translate_inertia(I, mass, com_final - com)
    return ColliderMass(c.path, V, com, J, density, source, mass, com_final, I, c.R_body_collider,
                        c.p_body_collider, shape, exact_volume)


def sum_parts(parts) -> tuple[float, np.ndarray, np.ndarray]:
    """usd-core's ``UsdPhysicsMassProperties::Sum`` in the body frame: total mass, COM and the
    tensor about that COM."""
    M = sum(p.mass for p in parts)
    coms = [p.R_body_collider @ p.com_C_final + p.p_body_collider for p in parts]
    C = sum(p.mass * c for p, c in zip(parts, coms)) / M if M > 0 else np.zeros(3)
    I = np.zeros((3, 3))
    for p, c in zip(parts, coms):
        I += _translate_inertia(p.R_body_collider @ p.I_C_final @ p.R_body_collider.T, p.mass, C - c)
    return M, C, I


def body_mass(stage, index: int, *, physx: bool = False, tol: float = UNSET_TOLERANCE) -> BodyMass:
    """One body's mass properties (stage units, body frame) by the rules of the module docstring."""
    body = stage.bodies[index]
    a = body.mass if body.mass.applied else None
    mass = a.mass if a and a.mass is not None and a.mass > 0 else None
    has_I = bool(a and is_set(a.diagonal_inertia, tol))
    has_q = bool(a and is_set(a.principal_axes, tol))
    com_B = a.center_of_mass * body.scale_world if a and finite_vector(a.center_of_mass) else None
    notes = []
    if mass is not None and has_I and com_B is not None:
        q = a.principal_axes if has_q else np.array([1.0, 0.0, 0.0, 0.0])
        R = principal_axes_matrix(q)
        out = BodyMass(index, mass, com_B, R @ np.diag(a.diagonal_inertia) @ R.T, "authored",
                       diagonal=np.array(a.diagonal_inertia), principal_axes=q)
        if not has_q:
            out.notes.append("principalAxes not authored: identity used (usd-core returns an uninitialised "
                             "quaternion here)")
        return out
    parts = []
    for c in body.colliders:
        solid = collider_solid(c, physx=physx, dynamic=body.dynamic)
        if "(" in solid[3]:
            notes.append(f"{c.path}: {solid[3]}")
        parts.append(collider_part(c, body, solid, meters_per_unit=stage.meters_per_unit,
                                   kilograms_per_unit=stage.kilograms_per_unit, tol=tol))
    if not parts:
        m = mass if mass is not None else 1.0
        if has_I:
            diag = np.array(a.diagonal_inertia)
        elif mass is not None:
            diag = np.full(3, 0.4 * m * (POINT_RADIUS / stage.meters_per_unit) ** 2)
        else:
            diag = np.ones(3)
        q = a.principal_axes if has_q else np.array([1.0, 0.0, 0.0, 0.0])
        R = principal_axes_matrix(q)
        source = "fallback" if mass is None else "authored" if has_I else "sphere"
        return BodyMass(index, m, com_B if com_B is not None else np.zeros(3), R @ np.diag(diag) @ R.T, source,
                        notes=notes, diagonal=diag, principal_axes=q)
    # the colliders' sum, scaled to an authored mass, carried to an authored COM (parallel axis)
    mass_sum, com_B_sum, I_B = sum_parts(parts)
    if mass is None:
        mass = mass_sum
    elif mass_sum > 0:
        I_B = I_B * (mass / mass_sum)
    if com_B is None:
        com_B = com_B_sum
    else:
        I_B = _translate_inertia(I_B, mass, com_B - com_B_sum)
    diag, q = np.linalg.eigvalsh(I_B), None
    if has_I or has_q:   # authored halves paired with the sum's Jacobi frame, as usd-core pairs them
        jd, jq = jacobi_principal(I_B)
        diag = np.array(a.diagonal_inertia) if has_I else jd
        q = a.principal_axes if has_q else jq
        R_BP = principal_axes_matrix(q)
        I_B = R_BP @ np.diag(diag) @ R_BP.T
    if a and (a.mass is not None and a.mass > 0 or has_I or finite_vector(a.center_of_mass)):
        source = "partly_authored"
    elif all(p.density_from == "default" for p in parts):
        source = "default_density"
    else:
        source = "colliders"
    return BodyMass(index, mass, com_B, I_B, source, parts, notes, diagonal=diag, principal_axes=q)


# ------------------------------------------------------------------------------ the stage


class UsdLinkMass(LinkMass):
    """A body's row: :class:`~inertia.robots.whole.LinkMass` plus its prim path and notes."""

    def __init__(self, *args, path: str = "", notes=(), exact_mass: float = math.nan, **kw):
        super().__init__(*args, **kw)
        self.path, self.notes, self.exact_mass = path, list(notes), exact_mass

    def to_dict(self) -> dict:
        out = super().to_dict()
        out.update({"path": self.path, "notes": self.notes})
        if math.isfinite(self.exact_mass):
            out["exact_mass"] = self.exact_mass
        return out


def to_world_si(stage, body, bm: BodyMass) -> MassProperties:
    """A body's result in the world frame, SI units."""
    m_unit, kg_unit = stage.meters_per_unit, stage.kilograms_per_unit
    R, p = body.R_world_body, body.p_world_body
    return MassProperties(bm.mass * kg_unit, (R @ bm.com_B + p) * m_unit, R @ bm.I_B @ R.T * kg_unit * m_unit ** 2,
                          frame="world", validate=False)


def stage_mass_properties(stage, *, physx: bool = False, tol: float = UNSET_TOLERANCE) -> RobotMassProperties:
    """Every rigid body of a stage (a path or a :class:`~.stage.Stage`) in the world frame, SI
    units, and their total (``format`` "usd", ``frame`` "world"); bodies that are kinematic or
    disabled are listed but not counted in the total."""
    if not hasattr(stage, "bodies"):
        stage = read_stage(stage)
    rows, notes = [], []
    names = [b.label for b in stage.bodies]
    for i, body in enumerate(stage.bodies):
        try:
            bm = body_mass(stage, i, physx=physx, tol=tol)
        except InertiaError as exc:
            raise InertiaError(f"{stage.path}: body {body.path}: {exc}") from None
        props = to_world_si(stage, body, bm)
        name = body.label if names.count(body.label) == 1 else body.path
        exact = math.nan
        if physx and any(p.shape != "exact" for p in bm.parts):
            exact = to_world_si(stage, body, body_mass(stage, i, tol=tol)).mass
        row = UsdLinkMass(name, None, bm.source, props, body.R_world_body, body.p_world_body * stage.meters_per_unit,
                          body.parent, path=body.path, notes=bm.notes, exact_mass=exact)
        row.dynamic = body.dynamic
        rows.append(row)
    if not stage.units_authored[0]:
        notes.append(f"metersPerUnit is not authored: UsdGeom's fallback {stage.meters_per_unit:g} m (centimetres) "
                     "is used")
    counted = [r.props for r in rows if r.dynamic and r.mass > 0]
    if not counted:
        from ..._core.errors import InputError

        raise InputError(f"{stage.path}: the stage has no dynamic rigid body with mass"
                         + ("" if stage.bodies else " (no prim has PhysicsRigidBodyAPI)"))
    total = combine(counted, frame="world", validate=False)
    out = RobotMassProperties(stage.path, "usd", "world", {}, rows, total, notes)
    out.articulations = {}
    for root, members in stage.articulations.items():
        parts = [rows[i].props for i in members if rows[i].mass > 0]
        out.articulations[root] = {"bodies": [rows[i].name for i in members],
                                   "total": combine(parts, frame="world", validate=False) if parts else None}
    return out


__all__ = ["stage_mass_properties", "body_mass", "collider_solid", "collider_part", "sum_parts", "jacobi_principal",
           "principal_axes_matrix", "to_world_si", "is_usd_path", "SOURCES", "UNSET_TOLERANCE"]
