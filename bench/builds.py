"""Speed of several builds of the compiled core side by side: ``python bench/builds.py NAME=PYTHON ...``.

Each build is an install in its own environment (e.g. ``native=../venv-native/bin/python
portable=../venv-portable/bin/python``; build them as wheels, ``pip install .
-C cmake.define.INERTIA_NATIVE=OFF``, see docs/performance.md).  One worker process per build
makes the inputs once; then every round asks each worker in turn for each row once, so the
builds are measured interleaved in one run.  Printed per row: best and median per build, and
its speed against the first build (best against best, and the median of the round-by-round
ratios; above 1 is slower than the first build).

Rows: ``mesh_properties`` (every check) of an icosphere of 1,280 faces, a torus of 5,000 (the
self-crossing search), an icosphere and a torus of 1.31M faces, and ``mesh_file_properties`` of
the large icosphere as binary STL (read, weld, checks): seconds per call, calls lasting about
``--budget`` s.  ``rollout`` of 100,096 bodies x 100 steps on 1 thread, rk4, splitting and
euler_explicit (body-steps/s, one call); ``integrate`` of one body, 200,000 steps, rk4 and
splitting (steps/s).  Each worker reports the
variant of the hot kernels it runs (``inertia._ext._isa()``); ``--isa NAME=VARIANT`` forces one
(``_force_isa``), e.g. ``port-sse2=x86-64`` beside ``port=...`` run by the same python.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent

WORKER = r"""
import json, sys, time
sys.path.insert(0, {here!r})
import numpy as np
import trimesh
import inertia
from inertia import _ext
from inertia.dynamics import RigidBody, integrate
from free_body import INERTIA_DIAG, OMEGA0, random_batch
from inertia.dynamics.rollouts import rollout

force = {force!r}
if force:
    _ext._force_isa(force)
budget = {budget!r}
N, STEPS, H = 100_096, 100, 1e-3
body = RigidBody(1.0, np.diag(INERTIA_DIAG))
xb = random_batch(N, np.random.default_rng(0))
meshes = {{}}
for name, m in (("icosphere 1,280", trimesh.creation.icosphere(subdivisions=3)),
                ("torus 5,000", trimesh.creation.torus(1.0, 0.3, major_sections=100, minor_sections=25)),
                ("icosphere 1.31M", trimesh.creation.icosphere(subdivisions=8)),
                ("torus 1.31M", trimesh.creation.torus(1.0, 0.3, major_sections=1280, minor_sections=512))):
    meshes[name] = (np.ascontiguousarray(m.vertices, dtype=np.float64), np.ascontiguousarray(m.faces, dtype=np.int64))

def per_call(fn):
    n, t0 = 0, time.perf_counter()
    while True:
        fn()
        n += 1
        if time.perf_counter() - t0 >= budget:
            return (time.perf_counter() - t0) / n

def once(fn, work):
    t0 = time.perf_counter()
    fn()
    return work / (time.perf_counter() - t0)

rows = {{}}
for name, (v, f) in meshes.items():
    rows[f"mesh_properties {{name}}, s"] = lambda v=v, f=f: per_call(lambda: inertia.mesh_properties(v, f, density=1.0))
rows["mesh_file_properties binary STL icosphere 1.31M, s"] = lambda: per_call(
    lambda: inertia.mesh_file_properties({stl!r}, density=1.0))
for m in ("rk4", "splitting", "euler_explicit"):
    rows[f"rollout {{m}}, 1 thread, body-steps/s"] = lambda m=m: once(
        lambda: rollout(xb, None, H, STEPS, body=body, method=m, save_every=None, threads=1), N * STEPS)
for m in ("rk4", "splitting"):
    rows[f"integrate {{m}}, one body, steps/s"] = lambda m=m: once(
        lambda: integrate([1, 0, 0, 0], OMEGA0, INERTIA_DIAG, 1e-5, 200_000, method=m, record_every=200_000),
        200_000)
for fn in rows.values():
    fn()                                                     # warm-up
print(json.dumps({{"isa": _ext._isa() if hasattr(_ext, "_isa") else "(no hook)", "rows": list(rows)}}), flush=True)
for line in sys.stdin:
    print(json.dumps({{name: fn() for name, fn in rows.items()}}), flush=True)
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("builds", nargs="+", help="NAME=PYTHON, the first is the reference")
    ap.add_argument("--isa", action="append", default=[], help="NAME=VARIANT: force that build's variant")
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--budget", type=float, default=0.3, help="seconds per mesh measurement")
    a = ap.parse_args(argv)
    force = dict(x.split("=", 1) for x in a.isa)
    import trimesh

    tmp = tempfile.TemporaryDirectory()
    stl = Path(tmp.name) / "icosphere.stl"                  # binary STL: the reader, the weld, the checks
    trimesh.creation.icosphere(subdivisions=8).export(stl)
    workers = {}
    for spec in a.builds:
        name, python = spec.split("=", 1)
        code = WORKER.format(here=str(HERE), force=force.get(name, ""), budget=a.budget, stl=str(stl))
        workers[name] = subprocess.Popen([python, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                         text=True, cwd="/")
    info = {name: json.loads(w.stdout.readline()) for name, w in workers.items()}
    rows = info[next(iter(info))]["rows"]
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs; {a.rounds} interleaved rounds")
    print("builds: " + ", ".join(f"{n} ({i['isa']})" for n, i in info.items()))
    got = {name: [] for name in workers}
    for _ in range(a.rounds):
        for name, w in workers.items():
            w.stdin.write("go\n")
            w.stdin.flush()
            got[name].append(json.loads(w.stdout.readline()))
    for w in workers.values():
        w.stdin.close()
        w.wait()
    print(f"load average {os.getloadavg()[0]:.1f} after\n")
    ref = next(iter(workers))
    print("| row | " + " | ".join(workers) + " |")
    print("|---|" + "---|" * len(workers))
    for row in rows:
        seconds = row.endswith(", s")
        cells = []
        for name in workers:
            r = [g[row] for g in got[name]]
            best = min(r) if seconds else max(r)
            med = statistics.median(r)
            cell = f"{best * 1e3:.3g} ms (median {med * 1e3:.3g})" if seconds else f"{best:.3g} (median {med:.3g})"
            if name != ref:
                q = [g[row] for g in got[ref]]
                qbest = min(q) if seconds else max(q)
                slow = best / qbest if seconds else qbest / best
                per_round = statistics.median((x / y) if seconds else (y / x) for x, y in zip(r, q))
                cell += f", {slow:.2f}x ({per_round:.2f}x)"
            cells.append(cell)
        print(f"| {row} | " + " | ".join(cells) + " |")
    print("\nNx: time against the first build, best against best (median of the per-round ratios); "
          "above 1 is slower")
    return 0


if __name__ == "__main__":
    sys.exit(main())
