"""Speed of ``inertia.dynamics.integrate`` (the README's API) per method, and of the whole
``inertia simulate`` process, beside MuJoCo's own C rollout of the same free body (RK4), in
one run.  By hand: ``python bench/integrate.py [--steps 1000000] [--repeat 5]``.

Prints steps/s of the public call (best of ``repeat``, numba cache warm), the ratio to the
anchor, and the wall time of ``inertia simulate --times 0,1e4 --step 0.01`` (1e6 steps).
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from free_body import INERTIA_DIAG, OMEGA0, best_time, mujoco_c_rollout_rate  # noqa: E402


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--steps", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    a = ap.parse_args(argv)
    from inertia.dynamics import integrate
    from inertia.dynamics.integrators import COMPILED_METHODS

    try:
        import mujoco
        anchor = mujoco_c_rollout_rate(mujoco, a.steps, a.repeat)
    except ImportError:
        anchor = None
    print(f"anchor: MuJoCo C rollout, RK4, one body: {anchor:.3g} steps/s" if anchor else "anchor: MuJoCo absent")
    for method in COMPILED_METHODS:
        for backend in ("numba", "numpy"):
            n = a.steps if backend == "numba" else a.steps // 100
            integrate([1, 0, 0, 0], OMEGA0, INERTIA_DIAG, 1e-5, 10, method=method, backend=backend)  # warm
            rate = n / best_time(lambda: integrate([1, 0, 0, 0], OMEGA0, INERTIA_DIAG, 1e-5, n, method=method,
                                                   record_every=n, backend=backend), a.repeat)
            ratio = f"  {rate / anchor:.2f}x anchor" if anchor else ""
            print(f"integrate {method:15s} {backend:6s} {rate:10.3g} steps/s{ratio}")
    for method in ("splitting", "rk4"):
        cmd = [sys.executable, "-m", "inertia.cli.main", "simulate", "--moments", "1,2,3", "--omega", "0.01,1,0",
               "--times", "0,1e4", "--step", "0.01", "--method", method]
        best = min(_wall(cmd) for _ in range(3))
        print(f"inertia simulate --times 0,1e4 --step 0.01 --method {method}: {best:.2f} s (1e6 steps, whole process)")
    return 0


def _wall(cmd) -> float:
    t = time.perf_counter()
    subprocess.run(cmd, check=True, capture_output=True)
    return time.perf_counter() - t


if __name__ == "__main__":
    sys.exit(main())
