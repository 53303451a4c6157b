"""Whole-robot mass properties: each link's mass, center of mass and inertia in the root
frame at a joint configuration, the robot's total, and the total of any subtree.

Where a link's mass properties come from (``source``):

* ``declared``: the file's inertial (URDF ``<inertial>``, SDF ``<inertial>``, MJCF
  ``<inertial>``);
* ``geometry``: MJCF bodies whose inertia MuJoCo infers from their geoms (no ``<inertial>``,
  or ``<compiler inertiafromgeom="true">``), computed as MuJoCo's compiler does (mesh
  inertia modes, fitted and shell primitives: :mod:`inertia.robots.mujoco_inertia`);
* ``sdf_default``: an SDF link without ``<inertial>`` has SDF's default inertial, mass 1 kg
  and inertia 1 kg m^2 about each axis at the link origin, which Gazebo simulates;
* ``none``: no mass (a URDF link without ``<inertial>``: a frame, as in urdfdom and
  Pinocchio; an MJCF body with neither inertial nor mass-carrying geoms);
* ``bound``: such an MJCF body given mass or inertia by ``<compiler boundmass
  boundinertia>`` (:func:`mujoco_compiler_adjustments`).

The root frame is MJCF's world, the URDF root link's frame, an SDF model's own frame (or the
world of an SDF ``<world>``): ``RobotMassProperties.frame`` names it.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._core.errors import InertiaError, InputError
from ..massprops.properties import MassProperties, combine

#: SDF's default inertial, which Gazebo gives a link without one: mass [kg], moments [kg m^2]
SDF_DEFAULT_MASS = 1.0
SDF_DEFAULT_MOMENT = 1.0


@dataclass
class LinkMass:
    """One link's mass properties in the root frame, and where they came from."""

    name: str
    line: int | None
    source: str
    props: MassProperties
    R_root_link: np.ndarray
    p_root_link: np.ndarray
    parent: int | None = None

    @property
    def mass(self) -> float:
        return self.props.mass

    @property
    def com(self) -> np.ndarray:
        return self.props.com

    @property
    def inertia_com(self) -> np.ndarray:
        return self.props.inertia_com

    def to_dict(self) -> dict:
        return {"name": self.name, "mass": self.mass, "com": self.com.tolist(),
                "inertia_com": self.inertia_com.tolist(), "source": self.source}


@dataclass
class RobotMassProperties:
    """The robot at one configuration: ``total`` and ``links`` in the root frame ``frame``."""

    path: object
    format: str
    frame: str
    configuration: dict
    links: list
    total: MassProperties
    notes: list = field(default_factory=list)

    def link(self, name: str) -> LinkMass:
        for lk in self.links:
            if lk.name == name:
                return lk
        raise InputError(f"{self.path}: no link named {name!r}; the links are "
                         f"{', '.join(repr(lk.name) for lk in self.links[:30])}"
                         + (f", ... ({len(self.links)} in all)" if len(self.links) > 30 else ""))

    def subtree_links(self, name: str) -> list:
        """The link called ``name`` and every link below it."""
        start = self.links.index(self.link(name))
        children: dict = {}
        for i, lk in enumerate(self.links):
            children.setdefault(lk.parent, []).append(i)
        out, stack = [], [start]
        while stack:
            i = stack.pop()
            out.append(self.links[i])
            stack.extend(reversed(children.get(i, [])))
        return out

    def subtree(self, name: str) -> MassProperties:
        """Mass properties of the link called ``name`` and everything it carries, root frame."""
        return _sum(self.subtree_links(name), self.frame, f"{self.path}: the subtree of link {name!r}")


def link_mass_properties(model, link, *, mesh_units: str = "m"):
    """``(MassProperties in the link frame or None, source)`` of one link (see the module
    docstring for the sources); InertiaError naming the link when its geometry cannot be used."""
    if model.format == "mjcf" and link.inertia_from_geoms:
        from .geometry import link_geometry_properties

        props, _, problems = link_geometry_properties(link, role="collision", mesh_units=mesh_units,
                                                      simulator=True)
        if props is None and problems:
            where = model.document.where(link.element) if link.element is not None else f"{model.path}:{link.line}"
            raise InertiaError(f"{where}: body {link.name!r}: MuJoCo takes its inertia from "
                               "its geoms, which cannot be used: " + "; ".join(m for _, m in problems))
        return props, "geometry" if props is not None else "none"
    if link.inertial is not None:
        i = link.inertial
        return MassProperties(i.mass, i.com_link, i.inertia_com, validate=False), "declared"
    if model.format == "sdf":
        return MassProperties(SDF_DEFAULT_MASS, np.zeros(3), SDF_DEFAULT_MOMENT * np.eye(3)), "sdf_default"
    return None, "none"


#: ``<compiler>`` attributes that change the bodies' mass properties, and their defaults
COMPILER_MASS = {"boundmass": "0", "boundinertia": "0", "balanceinertia": "false", "settotalmass": "-1"}


def compiler_mass_attrs(compilers) -> dict:
    """:data:`COMPILER_MASS` as the ``<compiler>`` elements set them (later ones override)."""
    attrs = dict(COMPILER_MASS)
    for el in compilers:
        attrs.update({k: el.get(k) for k in COMPILER_MASS if el.get(k) is not None})
    return attrs


def _active(attrs: dict, key: str, where: str) -> bool:
    """Whether option ``key`` of ``attrs`` changes anything."""
    from .urdf_sdf import floats

    return attrs[key] == "true" if key == "balanceinertia" else floats(attrs[key], 1, where, key)[0] > 0


