"""Mass properties of a link from its own geometry, in the link frame.

Each shape is a uniform solid (primitives in closed form, meshes by the exact mesh
kernel) placed at its pose; the shapes are summed as if they did not overlap, which is how
MuJoCo's ``inertiafromgeom`` and most CAD exports treat them.  With ``mass=`` the result is
scaled to that total mass (the declared one, when checking a file).
"""

from __future__ import annotations

import logging
import math
import warnings

import numpy as np

from .._core.errors import InertiaError, MeshError
from ..geometry.mesh_io import SUPPORTED_EXTENSIONS
from ..geometry.shapes import BOX_CORNER_SIGNS as CORNER_SIGNS
from .mujoco_inertia import MUJOCO_REFUSES_MESH

#: geometry used when a link has both: collision first (it is what the simulator sees)
ROLES = ("collision", "visual")


#: note code: a mesh of overlapping closed parts, summed as MuJoCo sums it
SUMMED_OVERLAP = "mesh_overlapping_shells"


def mujoco_mesh_arrays(params: dict, mesh_units: str = "m"):
    """Vertices and faces of an MJCF mesh asset as MuJoCo's compiler holds them.

    File coordinates rounded to float32 (MuJoCo stores them so), then ``refpos``/
    ``refquat`` and ``scale`` applied in double; an OBJ file read as MuJoCo reads it
    (``load_mesh(polygons="mujoco")``); a mesh given by vertices alone gets its convex hull as
    faces, as in MuJoCo.  A mirroring scale reverses the winding.  In ``exact`` mode MuJoCo's
    refusal of inconsistently wound faces is raised (:func:`.mujoco_inertia.check_orientation`).
    """
    from .._core.rotations import quat_normalize, quat_to_matrix
    from .mujoco_inertia import check_orientation, hull_faces

    if params.get("path") is not None:
        v, f = _load_cached(params["path"], mesh_units, "mujoco")
    elif params.get("vertices") is not None:
        v, f = params["vertices"], params.get("faces")
    else:
        raise InertiaError(f"mesh {params.get('uri')!r} not found")
    v = np.asarray(v, np.float32).astype(float)
    if f is not None and params.get("mujoco_inertia") == "exact":
        check_orientation(v, f)
    v = v - np.asarray(params.get("refpos", (0, 0, 0)), float)
    q = np.asarray(params.get("refquat", (1, 0, 0, 0)), float)
    if not np.array_equal(q, [1, 0, 0, 0]):
        v = v @ quat_to_matrix(quat_normalize(q))
    scale = np.asarray(params.get("scale", (1, 1, 1)), float)
    v = v * scale
    if f is None:
        f = hull_faces(v)
    elif np.prod(np.sign(scale)) < 0:
        f = f[:, ::-1]
    return v, np.asarray(f, np.int64)


#: meshes read by the robot checks, by (path, size, mtime, units): a robot uses a mesh in
#: several places (visual and collision, a fitted primitive, the bounds)
_MESH_CACHE: dict = {}
_MESH_CACHE_SIZE = 64


#: what the mesh reader's dependencies said while reading a file (trimesh logs a traceback for a
#: COLLADA texture it cannot load), by path: one line each, reported as a note on the shape
_MESH_MESSAGES: dict = {}


class _Collect(logging.Handler):
    """A logging handler that keeps each record as one line (its message and exception, no traceback)."""

    def __init__(self, lines: list):
        super().__init__(logging.WARNING)
        self.lines = lines

    def emit(self, record) -> None:
        line = record.getMessage().strip().splitlines()[0] if record.getMessage().strip() else record.levelname
        if record.exc_info and record.exc_info[1] is not None:
            line += f" ({type(record.exc_info[1]).__name__}: {str(record.exc_info[1]).splitlines()[0][:160]})"
        if line not in self.lines:
            self.lines.append(line)


