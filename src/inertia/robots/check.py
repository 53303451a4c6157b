"""Check every link's declared inertial: errors that break simulators, warnings that smell.

Errors (codes are stable; other tools rely on them):

* ``non_positive_mass``: mass <= 0 (or not finite);
* ``not_symmetric``: the tensor is not symmetric (only possible where a format stores all nine);
* ``not_positive_definite``: a principal moment <= 0;
* ``triangle_inequality``: I1 + I2 < I3 (the message gives the margin);
* ``mujoco_refuses_mesh``: an MJCF mesh MuJoCo's compiler refuses (faces inconsistently wound in
  ``inertia="exact"``; for a body whose inertia comes from its geoms, also a mesh of no area or
  volume, or a negative volume): the model does not load.

Warnings:

* ``com_outside_geometry``: the center of mass lies outside the bounding box of the link's
  shapes (plus 5 % of its diagonal);
* ``geometry_mismatch``: the tensor computed from the link's own geometry at the declared
  mass disagrees with the declared one: a principal-moment ratio outside [1/3, 3], or
  principal axes more than 45 degrees apart (visual shapes are used first: they describe the
  body, while collision shapes are often simplified) (axes compared only where the moments are
  distinct by more than 10 %);
* ``legacy_mesh_inertia``: an MJCF body whose inertia MuJoCo infers from meshes in its
  default ``inertia="legacy"`` mode differs from the exact solid by more than 5 % in mass or
  a principal moment (legacy overcounts non-convex meshes);
* ``mesh_not_found``, ``mesh_unreadable`` (a FIFO, a device, a folder...), ``unsupported_geometry``,
  ``unsupported_pose``: the reader could not use part of the file; the rest of the check goes on.

Notes (``notes`` in the JSON): ``geometry_unusable`` when the shapes exist but cannot be
integrated (an open or non-manifold mesh, an unsupported mesh format): the comparison with
the geometry is skipped, which says nothing about the declared inertial.

Links without an inertial are massless frames: neither an error nor a warning.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._core.findings import Finding
from .._core.tolerances import SIMULATOR_MIN_VALUE
from .geometry import geometry_bounds, link_geometry_properties, mujoco_refusal
from .mujoco_inertia import MUJOCO_REFUSES_MESH

#: the validity checks' tolerance, relative to the trace: the rounding of the principal moments
#: of a tensor written in float64 (a few ulps), so that a moment of 1e-12 beside 1 (which MuJoCo
#: compiles) is positive, while a triangle inequality broken by 1e-13 (which MuJoCo refuses) is
#: broken.  MuJoCo's absolute floor for moving bodies is the tree checks' (:mod:`.floors`).
ROUNDING_RTOL = 8 * float(np.finfo(float).eps)

MOMENT_RATIO_LIMIT = 3.0
AXIS_ANGLE_LIMIT_DEG = 45.0
COM_MARGIN = 0.05


class _Findings:
    """A list of findings, with views by severity."""

    findings: list

    def add(self, code: str, message: str, *, where: str = "", severity: str = "", values=None) -> None:
        self.findings.append(Finding(code, message, severity=severity, where=where, values=values or {}))

    def _of(self, severity: str) -> list:
        return [f for f in self.findings if f.severity == severity]

    errors = property(lambda self: self._of("error"), doc="The findings of severity error.")
    warnings = property(lambda self: self._of("warning"), doc="The findings of severity warning.")
    notes = property(lambda self: self._of("note"), doc="The findings of severity note (what was not checked).")


@dataclass
class LinkReport(_Findings):
    """One link's (body's) findings; ``line`` where it is declared."""

    name: str
    line: int | None
    findings: list = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"name": self.name, "line": self.line, "findings": [f.to_dict() for f in self.findings]}


@dataclass
class CheckReport(_Findings):
    """Every link's report, and the findings about the file as a whole (no links, joints that
    cannot be read, what the reader read although other tools would not)."""

    file: str
    links: list
    #: links with no mass that simulators accept (fixed joints, or welded to a body with mass)
    massless_frames: list = field(default_factory=list)
    findings: list = field(default_factory=list)

    @property
    def n_errors(self) -> int:
        return len(self.errors) + sum(len(lk.errors) for lk in self.links)

    @property
    def n_warnings(self) -> int:
        return len(self.warnings) + sum(len(lk.warnings) for lk in self.links)

    def to_dict(self) -> dict:
        return {"file": self.file, "links": [lk.to_dict() for lk in self.links],
                "massless_frames": list(self.massless_frames), "findings": [f.to_dict() for f in self.findings]}


def reader_finding(code: str, text: str, severity: str = "warning") -> Finding:
    """A reader's ``(code, "file:line: message")`` note as a finding (location in ``where``)."""
    head, sep, rest = text.partition(": ")
    if sep and " " not in head:
        return Finding(code, rest, severity=severity, where=head)
    return Finding(code, text, severity=severity)