def mujoco_compiler_adjustments(model, local: list, notes: list) -> list:
    """What MuJoCo's compiler does to each body's ``(props, source)`` (link frame) after
    computing it: ``boundmass`` and ``boundinertia`` (lower bounds on the mass and on each
    principal moment), ``balanceinertia`` (moments that break the triangle inequality become
    their mean), then ``settotalmass`` (every body scaled to that total).  A massless body
    lifted by a bound has MuJoCo's inertial frame: the body's own ``pos`` (not its frames).
    A body attached from another model (``<attach>``) has that model's bounds; ``settotalmass``
    is the main file's."""
    from .urdf_sdf import floats

    where = f"{model.path}: <compiler>"
    main = compiler_mass_attrs(model.document.root.findall("compiler"))
    per_link = [main if lk.mjcf_compilers is None else compiler_mass_attrs(lk.mjcf_compilers) for lk in model.links]
    total = floats(main["settotalmass"], 1, where, "settotalmass")[0]
    changed = list(dict.fromkeys(f"{k}={a[k]}" for k in COMPILER_MASS for a in [main, *per_link]
                                 if (k != "settotalmass" or a is main) and _active(a, k, where)))
    if not changed:
        return local
    out = []
    for lk, (props, source), attrs in zip(model.links, local, per_link):
        bound_m, bound_i = (floats(attrs[k], 1, where, k)[0] for k in ("boundmass", "boundinertia"))
        if props is None:
            props = MassProperties(0.0, floats(lk.element.get("pos", "0 0 0"), 3, where, "pos"), np.zeros((3, 3)),
                                   validate=False)
        w0, V = np.linalg.eigh(props.inertia_com)
        w = np.maximum(w0, bound_i)
        if attrs["balanceinertia"] == "true" and 2 * w.max() > w.sum():
            w = np.full(3, w.mean())
        inertia = (V * w) @ V.T if np.any(w != w0) else props.inertia_com
        props = props._replace(mass=max(props.mass, bound_m), inertia_com=inertia)
        out.append((props, "bound" if source == "none" and (props.mass > 0 or w.any()) else source))
    if total > 0:
        scale = total / sum(p.mass for p, _ in out)
        out = [(p._replace(mass=p.mass * scale, inertia_com=p.inertia_com * scale), src) for p, src in out]
    notes.append("MuJoCo's compiler options " + ", ".join(changed) + " applied to the bodies")
    return out


def robot_mass_properties(model, joints=None, *, mesh_units: str = "m", search_paths=()) -> RobotMassProperties:
    """The whole robot's mass properties at a configuration, and each link's, in the root frame.

    ``model``: a :class:`~inertia.robots.model.RobotModel` or a robot file's path (URDF, SDF,
    MJCF); ``joints``: name -> value [rad, m] of hinge and slide joints (the others, and those
    not given, at their default: MJCF ``qpos0``, URDF and SDF 0).  ``mesh_units``: the unit of
    the mesh files (for MJCF bodies whose inertia comes from their geoms).
    """
    from .kinematics import link_poses

    if isinstance(model, (str, Path)):
        from .io import read_robot

        model = read_robot(model, search_paths=search_paths)
    poses, values = link_poses(model, joints)
    frame = model.root_frame
    rows, notes = [], []
    local = [link_mass_properties(model, lk, mesh_units=mesh_units) for lk in model.links]
    if model.format == "mjcf":
        local = mujoco_compiler_adjustments(model, local, notes)
    for lk, (R, p), (props, source) in zip(model.links, poses, local):
        if props is None:
            props = MassProperties(0.0, p, np.zeros((3, 3)), validate=False)
        else:
            props = props.transformed(R, p)
        rows.append(LinkMass(lk.scoped_name or lk.name, lk.line, source, props._replace(frame=frame), R, p,
                             lk.parent))
    defaults = [r.name for r in rows if r.source == "sdf_default"]
    if defaults:
        notes.append(f"{len(defaults)} SDF link{'s' if len(defaults) > 1 else ''} without <inertial> "
                     f"({', '.join(defaults[:5])}{', ...' if len(defaults) > 5 else ''}) counted with SDF's default "
                     "inertial (1 kg, 1 kg m^2 about each axis), as Gazebo simulates them")
    auto = [lk.name for lk in model.links if model.format == "sdf" and lk.inertial is not None
            and getattr(lk.inertial.element, "get", lambda k: None)("auto") == "true"]
    if auto:
        notes.append(f"<inertial auto=\"true\"> on {', '.join(auto[:5])}: Gazebo computes these from the collision "
                     "shapes; counted here with the values written in the file")
    invalid = [r.name for r in rows if r.source == "declared" and r.props.check()]
    if invalid:
        notes.append(f"the declared inertial of {', '.join(invalid[:5])}{', ...' if len(invalid) > 5 else ''} is not "
                     "physical (inertia check FILE says why): the totals include it as written")
    total = _sum(rows, frame, f"{model.path}: the robot")
    return RobotMassProperties(model.path, model.format, frame, values, rows, total, notes)


def _sum(rows, frame: str, what: str) -> MassProperties:
    bodies = [r.props for r in rows if r.source != "none"]
    if not bodies or not sum(b.mass for b in bodies) > 0:
        raise InputError(f"{what} has no mass: no link carries an inertial")
    return combine(bodies, frame=frame, validate=False)._replace(frame=frame)
