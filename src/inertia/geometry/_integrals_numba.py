"""Numba kernels for :mod:`inertia.geometry.integrals` (optional; needs ``numba``).

This module imports ``numba`` at its top, so it must itself only be imported lazily
(:func:`inertia.geometry.integrals._numba_kernels` does so, and falls back to the
NumPy kernels when the import fails).

The kernels compute exactly the same per-face terms as the NumPy backend of
:mod:`~inertia.geometry.integrals` (see its docstring for the formulas and the
error analysis), in one pass over the faces with no temporaries:

* vertices are first shifted by the expansion point ``p``, once per vertex, with the
  same subtraction as the NumPy backend, so both backends see bit-identical local
  coordinates ``y = x - p``;
* sums are blocked: each block of :data:`BLOCK` faces is summed in local scalars and
  the block sums are added to the totals, so the summation error grows like
  ``(BLOCK + F / BLOCK) u`` rather than ``F u``;
* ``fastmath`` is restricted to ``contract`` (fused multiply-add).  Reassociation is
  deliberately *not* allowed: it would license the compiler to rewrite
  ``(x_a - p) + (x_b - p)`` as ``(x_a + x_b) - 2 p``, which reintroduces exactly the
  dependence on the mesh's distance from the origin that the shift removes.

Every kernel checks each vertex index against ``[0, V)`` and returns the index of the
first face holding a bad one (``-1`` when all are valid); the caller raises.

Compiled with ``cache=True`` (the machine code is cached next to this file) and
``nogil=True`` (callers may run several meshes in threads).

Repetition here is deliberate: the kernels are written as flat scalar arithmetic (numba
compiles it to registers; a helper returning tuples, or a loop over the three coordinates,
costs measurably in the inner loops), so a few lines of the same shape recur between kernels
that differ in what they accumulate.  ``duplicates`` lists them; they stay.
"""

from __future__ import annotations

import numba as nb
import numpy as np

#: Faces per block of the blocked summation (see the module docstring).
BLOCK = 256

#: Blocks are added into chunk totals of this many faces, and the chunk totals in order (the
#: summation of :mod:`._solid_numba`, so that both kernels give the same bits).
CHUNK = 64 * BLOCK

_JIT = dict(cache=True, nogil=True, boundscheck=False, fastmath={"contract"})

#: kernels whose cached machine code shows the module warm (:mod:`inertia._core.compiled`)
WARM_PROBE = ("solid_sums", "shell_sums")


@nb.njit(**_JIT)
def bbox_center(vertices, out):
    """Write the center of the axis-aligned bounding box of ``vertices`` (V, 3), V >= 1, into ``out`` (3,)."""
    lo0 = hi0 = vertices[0, 0]
    lo1 = hi1 = vertices[0, 1]
    lo2 = hi2 = vertices[0, 2]
    for j in range(1, vertices.shape[0]):
        x = vertices[j, 0]
        y = vertices[j, 1]
        z = vertices[j, 2]
        lo0 = min(lo0, x)
        hi0 = max(hi0, x)
        lo1 = min(lo1, y)
        hi1 = max(hi1, y)
        lo2 = min(lo2, z)
        hi2 = max(hi2, z)
    # same expression as integrals.reference_point, so both backends agree bit for bit
    out[0] = 0.5 * (lo0 + hi0)
    out[1] = 0.5 * (lo1 + hi1)
    out[2] = 0.5 * (lo2 + hi2)


@nb.njit(**_JIT)
def _shifted(vertices, p):
    """Local coordinates ``y = x - p`` (V, 3), one subtraction per coordinate."""
    nv = vertices.shape[0]
    y = np.empty((nv, 3))
    p0 = p[0]
    p1 = p[1]
    p2 = p[2]
    for j in range(nv):
        y[j, 0] = vertices[j, 0] - p0
        y[j, 1] = vertices[j, 1] - p1
        y[j, 2] = vertices[j, 2] - p2
    return y


