"""Benchmark: files per second of `inertia batch` with 1 and 2 workers, against a plain loop.

Generates N small binary STL meshes (rippled, stretched tori of 1,000 to 10,000 faces,
uniformly spread) and M large ones (perturbed icospheres of 81,920 faces) in a temporary
folder, then in one run measures:

* a plain Python loop over trimesh (``trimesh.load`` + ``mass_properties``), one process;
* ``run_batch`` on a local Dask cluster (``--scheduler cluster``) with 1 worker, then 2, each
  cluster alone on the machine, started and warmed up outside the timing (its start-up
  time is printed apart: it is paid once per run, whatever the number of files);

and prints files/s, the speed-up from 1 to 2 workers, the ratio to the trimesh loop, and the
peak resident memory of each worker.  Our rows include the full defect checks (edges,
winding, orientation) that the trimesh loop does not do.  The three are run in interleaved
rounds (machine noise drifts over time); best and median of the rounds are printed.

    python bench/batch.py [--small 2000] [--large 20] [--faces 1000 10000] [--repeat 5] [--keep DIR]

``--whole N [N ...]`` (default 500 2000) times whole processes instead, as a user meets them:
``inertia batch FOLDER -o out.parquet`` from its interpreter's start to its exit (imports,
the placement it chooses, worker start-up, the work, the output), with the default
placement (threads), ``--scheduler synchronous`` and ``--scheduler cluster``, and with
``--external`` on Dask clusters started apart as a user's (``dask scheduler`` and ``dask
worker`` processes: 2 workers of 1 thread, 1 worker of 2 threads, each started and warmed up
for its own timed run and closed after it, outside the timing: an idle cluster's heartbeats
would load the machine under the other rows), against a script that loops trimesh over the same N meshes, also timed
from its start; interleaved rounds.

    python bench/batch.py --whole 500 2000 [--external] [--faces 1000 10000] [--repeat 3] [--keep DIR]
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import shutil
import statistics
import struct
import tempfile
import time

import numpy as np
from startup import ensure_bytecode


def write_binary_stl(path, vertices, faces) -> None:
    tri = vertices[faces].astype("<f4")
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]).astype("<f4")
    rec = np.zeros(len(faces), dtype=[("n", "<f4", 3), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["n"], rec["v"] = n, tri
    with open(path, "wb") as fh:
        fh.write(b"inertia bench".ljust(80, b" "))
        fh.write(struct.pack("<I", len(faces)))
        fh.write(rec.tobytes())


def small_mesh(rng, faces: int):
    """A closed, outward-wound torus of about ``faces`` faces, stretched and rippled at random."""
    import trimesh

    minor = int(rng.integers(12, 33))
    major = max(3, round(faces / (2 * minor)))
    t = trimesh.creation.torus(major_radius=1.0, minor_radius=rng.uniform(0.2, 0.5),
                               major_sections=major, minor_sections=minor)
    v = t.vertices.copy()
    # ripple the tube radius around the ring (the surface stays closed, embedded, outward wound)
    ring = np.hypot(v[:, 0], v[:, 1])
    centre = v.copy()
    centre[:, :2] *= (1.0 / ring)[:, None]
    centre[:, 2] = 0.0
    ripple = 1.0 + 0.1 * np.sin(int(rng.integers(1, 6)) * np.arctan2(v[:, 1], v[:, 0]))
    v = centre + (v - centre) * ripple[:, None]
    return v * rng.uniform(0.5, 2.0, 3), t.faces


def make_dataset(folder, n_small: int, n_large: int, faces=(1000, 10000), seed: int = 0) -> list[str]:
    """``n_small`` meshes of ``faces`` faces (uniform in the range) and ``n_large`` of 81,920, as binary STL."""
    import trimesh

    rng = np.random.default_rng(seed)
    sphere = trimesh.creation.icosphere(subdivisions=6)
    paths = []
    for i in range(n_small):
        v, f = small_mesh(rng, int(rng.integers(faces[0], faces[1] + 1)))
        paths.append(os.path.join(folder, f"small_{i:05d}.stl"))
        write_binary_stl(paths[-1], v, f)
    for i in range(n_large):
        # star-shaped radial perturbation keeps the sphere closed and outward wound
        s = sphere.vertices
        r = 1.0 + 0.2 * rng.random() * np.sin(rng.integers(1, 5) * s[:, :1] * 3)
        paths.append(os.path.join(folder, f"large_{i:05d}.stl"))
        write_binary_stl(paths[-1], s * r * rng.uniform(0.5, 2.0, 3), sphere.faces)
    return paths


def _warm() -> None:
    """Import what a row needs (on a worker, before the timing)."""
    import inertia.batch.record  # noqa: F401
    import inertia.geometry.mesh_io  # noqa: F401
    import inertia.massprops.mesh  # noqa: F401


def trimesh_loop(paths) -> float:
    import trimesh

    t0 = time.perf_counter()
    for p in paths:
        m = trimesh.load(p)
        m.mass_properties  # noqa: B018 - computed on access
    return time.perf_counter() - t0


class Cluster:
    """The cluster run_batch starts by default, started and warmed up outside the timing."""

    def __init__(self, workers: int):
        import distributed

        from inertia.batch.run import local_cluster

        t0 = time.perf_counter()
        self.workers = workers
        self.cluster = local_cluster(workers, 1)
        self.client = distributed.Client(self.cluster)
        self.client.run(_warm)  # imports loaded outside the timing
        self.startup_s = time.perf_counter() - t0

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
            # VmHWM: the high-water mark of this process image (ru_maxrss would carry over
            # the parent's from before the exec that started the worker)
            try:
                with open("/proc/self/status") as fh:
                    return next(int(ln.split()[1]) for ln in fh if ln.startswith("VmHWM:")) / 1024
            except (OSError, StopIteration):
                import resource

                return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024

        return list(self.client.run(peak).values())

    def close(self) -> None:
        self.client.close()
        self.cluster.close()


def timed_run(workers: int, paths, out_dir: str) -> tuple[float, float, list[float]]:
    """One run on a fresh cluster alone on the machine: seconds, start-up seconds, peak MB per worker."""
    cluster = Cluster(workers)
    try:
        return cluster.run(paths, out_dir), cluster.startup_s, cluster.peak_rss_mb()
    finally:
        cluster.close()


_TRIMESH_LOOP = """
import sys
import trimesh
for p in open(sys.argv[1]).read().split("\\n"):
    trimesh.load(p).mass_properties
