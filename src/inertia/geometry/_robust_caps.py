"""Caps closing the boundary of the chain, for :mod:`inertia.geometry.robust`.

A triangle soup is treated as a 2-chain: every face carries an integer multiplicity (a
face listed twice counts twice, once the other way round cancels;
:func:`._robust_topo.dedupe_faces`).  Its *boundary* is the set of directed edges whose net
multiplicity is not zero (open edges, or edges where the winding is inconsistent;
:func:`._robust_topo.boundary_edges`).  Closing each connected piece of that boundary with a
*cap* -- a fan of triangles from the mean of its vertices -- gives a closed chain C' whose
winding number w' is integer everywhere; the generalised winding number of the input is
``w = w' - w_cap``, ``w_cap`` the winding number of the caps alone (Jacobson et al. 2013,
section 3).  :func:`cap_region_bound` bounds the volume where ``|w_cap|`` may reach a
threshold, which is where {w >= 1/2} and {w' >= 1} can differ.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components


class Caps:
    """Fan caps closing the boundary, one per connected piece of it.

    Attributes
    ----------
    apex : (K, 3) float, the fan apexes (mean of each piece's vertices).
    faces : (C, 3) int, cap faces ``(apex, head, tail)``; apex k has index ``n_vertices + k``.
    mult : (C,) float, their multiplicities.
    piece : (C,) int, the boundary piece of each cap face.
    planar_simple : (K,) bool, the piece is one planar loop around its apex, so its cap is
        a flat, simply covered polygon (``|w_cap| < 1/2`` off its plane).
    edges : (E, 2) int, edge_mult : (E,) float, the boundary edges.
    """

    def __init__(self, vertices, edges, emult, eps):
        nv = len(vertices)
        self.edges, self.edge_mult = edges, emult
        if len(edges) == 0:
            self.apex = np.zeros((0, 3))
            self.faces = np.zeros((0, 3), np.int64)
            self.mult = np.zeros(0)
            self.piece = np.zeros(0, np.int64)
            self.planar_simple = np.zeros(0, bool)
            return
        g = coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(nv, nv))
        _, lab = connected_components(g, directed=False)
        piece_of_edge = lab[edges[:, 0]]
        pieces, piece_of_edge = np.unique(piece_of_edge, return_inverse=True)
        K = len(pieces)
        used = np.unique(edges.ravel())
        vp = np.searchsorted(pieces, lab[used])
        cnt = np.bincount(vp, minlength=K)
        apex = np.stack([np.bincount(vp, weights=vertices[used, c], minlength=K) for c in range(3)], 1)
        apex /= cnt[:, None]
        self.apex = apex
        self.faces = np.stack([nv + piece_of_edge, edges[:, 1], edges[:, 0]], 1).astype(np.int64)
        self.mult = emult
        self.piece = piece_of_edge
        self.planar_simple = self._planar_simple(vertices, eps)

    def _planar_simple(self, vertices, eps):
        K = len(self.apex)
        out = np.zeros(K, bool)
        a = self.apex[self.piece]
        u = vertices[self.faces[:, 1]] - a
        v = vertices[self.faces[:, 2]] - a
        n = np.cross(u, v) * self.mult[:, None]
        for k in range(K):
            sel = self.piece == k
            nk = n[sel].sum(0)
            ln = np.linalg.norm(nk)
            if ln == 0.0 or np.any(self.mult[sel] != 1):
                continue
            nh = nk / ln
            pts = np.concatenate([u[sel], v[sel]])
            if np.abs(pts @ nh).max() > eps:
                continue                      # not flat
            s = n[sel] @ nh
            if np.any(s <= 0.0):
                continue                      # fan folds back: not a star around the apex
            # in-plane angles of the fan triangles must add up to one full turn
            cu = np.einsum("ij,ij->i", u[sel], v[sel])
            ang = np.arctan2(s, cu).sum()
            out[k] = abs(ang - 2.0 * math.pi) < 1e-6
        return out


def cap_region_bound(caps: Caps, vertices, threshold, winding, p, *, max_level=7, max_cells=200_000,
                     enough=0.0):
    """Upper bounds of ``int |1|, |y_i|, |y_i y_j|`` (y = x - p) over {x : |w_cap(x)| >= threshold}.

    Adaptive octree over the box around the caps outside which ``|w_cap| < threshold``
    (``|Omega| <= area / d^2``).  A cell that no cap triangle's box reaches is certified
    free when ``|w_cap(center)| + rho |grad w_cap|max < threshold``, the gradient bounded
    by the Biot-Savart form of the cap boundary (the mesh boundary edges):
    ``|grad w_cap| <= sum_e m_e len_e / (4 pi d_e^2)``.  Cells left at the last level
    count whole; refinement also stops once their volume is at most ``enough``.
    ``winding(points, cap_vertices, cap_faces, cap_mult, out)`` evaluates w_cap.

    Returns ``(volume bound, first (3,), second (3, 3), n_cells_left)``.
    """
    cv = np.concatenate([vertices, caps.apex])
    cf = caps.faces
    tri = cv[cf]
    area = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1) * caps.mult
    A = area.sum()
    lo = tri.reshape(-1, 3).min(0)
    hi = tri.reshape(-1, 3).max(0)
    r = math.sqrt(A / (4.0 * math.pi * threshold))
    lo, hi = lo - r, hi + r
    size = (hi - lo).max()
    centers = (0.5 * (lo + hi))[None, :]
    half = 0.5 * size
    tlo = tri.min(1)
    thi = tri.max(1)
    e0 = cv[caps.edges[:, 0]]
    e1 = cv[caps.edges[:, 1]]
    elen = np.linalg.norm(e1 - e0, axis=1) * caps.edge_mult
    vol = 0.0
    first = np.zeros(3)
    second = np.zeros((3, 3))
    left = 0
    for level in range(max_level + 1):
        rho = half * math.sqrt(3.0)
        # distance lower bound from each cell's ball to each cap triangle's box
        dbox = np.sqrt((np.maximum(0.0, np.maximum(tlo[None] - centers[:, None], centers[:, None] - thi[None])) ** 2)
                       .sum(-1)) - rho
        crossing = (dbox <= 0.0).any(1)
        w = np.zeros(len(centers))
        winding(centers, cv, cf, caps.mult, w)
        dedge = _segment_distance(centers, e0, e1) - rho
        with np.errstate(divide="ignore"):
            grad = np.where(dedge > 0, elen[None] / (4.0 * math.pi * np.maximum(dedge, 1e-300) ** 2), np.inf).sum(1)
        free = ~crossing & (np.abs(w) + rho * grad < threshold)
        busy = centers[~free]
        if len(busy) == 0:
            break
        if level == max_level or 8 * len(busy) > max_cells or len(busy) * (2 * half) ** 3 <= enough:
            cv_vol, cf1, cs2 = _box_bounds(busy, half, p)
            vol += cv_vol
            first += cf1
            second += cs2
            left = len(busy)
            break
        half *= 0.5
        offs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float) * half
        centers = (busy[:, None, :] + offs[None]).reshape(-1, 3)
    return vol, first, second, left


def _segment_distance(pts, a, b):
    """Distances (P, E) from points to segments a-b."""
    d = b - a
    dd = np.maximum((d * d).sum(1), 1e-300)
    t = np.clip(((pts[:, None, :] - a[None]) * d[None]).sum(-1) / dd[None], 0.0, 1.0)
    q = a[None] + t[..., None] * d[None]
    return np.linalg.norm(pts[:, None, :] - q, axis=-1)


def _box_bounds(centers, half, p):
    """Bounds of the integrals of |1|, |y_i|, |y_i y_j| over cubes (centers, half side)."""
    vol = (2.0 * half) ** 3
    m = np.abs(centers - p) + half          # max |y_i| over each cube
    return vol * len(centers), vol * m.sum(0), vol * (m[:, :, None] * m[:, None, :]).sum(0)