def _load_quietly(path, mesh_units: str, polygons: str):
    """:func:`~inertia.geometry.mesh_io.load_mesh`, with trimesh's log records kept as lines in
    :data:`_MESH_MESSAGES` instead of tracebacks on stderr."""
    from ..geometry.mesh_io import load_mesh

    lines: list = []
    logger = logging.getLogger("trimesh")
    handler, propagate = _Collect(lines), logger.propagate
    logger.addHandler(handler)
    logger.propagate = False
    try:
        return load_mesh(path, units=mesh_units, polygons=polygons)
    finally:
        logger.removeHandler(handler)
        logger.propagate = propagate
        if lines:
            _MESH_MESSAGES[str(path)] = lines


def mujoco_refusal(geom, mesh_units: str = "m") -> str | None:
    """Why MuJoCo's compiler refuses the mesh of an MJCF ``geom`` before any integral: its faces
    inconsistently wound in ``exact`` mode (the model then does not load, whatever the body's
    inertial); None otherwise (the integrals' refusals come with the geom's inertia)."""
    p = geom.params
    if geom.kind != "mesh" or p.get("mujoco_inertia") != "exact" or "error" in p:
        return None
    try:
        mujoco_mesh_arrays(p, mesh_units)
    except InertiaError as exc:
        return str(exc) if exc.code == MUJOCO_REFUSES_MESH else None
    return None


def mesh_messages(geom) -> list:
    """What the mesh reader's dependencies said about the geometry's mesh file (see :data:`_MESH_MESSAGES`)."""
    path = geom.params.get("path") if geom.kind == "mesh" else None
    return _MESH_MESSAGES.get(str(path), []) if path is not None else []


def _load_cached(path, mesh_units: str, polygons: str = "shorter"):
    """The mesh file's arrays, cached; OBJ polygons as ``load_mesh(polygons=)`` makes them: by
    default fanned, quadrilaterals split along their shorter diagonal as MuJoCo splits them (the
    exact solid); "mujoco" for what MuJoCo's compiler integrates."""
    if path.suffix.lower() != ".obj":
        polygons = "shorter"  # one reading of other formats
    try:
        st = path.stat()
        key = (str(path), st.st_size, st.st_mtime_ns, mesh_units, polygons)
    except OSError:
        return _load_quietly(path, mesh_units, polygons)
    if key not in _MESH_CACHE:
        if len(_MESH_CACHE) >= _MESH_CACHE_SIZE:
            _MESH_CACHE.pop(next(iter(_MESH_CACHE)))
        v, f = _load_quietly(path, mesh_units, polygons)
        v.setflags(write=False)
        f.setflags(write=False)
        _MESH_CACHE[key] = (v, f)
    return _MESH_CACHE[key]


def shape_properties(geom, *, density: float = 1000.0, mesh_units: str = "m", simulator: bool = False):
    """MassProperties of one :class:`~inertia.robots.model.Geometry` in the link frame.

    ``simulator=True``: what the simulator computes where it differs from the exact solid
    (MJCF meshes in their ``<mesh inertia>`` mode, MuJoCo's ellipsoid shell:
    :mod:`inertia.robots.mujoco_inertia`); otherwise the exact uniform solid (or shell).
    Raises InertiaError (with a message naming the shape) when it cannot be computed.
    """
    from ..massprops import primitives

    rho = geom.density if geom.density is not None else density
    k, p = geom.kind, geom.params
    shell = bool(p.get("shell", False))
    kind = "shell" if shell else "solid"
    if "error" in p:
        raise InertiaError(p["error"])
    if k == "box":
        props = primitives.box(tuple(p["size"]), density=rho, kind=kind)
    elif k == "sphere":
        props = primitives.sphere(p["radius"], density=rho, kind=kind)
    elif k == "cylinder":
        props = primitives.cylinder(p["radius"], p["length"], density=rho, kind=kind)
    elif k == "capsule":
        props = primitives.capsule(p["radius"], p["length"], density=rho, kind=kind)
    elif k == "ellipsoid" and shell and simulator:
        props = _mujoco_ellipsoid_shell(p["semi_axes"], rho, geom.mass)
    elif k == "ellipsoid":
        props = primitives.ellipsoid(tuple(p["semi_axes"]), density=rho, kind=kind)
    elif k == "mesh" and simulator and p.get("mujoco_inertia") is not None:
        props = _mujoco_mesh(p, rho, mesh_units)
    elif k == "mesh":
        props = _solid_mesh(p, rho, mesh_units)
    else:
        raise InertiaError(f"geometry {k!r} is not supported")
    if geom.mass is not None:
        props = props.with_mass(geom.mass)
    return props.transformed(geom.R_link_geom, geom.p_link_geom)


