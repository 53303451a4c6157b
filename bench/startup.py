"""Start-up time of ``inertia --help``, against ``python -c pass`` measured in the same run.

Usage::

    python bench/startup.py [--repeats 40] [--target-ms 100]

What it measures
----------------
* wall time of ``inertia --help`` (the installed console script, run by this interpreter;
  falls back to ``python -c "from inertia.cli.main import main; main()" --help``),
  ``inertia props --help`` and ``python -c pass``, each run ``--repeats`` times in alternation
  as separate processes; it reports min and median, and the median overhead over bare Python;
* which heavy modules (numpy, scipy, trimesh, numba, matplotlib) each ``--help`` imports, from
  ``sys.modules`` at exit in a subprocess, and the slowest imports from ``python -X importtime``.

Exit status 0 when no heavy module is imported and the minimum time of ``inertia --help`` is
below ``--target-ms``; 1 otherwise (the minimum, because load on the machine only adds time).
Times include process creation and interpreter start-up, so compare against the
``python -c pass`` line of the same run, not across machines.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HEAVY = ("numpy", "scipy", "trimesh", "numba", "matplotlib")

_PROBE = r"""
import contextlib, io, json, sys
from inertia.cli.main import main
with contextlib.redirect_stdout(io.StringIO()):
    try:
        main(sys.argv[1:])
    except SystemExit:
        pass
heavy = %r
print(json.dumps(sorted(m for m in sys.modules if m.split(".")[0] in heavy and "." not in m)))
""" % (HEAVY,)


def inertia_command() -> list[str]:
    """The console script next to this interpreter, run by this interpreter (no shell shims)."""
    bindir = Path(sys.executable).parent
    for name in ("inertia", "inertia.exe", "Scripts/inertia.exe"):
        script = bindir / name
        if script.is_file() and script.suffix != ".exe":
            return [sys.executable, str(script)]
    return [sys.executable, "-c", "import sys; from inertia.cli.main import main; sys.exit(main())"]


def ensure_bytecode(*packages: str) -> None:
    """Write the ``.pyc`` files of ``packages`` (import names) where they are missing, as an
    installed package has them (pip compiles them at install time).  Without them every
    process compiles the package's modules again (50 ms for inertia's batch command): a
    checkout run with PYTHONDONTWRITEBYTECODE=1 would time that, while the packages it is
    compared with (trimesh, numpy) were installed with their bytecode."""
    import compileall
    import importlib.util

    for name in packages:
        spec = importlib.util.find_spec(name)
        if spec is not None and spec.submodule_search_locations:
            for folder in spec.submodule_search_locations:
                compileall.compile_dir(folder, quiet=1)


def time_runs(commands: dict, repeats: int) -> dict:
    """Wall times (s) of each command, runs interleaved so that machine load hits all alike."""
    times = {k: [] for k in commands}
    env = dict(os.environ, PYTHONDONTWRITEBYTECODE="1")
    ensure_bytecode("inertia")
    for k, cmd in commands.items():  # warm-up: file cache
        subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
    for _ in range(repeats):
        for k, cmd in commands.items():
            t0 = time.perf_counter()
            subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False, env=env)
            times[k].append(time.perf_counter() - t0)
    return times


def heavy_imports(argv: list[str]) -> list[str]:
    """Heavy top-level modules present in sys.modules after ``inertia <argv>``."""
    out = subprocess.run([sys.executable, "-c", _PROBE, *argv], capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def slowest_imports(cmd: list[str], n: int = 8) -> list[tuple[int, str]]:
    """``(cumulative microseconds, module)`` of the slowest top-level imports under -X importtime."""
    out = subprocess.run([cmd[0], "-X", "importtime", *cmd[1:]], capture_output=True, text=True, check=False)
    rows = []
    for line in out.stderr.splitlines():
        # "import time: <self us> | <cumulative us> | <indent><module>"; top level = no extra indent
        if not line.startswith("import time:") or "cumulative" in line:
            continue
        _self_us, cum_us, name = line[len("import time:"):].split("|", 2)
        if not name[1:].startswith(" "):
            rows.append((int(cum_us), name.strip()))
    rows.sort(reverse=True)
    return rows[:n]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--repeats", type=int, default=40)
    ap.add_argument("--target-ms", type=float, default=100.0)
    a = ap.parse_args(argv)

    cmd = inertia_command()
    commands = {
        "python -c pass": [sys.executable, "-c", "pass"],
        "inertia --help": cmd + ["--help"],
        "inertia props --help": cmd + ["props", "--help"],
    }
    print(f"python: {sys.executable} ({sys.version.split()[0]})")
    print(f"inertia: {' '.join(cmd)}")
    print(f"repeats: {a.repeats} (interleaved, after one warm-up run each)\n")
    times = time_runs(commands, a.repeats)
    base = statistics.median(times["python -c pass"])
    w = max(len(k) for k in commands)
    print(f"{'command'.ljust(w)}  {'min [ms]':>9}  {'median [ms]':>11}  {'median - python [ms]':>20}")
    for k, t in times.items():
        med = statistics.median(t)
        print(f"{k.ljust(w)}  {min(t) * 1e3:9.1f}  {med * 1e3:11.1f}  {(med - base) * 1e3:20.1f}")

    print()
    ok = True
    from inertia.cli.main import COMMANDS

    for args in [["--help"]] + [[c, "--help"] for c in COMMANDS]:
        heavy = heavy_imports(args)
        ok &= not heavy
        print(f"heavy modules imported by 'inertia {' '.join(args)}': {', '.join(heavy) if heavy else 'none'}")

    print("\nslowest top-level imports of 'inertia --help' (python -X importtime, cumulative):")
    for us, name in slowest_imports(cmd + ["--help"]):
        print(f"  {us / 1e3:7.1f} ms  {name}")

    # the minimum is the least noisy estimate of start-up cost (the noise only ever adds time)
    min_help = min(times["inertia --help"]) * 1e3
    med_help = statistics.median(times["inertia --help"]) * 1e3
    fast = min_help < a.target_ms
    print(f"\n'inertia --help': min {min_help:.1f} ms, median {med_help:.1f} ms (target: min < {a.target_ms:g} ms): "
          f"{'PASS' if fast else 'FAIL'}; no heavy imports: {'PASS' if ok else 'FAIL'}")
    return 0 if (fast and ok) else 1


if __name__ == "__main__":
    sys.exit(main())
