"""The oracles of the robot tests: MuJoCo's compiler (MJCF, body by body in the world frame) and
Pinocchio (URDF through urdfdom), each asked through its own public API only."""

from __future__ import annotations

import contextlib
from pathlib import Path

import numpy as np
import pytest

from inertia.robots.io import read_robot
from inertia.robots.whole import robot_mass_properties


def mujoco_compiles(path) -> str | None:
    """None when MuJoCo compiles the file, else the first line of its error (MuJoCo's log file,
    MUJOCO_LOG.TXT, goes to the file's folder, not the working directory)."""
    mujoco = pytest.importorskip("mujoco")
    try:
        with contextlib.chdir(Path(path).parent):
            mujoco.MjModel.from_xml_path(str(Path(path).resolve()))
    except Exception as exc:  # noqa: BLE001 - MuJoCo raises ValueError or its own errors
        return str(exc).strip().splitlines()[0]
    return None


def mujoco_bodies(path, *, fusestatic: bool | None = False) -> dict:
    """MuJoCo's bodies at qpos0: name -> (mass, COM, inertia about the COM), world frame.

    ``fusestatic=None`` keeps the model's own setting; False compiles body for body.
    """
    mujoco = pytest.importorskip("mujoco")
    spec = mujoco.MjSpec.from_file(str(path))
    if fusestatic is not None:
        spec.compiler.fusestatic = fusestatic
    return compiled_bodies(spec.compile())


def compiled_bodies(m) -> dict:
    """The bodies of MuJoCo's compiled model ``m`` at qpos0: name -> (mass, COM, inertia about the
    COM), world frame (the world body left out)."""
    import mujoco

    d = mujoco.MjData(m)
    mujoco.mj_kinematics(m, d)
    out = {}
    for i in range(1, m.nbody):
        R = d.ximat[i].reshape(3, 3)
        out[mujoco.mj_id2name(m, mujoco.mjtObj.mjOBJ_BODY, i)] = (
            float(m.body_mass[i]), d.xipos[i].copy(), R @ np.diag(m.body_inertia[i]) @ R.T)
    return out


def _lumped(ours, names) -> dict:
    """Our links summed into the nearest ancestor that ``names`` holds (MuJoCo fuses static bodies)."""
    out: dict = {}
    for lk in ours.links:
        up = lk
        while up.name not in names and up.parent is not None:
            up = ours.links[up.parent]
        if up.name in names:
            out.setdefault(up.name, []).append(lk.props)
    from inertia.massprops.properties import combine

    return {k: combine(v, validate=False) if len(v) > 1 else v[0] for k, v in out.items()}


def worst_body_difference(path, *, fusestatic: bool | None = False) -> tuple[float, int]:
    """``(worst relative difference, bodies compared)`` between our links and MuJoCo's bodies
    with mass: mass relative, COM relative to the model's size, tensor relative to its largest entry."""
    theirs = mujoco_bodies(path, fusestatic=fusestatic)
    ours = _lumped(robot_mass_properties(read_robot(path)), set(theirs))
    length = max([1e-3] + [float(np.abs(c).max()) for _, c, _ in theirs.values()])
    worst, n = 0.0, 0
    for name, (mass, com, inertia) in theirs.items():
        if mass <= 0:
            continue
        mine = ours[name]
        n += 1
        worst = max(worst, abs(mine.mass - mass) / mass, float(np.abs(mine.com - com).max()) / length,
                    float(np.abs(mine.inertia_com - inertia).max()) / max(float(np.abs(inertia).max()), 1e-300))
    return worst, n


def pinocchio_links(path) -> tuple[set, float]:
    """Pinocchio's (urdfdom's) reading of a URDF: its link names and the robot's total mass."""
    pin = pytest.importorskip("pinocchio")
    model = pin.buildModelFromUrdf(str(path))
    names = {f.name for f in model.frames if f.type == pin.FrameType.BODY}
    return names, float(sum(model.inertias[i].mass for i in range(model.njoints)))
