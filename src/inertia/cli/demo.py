"""``inertia demo``: the package's main job on a real body, with no arguments needed.

By default it builds the demo body itself: a steel T-handle (the body of the famous
intermediate-axis flip videos), an assembly of two solid cylinders with exact mass properties
(:func:`inertia.massprops.bodies.t_handle`).  It prints the mass properties, the canonical form
(principal moments, axes, repeated-moment report), the validity check, the six-point and
four-point particle models, the equivalent uniform box and ellipsoid and the flip.

``--mesh FILE`` runs the same tour on your own body (``--units``, ``--density``/``--mass``
as for ``inertia props``; default there: metres and 1000 kg/m^3).
"""

from __future__ import annotations

import math

from . import _format as fmt

#: where the report goes by default (relative to the working folder)
DEFAULT_OUT = "inertia-report"

EPILOG = """\
default body: a steel T-handle built from two solid cylinders (cross-bar 80 mm long and 12 mm
thick, stem 50 mm long and 10 mm thick), 7850 kg/m^3, exact mass properties.

examples:
  inertia demo
  inertia demo --density 2700                 (the same T-handle in aluminium)
  inertia demo --mesh part.stl --units mm --mass 0.25
  inertia demo --output-units g,mm --no-report
  inertia demo --control                      (and hold the spin with reaction wheels)
  inertia demo --format json"""

HELP = "tour of the package on a steel T-handle (or on --mesh FILE)"
DESCRIPTION = ("Mass properties, canonical form, validity, six-point and four-point particle "
               "models and the equivalent box of a real body, in readable tables.")


def register(sub) -> None:
    from ._options import add_mesh_options, add_output_options, add_units
    from .props import add_format_argument

    p = fmt.add_command(sub, "demo", HELP, DESCRIPTION, EPILOG, usage="[--mesh FILE] [options]")
    p.add_argument("--mesh", metavar="FILE",
                   help="your own closed triangle mesh (STL, OBJ, PLY, OFF, ...) instead of the T-handle")
    g = p.add_argument_group("the body (give at most one of --density and --mass)")
    g.add_argument("--density", type=float, metavar="RHO",
                   help="density in kg/m^3 (default: 7850, steel, for the T-handle; 1000 for --mesh)")
    g.add_argument("--mass", type=float, metavar="KG", help="the body's mass in kg, its density following")
    add_units(g)
    add_format_argument(p)
    from ._control import HELP as CONTROL_HELP

    p.add_argument("--control", action="store_true", help=CONTROL_HELP)
    add_mesh_options(p)
    add_output_options(p)
    r = p.add_argument_group("report (a folder with index.html, plots, an animation and a 3D page)")
    r.add_argument("--out", metavar="DIR", default=DEFAULT_OUT,
                   help=f"report folder (default: ./{DEFAULT_OUT}); a folder inertia did not create is refused "
                        "unless --force")
    r.add_argument("--no-video", action="store_true", help="skip the animation (the slowest part)")
    r.add_argument("--video-format", choices=("auto", "mp4", "gif"), default="auto",
                   help="animation format: mp4 (720 px, 30 fps, the ffmpeg of imageio-ffmpeg) or gif (Pillow, 25 fps); "
                        "default auto: mp4 where imageio-ffmpeg is installed, else gif")
    r.add_argument("--video-view", choices=("body", "model"), default="body",
                   help="what the video shows: the body itself (default) or its equivalent box, six point masses "
                        "and principal axes")
    r.add_argument("--no-report", action="store_true", help="print the tables only; write no files")
    r.add_argument("--force", action="store_true", help="write the report into an existing foreign folder")
    p.set_defaults(func=run)


