"""``inertia props|check|fix STAGE.usd[a|c|z]``: the OpenUSD side of the robot commands.

``props``, ``check`` and ``fix`` hand a stage to this module (one dispatch line each); it reads
the stage with usd-core (the ``usd`` extra) and prints what the other robot formats print.
Only the standard library is imported at module level.
"""

from __future__ import annotations

import os

from . import _format as fmt
from ._options import USD_EXTENSIONS, add_usd_options


def is_usd_file(text) -> bool:
    """A path to something that is not a folder (the reader names what it is) with an OpenUSD extension."""
    text = str(text)
    return os.path.lexists(text) and not os.path.isdir(text) and os.path.splitext(text)[1].lower() in USD_EXTENSIONS


def unset_tolerance(args) -> float:
    from ..robots.usd.mass import UNSET_TOLERANCE

    return 0.0 if getattr(args, "zero_unset", False) else UNSET_TOLERANCE


def add_fix_arguments(p) -> None:
    """``fix``'s options for stages: --from SOURCE, --layer OUT, --map A=B."""
    add_usd_options(p, physx=False)
    g = p.add_argument_group("writing another description's values (fix STAGE --from SOURCE)")
    g.add_argument("--from", dest="from_source", metavar="SOURCE",
                   help="URDF, SDF, MJCF, xacro or USD file whose bodies' mass properties are written into STAGE "
                        "(bodies matched by name)")
    g.add_argument("--map", action="append", default=[], metavar="SOURCE_NAME=STAGE_NAME",
                   help="match a renamed body (repeatable)")
    g.add_argument("--layer", metavar="OUT.usda",
                   help="write an override layer that sublayers STAGE instead of editing it")


def _not_usd(args, path, options) -> bool:
    """True when ``path`` is no stage (after refusing the stage-only ``options`` that were given)."""
    from .._core.errors import InputError

    if is_usd_file(path):
        return False
    for flag, attr in options:
        if getattr(args, attr, None) not in (None, False, []):
            raise InputError(f"{flag} applies to OpenUSD stages only, not to {path!r}")
    return True


def _refuse_mesh_options(args) -> None:
    from .._core.errors import InputError

    for flag, attr, unset in (("--joint", "joint", []), ("--density", "density", None), ("--mass", "mass", None),
                              ("--xacro-arg", "xacro_arg", []), ("--shell", "shell", False),
                              ("--robot-format", "robot_format", None)):
        if getattr(args, attr, unset) not in (unset, None):
            raise InputError(f"{flag} does not apply to an OpenUSD stage (its bodies are read at their authored pose)")


def run_props(args, units) -> int | None:
    """``props`` for a stage (None: SOURCE is no stage)."""
    if _not_usd(args, args.source, (("--as-physx", "as_physx"), ("--zero-unset", "zero_unset"))):
        return None
    from ..robots.usd.mass import stage_mass_properties

    _refuse_mesh_options(args)
    result = stage_mass_properties(args.source, physx=args.as_physx, tol=unset_tolerance(args))
    sub = result.subtree(args.subtree) if args.subtree else None
    props = sub if sub is not None else result.total
    if args.format in ("urdf", "mjcf", "sdf"):
        fmt.emit(fmt.inertial_block(props, args.format))
        return 0
    links = result.subtree_links(args.subtree) if sub is not None else result.links
    if args.format == "json":
        from ._props_text import body_dict, link_dict

        u = units
        fmt.emit(fmt.to_json({
            "source": str(result.path), "format": result.format, "frame": result.frame, "subtree": args.subtree,
            "configuration": {}, **body_dict(props, u), "links": [link_dict(lk, u) for lk in links],
            "notes": list(result.notes),
            "articulations": {root: {"bodies": a["bodies"], **({"mass": u.mass(a["total"].mass),
                                                               "com": u.length(a["total"].com),
                                                               "inertia_com": u.inertia(a["total"].inertia_com)}
                                                              if a["total"] is not None else {})}
                              for root, a in result.articulations.items()},
            "as_physx": bool(args.as_physx), "output_units": u.to_dict(),
            "conventions": (f"{u.conventions()}; every position and tensor in the stage's world frame at the "
                            "authored pose; inertia_com about the center of mass")}))
    else:
        fmt.emit(props_lines(result, props, links, units, args.subtree, physx=args.as_physx))
    return 0


