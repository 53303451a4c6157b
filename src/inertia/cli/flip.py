"""``inertia flip``: the intermediate-axis (Dzhanibekov) flip and the stability of each axis.

For a body (``--moments I1,I2,I3`` or a SOURCE, as in ``inertia simulate``) and an initial
angular velocity ``--omega``, prints the predicted time between flips ``2 K(m) / lam``, its
near-separatrix approximation ``(2 / lam) ln(4 / k')``, the polhode period, the regime of
the motion, and the linear stability of steady spin about each principal axis at the spin
rate ``|omega|``.

Only the standard library is imported at module level.
"""

from __future__ import annotations

import math

from . import _format as fmt
from .simulate import add_body_arguments, check_spin_scale, initial_state, resolve_body

EPILOG = """\
examples:
  inertia flip --moments 1,2,3 --omega 0.01,1,0
  inertia flip --moments 1,2,3 --omega 0.01,1,0 --format json
  inertia flip box:0.1,0.2,0.4 --mass 2 --omega 0.05,5,0

JSON keys:
  flip_interval         s between flips (half the polhode period); null when there is no flip
                        (steady spin, separatrix) or no unique intermediate axis (the table
                        tells "never" from "n/a")
  flip_interval_approx  s, (2/lam) ln(4/k') (null outside the elliptic regimes)
  period                s, period of omega_body (null when omega is constant or never returns)
  unstable_axis         index (0, 1, 2) into "moments" of the unstable (intermediate) axis, or null
  eigenvalues           per axis (in the order of "moments") the three eigenvalues of the
                        linearised Euler equations at spin rate |omega|, each as [real, imag] in 1/s
  stability             per axis: "stable", "unstable" or "marginal"
  also: regime, moments, spin_rate, growth_rate, parameter_m, one_minus_m, rate_lambda,
        first_flip_time, unstable_axis_direction, conventions

exit status: 0 on success, 1 on bad input (the message names the problem), 2 on bad usage."""

HELP = "intermediate-axis flip interval and the stability of each principal axis"
DESCRIPTION = ("Dzhanibekov (intermediate-axis) flip: predicted time between flips, polhode period, "
               "regime, and the linear stability (eigenvalues) of steady spin about each principal axis "
               "at the spin rate |omega|.")

CONVENTIONS = ("SI units; moments in kg m^2 (for --moments in the given order, for a SOURCE its principal "
               "moments, ascending); axis indices are 0-based into moments; eigenvalues in 1/s as [real, imag]")


def register(sub) -> None:
    p = fmt.add_command(sub, "flip", HELP, DESCRIPTION, EPILOG,
                        usage="[SOURCE | --moments I1,I2,I3] --omega W1,W2,W3 [options]")
    add_body_arguments(p)
    p.add_argument("--format", choices=("table", "json"), default="table",
                   help="table: aligned text for people (default); json: machine-readable")
    p.set_defaults(func=run)


def analyse(body, w_P) -> dict:
    """Every figure of the report (numpy arrays and floats; non-finite values become null in JSON)."""
    import numpy as np

    from ..dynamics.exact import ExactSolution
    from ..dynamics.flip import axis_stability

    sol = ExactSolution(body.moments, w_P)
    spin = float(np.linalg.norm(w_P))
    stab = axis_stability(body.moments, spin)
    # the unstable axis depends on the moments alone (at zero spin every axis is marginal)
    unstable = [s.axis for s in axis_stability(body.moments, 1.0) if s.classification == "unstable"]
    u_axis = unstable[0] if unstable else None
    approx = math.nan
    first = math.nan
    if sol.regime in ("minor_axis", "major_axis"):
        kp = math.sqrt(sol.complementary_parameter)
        approx = 2.0 * math.log(4.0 / kp) / sol.rate
        nxt = sol.flip_times(0.0, sol.period)
        first = float(nxt[0]) if len(nxt) else math.nan
    return {
        "regime": sol.regime,
        "moments": body.moments,
        "flip_interval": sol.flip_interval,
        "flip_interval_approx": approx,
        "period": sol.period,
        "first_flip_time": first,
        "parameter_m": sol.parameter,
        "one_minus_m": sol.complementary_parameter,
        "rate_lambda": sol.rate,
        "spin_rate": spin,
        "unstable_axis": u_axis,
        "unstable_axis_direction": None if u_axis is None else body.R_BP[:, u_axis],
        "eigenvalues": [[[float(e.real), float(e.imag)] for e in s.eigenvalues] for s in stab],
        "stability": [s.classification for s in stab],
        "growth_rate": max(s.growth_rate for s in stab),
        "energy": sol.energy,
        "angular_momentum_norm": sol.angular_momentum_norm,
    }


def run(args) -> int:
    body = resolve_body(args)
    w_P, _ = initial_state(args, body)
    check_spin_scale(body.moments, w_P)
    report = analyse(body, w_P)
    if args.format == "json":
        out = dict(report)
        out.update({k: v for k, v in body.to_dict().items() if k != "moments"})
        out["conventions"] = CONVENTIONS
        fmt.emit(fmt.to_json(out))
    else:
        fmt.emit(table_lines(report, body))
    return 0


def _seconds(x) -> str:
    if x is None or (isinstance(x, float) and math.isnan(x)):
        return "n/a"
    if math.isinf(x):
        return "never (infinite)"
    return f"{fmt.num(x, 10)} s"


def table_lines(r: dict, body) -> list:
    names = {"minor_axis": "circulation about the minor axis (energy above the separatrix)",
             "major_axis": "circulation about the major axis (energy below the separatrix)",
             "separatrix": "on the separatrix (one flip, taking infinite time)",
             "symmetric_top": "symmetric top (no unique intermediate axis)",
             "sphere": "spherical body (constant angular velocity)",
             "steady_spin": "steady spin about a principal axis",
             "rest": "at rest"}
    lines = fmt.key_values([
        ("body", body.label),
        ("regime", names.get(r["regime"], r["regime"])),
        ("flip interval", _seconds(r["flip_interval"]) + "  (2 K(m) / lambda, half the polhode period)"),
        ("  approximation", _seconds(r["flip_interval_approx"]) + "  ((2 / lambda) ln(4 / sqrt(1 - m)))"),
        ("first flip at", _seconds(r["first_flip_time"])),
        ("polhode period", _seconds(r["period"])),
        ("m, 1 - m", f"{fmt.num(r['parameter_m'], 12)}, {fmt.num(r['one_minus_m'], 6)}"),
        ("lambda", fmt.num(r["rate_lambda"], 10) + (" 1/s" if r["rate_lambda"] == r["rate_lambda"] else "")),
    ], indent=0)
    lines += fmt.heading(f"Steady spin about each principal axis at |omega| = {fmt.num(r['spin_rate'])} rad/s")
    rows = []
    for j, (eig, kind) in enumerate(zip(r["eigenvalues"], r["stability"])):
        lam = eig[1]
        text = (f"+-{fmt.num(abs(lam[0]))}" if lam[0] != 0 else
                (f"+-{fmt.num(abs(lam[1]))} i" if lam[1] != 0 else "0"))
        rows.append([str(j + 1), fmt.num(r["moments"][j]), text, kind])   # axes 1, 2, 3 as everywhere
    lines += fmt.table(["axis", "moment [kg m^2]", "eigenvalues [1/s] (and 0)", "stability"], rows, indent=0)
    return lines
