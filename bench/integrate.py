"""Speed of the integrators beside their anchors, in one run: ``python bench/integrate.py``.

Rows (each timed once per round, rounds interleaved; best and median over the rounds, and the
ratio to the anchor of the same section taken round by round):

1. ``inertia.dynamics.integrate`` (the README's API), one body, every method: steps/s;
   anchor: MuJoCo's C rollout of the same free box, RK4, one thread (``mujoco.rollout``;
   needs ``pip install mujoco``).  h = 10 us (1e6 steps = 10 s: euler_explicit's energy
   growth stays finite).
2. ``inertia.dynamics.rollout``, a batch of ``--batch`` bodies (final state only), body-steps/s
   on 1 and 2 threads (``threads=``); anchor: the C loop of
   ``bench/rollout_soa.c`` (structure of arrays, chunks of 128 bodies kept in L1, the same
   RK4 / splitting step), built here with ``cc -O3 -march=native``, on 1 and 2 threads.
3. ``inertia simulate --times 0,1e4 --step 0.01`` (1e6 steps), whole process, wall time.
4. With ``--cold``: the first call of each method in a fresh process (an old install: with an
   empty numba cache, ``NUMBA_CACHE_DIR`` a new folder), CPU seconds.

The machine may be shared: the load average is printed before and after; compare ratios.  Run by
an install before the compiled core, the same rows drive its numba kernels (``backend="numba"``,
``numba.set_num_threads``; see ``free_body.run_rollout``), so old and new are measured by one script.
"""

from __future__ import annotations

import argparse
import ctypes
import os
import statistics
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from free_body import INERTIA_DIAG, OLD_API, OMEGA0, random_batch, run_rollout  # noqa: E402
from startup import ensure_bytecode  # noqa: E402

METHODS = ("euler_explicit", "euler_implicit", "rk4", "splitting", "dmv", "dmv4", "midpoint")
H = 1e-3


