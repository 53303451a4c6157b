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

CONVENTIONS = ("SI units (kg, m, kg m^2); every position and tensor in the root frame (MJCF world, URDF root link, "
               "SDF model); inertia_com about the center of mass, products of inertia negated (L = I w); joint "
               "values in rad (hinges) and m (slides)")

SOURCES = {"declared": "the file's inertial", "geometry": "MuJoCo's inertia from the body's geoms",
           "sdf_default": "SDF's default inertial (1 kg, 1 kg m^2), as Gazebo simulates it",
           "none": "no mass (no inertial)", "bound": "MuJoCo's <compiler boundmass/boundinertia> on a massless body"}

#: mesh-only options and the value each has when not given
_MESH_OPTIONS = (("--density", "density", None), ("--mass", "mass", None), ("--shell", "shell", False),
                 ("--fix-orientation", "fix_orientation", False), ("--accept-defects", "accept_defects", False),
                 ("--robust", "robust", False))
_ROBOT_OPTIONS = (("--joint", "joint", []), ("--subtree", "subtree", None), ("--xacro-arg", "xacro_arg", []),
                  ("--package-path", "package_path", []), ("--robot-format", "robot_format", None),
                  ("--mass-units", "mass_units", "kg"))


def is_robot_file(text: str) -> bool:
    """A path to something (a file, or what the reader refuses by name) whose extension names a robot format."""
    return os.path.lexists(text) and not os.path.isdir(text) and os.path.splitext(text)[1].lower() in ROBOT_EXTENSIONS


def add_robot_arguments(p) -> None:
    g = p.add_argument_group("robot files (SOURCE a URDF, SDF, MJCF or .xacro file)")
    g.add_argument("--joint", action="append", default=[], metavar="NAME=VALUE",
                   help="a hinge or slide joint's value in rad or m (repeatable); the others at their default "
                        "(MJCF qpos0, URDF/SDF 0)")
    g.add_argument("--subtree", metavar="LINK", help="the link LINK and everything below it, instead of the robot")
    g.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                   help="an argument of a .xacro file (repeatable)")
    g.add_argument("--package-path", action="append", default=[], metavar="DIR",
                   help="folder searched for package://, model:// and $(find PKG) (repeatable)")
    g.add_argument("--robot-format", choices=("urdf", "sdf", "mjcf"), help="override the detected format")
    g.add_argument("--mass-units", choices=("kg", "g", "lb"), default="kg",
                   help="unit of the file's masses (inertias in that unit times m^2; default kg)")


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
    from .check import MASS_UNITS, scale_masses

    _refuse(args, _MESH_OPTIONS, "mesh files and primitives")
    model = read_robot(args.source, format=args.robot_format, search_paths=args.package_path,
                       xacro_args=parse_xacro_args(args.xacro_arg))
    scale_masses(model, MASS_UNITS[args.mass_units])
    result = robot_mass_properties(model, _joint_values(args.joint), mesh_units=args.units)
    return result, (result.subtree(args.subtree) if args.subtree else None)


def run(args) -> int:
    result, sub = compute(args)
    props = sub if sub is not None else result.total
    if args.format in ("urdf", "mjcf", "sdf"):
        from ..robots.writers import inertial_block

        if sub is not None:  # in LINK's own frame: what replaces the subtree by one inertial on LINK
            lk = result.link(args.subtree)
            props = props.expressed_in(args.subtree, lk.R_root_link.T, -lk.R_root_link.T @ lk.p_root_link)
        fmt.emit(inertial_block(props, args.format))
        return 0
    links = result.subtree_links(args.subtree) if sub is not None else result.links
    if args.format == "json":
        fmt.emit(fmt.to_json(robot_dict(result, props, links, args.subtree)))
    else:
        fmt.emit(robot_lines(result, props, links, args.subtree))
    return 0


def robot_dict(result, props, links, subtree=None) -> dict:
    pf = props.principal_frame()
    return {
        "source": str(result.path), "format": result.format, "frame": result.frame, "subtree": subtree,
        "configuration": result.configuration,
        "mass": props.mass, "com": props.com, "inertia_com": props.inertia_com,
        "principal_moments": pf.moments, "principal_axes": pf.R_body_principal,
        "links": [lk.to_dict() for lk in links],
        "notes": list(result.notes), "conventions": CONVENTIONS,
    }


def robot_lines(result, props, links, subtree=None) -> list[str]:
    from ._props_text import XYZ, canonical_lines

    what = f"the subtree of link {subtree!r} ({len(links)} links)" if subtree else "the whole robot"
    lines = fmt.heading(f"Mass properties of {what}: {result.path}")[1:]
    moving = ", ".join(f"{k} = {fmt.num(v)}" for k, v in result.configuration.items())
    lines += fmt.key_values([
        ("format", f"{result.format.upper()}, {len(result.links)} links"),
        ("frame", f"{result.frame} (every position and axis below)"),
        ("configuration", (moving or "no hinge or slide joints") + " (rad, m)"),
        ("mass", f"{fmt.num(props.mass)} kg"),
        ("center of mass", fmt.vector(props.com) + " m"),
    ])
    lines += ["  inertia about the center of mass [kg m^2] (root-frame axes, products negated: L = I w):"]
    lines += fmt.matrix_lines(props.inertia_com, row_labels=XYZ, col_labels=XYZ, style="e")
    lines += canonical_lines(props)
    lines += fmt.heading("Links")
    rows = [[lk.name, fmt.num(lk.mass), *(fmt.num(x) for x in lk.com), lk.source] for lk in links]
    lines += fmt.table(["link", "mass [kg]", "com x [m]", "com y [m]", "com z [m]", "source"], rows)
    used = dict.fromkeys(lk.source for lk in links)
    lines += [f"  {s}: {SOURCES[s]}" for s in used]
    if result.notes:
        lines += fmt.heading("Notes") + [f"  - {n}" for n in result.notes]
    return lines