def inertia_violations(inertia, mass=None) -> list:
    """:func:`~inertia.massprops.validity.check_inertia` at :data:`ROUNDING_RTOL`: the one
    judgement of a tensor that ``check`` and ``fix`` share."""
    from ..massprops.validity import check_inertia

    return check_inertia(inertia, mass, rtol=ROUNDING_RTOL)


def flip_products(inertia) -> np.ndarray:
    """The tensor with its off-diagonal entries negated (tensor elements <-> CAD products)."""
    I = np.asarray(inertia, float)
    with np.errstate(over="ignore", invalid="ignore"):   # near the float limit: inf, refused by the checks
        return 2 * np.diag(np.diag(I)) - I


def check_link(link, where: str, *, mesh_units: str = "m", inertial_where: str | None = None,
               warnings: bool = True, compiler: dict | None = None) -> LinkReport:
    """The findings for one link (``where`` is ``file:line`` for messages); ``warnings=False``
    skips the comparisons with the geometry, which give warnings only (the errors are the same).
    ``compiler``: MJCF's ``<compiler>`` mass options for the body (MuJoCo repairs what they cover)."""
    rep = LinkReport(link.name, link.line)
    for code, msg in link.notes:
        rep.findings.append(reader_finding(code, msg))
    inertial = link.inertial
    if link.inertia_from_geoms:  # MJCF: MuJoCo computes this body's inertia from its geoms
        return _check_from_geoms(link, rep, where, mesh_units, warnings)
    if inertial is None:
        return rep
    at = f"{inertial_where or where}: link {link.name!r}"  # errors point at the <inertial> itself
    m = inertial.mass
    if m == 0 and not np.any(inertial.inertia_com_inertial):
        return rep  # a massless frame: an idiom, unless it moves alone (the tree checks, robots.floors)
    if not (math.isfinite(m) and m > 0):
        rep.add("non_positive_mass", f"mass is {m!r} kg with a non-zero tensor; a body needs a positive mass (a "
                "massless frame has mass 0 and a zero tensor)", where=at, values={"mass": m})
    violations = inertia_violations(inertial.inertia_com_inertial)
    hint = ""
    if any(v.code in ("triangle_inequality", "not_positive_definite") for v in violations):
        flipped = flip_products(inertial.inertia_com_inertial)
        if not inertia_violations(flipped) and not np.array_equal(flipped, inertial.inertia_com_inertial):
            hint = ("; with the signs of its products of inertia flipped it is physical: they were probably "
                    "copied from CAD, which lists positive products (this format wants the tensor elements "
                    "ixy = -sum m x y); 'inertia fix --flip-products' flips them")
    for v in violations:
        extra = hint if v.code in ("triangle_inequality", "not_positive_definite") else ""
        rep.findings.append(v.replace(message=v.message + extra, where=at))
    if inertial.form == "fullinertia" and not any(e.code in ("not_positive_definite", "non_finite")
                                                  for e in rep.errors):
        least = float(np.linalg.eigvalsh(0.5 * (inertial.inertia_com_inertial + inertial.inertia_com_inertial.T))[0])
        if not least >= SIMULATOR_MIN_VALUE:  # MuJoCo's rule for fullinertia, moving body or not
            rep.add("not_positive_definite", f"fullinertia's smallest principal moment is {least:.3g} kg m^2, below "
                    f"{SIMULATOR_MIN_VALUE:g}: MuJoCo refuses it (\"inertia must have positive eigenvalues\" in "
                    "fullinertia)", where=at, values={"moment": least, "floor": SIMULATOR_MIN_VALUE})
    if rep.errors and compiler:
        _compiler_repairs(rep, compiler)
    if violations or rep.errors or not warnings:
        return rep  # comparisons with the geometry need a valid tensor

    bounds = geometry_bounds(link, mesh_units=mesh_units)
    if bounds is not None:
        lo, hi = bounds
        with np.errstate(over="ignore", invalid="ignore"):  # shapes near the float limit: an infinite margin
            margin = COM_MARGIN * float(np.linalg.norm(hi - lo))
        c = inertial.com_link
        if np.any(c < lo - margin) or np.any(c > hi + margin):
            rep.add("com_outside_geometry", f"center of mass {np.round(c, 6).tolist()} m lies outside the bounds of "
                    f"the link's shapes {np.round(lo, 6).tolist()} .. {np.round(hi, 6).tolist()} m (link frame)",
                    where=at, values={"com": c, "lo": lo, "hi": hi})
    # compare with the visual shapes when there are any (they describe the body; collision
    # shapes are often simplified stand-ins, like a foot sphere), else with the collision ones
    role = "visual" if any(g.role == "visual" for g in link.geometries) else "collision"
    computed, role, problems = link_geometry_properties(link, role=role, mass=m, mesh_units=mesh_units)
    fallback = ""
    if computed is None and role == "visual" and any(g.role == "collision" and g.kind == "mesh"
                                                     for g in link.geometries):
        # an unusable visual (a .dae, an open mesh) leaves the collision shapes to compare with,
        # when they include a mesh: primitive-only collisions are usually stand-ins (a foot sphere)
        computed, _, collision_problems = link_geometry_properties(link, role="collision", mass=m,
                                                                   mesh_units=mesh_units)
        if computed is not None:
            role, fallback = "collision", "; compared with the collision shapes instead"
        else:
            problems = problems + collision_problems
    for code, msg in problems:  # e.g. an open visual mesh: no comparison, but no verdict on the inertial
        suffix = fallback or ("" if computed is not None else "; geometry comparison skipped")
        if code in ("mesh_not_found", "mesh_unreadable"):  # the reader's warning says it: one message per mesh
            _mark_skipped(rep, msg, suffix, code)
            continue
        rep.add(code, f"{msg}{suffix}", where=at, severity="note")
    if computed is not None:
        from ..massprops.principal import principal_axes

        declared_m, declared_R = principal_axes(inertial.inertia_com)
        comp_m, comp_R = principal_axes(computed.inertia_com)
        ratios = declared_m / comp_m
        worst = float(np.max(np.maximum(ratios, 1 / ratios)))
        angle = _axes_angle(declared_m, declared_R, comp_m, comp_R)
        if worst > MOMENT_RATIO_LIMIT or (angle is not None and angle > AXIS_ANGLE_LIMIT_DEG):
            rep.add("geometry_mismatch", f"declared principal moments {np.array2string(declared_m, precision=4)} "
                    f"kg m^2 vs {np.array2string(comp_m, precision=4)} from its {role} geometry at the declared mass "
                    f"(ratios {np.array2string(ratios, precision=3)}"
                    + (f", principal axes {angle:.0f} deg apart" if angle is not None else "") + ")",
                    where=at, values={"declared_moments": declared_m, "geometry_moments": comp_m,
                                      "axes_angle_deg": angle, "role": role})
    return rep


