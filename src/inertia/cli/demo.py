"""``inertia demo``: the package's main job on a real body, with no arguments needed.

By default it loads the bundled sample body ``inertia/data/wingnut.obj`` (a wing nut by
Oded Stein, Eitan Grinspun and Keenan Crane, CC BY 4.0; see ``inertia/data/README.md``),
reads its coordinates as centimetres (a hand-sized wing nut, 72 mm across the wings) and
gives it the density of steel, 7850 kg/m^3.  It prints the mass properties, the canonical
form (principal moments, axes, repeated-moment report), the validity check, the six-point
and four-point particle models and the equivalent uniform box and ellipsoid.

``--mesh FILE`` runs the same tour on your own body (``--units``, ``--density``/``--mass``
as for ``inertia props``; default there: metres and 1000 kg/m^3).
"""

from __future__ import annotations

from . import _format as fmt

#: bundled sample body (package data) and how the demo reads it
SAMPLE_FILE = "wingnut.obj"
SAMPLE_UNITS = "cm"
SAMPLE_DENSITY = 7850.0  # steel, kg/m^3
SAMPLE_CREDIT = ('"Wing nut" by Oded Stein, Eitan Grinspun and Keenan Crane '
                 "(github.com/odedstein/meshes), CC BY 4.0")
#: where the report goes by default (relative to the working folder)
DEFAULT_OUT = "inertia-report"

EPILOG = f"""\
default body: the bundled {SAMPLE_FILE}, "Wing nut" by Oded Stein, Eitan Grinspun and
Keenan Crane (github.com/odedstein/meshes, CC BY 4.0), read in {SAMPLE_UNITS} (72 mm across
the wings) with the density of steel, {SAMPLE_DENSITY:g} kg/m^3.

examples:
  inertia demo
  inertia demo --density 2700                 (the same wing nut in aluminium)
  inertia demo --mesh part.stl --units mm --mass 0.25
  inertia demo --format json"""


def register(sub) -> None:
    import argparse
    import textwrap

    from ._source import LENGTH_UNITS
    from .props import add_format_argument

    p = sub.add_parser(
        "demo", help="tour of the package on a bundled steel wing nut (or on --mesh FILE)",
        description=textwrap.fill("Mass properties, canonical form, validity, six-point and four-point particle "
                    "models and the equivalent box of a real body, in readable tables."),
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--mesh", metavar="FILE",
                   help="your own closed triangle mesh (STL, OBJ, PLY, OFF, ...) instead of the bundled wing nut")
    g = p.add_argument_group("mass (give at most one)")
    g.add_argument("--density", type=float, metavar="RHO",
                   help=f"density in kg/m^3 (default: {SAMPLE_DENSITY:g}, steel, for the bundled wing nut; "
                        "1000 for --mesh)")
    g.add_argument("--mass", type=float, metavar="KG", help="total mass in kg (the density follows)")
    p.add_argument("--units", choices=tuple(LENGTH_UNITS), metavar="UNIT",
                   help="length unit of the mesh: " + "|".join(LENGTH_UNITS)
                        + f" (default: {SAMPLE_UNITS} for the bundled wing nut, m for --mesh)")
    p.add_argument("--shell", action="store_true",
                   help="thin shell: mass spread over the surface (needs --mass, or --density in kg/m^2)")
    p.add_argument("--fix-orientation", action="store_true", help="repair inconsistent or inverted face winding")
    p.add_argument("--accept-defects", action="store_true",
                   help="compute even for an open/defective mesh; the result carries warnings")
    add_format_argument(p)
    r = p.add_argument_group("report (a folder with index.html, plots, an animation and a 3D page)")
    r.add_argument("--out", metavar="DIR", default=DEFAULT_OUT,
                   help=f"report folder (default: ./{DEFAULT_OUT}); a folder inertia did not create is refused "
                        "unless --force")
    r.add_argument("--no-video", action="store_true", help="skip the animation (the slowest part)")
    r.add_argument("--video-format", choices=("gif", "mp4"), default="gif",
                   help="animation format: gif (Pillow, default) or mp4 (the ffmpeg of imageio-ffmpeg)")
    r.add_argument("--no-report", action="store_true", help="print the tables only; write no files")
    r.add_argument("--force", action="store_true", help="write the report into an existing foreign folder")
    p.set_defaults(func=run)


