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

The eigensolver and the rule are one compiled kernel (``inertia._ext.principal``): cyclic
Jacobi rotations of the symmetric part, accurate to a few ulps of the largest moment at any
scale (a diagonal matrix exactly), the same bits in every process.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array
from .._ext import principal as _k

__all__ = ["PrincipalFrame", "principal_axes"]

#: PrincipalFrame.degenerate from the kernel's bits (1: I1 == I2, 2: I2 == I3)
_GROUPS = {0: (), 1: ((0, 1),), 2: ((1, 2),), 3: ((0, 1, 2),)}


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


def _frames(I: np.ndarray, rtol: float):
    """(moments, R_body_principal, repeated) of (N, 3, 3) matrices from the compiled kernel
    (``src/ext/principal/canonical.hpp``: cyclic Jacobi rotations, then the rule above; a
    diagonal matrix is sorted exactly, its axes a permutation)."""
    return _k.canonical_frames(np.ascontiguousarray(I, dtype=np.float64), float(rtol))


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
    moments, R, _ = _frames(I.reshape(-1, 3, 3), rtol)
    return moments.reshape(I.shape[:-1]), R.reshape(I.shape)


def principal_frame(inertia: np.ndarray, p_body_com: np.ndarray, rtol: float) -> PrincipalFrame:
    """:class:`PrincipalFrame` of one checked (3, 3) matrix (what ``MassProperties.principal`` returns)."""
    moments, R, repeated = _frames(np.reshape(inertia, (1, 3, 3)), rtol)
    groups = _GROUPS[int(repeated[0])]
    m, R, p = moments[0], R[0], np.array(p_body_com, dtype=float)
    for a in (m, R, p):
        a.setflags(write=False)
    return PrincipalFrame(m, R, p, groups, rtol)
