"""The 6-DOF transition function against MuJoCo on a free box: speed and energy drift.

Usage::

    python bench/free_body.py [--steps 20000] [--batch 100000] [--batch-steps 100] [--repeat 5]

Body: a box 0.1 x 0.2 x 0.4 m of 1 kg, moments (Ixx, Iyy, Izz) = (0.016667, 0.014167,
0.004167) kg m^2 in its body frame (y is the intermediate axis), spinning near the
intermediate axis, ``omega_body = (0.01, 10, 0)`` rad/s, no gravity, no contacts.  The
same body in MuJoCo: a free joint with that ``diaginertia``, ``gravity="0 0 0"``, contacts
disabled, ``timestep = 1 ms``.

Measured, all in this run (MuJoCo needs ``pip install mujoco``; without it only our rows):

1. **One body, RK4**: steps/s of ``inertia.dynamics.rollouts.rollout(..., method="rk4")``
   (final state only, and saving every state) against MuJoCo's loop
   (``mj_step`` called from Python with ``opt.integrator = RK4``) and, for reference, MuJoCo's
   C rollout (``mujoco.rollout.rollout``, one thread).  Target: >= 20x MuJoCo's loop.
2. **Batch**: 1e5 bodies with random initial states, body-steps/s on one core
   (``threads=1``) for each method, then on all cores.  Target:
   >= 5e7 body-steps/s per core.
3. **Energy drift** after 10 s at h = 1 ms for every method of ours (the transition function,
   torque-free) next to MuJoCo's Euler, implicit, implicitfast and RK4:
   ``T(10 s)/T0 - 1`` and ``max |T(t)/T0 - 1|`` (sampled every 10 ms), ``T = 1/2 w.I w``,
   the times of the Dzhanibekov flips (sign changes of omega_y) and the largest omega error
   against a DOP853 reference (rtol = atol = 1e-13).

Times are the minimum over ``--repeat`` runs after a warm-up (compilation excluded); the
machine may be shared, so compare the ratios within one run, not absolute numbers across runs.
Run by an older install (numba, ``backend=``), :func:`run_rollout` drives that API instead.
"""

from __future__ import annotations

import argparse
import inspect
import os
import platform
import time

import numpy as np

from inertia.dynamics import RigidBody, pack_state
from inertia.dynamics.integrators import METHODS
from inertia.dynamics.rollouts import rollout
from inertia.dynamics.state import OMEGA_BODY

SIZE = np.array([0.1, 0.2, 0.4])           # m, box edges along body x, y, z
MASS = 1.0                                 # kg
INERTIA_DIAG = MASS / 12.0 * np.array([SIZE[1] ** 2 + SIZE[2] ** 2, SIZE[0] ** 2 + SIZE[2] ** 2,
                                       SIZE[0] ** 2 + SIZE[1] ** 2])
# rad/s, near the intermediate (y) axis.  Not (0.01, 10, 0.01): for this box
# Ixx (Ixx - Iyy) = Izz (Iyy - Izz), so that state lies on the separatrix (infinite flip period)
# and the flip times would measure rounding, not the integrators.
OMEGA0 = np.array([0.01, 10.0, 0.0])
H = 1e-3                                   # s
T_END = 10.0                               # s, for the energy drift

MJCF = f"""
<mujoco model="free box">
  <option timestep="{H}" gravity="0 0 0">
    <flag contact="disable"/>
  </option>
  <worldbody>
    <body name="box">
      <freejoint/>
      <inertial pos="0 0 0" mass="{MASS}"
                diaginertia="{INERTIA_DIAG[0]:.17g} {INERTIA_DIAG[1]:.17g} {INERTIA_DIAG[2]:.17g}"/>
      <geom type="box" size="{SIZE[0] / 2} {SIZE[1] / 2} {SIZE[2] / 2}" contype="0" conaffinity="0" mass="0"/>
    </body>
  </worldbody>
</mujoco>
"""


def best_time(fn, repeat: int) -> float:
    fn()                                   # warm-up (compilation, caches)
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def kinetic_energy(omega_body) -> np.ndarray:
    return 0.5 * np.sum(INERTIA_DIAG * omega_body ** 2, axis=-1)


# ------------------------------------------------------------------------------ MuJoCo
def load_mujoco():
    try:
        import mujoco
    except ImportError as exc:
        return None, f"mujoco not importable ({exc}); pip install mujoco"
    return mujoco, None


def mujoco_model(mujoco, integrator: str):
    m = mujoco.MjModel.from_xml_string(MJCF)
    m.opt.integrator = getattr(mujoco.mjtIntegrator, f"mjINT_{integrator.upper()}")
    d = mujoco.MjData(m)
    assert np.array_equal(m.body_inertia[1], INERTIA_DIAG) and np.allclose(m.body_iquat[1], [1, 0, 0, 0])
    return m, d


