"""``inertia diff A B``: the bodies whose mass properties differ between two robot descriptions.

Any two of URDF, SDF, MJCF, ``.xacro`` and OpenUSD: what a format converter changed.  Only the
standard library is imported at module level.
"""

from __future__ import annotations

from . import _format as fmt

EPILOG = """\
examples:
  inertia diff robot.urdf robot.usda                     (what urdf-usd-converter changed)
  inertia diff scene.xml out/scene.usda --tol 1e-4
  inertia diff a.urdf b.sdf --map base_link=base --format json
  inertia diff a.urdf b.urdf --output-units g,mm

A pair differs when |m_A - m_B| / max(m_A, m_B), max|I_A - I_B| / max|I| (tensors about each COM,
root frame) or |c_A - c_B| (metres, root frame) exceeds --tol.  Bodies are matched by name, then by
their USD identifier (a-b -> a_b), then by --map.  A body with mass on one side only differs.

exit status: 0 no body differs, 1 some body differs (or bad input), 2 a file could not be read."""

HELP = "compare the mass properties of two robot descriptions (URDF, SDF, MJCF, xacro, USD), body by body"
DESCRIPTION = ("Read both descriptions at their default configuration, match their bodies by name and print "
               "every body whose mass, world center of mass or world inertia differs by more than --tol, worst "
               "first, with both values.")


def register(sub) -> None:
    from ._options import add_output_options, add_robot_options, add_units, add_usd_options

    p = fmt.add_command(sub, "diff", HELP, DESCRIPTION, EPILOG, usage="A B [options]")
    p.add_argument("a", metavar="A", help="the first description (the reference)")
    p.add_argument("b", metavar="B", help="the second description")
    p.add_argument("--tol", type=float, default=1e-6, metavar="TOL",
                   help="relative for mass and inertia, metres for the COM (default 1e-6)")
    p.add_argument("--map", action="append", default=[], metavar="NAME_A=NAME_B",
                   help="match a renamed body (repeatable)")
    add_units(p)
    p.add_argument("--format", choices=("table", "json"), default="table", help="output (default table)")
    p.add_argument("--limit", type=int, default=50, metavar="N", help="print at most N bodies (default 50; json: all)")
    add_output_options(p)
    add_robot_options(p, ("xacro-arg", "package-path"))
    add_usd_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import sys

    from .._core.errors import InputError, RobotFileError
    from ..robots.diff import diff_robots
    from ..robots.io import parse_xacro_args
    from .usd import name_pairs, unset_tolerance

    if not (args.tol >= 0):
        raise InputError(f"--tol must be a non-negative number, got {args.tol}")
    units = fmt.Units.from_args(args)
    try:
        report = diff_robots(args.a, args.b, tol=args.tol, rename=name_pairs(args.map), physx=args.as_physx,
                             unset_tolerance=unset_tolerance(args), search_paths=args.package_path,
                             xacro_args=parse_xacro_args(args.xacro_arg), mesh_units=args.units)
    except RobotFileError as exc:
        print(f"inertia diff: error: {exc}", file=sys.stderr)
        return 2
    if args.format == "json":
        fmt.emit(fmt.to_json(diff_dict(report, units)))
    else:
        fmt.emit(diff_lines(report, units, limit=args.limit))
    return 1 if report.differ else 0


def diff_dict(report, units) -> dict:
    """The library's report, its masses, positions and tensors in ``units``."""
    from ._props_text import converted

    out = report.to_dict()
    for d in out["differ"]:
        d.update({side: converted(d[side], units) for side in ("a", "b") if d[side] is not None})
    out["totals"] = {k: units.mass(v) if k.startswith("mass") else v for k, v in out["totals"].items()}
    out["output_units"] = units.to_dict()
    return out


def _values(r, u) -> str:
    if r is None:
        return "absent"
    return (f"{fmt.num(u.mass(r.mass))} {u.mass_unit}, COM {fmt.vector(u.length(r.com))} {u.length_unit}, moments "
            f"{fmt.vector(u.moments(_moments(r.inertia_com)))} {u.inertia_unit}")


def _moments(I):
    import numpy as np

    return np.linalg.eigvalsh(np.asarray(I))


def diff_lines(report, units, *, limit: int = 50) -> list:
    n, u = len(report.differ), units
    lines = [f"{report.a} vs {report.b}: {fmt.plural(n, 'body', 'bodies')} differ beyond {report.tol:g}, "
             f"{fmt.plural(report.same, 'body', 'bodies')} agree (total mass {fmt.num(u.mass(report.totals['mass_a']))}"
             f" vs {fmt.num(u.mass(report.totals['mass_b']))} {u.mass_unit})"]
    for d in report.differ[:limit]:
        name = d.name_a if d.name_b in (None, d.name_a) else f"{d.name_a} -> {d.name_b}" if d.name_a else d.name_b
        errs = ", ".join(f"{k} {v:.3g}" for k, v in sorted(d.errors.items(), key=lambda kv: -kv[1]) if v > report.tol)
        lines += [f"  {name}: {errs}", f"    A: {_values(d.a, u)}", f"    B: {_values(d.b, u)}"]
    if n > limit:
        lines.append(f"  ... {n - limit} more (--limit, or --format json for all)")
    if report.massless_unmatched:
        lines.append(f"  massless bodies on one side only (not counted): {', '.join(report.massless_unmatched[:8])}"
                     + (" ..." if len(report.massless_unmatched) > 8 else ""))
    lines += [f"  note: {n}" for n in report.notes]
    return lines
