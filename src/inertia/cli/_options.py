"""Options that several commands share, each defined and documented once.

In a command's ``--help`` a shared block is one line of its option names; ``inertia help TOPIC``
prints the block in full, from these same definitions (and docs/cli.md describes it once).
Only the standard library is imported here.
"""

from __future__ import annotations

from .._core.units import LENGTH_UNITS
from ._format import MASS_UNITS

#: the sentence every SOURCE command ends its description with
DENSITY_NOTE = "Default density: 1000 kg/m^3 (water) when neither --mass nor --density is given."

USD_EXTENSIONS = (".usd", ".usda", ".usdc", ".usdz")


def _group(p, title: str, topic: str, collapsed: bool):
    g = p.add_argument_group(title)
    if collapsed:
        g.topic = topic
    return g


def add_units(group) -> None:
    """``--units``: the length unit of every mesh file and primitive dimension a command reads."""
    group.add_argument("--units", default="m", choices=tuple(LENGTH_UNITS), metavar="UNIT",
                       help="length unit of mesh coordinates, primitive dimensions and the mesh files a robot "
                            "file names: " + "|".join(LENGTH_UNITS) + " (default m); results are always SI")


def add_body_options(p, *, collapsed: bool = True) -> None:
    """``--density``, ``--mass`` and ``--units``: how SOURCE becomes a body (topic ``source``)."""
    g = _group(p, "the body (SOURCE)", "source", collapsed)
    g.add_argument("--density", type=float, metavar="RHO",
                   help="density in kg/m^3 (kg/m^2 with --shell); default 1000 kg/m^3, water, when neither "
                        "--density nor --mass is given")
    g.add_argument("--mass", type=float, metavar="KG", help="total mass in kg (the density follows)")
    add_units(g)


def add_mesh_options(p, *, collapsed: bool = True) -> None:
    """How a mesh file becomes a body (topic ``mesh``)."""
    g = _group(p, "mesh files", "mesh", collapsed)
    g.add_argument("--shell", action="store_true",
                   help="thin shell: mass spread over the surface (needs --mass, or --density in kg/m^2)")
    g.add_argument("--fix-orientation", action="store_true",
                   help="repair inconsistent or inverted face winding instead of refusing the mesh")
    g.add_argument("--accept-defects", action="store_true",
                   help="compute even when the mesh is open or defective; the result carries the defects as "
                        "warnings (batch: a warning row instead of an error row)")
    g.add_argument("--robust", action="store_true",
                   help="for an open, overlapping or self-intersecting solid, integrate the points of "
                        "generalised winding number >= 1/2, with an error bound (docs/robust.md)")
    g.add_argument("--robust-tol", type=float, default=1e-3, metavar="REL",
                   help="with --robust: the relative error bound to reach (default 1e-3)")
    g.add_argument("--robust-budget", type=float, default=None, metavar="SECONDS",
                   help="with --robust: stop refining after SECONDS and report the bound reached (default: "
                        "no limit); progress is shown on a terminal")
    g.add_argument("--self-crossing", choices=("search", "certificate"), default="search",
                   help="how a closed mesh is shown not to pass through itself: search (default) proves it in "
                        "one pass when it is star-shaped from its center of mass and tests face pairs otherwise; "
                        "certificate only tries the proof and notes a mesh it does not prove")


def add_output_options(p, *, collapsed: bool = True) -> None:
    """``--convention`` and ``--output-units``: how printed numbers are expressed (topic ``output``)."""
    g = _group(p, "printed numbers", "output", collapsed)
    g.add_argument("--convention", choices=("tensor", "cad"), default="tensor",
                   help="products of inertia as tensor elements, negated (Ixy = -sum m x y, L = I w, as URDF, "
                        "MJCF and SDF write them; the default) or positive, as CAD programs list them")
    g.add_argument("--output-units", metavar="MASS,LENGTH",
                   help="units of the printed masses and lengths, and so of volumes, densities and inertias "
                        f"(g,mm: kg -> g, m -> mm, kg m^2 -> g mm^2): MASS {'|'.join(MASS_UNITS)}, LENGTH "
                        f"{'|'.join(LENGTH_UNITS)} (default kg,m)")


