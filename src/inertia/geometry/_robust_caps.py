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


class CapGeometry:
    """The caps as the octree kernel (:func:`._robust_capk.cap_cells`) reads them: faces and
    loop edges grouped by cap, boxes, and each cap's area, perimeter, diameter and flatness."""

    def __init__(self, caps: Caps, vertices, eps):
        order = np.argsort(caps.piece, kind="stable")
        K = len(caps.apex)
        self.ptr = np.searchsorted(caps.piece[order], np.arange(K + 1)).astype(np.int64)
        self.CV = np.ascontiguousarray(np.concatenate([vertices, caps.apex]))
        self.CF = np.ascontiguousarray(caps.faces[order])
        self.CM = np.ascontiguousarray(caps.mult[order])
        tri = self.CV[self.CF]
        self.face_lo = np.ascontiguousarray(tri.min(1))
        self.face_hi = np.ascontiguousarray(tri.max(1))
        e = caps.edges[order]
        self.E0 = np.ascontiguousarray(vertices[e[:, 0]])
        self.E1 = np.ascontiguousarray(vertices[e[:, 1]])
        self.EM = np.ascontiguousarray(caps.edge_mult[order])
        self.cap_lo = np.array([self.face_lo[a:b].min(0) for a, b in zip(self.ptr[:-1], self.ptr[1:])]).reshape(K, 3)
        self.cap_hi = np.array([self.face_hi[a:b].max(0) for a, b in zip(self.ptr[:-1], self.ptr[1:])]).reshape(K, 3)
        fa = 0.5 * np.linalg.norm(np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]), axis=1) * self.CM
        el = np.linalg.norm(self.E1 - self.E0, axis=1) * self.EM
        self.area = np.add.reduceat(fa, self.ptr[:-1]) if K else np.zeros(0)
        self.perimeter = np.add.reduceat(el, self.ptr[:-1]) if K else np.zeros(0)
        self.diameter = np.linalg.norm(self.cap_hi - self.cap_lo, axis=1)
        self.flat = np.ascontiguousarray(caps.planar_simple)
        nrm = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]) * self.CM[:, None]
        nrm = np.add.reduceat(nrm, self.ptr[:-1], axis=0) if K else np.zeros((0, 3))
        ln = np.linalg.norm(nrm, axis=1)
        self.normal = np.ascontiguousarray(nrm / np.where(ln > 0, ln, 1.0)[:, None])
        self.apex = np.ascontiguousarray(caps.apex)
        self.flat_tol = float(eps)
        self.total_area = float(fa.sum())


def cap_region_bound(geo: CapGeometry, threshold, kern, p, *, max_level=10, max_cells=200_000, enough=0.0):
    """Upper bounds of ``int |1|, |y_i|, |y_i y_j|`` (y = x - p) over {x : |w_cap(x)| >= threshold}.

    Adaptive octree over the box around the caps outside which ``|w_cap| < threshold``
    (``|Omega| <= area / d^2``); :func:`._robust_capk.cap_cells` certifies cells free, or
    (threshold 1/2) bounds the part of a cell near a single flat cap in closed form.
    Cells left at the last level count whole; refinement also stops once the bound is at
    most ``enough``.

    Returns ``(volume bound, first (3,), second (3, 3), n_cells_left)``.
    """
    r = math.sqrt(geo.total_area / (4.0 * math.pi * threshold))
    lo, hi = geo.cap_lo.min(0) - r, geo.cap_hi.max(0) + r
    size = float((hi - lo).max())
    centers = (0.5 * (lo + hi))[None, :]
    half = 0.5 * size
    vol, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    left = 0
    args = (geo.CV, geo.CF, geo.CM, geo.ptr, geo.face_lo, geo.face_hi, geo.E0, geo.E1, geo.EM, geo.ptr,
            geo.flat, geo.diameter, geo.normal, geo.apex, geo.flat_tol)
    K = len(geo.area)
    cap_delta = np.zeros(K)                 # largest Delta of the accepted cells near each flat cap
    # Delta that keeps the flat caps' layers within half of ``enough`` (V_k ~ 4 A_k D_k Delta)
    target = 0.5 * enough / max(4.0 * float(geo.area @ geo.diameter), 1e-300)
    for level in range(max_level + 1):
        n = len(centers)
        status, which = np.empty(n, np.int64), np.empty(n, np.int64)
        delta, w_rest = np.empty(n), np.empty(n)
        kern.cap_cells(np.ascontiguousarray(centers), half, threshold, *args, status, which, delta, w_rest)
        cell_vol = (2 * half) ** 3
        last = level == max_level or 8 * int((status != 0).sum()) > max_cells
        # a cell near one flat cap is accepted once its Delta meets the target, or stops
        # shrinking (a cell well inside the cap's size, the other caps' value dominating),
        # or refinement has to stop
        near = status == 1
        small = half <= 0.25 * geo.diameter[np.maximum(which, 0)]
        accept = near & ((delta <= target) | ((delta <= 2.0 * w_rest) & small) | last)
        np.maximum.at(cap_delta, which[accept], delta[accept])
        status[near & ~accept] = 2
        busy = centers[status == 2]
        if len(busy) == 0:
            break
        if last or _flat_total(geo, cap_delta) + vol + len(busy) * cell_vol <= enough:
            deferred = (status == 2) & near
            np.maximum.at(cap_delta, which[deferred], delta[deferred])
            whole = centers[(status == 2) & ~near]
            dv, df, ds = _box_bounds(whole, half, p, np.full(len(whole), cell_vol))
            vol, first, second = vol + dv, first + df, second + ds
            left = len(whole)
            break
        half *= 0.5
        offs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float) * half
        centers = (busy[:, None, :] + offs[None]).reshape(-1, 3)
    for k in np.flatnonzero(cap_delta > 0):
        dv = kern.flat_cap_volume(float(cap_delta[k]), float(geo.area[k]), float(geo.perimeter[k]),
                                  float(geo.diameter[k]), geo.flat_tol)
        h_in, r_max, h_max = kern.flat_cap_heights(float(cap_delta[k]), float(geo.diameter[k]))
        grow = r_max + max(h_in, h_max) + geo.flat_tol
        m = np.maximum(np.abs(geo.cap_lo[k] - grow - p), np.abs(geo.cap_hi[k] + grow - p))
        vol, first, second = vol + dv, first + dv * m, second + dv * np.outer(m, m)
    return vol, first, second, left


def _flat_total(geo, cap_delta):
    """Sum of the closed-form layer bounds of the flat caps for their current Delta (approximate: 4 A D Delta)."""
    return float(4.0 * (geo.area * geo.diameter) @ cap_delta)


def _box_bounds(centers, half, p, vols):
    """Bounds of the integrals of |1|, |y_i|, |y_i y_j| over parts (volumes ``vols``) of cubes."""
    m = np.abs(centers - p) + half          # max |y_i| over each cube
    return float(vols.sum()), vols @ m, np.einsum("i,ij,ik->jk", vols, m, m)