def _compiler_repairs(rep, compiler: dict) -> None:
    """Errors MuJoCo's compiler repairs become warnings (``compiler_repairs_inertia``): a zero
    mass under ``boundmass``, a moment under ``boundinertia``, a broken triangle inequality under
    ``balanceinertia`` (the moments become their mean)."""
    from .urdf_sdf import floats

    repairs = {"non_positive_mass": floats(compiler["boundmass"], 1, "<compiler>", "boundmass")[0] > 0,
               "not_positive_definite": floats(compiler["boundinertia"], 1, "<compiler>", "boundinertia")[0] > 0,
               "triangle_inequality": compiler["balanceinertia"] == "true"}
    option = {"non_positive_mass": "boundmass", "not_positive_definite": "boundinertia",
              "triangle_inequality": "balanceinertia"}
    errors = rep.errors
    if not all(repairs.get(e.code) for e in errors) or any(e.values.get("mass", 0.0) < 0 for e in errors):
        return  # something MuJoCo refuses remains (a negative mass is refused whatever the bounds)
    rep.findings = [f for f in rep.findings if f.severity != "error"]
    for e in errors:
        rep.add("compiler_repairs_inertia", f"{e.message}; MuJoCo's <compiler "
                f"{option[e.code]}={compiler[option[e.code]]!r}> repairs it when it compiles the model (the file "
                "itself stays invalid for other tools)", where=e.where, values={**e.values, "repairs": e.code})