def _solid_mesh(p: dict, rho: float, mesh_units: str):
    """The exact uniform solid of a mesh file (closed parts that overlap are summed)."""
    from ..massprops.mesh import mesh_properties

    path = p.get("path")
    if path is None and p.get("vertices") is not None:
        vertices, faces = mujoco_mesh_arrays(p, mesh_units)
        return mesh_properties(vertices, faces, density=rho, name=p.get("where", "mesh"))
    if path is None:
        raise InertiaError(f"mesh {p.get('uri')!r} not found")
    if path.suffix.lower() not in SUPPORTED_EXTENSIONS:
        raise InertiaError(f"mesh {path.name}: format {path.suffix} is not supported for inertia")
    vertices, faces = _load_cached(path, mesh_units)
    vertices = vertices * np.asarray(p.get("scale", (1, 1, 1)), float)
    if np.prod(np.sign(p.get("scale", (1, 1, 1)))) < 0:  # a mirroring scale turns the winding inside out
        faces = faces[:, ::-1]
    return summed_solid(vertices, faces, density=rho, name=str(path))


def summed_solid(vertices, faces, *, density: float, name: str):
    """The uniform solid of a mesh as simulators integrate it: closed parts that overlap, or a
    shell through itself, are summed (MuJoCo and PhysX integrate the signed volume), and the
    result's findings say so; any other defect is refused.  The self-crossing certificate alone:
    a shell it cannot prove is summed too (MuJoCo integrates whatever the mesh holds)."""
    from ..massprops.mesh import mesh_properties

    try:
        return mesh_properties(vertices, faces, density=density, name=name, self_crossing="certificate")
    except MeshError as exc:
        errors = {d.code for d in exc.report.errors} if exc.report is not None else set()
        if not errors or not errors <= {"overlapping_shells", "self_intersecting"}:
            raise
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")   # the accepted defects are in the result's findings
        return mesh_properties(vertices, faces, density=density, name=name, on_defect="warn",
                               self_crossing="certificate")


def _mujoco_mesh(p: dict, rho: float, mesh_units: str):
    """What MuJoCo's compiler computes for a mesh geom in its asset's inertia mode."""
    from ..massprops.properties import MassProperties
    from .mujoco_inertia import check_mesh_inertia, mesh_inertia

    if p.get("path") is not None and p["path"].suffix.lower() not in SUPPORTED_EXTENSIONS:
        raise InertiaError(f"mesh {p['path'].name}: format {p['path'].suffix} is not supported for inertia")
    v, f = mujoco_mesh_arrays(p, mesh_units)
    measure, com, inertia = mesh_inertia(v, f, p["mujoco_inertia"])
    check_mesh_inertia(np.linalg.eigvalsh(inertia))
    shell = p["mujoco_inertia"] == "shell"
    return MassProperties(rho * measure, com, rho * inertia, volume=math.nan if shell else measure, validate=False)


def _mujoco_ellipsoid_shell(semi_axes, rho: float, mass):
    from ..massprops.properties import MassProperties
    from .mujoco_inertia import ellipsoid_shell

    area, _ = ellipsoid_shell(semi_axes, 1.0)
    m = mass if mass is not None else rho * area
    _, moments = ellipsoid_shell(semi_axes, m)
    return MassProperties(m, np.zeros(3), np.diag(moments), validate=False)


