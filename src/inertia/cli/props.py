"""``inertia props SOURCE``: mass, center of mass, inertia, principal axes and validity.

SOURCE a robot file (URDF, SDF, MJCF, ``.xacro``): the whole robot and each link
(:mod:`inertia.cli.props_robot`).

Output (``--format table`` or ``json``) is in SI units; the inertia matrix is about the
center of mass, in the axes of the mesh file (or primitive), with negated products of
inertia (``L = I w``).  Principal moments are ascending and the principal axes are the
columns of a proper rotation ``R_body_principal`` (det +1).
"""

from __future__ import annotations

from . import _format as fmt
from ._options import (
    DENSITY_NOTE,
    add_body_options,
    add_mesh_options,
    add_output_options,
    add_robot_options,
    add_usd_options,
)
from ._props_text import XYZ, canonical_lines, inertia_lines

__all__ = ["register", "run", "props_dict", "props_lines", "summary_lines", "inertia_lines", "canonical_lines",
           "validity_lines", "warnings_lines", "XYZ"]


def conventions(units) -> str:
    """The JSON's ``conventions`` sentence."""
    return (f"{units.conventions()}; inertia_com about the center of mass in the body axes; principal_moments "
            "ascending; the columns of R_body_principal are the principal axes (det +1)")

EPILOG = """\
examples:
  inertia props box:0.1,0.2,0.4 --mass 2
  inertia props part.stl --units mm --density 2700 --format json
  inertia props part.stl --units mm --density 2700 --output-units g,mm --convention cad
  inertia props part.stl --units mm --density 2700 --format urdf   (a ready-to-paste <inertial>)
  inertia props robot.urdf --joint elbow=0.5   (whole robot and each link, root frame)
  inertia props scene.xml --subtree gripper --format json

exit status: 0 on success, 1 on bad input (the message on stderr names the problem), 2 on bad usage."""

HELP = "mass properties of a mesh file, a primitive or a whole robot"
DESCRIPTION = ("Mass, volume, center of mass, inertia about the center of mass, principal moments and axes "
               "and physical validity of a mesh file or a primitive shape, or of a whole robot (URDF, SDF, MJCF, "
               "xacro, OpenUSD) at a joint configuration with each of its links, in the root frame.  "
               + DENSITY_NOTE)


def register(sub) -> None:
    p = fmt.add_command(sub, "props", HELP, DESCRIPTION, EPILOG, usage="SOURCE [options]")
    p.add_argument("source", metavar="SOURCE",
                   help="a mesh file, a primitive NAME:numbers such as box:0.1,0.2,0.4 (inertia help source), "
                        "or a robot file")
    add_format_argument(p, robot=True)
    add_body_options(p)
    add_mesh_options(p)
    add_output_options(p)
    add_robot_options(p)
    add_usd_options(p)
    p.set_defaults(func=run)


def add_format_argument(p, *, robot: bool = False) -> None:
    if robot:
        p.add_argument("--format", choices=("table", "json", "urdf", "mjcf", "sdf"), default="table",
                       help="table (default), json, or urdf|mjcf|sdf: a ready-to-paste <inertial> block (SI, "
                            "tensor elements, 6 significant digits or as many as keep it physical)")
        return
    p.add_argument("--format", choices=("table", "json"), default="table",
                   help="table: aligned text for people (default); json: machine-readable")


def run(args) -> int:
    from . import props_robot
    from ._source import load_source
    from .usd import run_props

    units = fmt.Units.from_args(args)
    if args.format in BLOCK_FORMATS and not units.si:
        from .._core.errors import InputError

        raise InputError(f"--format {args.format} writes SI units and tensor elements, as the format requires: "
                         "drop --output-units and --convention")
    if (code := run_props(args, units)) is not None:
        return code
    if props_robot.is_robot_file(args.source):
        return props_robot.run(args, units)
    props_robot.refuse_robot_options(args)
    props, info = load_source(args)
    if args.format in BLOCK_FORMATS:
        fmt.emit(fmt.inertial_block(props, args.format))
        return 0
    if args.format == "json":
        fmt.emit(fmt.to_json(props_dict(props, info, units)))
    else:
        fmt.emit(props_lines(props, info, units))
    return 0


