"""scipy Rotation as an independent oracle, in our scalar-first order, for every scipy version
(``scalar_first=`` exists only from scipy 1.14; the floor is older)."""

from __future__ import annotations

import numpy as np
from scipy.spatial.transform import Rotation


def as_wxyz(rotation: Rotation) -> np.ndarray:
    """(..., 4) scalar-first quaternions of a scipy Rotation."""
    return np.asarray(rotation.as_quat())[..., [3, 0, 1, 2]]


def from_wxyz(q) -> Rotation:
    """A scipy Rotation from scalar-first quaternions (..., 4)."""
    return Rotation.from_quat(np.asarray(q, float)[..., [1, 2, 3, 0]])