def sample_path():
    """Context manager yielding the path of the bundled sample mesh (works from a wheel install)."""
    from importlib.resources import as_file, files

    return as_file(files("inertia").joinpath("data", SAMPLE_FILE))


def run(args) -> int:
    import argparse

    from ._source import load_source

    bundled = args.mesh is None
    ns = argparse.Namespace(
        source=args.mesh, units=args.units or (SAMPLE_UNITS if bundled else "m"),
        density=args.density, mass=args.mass, shell=args.shell,
        fix_orientation=args.fix_orientation, accept_defects=args.accept_defects, command="demo")
    if bundled and args.density is None and args.mass is None and not args.shell:
        ns.density = SAMPLE_DENSITY
    if bundled:
        with sample_path() as path:
            if not path.is_file():
                from .._core.errors import MeshFileError

                raise MeshFileError(f"the bundled sample {SAMPLE_FILE} is missing from {path.parent}: the package "
                                    "was installed without its data files; reinstall it with pip install")
            props, info = _load_bundled(ns, path)
        info.source = f"bundled {SAMPLE_FILE}"
        if info.density_source == "--density" and args.density is None:
            info.density_source = "steel, the demo's default"
    else:
        props, info = load_source(ns)
    report = build_report(props)
    title = ("a steel wing nut" if bundled and info.density_source.startswith("steel") else str(info.source))
    files = None
    if args.no_report:
        from ..viz.flipdata import flip_study

        study = flip_study(props.principal()[0])
    else:
        files = _write_report(args, props, title, bundled, ns)
        if files is None:  # plotting libraries missing: the tables still come
            from ..viz.flipdata import flip_study

            study = flip_study(props.principal()[0])
        else:
            study = files["study"]
    if args.format == "json":
        d = report_dict(props, info, report, bundled=bundled)
        d["flip"] = _flip_dict(study)
        if files is not None:
            d["report"] = {"index": str(files["index"]), "files": sorted(f for v in files["files"].values() for f in v)}
        fmt.emit(fmt.to_json(d))
    else:
        lines = report_lines(props, info, report, bundled=bundled) + flip_lines(study)
        if files is not None:
            lines += fmt.heading("8. Report") + [f"  {files['index']}  (open it in a browser; "
                                                 f"{sum(len(v) for v in files['files'].values()) + 1} files)"]
        fmt.emit(lines)
    return 0


