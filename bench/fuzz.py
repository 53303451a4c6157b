"""Fuzz inertia's readers and writers: mutated files, special paths, failing outputs; count outcomes.

    python bench/fuzz.py [--n 100000] [--seed 0] [--kinds mesh,robot] [--no-special] [--no-outputs]

* Mutated files: each is written to a temporary file and read in a worker process, as a user's
  call would: meshes through ``inertia.mesh_file_properties``, robot files through
  ``inertia.robots.read_robot`` + ``check_model``.
* Special paths: every reader family of ``tests/special_paths.py`` given every kind of path that
  is not a regular file (FIFO, device, socket, folder, symlink loop, dangling link, vanished,
  growing), under a 30 s alarm.
* Output faults: CLI commands whose stdout is a full device (/dev/full), a file under a size
  limit, or a pipe whose reader is gone, and whose output files (``fix -o``, ``batch -o``) meet
  the size limit; compared with the same command's whole output.

Outcomes: ``ok``, ``refused`` (one of our errors, named), and the bugs: ``internal`` (another
exception, exit 3, a traceback), ``crash`` (the worker died), ``hang``, ``nonfinite`` (NaN/inf
returned), ``unnamed`` (a refusal that does not name the path and its kind), ``silent`` (a cut
output with exit 0); plus ``leaked_warnings`` (NumPy RuntimeWarnings that reached the caller).
Prints the counts, the time and the first examples of each bug class; exit 1 if any bug was found.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from tests.fuzzing import MESH_SEEDS, ROBOT_SEEDS, mutate_any, seed_ply_binary, seed_stl_binary  # noqa: E402

BUGS = ("internal", "crash", "hang", "nonfinite", "unnamed", "silent")

WORKER = r'''
import json, os, re, signal, sys, tempfile, time, warnings
from pathlib import Path
import numpy as np
from inertia.errors import InertiaError

def hung(*_):
    raise TimeoutError("hang")

def read_file(path):
    if path.endswith((".urdf", ".xml", ".sdf")):
        from inertia.robots import read_robot, check_model
        model = read_robot(path)
        check_model(model)
        return [getattr(link.inertial, "mass", 0.0) for link in model.links if link.inertial is not None]
    import inertia
    p = inertia.mesh_file_properties(path, density=1.0)
    return [p.mass, *np.ravel(p.com), *np.ravel(p.inertia_com)]

def read_special(family, kind):
    from tests.special_paths import EXPECTED, FAMILIES, KINDS, make_special
    name, setup, read = FAMILIES[family]
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        if setup is not None:
            setup(d)
        keep = make_special(kind, d / name)
        try:
            expected = EXPECTED.get((family, kind), KINDS[kind])
            if expected is None:
                return "ok", ""
            message = read(d)
        finally:
            if keep is not None:
                keep.close()
    named = re.search(expected, message) and Path(name).name in message
    return ("refused" if named else "unnamed"), message[:300]

def run(line):
    t0 = time.perf_counter()
    out, msg, leaked = answer(line)
    return out, msg, leaked, time.perf_counter() - t0

def answer(line):
    signal.signal(signal.SIGALRM, hung)
    signal.alarm(30)
    with warnings.catch_warnings(record=True) as w:
        warnings.simplefilter("always")
        try:
            if line.startswith("special\t"):
                out, msg = read_special(*line.split("\t")[1:])
            else:
                vals = read_file(line)
                out = "ok" if all(np.isfinite(np.asarray(vals, dtype=float))) else "nonfinite"
                msg = ""
        except InertiaError as e:
            out, msg = "refused", f"{type(e).__name__}: {e}"[:300]
        except TimeoutError:
            out, msg = "hang", "no answer in 30 s"
        except Exception:
            import traceback
            out, msg = "internal", traceback.format_exc()[-600:]
        finally:
            signal.alarm(0)
        leaked = [str(x.message)[:120] for x in w if issubclass(x.category, RuntimeWarning)]
    return out, msg, leaked

for line in sys.stdin:
    line = line.rstrip("\n")
    if line:
        sys.stdout.write(json.dumps([line, *run(line)]) + "\n")
        sys.stdout.flush()
'''


def make_inputs(n: int, seed: int, kinds, folder: Path):
    rng = random.Random(seed)
    seeds = []
    if "mesh" in kinds:
        seeds += [(ext, f()) for ext, f in MESH_SEEDS.items()] + [(".stl", seed_stl_binary()),
                                                                   (".ply", seed_ply_binary())]
    if "robot" in kinds:
        seeds += list(ROBOT_SEEDS.items())
    paths = []
    for i in range(n):
        ext, data = seeds[i % len(seeds)]
        p = folder / f"in{i:06d}{ext}"
        p.write_bytes(mutate_any(data, rng))
        paths.append(str(p))
    return paths


def special_inputs():
    from tests.special_paths import FAMILIES, KINDS

    return [f"special\t{family}\t{kind}" for family in FAMILIES for kind in KINDS
            if not (kind == "unreadable" and os.geteuid() == 0)]   # root reads every file


def run_all(lines, chunk=2000):
    """Each line through a worker process (a new one after a crash or a hang)."""
    results = {}
    todo = list(lines)
    env = dict(os.environ, PYTHONWARNINGS="ignore", PYTHONPATH=str(ROOT))
    while todo:
        batch, todo = todo[:chunk], todo[chunk:]
        proc = subprocess.Popen([sys.executable, "-c", WORKER], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True, env=env, cwd=tempfile.gettempdir())
        try:
            out, _ = proc.communicate("\n".join(batch) + "\n", timeout=120 + 0.5 * len(batch))
            why = f"worker exit {proc.returncode}"
        except subprocess.TimeoutExpired:
            proc.kill()
            out, _ = proc.communicate()
            why = "the worker hung"
        done = [json.loads(x) for x in out.splitlines() if x.strip()]
        for line, o, msg, leaked, seconds in done:
            results[line] = (o, msg, leaked, seconds)
        if len(done) < len(batch):  # the worker died (or hung) on batch[len(done)]
            results[batch[len(done)]] = ("crash" if why.startswith("worker") else "hang", why, [], None)
            todo = batch[len(done) + 1:] + todo
    return results


# ------------------------------------------------------------------------------ output faults
URDF = ('<robot name="r"><link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="2" izz="2.5" ixy="0" '
        'ixz="0" iyz="0"/></inertial></link>' + "<!-- padding -->" * 300 + '</robot>\n')


def _commands(d: Path):
    """(name, argv, output file or None): commands whose output is stdout, or a file they write."""
    (d / "m.stl").write_bytes(seed_stl_binary())
    (d / "r.urdf").write_text(URDF)
    (d / "meshes").mkdir()
    for k in range(20):
        (d / "meshes" / f"m{k}.stl").write_bytes(seed_stl_binary())
    out = [("props text", ["props", "m.stl"], None), ("props json", ["props", "m.stl", "--format", "json"], None),
           ("props robot", ["props", "r.urdf"], None), ("check", ["check", "r.urdf"], None),
           ("check json", ["check", "r.urdf", "--format", "json"], None),
           ("simulate", ["simulate", "box:0.1,0.2,0.3", "--mass", "1", "--omega", "0,5,0.1", "--times", "0,1,2"],
            None), ("lagrangian", ["lagrangian", "--format", "python"], None),
           ("particles", ["particles", "m.stl"], None),
           ("fix -o", ["fix", "r.urdf", "-o", "fixed.urdf"], "fixed.urdf")]
    out += [(f"batch -o {ext}", ["batch", "meshes", "-o", f"out.{ext}", "--no-progress", "--force"], f"out.{ext}")
            for ext in ("jsonl", "csv", "parquet")]
    return out


def _cli(argv, d, *, stdout, fsize=None):
    def limit():
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    return subprocess.run([sys.executable, "-c", "from inertia.cli.main import entry; entry()", *argv],
                          stdout=stdout, stderr=subprocess.PIPE, cwd=d, preexec_fn=limit, timeout=300)


def output_faults():
    """``{case: (outcome, message)}`` for every command under every output fault."""
    results = {}
    with tempfile.TemporaryDirectory() as d:
        d = Path(d)
        for name, argv, file in _commands(d):
            whole = _cli(argv, d, stdout=subprocess.PIPE)
            expected = (d / file).read_bytes() if file else whole.stdout
            if file:
                (d / file).unlink()
            if whole.returncode not in (0, 1):
                results[f"{name} (no fault)"] = ("internal", whole.stderr.decode()[-300:])
                continue
            faults = [("full", None)] if os.path.exists("/dev/full") and not file else []
            faults += [(f"fsize {n}", n) for n in (0, 1, 100, 1000, 4096)]
            faults += [] if file else [("closed pipe", None)]
            for fault, fsize in faults:
                case = f"{name}: {fault}"
                try:
                    results[case] = _one_fault(argv, d, fault, fsize, file, expected)
                except subprocess.TimeoutExpired:
                    results[case] = ("hang", "no end in 300 s")
                if file and (d / file).exists():
                    (d / file).unlink()
    return results


def _one_fault(argv, d, fault, fsize, file, expected):
    if fault == "full":
        with open("/dev/full", "wb") as full:
            r = _cli(argv, d, stdout=full)
        got = None
    elif fault == "closed pipe":
        read, write = os.pipe()
        os.close(read)                     # the reader is gone before the first write
        try:
            r = _cli(argv, d, stdout=write)
        finally:
            os.close(write)
        got = None
    else:
        with open(d / "stdout.txt", "wb") as fh:
            r = _cli(argv, d, stdout=subprocess.DEVNULL if file else fh, fsize=fsize)
        got = (d / file).read_bytes() if file and (d / file).exists() else (d / "stdout.txt").read_bytes()
    err = r.stderr.decode(errors="replace")
    if r.returncode == 3 or "Traceback" in err or "internal error" in err:
        return "internal", err[-300:]
    if fault == "closed pipe":
        return ("refused" if r.returncode == 0 and not err else "unnamed"), err[-300:]
    if r.returncode == 0:
        return ("ok" if got == expected else "silent"), f"exit 0 with {len(got or b'')} of {len(expected)} bytes"
    return ("refused" if "cannot write the output" in err else "unnamed"), err[-300:]


def print_table(res) -> None:
    """Special paths: reader family x path kind -> outcome (named: a refusal naming the path and the
    kind; format: the path means something else in that format, see tests/special_paths.EXPECTED)."""
    from tests.special_paths import FAMILIES, KINDS

    kinds = [k for k in KINDS if any(f"special\t{f}\t{k}" in res for f in FAMILIES)]
    print(f"\n{'family':22s} " + " ".join(f"{k:>10s}" for k in kinds))
    slowest = 0.0
    for family in FAMILIES:
        cells = []
        for kind in kinds:
            o, _, _, seconds = res[f"special\t{family}\t{kind}"]
            slowest = max(slowest, seconds or 0.0)
            cells.append({"refused": "named", "ok": "format"}.get(o, o.upper()))
        print(f"{family:22s} " + " ".join(f"{c:>10s}" for c in cells))
    print(f"slowest answer {slowest:.2f} s")


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000, help="mutated files")
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--kinds", default="mesh,robot")
    ap.add_argument("--no-special", action="store_true")
    ap.add_argument("--no-outputs", action="store_true")
    ap.add_argument("--keep", help="copy the inputs of each bug here")
    a = ap.parse_args(argv)
    t0 = time.perf_counter()
    with tempfile.TemporaryDirectory() as d:
        lines = make_inputs(a.n, a.seed, a.kinds.split(","), Path(d)) + ([] if a.no_special else special_inputs())
        res = run_all(lines)
        t1 = time.perf_counter()
        outputs = {} if a.no_outputs else output_faults()
        counts, examples, leak_kinds, leaks = {}, {}, {}, 0
        for line, (o, msg, leaked, _) in res.items():
            counts[o] = counts.get(o, 0) + 1
            leaks += bool(leaked)
            for text in leaked:
                leak_kinds.setdefault(text, Path(line).name)
            if o in BUGS and len(examples.setdefault(o, [])) < 5:
                special = line.startswith("special\t")
                head = b"" if special else Path(line).read_bytes()[:200]
                examples[o].append((line.replace("\t", " ") if special else Path(line).name, head, msg))
                if a.keep and not special:
                    Path(a.keep).mkdir(parents=True, exist_ok=True)
                    Path(a.keep, Path(line).name).write_bytes(Path(line).read_bytes())
    out_counts = {}
    for case, (o, msg) in outputs.items():
        out_counts[o] = out_counts.get(o, 0) + 1
        if o in BUGS and len(examples.setdefault(o, [])) < 5:
            examples[o].append((case, b"", msg))
    t2 = time.perf_counter()
    n_special = sum(1 for line in res if line.startswith("special\t"))
    print(f"inputs {len(res) + len(outputs)} in {t2 - t0:.0f} s: {len(res) - n_special} mutated files and "
          f"{n_special} special paths in {t1 - t0:.0f} s, {len(outputs)} output faults in {t2 - t1:.0f} s")
    print("files and paths: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))
          + f"; leaked RuntimeWarnings in {leaks}")
    if outputs:
        print("output faults: " + ", ".join(f"{k} {v}" for k, v in sorted(out_counts.items())))
    for text, name in sorted(leak_kinds.items()):
        print(f"leaked: {text!r} (e.g. {name})")
    for kind, ex in examples.items():
        print(f"--- {kind}")
        for name, head, msg in ex:
            print(f"{name}: {head!r}\n    {msg.strip().splitlines()[-1] if msg.strip() else ''}")
    if n_special:
        print_table(res)
    bugs = sum(counts.get(k, 0) + out_counts.get(k, 0) for k in BUGS)
    return 1 if bugs else 0


if __name__ == "__main__":
    sys.exit(main())