def props_lines(result, props, links, units, subtree=None, *, physx: bool = False) -> list:
    from ..robots.usd.mass import SOURCES
    from ._props_text import canonical_lines, inertia_lines

    u = units
    what = f"the subtree of body {subtree!r} ({len(links)} bodies)" if subtree else "every dynamic body"
    lines = fmt.heading(f"Mass properties of {what}: {result.path}")[1:]
    lines += fmt.key_values([
        ("format", f"OpenUSD (UsdPhysics), {fmt.plural(len(result.links), 'rigid body', 'rigid bodies')}"
                   + (f", {len(result.articulations)} articulation(s)" if result.articulations else "")),
        ("frame", "world, at the authored pose (SI units)"),
        ("colliders", "as PhysX simulates them (--as-physx)" if physx else "exact solids"),
        ("mass", f"{fmt.num(u.mass(props.mass))} {u.mass_unit}"),
        ("center of mass", f"{fmt.vector(u.length(props.com))} {u.length_unit}"),
    ])
    lines += inertia_lines(props, u, heading=False, axes="world axes")
    lines += canonical_lines(props, u)
    lines += fmt.heading("Bodies")
    m, L = u.mass_unit, u.length_unit
    rows = [[lk.name, fmt.num(u.mass(lk.mass)), *(fmt.num(x) for x in u.length(lk.com)), lk.source
             + ("" if lk.exact_mass != lk.exact_mass else f" (exact solid {fmt.num(u.mass(lk.exact_mass))} {m})")]
            for lk in links]
    lines += fmt.table(["body", f"mass [{m}]", f"com x [{L}]", f"com y [{L}]", f"com z [{L}]", "source"], rows)
    lines += [f"  {s}: {SOURCES[s]}" for s in dict.fromkeys(lk.source for lk in links)]
    for root, a in result.articulations.items():
        total = "no mass" if a["total"] is None else (f"{fmt.num(u.mass(a['total'].mass))} {m}, COM "
                                                      f"{fmt.vector(u.length(a['total'].com))} {L}")
        lines.append(f"  articulation {root}: {fmt.plural(len(a['bodies']), 'body', 'bodies')}, {total}")
    notes = list(result.notes) + [f"{lk.name}: {n}" for lk in links for n in lk.notes]
    if notes:
        lines += fmt.heading("Notes") + [f"  - {n}" for n in notes]
    return lines


def run_check(args) -> int | None:
    """``check`` for a stage (None: FILE is no stage)."""
    import sys

    if _not_usd(args, args.file, (("--zero-unset", "zero_unset"),)):
        return None
    from .._core.errors import RobotFileError
    from ..robots.usd.check import check_stage
    from ..robots.usd.stage import read_stage

    try:
        stage = read_stage(args.file)
    except RobotFileError as exc:
        print(f"inertia check: error: {exc}", file=sys.stderr)
        return 2
    report = check_stage(stage, tol=unset_tolerance(args))
    if args.format == "json":
        fmt.emit(fmt.to_json(report.to_dict()))
    else:
        fmt.emit(check_lines(report, detail=args.detail))
    return 1 if report.n_errors else 0


def check_lines(report, *, detail: str = "default") -> list:
    """One summary line, then each body's errors and warnings (``detail`` as for the other formats)."""
    lines = [f"{report.file} (OpenUSD, {fmt.plural(len(report.links), 'rigid body', 'rigid bodies')}): "
             f"{fmt.plural(report.n_errors, 'error')}, {fmt.plural(report.n_warnings, 'warning')}"]
    if detail == "quiet":
        return lines
    lines += [f"  error {e.code}: {e.message}" for e in report.errors]
    if detail != "errors":
        lines += [f"  warning {w.code}: {w.message}" for w in report.warnings]
    kinds = ["errors"] + (["warnings"] if detail != "errors" else []) + (["notes"] if detail == "verbose" else [])
    for lk in report.links:
        found = [(kind[:-1], f) for kind in kinds for f in getattr(lk, kind)]
        if found:
            lines.append(f"  body {lk.name!r}:")
            lines += [f"    {kind} {f.code}: {f.message}" for kind, f in found]
    return lines


def run_fix(args) -> int | None:
    """``fix`` for a stage (None: FILE is no stage)."""
    import sys

    if _not_usd(args, args.file, (("--zero-unset", "zero_unset"), ("--from", "from_source"), ("--map", "map"),
                                  ("--layer", "layer"))):
        return None
    from .._core.errors import InputError, RobotFileError
    from ..robots.usd.write import check_written, fix_stage

    if args.from_geometry or args.flip_products or args.density is not None:
        raise InputError("for an OpenUSD stage, fix repairs the authored MassAPI values (the default) or writes "
                         "another description's values (--from SOURCE); --from-geometry, --flip-products and "
                         "--density are for URDF, SDF and MJCF files")
    rename = name_pairs(args.map)
    tol = unset_tolerance(args)
    try:
        report = fix_stage(args.file, args.output, source=args.from_source, rename=rename, in_place=args.in_place,
                           layer=args.layer, unset_tolerance=tol)
    except RobotFileError as exc:
        print(f"inertia fix: error: {exc}", file=sys.stderr)
        return 2
    check_written(report, args.from_source, rename=rename, unset_tolerance=tol)
    fmt.emit(fix_lines(report), file=sys.stderr)
    return 1 if report.remaining else 0


def fix_lines(report) -> list:
    """What the fix wrote where, what it left and why the result still fails (if it does)."""
    if report.identical:
        lines = [f"{report.output}: nothing to write; the stage already holds these values"]
    else:
        lines = [f"wrote {', '.join(report.layers)}: {fmt.plural(len(report.changed), 'body', 'bodies')} changed "
                 "(only the MassAPI attributes that change)"]
    lines += fmt.fix_report_lines(report, "body", "bodies", "still fails")
    return lines + [f"  note: {n}" for n in report.notes]


def name_pairs(items) -> dict:
    from .._core.errors import InputError

    out = {}
    for item in items or ():
        a, sep, b = str(item).partition("=")
        if not sep or not a.strip() or not b.strip():
            raise InputError(f"--map {item!r} must read NAME_IN_A=NAME_IN_B")
        out[a.strip()] = b.strip()
    return out