def _mark_skipped(rep, problem: str, suffix: str, code: str) -> None:
    """Add ``suffix`` to the reader's ``code`` warning (mesh_not_found, mesh_unreadable) for the
    shape ``problem`` names (``"line N: ..."``), instead of a second message about the same mesh."""
    line = problem.split(":", 1)[0].removeprefix("line ").strip()
    for k, w in enumerate(rep.findings):
        if w.code == code and f":{line}: " in f"{w}: " and not w.message.endswith(suffix):
            rep.findings[k] = w.replace(message=w.message + suffix)


def _check_from_geoms(link, rep, where, mesh_units, warnings: bool = True):
    """A body whose inertia MuJoCo takes from its geoms: check what it would compute."""
    at = f"{where}: body {link.name!r}"
    props, _, problems = link_geometry_properties(link, role="collision", mesh_units=mesh_units, simulator=True)
    for code, msg in problems:
        if code == MUJOCO_REFUSES_MESH:  # the model does not load
            rep.add(code, msg, where=at, severity="error")
        else:
            rep.add(code, f"inertia comes from the geoms (inertiafromgeom), but {msg}", where=at, severity="warning")
    if props is not None:
        from ..massprops.validity import check_inertia

        for v in check_inertia(props.inertia_com, props.mass):  # sums of shapes: the default rounding
            rep.findings.append(v.replace(message=f"the inertia computed from its geoms: {v.message}", where=at))
        if link.inertial is not None:
            rep.add("inertial_ignored", "inertiafromgeom=\"true\": the declared <inertial> is replaced by the "
                    "geoms' inertia", where=at)
        if not rep.errors and warnings:
            _compare_legacy(link, props, rep, at, mesh_units)
    return rep


#: relative difference in mass or a principal moment between MuJoCo's legacy mesh inertia and
#: the exact solid above which the check warns (``legacy_mesh_inertia``)
LEGACY_RTOL = 0.05


