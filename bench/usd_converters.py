"""What format converters do to robots' mass properties, measured; and what ``inertia fix --from`` restores.

Usage::

    python bench/usd_converters.py MODEL_DIR [MODEL_DIR ...] [--out DIR] [--json FILE]
        [--mjcf-converter EXE] [--urdf-converter EXE] [--repeat 3] [--package NAME=DIR ...]

For every robot of each folder (MJCF: ``*.xml`` files with ``<mujoco>`` and bodies, scenes
skipped when the robot file is there; URDF: ``*.urdf``), the script

1. converts it to OpenUSD with ``mujoco_usd_converter`` / ``urdf_usd_converter`` (their own
   environment: usd-exchange ships its own OpenUSD modules, which must not meet usd-core's);
2. counts the bodies whose mass, world COM or world inertia the conversion changed, against the
   truth (MJCF: MuJoCo's compiled model at ``qpos0``, ``body_mass``, ``xipos``, ``ximat``,
   ``body_inertia``; URDF: the file's inertials) and with ``inertia diff`` (the two counts must
   agree), both as usd-core's ``ComputeMassProperties`` reads the stage and as authored
   (``--zero-unset``), with the worst relative error;
3. runs ``inertia fix STAGE --from MODEL --in-place`` on a copy and counts again; then compares
   usd-core's ``ComputeMassProperties`` on the fixed stage with the truth at 1e-6;
4. times ``inertia check`` on each stage (best of ``--repeat``).

Prints a table and writes every figure to ``--json``.  Truth tolerance: 1e-6 (relative for mass
and inertia, metres for the COM).
"""

from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # the checkout: its tests' oracle helpers

TOL = 1e-6


def find_models(folder: Path) -> list:
    """``[(kind, path)]``: the robot files of a model folder."""
    out = []
    for p in sorted(folder.glob("*.urdf")):
        out.append(("urdf", p))
    xmls = [p for p in sorted(folder.glob("*.xml")) if "<mujoco" in p.read_text(errors="replace")[:4000]]
    robots = [p for p in xmls if not p.stem.startswith("scene") and "<body" in p.read_text(errors="replace")]
    # a robot included by several actuator variants (tiago_motor.xml, ...) is converted once
    base = [p for p in robots if not any(q != p and p.stem.startswith(q.stem + "_") for q in robots)]
    out += [("mjcf", p) for p in base]
    return out


def convert(exe: str, model: Path, out: Path, extra=()) -> tuple[Path, float]:
    if out.exists():
        shutil.rmtree(out)
    t = time.perf_counter()
    run = subprocess.run([exe, str(model), str(out), *extra], capture_output=True, text=True)
    seconds = time.perf_counter() - t
    stages = sorted(out.glob("*.usda"))
    if run.returncode != 0 or not stages:
        raise RuntimeError(f"{exe} failed on {model}: {run.stderr.strip()[-500:]}")
    return stages[0], seconds


def mujoco_truth(model: Path):
    """A RobotMassProperties-like table of MuJoCo's compiled bodies (world frame, qpos0)."""
    import mujoco

    from inertia.massprops.properties import MassProperties

    m = mujoco.MjModel.from_xml_path(str(model))
    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    mujoco.mj_comPos(m, d)

    class Row:
        def __init__(self, name, props):
            self.name, self.props, self.source = name, props, "mujoco"
            self.mass, self.com, self.inertia_com = props.mass, props.com, props.inertia_com

    rows = []
    for i in range(1, m.nbody):
        R = d.ximat[i].reshape(3, 3)
        rows.append(Row(m.body(i).name or f"body{i}",
                        MassProperties(float(m.body_mass[i]), d.xipos[i].copy(), R @ np.diag(m.body_inertia[i]) @ R.T,
                                       frame="world", validate=False)))

    class Table:
        pass

    t = Table()
    t.path, t.links, t.frame = model, rows, "world"
    t.total = MassProperties(sum(r.mass for r in rows), np.zeros(3), np.zeros((3, 3)), validate=False)
    return t


