"""The figures of the control showcase (matplotlib, Agg, each saved as PNG and SVG): the passive
wheel sweep, the active hold of each body (tilt, wheel momenta and torques against their limits)
and the Monte Carlo histogram.  Each returns the numbers it drew."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import AXIS_COLORS, pyplot, save_figure

HELD, FREE, LIMIT, FAIL = "#2b7bba", "#c0392b", "0.35", "#d62728"


def passive_plot(sweeps: dict, out_dir, stem: str = "control-passive") -> dict:
    """Largest tilt over the run against h / h_min, one curve per body; the formula at 1, the
    simulated threshold marked."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    drawn = {}
    for (name, sw), color in zip(sweeps.items(), (HELD, "#e08a1e")):
        ax.semilogy(sw.ratios, np.degrees(sw.max_tilt), "o-", color=color, ms=3.5, lw=1.3,
                    label=f"{name}: threshold {sw.h_threshold:.4g} N m s simulated, {sw.h_min:.4g} formula "
                          f"({100 * sw.threshold_error:+.2f} %)")
        ax.axvline(sw.h_threshold / sw.h_min, color=color, ls=":", lw=1.0)
        drawn[name] = {"ratios": sw.ratios.tolist(), "max_tilt_deg": np.degrees(sw.max_tilt).tolist()}
    ax.axvline(1.0, color=LIMIT, ls="--", lw=1.0, label="$h_{min} = (I_3 - I_2)\\,\\Omega$ (formula)")
    ax.set_xlabel("wheel momentum along the spin axis, $h / h_{min}$")
    ax.set_ylabel("largest tilt of the spin axis [deg]")
    ax.set_title("A constant wheel momentum: below $h_{min}$ the spin departs, above it holds")
    ax.legend(fontsize=7, loc="lower left")
    ax.grid(alpha=0.3, which="both")
    files = save_figure(fig, Path(out_dir), stem)
    plt.close(fig)
    return {"files": files, "curves": drawn}


def active_plot(run, out_dir, stem: str) -> dict:
    """Three panels against time: the tilt held and free (the 1 degree bound), the wheel momenta and
    the wheel torques, each against its limit."""
    plt = pyplot()
    st, g = run.setup, run.setup.gyrostat
    fig, axes = plt.subplots(3, 1, figsize=(8, 6.4), sharex=True, layout="constrained")
    ax = axes[0]
    ax.semilogy(run.t, np.degrees(run.tilt_free), color=FREE, lw=1.0, label="wheels idle (free: flips)")
    ax.semilogy(run.t, np.maximum(np.degrees(run.tilt_held), 1e-12), color=HELD, lw=1.3, label="LQR on the wheels")
    ax.axhline(np.degrees(st.max_tilt), color=LIMIT, ls="--", lw=1.0, label=f"{np.degrees(st.max_tilt):g} deg")
    ax.axvline(st.settle, color=LIMIT, ls=":", lw=0.8, label=f"judged from {st.settle:g} s")
    ax.set_ylim(1e-4, 300)                                     # below: the hold converging to rounding
    ax.set_ylabel("tilt [deg]")
    ax.legend(fontsize=7, loc="lower left", ncol=2)
    t_mid = 0.5 * (run.t[1:] + run.t[:-1])
    for ax, data, limit, unit, what in ((axes[1], run.held[:, 13:], g.max_momentum, "N m s", "wheel momentum"),
                                        (axes[2], run.torque, g.max_torque, "N m", "wheel torque")):
        t = run.t if data.shape[0] == run.t.size else t_mid
        for k in range(g.n_wheels):
            ax.plot(t, data[:, k], color=AXIS_COLORS[k % 3], lw=1.0, label=f"wheel {k + 1}")
        lim = float(np.max(limit))
        ax.axhline(lim, color=LIMIT, ls="--", lw=0.9, label=f"limit {lim:g} {unit}")
        ax.axhline(-lim, color=LIMIT, ls="--", lw=0.9)
        ax.set_ylabel(f"{what} [{unit}]")
        ax.legend(fontsize=7, loc="upper right", ncol=4)
        ax.grid(alpha=0.3)
    axes[0].grid(alpha=0.3, which="both")
    axes[2].set_xlabel("t [s]")
    axes[2].set_xscale("symlog", linthresh=max(st.settle, st.period), linscale=2.0)   # the capture, then the hold
    axes[2].set_xlim(0.0, st.duration)
    fig.suptitle(f"{st.name}: {st.spin_rate:g} rad/s about the intermediate axis, {np.degrees(st.initial_tilt):g} deg "
                 "off at t = 0", fontsize=10)
    files = save_figure(fig, Path(out_dir), stem)
    plt.close(fig)
    return {"files": files, "max_tilt_after_settle_deg": float(np.degrees(run.max_tilt_after_settle)),
            "capture_time_s": run.capture_time}


def monte_carlo_plot(studies: dict, out_dir, stem: str = "control-monte-carlo") -> dict:
    """Histogram (log bins) of each run's largest tilt after settling, the bound and the failures marked."""
    plt = pyplot()
    fig, axes = plt.subplots(1, len(studies), figsize=(8, 3.6), squeeze=False, layout="constrained")
    drawn = {}
    for ax, (name, mc) in zip(axes[0], studies.items()):
        deg = np.maximum(np.degrees(mc.max_tilt), 1e-12)
        bound = np.degrees(mc.setup.max_tilt)
        lo = np.floor(np.log10(min(deg.min(), bound))) - 0.5
        hi = np.ceil(np.log10(max(deg.max(), bound))) + 0.5
        bins = np.logspace(lo, hi, 40)
        ax.hist(deg[deg <= bound], bins=bins, color=HELD, label=f"held: {mc.success.sum()} of {deg.size}")
        ax.hist(deg[deg > bound], bins=bins, color=FAIL, label=f"failed: {(~mc.success).sum()}")
        ax.axvline(bound, color=LIMIT, ls="--", lw=1.0, label=f"{bound:g} deg")
        ax.set_xscale("log")
        ax.set_xlabel(f"largest tilt after {mc.setup.settle:g} s [deg]")
        ax.set_title(f"{name}\n{mc.success_rate:.1%} of {deg.size} runs held", fontsize=9)
        ax.legend(fontsize=7, loc="upper left")
        ax.grid(alpha=0.3)
        drawn[name] = {"success_rate": mc.success_rate, "failures_deg": deg[deg > bound].tolist()}
    axes[0][0].set_ylabel("runs")
    fig.suptitle("Controllers designed on models wrong by up to 20 % per moment and 5 deg in the axes", fontsize=10)
    files = save_figure(fig, Path(out_dir), stem)
    plt.close(fig)
    return {"files": files, "studies": drawn}