"""


def whole_process(cmd) -> float:
    """Seconds of a command, from the start of its interpreter to its exit."""
    import subprocess
    import sys

    t0 = time.perf_counter()
    subprocess.run([sys.executable, *cmd], check=True, capture_output=True)
    return time.perf_counter() - t0


def whole_process_case(folder, n_small: int, faces, repeat: int, variants) -> None:
    """Whole-process times of `inertia batch` (start-up, placement, work, output) against a
    plain trimesh loop in its own interpreter, on ``n_small`` meshes: interleaved rounds."""
    import sys

    sub = os.path.join(folder, f"whole_{n_small}")
    if not os.path.isdir(sub):
        os.makedirs(sub)
        make_dataset(sub, n_small, 0, faces, seed=n_small)
    paths = sorted(os.path.join(sub, f) for f in os.listdir(sub) if f.endswith(".stl"))
    listing = os.path.join(folder, f"list_{n_small}.txt")
    with open(listing, "w") as fh:
        fh.write("\n".join(paths))
    out = os.path.join(folder, f"whole_{n_small}.parquet")
    runs = {"trimesh loop": ["-c", _TRIMESH_LOOP, listing]}
    for name, extra in variants.items():
        runs[name] = ["-m", "inertia.cli.main", "batch", sub, "-o", out, "--force", "--no-progress",
                      *(extra if isinstance(extra, list) else [])]
    times = {name: [] for name in runs}
    ensure_bytecode("inertia", "trimesh")        # as installed packages have it (see bench/startup.py)
    for _ in range(repeat):
        for name, cmd in runs.items():
            spec = variants.get(name)
            if isinstance(spec, ExternalSpec):   # started for its own run only: idle, its processes load the machine
                cluster = ExternalCluster(spec.workers, spec.threads)
                try:
                    times[name].append(whole_process([*cmd, "--scheduler", cluster.address]))
                finally:
                    cluster.close()
            else:
                times[name].append(whole_process(cmd))
    summary = subprocess_summary(runs[next(iter(variants))])
    print(f"{n_small} meshes of {faces[0]}-{faces[1]} faces, whole process, {repeat} interleaved rounds "
          f"({summary})")
    base = times["trimesh loop"]
    for name, ts in times.items():
        print(f"  {name:28s} best {min(ts):6.2f} s, median {statistics.median(ts):6.2f} s: "
              f"{min(base) / min(ts):5.1f}x / {statistics.median(base) / statistics.median(ts):5.1f}x the loop")
    sys.stdout.flush()


@dataclasses.dataclass(frozen=True)
class ExternalSpec:
    """A Dask cluster started apart for one timed run: ``workers`` of ``threads`` threads."""
    workers: int
    threads: int


class ExternalCluster:
    """A Dask cluster as a user starts one: ``dask scheduler`` and ``dask worker`` processes
    of their own (``workers`` of ``threads`` threads each), on the loopback."""

    def __init__(self, workers: int, threads: int):
        import socket
        import subprocess
        import sys

        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        self.address = f"tcp://127.0.0.1:{port}"
        dask = [sys.executable, "-m", "distributed.cli.dask_scheduler"]
        quiet = dict(stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.procs = [subprocess.Popen(dask + ["--host", "127.0.0.1", "--port", str(port),
                                               "--dashboard-address", ":0"], **quiet)]
        time.sleep(2.0)
        for _ in range(workers):
            self.procs.append(subprocess.Popen([sys.executable, "-m", "distributed.cli.dask_worker", self.address,
                                                "--nthreads", str(threads), "--no-dashboard"], **quiet))
        import distributed

        with distributed.Client(self.address, timeout="60s") as client:
            client.wait_for_workers(workers, timeout=60)
            client.run(_warm)

    def close(self) -> None:
        for proc in reversed(self.procs):
            proc.terminate()
        for proc in self.procs:
            proc.wait(timeout=30)


def subprocess_summary(cmd) -> str:
    """The placement line of a run's summary (what `inertia batch` chose)."""
    import subprocess
    import sys

    err = subprocess.run([sys.executable, *cmd], check=True, capture_output=True, text=True).stderr
    lines = [ln.strip() for ln in err.splitlines() if ln.strip().startswith("ran ")]
    return lines[0] if lines else "no placement line"


