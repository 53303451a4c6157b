"""Benchmark: the public mesh call with every check on, against what a trimesh user runs.

Run by hand::

    python bench/mesh_public.py [--rounds 7]

Per mesh, interleaved rounds in one process (ours, then trimesh, then ours ...), best and
median seconds per call, and the ratio trimesh / ours:

* ours: ``inertia.mesh_properties(vertices, faces, density=1.0)``: closedness, manifold,
  winding, degenerate faces, self-crossing (certificate or search), overlap, then the
  integrals and the validated result;
* trimesh: ``trimesh.Trimesh(vertices, faces).mass_properties`` (its constructor merges and
  validates as it does by default, then integrates; nothing is checked).

Meshes: icospheres of 1,280 and 1.31M faces (star-shaped: the self-crossing certificate
proves them in the integrals' pass), tori of 5,000 and 1.31M faces (not star-shaped: the
face-pair search runs; above SEARCH_MAX_FACES a note instead).
"""

from __future__ import annotations

import argparse
import os
import statistics
import sys
import time

import numpy as np


def meshes():
    import trimesh

    out = []
    for name, m in (("icosphere 1,280", trimesh.creation.icosphere(subdivisions=3)),
                    ("torus 5,000", trimesh.creation.torus(1.0, 0.3, major_sections=100, minor_sections=25)),
                    ("icosphere 1.31M", trimesh.creation.icosphere(subdivisions=8)),
                    ("torus 1.31M", trimesh.creation.torus(1.0, 0.3, major_sections=1280, minor_sections=512))):
        out.append((name, np.ascontiguousarray(m.vertices, dtype=np.float64),
                    np.ascontiguousarray(m.faces, dtype=np.int64)))
    return out


def per_call(fn, budget: float) -> tuple[float, float]:
    """(wall, CPU) seconds per call over calls lasting about ``budget`` seconds."""
    n, w0, c0 = 0, time.perf_counter(), time.process_time()
    while True:
        fn()
        n += 1
        if time.perf_counter() - w0 >= budget:
            break
    return (time.perf_counter() - w0) / n, (time.process_time() - c0) / n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--budget", type=float, default=0.3, help="seconds per measurement")
    args = ap.parse_args(argv)
    import trimesh

    import inertia

    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs; {args.rounds} interleaved rounds")
    print(f"{'mesh':<18} {'ours best':>10} {'median':>9} {'trimesh best':>13} {'median':>9} {'x best':>7} "
          f"{'x median':>8} {'x CPU':>6}")
    for name, v, f in meshes():
        ours = lambda v=v, f=f: inertia.mesh_properties(v, f, density=1.0)  # noqa: E731
        theirs = lambda v=v, f=f: trimesh.Trimesh(v, f).mass_properties  # noqa: E731
        ours()
        theirs()
        o, t = [], []
        for _ in range(args.rounds):
            o.append(per_call(ours, args.budget))
            t.append(per_call(theirs, args.budget))
        ob, om = min(x[0] for x in o), statistics.median(x[0] for x in o)
        tb, tm = min(x[0] for x in t), statistics.median(x[0] for x in t)
        cpu = min(x[1] for x in t) / min(x[1] for x in o)
        print(f"{name:<18} {ob * 1e3:>9.3f}ms {om * 1e3:>7.3f}ms {tb * 1e3:>11.3f}ms {tm * 1e3:>7.3f}ms "
              f"{tb / ob:>7.1f} {tm / om:>8.1f} {cpu:>6.1f}", flush=True)
    print("\nx = trimesh / ours (higher is better); x CPU: the same with process CPU time (noise of a shared machine)")
    return 0


if __name__ == "__main__":
    sys.exit(main())
