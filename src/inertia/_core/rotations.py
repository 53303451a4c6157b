"""Unit quaternions, scalar-first ``(w, x, y, z)``, acting body -> world.

``q_world_body`` rotates body coordinates into world coordinates:
``v_W = R(q_WB) @ v_B``.  Composition: ``q_WC = q_WB (x) q_BC``.  All functions
accept leading batch dimensions.
"""

from __future__ import annotations

import numpy as np


def quat_multiply(p, q) -> np.ndarray:
    """Hamilton product ``p (x) q`` of (..., 4) quaternions."""
    p = np.asarray(p, float)
    q = np.asarray(q, float)
    pw, px, py, pz = np.moveaxis(p, -1, 0)
    qw, qx, qy, qz = np.moveaxis(q, -1, 0)
    return np.stack([
        pw * qw - px * qx - py * qy - pz * qz,
        pw * qx + px * qw + py * qz - pz * qy,
        pw * qy - px * qz + py * qw + pz * qx,
        pw * qz + px * qy - py * qx + pz * qw,
    ], axis=-1)


def quat_conjugate(q) -> np.ndarray:
    """Conjugate (the inverse of a unit quaternion)."""
    q = np.asarray(q, float)
    return q * np.array([1.0, -1.0, -1.0, -1.0])


def quat_normalize(q) -> np.ndarray:
    """Scale to unit norm (..., 4)."""
    q = np.asarray(q, float)
    return q / np.linalg.norm(q, axis=-1, keepdims=True)


def quat_canonical(q) -> np.ndarray:
    """Representative with ``w >= 0`` (q and -q are the same rotation)."""
    q = np.asarray(q, float)
    return np.where(q[..., :1] < 0, -q, q)


def quat_to_matrix(q) -> np.ndarray:
    """Rotation matrix (..., 3, 3) of a unit quaternion (..., 4): ``R_WB`` from ``q_WB``."""
    q = np.asarray(q, float)
    w, x, y, z = np.moveaxis(q, -1, 0)
    return np.stack([
        np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
        np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
        np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1),
    ], axis=-2)


def matrix_to_quat(R) -> np.ndarray:
    """Unit quaternion (..., 4) with ``w >= 0`` of a rotation matrix (..., 3, 3).

    Shepperd's method: pick the largest of (trace, R_xx, R_yy, R_zz) as the pivot so the
    division is well conditioned (Markley 2008, "Unit quaternion from rotation matrix").
    """
    R = np.asarray(R, float)
    shape = R.shape[:-2]
    R = R.reshape(-1, 3, 3)
    tr = np.trace(R, axis1=-2, axis2=-1)
    diag = np.diagonal(R, axis1=-2, axis2=-1)
    pivot = np.argmax(np.concatenate([tr[:, None], diag], axis=1), axis=1)
    q = np.empty((R.shape[0], 4))
    for k in range(R.shape[0]):
        r = R[k]
        i = pivot[k]
        if i == 0:
            s = 2.0 * np.sqrt(1.0 + tr[k])
            q[k] = [0.25 * s, (r[2, 1] - r[1, 2]) / s, (r[0, 2] - r[2, 0]) / s, (r[1, 0] - r[0, 1]) / s]
        elif i == 1:
            s = 2.0 * np.sqrt(1.0 + r[0, 0] - r[1, 1] - r[2, 2])
            q[k] = [(r[2, 1] - r[1, 2]) / s, 0.25 * s, (r[0, 1] + r[1, 0]) / s, (r[0, 2] + r[2, 0]) / s]
        elif i == 2:
            s = 2.0 * np.sqrt(1.0 - r[0, 0] + r[1, 1] - r[2, 2])
            q[k] = [(r[0, 2] - r[2, 0]) / s, (r[0, 1] + r[1, 0]) / s, 0.25 * s, (r[1, 2] + r[2, 1]) / s]
        else:
            s = 2.0 * np.sqrt(1.0 - r[0, 0] - r[1, 1] + r[2, 2])
            q[k] = [(r[1, 0] - r[0, 1]) / s, (r[0, 2] + r[2, 0]) / s, (r[1, 2] + r[2, 1]) / s, 0.25 * s]
    q = quat_canonical(quat_normalize(q))
    return q.reshape(shape + (4,))


def quat_from_rotvec(v) -> np.ndarray:
    """Quaternion of the rotation vector v (..., 3) [rad]: angle |v| about v/|v| (the exponential map).

    Uses sin(x/2)/x with a Taylor series near zero so small rotations keep full precision.
    """
    v = np.asarray(v, float)
    theta = np.linalg.norm(v, axis=-1, keepdims=True)
    half = 0.5 * theta
    small = theta < 1e-4
    # sin(t/2)/t = 1/2 - t^2/48 + t^4/3840 - ...
    t2 = theta * theta
    k = np.where(small, 0.5 - t2 / 48.0 + t2 * t2 / 3840.0, np.sin(half) / np.where(small, 1.0, theta))
    return np.concatenate([np.cos(half), k * v], axis=-1)


def quat_to_rotvec(q) -> np.ndarray:
    """Rotation vector (..., 3) [rad] of a unit quaternion, angle in [0, pi] (the logarithm map)."""
    q = quat_canonical(np.asarray(q, float))
    w = np.clip(q[..., :1], -1.0, 1.0)
    xyz = q[..., 1:]
    s = np.linalg.norm(xyz, axis=-1, keepdims=True)
    angle = 2.0 * np.arctan2(s, w)
    small = s < 1e-8
    # angle / sin(angle/2) -> 2 / w (1 + s^2/(6 w^2)) for small s
    k = np.where(small, 2.0 / w * (1.0 + s * s / (6.0 * w * w)), angle / np.where(small, 1.0, s))
    return k * xyz


def quat_rotate(q, v) -> np.ndarray:
    """Rotate vectors v (..., 3) by unit quaternions q (..., 4): ``R(q) @ v``."""
    q = np.asarray(q, float)
    v = np.asarray(v, float)
    u = q[..., 1:]
    w = q[..., :1]
    t = 2.0 * np.cross(u, v)
    return v + w * t + np.cross(u, t)