def demo_body(args):
    """``(props, info, display_mesh or None, built_body or None)`` for the demo's body."""
    from .._core.errors import InputError
    from ._source import SourceInfo, load_source

    if args.mesh is not None:
        props, info = load_source(args, source=args.mesh)
        return props, info, None, None
    used = [flag for flag, on in (("--units", args.units != "m"), ("--shell", args.shell),
                                  ("--fix-orientation", args.fix_orientation),
                                  ("--accept-defects", args.accept_defects), ("--robust", args.robust)) if on]
    if used:
        raise InputError(f"{', '.join(used)} appl{'ies' if len(used) == 1 else 'y'} to --mesh FILE only, not to the "
                         "built-in T-handle")
    if args.density is not None and args.mass is not None:
        raise InputError(f"give at most one of --density ({args.density!r}) and --mass ({args.mass!r})")
    from ..massprops.bodies import STEEL_DENSITY, t_handle

    body = t_handle(density=STEEL_DENSITY if args.density is None else args.density)
    props = body.props
    if args.mass is not None:
        from .._core.validation import as_positive_scalar

        props = props.with_mass(as_positive_scalar(args.mass, "--mass"))
    source = "--density" if args.density is not None else (
        "from --mass" if args.mass is not None else "steel, the demo's default")
    info = SourceInfo("built-in T-handle", "assembly", "m", props.mass / props.volume, source)
    info.dimensions_text = body.description
    return props, info, body.display_mesh(), body


def run(args) -> int:
    if args.control and args.mesh is not None:
        from .._core.errors import InputError

        raise InputError("--control shows the built-in T-handle and Basilisk's spacecraft; it does not take --mesh")
    units = fmt.Units.from_args(args)
    props, info, display_mesh, body = demo_body(args)
    bundled = body is not None
    report = build_report(props)
    control = None
    if args.control:
        from ..control.studies import showcase

        control = showcase()
    import os

    title = body.name if bundled else os.path.basename(str(info.source))
    files = study = None
    repeated = props.principal().degenerate
    if repeated:      # no unique intermediate axis (within the input's precision): no flip to show
        import sys

        if not args.no_report:
            print("inertia demo: note: no report written: it shows the intermediate-axis flip, and this body "
                  "has repeated principal moments", file=sys.stderr)
    elif not args.no_report:
        files = _write_report(args, props, title, display_mesh, _describe(info, body), control)
    if files is not None:
        study = files["study"]
    elif not repeated:  # --no-report, or the plotting libraries are missing: the tables still come
        from ..dynamics.flip_study import flip_study

        study = flip_study(props.principal().moments)
    if args.format == "json":
        d = report_dict(props, info, report, units, bundled=bundled)
        d["flip"] = None if study is None else _flip_dict(study)
        if control is not None:
            from ._control import control_dict

            d["control"] = control_dict(control)
        if files is not None:
            d["report"] = {"index": str(files["index"]), "files": sorted(f for v in files["files"].values() for f in v)}
        fmt.emit(fmt.to_json(d))
    else:
        lines = report_lines(props, info, report, units, bundled=bundled) + flip_lines(study, props)
        if control is not None:
            from ._control import control_lines

            lines += control_lines(control, 8)
        if files is not None:
            lines += fmt.heading(f"{8 + (control is not None)}. Report") + [
                f"  {files['index']}  (open it in a browser; {sum(len(v) for v in files['files'].values()) + 1} files)"]
        fmt.emit(lines)
    return 0


#: the steps of the report, for the progress bar
REPORT_STEPS = ("simulating the flip", "plotting", "animating", "writing the 3D page")


def _describe(info, body) -> str:
    """One line about the body for the report's header."""
    if body is not None:
        return f"{body.description}; {info.density:g} kg/m\u00b3 ({info.density_source})"
    return f"mesh {info.source} (lengths in {info.units})"


