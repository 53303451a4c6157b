"""Principal moments and axes in one canonical form, for one body or a batch.

The rule, every clause tested:

1. Moments ascending: ``I1 <= I2 <= I3``.
2. Axes are the columns of ``R_body_principal`` (principal coordinates to body coordinates),
   a proper rotation (det +1).
3. Sign rule: axes 1 and 2 each have their largest-magnitude component positive (the first
   such component on exact ties); axis 3 is ``e1 x e2``.
4. Repeated moments (within ``rtol * I3``, default ``REPEATED_MOMENTS_RTOL``): all three equal
   gives the identity; two equal take the distinct axis from the eigensolver (sign rule), then
   the coordinate axis least aligned with it (the first on ties), projected into the repeated
   plane, and the cross product completes a right-handed frame.  The groups are reported
   (``PrincipalFrame.degenerate``) so that callers know which axes are a choice.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.rotations import cross3
from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array

__all__ = ["PrincipalFrame", "principal_axes"]


@dataclass(frozen=True)
class PrincipalFrame:
    """The principal frame P of a body, in canonical form (see the module docstring).

    Attributes
    ----------
    moments : (3,) float, kg m^2, ascending.
    R_body_principal : (3, 3) float, the principal axes as columns in the body frame, det +1.
    p_body_com : (3,) float, m, the origin of P (the COM) in the body frame.
    degenerate : tuple of tuples of int, the groups of repeated moments (``((0, 1),)`` for a
        symmetric top); empty when all three are distinct.
    rtol : float, the tolerance that decided ``degenerate``.
    """

    moments: np.ndarray
    R_body_principal: np.ndarray
    p_body_com: np.ndarray
    degenerate: tuple
    rtol: float


def _repeated(moments: np.ndarray, rtol: float):
    """``(I1 == I2, I2 == I3)`` within ``rtol`` times the largest moment, (N,) each."""
    scale = np.maximum(np.maximum(np.abs(moments[:, 2]), np.abs(moments[:, 0])), np.finfo(float).tiny)
    gap = np.diff(moments, axis=-1)
    return np.abs(gap[:, 0]) <= rtol * scale, np.abs(gap[:, 1]) <= rtol * scale


def _sign_fixed(v: np.ndarray) -> np.ndarray:
    """Rows of ``v`` (N, 3) flipped so that their largest-magnitude entry is positive (the first on ties)."""
    k = np.argmax(np.abs(v), axis=-1)
    return np.where(v[np.arange(len(v)), k][:, None] < 0, -v, v)


def _plane_axis(n: np.ndarray) -> np.ndarray:
    """The coordinate axis least aligned with each unit row of ``n`` (the first on ties), made
    perpendicular to it and unit."""
    k = np.argmin(np.abs(n), axis=-1)
    e = np.zeros_like(n)
    e[np.arange(len(n)), k] = 1.0
    p = e - n[np.arange(len(n)), k][:, None] * n
    return p / np.linalg.norm(p, axis=-1, keepdims=True)


def _canonical_axes(moments: np.ndarray, vecs: np.ndarray, rtol: float) -> np.ndarray:
    """The canonical ``R_body_principal`` (N, 3, 3) from ascending ``moments`` (N, 3) and any
    eigenvectors ``vecs`` (N, 3, 3, as columns) of them."""
    c01, c12 = _repeated(moments, rtol)
    cols = np.swapaxes(vecs, -1, -2)            # cols[:, i] = axis i
    e1, e2 = _sign_fixed(cols[:, 0]), _sign_fixed(cols[:, 1])
    e3 = cross3(e1, e2)
    # two equal, (1, 2): the distinct axis 3, then its plane
    pair = c01 & ~c12
    if pair.any():
        d = _sign_fixed(cols[pair, 2])
        a = _plane_axis(d)
        e1[pair], e2[pair], e3[pair] = a, cross3(d, a), d
    # two equal, (2, 3): the distinct axis 1, then its plane
    pair = c12 & ~c01
    if pair.any():
        d = e1[pair]
        a = _plane_axis(d)
        e2[pair], e3[pair] = a, cross3(d, a)
    out = np.stack([e1, e2, e3], axis=-1)
    out[c01 & c12] = np.eye(3)                  # every frame is principal: keep the body's
    return out


def _eigen(I: np.ndarray):
    """Ascending eigenvalues and eigenvectors of symmetric (N, 3, 3) matrices; a diagonal matrix
    is sorted exactly (its vectors a permutation), never passed through the eigensolver."""
    off = I[:, [0, 0, 1], [1, 2, 2]]
    if not np.any(off):
        diag = np.diagonal(I, axis1=-2, axis2=-1)
        order = np.argsort(diag, axis=-1, kind="stable")
        vecs = (np.arange(3)[None, :, None] == order[:, None, :]).astype(float)   # vecs[:, i, k] = [i == order[k]]
        return np.take_along_axis(diag, order, axis=-1), vecs
    return np.linalg.eigh(0.5 * (I + np.swapaxes(I, -1, -2)))


def principal_axes(inertia, *, rtol: float = REPEATED_MOMENTS_RTOL) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and axes of symmetric inertia matrices, in canonical form.

    Parameters
    ----------
    inertia : (..., 3, 3) float, kg m^2, about the COM, in the body frame.
    rtol : float, the relative tolerance under which moments count as repeated.

    Returns
    -------
    moments : (..., 3) float, kg m^2, ascending.
    R_body_principal : (..., 3, 3) float, the axes as columns (det +1), so that
        ``inertia = R_body_principal @ diag(moments) @ R_body_principal.T``.
    """
    I = as_float_array(inertia, "inertia", (3, 3))
    flat = I.reshape(-1, 3, 3)
    moments, vecs = _eigen(flat)
    return moments.reshape(I.shape[:-1]), _canonical_axes(moments, vecs, rtol).reshape(I.shape)


def principal_frame(inertia: np.ndarray, p_body_com: np.ndarray, rtol: float) -> PrincipalFrame:
    """:class:`PrincipalFrame` of one checked (3, 3) matrix (what ``MassProperties.principal`` returns)."""
    moments, vecs = _eigen(inertia[None])
    c01, c12 = (bool(x[0]) for x in _repeated(moments, rtol))
    groups = ((0, 1, 2),) if c01 and c12 else ((0, 1),) if c01 else ((1, 2),) if c12 else ()
    R = _canonical_axes(moments, vecs, rtol)[0]
    m, p = moments[0], np.array(p_body_com, dtype=float)
    for a in (m, R, p):
        a.setflags(write=False)
    return PrincipalFrame(m, R, p, groups, rtol)