def count(report) -> tuple[int, float]:
    return len(report.differ), max((d.worst for d in report.differ), default=0.0)


def usd_core_vs_truth(stage_path: Path, truth) -> tuple[int, int, float]:
    """``(agree, compared, worst)``: usd-core's ComputeMassProperties (fed with our per-collider values
    where it sums colliders) against the truth, body by body as ``inertia diff`` pairs them, at TOL."""
    from pxr import UsdPhysics

    from inertia.massprops.properties import MassProperties, combine
    from inertia.robots.diff import diff_robots
    from inertia.robots.usd.mass import body_mass, principal_axes_matrix
    from inertia.robots.usd.stage import read_stage
    from tests.robots.usd_make import collider_information  # the oracle's callback, as the tests feed it

    stage = read_stage(stage_path)

    class Row:
        def __init__(self, name, props, parent):
            self.name, self.props, self.parent, self.source = name, props, parent, "usd-core"
            self.mass, self.com, self.inertia_com = props.mass, props.com, props.inertia_com

    rows = []
    for i, b in enumerate(stage.bodies):
        info = collider_information(body_mass(stage, i).parts)
        prim = stage.usd_stage.GetPrimAtPath(b.path)
        mass, diag, com, q = UsdPhysics.RigidBodyAPI(prim).ComputeMassProperties(info)
        R = principal_axes_matrix([q.GetReal(), *q.GetImaginary()]) if q.GetLength() > 0.5 else np.eye(3)
        m_unit, kg_unit, Rw, pw = stage.meters_per_unit, stage.kilograms_per_unit, b.R_world_body, b.p_world_body
        rows.append(Row(b.label, MassProperties(
            mass * kg_unit, (Rw @ np.array(com, float) + pw) * m_unit,
            Rw @ R @ np.diag(np.array(diag, float)) @ R.T @ Rw.T * kg_unit * m_unit ** 2, frame="world",
            validate=False), b.parent))

    class Table:
        pass

    table = Table()
    table.path, table.links, table.frame = stage_path, rows, "world"
    table.total = combine([r.props for r in rows if r.mass > 0], frame="world", validate=False)
    d = diff_robots(truth, table, tol=TOL)
    return d.same, d.same + len(d.differ), max((x.worst for x in d.differ), default=0.0)


def time_from_colliders(stage, path: Path, repeat: int) -> float:
    """Best time of ``check`` on the stage with every body's PhysicsMassAPI deleted (an override
    layer): every collider is then integrated, and every mesh's hull built."""
    from pxr import Sdf

    from inertia.robots.usd.check import check_stage
    from inertia.robots.usd.stage import read_stage

    layer = Sdf.Layer.CreateNew(str(path))
    layer.subLayerPaths.append(str(stage.path.resolve()))
    for key in ("metersPerUnit", "kilogramsPerUnit"):
        root = stage.usd_stage.GetRootLayer().pseudoRoot
        if root.HasInfo(key):
            layer.pseudoRoot.SetInfo(key, root.GetInfo(key))
    for b in stage.bodies:
        spec = Sdf.CreatePrimInLayer(layer, b.path)
        op = Sdf.TokenListOp()
        op.deletedItems = ["PhysicsMassAPI"]
        spec.SetInfo("apiSchemas", op)
    layer.Save()
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        check_stage(read_stage(path))
        times.append(time.perf_counter() - t)
    return min(times)