def link_geometry_properties(link, *, role: str | None = None, density: float = 1000.0, mass=None,
                             mesh_units: str = "m", simulator: bool = False):
    """``(MassProperties or None, role used, problems)`` from the link's geometry.

    ``role=None`` uses the collision shapes, or the visual ones when there are none.
    ``problems`` lists ``(code, message)`` for shapes that could not be used (``mesh_not_found``,
    ``mujoco_refuses_mesh``, ``geometry_unusable``); any such shape makes the result None (a
    partial sum would be silently wrong).  With a result, the list holds the notes on it
    (:data:`SUMMED_OVERLAP`: a mesh whose closed parts overlap, summed as the simulator sums it).
    """
    roles = [role] if role else list(ROLES)
    for r in roles:
        shapes = [g for g in link.geometries if g.role == r]
        if not shapes:
            continue
        total, problems, notes = None, [], []
        for g in shapes:
            try:
                part = shape_properties(g, density=density, mesh_units=mesh_units, simulator=simulator)
            except InertiaError as exc:
                missing = g.kind == "mesh" and g.params.get("path") is None
                said = f" (its reader said: {'; '.join(mesh_messages(g))})" if mesh_messages(g) else ""
                code = "mesh_not_found" if missing else "mesh_unreadable" if g.params.get("unreadable") else \
                    exc.code if exc.code == MUJOCO_REFUSES_MESH else "geometry_unusable"
                problems.append((code, f"line {g.line}: {r} {g.kind}: {_short(exc, g)}{said}"))
                continue
            total = part if total is None else total + part
            if mesh_messages(g):
                notes.append(("mesh_reader_message", f"line {g.line}: {r} mesh {g.params.get('path')}: its reader "
                              f"said: {'; '.join(mesh_messages(g))} (the triangles were read)"))
            if any(f.code in ("overlapping_shells", "self_intersecting") for f in part.findings):
                notes.append((SUMMED_OVERLAP, f"line {g.line}: {r} mesh {g.params.get('path')}: closed parts of "
                              "the mesh overlap; summed as the simulator sums them (the overlap counts twice)"))
        if problems:
            return None, r, problems
        if total is not None and mass is not None:
            total = total.with_mass(mass)
        return total, r, notes
    return None, None, []


def _short(exc, geom) -> str:
    """One line for a mesh that is not a solid: its defect codes, and where the details are.

    The full defect report runs to many lines per mesh; a robot with a dozen such meshes
    would bury its real findings, so the check names the codes only.
    """
    report = getattr(exc, "report", None)
    path = geom.params.get("path") if geom.kind == "mesh" else None
    if report is None or path is None or not report.codes:
        return str(exc)
    name = geom.params.get("uri") or path
    return (f"mesh {str(name)!r} is not a closed, consistently wound solid "
            f"({', '.join(dict.fromkeys(report.codes))}); details: inertia props {path}")


def geometry_bounds(link, *, mesh_units: str = "m"):
    """Axis-aligned bounds ``(lo, hi)`` of the link's shapes in the link frame, or None."""
    pts = []
    for g in link.geometries:
        R, t = g.R_link_geom, g.p_link_geom
        p = g.params
        if "error" in p:
            continue
        if g.kind == "box":
            h = np.asarray(p["size"]) / 2
            corners = CORNER_SIGNS * h
        elif g.kind == "sphere":
            corners = CORNER_SIGNS * p["radius"]
        elif g.kind in ("cylinder", "capsule"):
            hz = p["length"] / 2 + (p["radius"] if g.kind == "capsule" else 0.0)
            r = p["radius"]
            corners = CORNER_SIGNS * (r, r, hz)
        elif g.kind == "ellipsoid":
            corners = CORNER_SIGNS * p["semi_axes"]
        elif g.kind == "mesh" and (p.get("vertices") is not None or (
                p.get("path") is not None and p["path"].suffix.lower() in SUPPORTED_EXTENSIONS)):
            try:
                if p.get("mujoco_inertia") is not None:
                    corners, _ = mujoco_mesh_arrays(p, mesh_units)
                else:
                    corners = _load_cached(p["path"], mesh_units)[0] * np.asarray(p.get("scale", (1, 1, 1)), float)
            except InertiaError:
                continue
        else:
            continue
        pts.append(corners @ R.T + t)
    if not pts:
        return None
    allp = np.concatenate(pts)
    return allp.min(axis=0), allp.max(axis=0)
