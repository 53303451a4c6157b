"""``inertia check FILE``: every problem of every link's inertial in a URDF, SDF or MJCF file.

Exit status: 0 no errors (warnings allowed), 1 errors found, 2 the file could not be read.
Only the standard library is imported at module level.
"""

from __future__ import annotations

from . import _format as fmt

EPILOG = """\
examples:
  inertia check robot.urdf
  inertia check model.sdf --package-path ~/gazebo_models --format json
  inertia check scene.xml --units mm --mass-units g
  inertia check robot.urdf --errors-only

errors (by code): non_positive_mass, not_symmetric, not_positive_definite, triangle_inequality,
massless_moving_link, below_simulator_floor (a moving body with a mass or moment under 1e-15,
which MuJoCo refuses), no_links, joints_unreadable.
warnings: com_outside_geometry, geometry_mismatch (declared vs computed from the link's own shapes at
the declared mass: principal-moment ratio outside [1/3, 3] or axes over 45 deg apart),
implausible_inertia (radius of gyration under 1 % of the link's size), legacy_mesh_inertia,
mesh_not_found (one line per folder or package; --verbose lists each mesh), mesh_unreadable,
unsupported_geometry, unsupported_pose.  notes: geometry_unusable (comparison skipped).
Massless frames (no inertial, or mass 0 and tensor 0, on fixed joints or welded to a body with mass)
are an idiom, listed in one line; a massless link that moves alone is an error.

JSON: {"file": ..., "links": [{"name": ..., "line": ..., "errors": [{"code": ..., "message": ...}],
       "warnings": [...], "notes": [...]}]}

exit status: 0 no errors, 1 errors found, 2 the file could not be read (or bad usage)."""

HELP = "check the inertials of a URDF, SDF, MJCF or OpenUSD file"
DESCRIPTION = ("For each link: non-positive mass, non-symmetric or non-positive-definite tensor, "
               "triangle-inequality violation (with the margin), center of mass outside the link's "
               "geometry, and the declared inertial against the one computed from the link's own geometry.")


def add_file_argument(p) -> None:
    """FILE and --units, the two arguments of every robot command."""
    from ._options import add_units

    p.add_argument("file", metavar="FILE", help="URDF (.urdf), SDF (.sdf), MJCF (.xml with <mujoco>), xacro or "
                                                "OpenUSD file")
    add_units(p)


def register(sub) -> None:
    from ._options import add_robot_options, add_usd_options

    p = fmt.add_command(sub, "check", HELP, DESCRIPTION, EPILOG, usage="FILE [options]")
    add_file_argument(p)
    p.add_argument("--format", choices=("table", "json"), default="table", help="output (default table)")
    detail = p.add_mutually_exclusive_group()
    detail.add_argument("-q", "--quiet", dest="detail", action="store_const", const="quiet", default="default",
                        help="print only the summary line (the exit status says the rest)")
    detail.add_argument("--errors-only", dest="detail", action="store_const", const="errors",
                        help="print the errors, not the warnings and notes")
    detail.add_argument("-v", "--verbose", dest="detail", action="store_const", const="verbose",
                        help="print every note, and every missing mesh, too")
    add_robot_options(p, ("xacro-arg", "package-path", "robot-format", "mass-units"))
    add_usd_options(p, physx=False)
    p.set_defaults(func=run)


def run(args) -> int:
    import sys

    from ..robots.xmlsafe import RobotFileError
    from ._format import MASS_UNITS
    from .props_robot import scale_masses
    from .usd import run_check

    if (code := run_check(args)) is not None:
        return code
    try:
        from ..robots.check import check_model
        from ..robots.io import parse_xacro_args, read_robot

        model = read_robot(args.file, format=args.robot_format, search_paths=args.package_path,
                           xacro_args=parse_xacro_args(args.xacro_arg))
    except RobotFileError as exc:
        print(f"inertia check: error: {exc}", file=sys.stderr)
        return 2
    scale_masses(model, MASS_UNITS[args.mass_units])
    report = check_model(model, mesh_units=args.units)
    if args.format == "json":
        fmt.emit(fmt.to_json(report.to_dict()))
    else:
        fmt.emit(report_lines(report, model, detail=args.detail))
    return 1 if report.n_errors else 0