def _compare_legacy(link, simulated, rep, at, mesh_units) -> None:
    """Warn when MuJoCo's default (legacy) mesh inertia is far from the body's exact solid.

    Legacy counts the volume of pyramids as positive, so a non-convex or open mesh gets more
    mass and inertia than the solid it bounds; the body then simulates heavier than it is.
    """
    meshes = [g for g in link.geometries if g.role == "collision" and g.kind == "mesh"]
    legacy = [g for g in meshes if g.params.get("mujoco_inertia") == "legacy"]
    if not any(g.params.get("mujoco_inertia") in ("legacy", "exact") for g in meshes):
        return  # primitives, convex hulls and shells: what MuJoCo computes is well defined
    solid, _, problems = link_geometry_properties(link, role="collision", mesh_units=mesh_units)
    if solid is None:  # an open or non-manifold mesh: MuJoCo's number bounds no solid
        for code, msg in problems:
            rep.add(code, f"{msg}; MuJoCo still infers mass {simulated.mass:.6g} kg from it (pyramids to a "
                    "centroid), which is not the mass of a solid", where=at, severity="warning")
        return
    if not legacy:
        return
    dm = abs(simulated.mass - solid.mass) / solid.mass
    moments_sim, moments_solid = simulated.principal().moments, solid.principal().moments
    dI = float(np.max(np.abs(moments_sim - moments_solid) / moments_solid))
    if max(dm, dI) > LEGACY_RTOL:
        names = ", ".join(sorted({str(g.params.get("uri") or g.params.get("where")) for g in legacy}))
        rep.add("legacy_mesh_inertia", (
            f"MuJoCo's default mesh inertia (legacy) gives mass {simulated.mass:.6g} kg and principal moments "
            f"{np.array2string(moments_sim, precision=4)} kg m^2, the exact solid {solid.mass:.6g} kg and "
            f"{np.array2string(moments_solid, precision=4)} ({100 * dm:.0f} % in mass, up to {100 * dI:.0f} % in "
            f"a moment): legacy overcounts non-convex meshes ({names}); set inertia=\"exact\" (closed meshes) or "
            "\"convex\" on the <mesh> asset, or declare an <inertial>"), where=at,
            values={"mass_relative": dm, "moment_relative": dI})


def _refused_meshes(link, rep, where: str, mesh_units: str = "m") -> None:
    """``mujoco_refuses_mesh`` for each mesh of the MJCF body that MuJoCo's compiler refuses
    whatever the body's inertial (:func:`.geometry.mujoco_refusal`), unless already found."""
    for g in link.geometries:
        said = [e.message for e in rep.errors if e.code == MUJOCO_REFUSES_MESH]
        if any(f"line {g.line}: " in m for m in said):
            continue
        why = mujoco_refusal(g, mesh_units)
        if why is not None:
            rep.add(MUJOCO_REFUSES_MESH, f"line {g.line}: {g.role} mesh {g.params.get('uri')!r}: {why}",
                    where=f"{where}: body {link.name!r}", severity="error")


def _well_defined(moments, i: int) -> bool:
    """Principal axis i is well defined: its moment is 10 % away from the other two."""
    return all(abs(moments[i] - moments[j]) >= 0.1 * moments[i] for j in range(3) if j != i)


def _axes_angle(moments_a, R_a, moments_b, R_b):
    """Largest angle [deg] between matching principal axes well defined in both tensors, or None."""
    worst = None
    for i in range(3):
        if not (_well_defined(moments_a, i) and _well_defined(moments_b, i)):
            continue
        c = abs(float(R_a[:, i] @ R_b[:, i]))
        ang = math.degrees(math.acos(min(1.0, c)))
        worst = ang if worst is None else max(worst, ang)
    return worst