def _write_report(args, props, title, display_mesh, description, control=None):
    """The report folder, or None (with a note) when the plotting libraries are missing."""
    import sys

    from .._core.progress import StepProgress

    mesh = display_mesh
    if mesh is None and args.mesh:
        try:
            from ..geometry.mesh_io import load_mesh

            mesh = load_mesh(args.mesh, units=args.units)
        except Exception:  # noqa: BLE001 - the page then shows the equivalent box only
            mesh = None
    try:
        import matplotlib  # noqa: F401 - the report needs it; the tables do not
    except ImportError:
        print("inertia demo: note: no report written: it needs matplotlib and Pillow "
              "(pip install 'inertia[viz]' or '.[all]')", file=sys.stderr)
        return None
    from ..viz.report import build_report as build_folder

    bar = StepProgress(REPORT_STEPS + (("holding the spin",) if control is not None else ()))
    try:
        return build_folder(args.out, props, title=title, description=description, mesh=mesh,
                            video=not args.no_video, force=args.force, progress=bar,
                            animation_format=args.video_format, video_view=args.video_view, control=control)
    finally:
        bar.clear()


def _flip_dict(study) -> dict:
    return {"moments": study.moments.tolist(), "omega0_body_principal": study.omega0_body.tolist(),
            "flip_interval": float(study.flip_interval), "flip_times": study.flip_times.tolist(),
            "flips_detected": study.detected_flips.tolist(),
            "integrators": {k: {"h": v["h"], "max_energy_error": float(v["energy_error"].max()),
                                "max_momentum_error": float(v["momentum_error"].max()),
                                "max_attitude_error_rad": float(v["attitude_error"].max())}
                            for k, v in study.integrators.items()}}


def flip_lines(study, props) -> list[str]:
    """Section 7: the intermediate-axis flip, predicted and simulated (None: repeated moments)."""
    lines = fmt.heading("7. Spin about the intermediate axis: the Dzhanibekov flip")
    if study is None:
        groups = " and ".join("I" + " = I".join(str(k + 1) for k in g) for g in props.principal().degenerate)
        return lines + [f"  none: {groups} within {props.moments_rtol:.2g} of the largest moment (the input's "
                        "precision), so there is no unique intermediate axis to flip about"]
    w = study.omega0_body
    lines += [f"  spin            omega0 = [{', '.join(fmt.num(x) for x in w)}] rad/s about principal axes 1, 2, 3",
              f"  predicted       a flip every 2K(m)/lambda = {fmt.num(study.flip_interval)} s",
              f"  exact solution  flips at {', '.join(f'{x:.4f}' for x in study.detected_flips)} s "
              f"(predicted {', '.join(f'{x:.4f}' for x in study.flip_times[:len(study.detected_flips)])} s)"]
    rows = [[name, fmt.num(v["h"]), f"{v['energy_error'].max():.2e}", f"{v['momentum_error'].max():.2e}",
             f"{v['attitude_error'].max():.2e}"]
            for name, v in study.integrators.items()]
    lines += fmt.table(["integrator", "h [s]", "max |dE/E|", "max |d|L|/|L||", "max attitude error [rad]"], rows)
    from ..dynamics.flip_study import ANGLE_PER_STEP, MAX_STEPS

    turn = max(v["h"] for v in study.integrators.values()) * math.hypot(*(float(x) for x in w))
    if turn > ANGLE_PER_STEP * (1 + 1e-9):
        lines.append(f"  note: {MAX_STEPS:,} steps cannot reach {ANGLE_PER_STEP} rad per step over this slow flip: "
                     f"each step turns the body {turn:.2g} rad, and the attitude error shows what that costs")
    return lines


def build_report(props) -> dict:
    """Everything the demo shows beyond the mass properties (models and equivalent solids)."""
    from ..massprops.equivalent import equivalent_box, equivalent_ellipsoid
    from ..particles.models import four_point_model, six_point_model

    return {
        "canonical": props.principal(),
        "six_point": six_point_model(props),
        "four_point": four_point_model(props),
        "equivalent_box": equivalent_box(props),
        "equivalent_ellipsoid": equivalent_ellipsoid(props),
    }


def _canonical_dict(cf) -> dict:
    return {
        "principal_moments": cf.moments,
        "R_body_principal": cf.R_body_principal,
        "p_body_com": cf.p_body_com,
        "degenerate_moments": [list(g) for g in cf.degenerate],
        "rtol": cf.rtol,
    }


