"""``inertia fix FILE -o OUT``: a corrected copy of a robot file's inertials (atomic write).

Only the standard library is imported at module level.
"""

from __future__ import annotations

from . import _format as fmt

EPILOG = """\
examples:
  inertia fix model.sdf -o fixed.sdf                        (invalid tensors -> nearest physical)
  inertia fix robot.urdf -o fixed.urdf --from-geometry collision --units mm
  inertia fix scene.xml -o scene_fixed.xml --from-geometry visual --density 2700 --all-links
  inertia fix robot.urdf --in-place --nearest-valid
  inertia fix stage.usda -o fixed.usda --from robot.urdf    (an OpenUSD stage from another description)

Nearest physical tensor: the declared tensor's principal moments projected (least squares) onto
{I_i >= m, I_i + I_j - I_k >= m}, m = 1e-6 trace (a margin inside the physical set), axes and COM
kept.  From geometry: the link's shapes as uniform solids, at the declared mass (or at --density),
COM and tensor written in the link frame; only non-physical inertials unless --all-links.
The output is the input byte for byte except the numbers (or inertial elements) that change:
quoting, attribute order, indentation, line endings, comments and encoding are kept, and a
file with nothing to fix comes back identical.  A tensor that is zero or rounding noise
(largest moment below 1e-15 kg m^2, the least MuJoCo accepts) is not "fixed" into another
meaningless number: it is kept and reported, and the exit status says the output still fails.

exit status: 0 written and valid, 1 bad input or the written file still fails the check (the
same judgement as 'inertia check' of the written file: it says which links and why), 2 the file
could not be read."""

HELP = "write a corrected copy of a URDF, SDF or MJCF file's inertials"
DESCRIPTION = ("Recompute inertials from each link's collision (or visual) geometry, or replace invalid "
               "tensors by the nearest physically valid one; write the result atomically.")


def register(sub) -> None:
    from ._options import add_robot_options
    from .check import add_file_argument

    p = fmt.add_command(sub, "fix", HELP, DESCRIPTION, EPILOG, usage="FILE (-o OUT | --in-place) [options]")
    add_file_argument(p)
    p.add_argument("-o", "--output", metavar="OUT", help="corrected copy (required unless --in-place)")
    p.add_argument("--in-place", action="store_true", help="replace FILE itself")
    mode = p.add_mutually_exclusive_group()
    mode.add_argument("--from-geometry", nargs="?", const="auto", choices=("auto", "collision", "visual"),
                      help="recompute non-physical inertials from the link's geometry (default: collision, else "
                           "visual); with --all-links every inertial")
    mode.add_argument("--nearest-valid", action="store_true",
                      help="replace only non-physical tensors by the nearest physical one (the default)")
    mode.add_argument("--flip-products", action="store_true",
                      help="negate the products of non-physical tensors that the negation makes physical "
                           "(products copied from CAD with the wrong sign)")
    p.add_argument("--density", type=float, metavar="RHO",
                   help="with --from-geometry: kg/m^3, the mass then follows from the volume")
    p.add_argument("--all-links", action="store_true",
                   help="with --from-geometry: recompute every link's inertial, valid ones too")
    add_robot_options(p, ("package-path", "mass-units"))
    from .usd import add_fix_arguments
    add_fix_arguments(p)
    p.set_defaults(func=run)


def run(args) -> int:
    import sys

    from .._core.errors import InputError
    from ..robots.xmlsafe import RobotFileError
    from ._format import MASS_UNITS
    from .usd import run_fix

    if (code := run_fix(args)) is not None:
        return code
    if args.density is not None and not args.from_geometry:
        raise InputError("--density needs --from-geometry")
    if args.all_links and not args.from_geometry:
        raise InputError("--all-links needs --from-geometry")
    if args.density is not None and not (args.density > 0 and args.density != float("inf")):
        raise InputError(f"--density must be finite and positive, got {args.density}")
    try:
        from ..robots.fix import fix_file

        mode = "geometry" if args.from_geometry else "flip" if args.flip_products else "nearest"
        report = fix_file(args.file, args.output, mode=mode,
                          role=None if args.from_geometry in (None, "auto") else args.from_geometry,
                          density=args.density, in_place=args.in_place, search_paths=args.package_path,
                          mesh_units=args.units, mass_scale=MASS_UNITS[args.mass_units],
                          links="all" if args.all_links else "invalid")
    except RobotFileError as exc:
        print(f"inertia fix: error: {exc}", file=sys.stderr)
        return 2
    fmt.emit(fix_summary(report, mode), file=sys.stderr)
    return 1 if report.remaining else 0


def fix_summary(report, mode: str) -> list:
    """What the fix did, what it left and why the output is still invalid (if it is)."""
    n = len(report.changed)
    if report.identical:
        what = "nothing changed" if report.remaining else "nothing to fix"
        lines = [f"wrote {report.output}: {what}; it is byte-identical to the input"]
    else:
        lines = [f"wrote {report.output}: {fmt.plural(n, 'inertial')} changed (only their numbers; every other "
                 "byte as in the input)"]
    lines += fmt.fix_report_lines(report, "link", "links", "still fails the check")
    if report.remaining:
        if mode == "flip":
            lines.append("  --flip-products only negates products where that makes the tensor physical; "
                         "for these it does not: try --nearest-valid or --from-geometry")
        elif mode == "nearest":
            lines.append("  try --from-geometry, or declare these tensors")
    return lines