BLOCK_FORMATS = ("urdf", "mjcf", "sdf")


# ---------------------------------------------------------------------------- content


def props_dict(props, info, units=None) -> dict:
    """JSON-ready dict of the mass properties and how they were obtained (in ``units``, SI by default)."""
    u = units or fmt.Units()
    pf = props.principal()
    violations = props.check()
    out = dict(info.to_dict(u))
    out.update({
        "frame": props.frame,
        "mass": u.mass(props.mass),
        "volume": u.volume(props.volume),
        "com": u.length(props.com),
        "inertia_com": u.inertia(props.inertia_com),
        "principal_moments": u.moments(pf.moments),
        "R_body_principal": pf.R_body_principal,
        "degenerate_moments": [list(g) for g in pf.degenerate],
        "radii_of_gyration": u.length(props.radii_of_gyration),
        "validity": [{"code": v.code, "message": v.message} for v in violations],
        **_robust_bounds(props),
        "physical": not violations,
        "warnings": list(getattr(info, "notes", [])) + [f.message for f in props.findings],
        "findings": [f.to_dict() for f in props.findings],
        "output_units": u.to_dict(),
        "conventions": conventions(u),
    })
    return out


def _robust_bounds(props) -> dict:
    """``error_bound`` (the result's relative bound) and ``bounds`` {volume, com, inertia}, as numbers,
    when the result is a robust solid's; nothing otherwise (an exact result has no bound)."""
    for f in props.findings:
        if f.code == "robust_solid":
            v = f.values
            return {"error_bound": float(v["error_bound"]), "bounds": {k: float(x) for k, x in v["bounds"].items()},
                    "robust_tol": float(v["tol"]), "robust_converged": bool(v["converged"])}
    return {}


def props_lines(props, info, units=None, *, title: str | None = None) -> list[str]:
    """Readable tables of the mass properties (used by ``props`` and ``demo``)."""
    u = units or fmt.Units()
    lines = summary_lines(props, info, u, title=title or f"Mass properties of {info.source}")
    lines += inertia_lines(props, u)
    lines += canonical_lines(props, u)
    lines += fmt.heading("Validity")
    lines += validity_lines(props.check())
    lines += fmt.heading("Warnings")
    lines += warnings_lines(list(getattr(info, "notes", [])) + [f.message for f in props.findings])
    return lines


def summary_lines(props, info, u, *, title: str) -> list[str]:
    """Title, source, mass, volume, density, center of mass."""
    lines = fmt.heading(title)[1:]  # no blank line before the first heading
    L = u.length_unit
    results = "results in SI units" if u.si else f"results in {u.mass_unit} and {L}"
    if info.kind == "assembly":
        src = [("source", f"{info.source} (an assembly of primitives; {'SI units' if u.si else results})")]
    else:
        src = [("source", f"{info.source} ({info.kind}; lengths read in {info.units}, {results})")]
    if info.kind in ("primitive", "assembly"):
        src.append(("dimensions", info.dimensions(u)))
    if info.mesh is not None:
        m = info.mesh
        src.append(("mesh", f"{m['n_vertices']} vertices, {m['n_faces']} faces (after merging duplicates)"))
        src.append(("extents", f"{fmt.vector(u.length(m['extents']))} {L} (bounding box "
                    f"{fmt.vector(u.length(m['bbox_min']))} .. {fmt.vector(u.length(m['bbox_max']))} {L})"))
    volume = f"{fmt.num(u.volume(props.volume))} {L}^3" if props.volume == props.volume else "n/a (thin shell)"
    lines += fmt.key_values(src + [
        ("mass", f"{fmt.num(u.mass(props.mass))} {u.mass_unit}"),
        ("volume", volume),
        ("density", info.density_text(u)),
        ("center of mass", f"{fmt.vector(u.length(props.com))} {L} (in frame {props.frame!r})"),
    ])
    return lines


def validity_lines(violations) -> list[str]:
    """'physical: ...' or one line per violated condition."""
    if not violations:
        return ["  physical: positive mass, finite, symmetric, positive definite, triangle inequality hold"]
    return ["  NOT physical:"] + [f"  - [{v.code}] {v.message}" for v in violations]


def warnings_lines(warnings) -> list[str]:
    return ["  - " + w for w in warnings] or ["  none"]
