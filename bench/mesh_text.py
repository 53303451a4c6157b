"""Benchmark: reading text meshes (ASCII STL, OBJ) with their mass properties, against trimesh.

Writes a closed, star-shaped perturbed icosphere (subdivision 8: 1,310,720 faces by default)
as ASCII STL (``%.6e`` coordinates, as CAD exporters write float32 values) and as OBJ
(``%.6f``, as Blender writes), then measures in one process, in interleaved rounds:

* ours: ``inertia.mesh_file_properties(path, density=1.0)`` (the whole public call: reading,
  welding, every mesh check, the integrals);
* anchor: ``trimesh.load(path)`` + ``.mass_properties`` (what a user would run instead).

Wall seconds are the figure; CPU seconds (all threads) are printed beside them, as the ratio
that holds on a machine busy with other work (a large ASCII STL is read by several threads).

Then the peak resident memory of each call, each in a fresh subprocess: its ``VmHWM`` after
the call, minus its ``VmHWM`` of the same subprocess after its imports and a warm-up call on a
small file of the same format (the interpreter, NumPy, the compiled kernels); printed with
the file size, whose double is the goal.  ``--digits 17`` writes every coordinate with 17
significant digits (``repr`` of doubles: the slow path of the number reader).

``--startup N``: instead, the whole process of ``inertia props small.stl`` (5,120 faces, binary
and ASCII STL) against trimesh's one-shot (``python -c`` loading the file and its
``mass_properties``), N runs each, interleaved; the goal is half trimesh's time or less.

    python bench/mesh_text.py [--subdivisions 8] [--repeat 3] [--formats stl obj] [--digits 7] [--keep DIR]
    python bench/mesh_text.py --startup 20
"""

from __future__ import annotations

import argparse
import os
import shutil
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np


def sphere(subdivisions: int):
    """Vertices and faces of a star-shaped perturbed icosphere (closed, outward wound)."""
    import trimesh

    s = trimesh.creation.icosphere(subdivisions=subdivisions)
    v = s.vertices
    r = 1.0 + 0.1 * np.sin(3 * v[:, :1]) * np.cos(2 * v[:, 1:2])
    return v * r * np.array([1.0, 0.7, 1.3]) + np.array([0.3, -0.2, 0.1]), np.asarray(s.faces)


def _fmt(digits: int) -> str:
    return f"%.{digits - 1}e"


def write_ascii_stl(path, v, f, digits: int = 7, chunk: int = 100_000) -> None:
    """ASCII STL as exporters write it: one facet of 7 lines per triangle."""
    x = _fmt(digits)
    facet = (f"  facet normal {x} {x} {x}\n    outer loop\n" + f"      vertex {x} {x} {x}\n" * 3
             + "    endloop\n  endfacet\n")
    with open(path, "w") as fh:
        fh.write("solid bench\n")
        for s in range(0, len(f), chunk):
            tri = v[f[s:s + chunk]]
            n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
            n /= np.linalg.norm(n, axis=1)[:, None]
            rows = np.concatenate([n, tri.reshape(-1, 9)], axis=1)
            fh.write("".join(facet % tuple(r) for r in rows.tolist()))
        fh.write("endsolid bench\n")


def write_obj(path, v, f, digits: int = 7) -> None:
    """OBJ as Blender writes it (``v`` with 6 decimals, then ``f`` lines)."""
    x = "%.6f" if digits <= 7 else _fmt(digits)
    with open(path, "w") as fh:
        fh.write("# bench\no bench\n")
        fh.write("".join(f"v {x} {x} {x}\n" % tuple(r) for r in v.tolist()))
        fh.write("".join("f %d %d %d\n" % tuple(r) for r in (f + 1).tolist()))


def ours(path) -> tuple[float, float]:
    """Wall and CPU seconds (all threads) of our public call."""
    import inertia

    t0, c0 = time.perf_counter(), time.process_time()
    inertia.mesh_file_properties(path, density=1.0)
    return time.perf_counter() - t0, time.process_time() - c0


def anchor(path) -> tuple[float, float]:
    import trimesh

    t0, c0 = time.perf_counter(), time.process_time()
    trimesh.load(path).mass_properties  # noqa: B018 - computed on access
    return time.perf_counter() - t0, time.process_time() - c0


_PEAK = """
import sys
import numpy as np
def hwm():  # VmHWM: this process image's peak (ru_maxrss keeps the parent's from before the exec)
    with open("/proc/self/status") as fh:
        return next(int(ln.split()[1]) for ln in fh if ln.startswith("VmHWM:"))
warm, path, who = sys.argv[1:4]
if who == "ours":
    import inertia
    call = lambda p: inertia.mesh_file_properties(p, density=1.0)
else:
    import trimesh
    call = lambda p: trimesh.load(p).mass_properties
call(warm)
base = hwm()
call(path)
print(base, hwm())
"""


