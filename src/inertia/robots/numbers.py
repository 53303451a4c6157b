"""Numbers and rotations as robot files write them: whitespace-separated finite numbers, and
URDF/SDF fixed-axis roll-pitch-yaw."""

from __future__ import annotations

import math

import numpy as np

from .._core.tolerances import COORDINATE_LIMIT
from .xmlsafe import RobotFileError


def rpy_matrix(roll: float, pitch: float, yaw: float) -> np.ndarray:
    """``Rz(yaw) Ry(pitch) Rx(roll)``: URDF/SDF fixed-axis roll-pitch-yaw."""
    cr, sr = math.cos(roll), math.sin(roll)
    cp, sp = math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def floats(text, n: int | None, where: str, what: str) -> list[float]:
    """Parse ``n`` whitespace-separated finite numbers; RobotFileError naming ``where`` otherwise."""
    parts = (text or "").split()
    try:
        vals = [float(p) for p in parts]
    except ValueError:
        raise RobotFileError(f"{where}: {what} must be numbers, got {text!r}") from None
    if n is not None and len(vals) != n:
        raise RobotFileError(f"{where}: {what} needs {n} numbers, got {len(vals)} ({text!r})")
    if not all(math.isfinite(v) for v in vals):
        raise RobotFileError(f"{where}: {what} holds a non-finite number ({text!r})")
    big = [v for v in vals if abs(v) > COORDINATE_LIMIT]
    if big:
        raise RobotFileError(f"{where}: {what} holds {big[0]:g}, beyond +-{COORDINATE_LIMIT:g}: no length, mass or "
                             "inertia of a robot is that large, and the mass properties would overflow (check the "
                             "units)")
    return vals