def check_model(model, *, mesh_units: str = "m", warnings: bool = True) -> CheckReport:
    """Every link's findings (:func:`check_link`), then those that need the kinematic tree
    (:mod:`inertia.robots.floors`): moving bodies below the simulators' floor, massless moving
    links, planes in moving MJCF bodies, implausible radii of gyration, kinematic loops, and
    the list of massless frames.  ``warnings=False``: the errors only (what ``fix`` asks)."""
    links = []
    doc = model.document
    main_compiler = None
    if model.format == "mjcf" and doc is not None:
        from .whole import compiler_mass_attrs

        main_compiler = compiler_mass_attrs(doc.root.findall("compiler"))
    for link in model.links:
        if doc is not None and link.element is not None:
            where = doc.where(link.element)
            inertial_where = doc.where(link.inertial.element) if link.inertial is not None else where
        else:
            where = inertial_where = f"{model.path}:{link.line}" if link.line else str(model.path)
        compiler = main_compiler
        if main_compiler is not None and link.mjcf_compilers is not None:
            from .whole import compiler_mass_attrs

            compiler = compiler_mass_attrs(link.mjcf_compilers)
        links.append(check_link(link, where, mesh_units=mesh_units, inertial_where=inertial_where,
                                warnings=warnings, compiler=compiler))
        if model.format == "mjcf":
            _refused_meshes(link, links[-1], where, mesh_units)
    report = CheckReport(str(model.path), links)
    for code, message in getattr(doc, "notes", ()):
        report.findings.append(reader_finding(code, message))
    if not model.links and model.format == "mjcf":
        report.add("no_bodies", "the file holds no body: nothing to check (MuJoCo compiles it: an include fragment "
                   "of defaults, assets or keyframes, or a scene without bodies)", where=str(model.path))
        return report
    if not model.links:
        report.add("no_links", "the file holds no link: nothing to simulate or check "
                   f"({'urdfdom' if model.format == 'urdf' else 'libsdformat'} refuses such a robot)",
                   where=str(model.path))
        return report
    _tree_checks(model, report, mesh_units, warnings)
    return report


def _tree_checks(model, report: CheckReport, mesh_units: str, warnings: bool = True) -> None:
    from .._core.errors import InertiaError
    from . import floors
    from .whole import link_mass_properties

    if model.format in ("urdf", "sdf"):
        from .tree import read_tree

        try:
            read_tree(model)
        except InertiaError as exc:
            report.findings.append(reader_finding("joints_unreadable", f"{exc} (the checks of moving bodies did not "
                                                  "run)", "error"))
            return

    known: dict = {}

    def props_of(link):
        """The link's mass properties (declared, or from its geoms), computed once per link."""
        if id(link) not in known:
            try:
                known[id(link)] = link_mass_properties(model, link, mesh_units=mesh_units)[0]
            except InertiaError:
                known[id(link)] = None
        return known[id(link)]

    if model.format == "mjcf":  # what MuJoCo simulates: after boundmass, boundinertia, balanceinertia
        from .whole import mujoco_compiler_adjustments

        local = [(props_of(lk), "declared") for lk in model.links]
        for lk, (props, _) in zip(model.links, mujoco_compiler_adjustments(model, local, [])):
            known[id(lk)] = props

    loops = getattr(model, "loop_joints", [])
    if loops:
        report.add("kinematic_loop", (
            f"{len(loops)} joint{'s close' if len(loops) > 1 else ' closes'} a kinematic loop: "
            + "; ".join(f"line {j.line}: joint {j.name!r} (its child link {child!r} already has a parent)"
                        for j, child in loops[:10]) + (" ..." if len(loops) > 10 else "")
            + ". Mass properties need no tree: each link is counted once, at the pose of the tree without "
            "these joints"), where=str(model.path))
    moving = floors.moving_links(model)
    groups = floors.welded_groups(model, moving)
    if model.format == "mjcf":
        _static_zero_moments(model, report, {i for members in groups.values() for i, _, _ in members})
    for g, members in groups.items():
        for i, _, _ in members:
            for what in model.links[i].static_only:
                report.links[i].add("plane_in_moving_body", f"body {model.links[i].name!r} moves (it or a body it is "
                                    "welded to has a joint), and MuJoCo refuses it: \"plane only allowed in static "
                                    "bodies\"", where=what)
    for g, members in groups.items():
        rep = report.links[g]
        if rep.errors:
            continue
        mass, moments = floors.group_mass(model, members, props_of)
        if mass == 0:
            joint = next((j for j in model.links[g].joints if j.kind != "fixed"), None)
            how = ("a free body" if joint is None else f"an unnamed {joint.type} joint" if not joint.name
                   else f"joint {joint.name!r} ({joint.type})")
            shapes = model.format == "urdf" and any(model.links[i].geometries for i, _, _ in members)
            rep.add("massless_moving_link", (
                f"link {model.links[g].name!r} moves ({how}) but neither it nor any link welded "
                "to it has mass: simulators refuse it (MuJoCo: \"mass and inertia of moving bodies must be larger "
                "than mjMINVAL\"; Pinocchio's mass matrix is singular)"
                + ("; MuJoCo's URDF import infers a mass from its shapes, Pinocchio and Gazebo do not" if shapes
                   else "") + "; give it its inertial, or make the joint fixed"), where=_where(model, g))
        elif not (mass >= SIMULATOR_MIN_VALUE and moments.min() >= SIMULATOR_MIN_VALUE):
            rep.add("below_simulator_floor", floors.floor_message(model.links[g].name, mass, moments),
                    where=_where(model, g), values={"mass": mass, "moments": moments})
    for i, (link, rep) in enumerate(zip(model.links, report.links)):
        props = props_of(link)
        if props is None or (props.mass == 0 and not np.any(props.inertia_com)):
            if not any(e.code in ("massless_moving_link", MUJOCO_REFUSES_MESH) for e in rep.errors):
                report.massless_frames.append(link.name)
            continue
        if model.format == "sdf" and link.inertial is None:
            rep.add("sdf_default_inertial", f"link {link.name!r} has no <inertial>: Gazebo simulates it with mass "
                    "1 kg and moments 1 kg m^2", where=_where(model, i))
        if link.inertial is not None and not rep.errors and warnings:
            _gyration(model, i, link, rep, mesh_units, floors)


