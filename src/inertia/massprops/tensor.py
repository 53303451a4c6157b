"""Pure functions on inertia tensors: build, shift, rotate, project, convert.

Convention (the whole package): the inertia matrix holds the *negated* products,
``I = sum m (|r|^2 1 - r r^T)``, so off-diagonal entries are ``-sum m x y`` and
``L = I @ omega``.  Rotation matrices map body to world: ``v_W = R_WB @ v_B``.
All functions accept leading batch dimensions.
"""

from __future__ import annotations

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_float_array

_EYE = np.eye(3)


def point_mass_inertia(masses, positions) -> np.ndarray:
    """Inertia of point masses about the origin of their frame.

    Parameters
    ----------
    masses : (..., N) float, kg
    positions : (..., N, 3) float, m, in the frame F

    Returns
    -------
    (..., 3, 3) float, kg m^2, ``I_ij = sum_k m_k (|r_k|^2 delta_ij - r_ki r_kj)`` about F's origin, in F.
    """
    m = as_float_array(masses, "masses", ())
    r = as_float_array(positions, "positions", (3,))
    if m.shape != r.shape[:-1]:
        raise InputError(f"masses shape {m.shape} does not match positions shape {r.shape} "
                         f"(expected masses (..., N), positions (..., N, 3))")
    # sum_k m_k r_k r_k^T, then I = tr(S) 1 - S
    S = np.einsum("...k,...ki,...kj->...ij", m, r, r)
    return np.trace(S, axis1=-2, axis2=-1)[..., None, None] * _EYE - S


def shift_matrix(mass, offset) -> np.ndarray:
    """Parallel-axis term ``m (|d|^2 1 - d d^T)`` for an offset d (..., 3) [m]; mass (...) [kg]."""
    d = np.asarray(offset, dtype=float)
    m = np.asarray(mass, dtype=float)
    ddT = d[..., :, None] * d[..., None, :]
    return m[..., None, None] * (np.einsum("...i,...i->...", d, d)[..., None, None] * _EYE - ddT)


def inertia_about_point(inertia_com, mass, com, point) -> np.ndarray:
    """Parallel-axis theorem, COM to point: ``I_P = I_com + m (|d|^2 1 - d d^T)``, ``d = com - point``.

    All quantities expressed in the same frame.  Shapes broadcast: (..., 3, 3), (...), (..., 3), (..., 3).
    """
    return np.asarray(inertia_com, float) + shift_matrix(mass, np.asarray(com, float) - np.asarray(point, float))


def inertia_about_com(inertia_point, mass, com, point) -> np.ndarray:
    """Parallel-axis theorem, point to COM: ``I_com = I_P - m (|d|^2 1 - d d^T)``, ``d = com - point``."""
    return np.asarray(inertia_point, float) - shift_matrix(mass, np.asarray(com, float) - np.asarray(point, float))


def rotate_inertia(inertia_B, R_AB) -> np.ndarray:
    """Re-express an inertia matrix from frame B in frame A: ``I_A = R_AB I_B R_AB^T``."""
    R = np.asarray(R_AB, float)
    return R @ np.asarray(inertia_B, float) @ np.swapaxes(R, -1, -2)


def moment_about_line(inertia_com, mass, com, direction, point=None) -> np.ndarray:
    """Moment of inertia [kg m^2] about the line through ``point`` along ``direction``.

    ``D^T I_com D + m |d_perp|^2`` with ``D`` the unit direction and ``d_perp`` the
    component of ``com - point`` perpendicular to the line.  ``point`` defaults to the COM.
    The direction need not be unit length but must be non-zero.
    """
    D = np.asarray(direction, float)
    n = np.linalg.norm(D, axis=-1)
    if np.any(n == 0) or not np.all(np.isfinite(n)):
        raise InputError(f"direction must be a finite non-zero vector, got {D.tolist()}")
    D = D / n[..., None]
    I = np.asarray(inertia_com, float)
    j = np.einsum("...i,...ij,...j->...", D, I, D)
    if point is None:
        return j
    d = np.asarray(com, float) - np.asarray(point, float)
    d_perp = d - np.einsum("...i,...i->...", d, D)[..., None] * D
    return j + np.asarray(mass, float) * np.einsum("...i,...i->...", d_perp, d_perp)


PRODUCT_CONVENTIONS = ("tensor", "cad")


def _check_convention(convention: str) -> float:
    if convention == "tensor":
        return 1.0
    if convention == "cad":
        return -1.0
    raise InputError(f"products convention must be 'tensor' (negated, I_xy = -sum m x y, as in URDF/MJCF/SDF) "
                     f"or 'cad' (positive, P_xy = +sum m x y, as many CAD tools print), got {convention!r}")


def inertia_from_elements(ixx, iyy, izz, ixy=0.0, ixz=0.0, iyz=0.0, *, convention: str = "tensor") -> np.ndarray:
    """Build the (..., 3, 3) inertia matrix from moments and products.

    ``convention='tensor'``: the products are the matrix entries (``ixy = -sum m x y``),
    as URDF, MJCF ``fullinertia`` and SDF write them.  ``convention='cad'``: the
    products are positive integrals ``P_xy = +sum m x y`` (SolidWorks-style), so the
    matrix entry is ``-P_xy``.
    """
    s = _check_convention(convention)
    ixx, iyy, izz, ixy, ixz, iyz = np.broadcast_arrays(*(np.asarray(v, float) for v in (ixx, iyy, izz, ixy, ixz, iyz)))
    out = np.empty(ixx.shape + (3, 3))
    out[..., 0, 0], out[..., 1, 1], out[..., 2, 2] = ixx, iyy, izz
    out[..., 0, 1] = out[..., 1, 0] = s * ixy
    out[..., 0, 2] = out[..., 2, 0] = s * ixz
    out[..., 1, 2] = out[..., 2, 1] = s * iyz
    return out


def elements_from_inertia(inertia, *, convention: str = "tensor") -> dict:
    """Inverse of :func:`inertia_from_elements`: dict of ixx, iyy, izz, ixy, ixz, iyz (arrays of shape (...))."""
    s = _check_convention(convention)
    I = np.asarray(inertia, float)
    return {"ixx": I[..., 0, 0], "iyy": I[..., 1, 1], "izz": I[..., 2, 2],
            "ixy": s * I[..., 0, 1], "ixz": s * I[..., 0, 2], "iyz": s * I[..., 1, 2]}
