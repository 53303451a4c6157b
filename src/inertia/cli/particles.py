"""``inertia particles SOURCE``: six-point and four-point particle models of a body.

Each model is a set of point masses (kg) at positions (m, in the body frame of SOURCE)
with the same total mass, center of mass and full inertia tensor as the body.
"""

from __future__ import annotations

from . import _format as fmt
from ._source import DENSITY_NOTE, add_source_arguments

EPILOG = """\
examples:
  inertia particles box:0.1,0.2,0.4 --mass 2
  inertia particles part.stl --units mm --density 7850 --format json

JSON: {"six_point": {"masses": [...], "positions": [[x, y, z], ...]}, "four_point": {...}, ...}
with masses in kg and positions in m in the body frame."""

HELP = "six-point and four-point particle models of a body"
DESCRIPTION = ("Point-mass models with exactly the mass, center of mass and inertia tensor "
               "of a mesh file or primitive: six equal-mass-pair points on the principal axes, "
               "and four points.  " + DENSITY_NOTE)

MODELS = (("six_point", "Six-point model", "six_point_model"),
          ("four_point", "Four-point model", "four_point_model"))


def register(sub) -> None:
    from .props import add_format_argument

    p = fmt.add_command(sub, "particles", HELP, DESCRIPTION, EPILOG)
    add_source_arguments(p)
    add_format_argument(p)
    p.set_defaults(func=run)


def run(args) -> int:
    from ._source import load_source

    props, info = load_source(args)
    models = build_models(props)
    if args.format == "json":
        out = dict(info.to_dict())
        out.update({"mass": props.mass, "com": props.com, "inertia_com": props.inertia_com,
                    "frame": props.frame})
        out.update(models_dict(models, props))
        fmt.emit(fmt.to_json(out))
    else:
        lines = fmt.heading(f"Particle models of {info.source}")[1:]
        lines += fmt.key_values([
            ("source", f"{info.source} ({info.kind}; lengths read in {info.units}, results in SI units)"),
            ("mass", f"{fmt.num(props.mass)} kg"),
            ("density", info.density_text()),
            ("center of mass", fmt.vector(props.com) + f" m (in frame {props.frame!r})"),
        ])
        for key, title, _ in MODELS:
            lines += model_lines(title, models[key], props)
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


def model_dict(model, props) -> dict:
    """JSON-ready dict of one model: ``masses`` (kg), ``positions`` (m, body frame) and more."""
    r = model.positions_body
    out = model.to_dict()  # kind, frame, masses, positions_body, positions_principal, pose, warnings
    out["positions"] = r   # = positions_body, under the short name the CLI documents
    out["max_relative_error"] = reproduction_error(model, props)
    return out


def models_dict(models: dict, props) -> dict:
    """``{"six_point": {...}, "four_point": {...}}`` (see :func:`model_dict`)."""
    return {key: model_dict(model, props) for key, model in models.items()}


def model_lines(title: str, model, props) -> list[str]:
    """A table of one particle model: mass and x, y, z of each point, and how well it reproduces the body."""
    m, r = model.masses, model.positions_body
    fx = fmt.fixed_formatter(r)  # one fixed-point format for all coordinates: columns line up
    rows = [[str(k + 1), fmt.num(mk), *(fx(x) for x in rk)] for k, (mk, rk) in enumerate(zip(m.tolist(), r.tolist()))]
    lines = fmt.heading(f"{title}: {len(rows)} point masses (positions in the body frame)")
    lines += fmt.table(["point", "mass [kg]", "x [m]", "y [m]", "z [m]"], rows)
    err = reproduction_error(model, props)
    # below 1e-14 the exact figure is rounding noise that differs between machines and kernels
    how = "to rounding (relative error < 1e-14)" if err < 1e-14 else f"to a relative error of {err:.1e}"
    lines.append(f"  sum of masses {fmt.num(float(m.sum()))} kg; reproduces mass, COM and inertia tensor {how}")
    for w in model.findings:
        lines.append(f"  warning: {w.message}")
    return lines