# ---------------------------------------------------------------------------- timing helpers
def seconds(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def run_rounds(rows: dict, rounds: int) -> dict:
    """``rows``: name -> (work, fn); each fn runs once per round, rows interleaved. name -> rates."""
    for _, fn in rows.values():
        fn()                                            # warm-up: compile or load, caches
    rates = {name: [] for name in rows}
    for _ in range(rounds):
        for name, (work, fn) in rows.items():
            rates[name].append(work / seconds(fn))
    return rates


def report(rates: dict, anchor: str | None, unit: str) -> None:
    print(f"| row | best {unit} | median {unit} | vs anchor (best, median) |")
    print("|---|---|---|---|")
    for name, r in rates.items():
        vs = "-"
        if anchor and name != anchor:
            ratios = [a / b for a, b in zip(r, rates[anchor])]
            vs = f"{max(r) / max(rates[anchor]):.2f}x, {statistics.median(ratios):.2f}x"
        print(f"| {name} | {max(r):.3g} | {statistics.median(r):.3g} | {vs} |")


# ---------------------------------------------------------------------------- 1. integrate
def integrate_rows(steps: int) -> dict:
    from inertia.dynamics import integrate

    kw = {"backend": "numba"} if OLD_API else {}
    rows = {}
    for method in METHODS:
        rows[f"integrate {method}"] = (steps, lambda m=method: integrate(
            [1, 0, 0, 0], OMEGA0, INERTIA_DIAG, 1e-5, steps, method=m, record_every=steps, **kw))
    try:
        import mujoco
        from free_body import mujoco_model, mujoco_reset
        from mujoco import rollout as mj_rollout
        m, d = mujoco_model(mujoco, "RK4")
        mujoco_reset(mujoco, m, d)
        spec = mujoco.mjtState.mjSTATE_FULLPHYSICS
        x0 = np.empty(mujoco.mj_stateSize(m, spec))
        mujoco.mj_getState(m, d, x0, spec)
        n = max(1000, steps // 20)
        state = np.empty((1, n, x0.size))
        rows["anchor: MuJoCo C rollout, RK4"] = (n, lambda: mj_rollout.rollout(m, d, x0[None], nstep=n, state=state))
    except ImportError:
        pass
    return rows


# ---------------------------------------------------------------------------- 2. rollout
def build_c_anchor(tmp: Path):
    """ctypes function ``rollout(method, N, n_steps, h, x, I, force, mass, gravity)`` or None."""
    so = tmp / "rollout_soa.so"
    cmd = ["cc", "-O3", "-march=native", "-fno-math-errno", "-shared", "-fPIC", str(HERE / "rollout_soa.c"),
           "-o", str(so), "-lm"]
    try:
        subprocess.run(cmd, check=True, capture_output=True)
    except (OSError, subprocess.CalledProcessError) as exc:
        print(f"# C anchor not built ({exc})")
        return None
    lib = ctypes.CDLL(str(so))
    f = lib.rollout
    dp = ctypes.POINTER(ctypes.c_double)
    f.argtypes = [ctypes.c_int, ctypes.c_long, ctypes.c_long, ctypes.c_double, dp, dp, dp, ctypes.c_double, dp]
    f.restype = None
    return f


def c_rollout(f, method_id: int, x: np.ndarray, n: int, threads: int) -> None:
    """The C loop over ``x`` (N, 13) in place, its bodies split over ``threads`` Python threads."""
    dp = ctypes.POINTER(ctypes.c_double)
    I, F, g = np.array(INERTIA_DIAG), np.zeros(3), np.zeros(3)
    chunks = x.shape[0] // 128
    bounds = [128 * (chunks * k // threads) for k in range(threads + 1)]

    def part(lo, hi):
        sub = x[lo:hi]
        f(method_id, hi - lo, n, H, sub.ctypes.data_as(dp), I.ctypes.data_as(dp), F.ctypes.data_as(dp), 1.0,
          g.ctypes.data_as(dp))
    ts = [threading.Thread(target=part, args=(lo, hi)) for lo, hi in zip(bounds[:-1], bounds[1:])]
    for t in ts:
        t.start()
    for t in ts:
        t.join()


def rollout_rows(N: int, n: int, cfun) -> dict:
    from inertia.dynamics import RigidBody

    body = RigidBody(1.0, np.diag(INERTIA_DIAG))
    xb = random_batch(N, np.random.default_rng(0))

    def ours(method, threads, steps):
        def run():
            run_rollout(xb, None, H, steps, body=body, method=method, save_every=None, threads=threads)
        return N * steps, run

    rows = {}
    for method in METHODS:
        steps = n if method in ("euler_explicit", "rk4", "splitting") else max(1, n // 10)
        rows[f"rollout {method}, 1 thread"] = ours(method, 1, steps)
    for method in ("rk4", "splitting"):
        rows[f"rollout {method}, 2 threads"] = ours(method, 2, n)
    if cfun is not None:
        xc = xb.copy()
        for cid, name in ((0, "rk4"), (1, "splitting")):
            for threads in (1, 2):
                rows[f"anchor: C SoA {name}, {threads} thread{'s' * (threads > 1)}"] = (
                    N * n, lambda c=cid, t=threads: c_rollout(cfun, c, xc, n, t))
    return rows


# ---------------------------------------------------------------------------- 3. simulate
def simulate_walls(method: str, runs: int) -> list:
    cmd = [sys.executable, "-m", "inertia.cli.main", "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0",
           "--times", "0,1e4", "--step", "0.01", "--method", method]
    ensure_bytecode("inertia")                                 # as installed (see bench/startup.py)
    subprocess.run(cmd, check=True, capture_output=True)      # warm the file cache (an old install: numba's)
    return [seconds(lambda: subprocess.run(cmd, check=True, capture_output=True)) for _ in range(runs)]


# ---------------------------------------------------------------------------- 4. cold compile
_COLD = """
import sys, time, numpy as np
sys.path.insert(0, {here!r})
from free_body import OLD_API
from inertia.dynamics import integrate, RigidBody, pack_state
from inertia.dynamics.rollouts import rollout
m = sys.argv[1]
kw = dict(backend="numba") if OLD_API else dict()
t = time.process_time()
integrate([1, 0, 0, 0], [0.01, 1, 0], [1, 2, 3], 0.01, 10, method=m, **kw)
a = time.process_time() - t
t = time.process_time()
rollout(np.broadcast_to(pack_state([0, 0, 0], [0, 0, 0], [1, 0, 0, 0], [0.01, 1, 0]), (200, 13)), None, 0.01, 2,
        body=RigidBody(1.0, np.diag([1.0, 2, 3])), method=m, save_every=None, **kw)
print(f"{{a:.2f}} {{time.process_time() - t:.2f}}")
"""


def cold_compile() -> None:
    print("\n## 4. First call in a fresh process (CPU s; an old install: with an empty numba cache)\n")
    print("| method | integrate | rollout |\n|---|---|---|")
    for method in METHODS:
        with tempfile.TemporaryDirectory() as cache:
            env = dict(os.environ, NUMBA_CACHE_DIR=cache)
            out = subprocess.run([sys.executable, "-c", _COLD.format(here=str(HERE)), method], env=env, check=True, capture_output=True,
                                 text=True).stdout.split()
        print(f"| {method} | {out[0]} | {out[1]} |")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1_000_000, help="steps of the one-body integrate rows")
    ap.add_argument("--batch", type=int, default=100_096, help="bodies of the rollout rows (a multiple of 128)")
    ap.add_argument("--batch-steps", type=int, default=100)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--cold", action="store_true", help="also time cold compilation (slow)")
    ap.add_argument("--sections", default="123", help="which sections to run, e.g. 2 (default 123)")
    a = ap.parse_args(argv)
    print(f"# {os.cpu_count()} cores, numpy {np.__version__}, {'old API (numba)' if OLD_API else 'compiled core'}; "
          f"load average before: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")

    if "1" in a.sections:
        print(f"\n## 1. integrate, one body, steps/s ({a.rounds} interleaved rounds)\n")
        report(run_rounds(integrate_rows(a.steps), a.rounds), "anchor: MuJoCo C rollout, RK4", "steps/s")
    if "2" in a.sections:
        rollout_section(a)
    if "3" in a.sections:
        print("\n## 3. inertia simulate --times 0,1e4 --step 0.01 (1e6 steps), whole process\n")
        for method in ("splitting", "rk4", "dmv"):
            w = simulate_walls(method, 3)
            print(f"--method {method}: best {min(w):.2f} s, median {statistics.median(w):.2f} s")
    if a.cold:
        cold_compile()
    print(f"\n# load average after: {' '.join(f'{x:.2f}' for x in os.getloadavg())}")
    return 0


def rollout_section(a) -> None:
    with tempfile.TemporaryDirectory() as tmp:
        cfun = build_c_anchor(Path(tmp))
        print(f"\n## 2. rollout, {a.batch} bodies x {a.batch_steps} steps (implicit methods: a tenth), "
              f"body-steps/s\n")
        report(run_rounds(rollout_rows(a.batch, a.batch_steps, cfun), a.rounds),
               "anchor: C SoA rk4, 1 thread" if cfun else None, "body-steps/s")


if __name__ == "__main__":
    sys.exit(main())