def mujoco_reset(mujoco, m, d):
    mujoco.mj_resetData(m, d)
    d.qvel[3:6] = OMEGA0                   # free joint: angular velocity in the body frame


def mujoco_loop_rate(mujoco, n: int, repeat: int, integrator: str = "RK4") -> float:
    m, d = mujoco_model(mujoco, integrator)

    def run():
        mujoco_reset(mujoco, m, d)
        for _ in range(n):
            mujoco.mj_step(m, d)
    return n / best_time(run, repeat)


def mujoco_c_rollout_rate(mujoco, n: int, repeat: int):
    """MuJoCo's own C rollout (one thread, no Python in the loop), steps/s; None if unavailable."""
    try:
        from mujoco import rollout as mj_rollout
    except ImportError:
        return None
    m, d = mujoco_model(mujoco, "RK4")
    mujoco_reset(mujoco, m, d)
    spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
    x0 = np.empty(mujoco.mj_stateSize(m, spec))
    mujoco.mj_getState(m, d, x0, spec)
    state = np.empty((1, n, x0.size))
    return n / best_time(lambda: mj_rollout.rollout(m, d, x0[None], nstep=n, state=state), repeat)


def mujoco_energy(mujoco, integrator: str, n: int, every: int):
    m, d = mujoco_model(mujoco, integrator)
    mujoco_reset(mujoco, m, d)
    w = [d.qvel[3:6].copy()]
    for k in range(n):
        mujoco.mj_step(m, d)
        if (k + 1) % every == 0:
            w.append(d.qvel[3:6].copy())
    w = np.array(w)
    return kinetic_energy(w), w


# ------------------------------------------------------------------------------ ours
#: an install before the compiled core: numba kernels chosen by ``backend=``, threads by numba
OLD_API = "backend" in inspect.signature(rollout).parameters


def run_rollout(x0, u, h, n=None, *, threads=1, **kw):
    """``rollout`` on ``threads`` threads, on this install's API or on the old one's."""
    if not OLD_API:
        return rollout(x0, u, h, n, threads=threads, **kw)
    import numba
    numba.set_num_threads(min(threads, numba.config.NUMBA_NUM_THREADS))
    return rollout(x0, u, h, n, backend="numba", **kw)


def our_body() -> RigidBody:
    return RigidBody(MASS, np.diag(INERTIA_DIAG))


def our_x0() -> np.ndarray:
    return pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], OMEGA0)


def our_energy(method: str, n: int, every: int):
    traj = run_rollout(our_x0(), None, H, n, body=our_body(), method=method, save_every=every)
    return kinetic_energy(traj[:, OMEGA_BODY]), traj[:, OMEGA_BODY]


def reference_omega(n: int, every: int) -> np.ndarray:
    """Torque-free omega_body sampled every ``every`` steps: scipy DOP853, rtol = atol = 1e-13."""
    from scipy.integrate import solve_ivp
    t = np.arange(0, n + 1, every) * H
    sol = solve_ivp(lambda _, w: np.cross(INERTIA_DIAG * w, w) / INERTIA_DIAG, (0.0, t[-1]), OMEGA0,
                    method="DOP853", rtol=1e-13, atol=1e-13, t_eval=t)
    return sol.y.T


def flip_times(omega: np.ndarray, every: int) -> str:
    """Times (s) at which omega_y changes sign: the Dzhanibekov flips."""
    s = np.sign(omega[:, 1])
    k = np.flatnonzero(s[1:] != s[:-1]) + 1
    return " ".join(f"{t:.2f}" for t in k * every * H) or "-"


