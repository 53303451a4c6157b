"""Fuzz inertia's file readers with mutated seed files and count outcomes.

    python bench/fuzz.py [--n 100000] [--seed 0] [--kinds mesh,robot]

Every input is written to a temporary file and read in a worker process, as a user's
call would: meshes through ``inertia.mesh_file_properties``, robot files through
``inertia.robots.read_robot`` + ``check_model``.  Outcomes: ``ok`` (finite numbers),
``refused`` (one of our errors, InertiaError), ``internal`` (any other exception: a bug),
``crash`` (the worker died: a bug), ``nonfinite`` (a returned number is NaN/inf: a silent
wrong number), plus ``leaked_warnings`` (NumPy RuntimeWarnings that reached the caller).
Prints the counts and the first examples of each bug class; exit 1 if any bug was found.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from tests.fuzzing import MESH_SEEDS, ROBOT_SEEDS, mutate_any, seed_stl_binary  # noqa: E402

WORKER = r'''
import json, sys, warnings
import numpy as np
from inertia.errors import InertiaError
def run(path):
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            if path.endswith((".urdf", ".xml", ".sdf")):
                from inertia.robots import read_robot, check_model
                model = read_robot(path)
                rep = check_model(model)
                vals = []
                for link in getattr(model, "links", []):
                    inl = getattr(link, "inertial", None)
                    if inl is not None:
                        vals += [getattr(inl, "mass", 0.0)]
                out = "ok"
            else:
                import inertia
                p = inertia.mesh_file_properties(path, density=1.0)
                vals = [p.mass, *np.ravel(p.com), *np.ravel(p.inertia_com)]
                out = "ok"
            if not all(np.isfinite(np.asarray(vals, dtype=float))):
                out = "nonfinite"
            msg = ""
        except InertiaError as e:
            out, msg = "refused", f"{type(e).__name__}: {e}"[:300]
        except Exception as e:
            import traceback
            out, msg = "internal", traceback.format_exc()[-600:]
        leaked = [str(x.message)[:120] for x in w if issubclass(x.category, RuntimeWarning)]
    return out, msg, leaked
for line in sys.stdin:
    path = line.strip()
    if not path:
        continue
    out, msg, leaked = run(path)
    sys.stdout.write(json.dumps([path, out, msg, leaked]) + "\n")
    sys.stdout.flush()
'''


def make_inputs(n: int, seed: int, kinds, folder: Path):
    rng = random.Random(seed)
    seeds = []
    if "mesh" in kinds:
        seeds += [(ext, f()) for ext, f in MESH_SEEDS.items()] + [(".stl", seed_stl_binary())]
    if "robot" in kinds:
        seeds += list(ROBOT_SEEDS.items())
    paths = []
    for i in range(n):
        ext, data = seeds[i % len(seeds)]
        p = folder / f"in{i:06d}{ext}"
        p.write_bytes(mutate_any(data, rng))
        paths.append(p)
    return paths


def run_all(paths, chunk=2000, timeout=60.0):
    results = {}
    todo = [str(p) for p in paths]
    env = dict(os.environ, PYTHONWARNINGS="ignore")
    while todo:
        batch, todo = todo[:chunk], todo[chunk:]
        proc = subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True, env=env)
        try:
            out, _ = proc.communicate("\n".join(batch) + "\n", timeout=timeout + 0.05 * len(batch))
        except subprocess.TimeoutExpired:
            proc.kill()
            out, _ = proc.communicate()
        done = [json.loads(x) for x in out.splitlines() if x.strip()]
        for path, o, msg, leaked in done:
            results[path] = (o, msg, leaked)
        if len(done) < len(batch):  # the worker died (or hung) on batch[len(done)]
            bad = batch[len(done)]
            results[bad] = ("crash", f"worker exit {proc.returncode}", [])
            todo = batch[len(done) + 1:] + todo
    return results


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--kinds", default="mesh,robot")
    ap.add_argument("--keep", help="copy the inputs of each bug here")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        paths = make_inputs(a.n, a.seed, a.kinds.split(","), Path(d))
        res = run_all(paths)
        counts, examples, leak_kinds = {}, {}, {}
        leaks = 0
        for path, (o, msg, leaked) in res.items():
            counts[o] = counts.get(o, 0) + 1
            leaks += bool(leaked)
            for text in leaked:
                leak_kinds.setdefault(text, Path(path).name)
            if o in ("internal", "crash", "nonfinite") and len(examples.setdefault(o, [])) < 5:
                examples[o].append((Path(path).name, Path(path).read_bytes()[:200], msg))
                if a.keep:
                    Path(a.keep).mkdir(parents=True, exist_ok=True)
                    Path(a.keep, Path(path).name).write_bytes(Path(path).read_bytes())
    dt = time.perf_counter() - t0
    print(f"inputs {len(res)} in {dt:.0f} s: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + f"; leaked RuntimeWarnings in {leaks}")
    for text, name in sorted(leak_kinds.items()):
        print(f"leaked: {text!r} (e.g. {name})")
    for kind, ex in examples.items():
        print(f"--- {kind}")
        for name, head, msg in ex:
            print(f"{name}: {head!r}\n    {msg.strip().splitlines()[-1] if msg.strip() else ''}")
    bugs = sum(counts.get(k, 0) for k in ("internal", "crash", "nonfinite"))
    return 1 if bugs else 0


if __name__ == "__main__":
    sys.exit(main())
