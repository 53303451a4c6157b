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
from ._props_text import XYZ, canonical_lines, degenerate_text
from ._source import DENSITY_NOTE, add_source_arguments

__all__ = ["register", "run", "props_dict", "props_lines", "summary_lines", "inertia_lines", "canonical_lines",
           "degenerate_text", "validity_lines", "warnings_lines", "XYZ"]

CONVENTIONS = ("SI units (kg, m, kg m^2); inertia_com about the center of mass in the body axes, "
               "products of inertia negated (L = I w); principal_moments ascending; principal_axes "
               "are the columns of R_body_principal (det +1)")

EPILOG = """\
examples:
  inertia props box:0.1,0.2,0.4 --mass 2
  inertia props part.stl --units mm --density 2700 --format json
  inertia props sphere:5 --units cm            (water, 1000 kg/m^3, by default)
  inertia props robot.urdf --joint elbow=0.5   (whole robot and each link, root frame)
  inertia props scene.xml --subtree gripper --format json
  inertia props robot.urdf.xacro --xacro-arg prefix:=left_ --package-path ~/ws/src

exit status: 0 on success, 1 on bad input (the message on stderr names the problem), 2 on bad usage."""

HELP = "mass properties of a mesh file, a primitive or a whole robot"
DESCRIPTION = ("Mass, volume, center of mass, inertia about the center of mass, principal "
               "moments and axes, repeated-moment report and physical validity of a mesh file "
               "or a primitive shape.  " + DENSITY_NOTE + "  For a robot file (URDF, SDF, MJCF, "
               ".xacro): the whole robot's mass, center of mass and inertia at a joint "
               "configuration, and each link's, in the root frame (--units: the unit of its mesh files).")


def register(sub) -> None:
    p = fmt.add_command(sub, "props", HELP, DESCRIPTION, EPILOG)
    from .props_robot import add_robot_arguments

    add_source_arguments(p)
    add_format_argument(p, robot=True)
    add_robot_arguments(p)
    from .usd import add_usd_arguments
    add_usd_arguments(p)
    p.set_defaults(func=run)


def add_format_argument(p, *, robot: bool = False) -> None:
    if robot:
        p.add_argument("--format", choices=("table", "json", "urdf", "mjcf", "sdf"), default="table",
                       help="table: aligned text for people (default); json: machine-readable; urdf, mjcf, "
                            "sdf: a ready-to-paste <inertial> block (COM and tensor in the mesh's axes, "
                            "tensor-element products)")
        return
    p.add_argument("--format", choices=("table", "json"), default="table",
                   help="table: aligned text for people (default); json: machine-readable")


def run(args) -> int:
    from . import props_robot
    from ._source import load_source
    from .usd import run_props

    if (code := run_props(args)) is not None:
        return code
    if props_robot.is_robot_file(args.source):
        return props_robot.run(args)
    props_robot.refuse_robot_options(args)
    props, info = load_source(args)
    if args.format in ("urdf", "mjcf", "sdf"):
        from ..robots.writers import inertial_block

        fmt.emit(inertial_block(props, args.format))
        return 0
    if args.format == "json":
        fmt.emit(fmt.to_json(props_dict(props, info)))
    else:
        fmt.emit(props_lines(props, info))
    return 0


# ---------------------------------------------------------------------------- content


def props_dict(props, info) -> dict:
    """JSON-ready dict of the mass properties and how they were obtained."""
    pf = props.principal()
    violations = props.check()
    out = dict(info.to_dict())
    out.update({
        "frame": props.frame,
        "mass": props.mass,
        "volume": props.volume,
        "com": props.com,
        "inertia_com": props.inertia_com,
        "principal_moments": pf.moments,
        "principal_axes": pf.R_body_principal,
        "degenerate_moments": [list(g) for g in pf.degenerate],
        "radii_of_gyration": props.radii_of_gyration,
        "validity": [{"code": v.code, "message": v.message} for v in violations],
        "physical": not violations,
        "warnings": list(getattr(info, "notes", [])) + [f.message for f in props.findings],
        "conventions": CONVENTIONS,
    })
    return out


def props_lines(props, info, *, title: str | None = None) -> list[str]:
    """Readable tables of the mass properties (used by ``props`` and ``demo``)."""
    lines = summary_lines(props, info, title=title or f"Mass properties of {info.source}")
    lines += inertia_lines(props)
    lines += canonical_lines(props)
    lines += fmt.heading("Validity")
    lines += validity_lines(props.check())
    lines += fmt.heading("Warnings")
    lines += warnings_lines(list(getattr(info, "notes", [])) + [f.message for f in props.findings])
    return lines


def summary_lines(props, info, *, title: str) -> list[str]:
    """Title, source, mass, volume, density, center of mass."""
    lines = fmt.heading(title)[1:]  # no blank line before the first heading
    if info.kind == "assembly":
        src = [("source", f"{info.source} (an assembly of primitives; SI units)")]
    else:
        src = [("source", f"{info.source} ({info.kind}; lengths read in {info.units}, results in SI units)")]
    if info.kind in ("primitive", "assembly"):
        src.append(("dimensions", info.dimensions_text))
    if info.mesh is not None:
        m = info.mesh
        src.append(("mesh", f"{m['n_vertices']} vertices, {m['n_faces']} faces (after merging duplicates)"))
        src.append(("extents", fmt.vector(m["extents"]) + " m (bounding box " + fmt.vector(m["bbox_min"]) + " .. "
                    + fmt.vector(m["bbox_max"]) + " m)"))
    volume = f"{fmt.num(props.volume)} m^3" if props.volume == props.volume else "n/a (thin shell)"
    lines += fmt.key_values(src + [
        ("mass", f"{fmt.num(props.mass)} kg"),
        ("volume", volume),
        ("density", info.density_text()),
        ("center of mass", fmt.vector(props.com) + f" m (in frame {props.frame!r})"),
    ])
    return lines


def inertia_lines(props, *, heading: bool = True) -> list[str]:
    """The central inertia matrix, labelled (as its own section, or as a block of the previous one)."""
    text = "Inertia about the center of mass [kg m^2] (body axes, products negated: L = I w)"
    lines = fmt.heading(text) if heading else ["  " + text[0].lower() + text[1:] + ":"]
    return lines + fmt.matrix_lines(props.inertia_com, row_labels=XYZ, col_labels=XYZ, style="e")


def validity_lines(violations) -> list[str]:
    """'physical: ...' or one line per violated condition."""
    if not violations:
        return ["  physical: positive mass, finite, symmetric, positive definite, triangle inequality hold"]
    return ["  NOT physical:"] + [f"  - [{v.code}] {v.message}" for v in violations]


def warnings_lines(warnings) -> list[str]:
    return ["  - " + w for w in warnings] or ["  none"]