def main() -> None:
    import logging

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--small", type=int, default=2000)
    ap.add_argument("--large", type=int, default=20)
    ap.add_argument("--faces", type=int, nargs=2, default=(1000, 10000), metavar=("LO", "HI"),
                    help="face count range of the small meshes (default 1000 10000)")
    ap.add_argument("--repeat", type=int, default=5, help="rounds; each round runs all three, interleaved")
    ap.add_argument("--keep", metavar="DIR", help="generate into DIR and keep it")
    ap.add_argument("--whole", type=int, nargs="*", metavar="N",
                    help="instead: whole-process times of `inertia batch` against a trimesh loop script on N small "
                         "meshes each (default 500 2000), the default placement and the forced ones")
    ap.add_argument("--external", action="store_true",
                    help="with --whole: also against Dask clusters started apart (dask scheduler + dask worker "
                         "processes: 2 workers of 1 thread, 1 worker of 2 threads), as a user's cluster")
    args = ap.parse_args()
    if args.whole is not None:
        folder = args.keep or tempfile.mkdtemp(prefix="inertia-bench-")
        variants = {"inertia batch (threads)": [], "--self-crossing certificate": ["--self-crossing", "certificate"],
                    "--scheduler synchronous": ["--scheduler", "synchronous"],
                    "--scheduler cluster": ["--scheduler", "cluster"]}
        if args.external:
            for w, t in ((2, 1), (1, 2)):
                variants[f"external cluster, {w}x{t} threads"] = ExternalSpec(w, t)
        try:
            for n in args.whole or [500, 2000]:
                whole_process_case(folder, n, tuple(args.faces), args.repeat, variants)
        finally:
            if not args.keep:
                shutil.rmtree(folder, ignore_errors=True)
        return
    logging.getLogger("distributed").setLevel(logging.ERROR)  # no INFO lines at cluster close
    folder = args.keep or tempfile.mkdtemp(prefix="inertia-bench-")
    os.makedirs(folder, exist_ok=True)
    try:
        t0 = time.perf_counter()
        paths = make_dataset(folder, args.small, args.large, tuple(args.faces))
        n = len(paths)
        print(f"{args.small} small ({args.faces[0]}-{args.faces[1]} faces) + {args.large} large (81,920 faces) meshes "
              f"generated in {time.perf_counter() - t0:.1f} s; {os.cpu_count()} cores; "
              f"{args.repeat} interleaved rounds (machine noise: compare the best and the median)")
        times = {"trimesh": [], 1: [], 2: []}
        startup: dict[int, list[float]] = {1: [], 2: []}
        peaks: dict[int, list[float]] = {1: [], 2: []}
        for _ in range(args.repeat):
            times["trimesh"].append(trimesh_loop(paths))
            for w in (1, 2):
                seconds, start_s, peak = timed_run(w, paths, folder)
                times[w].append(seconds)
                startup[w].append(start_s)
                peaks[w] = [max(a, b) for a, b in zip(peaks[w], peak)] if peaks[w] else peak

        def line(label, ts):
            return (f"{label}: best {n / min(ts):7.1f} files/s ({min(ts):.2f} s), "
                    f"median {n / statistics.median(ts):7.1f} files/s")

        print(line("plain trimesh loop, 1 process", times["trimesh"]))
        for w in (1, 2):
            print(line(f"inertia batch, {w} worker(s) ", times[w])
                  + f"; peak RSS per worker {', '.join(f'{p:.0f}' for p in peaks[w])} MB; "
                  f"cluster start {statistics.median(startup[w]):.1f} s (not timed)")
        for how, f in (("best", min), ("median", statistics.median)):
            print(f"{how:6s}: speed-up 1 -> 2 workers {f(times[1]) / f(times[2]):.2f}x; "
                  f"2 workers vs trimesh loop {f(times['trimesh']) / f(times[2]):.2f}x files/s")
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