class _Progress:
    """A progress bar on stderr while the report is built (only on a terminal)."""

    STEPS = ("simulating the flip", "plotting", "animating", "writing the 3D page")

    def __init__(self, enabled: bool):
        import sys

        self.enabled = enabled and sys.stderr.isatty()
        self.k = 0

    def __call__(self, name: str) -> None:
        import sys

        if not self.enabled:
            return
        self.k += 1
        n = len(self.STEPS)
        bar = "#" * (20 * self.k // n) + "." * (20 - 20 * self.k // n)
        sys.stderr.write(f"\r[{bar}] {name}...".ljust(60))
        sys.stderr.flush()

    def done(self) -> None:
        import sys

        if self.enabled:
            sys.stderr.write("\r" + " " * 60 + "\r")
            sys.stderr.flush()


def _write_report(args, props, title, bundled, ns):
    from ..viz.report import build_report as build_folder

    mesh = None
    try:
        from ..geometry.mesh_io import load_mesh

        if bundled:
            with sample_path() as path:
                mesh = load_mesh(path, units=ns.units)
        elif args.mesh:
            mesh = load_mesh(args.mesh, units=ns.units)
    except Exception:  # noqa: BLE001 - the page then shows the equivalent box only
        mesh = None
    bar = _Progress(True)
    try:
        import matplotlib  # noqa: F401 - the report needs it; the tables do not
    except ImportError:
        import sys

        print("inertia demo: note: no report written: it needs matplotlib and Pillow "
              "(pip install 'inertia[viz]' or '.[all]')", file=sys.stderr)
        return None
    try:
        return build_folder(args.out, props, title=f"inertia demo: {title}", credit=SAMPLE_CREDIT if bundled else None,
                            mesh=mesh, video=not args.no_video, force=args.force, progress=bar,
                            animation_format=args.video_format)
    finally:
        bar.done()


def _flip_dict(study) -> dict:
    return {"moments": study.moments.tolist(), "omega0_body_principal": study.omega0_body.tolist(),
            "flip_interval": float(study.flip_interval), "flip_times": study.flip_times.tolist(),
            "flips_detected": study.detected_flips.tolist(),
            "integrators": {k: {"h": v["h"], "max_energy_error": float(v["energy_error"].max()),
                                "max_momentum_error": float(v["momentum_error"].max())}
                            for k, v in study.integrators.items()}}


def flip_lines(study) -> list[str]:
    """Section 7: the intermediate-axis flip, predicted and simulated."""
    lines = fmt.heading("7. Spin about the intermediate axis: the Dzhanibekov flip")
    w = study.omega0_body
    lines += [f"  spin            omega0 = [{', '.join(fmt.num(x) for x in w)}] rad/s about principal axes 1, 2, 3",
              f"  predicted       a flip every 2K(m)/lambda = {fmt.num(study.flip_interval)} s",
              f"  exact solution  flips at {', '.join(f'{x:.4f}' for x in study.detected_flips)} s "
              f"(predicted {', '.join(f'{x:.4f}' for x in study.flip_times[:len(study.detected_flips)])} s)"]
    rows = [[name, fmt.num(v["h"]), f"{v['energy_error'].max():.2e}", f"{v['momentum_error'].max():.2e}"]
            for name, v in study.integrators.items()]
    lines += fmt.table(["integrator", "h [s]", "max |dE/E|", "max |d|L|/|L||"], rows)
    return lines


def _load_bundled(ns, path):
    """The bundled sample through the normal mesh reader, or, when the optional trimesh is not
    installed, through :func:`read_simple_obj` (the file is a plain triangle OBJ)."""
    from .._core.errors import MissingDependencyError

    from ._source import LENGTH_UNITS, SourceInfo, load_source

    try:
        return load_source(ns, source=str(path))
    except MissingDependencyError:
        import inertia

        vertices, faces = read_simple_obj(path)
        props = inertia.mesh_properties(vertices * LENGTH_UNITS[ns.units], faces, density=ns.density,
                                        mass=ns.mass, shell=ns.shell, fix_orientation=ns.fix_orientation,
                                        on_defect="warn" if ns.accept_defects else "raise", name=SAMPLE_FILE)
        density = ns.density if ns.density is not None else props.density
        info = SourceInfo(str(path), "mesh", ns.units, density,
                          "--density" if ns.density is not None else "from --mass", shell=ns.shell)
        return props, info


def read_simple_obj(path):
    """``(vertices (V, 3) float, faces (F, 3) int)`` of an OBJ file's ``v`` and ``f`` lines.

    Enough for the bundled sample when trimesh is missing: polygons are split into triangle
    fans, ``f a/b/c`` keeps the vertex index, negative (relative) indices are resolved.
    """
    import numpy as np

    vertices, faces = [], []
    with open(path, encoding="utf-8") as fh:
        for line in fh:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == "v":
                vertices.append([float(x) for x in parts[1:4]])
            elif parts[0] == "f":
                idx = [int(p.split("/")[0]) for p in parts[1:]]
                idx = [i - 1 if i > 0 else len(vertices) + i for i in idx]  # OBJ is 1-based; -1 = last
                faces += [[idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1)]
    return np.array(vertices, dtype=np.float64), np.array(faces, dtype=np.int64)


def build_report(props) -> dict:
    """Everything the demo shows beyond the mass properties (models and equivalent solids)."""
    import inertia

    return {
        "canonical": props.canonical(),
        "six_point": inertia.six_point_model(props),
        "four_point": inertia.four_point_model(props),
        "equivalent_box": inertia.equivalent_box(props),
        "equivalent_ellipsoid": inertia.equivalent_ellipsoid(props),
    }


def _canonical_dict(cf) -> dict:
    return {
        "principal_moments": cf.moments,
        "R_body_principal": cf.R_body_principal,
        "p_body_com": cf.p_body_com,
        "degenerate_moments": [list(g) for g in cf.degenerate],
        "rtol": cf.rtol,
    }


def report_dict(props, info, report, *, bundled: bool) -> dict:
    """JSON-ready dict of the whole demo."""
    from .particles import model_dict
    from .props import props_dict

    body = info.to_dict()
    if bundled:
        body["credit"] = SAMPLE_CREDIT
    return {
        "body": body,
        "mass_properties": props_dict(props, info),
        "canonical_form": _canonical_dict(report["canonical"]),
        "validity": [{"code": v.code, "message": v.message} for v in props.check()],
        "six_point": model_dict(report["six_point"], props),
        "four_point": model_dict(report["four_point"], props),
        "equivalent_box": report["equivalent_box"].to_dict(),
        "equivalent_ellipsoid": report["equivalent_ellipsoid"].to_dict(),
    }


def report_lines(props, info, report, *, bundled: bool) -> list[str]:
    """The demo's readable tables."""
    from .particles import model_lines
    from .props import canonical_lines, inertia_lines, summary_lines, validity_lines, warnings_lines

    title = "inertia demo: a steel wing nut" if bundled and info.density_source.startswith("steel") \
        else f"inertia demo: {info.source}"
    lines = [title, "=" * len(title)]
    if bundled:
        lines += [f"Body: {SAMPLE_CREDIT}.",
                  f"Mesh coordinates read in {info.units}; SI units throughout.  Your own body: "
                  "inertia demo --mesh FILE [--units mm] [--density RHO | --mass KG]"]
    lines += [""] + summary_lines(props, info, title="1. Mass properties")
    lines += inertia_lines(props, heading=False)
    lines += canonical_lines(props, title="2. Canonical form: principal moments and axes")
    lines += fmt.heading("3. Validity")
    lines += validity_lines(props.check())
    lines += ["  warnings:"] + ["  " + w for w in warnings_lines(props.warnings)]
    lines += model_lines("4. Six-point model", report["six_point"], props)
    lines += model_lines("5. Four-point model", report["four_point"], props)
    lines += _equivalent_lines(props, report["equivalent_box"], report["equivalent_ellipsoid"])
    return lines


def _equivalent_lines(props, box, ellipsoid) -> list[str]:
    """Equivalent uniform box and ellipsoid: dimensions along the principal axes, volume, density."""
    lines = fmt.heading("6. Equivalent uniform solids (same mass, COM and inertia tensor)")
    rows = []
    fx = fmt.fixed_formatter([box.dims, ellipsoid.dims])
    for name, what, solid in (("box", "edge", box), ("ellipsoid", "semi-axis", ellipsoid)):
        rows.append([name, what, *(fx(x) for x in solid.dims.tolist()),
                     fmt.num(solid.volume), fmt.num(solid.density)])
    lines += fmt.table(["solid", "dimension", "axis 1 [m]", "axis 2 [m]", "axis 3 [m]", "volume [m^3]",
                        "density [kg/m^3]"], rows)
    volume = f"{fmt.num(props.volume)} m^3" if props.volume == props.volume else "n/a (thin shell)"
    lines.append(f"  axes: the principal axes of section 2, centred on the COM; body volume {volume}")
    for w in tuple(box.warnings) + tuple(ellipsoid.warnings):
        lines.append(f"  warning: {w}")
    return lines
