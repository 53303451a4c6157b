"""Benchmark: solid mass properties of triangle meshes, inertia vs trimesh.

Run by hand::

    python bench/mesh_mass_properties.py [--repeat 7] [--min-time 0.2]

Meshes: icospheres (trimesh.creation.icosphere, subdivisions 3..8: 1.3k .. 1.3M faces)
and the largest real mesh of the shared data, koala_large.obj (loaded with
``trimesh.load(..., process=True)``).

What is timed, per call, from the same (vertices, faces) arrays in the same process:

* ours: ``central_inertia(*solid_integrals(vertices, faces), 1.0)``, i.e. the whole of the
  integrals' work from the arrays to (volume, COM, central inertia): input checks, reference
  point, kernel pass(es) (``inertia._ext.integrals``), COM and inertia.
* trimesh: ``trimesh.triangles.mass_properties(vertices[faces])``.  This is exactly
  what ``Trimesh.mass_properties`` runs on a fresh mesh (it gathers ``triangles =
  vertices[faces]`` and their cross products, then integrates), without the Trimesh
  constructor, its processing, or its result cache -- so trimesh is not charged for
  anything but its mass-properties computation.

Each entry is the minimum over ``--repeat`` measurements (each measurement runs the
call enough times to last ``--min-time`` seconds, garbage collector off, via timeit);
``spread`` is (median - min) / min over the repeats, a measure of machine noise.
"""

from __future__ import annotations

import argparse
import os
import platform
import statistics
import sys
import timeit
from pathlib import Path

import numpy as np

# ../shared/data/meshes beside the checkout (this file is bench/ in the repository root)
MESH_DIR = Path(os.environ.get("INERTIA_MESH_DIR",
                               Path(__file__).resolve().parents[2] / "shared" / "data" / "meshes"))


def load_meshes():
    """[(name, vertices (V, 3) float64, faces (F, 3) int64)] in increasing size."""
    import trimesh

    meshes = []
    for sub in range(3, 9):
        m = trimesh.creation.icosphere(subdivisions=sub)
        meshes.append((f"icosphere({sub})", np.ascontiguousarray(m.vertices, dtype=np.float64),
                       np.ascontiguousarray(m.faces, dtype=np.int64)))
    koala = MESH_DIR / "koala_large.obj"
    if koala.exists():
        m = trimesh.load(koala, process=True, force="mesh")
        meshes.append(("koala_large.obj", np.ascontiguousarray(m.vertices, dtype=np.float64),
                       np.ascontiguousarray(m.faces, dtype=np.int64)))
    else:
        print(f"(skipping koala_large.obj: not found in {MESH_DIR})", file=sys.stderr)
    return sorted(meshes, key=lambda t: len(t[2]))


def time_call(fn, repeat: int, min_time: float):
    """(min seconds per call, relative spread (median - min) / min) over ``repeat`` measurements."""
    t1 = timeit.Timer(fn).timeit(1)
    number = max(1, int(min_time / max(t1, 1e-9)))
    per_call = [t / number for t in timeit.Timer(fn).repeat(repeat=repeat, number=number)]
    best = min(per_call)
    return best, (statistics.median(per_call) - best) / best


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeat", type=int, default=7, help="measurements per entry (default 7)")
    ap.add_argument("--min-time", type=float, default=0.2, help="seconds per measurement (default 0.2)")
    args = ap.parse_args(argv)

    import trimesh
    from trimesh.triangles import mass_properties as trimesh_mass_properties

    from inertia.geometry import integrals as mk

    print(f"python {platform.python_version()}, numpy {np.__version__}, trimesh {trimesh.__version__}, "
          f"{os.cpu_count()} CPUs ({platform.processor() or platform.machine()})")
    print(f"min of {args.repeat} measurements of >= {args.min_time} s each; spread = (median - min) / min\n")

    cols = ("trimesh", "ours")
    head = f"{'mesh':<16} {'faces':>9} | " + " | ".join(f"{c + ' Mface/s':>15} {'us/call':>10} {'spread':>6}"
                                                      for c in cols)
    head += f" | {'x ours':>9} | max rel diff"
    print(head)
    print("-" * len(head))
    for name, v, f in load_meshes():
        n = len(f)

        def run_trimesh(v=v, f=f):
            return trimesh_mass_properties(v[f])

        def run_ours(v=v, f=f):
            return mk.central_inertia(*mk.solid_integrals(v, f), 1.0)

        results = {c: time_call(fn, args.repeat, args.min_time) for c, fn in zip(cols, (run_trimesh, run_ours))}
        ref = run_trimesh()
        diff = np.abs(run_ours()[1] - ref.inertia).max() / np.abs(ref.inertia).max()
        row = f"{name:<16} {n:>9} | "
        row += " | ".join(f"{n / results[c][0] / 1e6:>15.2f} {results[c][0] * 1e6:>10.1f} {results[c][1]:>6.1%}"
                          for c in cols)
        row += f" | {results['trimesh'][0] / results['ours'][0]:>9.1f} | {diff:.1e}"
        print(row, flush=True)
    print("\nx ours = trimesh time / our time (throughput ratio, higher is better);"
          " max rel diff = max |I_ours - I_trimesh| / max |I_trimesh| (both near the origin).")
    return 0


if __name__ == "__main__":
    sys.exit(main())
