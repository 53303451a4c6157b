"""Exact volume and surface integrals of triangle meshes (reference NumPy kernel).

Solid (divergence theorem): every face (a, b, c) with the reference point r forms a
signed tetrahedron (r, a, b, c); with vertices taken relative to r,
``det = a . (b x c)``, ``V = det / 6``, ``int x dV = V (a + b + c) / 4``,
``int x x^T dV = det / 120 (a a^T + b b^T + c c^T + s s^T)``, ``s = a + b + c``
(Tonon 2004, "Explicit exact formulas for the 3-D tetrahedron inertia tensor";
Eberly, "Polyhedral mass properties").  Summed over a closed, consistently
outward-wound mesh these are exact.

Thin shell (uniform surface density): ``A = |(b - a) x (c - a)| / 2``,
``int x dA = A s / 3``, ``int x x^T dA = A / 12 (a a^T + b b^T + c c^T + s s^T)``.

Precision: coordinates are shifted by a reference point near the mesh before any
product is formed, so results do not depend on where the mesh lies.
"""

from __future__ import annotations

import numpy as np


def reference_point(vertices: np.ndarray) -> np.ndarray:
    """Center of the axis-aligned bounding box: inside or near the body, cheap, deterministic."""
    return 0.5 * (vertices.min(axis=0) + vertices.max(axis=0))


def solid_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None):
    """Volume integrals of a closed mesh relative to ``reference``.

    Returns
    -------
    volume : float, m^3 (signed: negative when the mesh is wound inward)
    first : (3,) float, ``int (x - r) dV``, m^4
    second : (3, 3) float, ``int (x - r)(x - r)^T dV``, m^5
    reference : (3,) the reference point r used
    """
    r = reference_point(vertices) if reference is None else np.asarray(reference, float)
    tri = vertices[faces] - r
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    det = np.einsum("ij,ij->i", a, np.cross(b, c))
    s = a + b + c
    volume = det.sum() / 6.0
    first = det @ s / 24.0
    second = (np.einsum("f,fi,fj->ij", det, a, a) + np.einsum("f,fi,fj->ij", det, b, b)
              + np.einsum("f,fi,fj->ij", det, c, c) + np.einsum("f,fi,fj->ij", det, s, s)) / 120.0
    return float(volume), first, second, r


def shell_integrals(vertices: np.ndarray, faces: np.ndarray, reference: np.ndarray | None = None):
    """Surface integrals of a triangle mesh relative to ``reference`` (orientation-free).

    Returns ``(area m^2, int (x - r) dA, int (x - r)(x - r)^T dA, r)``.
    """
    r = reference_point(vertices) if reference is None else np.asarray(reference, float)
    tri = vertices[faces] - r
    a, b, c = tri[:, 0], tri[:, 1], tri[:, 2]
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)
    s = a + b + c
    A = area.sum()
    first = area @ s / 3.0
    second = (np.einsum("f,fi,fj->ij", area, a, a) + np.einsum("f,fi,fj->ij", area, b, b)
              + np.einsum("f,fi,fj->ij", area, c, c) + np.einsum("f,fi,fj->ij", area, s, s)) / 12.0
    return float(A), first, second, r


def central_inertia(measure: float, first: np.ndarray, second: np.ndarray, reference: np.ndarray, density: float):
    """Turn integrals into (com (3,), inertia about the COM (3, 3)) for a uniform ``density``.

    ``C = second - measure c c^T`` (c = local COM) is the central second moment;
    the inertia is ``density (tr(C) 1 - C)``.
    """
    c = first / measure
    C = second - measure * np.outer(c, c)
    C = 0.5 * (C + C.T)
    inertia = density * (np.trace(C) * np.eye(3) - C)
    return reference + c, inertia
