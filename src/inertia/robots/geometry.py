"""Mass properties of a link from its own geometry, in the link frame.

Each shape is a uniform solid (primitives in closed form, meshes by the exact mesh
kernel) placed at its pose; the shapes are summed as if they did not overlap, which is how
MuJoCo's ``inertiafromgeom`` and most CAD exports treat them.  With ``mass=`` the result is
scaled to that total mass (the declared one, when checking a file).
"""

from __future__ import annotations

import warnings

import numpy as np

from .._core.errors import InertiaError, MeshError
from ..geometry.mesh_io import SUPPORTED_EXTENSIONS
from ..geometry.shapes import BOX_CORNER_SIGNS as CORNER_SIGNS

#: geometry used when a link has both: collision first (it is what the simulator sees)
ROLES = ("collision", "visual")


#: note code: a mesh of overlapping closed parts, summed as MuJoCo sums it
SUMMED_OVERLAP = "mesh_overlapping_shells"


def shape_properties(geom, *, density: float = 1000.0, mesh_units: str = "m"):
    """MassProperties of one :class:`~inertia.robots.model.Geometry` in the link frame.

    Raises InertiaError (with a message naming the shape) when it cannot be computed.
    """
    from ..geometry.mesh_io import load_mesh
    from ..massprops import primitives
    from ..massprops.mesh import mesh_properties

    rho = geom.density if geom.density is not None else density
    k, p = geom.kind, geom.params
    if k == "box":
        props = primitives.box(tuple(p["size"]), density=rho)
    elif k == "sphere":
        props = primitives.sphere(p["radius"], density=rho)
    elif k == "cylinder":
        props = primitives.cylinder(p["radius"], p["length"], density=rho)
    elif k == "capsule":
        props = primitives.capsule(p["radius"], p["length"], density=rho)
    elif k == "ellipsoid":
        props = primitives.ellipsoid(tuple(p["semi_axes"]), density=rho)
    elif k == "mesh":
        path = p.get("path")
        if path is None:
            raise InertiaError(f"mesh {p.get('uri')!r} not found")
        if path.suffix.lower() not in SUPPORTED_EXTENSIONS:
            raise InertiaError(f"mesh {path.name}: format {path.suffix} is not supported for inertia")
        vertices, faces = load_mesh(path, units=mesh_units)
        vertices = vertices * np.asarray(p.get("scale", (1, 1, 1)), float)
        if np.prod(np.sign(p.get("scale", (1, 1, 1)))) < 0:  # a mirroring scale turns the winding inside out
            faces = faces[:, ::-1]
        try:
            props = mesh_properties(vertices, faces, density=rho, name=str(path))
        except MeshError as exc:
            if exc.report is None or set(exc.report.codes) != {"overlapping_shells"}:
                raise
            # closed parts that overlap: the simulator sums them (MuJoCo integrates the signed
            # volume), so the comparison does too; the caller notes it (SUMMED_OVERLAP)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                props = mesh_properties(vertices, faces, density=rho, name=str(path), on_defect="warn")
    else:
        raise InertiaError(f"geometry {k!r} is not supported")
    if geom.mass is not None:
        props = props.with_mass(geom.mass)
    return props.transformed(geom.R_link_geom, geom.p_link_geom)


def link_geometry_properties(link, *, role: str | None = None, density: float = 1000.0, mass=None,
                             mesh_units: str = "m"):
    """``(MassProperties or None, role used, problems)`` from the link's geometry.

    ``role=None`` uses the collision shapes, or the visual ones when there are none.
    ``problems`` lists ``(code, message)`` for shapes that could not be used; any such
    shape makes the result None (a partial sum would be silently wrong).  With a result,
    the list holds the notes on it (:data:`SUMMED_OVERLAP`: a mesh whose closed parts
    overlap, summed as the simulator sums it).
    """
    roles = [role] if role else list(ROLES)
    for r in roles:
        shapes = [g for g in link.geometries if g.role == r]
        if not shapes:
            continue
        total, problems, notes = None, [], []
        for g in shapes:
            try:
                part = shape_properties(g, density=density, mesh_units=mesh_units)
            except InertiaError as exc:
                problems.append(("geometry_unusable", f"line {g.line}: {r} {g.kind}: {_short(exc, g)}"))
                continue
            total = part if total is None else total + part
            if any("overlapping_shells accepted" in w for w in part.warnings):
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
    return (f"mesh {path} is not a closed, consistently wound solid "
            f"({', '.join(dict.fromkeys(report.codes))}); details: inertia props {path}")


def geometry_bounds(link, *, mesh_units: str = "m"):
    """Axis-aligned bounds ``(lo, hi)`` of the link's shapes in the link frame, or None."""
    from ..geometry.mesh_io import load_mesh

    pts = []
    for g in link.geometries:
        R, t = g.R_link_geom, g.p_link_geom
        p = g.params
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
        elif g.kind == "mesh" and p.get("path") is not None and p["path"].suffix.lower() in SUPPORTED_EXTENSIONS:
            try:
                v, _ = load_mesh(p["path"], units=mesh_units)
            except InertiaError:
                continue
            corners = v * np.asarray(p.get("scale", (1, 1, 1)), float)
        else:
            continue
        pts.append(corners @ R.T + t)
    if not pts:
        return None
    allp = np.concatenate(pts)
    return allp.min(axis=0), allp.max(axis=0)
