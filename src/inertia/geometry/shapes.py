"""Shapes the library draws and bounds: the box-corner table and generated triangle meshes.

The meshes are closed, consistently wound with outward normals (counter-clockwise seen from
outside), and have no repeated vertex, so the exact mesh kernel integrates them as given;
they are polyhedral approximations (a cylinder of ``n`` sides has area
``n/2 r^2 sin(2 pi / n)``, short of ``pi r^2`` by O(1/n^2)), meant for pictures and tests.
"""

from __future__ import annotations

import numpy as np

from .._core.validation import as_positive_scalar, as_rotation_matrix, as_vector3

#: the eight corners of the cube [-1, 1]^3 (rows; x slowest, z fastest); scaled by
#: half-extents they are a box's corners, and two corners differing in exactly one sign
#: share an edge
BOX_CORNER_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=float)


def box_edges() -> list[tuple[int, int]]:
    """The 12 edges of the box as pairs of row indices of :data:`BOX_CORNER_SIGNS`."""
    s = BOX_CORNER_SIGNS
    return [(i, j) for i in range(8) for j in range(i + 1, 8) if np.count_nonzero(s[i] != s[j]) == 1]


def cylinder_mesh(radius, height, *, sides: int = 48, R_body_cylinder=None, p_body_cylinder=(0.0, 0.0, 0.0)):
    """Closed triangle mesh of a right prism with a regular ``sides``-gon base (a cylinder).

    Parameters
    ----------
    radius : float, m
        Circumradius of the polygon (its corners lie on the cylinder).
    height : float, m
        Length along the cylinder's axis z; it spans ``-height/2 <= z <= height/2``.
    sides : int, >= 3
    R_body_cylinder : (3, 3) proper rotation, optional
        Maps the cylinder's own axes (axis along z) into the body frame; default identity.
    p_body_cylinder : (3,) m
        Centre of the cylinder in the body frame.

    Returns
    -------
    vertices : (2 sides + 2, 3) float, m, body frame.
    faces : (4 sides, 3) int, outward winding.
    """
    r = as_positive_scalar(radius, "radius")
    h = as_positive_scalar(height, "height")
    n = int(sides)
    if n < 3 or n != sides:
        from .._core.errors import InputError

        raise InputError(f"sides must be a whole number >= 3, got {sides!r}")
    a = 2.0 * np.pi * np.arange(n) / n
    ring = np.stack([r * np.cos(a), r * np.sin(a), np.zeros(n)], axis=1)
    bottom, top = ring + [0.0, 0.0, -0.5 * h], ring + [0.0, 0.0, 0.5 * h]
    vertices = np.vstack([bottom, top, [[0.0, 0.0, -0.5 * h], [0.0, 0.0, 0.5 * h]]])
    k = np.arange(n)
    k1 = (k + 1) % n
    cb, ct = 2 * n, 2 * n + 1
    faces = np.concatenate([
        np.stack([k, k1 + n, k + n], axis=1),          # side, lower triangle (outward)
        np.stack([k, k1, k1 + n], axis=1),             # side, upper triangle
        np.stack([np.full(n, cb), k1, k], axis=1),     # bottom cap, normal -z
        np.stack([np.full(n, ct), k + n, k1 + n], axis=1),  # top cap, normal +z
    ]).astype(np.int64)
    R = np.eye(3) if R_body_cylinder is None else as_rotation_matrix(R_body_cylinder, "R_body_cylinder",
                                                                      allow_batch=False)
    p = as_vector3(p_body_cylinder, "p_body_cylinder")
    return vertices @ R.T + p, faces


def merge_meshes(meshes) -> tuple[np.ndarray, np.ndarray]:
    """Concatenate ``[(vertices, faces), ...]`` into one mesh (faces re-indexed; shells kept apart)."""
    vs, fs, offset = [], [], 0
    for v, f in meshes:
        vs.append(np.asarray(v, float))
        fs.append(np.asarray(f, np.int64) + offset)
        offset += len(v)
    return np.vstack(vs), np.vstack(fs)