def measure(kind: str, model: Path, exe: str, out: Path, repeat: int, packages=()) -> dict:
    from inertia.robots.diff import diff_robots, read_bodies
    from inertia.robots.usd.check import check_stage
    from inertia.robots.usd.stage import read_stage
    from inertia.robots.usd.write import fix_stage

    name = f"{model.parent.name}_{model.stem}"
    extra = [a for p in packages for a in ("--package", p)] if kind == "urdf" else []
    stage, seconds = convert(exe, model, out / name, extra)
    truth = mujoco_truth(model) if kind == "mjcf" else read_bodies(model)
    row = {"model": str(model), "kind": kind, "stage": str(stage), "convert_s": round(seconds, 2),
           "bodies": len(truth.links)}
    for label, tol in (("usd_core", None), ("authored", 0.0)):
        n, worst = count(diff_robots(truth, stage, tol=TOL, unset_tolerance=tol))
        ours, _ = count(diff_robots(model, stage, tol=TOL, unset_tolerance=tol))
        row[f"changed_{label}"], row[f"worst_{label}"], row[f"diff_{label}"] = n, worst, ours
    times = []
    for _ in range(repeat):
        t = time.perf_counter()
        rep = check_stage(read_stage(stage))
        times.append(time.perf_counter() - t)
    row["check_s"] = round(min(times), 3)
    st = read_stage(stage)
    row["check_from_colliders_s"] = round(time_from_colliders(st, out / f"{name}_nomass.usda", repeat), 3)
    row["colliders"] = sum(len(b.colliders) for b in st.bodies)
    row["triangles"] = sum(len(c.params.get("faces", ())) for b in st.bodies for c in b.colliders)
    row["check_findings"] = sorted({f.code for lk in rep.links for f in lk.errors + lk.warnings}
                                   | {f.code for f in rep.warnings})
    fixed = out / (name + "_fixed")
    if fixed.exists():
        shutil.rmtree(fixed)
    shutil.copytree(stage.parent, fixed)
    fixed_stage = fixed / stage.name
    fix = fix_stage(fixed_stage, source=model, in_place=True)
    row["fix_changed"] = len(fix.changed)
    for label, tol in (("usd_core", None), ("authored", 0.0)):
        row[f"after_{label}"], row[f"after_worst_{label}"] = count(diff_robots(truth, fixed_stage, tol=TOL,
                                                                              unset_tolerance=tol))
    row["usd_core_agree"], row["usd_core_matched"], row["usd_core_worst"] = usd_core_vs_truth(fixed_stage, truth)
    small = [b.name for b in read_stage(fixed_stage).bodies if b.mass.diagonal_inertia is not None
             and 0 < np.linalg.norm(b.mass.diagonal_inertia) <= 1e-5]
    row["inertia_below_1e-5"] = len(small)
    return row


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("folders", nargs="+", type=Path)
    ap.add_argument("--out", type=Path, default=Path("usd_converters_out"))
    ap.add_argument("--json", type=Path)
    ap.add_argument("--mjcf-converter", default=shutil.which("mujoco_usd_converter"))
    ap.add_argument("--urdf-converter", default=shutil.which("urdf_usd_converter"))
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--package", action="append", default=[], metavar="NAME=DIR",
                    help="a ROS package for package:// URIs (passed to urdf_usd_converter)")
    args = ap.parse_args(argv)
    rows = []
    for folder in args.folders:
        for kind, model in find_models(folder):
            exe = args.mjcf_converter if kind == "mjcf" else args.urdf_converter
            if not exe:
                print(f"skip {model}: no {kind} converter (--{kind}-converter)", file=sys.stderr)
                continue
            try:
                rows.append(measure(kind, model, exe, args.out, args.repeat, args.package))
            except Exception as exc:  # noqa: BLE001 - one model's failure is a row, not the end
                rows.append({"model": str(model), "kind": kind, "error": f"{type(exc).__name__}: {exc}"[:300]})
            print(json.dumps(rows[-1]), file=sys.stderr)
    head = ("model", "bodies", "changed_usd_core", "diff_usd_core", "worst_usd_core", "changed_authored",
            "worst_authored", "after_usd_core", "after_authored", "usd_core_agree", "usd_core_matched",
            "inertia_below_1e-5", "check_s", "check_from_colliders_s")
    print(" | ".join(head))
    for r in rows:
        if "error" in r:
            print(f"{Path(r['model']).name} | error: {r['error']}")
            continue
        cells = [Path(r["model"]).name] + [f"{r[k]:.3g}" if isinstance(r[k], float) else str(r[k]) for k in head[1:]]
        print(" | ".join(cells))
    if args.json:
        args.json.write_text(json.dumps(rows, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())