def report_lines(report, model, *, detail: str = "default") -> list:
    """The table: one summary line, then (unless ``detail="quiet"``) each link's errors and
    warnings (``"errors"``: errors only; ``"verbose"``: notes too), and one line per kind of
    note left out."""
    n_notes = sum(len(lk.notes) for lk in report.links)
    lines = [f"{report.file} ({model.format.upper()}, {fmt.plural(len(report.links), 'link')}): "
             f"{fmt.plural(report.n_errors, 'error')}, {fmt.plural(report.n_warnings, 'warning')}"
             + (f", {fmt.plural(n_notes, 'note')}" if n_notes else "")]
    if detail == "quiet":
        return lines
    lines += [f"  error {e.code}: {e.message}" for e in report.errors]
    missing = {} if detail == "verbose" else _missing_meshes(report)
    if detail != "errors":
        lines += [f"  warning {w.code}: {w.message}" for w in report.warnings if id(w) not in missing]
        lines += [f"  note {n.code}: {n.message}" for n in report.notes]
        lines += _missing_summary(missing)
    if report.massless_frames and detail != "errors":
        names = report.massless_frames
        shown = ", ".join(names[:8]) + (f", ... ({len(names) - 8} more)" if len(names) > 8 else "")
        lines.append(f"  {fmt.plural(len(names), 'massless frame')} (mass 0 on fixed joints, or welded to a body "
                     f"with mass; an idiom, not errors): {shown}")
    kinds = ["errors"] + (["warnings"] if detail != "errors" else []) + (["notes"] if detail == "verbose" else [])
    for lk in report.links:
        found = [(kind[:-1], f) for kind in kinds for f in getattr(lk, kind) if id(f) not in missing]
        if not found:
            continue
        lines.append(f"  link {lk.name!r} (line {lk.line}):")
        lines += [f"    {kind} {f.code}: {_short(f.message, report.file, lk.name)}" for kind, f in found]
    if n_notes and detail == "default":
        lines += _note_summary(report)
    return lines


def _missing_meshes(report) -> dict:
    """``{id(finding): (root, mesh, link)}`` for each mesh_not_found warning whose message names the
    mesh: root is the folder it was looked for in, or ``package://NAME``, ``model://NAME``."""
    import os
    import re

    out = {}
    for lk in [None, *report.links]:
        for w in report.warnings if lk is None else lk.warnings:
            m = w.code == "mesh_not_found" and re.search(r"(?:mesh|file) '([^']*)' not found \(([^)]*)\)", w.message)
            if not m:
                continue
            uri, how = m.groups()
            if uri.startswith(("package://", "model://")):
                root = uri.split("/", 3)[2] and "/".join(uri.split("/", 3)[:3])
            elif how.startswith("looked for "):
                root = os.path.normpath(os.path.dirname(how[len("looked for "):]))
            else:
                root = how if how == "meshdir" else os.path.dirname(uri) or "."
            out[id(w)] = (root, os.path.basename(uri), None if lk is None else lk.name)
    return out


def _missing_summary(missing: dict) -> list:
    """One line per folder or package of missing meshes, then one hint."""
    by_root: dict = {}
    for root, mesh, link in missing.values():
        by_root.setdefault(root, []).append((mesh, link))
    lines = []
    for root, found in by_root.items():
        meshes, links = dict.fromkeys(m for m, _ in found), {lk for _, lk in found if lk}
        where = "the file's meshdir" if root == "meshdir" else root
        lines.append(f"  warning mesh_not_found: {fmt.plural(len(meshes), 'mesh', 'meshes')} of "
                     f"{fmt.plural(len(links), 'link')} not found in {where} (e.g. {next(iter(meshes))}); "
                     "their geometry comparisons are skipped")
    if by_root:
        package = any(r.startswith(("package://", "model://")) for r in by_root)
        lines.append("  hint: " + ("--package-path DIR adds a folder to search for package:// and model:// meshes; "
                                   if package else "mesh paths are read relative to the robot file (MJCF: its "
                                                   "meshdir); ") + "--verbose lists each missing mesh")
    return lines


def _short(message: str, path: str, name: str) -> str:
    """A finding's message under its link's heading: ``line N:`` for this file's
    ``file:N:``, without the link's name again."""
    if message.startswith(f"{path}:"):
        message = "line " + message[len(path) + 1:]
    for kind in ("link", "body"):
        message = message.replace(f" {kind} {name!r}:", "", 1)
    import re

    return re.sub(r"^line \d+: (line \d+: )", r"\1", message)  # the shape's own line, not its link's


def _note_summary(report) -> list:
    """One line per kind of note: how many, and the command that lists them."""
    counts: dict = {}
    for lk in report.links:
        for n in lk.notes:
            counts.setdefault(n.code, set()).add(lk.name)
    what = {"geometry_unusable": "geometry comparisons skipped (shapes that are not usable solids, e.g. open meshes)",
            "mesh_overlapping_shells": "meshes whose closed parts overlap, summed as the simulator sums them",
            "inertial_ignored": "declared inertials ignored (inertiafromgeom)",
            "mesh_reader_message": "mesh files whose reader complained (e.g. a COLLADA texture it cannot load)"}
    return [f"  notes: {what.get(code, code)} in {fmt.plural(len(names), 'link')}; --verbose lists them"
            for code, names in counts.items()]
