"""``inertia demo --control``: the tables and the JSON of the spin-hold showcase
(:func:`inertia.control.studies.showcase`); no numerics here."""

from __future__ import annotations

import math

from . import _format as fmt

HELP = ("also hold the T-handle's spin about its intermediate axis with reaction wheels (passive wheel sweep, LQR, "
        "1,000-run Monte Carlo with wrong models), and Basilisk's 900/800/600 kg m^2 spacecraft; adds a section to "
        "the report")


def control_lines(sc, number: int) -> list[str]:
    """Section ``number``: the threshold, the hold and the Monte Carlo, per body."""
    lines = fmt.heading(f"{number}. Holding the spin about the intermediate axis with reaction wheels")
    for name, st in sc.setups.items():
        g = st.gyrostat
        lines.append(f"  {name}: {fmt.num(st.spin_rate)} rad/s about the intermediate axis; three wheels along the "
                     f"principal axes, {fmt.num(g.max_torque.max())} N m and {fmt.num(g.max_momentum.max())} N m s "
                     f"each; torques every {fmt.num(1e3 * st.period)} ms; {fmt.num(st.duration)} s runs")
    lines += ["", "  (a) passive: one wheel along the spin axis at a constant momentum h (largest tilt over the run)"]
    names = list(sc.setups)
    first = sc.passive[names[0]]
    rows = []
    for k, r in enumerate(first.ratios):
        cells = [f"{r:g}"]
        for name in names:
            p = sc.passive[name]
            cells.append(f"{math.degrees(p.max_tilt[k]):.3g} deg, {'departs' if p.departs[k] else 'holds'}")
        rows.append(cells)
    lines += fmt.table(["h / h_min"] + names, rows)
    for name in names:
        p = sc.passive[name]
        lines.append(f"  {name}: h_min = (I3 - I2) Omega = {fmt.num(p.h_min)} N m s; simulated threshold "
                     f"{fmt.num(p.h_threshold)} N m s ({100 * p.threshold_error:+.2f} %)")
    st0 = first_setup(sc)
    lines += ["", f"  (b) active: LQR on the gyrostat's Jacobians, from {math.degrees(st0.initial_tilt):g} deg off; "
                  f"within {math.degrees(st0.max_tilt):g} deg after settling?"]
    rows = []
    for name in names:
        a, st = sc.active[name], sc.setups[name]
        g = st.gyrostat
        rows.append([name, f"{a.capture_time:.3g}", f"{st.settle:g}", f"{math.degrees(a.max_tilt_after_settle):.2e}",
                     f"{abs(a.torque).max() / g.max_torque.max():.2f}",
                     f"{abs(a.held[:, 13:]).max() / g.max_momentum.max():.2f}",
                     f"{math.degrees(a.tilt_free.max()):.1f}"])
    lines += fmt.table(["body", "capture [s]", "settle [s]", "max tilt after [deg]", "max |torque|/limit",
                        "max |h|/limit", "free: max tilt [deg]"], rows)
    lines += ["", "  (c) Monte Carlo: each run's controller designed on a model off by up to 20 % per moment and "
                  "5 deg in the axes"]
    rows = []
    for name in names:
        m = sc.monte_carlo[name]
        q = [math.degrees(x) for x in sorted(m.max_tilt)]
        rows.append([name, f"{m.success.sum()}/{m.success.size}", f"{m.success_rate:.1%}",
                     f"{q[len(q) // 2]:.2e}", f"{q[min(len(q) - 1, int(0.99 * len(q)))]:.2e}", f"{q[-1]:.2e}",
                     f"{m.design_seconds:.2f}", f"{m.rollout_seconds:.2f}", f"{m.steps:.3g}"])
    lines += fmt.table(["body", "held", "rate", "median [deg]", "99 % [deg]", "worst [deg]", "designs [s]",
                        "runs [s]", "steps"], rows)
    return lines


def first_setup(sc):
    return next(iter(sc.setups.values()))


def control_dict(sc) -> dict:
    """The showcase's numbers for ``--format json``."""
    out = {}
    for name, st in sc.setups.items():
        p, a, m = sc.passive[name], sc.active[name], sc.monte_carlo[name]
        out[name] = {
            "spin_rate": st.spin_rate, "max_torque": st.gyrostat.max_torque.tolist(),
            "max_momentum": st.gyrostat.max_momentum.tolist(), "period": st.period, "duration": st.duration,
            "passive": {"h_min_formula": p.h_min, "h_threshold_simulated": p.h_threshold, "ratios": p.ratios.tolist(),
                        "max_tilt_rad": p.max_tilt.tolist(), "departs": p.departs.tolist()},
            "active": {"capture_time": a.capture_time, "max_tilt_after_settle_rad": a.max_tilt_after_settle,
                       "max_torque_applied": abs(a.torque).max(axis=0).tolist(),
                       "max_wheel_momentum": abs(a.held[:, 13:]).max(axis=0).tolist(),
                       "free_max_tilt_rad": float(a.tilt_free.max())},
            "monte_carlo": {"runs": int(m.success.size), "success_rate": m.success_rate,
                            "max_tilt_rad": m.max_tilt.tolist(), "design_seconds": m.design_seconds,
                            "rollout_seconds": m.rollout_seconds}}
    return out
