"""Benchmark: files per second of `inertia batch` with 1 and 2 workers, against a plain loop.

Generates N small binary STL meshes (perturbed icospheres, 1,280 to 5,120 faces... up to
~10k with --small-faces) and M large ones (81,920 faces) in a temporary folder, then in one
run measures:

* a plain Python loop over trimesh (``trimesh.load`` + ``mass_properties``), one process;
* ``run_batch`` on a local Dask cluster with 1 worker, then with 2 workers;

and prints files/s, the speed-up from 1 to 2 workers, the ratio to the trimesh loop, and the
peak resident memory of each worker.  Our rows include the full defect checks (edges,
winding, orientation) that the trimesh loop does not do.  The three are run in interleaved
rounds (machine noise drifts over time); best and median of the rounds are printed.

    python bench/batch.py [--small 2000] [--large 20] [--repeat 3] [--keep DIR]
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
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


class Cluster:
    """The cluster run_batch starts by default, kept up across repeats (started outside the timing)."""

    def __init__(self, workers: int):
        import distributed

        from inertia.batch.record import warm_up
        from inertia.batch.run import local_cluster

        self.workers = workers
        self.cluster = local_cluster(workers)
        self.client = distributed.Client(self.cluster)
        self.client.run(warm_up)  # imports and compiled kernels loaded outside the timing

    def run(self, paths, out_dir: str) -> float:
        from inertia.batch import run_batch

        out = os.path.join(out_dir, f"bench-{self.workers}.parquet")
        t0 = time.perf_counter()
        summary = run_batch(paths, out, scheduler=self.client, progress=False, overwrite=True)
        elapsed = time.perf_counter() - t0
        assert summary.errors == 0, summary.lines()
        return elapsed

    def peak_rss_mb(self) -> list[float]:
        def peak():
            import resource

            return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

        return list(self.client.run(peak).values())

    def close(self) -> None:
        self.client.close()
        self.cluster.close()


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--small", type=int, default=2000)
    ap.add_argument("--large", type=int, default=20)
    ap.add_argument("--repeat", type=int, default=3, help="rounds; each round runs all three, interleaved")
    ap.add_argument("--keep", metavar="DIR", help="generate into DIR and keep it")
    args = ap.parse_args()
    folder = args.keep or tempfile.mkdtemp(prefix="inertia-bench-")
    os.makedirs(folder, exist_ok=True)
    clusters = {}
    try:
        t0 = time.perf_counter()
        paths = make_dataset(folder, args.small, args.large)
        n = len(paths)
        print(f"{args.small} small (1,280 / 5,120 faces) + {args.large} large (81,920 faces) meshes "
              f"generated in {time.perf_counter() - t0:.1f} s; {os.cpu_count()} cores; "
              f"{args.repeat} interleaved rounds (machine noise: compare the best and the median)")
        clusters = {w: Cluster(w) for w in (1, 2)}
        times = {"trimesh": [], 1: [], 2: []}
        for _ in range(args.repeat):
            times["trimesh"].append(trimesh_loop(paths))
            for w, c in clusters.items():
                times[w].append(c.run(paths, folder))

        def line(label, ts):
            return (f"{label}: best {n / min(ts):7.1f} files/s ({min(ts):.2f} s), "
                    f"median {n / statistics.median(ts):7.1f} files/s")

        print(line("plain trimesh loop, 1 process", times["trimesh"]))
        for w, c in clusters.items():
            print(line(f"inertia batch, {w} worker(s) ", times[w])
                  + f"; peak RSS per worker {', '.join(f'{p:.0f}' for p in c.peak_rss_mb())} MB")
        for how, f in (("best", min), ("median", statistics.median)):
            print(f"{how:6s}: speed-up 1 -> 2 workers {f(times[1]) / f(times[2]):.2f}x; "
                  f"2 workers vs trimesh loop {f(times['trimesh']) / f(times[2]):.2f}x files/s")
    finally:
        for c in clusters.values():
            c.close()
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
