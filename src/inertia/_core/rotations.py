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
    pw, px, py, pz = p[..., 0], p[..., 1], p[..., 2], p[..., 3]
    qw, qx, qy, qz = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
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
    return q / np.sqrt(np.sum(q * q, axis=-1, keepdims=True))


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
    r = lambda i, j: R[:, i, j]  # noqa: E731
    tr = r(0, 0) + r(1, 1) + r(2, 2)
    pivot = np.argmax(np.stack([tr, r(0, 0), r(1, 1), r(2, 2)], axis=1), axis=1)
    # the four candidate formulas, vectorised; each is used only where its pivot is largest
    # (so its square root is of a number >= 1 and the divisions are well conditioned)
    with np.errstate(invalid="ignore", divide="ignore"):
        s0 = 2.0 * np.sqrt(1.0 + tr)
        s1 = 2.0 * np.sqrt(1.0 + r(0, 0) - r(1, 1) - r(2, 2))
        s2 = 2.0 * np.sqrt(1.0 - r(0, 0) + r(1, 1) - r(2, 2))
        s3 = 2.0 * np.sqrt(1.0 - r(0, 0) - r(1, 1) + r(2, 2))
        cands = np.stack([
            np.stack([0.25 * s0, (r(2, 1) - r(1, 2)) / s0, (r(0, 2) - r(2, 0)) / s0, (r(1, 0) - r(0, 1)) / s0], -1),
            np.stack([(r(2, 1) - r(1, 2)) / s1, 0.25 * s1, (r(0, 1) + r(1, 0)) / s1, (r(0, 2) + r(2, 0)) / s1], -1),
            np.stack([(r(0, 2) - r(2, 0)) / s2, (r(0, 1) + r(1, 0)) / s2, 0.25 * s2, (r(1, 2) + r(2, 1)) / s2], -1),
            np.stack([(r(1, 0) - r(0, 1)) / s3, (r(0, 2) + r(2, 0)) / s3, (r(1, 2) + r(2, 1)) / s3, 0.25 * s3], -1),
        ], axis=1)
    q = cands[np.arange(R.shape[0]), pivot]
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


def cross3(a, b) -> np.ndarray:
    """``a x b`` for (..., 3) arrays (faster than ``np.cross`` on small arrays)."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)


def quat_multiply_vector(q, v) -> np.ndarray:
    """``q (x) (0, v)`` for quaternions q (..., 4) and vectors v (..., 3)."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    a, b, c = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([-x * a - y * b - z * c,
                     w * a + y * c - z * b,
                     w * b - x * c + z * a,
                     w * c + x * b - y * a], axis=-1)


def vector_multiply_quat(v, q) -> np.ndarray:
    """``(0, v) (x) q`` for vectors v (..., 3) and quaternions q (..., 4)."""
    w, x, y, z = q[..., 0], q[..., 1], q[..., 2], q[..., 3]
    a, b, c = v[..., 0], v[..., 1], v[..., 2]
    return np.stack([-a * x - b * y - c * z,
                     a * w + b * z - c * y,
                     b * w + c * x - a * z,
                     c * w + a * y - b * x], axis=-1)