def report_dict(props, info, report, units, *, bundled: bool) -> dict:
    """JSON-ready dict of the whole demo (its masses, lengths and tensors in ``units``)."""
    from .particles import model_dict
    from .props import props_dict

    u = units
    canonical = _canonical_dict(report["canonical"])
    canonical.update(principal_moments=u.moments(canonical["principal_moments"]),
                     p_body_com=u.length(canonical["p_body_com"]))
    return {
        "body": info.to_dict(u),
        "mass_properties": props_dict(props, info, u),
        "canonical_form": canonical,
        "validity": [{"code": v.code, "message": v.message} for v in props.check()],
        "six_point": model_dict(report["six_point"], props, u),
        "four_point": model_dict(report["four_point"], props, u),
        "equivalent_box": _solid_dict(report["equivalent_box"], u),
        "equivalent_ellipsoid": _solid_dict(report["equivalent_ellipsoid"], u),
        "output_units": u.to_dict(),
    }


def _solid_dict(solid, u) -> dict:
    """An equivalent solid's ``to_dict()`` in ``u``: its mass, volume and every length."""
    d = solid.to_dict()
    by_key = {"mass": u.mass, "volume": u.volume, "p_body_com": u.length}
    return {k: by_key[k](v) if k in by_key else u.length(v) if isinstance(v, list) and k != "R_body_principal"
            and k != "warnings" else v for k, v in d.items()}


def report_lines(props, info, report, units, *, bundled: bool) -> list[str]:
    """The demo's readable tables."""
    from .particles import model_lines
    from .props import canonical_lines, inertia_lines, summary_lines, validity_lines, warnings_lines

    u = units
    title = "inertia demo: " + ((("a steel " if info.density_source.startswith("steel") else "a ") + "T-handle")
                                if bundled else str(info.source))
    lines = [title, "=" * len(title)]
    if bundled:
        lines += ["Body: a T-handle built from two solid cylinders (exact mass properties); "
                  + ("SI units throughout." if u.si else f"masses in {u.mass_unit}, lengths in {u.length_unit}."),
                  "Your own body: inertia demo --mesh FILE [--units mm] [--density RHO | --mass KG]"]
    lines += [""] + summary_lines(props, info, u, title="1. Mass properties")
    lines += inertia_lines(props, u, heading=False)
    lines += canonical_lines(props, u, title="2. Canonical form: principal moments and axes")
    lines += fmt.heading("3. Validity")
    lines += validity_lines(props.check())
    lines += ["  warnings:"] + ["  " + w for w in warnings_lines([f.message for f in props.findings])]
    lines += model_lines("4. Six-point model", report["six_point"], props, u)
    lines += model_lines("5. Four-point model", report["four_point"], props, u)
    lines += _equivalent_lines(props, report["equivalent_box"], report["equivalent_ellipsoid"], u)
    return lines


def _equivalent_lines(props, box, ellipsoid, u) -> list[str]:
    """Equivalent uniform box and ellipsoid: dimensions along the principal axes, volume, density."""
    lines = fmt.heading("6. Equivalent uniform solids (same mass, COM and inertia tensor)")
    rows = []
    fx = fmt.fixed_formatter([u.length(box.dims), u.length(ellipsoid.dims)])
    for name, what, solid in (("box", "edge", box), ("ellipsoid", "semi-axis", ellipsoid)):
        rows.append([name, what, *(fx(x) for x in u.length(solid.dims)),
                     fmt.num(u.volume(solid.volume)), fmt.num(u.density(solid.density))])
    L = u.length_unit
    lines += fmt.table(["solid", "dimension", f"axis 1 [{L}]", f"axis 2 [{L}]", f"axis 3 [{L}]", f"volume [{L}^3]",
                        f"density [{u.density_unit}]"], rows)
    volume = f"{fmt.num(u.volume(props.volume))} {L}^3" if props.volume == props.volume else "n/a (thin shell)"
    lines.append(f"  axes: the principal axes of section 2, centred on the COM; body volume {volume}")
    for w in tuple(box.findings) + tuple(ellipsoid.findings):
        lines.append(f"  warning: {w.message}")
    return lines
