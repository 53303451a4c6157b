"""``inertia particles SOURCE``: six-point and four-point particle models of a body.

Each model is a set of point masses (kg) at positions (m, in the body frame of SOURCE)
with the same total mass, center of mass and full inertia tensor as the body.
"""

from __future__ import annotations

from . import _format as fmt
from ._options import DENSITY_NOTE, add_body_options, add_mesh_options, add_output_options

EPILOG = """\
examples:
  inertia particles box:0.1,0.2,0.4 --mass 2
  inertia particles part.stl --units mm --density 7850 --format json
  inertia particles part.stl --units mm --density 7850 --output-units g,mm

JSON: {"six_point": {"masses": [...], "positions": [[x, y, z], ...]}, "four_point": {...}, ...}
with masses in kg and positions in m in the body frame (or in --output-units)."""

HELP = "six-point and four-point particle models of a body"
DESCRIPTION = ("Point-mass models with exactly the mass, center of mass and inertia tensor "
               "of a mesh file or primitive: six equal-mass-pair points on the principal axes, "
               "and four points.  " + DENSITY_NOTE)

MODELS = (("six_point", "Six-point model", "six_point_model"),
          ("four_point", "Four-point model", "four_point_model"))


def register(sub) -> None:
    from .props import add_format_argument

    p = fmt.add_command(sub, "particles", HELP, DESCRIPTION, EPILOG, usage="SOURCE [options]")
    p.add_argument("source", metavar="SOURCE",
                   help="a mesh file or a primitive NAME:numbers such as box:0.1,0.2,0.4 (inertia help source)")
    add_format_argument(p)
    add_body_options(p)
    add_mesh_options(p)
    add_output_options(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ._source import load_source

    u = fmt.Units.from_args(args)
    props, info = load_source(args)
    models = build_models(props)
    if args.format == "json":
        out = dict(info.to_dict(u))
        out.update({"mass": u.mass(props.mass), "com": u.length(props.com), "inertia_com": u.inertia(props.inertia_com),
                    "frame": props.frame, "output_units": u.to_dict()})
        out.update(models_dict(models, props, u))
        fmt.emit(fmt.to_json(out))
    else:
        results = "results in SI units" if u.si else f"results in {u.mass_unit} and {u.length_unit}"
        lines = fmt.heading(f"Particle models of {info.source}")[1:]
        lines += fmt.key_values([
            ("source", f"{info.source} ({info.kind}; lengths read in {info.units}, {results})"),
            ("mass", f"{fmt.num(u.mass(props.mass))} {u.mass_unit}"),
            ("density", info.density_text(u)),
            ("center of mass", f"{fmt.vector(u.length(props.com))} {u.length_unit} (in frame {props.frame!r})"),
        ])
        for key, title, _ in MODELS:
            lines += model_lines(title, models[key], props, u)
        fmt.emit(lines)
    return 0


def build_models(props) -> dict:
    """``{"six_point": ParticleModel, "four_point": ParticleModel}`` for ``props``."""
    from ..particles import models

    return {key: getattr(models, fn)(props) for key, _, fn in MODELS}


def reproduction_error(model, props) -> float:
    """Largest relative error of the model's mass, COM and inertia against ``props``
    (inertia relative to its largest entry, COM relative to the radius of gyration)."""
    import numpy as np

    from ..massprops.properties import MassProperties

    m, r = model.masses, model.positions_body
    back = MassProperties.from_point_masses(m, r, validate=False)  # recomputed from the points alone
    scale_I = float(np.abs(props.inertia_com).max())
    scale_r = float(np.sqrt(scale_I / props.mass))
    return max(abs(back.mass - props.mass) / props.mass,
               float(np.abs(back.com - props.com).max()) / scale_r,
               float(np.abs(back.inertia_com - props.inertia_com).max()) / scale_I)


def model_dict(model, props, units=None) -> dict:
    """JSON-ready dict of one model: ``masses`` (kg), ``positions`` (m, body frame) and more (in ``units``)."""
    u = units or fmt.Units()
    out = model.to_dict()  # kind, frame, masses, positions_body, positions_principal, pose, warnings
    out.update({k: u.length(out[k]) for k in ("positions_body", "positions_principal", "p_body_com") if k in out})
    out["masses"] = u.mass(out["masses"])
    out["positions"] = u.length(model.positions_body)   # = positions_body, under the short name the CLI documents
    out["max_relative_error"] = reproduction_error(model, props)
    return out


def models_dict(models: dict, props, units=None) -> dict:
    """``{"six_point": {...}, "four_point": {...}}`` (see :func:`model_dict`)."""
    return {key: model_dict(model, props, units) for key, model in models.items()}


def model_lines(title: str, model, props, units=None) -> list[str]:
    """A table of one particle model: mass and x, y, z of each point, and how well it reproduces the body."""
    u = units or fmt.Units()
    m, r = u.mass(model.masses), u.length(model.positions_body)
    fx = fmt.fixed_formatter(r)  # one fixed-point format for all coordinates: columns line up
    rows = [[str(k + 1), fmt.num(mk), *(fx(x) for x in rk)] for k, (mk, rk) in enumerate(zip(m, r))]
    lines = fmt.heading(f"{title}: {len(rows)} point masses (positions in the body frame)")
    L = u.length_unit
    lines += fmt.table(["point", f"mass [{u.mass_unit}]", f"x [{L}]", f"y [{L}]", f"z [{L}]"], rows)
    err = reproduction_error(model, props)
    # below 1e-14 the exact figure is rounding noise that differs between machines and kernels
    how = "to rounding (relative error < 1e-14)" if err < 1e-14 else f"to a relative error of {err:.1e}"
    lines.append(f"  sum of masses {fmt.num(sum(m))} {u.mass_unit}; reproduces mass, COM and inertia tensor {how}")
    for w in model.findings:
        lines.append(f"  warning: {w.message}")
    return lines
