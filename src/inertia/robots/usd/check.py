"""Check a stage's rigid bodies: the findings of every robot format, and OpenUSD's own.

Errors (stable codes):

* ``non_positive_mass``, ``not_positive_definite``, ``triangle_inequality``: the body's mass
  properties as UsdPhysics resolves them (:mod:`.mass`) are not physical;
* ``below_simulator_floor``: a dynamic body's mass or a principal moment is positive but below
  1e-15 (kg, kg m^2);
* ``negative_mass``: an authored ``physics:mass`` below 0, which every reader takes as "not set";
* ``non_unit_principal_axes``: a ``principalAxes`` quaternion whose norm is not 1 (NVIDIA's
  asset validator refuses it; usd-core builds a matrix that is no rotation from it);
* ``mass_fallback``: a dynamic body with no mass and no collider: UsdPhysics' default 1 kg.

Warnings:

* ``inertia_below_usd_tolerance``: an authored ``diagonalInertia`` whose norm is at most 1e-5
  in stage units, which usd-core's ComputeMassProperties reads as not set (the tensor then comes
  from the colliders, or a 0.1 m sphere);
* ``mass_without_inertia`` / ``inertia_without_mass``: one authored without the other;
* ``default_density``: the mass comes from colliders at the default 1000 kg/m^3, nothing authored
  (what converters leave for a link without an inertial);
* ``hull_differs``: a dynamic body's mass comes from a triangle mesh that PhysX simulates as an
  approximation (its convex hull for ``none`` and ``convexHull``), and the two differ by more than
  :data:`HULL_RTOL` in mass or a principal moment;
* ``mass_api_not_applied``: mass attributes authored on a prim without ``PhysicsMassAPI`` (ignored);
* ``mesh_not_solid``: a mesh collider that bounds no solid (open, inconsistently wound): its
  convex hull stands in for it (what PhysX cooks for a dynamic body);
* ``geometry_unusable``: a collider whose shape cannot be integrated.

Stage warnings: ``missing_units`` (``metersPerUnit`` or ``kilogramsPerUnit`` not authored: the
fallbacks are 0.01 m and 1 kg), ``mass_on_non_physics_prim`` (a ``PhysicsMassAPI`` on a prim that
is neither a rigid body nor a collider, e.g. a visual mesh: physics ignores it).
"""

from __future__ import annotations

import numpy as np

from ..._core.errors import InertiaError
from ..._core.tolerances import SIMULATOR_MIN_VALUE
from ..check import CheckReport, LinkReport
from .mass import UNSET_TOLERANCE, body_mass, is_set, to_world_si
from .stage import read_stage

#: relative difference in mass or a principal moment between a mesh and PhysX's approximation of
#: it above which ``hull_differs`` is reported
HULL_RTOL = 0.05
#: how far from 1 a principalAxes quaternion's norm may be (float32 rounding of a unit quaternion
#: stays within 3e-7)
QUAT_NORM_ATOL = 1e-6


def _attr_findings(rep, where: str, attrs, tol: float) -> None:
    if attrs.authored and not attrs.applied:
        rep.add("mass_api_not_applied", "mass attributes are authored but PhysicsMassAPI is not applied: usd-core "
                "and PhysX ignore them", where=where)
        return
    if attrs.mass is not None and attrs.mass < 0:
        rep.add("negative_mass", f"physics:mass = {attrs.mass:g} is negative: every reader takes it as not set (0 "
                "and below mean \"not set\")", where=where, values={"mass": attrs.mass})
    q = attrs.principal_axes
    if q is not None and is_set(q, tol) and abs(float(np.linalg.norm(q)) - 1.0) > QUAT_NORM_ATOL:
        rep.add("non_unit_principal_axes", (
            f"physics:principalAxes {np.round(q, 7).tolist()} has norm {np.linalg.norm(q):.7g}, not 1: "
            "NVIDIA's asset validator refuses it and usd-core turns it into a matrix that is no rotation; "
            "'inertia fix' normalises it"), where=where, values={"norm": float(np.linalg.norm(q))})
    d = attrs.diagonal_inertia
    if d is not None and np.any(d != 0) and not is_set(d, tol):
        rep.add("inertia_below_usd_tolerance", (
            f"physics:diagonalInertia {np.array2string(d, precision=4)} has norm {np.linalg.norm(d):.3g}, "
            f"at most {UNSET_TOLERANCE:g} (stage units): usd-core's ComputeMassProperties reads it as not set"),
            where=where, values={"norm": float(np.linalg.norm(d))})