@nb.njit(**_JIT)
def solid_sums(vertices, faces, p, out):
    """Unscaled volume sums about ``p``; returns the first bad face index or -1.

    ``out`` (10,) receives ``sum det``, ``sum det s`` (3) and ``sum det Q`` for
    ``Q = a a^T + b b^T + c c^T + s s^T`` in the order xx, yy, zz, xy, yz, zx, where
    ``det = a . ((b - a) x (c - a))`` and ``s = a + b + c`` with ``a, b, c`` the face's corners
    relative to ``p``.  Divide by 6, 24 and 120 for the volume, first and second moments.
    """
    nv = vertices.shape[0]
    nf = faces.shape[0]
    y = _shifted(vertices, p)
    chunk = np.zeros(10)
    for k in range(10):
        out[k] = 0.0
    start = 0
    while start < nf:
        stop = min(start + BLOCK, nf)
        t0 = 0.0
        t1 = 0.0
        t2 = 0.0
        t3 = 0.0
        txx = 0.0
        tyy = 0.0
        tzz = 0.0
        txy = 0.0
        tyz = 0.0
        tzx = 0.0
        for i in range(start, stop):
            ia = faces[i, 0]
            ib = faces[i, 1]
            ic = faces[i, 2]
            if ia < 0 or ia >= nv or ib < 0 or ib >= nv or ic < 0 or ic >= nv:
                return i
            ax = y[ia, 0]
            ay = y[ia, 1]
            az = y[ia, 2]
            bx = y[ib, 0]
            by = y[ib, 1]
            bz = y[ib, 2]
            cx = y[ic, 0]
            cy = y[ic, 1]
            cz = y[ic, 2]
            # det = a . (b x c) = a . ((b - a) x (c - a)) = 6 x signed volume of the
            # tetrahedron (p, a, b, c); the edge form keeps the error relative to |a| |n|,
            # not |a| |b| |c| (a face far from p would otherwise cancel like (rho / h)^2)
            ux = bx - ax
            uy = by - ay
            uz = bz - az
            vx = cx - ax
            vy = cy - ay
            vz = cz - az
            d = ax * (uy * vz - uz * vy) + ay * (uz * vx - ux * vz) + az * (ux * vy - uy * vx)
            sx = ax + bx + cx
            sy = ay + by + cy
            sz = az + bz + cz
            t0 += d
            t1 += d * sx
            t2 += d * sy
            t3 += d * sz
            txx += d * (ax * ax + bx * bx + cx * cx + sx * sx)
            tyy += d * (ay * ay + by * by + cy * cy + sy * sy)
            tzz += d * (az * az + bz * bz + cz * cz + sz * sz)
            txy += d * (ax * ay + bx * by + cx * cy + sx * sy)
            tyz += d * (ay * az + by * bz + cy * cz + sy * sz)
            tzx += d * (az * ax + bz * bx + cz * cx + sz * sx)
        chunk[0] += t0
        chunk[1] += t1
        chunk[2] += t2
        chunk[3] += t3
        chunk[4] += txx
        chunk[5] += tyy
        chunk[6] += tzz
        chunk[7] += txy
        chunk[8] += tyz
        chunk[9] += tzx
        if stop % CHUNK == 0 or stop == nf:      # chunk totals, added in order
            for k in range(10):
                out[k] += chunk[k]
                chunk[k] = 0.0
        start = stop
    return -1


@nb.njit(**_JIT)
def shell_sums(vertices, faces, p, out):
    """Unscaled surface sums about ``p``; returns the first bad face index or -1.

    ``out`` (10,) receives ``sum w``, ``sum w s`` (3) and ``sum w Q`` (xx, yy, zz, xy,
    yz, zx) with ``w = |(b - a) x (c - a)| = 2 x area``.  Divide by 2, 6 and 24 for the
    area, first and second moments.
    """
    nv = vertices.shape[0]
    nf = faces.shape[0]
    y = _shifted(vertices, p)
    for k in range(10):
        out[k] = 0.0
    start = 0
    while start < nf:
        stop = min(start + BLOCK, nf)
        t0 = 0.0
        t1 = 0.0
        t2 = 0.0
        t3 = 0.0
        txx = 0.0
        tyy = 0.0
        tzz = 0.0
        txy = 0.0
        tyz = 0.0
        tzx = 0.0
        for i in range(start, stop):
            ia = faces[i, 0]
            ib = faces[i, 1]
            ic = faces[i, 2]
            if ia < 0 or ia >= nv or ib < 0 or ib >= nv or ic < 0 or ic >= nv:
                return i
            ax = y[ia, 0]
            ay = y[ia, 1]
            az = y[ia, 2]
            bx = y[ib, 0]
            by = y[ib, 1]
            bz = y[ib, 2]
            cx = y[ic, 0]
            cy = y[ic, 1]
            cz = y[ic, 2]
            ux = bx - ax
            uy = by - ay
            uz = bz - az
            vx = cx - ax
            vy = cy - ay
            vz = cz - az
            nx = uy * vz - uz * vy
            ny = uz * vx - ux * vz
            nz = ux * vy - uy * vx
            w = np.sqrt(nx * nx + ny * ny + nz * nz)
            sx = ax + bx + cx
            sy = ay + by + cy
            sz = az + bz + cz
            t0 += w
            t1 += w * sx
            t2 += w * sy
            t3 += w * sz
            txx += w * (ax * ax + bx * bx + cx * cx + sx * sx)
            tyy += w * (ay * ay + by * by + cy * cy + sy * sy)
            tzz += w * (az * az + bz * bz + cz * cz + sz * sz)
            txy += w * (ax * ay + bx * by + cx * cy + sx * sy)
            tyz += w * (ay * az + by * bz + cy * cz + sy * sz)
            tzx += w * (az * ax + bz * bx + cz * cx + sz * sx)
        out[0] += t0
        out[1] += t1
        out[2] += t2
        out[3] += t3
        out[4] += txx
        out[5] += tyy
        out[6] += tzz
        out[7] += txy
        out[8] += tyz
        out[9] += tzx
        start = stop
    return -1