def _static_zero_moments(model, report, in_motion: set) -> None:
    """A body welded to the world with a ``diaginertia`` moment of exactly 0 (a rod, a point):
    MuJoCo compiles it (it never moves), so the error becomes a warning."""
    for i, (link, rep) in enumerate(zip(model.links, report.links)):
        inertial = link.inertial
        if i in in_motion or inertial is None or inertial.form != "diaginertia":
            continue
        errors = rep.errors
        if [e.code for e in errors] == ["not_positive_definite"] and np.diag(inertial.inertia_com_inertial).min() == 0:
            rep.findings = [f for f in rep.findings if f.severity != "error"]
            for e in errors:
                rep.add("static_degenerate_inertia", f"{e.message}; the body is welded to the world (it never moves), "
                        "and MuJoCo compiles it", where=e.where, values=e.values)


def _where(model, i: int) -> str:
    link = model.links[i]
    doc = model.document
    el = link.inertial.element if link.inertial is not None and link.inertial.element is not None else link.element
    if doc is not None and el is not None:
        return doc.where(el)
    return f"{model.path}:{link.line}" if link.line else str(model.path)


def _gyration(model, i: int, link, rep, mesh_units: str, floors) -> None:
    """Warn when the link's largest radius of gyration is far below any length it spans."""
    k = floors.radius_of_gyration(link.inertial)
    size = floors.link_size(model, i, geometry_bounds(link, mesh_units=mesh_units))
    if math.isfinite(k) and size > 0 and k < floors.GYRATION_RATIO * size:
        rep.add("implausible_inertia", (
            f"link {link.name!r}: its largest radius of gyration sqrt(I3 / m) is {k:.3g} m, "
            f"under {floors.GYRATION_RATIO:g} of the {size:.3g} m the link spans: not the tensor of a body of "
            "that size (a unit slip, or a placeholder such as 1e-6 kg m^2)"), where=_where(model, i),
            values={"radius_of_gyration": k, "size": size})