def _body_findings(stage, i: int, rep, tol: float) -> None:
    from ...massprops.validity import check_inertia

    body = stage.bodies[i]
    where = body.path
    _attr_findings(rep, where, body.mass, tol)
    for c in body.colliders:
        _attr_findings(rep, c.path, c.mass, tol)
    a = body.mass if body.mass.applied else None
    has_m = bool(a and a.mass is not None and a.mass > 0)
    has_I = bool(a and is_set(a.diagonal_inertia, tol))
    try:
        bm = body_mass(stage, i, tol=tol)
    except InertiaError as exc:
        rep.add("geometry_unusable", f"{exc}; its mass properties cannot be computed", where=where,
                severity="warning")
        return
    props = to_world_si(stage, body, bm)
    if has_m and not has_I and (a.diagonal_inertia is None or not np.any(a.diagonal_inertia)):
        how = ("its colliders' inertia scaled to that mass" if body.colliders else
               f"usd-core's 0.1 m sphere, {bm.I_B[0, 0]:.3g} about each axis (stage units)")
        rep.add("mass_without_inertia", f"physics:mass is authored without physics:diagonalInertia: the inertia "
                f"is {how}", where=where)
    if has_I and not has_m:
        rep.add("inertia_without_mass", f"physics:diagonalInertia is authored without physics:mass: the mass "
                f"({props.mass:.6g} kg) comes from the colliders while the inertia stays as authored", where=where)
    if bm.source == "fallback" and body.dynamic:
        rep.add("mass_fallback", "no mass is authored and the body has no collider: UsdPhysics' default 1 kg is "
                "used (usd-core returns -1)", where=where)
    if bm.source == "default_density":
        rep.add("default_density", f"no mass or density is authored: the mass {props.mass:.6g} kg is its "
                "colliders' volume at the default 1000 kg/m^3", where=where)
    rep.findings += [v.replace(where=where) for v in check_inertia(props.inertia_com, props.mass)]
    if body.dynamic and not rep.errors:
        w = np.linalg.eigvalsh(props.inertia_com)
        if 0 < props.mass < SIMULATOR_MIN_VALUE or 0 < w[0] < SIMULATOR_MIN_VALUE:
            rep.add("below_simulator_floor", (
                f"mass {props.mass:.3g} kg, principal moments {', '.join(f'{x:.3g}' for x in w)} kg m^2: "
                f"below {SIMULATOR_MIN_VALUE:g}, the least a simulator accepts for a moving body"), where=where,
                values={"mass": props.mass, "moments": w})
    for part in bm.parts:
        if part.shape.startswith("hull ("):
            rep.add("mesh_not_solid", (
                f"the mesh collider is not a closed solid ({part.shape.split(': ', 1)[-1].rstrip(')')}): "
                "its convex hull stands in for it, as PhysX cooks it for a dynamic body"), where=part.path)
    if body.dynamic and bm.parts and any(c.kind == "mesh" for c in body.colliders):
        _hull_finding(stage, i, bm, rep, tol)


def _hull_finding(stage, i: int, exact, rep, tol: float) -> None:
    """``hull_differs`` when PhysX's approximation of the body's meshes changes its mass properties."""
    body = stage.bodies[i]
    physx = body_mass(stage, i, physx=True, tol=tol)
    if all(p.shape == "exact" for p in physx.parts):
        return
    m0, m1 = exact.mass, physx.mass
    w0, w1 = np.linalg.eigvalsh(exact.I_B), np.linalg.eigvalsh(physx.I_B)
    dm = abs(m1 - m0) / m0 if m0 > 0 else 0.0
    dI = float(np.max(np.abs(w1 - w0) / np.maximum(np.abs(w0), 1e-300)))
    if max(dm, dI) > HULL_RTOL:
        kinds = ", ".join(sorted({p.shape for p in physx.parts if p.shape != "exact"}))
        kg = stage.kilograms_per_unit
        rep.add("hull_differs", (
            f"PhysX simulates its triangle mesh as {kinds}: mass {m1 * kg:.6g} kg (the solid: "
            f"{m0 * kg:.6g} kg, {100 * dm:.1f} % apart), principal moments up to {100 * dI:.1f} % apart; author "
            "the body's mass, inertia and COM, or a convex collider"), where=body.path,
            values={"mass_relative": dm, "moment_relative": dI})


def check_stage(stage, *, tol: float = UNSET_TOLERANCE) -> CheckReport:
    """The findings for every rigid body of a stage (a path or a read :class:`~.stage.Stage`)."""
    if not hasattr(stage, "bodies"):
        stage = read_stage(stage)
    report = CheckReport(str(stage.path), [])
    for i, body in enumerate(stage.bodies):
        rep = LinkReport(body.label if [b.label for b in stage.bodies].count(body.label) == 1 else body.path, None)
        _body_findings(stage, i, rep, tol)
        report.links.append(rep)
    missing = [name for name, done in zip(("metersPerUnit", "kilogramsPerUnit"), stage.units_authored) if not done]
    if missing:
        report.add("missing_units", (
            f"{' and '.join(missing)} not authored: the fallbacks are 0.01 m per unit (centimetres) and "
            "1 kg per unit; author them in the root layer's metadata"), where=str(stage.path))
    for path, attrs in stage.stray_mass:
        report.add("mass_on_non_physics_prim", (
            f"carries {'PhysicsMassAPI' if attrs.applied else 'mass attributes'} but is neither a rigid body "
            "nor a collider: physics ignores it (put the mass on the body or on a collider)"), where=str(path))
    if not stage.bodies:
        report.add("no_links", "no prim has PhysicsRigidBodyAPI: nothing to check", where=str(stage.path))
    return report
