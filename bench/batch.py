"""Benchmark: files per second of `inertia batch` with 1 and 2 workers, against a plain loop.

Generates N small binary STL meshes (perturbed icospheres, 1,280 to 5,120 faces... up to
~10k with --small-faces) and M large ones (81,920 faces) in a temporary folder, then in one
run measures:

* a plain Python loop over trimesh (``trimesh.load`` + ``mass_properties``), one process;
* ``run_batch`` on a local Dask cluster with 1 worker, then with 2 workers;

and prints files/s, the speed-up from 1 to 2 workers, the ratio to the trimesh loop, and the
peak resident memory of each worker.  Our rows include the full defect checks (edges,
winding, orientation) that the trimesh loop does not do.

    python bench/batch.py [--small 2000] [--large 20] [--keep DIR]
"""

from __future__ import annotations

import argparse
import os
import shutil
import struct
import tempfile
import time

import numpy as np


def write_binary_stl(path, vertices, faces) -> None:
    tri = vertices[faces].astype("<f4")
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]).astype("<f4")
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = n, tri
    with open(path, "wb") as fh:
        fh.write(b"inertia bench".ljust(80, b" "))
        fh.write(struct.pack("<I", len(faces)))
        fh.write(rec.tobytes())


def make_dataset(folder, n_small: int, n_large: int, seed: int = 0) -> list[str]:
    import trimesh

    rng = np.random.default_rng(seed)
    spheres = {k: trimesh.creation.icosphere(subdivisions=k) for k in (3, 4, 6)}
    paths = []
    for i in range(n_small + n_large):
        level = 6 if i >= n_small else (3 if i % 2 else 4)
        s = spheres[level]
        # star-shaped radial perturbation keeps the mesh closed and outward-wound
        r = 1.0 + 0.2 * rng.random() * np.sin(rng.integers(1, 5) * s.vertices[:, :1] * 3)
        v = s.vertices * r * rng.uniform(0.5, 2.0, 3)
        p = os.path.join(folder, f"{'large' if level == 6 else 'small'}_{i:05d}.stl")
        write_binary_stl(p, v, s.faces)
        paths.append(p)
    return paths


def trimesh_loop(paths) -> float:
    import trimesh

    t0 = time.perf_counter()
    for p in paths:
        m = trimesh.load(p)
        m.mass_properties  # noqa: B018 - computed on access
    return time.perf_counter() - t0


def ours(paths, workers: int, out_dir: str):
    import distributed

    from inertia.batch import run_batch
    from inertia.batch.run import local_cluster

    cluster = local_cluster(workers)  # the cluster run_batch starts by default
    client = distributed.Client(cluster)
    try:
        from inertia.batch.record import warm_up

        client.run(warm_up)  # imports and compiled kernels loaded outside the timing
        out = os.path.join(out_dir, f"bench-{workers}.parquet")
        t0 = time.perf_counter()
        summary = run_batch(paths, out, scheduler=client, progress=False, overwrite=True)
        elapsed = time.perf_counter() - t0

        def peak_rss_mb():
            import resource

            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

        peaks = list(client.run(peak_rss_mb).values())
    finally:
        client.close()
        cluster.close()
    assert summary.errors == 0, summary.lines()
    return elapsed, peaks


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--small", type=int, default=2000)
    ap.add_argument("--large", type=int, default=20)
    ap.add_argument("--keep", metavar="DIR", help="generate into DIR and keep it")
    args = ap.parse_args()
    folder = args.keep or tempfile.mkdtemp(prefix="inertia-bench-")
    os.makedirs(folder, exist_ok=True)
    try:
        t0 = time.perf_counter()
        paths = make_dataset(folder, args.small, args.large)
        n = len(paths)
        print(f"{args.small} small (1,280 / 5,120 faces) + {args.large} large (81,920 faces) meshes "
              f"generated in {time.perf_counter() - t0:.1f} s; {os.cpu_count()} cores")
        base = trimesh_loop(paths)
        print(f"plain trimesh loop, 1 process : {n / base:8.1f} files/s ({base:.1f} s)")
        results = {}
        for w in (1, 2):
            el, peaks = ours(paths, w, folder)
            results[w] = el
            print(f"inertia batch, {w} worker(s)  : {n / el:8.1f} files/s ({el:.1f} s), "
                  f"peak RSS per worker {', '.join(f'{p:.0f}' for p in peaks)} MB")
        print(f"speed-up 1 -> 2 workers: {results[1] / results[2]:.2f}x; "
              f"2 workers vs trimesh loop: {base / results[2]:.2f}x files/s")
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
