"""Acceptance run of the robot readers over fetched robot repositories (nothing is committed).

    python bench/robots_acceptance.py FOLDER [FOLDER ...] [--out results.jsonl] [--timeout 120]

Every ``.urdf``, ``.sdf``, ``.world``, ``.mjcf`` and ``.xml`` robot file under the folders (an
``.xml`` whose root is ``<mujoco>``, ``<robot>`` or ``<sdf>``) is read and judged, each against
the oracle its format has here:

* MJCF: MuJoCo's compiler.  Per body (static bodies not fused), the worst relative difference of
  mass, COM (relative to the model's size) and the tensor about the COM (relative to its
  largest entry), all in the world frame at qpos0; a *false error* is an error of ours (read
  failure or ``check`` error) on a file MuJoCo compiles, a *missed refusal* a file MuJoCo
  refuses that we read without an error.
* URDF: Pinocchio (urdfdom).  Total mass, COM and inertia about the COM in the root link's frame
  at q = 0; a read failure or a tree error of ours on a file Pinocchio builds is a false error
  (Pinocchio does not judge physical validity: the inertials ``check`` flags are rechecked below).
* URDF and SDF inertials ``check`` calls non-physical are checked again at 50 digits (mpmath):
  a tensor that is physical there is a false error.
* Every file: ``fix`` (nearest valid) writes a copy beside the input, and ``check`` of that copy
  must find errors exactly when ``fix`` says the copy still fails (``fix/check agree``).

Times are of ``check``'s errors (``check_model(warnings=False)``, what ``fix`` runs), in process;
``--full`` times the whole ``check`` (with the geometry comparisons) instead.  A file that takes
longer than ``--timeout`` seconds is recorded as such.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # the checkout: its tests' oracle helpers
from tests.robots._oracles import compiled_bodies  # noqa: E402 - the tests' reading of MuJoCo's bodies

ROBOT_ROOTS = {b"<mujoco": "mjcf", b"<robot": "urdf", b"<sdf": "sdf"}
EXTENSIONS = {".urdf": "urdf", ".sdf": "sdf", ".world": "sdf", ".mjcf": "mjcf", ".xml": None}


def robot_files(folders):
    """``(path, format)`` of every robot file under ``folders``."""
    import re

    for folder in folders:
        for path in sorted(Path(folder).rglob("*")):
            ext = path.suffix.lower()
            if ext not in EXTENSIONS or not path.is_file():
                continue
            head = path.read_bytes()[:4096]
            head = re.sub(rb"<\?.*?\?>|<!--.*?-->", b"", head, flags=re.S).lstrip()
            fmt = next((f for tag, f in ROBOT_ROOTS.items() if head.startswith(tag)), None)
            if fmt is not None:
                yield path, fmt


class Timeout(BaseException):
    """A file over the time limit (not an Exception: the oracles' ``except Exception`` let it through)."""


def _alarm(signum, frame):
    raise Timeout()


def mujoco_judgement(path):
    """``(error or None, {name: (mass, com, inertia)})`` of MuJoCo's compiler, world frame."""
    import mujoco

    try:
        spec = mujoco.MjSpec.from_file(str(path))
        spec.compiler.fusestatic = False
        m = spec.compile()
    except Exception as exc:  # noqa: BLE001
        return (str(exc).strip().splitlines() or [type(exc).__name__])[0][:200], {}
    return None, compiled_bodies(m)


def mujoco_agreement(ours, theirs) -> tuple[float, int, str]:
    """Worst per-body relative difference, bodies compared, and the worst body's name."""
    length = max([1e-3] + [float(np.abs(c).max()) for _, c, _ in theirs.values()])
    by_name = {lk.name: lk for lk in ours.links}
    worst, n, where = 0.0, 0, ""
    for name, (mass, com, inertia) in theirs.items():
        lk = by_name.get(name)
        if mass <= 0 or lk is None:
            continue
        n += 1
        d = max(abs(lk.mass - mass) / mass, float(np.abs(lk.com - com).max()) / length,
                float(np.abs(lk.inertia_com - inertia).max()) / max(float(np.abs(inertia).max()), 1e-300))
        if d > worst:
            worst, where = d, name
    return worst, n, where


def pinocchio_judgement(path):
    """``(error or None, (mass, com, inertia about the COM))`` of Pinocchio at q = 0, root link frame."""
    import pinocchio as pin

    try:
        model = pin.buildModelFromUrdf(str(path))
    except Exception as exc:  # noqa: BLE001
        return (str(exc).strip().splitlines() or [type(exc).__name__])[0][:200], None
    data = model.createData()
    pin.forwardKinematics(model, data, pin.neutral(model))
    total = pin.Inertia.Zero()
    for i in range(model.njoints):  # the root link's inertia is the universe's (joint 0)
        total += data.oMi[i].act(model.inertias[i])
    return None, (float(total.mass), np.array(total.lever), np.array(total.inertia))


def mp_physical(inertia) -> bool:
    """The tensor is physical at 50 digits (positive moments, triangle inequality)."""
    import mpmath

    mpmath.mp.dps = 50
    A = mpmath.matrix([[mpmath.mpf(float(inertia[i][j])) for j in range(3)] for i in range(3)])
    A = (A + A.T) / 2
    w = sorted(mpmath.eigsy(A)[0])
    return bool(w[0] > 0 and w[0] + w[1] >= w[2])


def _check(model, full: bool):
    """``check_model`` (an older inertia without ``warnings=``: the whole check)."""
    from inertia.robots.check import check_model

    try:
        return check_model(model, warnings=full)
    except TypeError:
        return check_model(model)


def judge(path: Path, fmt: str, full: bool) -> dict:
    from inertia.robots.fix import fix_file
    from inertia.robots.io import read_robot
    from inertia.robots.whole import robot_mass_properties

    row = {"file": str(path), "format": fmt}
    t0 = time.perf_counter()
    try:
        model = read_robot(path)
        report = _check(model, full)
        row["errors"] = sorted({e.code for e in report.errors} | {e.code for lk in report.links for e in lk.errors})
        row["read_error"] = None
    except Exception as exc:  # noqa: BLE001 - every failure is a row
        row["errors"], row["read_error"] = ["read"], f"{type(exc).__name__}: {str(exc)[:200]}"
        model = report = None
    row["check_seconds"] = time.perf_counter() - t0
    if fmt == "mjcf":
        refusal, theirs = mujoco_judgement(path)
        row["oracle_refuses"] = refusal
        if refusal is None and model is not None:
            try:
                row["worst"], row["bodies"], row["worst_body"] = mujoco_agreement(robot_mass_properties(model), theirs)
            except Exception as exc:  # noqa: BLE001
                row["props_error"] = f"{type(exc).__name__}: {str(exc)[:200]}"
    elif fmt == "urdf":
        refusal, total = pinocchio_judgement(path)
        row["oracle_refuses"] = refusal
        if refusal is None and model is not None and total is not None and total[0] > 0:
            try:
                ours = robot_mass_properties(model).total
                scale = max(float(np.abs(total[2]).max()), 1e-300)
                row["worst"] = max(abs(ours.mass - total[0]) / total[0], float(np.abs(ours.com - total[1]).max()),
                                   float(np.abs(ours.inertia_com - total[2]).max()) / scale)
                row["bodies"] = len(model.links)
            except Exception as exc:  # noqa: BLE001
                row["props_error"] = f"{type(exc).__name__}: {str(exc)[:200]}"
    if report is not None and fmt in ("urdf", "sdf"):
        flagged = [lk for lk, r in zip(model.links, report.links)
                   if any(e.code in ("not_positive_definite", "triangle_inequality") for e in r.errors)]
        row["inertia_flagged"] = len(flagged)
        row["inertia_false"] = [lk.name for lk in flagged if mp_physical(lk.inertial.inertia_com_inertial)]
    if model is not None:
        out = path.with_name(f".acceptance_fix_{os.getpid()}_{path.name}")
        try:
            fixed = fix_file(path, out)
            again = _check(read_robot(out), False)
            row["fix_fails"] = bool(fixed.remaining)
            row["check_of_fix_fails"] = again.n_errors > 0
        except Exception as exc:  # noqa: BLE001
            row["fix_error"] = f"{type(exc).__name__}: {str(exc)[:200]}"
        finally:
            out.unlink(missing_ok=True)
    return row


def summary(rows: list) -> list:
    """The table: per format, files, bodies, worst agreement, false errors, fix/check agreement, times."""
    lines = ["| format | files | read | oracle refuses | bodies | worst agreement | false errors | missed refusals "
             "| inertia flagged (false) | fix/check agree | check s: median / max |", "|" + "---|" * 11]
    for fmt in ("mjcf", "urdf", "sdf"):
        rs = [r for r in rows if r.get("format") == fmt]
        if not rs:
            continue
        ok = [r for r in rs if r.get("read_error") is None]
        loads = [r for r in rs if fmt == "sdf" or r.get("oracle_refuses") is None]
        false = [r for r in loads if fmt == "mjcf" and r["errors"] or r.get("read_error") and fmt != "sdf"
                 or "joints_unreadable" in r["errors"] and fmt == "urdf" or r.get("inertia_false")]
        missed = [r for r in rs if r.get("oracle_refuses") and not r["errors"]]
        worst = max([r.get("worst", 0.0) for r in rs] or [0.0])
        fixes = [r for r in rs if "fix_fails" in r]
        agree = sum(r["fix_fails"] == r["check_of_fix_fails"] for r in fixes)
        times = sorted(r["check_seconds"] for r in rs)
        flagged = sum(r.get("inertia_flagged", 0) for r in rs)
        wrongly = sum(len(r.get("inertia_false", [])) for r in rs)
        lines.append(f"| {fmt} | {len(rs)} | {len(ok)} | {sum(1 for r in rs if r.get('oracle_refuses'))} | "
                     f"{sum(r.get('bodies', 0) for r in rs)} | {worst:.2g} | {len(false)} | {len(missed)} | "
                     f"{flagged} ({wrongly}) | {agree}/{len(fixes)} | {times[len(times) // 2]:.2f} / {times[-1]:.1f} |")
    return lines


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("folders", nargs="+", type=Path)
    p.add_argument("--out", type=Path, help="one JSON row per file")
    p.add_argument("--timeout", type=float, default=120.0, help="seconds per file")
    p.add_argument("--full", action="store_true", help="time the whole check (geometry comparisons included)")
    args = p.parse_args(argv)
    warnings.simplefilter("ignore")
    signal.signal(signal.SIGALRM, _alarm)
    args.folders = [f.resolve() for f in args.folders]
    args.out = args.out.resolve() if args.out else None
    os.chdir(tempfile.mkdtemp(prefix="acceptance_"))  # MuJoCo writes MUJOCO_LOG.TXT where it runs
    rows = []
    sink = open(args.out, "w") if args.out else None
    for path, fmt in robot_files(args.folders):
        signal.setitimer(signal.ITIMER_REAL, args.timeout)
        try:
            row = judge(path, fmt, args.full)
        except Timeout:
            row = {"file": str(path), "format": fmt, "timeout": args.timeout, "errors": ["timeout"],
                   "check_seconds": args.timeout, "read_error": "timeout"}
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        rows.append(row)
        if sink:
            sink.write(json.dumps(row, default=float) + "\n")
            sink.flush()
    print("\n".join(summary(rows)))
    bad = [r for r in rows if r.get("worst", 0) > 1e-7 or (r.get("oracle_refuses") is None and r["format"] == "mjcf"
                                                           and r["errors"])
           or r.get("inertia_false") or ("fix_fails" in r and r["fix_fails"] != r["check_of_fix_fails"])
           or (r.get("read_error") and not r.get("oracle_refuses"))]
    for r in bad:
        print(f"  {r['file']}: worst {r.get('worst', 0):.2g} {r.get('worst_body', '')} errors {r['errors']} "
              f"{r.get('read_error') or ''} {r.get('oracle_refuses') or ''}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