#: the robot-file options, in the order --help lists them
ROBOT_OPTIONS = ("joint", "subtree", "xacro-arg", "package-path", "robot-format", "mass-units")


def add_robot_options(p, which=ROBOT_OPTIONS, *, collapsed: bool = True) -> None:
    """The options of robot files (topic ``robot``); ``which`` names those the command takes."""
    g = _group(p, "robot files (URDF, SDF, MJCF, xacro)", "robot", collapsed)
    if "joint" in which:
        g.add_argument("--joint", action="append", default=[], metavar="NAME=VALUE",
                       help="a hinge or slide joint's value in rad or m (repeatable); the others at their "
                            "default (MJCF qpos0, URDF/SDF 0)")
    if "subtree" in which:
        g.add_argument("--subtree", metavar="LINK", help="the link LINK and everything below it, instead of the robot")
    if "xacro-arg" in which:
        g.add_argument("--xacro-arg", action="append", default=[], metavar="NAME:=VALUE",
                       help="an argument of a .xacro file (repeatable)")
    if "package-path" in which:
        g.add_argument("--package-path", action="append", default=[], metavar="DIR",
                       help="folder searched for package://, model:// and $(find PKG) meshes (repeatable)")
    if "robot-format" in which:
        g.add_argument("--robot-format", choices=("urdf", "sdf", "mjcf"), help="override the detected format")
    if "mass-units" in which:
        g.add_argument("--mass-units", choices=tuple(MASS_UNITS), default="kg",
                       help="unit of the file's masses (its inertias in that unit times m^2; default kg)")


ZERO_UNSET_HELP = ("read only exact zeros as 'not set' (the schema's text), instead of usd-core's "
                   "ComputeMassProperties, which also ignores a diagonalInertia or principalAxes of norm <= 1e-5")


def add_usd_options(p, *, physx: bool = True, collapsed: bool = True) -> None:
    """The options that only OpenUSD stages take (topic ``usd``)."""
    g = _group(p, "OpenUSD stages (" + ", ".join(USD_EXTENSIONS) + "; the usd extra)", "usd", collapsed)
    if physx:
        g.add_argument("--as-physx", action="store_true",
                       help="what PhysX simulates: a triangle mesh on a dynamic body as its convex hull (or the "
                            "physics:approximation it names); the report gives the exact mass beside it")
    g.add_argument("--zero-unset", action="store_true", help=ZERO_UNSET_HELP)


def _source_intro() -> str:
    from ._source import PRIMITIVES

    specs = ", ".join(p.usage for p in PRIMITIVES.values())
    return ("SOURCE (props, particles, simulate, flip) is a mesh file (STL, OBJ, PLY, OFF, glTF, ...) or a primitive "
            f"NAME:numbers, one of: {specs}; dimensions in --units.  " + DENSITY_NOTE)


#: topic -> (intro, function adding the block in full, the commands that take it)
TOPICS = {
    "source": (_source_intro, add_body_options, "props, particles, simulate, flip"),
    "mesh": (lambda: "How a mesh file becomes a body; a mesh with defects is refused, naming them, unless one of "
                     "these options says what to do.", add_mesh_options, "props, particles, simulate, flip, batch, "
                                                                          "demo"),
    "output": (lambda: "How the numbers a command prints are expressed; the JSON says which (output_units). "
                       "Blocks for robot files (--format urdf|mjcf|sdf) are always SI tensor elements.",
               add_output_options, "props, particles, demo, diff"),
    "robot": (lambda: "How a robot file is read; --units gives the length unit of the mesh files it names.",
              add_robot_options, "props, check, fix, diff (each the options that apply to it)"),
    "usd": (lambda: "OpenUSD stages are read with usd-core (pip install 'inertia[usd]').", add_usd_options,
            "props, check, fix, diff"),
}


def topic_help(name: str) -> str:
    """The full text of a shared block, from the definitions its commands use."""
    import argparse
    import textwrap

    from ._format import Parser

    intro, add, commands = TOPICS[name]
    p = Parser(prog=f"inertia help {name}", add_help=False, usage=argparse.SUPPRESS,
               description=textwrap.fill(intro()) + f"\n\nTaken by: {commands}.",
               formatter_class=argparse.RawDescriptionHelpFormatter)
    add(p, collapsed=False)
    return p.format_help()
