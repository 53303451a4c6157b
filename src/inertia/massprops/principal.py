"""Principal moments and axes with a fully deterministic canonical form.

The rule (the *canonical form* of the founding write-up):

1. Moments ascending: ``I1 <= I2 <= I3``.
2. Axes are the columns of ``R_body_principal`` (maps principal coordinates to body
   coordinates: the axes expressed in the body frame), a proper rotation (det +1).
3. Sign rule: axes 1 and 2 each have their largest-magnitude component positive (the first
   such component on exact ties); axis 3 is ``e1 x e2``.
4. Repeated moments (within ``REPEATED_MOMENTS_RTOL * I3``):

   * all three equal: ``R_body_principal`` is the identity;
   * two equal: the distinct axis is taken from the eigensolver (with the sign rule),
     and the first axis of the repeated pair is the projection onto the repeated plane of the
     coordinate axis of F least aligned with the distinct axis (the first on ties); the
     remaining axis completes a right-handed frame.

   The groups of repeated moments are reported so that callers know which axes are a choice.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array


def _unit(v):
    return v / np.linalg.norm(v)


def _plane_axis(n: np.ndarray) -> np.ndarray:
    """Deterministic unit vector perpendicular to n: the coordinate axis least aligned with n, projected."""
    k = int(np.argmin(np.abs(n)))
    e = np.zeros(3)
    e[k] = 1.0
    return _unit(e - np.dot(e, n) * n)


def degenerate_groups(moments, rtol: float = REPEATED_MOMENTS_RTOL) -> tuple[tuple[int, ...], ...]:
    """Groups (tuples of indices, length >= 2) of ascending moments equal within ``rtol * max(moments)``."""
    I = np.asarray(moments, float)
    scale = max(abs(I[-1]), abs(I[0]), np.finfo(float).tiny)
    close01 = abs(I[1] - I[0]) <= rtol * scale
    close12 = abs(I[2] - I[1]) <= rtol * scale
    if close01 and close12:
        return ((0, 1, 2),)
    if close01:
        return ((0, 1),)
    if close12:
        return ((1, 2),)
    return ()


def _sign_fixed(v: list) -> list:
    """v flipped so that its largest-magnitude component is positive (the first one on ties)."""
    k = 0
    for i in (1, 2):
        if abs(v[i]) > abs(v[k]):
            k = i
    return [-x for x in v] if v[k] < 0 else list(v)


def _cross(a: list, b: list) -> list:
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def _canonical_axes_single(moments: np.ndarray, vecs: np.ndarray, rtol: float, groups=None) -> np.ndarray:
    # one 3x3 at a time, in Python floats: the same arithmetic as the vectorised helpers,
    # without NumPy's per-call overhead on 3-vectors (this runs once per mesh in batch runs);
    # ``groups``: degenerate_groups(moments, rtol), when known
    if groups is None:
        groups = degenerate_groups(moments, rtol)
    if groups == ((0, 1, 2),):
        return np.eye(3)  # sphere-like: every frame is principal; choose F itself
    cols = vecs.T.tolist()
    if groups == ((0, 1),):
        e3 = _sign_fixed(cols[2])
        e1 = _plane_axis(np.array(e3)).tolist()
        e2 = _cross(e3, e1)
    elif groups == ((1, 2),):
        e1 = _sign_fixed(cols[0])
        e2 = _plane_axis(np.array(e1)).tolist()
        e3 = _cross(e1, e2)
    else:
        e1 = _sign_fixed(cols[0])
        e2 = _sign_fixed(cols[1])
        e3 = _cross(e1, e2)
    return np.array([e1, e2, e3]).T


def principal_axes(inertia, *, rtol: float = REPEATED_MOMENTS_RTOL) -> tuple[np.ndarray, np.ndarray]:
    """Principal moments and axes of a symmetric inertia matrix, in canonical form.

    Parameters
    ----------
    inertia : (..., 3, 3) float, kg m^2, about the COM, in frame F.
    rtol : float
        Relative tolerance under which moments count as repeated (see module docstring).

    Returns
    -------
    moments : (..., 3) float, kg m^2, ascending.
    R_body_principal : (..., 3, 3) float, principal axes as columns (det +1), so that
        ``inertia = R_body_principal @ diag(moments) @ R_body_principal.T``.
    """
    I = as_float_array(inertia, "inertia", (3, 3))
    if I.ndim == 2:
        moments, R, _ = _principal_single(I, rtol)
        return moments, R
    I = 0.5 * (I + np.swapaxes(I, -1, -2))
    moments, vecs = np.linalg.eigh(I)
    flat_m = moments.reshape(-1, 3)
    flat_v = vecs.reshape(-1, 3, 3)
    out = np.empty_like(flat_v)
    for k in range(flat_m.shape[0]):
        out[k] = _canonical_axes_single(flat_m[k], flat_v[k], rtol)
    return moments, out.reshape(vecs.shape)


def _principal_single(I: np.ndarray, rtol: float):
    """``(moments, R_body_principal, degenerate groups)`` of one checked (3, 3) float64 matrix."""
    moments, vecs = np.linalg.eigh(0.5 * (I + I.T))
    groups = degenerate_groups(moments, rtol)
    return moments, _canonical_axes_single(moments, vecs, rtol, groups), groups


@dataclass(frozen=True)
class PrincipalFrame:
    """Principal moments and axes, with the repeated-moment report.

    Attributes
    ----------
    moments : (3,) float, kg m^2, ascending.
    R_body_principal : (3, 3) float, axes as columns in the original frame F, det +1.
    degenerate : tuple of tuples of int
        Indices of moments equal within ``rtol`` (e.g. ``((0, 1),)`` for a cylinder
        about its axis); empty when all three are distinct.
    rtol : float
        The tolerance that decided ``degenerate``.
    """

    moments: np.ndarray
    R_body_principal: np.ndarray
    degenerate: tuple
    rtol: float


def principal_frame(inertia, *, rtol: float = REPEATED_MOMENTS_RTOL) -> PrincipalFrame:
    """Single-body version of :func:`principal_axes` that also reports degeneracy."""
    moments, R, groups = _principal_single(as_float_array(inertia, "inertia", (3, 3), allow_batch=False), rtol)
    moments.setflags(write=False)
    R.setflags(write=False)
    return PrincipalFrame(moments, R, groups, rtol)


def principal_axes_batch(inertia) -> tuple[np.ndarray, np.ndarray, bool]:
    """``(moments, R_body_principal, principal_is_body)`` of many inertia matrices at once.

    A vectorised route for integrators, which need *a* principal frame but not the
    canonical one: any proper principal frame gives the same motion (the integrators are
    equivariant under the sign changes), so the choice only moves rounding.  Use
    :func:`principal_axes` where the axes are reported.

    Parameters
    ----------
    inertia : (..., 3, 3) float, kg m^2, symmetric (not checked here).

    Returns
    -------
    moments : (..., 3) float, ascending (a body and any rotated copy of it get the same
        axis order, which the splitting methods depend on).
    R_body_principal : (..., 3, 3) float, proper rotations (det +1), principal axes as columns.
    principal_is_body : bool
        True when every matrix is diagonal with an ascending diagonal: then P = B, the
        rotations are the identity and nothing is rounded by a frame change.

    Notes
    -----
    Diagonal input (every product exactly zero): ``R`` is the signed permutation that sorts
    the diagonal (exact; its quaternion has entries 0, 1/2, sqrt(1/2) or 1).  General input:
    the eigenvectors of ``numpy.linalg.eigh`` as columns, the third negated where needed to
    make ``det R = +1``.
    """
    I_B = np.asarray(inertia, dtype=np.float64)
    off = I_B[..., [0, 0, 1], [1, 2, 2]]
    if not np.any(off):
        diag = np.diagonal(I_B, axis1=-2, axis2=-1)
        if np.all(np.diff(diag, axis=-1) >= 0):
            return diag.copy(), np.broadcast_to(np.eye(3), I_B.shape).copy(), True
        order = np.argsort(diag, axis=-1, kind="stable")
        moments = np.take_along_axis(diag, order, axis=-1)
        R = (np.arange(3)[..., :, None] == order[..., None, :]).astype(float)  # R[i, k] = [i == order[k]]
    else:
        moments, R = np.linalg.eigh(I_B)
    det = np.linalg.det(R)
    R[..., :, 2] *= np.where(det < 0, -1.0, 1.0)[..., None]
    return moments, R, False
