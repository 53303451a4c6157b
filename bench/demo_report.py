"""Time of each step of the demo report (``inertia demo``), as ratios to an anchor.

    python bench/demo_report.py [--mesh FILE --units mm] [--rounds 3]

Runs the report builder in this process (steps: the flip study, the plots, the video, the
3D page) ``--rounds`` times, and a fixed NumPy workload (the anchor: 200 products of two
400 x 400 matrices) before each round, so figures from a busy shared machine compare as
ratios.  Prints best and median seconds and the ratio of each step to the anchor.
Compare two checkouts by running this file with each one's ``src`` on ``PYTHONPATH``.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time

import numpy as np


def anchor() -> float:
    rng = np.random.default_rng(0)
    a, b = rng.normal(size=(400, 400)), rng.normal(size=(400, 400))
    t0 = time.perf_counter()
    for _ in range(200):
        a @ b
    return time.perf_counter() - t0


def one_round(props, mesh, title) -> dict:
    from inertia.viz.report import build_report

    marks = []

    def step(name):
        marks.append((name, time.perf_counter()))

    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        build_report(out + "/r", props, title=title, mesh=mesh, progress=step)
        end = time.perf_counter()
    marks.append(("end", end))
    times = {name: marks[k + 1][1] - t for k, (name, t) in enumerate(marks[:-1])}
    times["total"] = end - t0
    return times


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--mesh")
    p.add_argument("--units", default="m")
    p.add_argument("--rounds", type=int, default=3)
    args = p.parse_args()
    if args.mesh:
        from inertia import load_mesh, mesh_file_properties

        props = mesh_file_properties(args.mesh, units=args.units, density=1000.0)
        mesh, title = load_mesh(args.mesh, units=args.units), args.mesh
    else:
        from inertia.massprops.bodies import t_handle

        body = t_handle()
        props, mesh, title = body.props, body.display_mesh(), body.name
    rows, anchors = [], []
    for _ in range(args.rounds):
        anchors.append(anchor())
        rows.append(one_round(props, mesh, title))
    a = min(anchors)
    print(f"anchor: best {a:.3f} s, median {statistics.median(anchors):.3f} s")
    for name in rows[0]:
        vals = [r[name] for r in rows]
        print(f"{name:22s} best {min(vals):6.2f} s  median {statistics.median(vals):6.2f} s  "
              f"best/anchor {min(vals) / a:6.1f}")


if __name__ == "__main__":
    main()
