"""The Monte Carlo of the spin hold, timed whole: 1,000 runs x 60 s at 100 Hz (6e6 closed-loop steps).

Usage::

    python bench/control.py [--runs 1000] [--repeat 3] [--threads 1 2] [--python-loop]

Each round is one call of :func:`inertia.control.studies.monte_carlo` on the steel T-handle
(10 rad/s about its intermediate axis, three wheels, 2 plant steps per 10 ms control period):
the 1,000 wrong models sampled, their 1,000 LQR designs (one batch of complex-step Jacobians, one
batched Riccati solve), the 1,000 closed-loop runs in one compiled rollout with the controller
inside the loop, and the success statistics.  Target: <= 10 s on 2 cores.

Printed: best and median wall time over ``--repeat`` rounds per thread count, the split into
designs and rollout, the cost per closed-loop control period (and per plant step) on each
thread, the success rate, and the load average of the machine before and after (the machine
may be shared: a load above the core count slows every figure).  ``--python-loop`` adds the
anchor: the same runs with the controller evaluated in NumPy across the batch and the plant
stepped by one ``gyrostat_rollout`` call per control period (what the compiled loop replaces).
Basilisk's spacecraft (600 s at 10 Hz, the same number of steps) is timed once for reference.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np

from inertia.control.studies import basilisk_setup, monte_carlo, t_handle_setup


def load() -> str:
    return "/".join(f"{x:.1f}" for x in os.getloadavg())


def python_loop(setup, runs: int, seed: int = 0) -> float:
    """Wall time of the anchor: NumPy controller across runs, one compiled call per control period."""
    from inertia.control.lqr import design_spin_hold
    from inertia.control.studies import initial_state, perturbed_models
    from inertia.dynamics.gyrostat import gyrostat_rollout, saturate_wheel_torque

    t0 = time.perf_counter()
    rng = np.random.default_rng(seed)
    models, _, _ = perturbed_models(setup.gyrostat.body, runs, rng, moment_error=0.2, axis_error=np.radians(5))
    c = design_spin_hold(setup.gyrostat.with_body(models), setup.spin_axis, setup.spin_rate, setup.period,
                         substeps=setup.substeps)
    x = initial_state(setup, rng.uniform(0, 2 * np.pi, runs))
    g, n = setup.gyrostat, setup.gyrostat.n_wheels
    u = np.zeros((runs, 6 + n))
    for _ in range(setup.n_steps):
        z = np.concatenate([x[:, 10:13] - c.omega_ref, x[:, 13:] - c.h_ref], axis=-1)
        u[:, 6:] = saturate_wheel_torque(-np.einsum("rij,rj->ri", c.gain, z), x[:, 13:], setup.period,
                                         max_torque=g.max_torque, max_momentum=g.max_momentum)
        x = gyrostat_rollout(x, setup.period / setup.substeps, 1, gyrostat=g, u=u, substeps=setup.substeps,
                             save_every=None, threads=2).states[0]
    return time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", type=int, default=1000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--threads", type=int, nargs="+", default=[1, 2])
    ap.add_argument("--python-loop", action="store_true")
    args = ap.parse_args()
    setup = t_handle_setup()
    monte_carlo(setup, 32)                                     # warm-up (imports, first calls)
    print(f"T-handle Monte Carlo: {args.runs} runs x {setup.duration:g} s at {1 / setup.period:g} Hz "
          f"({args.runs * setup.n_steps:.3g} closed-loop steps, {setup.substeps} plant steps each); "
          f"{os.cpu_count()} cores, load average {load()}")
    print(f"{'threads':>7} {'best s':>8} {'median s':>9} {'designs s':>10} {'rollout s':>10} "
          f"{'ns/step/thread':>15} {'ns/plant step':>14} {'success':>8}  load after")
    for th in args.threads:
        rounds = []
        for _ in range(args.repeat):
            t0 = time.perf_counter()
            mc = monte_carlo(setup, args.runs, threads=th)
            rounds.append((time.perf_counter() - t0, mc))
        best_t, best = min(rounds, key=lambda r: r[0])
        per_step = best.rollout_seconds * th / best.steps * 1e9
        print(f"{th:>7} {best_t:>8.2f} {np.median([r[0] for r in rounds]):>9.2f} {best.design_seconds:>10.2f} "
              f"{best.rollout_seconds:>10.2f} {per_step:>15.0f} {per_step / setup.substeps:>14.0f} "
              f"{best.success_rate:>8.1%}  {load()}")
    if args.python_loop:
        t = python_loop(setup, args.runs)
        print(f"anchor (NumPy controller across runs, a compiled call per period, 2 threads): {t:.2f} s, "
              f"load {load()}")
    b = basilisk_setup()
    t0 = time.perf_counter()
    mc = monte_carlo(b, args.runs, threads=max(args.threads))
    print(f"Basilisk spacecraft: {args.runs} runs x {b.duration:g} s at {1 / b.period:g} Hz: "
          f"{time.perf_counter() - t0:.2f} s ({max(args.threads)} threads), success {mc.success_rate:.1%}, "
          f"load {load()}")


if __name__ == "__main__":
    main()