def random_batch(n: int, rng) -> np.ndarray:
    q = rng.normal(size=(n, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    return np.concatenate([rng.normal(size=(n, 3)), rng.normal(size=(n, 3)), q,
                           OMEGA0 + rng.normal(size=(n, 3))], axis=1)


# ------------------------------------------------------------------------------ main
def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--steps", type=int, default=20000, help="steps of the one-body speed runs")
    ap.add_argument("--batch", type=int, default=100_000, help="bodies in the batch run")
    ap.add_argument("--batch-steps", type=int, default=100, help="steps of the batch run")
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args(argv)

    mujoco, why = load_mujoco()
    print(f"# free box {SIZE.tolist()} m, {MASS} kg, I = {np.round(INERTIA_DIAG, 6).tolist()} kg m^2, "
          f"omega0 = {OMEGA0.tolist()} rad/s, h = {H * 1e3:g} ms")
    print(f"# {platform.processor() or platform.machine()}, {os.cpu_count()} logical cores, numpy {np.__version__}"
          + (", old API (numba)" if OLD_API else ", compiled core")
          + (f", mujoco {mujoco.__version__}" if mujoco else f", {why}"))
    body, x0 = our_body(), our_x0()

    # ---------------------------------------------------------------- 1. one body, RK4
    n = args.steps
    r_final = n / best_time(lambda: run_rollout(x0, None, H, n, body=body, method="rk4", save_every=None),
                            args.repeat)
    r_traj = n / best_time(lambda: run_rollout(x0, None, H, n, body=body, method="rk4"), args.repeat)
    print("\n## 1. One body, RK4, steps/s (one thread)\n")
    print(f"| {'run':<52} | {'steps/s':>10} | {'vs MuJoCo loop':>14} |")
    print(f"|{'-' * 54}|{'-' * 12}|{'-' * 16}|")
    mj_loop = None
    rows = [("ours, rollout, final state only", r_final), ("ours, rollout, every state saved", r_traj)]
    if mujoco:
        mj_loop = mujoco_loop_rate(mujoco, n, args.repeat, "RK4")
        rows.append(("MuJoCo mj_step loop in Python, RK4", mj_loop))
        rows.append(("MuJoCo mj_step loop in Python, Euler", mujoco_loop_rate(mujoco, n, args.repeat, "Euler")))
        c_rate = mujoco_c_rollout_rate(mujoco, n, args.repeat)
        if c_rate:
            rows.append(("MuJoCo rollout.rollout (C loop, 1 thread), RK4", c_rate))
    for name, rate in rows:
        ratio = f"{rate / mj_loop:13.1f}x" if mj_loop else f"{'-':>14}"
        print(f"| {name:<52} | {rate:10.3g} | {ratio} |")
    if mj_loop:
        verdict = "met" if r_final / mj_loop >= 20 else "NOT met"
        print(f"\nTarget >= 20x MuJoCo's RK4 loop: {r_final / mj_loop:.1f}x (final state only), "
              f"{r_traj / mj_loop:.1f}x (every state saved): {verdict}.")

    # ---------------------------------------------------------------- 2. batch
    rng = np.random.default_rng(0)
    N, nb = args.batch, args.batch_steps
    xb = random_batch(N, rng)
    print(f"\n## 2. Batch of {N} bodies, {nb} steps, body-steps/s\n")
    cores = os.cpu_count() or 1
    hdr = f"| {'method':<16} | {'1 core':>10} | {f'all cores ({cores})':>16} |"
    print(hdr)
    print("|" + "|".join("-" * (len(c) + 0) for c in hdr.split("|")[1:-1]) + "|")
    per_core = {}
    for method in METHODS:
        def run(threads, meth=method):
            run_rollout(xb, None, H, nb, body=body, method=meth, save_every=None, threads=threads)
        one = N * nb / best_time(lambda: run(1), args.repeat)
        every = N * nb / best_time(lambda: run(cores), args.repeat)
        per_core[method] = one
        print(f"| {method:<16} | {one:10.3g} | {every:16.3g} |")
    best = max(per_core, key=per_core.get)
    print(f"\nTarget >= 5e7 body-steps/s per core: rk4 {per_core['rk4']:.3g} "
          f"({'met' if per_core['rk4'] >= 5e7 else 'NOT met'}); best {best} {per_core[best]:.3g}.")

    # ---------------------------------------------------------------- 3. energy drift
    n = int(round(T_END / H))
    every = 10
    print(f"\n## 3. Energy drift after {T_END:g} s at h = {H * 1e3:g} ms (torque-free, near the intermediate axis)\n")
    w_ref = reference_omega(n, every)

    def row(label, T, w):
        err = np.abs(w - w_ref).max()
        print(f"| {label:<30} | {T[-1] / T[0] - 1:14.3e} | {np.abs(T / T[0] - 1).max():14.3e} | "
              f"{err:16.2e} | {flip_times(w, every):<26} |")

    print(f"| {'integrator':<30} | {'T(10s)/T0 - 1':>14} | {'max |T/T0 - 1|':>14} | {'max |w - w_ref|':>16} | "
          f"{'flips of omega_y (s)':<26} |")
    print(f"|{'-' * 32}|{'-' * 16}|{'-' * 16}|{'-' * 18}|{'-' * 28}|")
    row("reference (DOP853, 1e-13)", kinetic_energy(w_ref), w_ref)
    results = {}
    for method in METHODS:
        T, w = our_energy(method, n, every)
        results[f"ours {method}"] = w
        row(f"ours {method}", T, w)
    if mujoco:
        for integ in ("Euler", "implicit", "implicitfast", "RK4"):
            T, w = mujoco_energy(mujoco, integ, n, every)
            results[f"MuJoCo {integ}"] = w
            row(f"MuJoCo {integ}", T, w)
        diff = np.abs(results["ours rk4"] - results["MuJoCo RK4"]).max()
        print(f"\nmax |omega_ours_rk4 - omega_mujoco_rk4| over the 10 s = {diff:.2e} rad/s (same model).")
    else:
        print(f"\nMuJoCo rows skipped: {why}")


if __name__ == "__main__":
    main()
