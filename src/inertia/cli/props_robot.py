"""``inertia props ROBOT_FILE``: the whole robot's mass properties, and each link's.

URDF, SDF, MJCF (and ``.xacro`` files expanding to them) at a joint configuration (the
default: MJCF ``qpos0``, URDF/SDF joints at 0; ``--joint NAME=VALUE`` sets one), all in
the root frame (MJCF world, URDF root link, SDF model); ``--subtree LINK`` for a link and
everything it carries.  Only the standard library is imported at module level.
"""

from __future__ import annotations

import os

from . import _format as fmt

#: extensions always read as robot files (``.xml`` too, by its root element)
ROBOT_EXTENSIONS = (".urdf", ".sdf", ".world", ".mjcf", ".xacro", ".xml")


def conventions(units) -> str:
    """The JSON's ``conventions`` sentence."""
    return (f"{units.conventions()}; every position and tensor in the root frame (MJCF world, URDF root link, "
            "SDF model); inertia_com about the center of mass; joint values in rad (hinges) and m (slides)")


SOURCES = {"declared": "the file's inertial", "geometry": "MuJoCo's inertia from the body's geoms",
           "sdf_default": "SDF's default inertial (1 kg, 1 kg m^2), as Gazebo simulates it",
           "none": "no mass (no inertial)", "bound": "MuJoCo's <compiler boundmass/boundinertia> on a massless body"}

#: mesh-only options and the value each has when not given
_MESH_OPTIONS = (("--density", "density", None), ("--mass", "mass", None), ("--shell", "shell", False),
                 ("--fix-orientation", "fix_orientation", False), ("--accept-defects", "accept_defects", False),
                 ("--robust", "robust", False), ("--self-crossing", "self_crossing", "search"))
_ROBOT_OPTIONS = (("--joint", "joint", []), ("--subtree", "subtree", None), ("--xacro-arg", "xacro_arg", []),
                  ("--package-path", "package_path", []), ("--robot-format", "robot_format", None),
                  ("--mass-units", "mass_units", "kg"))


def is_robot_file(text: str) -> bool:
    """A path to something (a file, or what the reader refuses by name) whose extension names a robot format."""
    return os.path.lexists(text) and not os.path.isdir(text) and os.path.splitext(text)[1].lower() in ROBOT_EXTENSIONS


def refuse_robot_options(args) -> None:
    """SOURCE is a mesh or a primitive: the robot-only options make no sense."""
    _refuse(args, _ROBOT_OPTIONS, "robot files (URDF, SDF, MJCF)")


def _refuse(args, options, what: str) -> None:
    from .._core.errors import InputError

    for flag, attr, unset in options:
        if getattr(args, attr, unset) not in (unset, None):
            raise InputError(f"{flag} applies to {what} only, not to {args.source!r}")


def _joint_values(items) -> dict:
    from .._core.errors import InputError

    out = {}
    for item in items:
        name, sep, value = item.partition("=")
        try:
            out[name.strip()] = float(value)
        except ValueError:
            sep = ""
        if not sep or not name.strip():
            raise InputError(f"--joint {item!r} must read NAME=VALUE with VALUE a number (rad or m)")
    return out


def compute(args):
    """``(RobotMassProperties, subtree MassProperties or None)`` for the command's options."""
    from ..robots.io import parse_xacro_args, read_robot
    from ..robots.whole import robot_mass_properties
    from ._format import MASS_UNITS

    _refuse(args, _MESH_OPTIONS, "mesh files and primitives")
    model = read_robot(args.source, format=args.robot_format, search_paths=args.package_path,
                       xacro_args=parse_xacro_args(args.xacro_arg))
    scale_masses(model, MASS_UNITS[args.mass_units])
    result = robot_mass_properties(model, _joint_values(args.joint), mesh_units=args.units)
    return result, (result.subtree(args.subtree) if args.subtree else None)


def run(args, units) -> int:
    result, sub = compute(args)
    props = sub if sub is not None else result.total
    if args.format in ("urdf", "mjcf", "sdf"):
        if sub is not None:  # in LINK's own frame: what replaces the subtree by one inertial on LINK
            lk = result.link(args.subtree)
            props = props.expressed_in(args.subtree, lk.R_root_link.T, -lk.R_root_link.T @ lk.p_root_link)
        fmt.emit(fmt.inertial_block(props, args.format))
        return 0
    links = result.subtree_links(args.subtree) if sub is not None else result.links
    if args.format == "json":
        fmt.emit(fmt.to_json(robot_dict(result, props, links, units, args.subtree)))
    else:
        fmt.emit(robot_lines(result, props, links, units, args.subtree))
    return 0


def scale_masses(model, scale: float) -> None:
    """Convert the declared masses and tensors of a model to kg (in place)."""
    if scale == 1.0:
        return
    for link in model.links:
        if link.inertial is not None:
            link.inertial.mass *= scale
            link.inertial.inertia_com_inertial = link.inertial.inertia_com_inertial * scale


def robot_dict(result, props, links, units, subtree=None) -> dict:
    from ._props_text import body_dict, link_dict

    return {"source": str(result.path), "format": result.format, "frame": result.frame, "subtree": subtree,
            "configuration": result.configuration, **body_dict(props, units),
            "links": [link_dict(lk, units) for lk in links], "notes": list(result.notes),
            "output_units": units.to_dict(), "conventions": conventions(units)}


def robot_lines(result, props, links, units, subtree=None) -> list[str]:
    from ._props_text import canonical_lines, inertia_lines, links_table

    u = units
    what = f"the subtree of link {subtree!r} ({len(links)} links)" if subtree else "the whole robot"
    lines = fmt.heading(f"Mass properties of {what}: {result.path}")[1:]
    moving = ", ".join(f"{k} = {fmt.num(v)}" for k, v in result.configuration.items())
    lines += fmt.key_values([
        ("format", f"{result.format.upper()}, {len(result.links)} links"),
        ("frame", f"{result.frame} (every position and axis below)"),
        ("configuration", (moving or "no hinge or slide joints") + " (rad, m)"),
        ("mass", f"{fmt.num(u.mass(props.mass))} {u.mass_unit}"),
        ("center of mass", f"{fmt.vector(u.length(props.com))} {u.length_unit}"),
    ])
    lines += inertia_lines(props, u, heading=False, axes="root-frame axes")
    lines += canonical_lines(props, u)
    lines += fmt.heading("Links")
    lines += links_table(links, u)
    used = dict.fromkeys(lk.source for lk in links)
    lines += [f"  {s}: {SOURCES[s]}" for s in used]
    if result.notes:
        lines += fmt.heading("Notes") + [f"  - {n}" for n in result.notes]
    return lines