def peak_mb(warm: str, path: str, who: str) -> tuple[float, float]:
    """(peak RSS of the call over the warmed-up process, peak RSS of the process), MB."""
    out = subprocess.run([sys.executable, "-c", _PEAK, warm, path, who], capture_output=True, text=True,
                         check=True, env=dict(os.environ))
    base, peak = (int(x) / 1024 for x in out.stdout.split())
    return peak - base, peak


_ONE_SHOT = "import sys, trimesh; trimesh.load(sys.argv[1]).mass_properties"


def startup(folder: str, runs: int) -> None:
    """Wall seconds of whole processes: ``inertia props small.stl`` against trimesh's one-shot."""
    v, f = sphere(4)
    binary = os.path.join(folder, "small.stl")
    tri = v[f].astype("<f4")
    rec = np.zeros(len(f), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = tri
    with open(binary, "wb") as fh:
        fh.write(b"bench".ljust(80) + len(f).to_bytes(4, "little") + rec.tobytes())
    ascii_ = os.path.join(folder, "small_ascii.stl")
    write_ascii_stl(ascii_, tri.astype(float).reshape(-1, 3), np.arange(3 * len(f)).reshape(-1, 3))
    from startup import ensure_bytecode  # (bench/startup.py: .pyc files as an installed package has them)

    ensure_bytecode("inertia", "trimesh")
    script = os.path.join(os.path.dirname(sys.executable), "inertia")
    ours = [sys.executable, script] if os.path.exists(script) else [sys.executable, "-m", "inertia.cli.main"]
    for path in (binary, ascii_):
        commands = {"inertia props": ours + ["props", path], "trimesh one-shot": [sys.executable, "-c", _ONE_SHOT, path]}
        times = {k: [] for k in commands}
        for cmd in commands.values():   # file cache, bytecode
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
        for _ in range(runs):
            for k, cmd in commands.items():
                t0 = time.perf_counter()
                subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
                times[k].append(time.perf_counter() - t0)
        a, b = times["inertia props"], times["trimesh one-shot"]
        print(f"{os.path.basename(path)} ({len(f):,} faces): inertia props best {min(a):.3f} s, median "
              f"{statistics.median(a):.3f} s; trimesh one-shot best {min(b):.3f} s, median {statistics.median(b):.3f} s; "
              f"ratio {min(a) / min(b):.2f} best, {statistics.median(a) / statistics.median(b):.2f} median")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--subdivisions", type=int, default=8, help="icosphere subdivisions (8: 1,310,720 faces)")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--formats", nargs="+", default=["stl", "obj"], choices=["stl", "obj"])
    ap.add_argument("--digits", type=int, default=7, help="significant digits of the coordinates (17: repr)")
    ap.add_argument("--no-memory", action="store_true", help="skip the subprocess memory runs")
    ap.add_argument("--keep", metavar="DIR", help="write the files into DIR and keep them (reused if present)")
    ap.add_argument("--startup", type=int, metavar="N", help="time whole processes on a small STL instead")
    args = ap.parse_args()
    folder = args.keep or tempfile.mkdtemp(prefix="inertia-bench-text-")
    os.makedirs(folder, exist_ok=True)
    try:
        if args.startup:
            return startup(folder, args.startup)
        v, f = sphere(args.subdivisions)
        small_v, small_f = sphere(2)
        writers = {"stl": write_ascii_stl, "obj": write_obj}
        for fmt in args.formats:
            path = os.path.join(folder, f"sphere{args.subdivisions}_{args.digits}.{fmt}")
            warm = os.path.join(folder, f"warm.{fmt}")
            t0 = time.perf_counter()
            if not os.path.exists(path):
                writers[fmt](path, v, f, args.digits)
            writers[fmt](warm, small_v, small_f, args.digits)
            size_mb = os.path.getsize(path) / 2**20
            print(f"{fmt}: {len(f):,} faces, {size_mb:.0f} MB ({args.digits} digits), "
                  f"written in {time.perf_counter() - t0:.1f} s")
            ours(warm), anchor(warm)   # imports and compiled kernels outside the timing
            times = {"ours": [], "trimesh": []}
            for _ in range(args.repeat):
                times["ours"].append(ours(path))
                times["trimesh"].append(anchor(path))
            for how, pick in (("best", min), ("median", statistics.median)):
                a, b = (pick(t[0] for t in times[k]) for k in ("ours", "trimesh"))
                ca, cb = (pick(t[1] for t in times[k]) for k in ("ours", "trimesh"))
                print(f"  {how:6s}: ours {a:.3f} s, trimesh load + mass_properties {b:.3f} s: {b / a:.1f}x "
                      f"(CPU seconds, all threads: {ca:.3f} vs {cb:.3f}: {cb / ca:.1f}x)")
            if not args.no_memory:
                for who in ("ours", "trimesh"):
                    delta, peak = peak_mb(warm, path, who)
                    print(f"  peak memory {who:7s}: +{delta:.0f} MB over the warmed-up process "
                          f"({delta / size_mb:.2f}x the file; process peak {peak:.0f} MB)")
    finally:
        if not args.keep:
            shutil.rmtree(folder, ignore_errors=True)


if __name__ == "__main__":
    main()
