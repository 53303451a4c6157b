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
    near_flat : (K,) bool, flat_dev : (K,) float, the same within ``flat_dev`` of a plane
        (at most 1e-3 of the cap's size).
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
            self.near_flat = np.zeros(0, bool)
            self.flat_dev = np.zeros(0)
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
        """Flat caps: exactly (within eps) and nearly (a star fan projected along its mean normal,
        within 1e-3 of its size of that plane); sets ``flat_dev``, the largest distance of a loop
        vertex from the plane through the apex (0 when exactly flat)."""
        K = len(self.apex)
        out = np.zeros(K, bool)
        self.near_flat = np.zeros(K, bool)
        self.flat_dev = np.zeros(K)
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
            dev = float(np.abs(pts @ nh).max())
            size = float(np.linalg.norm(pts.max(0) - pts.min(0)))
            if dev > 1e-3 * size:
                continue                      # not flat
            s = n[sel] @ nh
            if np.any(s <= 0.0):
                continue                      # fan folds back: not a star around the apex
            # in-plane angles of the fan triangles must add up to one full turn
            un = u[sel] - np.outer(u[sel] @ nh, nh)
            vn = v[sel] - np.outer(v[sel] @ nh, nh)
            ang = np.arctan2(s, np.einsum("ij,ij->i", un, vn)).sum()
            if abs(ang - 2.0 * math.pi) < 1e-6:
                self.near_flat[k] = True
                self.flat_dev[k] = dev
                out[k] = dev <= eps
        return out


class CapGeometry:
    """The caps as the octree kernel (:func:`._robust_capk.cap_cells`) reads them, in *groups*:
    faces and loop edges grouped, boxes, and each group's area, perimeter, diameter, plane and
    flatness.

    A group is one cap, or several (nearly) flat caps in one plane whose coverage stays in
    {-1, 0, 1} (any two of opposite orientation, or of the same orientation with disjoint
    boxes): for the octree's closed-form layer it is one flat region covered once.
    """

    def __init__(self, caps: Caps, vertices, eps):
        K0 = len(caps.apex)
        self.CV = np.ascontiguousarray(np.concatenate([vertices, caps.apex]))
        tri0 = self.CV[caps.faces]
        fa0 = 0.5 * np.linalg.norm(np.cross(tri0[:, 1] - tri0[:, 0], tri0[:, 2] - tri0[:, 0]), axis=1) * caps.mult
        nrm0 = np.zeros((K0, 3))
        np.add.at(nrm0, caps.piece, np.cross(tri0[:, 1] - tri0[:, 0], tri0[:, 2] - tri0[:, 0]) * caps.mult[:, None])
        ln = np.linalg.norm(nrm0, axis=1)
        nrm0 /= np.where(ln > 0, ln, 1.0)[:, None]
        lo0 = np.full((K0, 3), np.inf)
        hi0 = np.full((K0, 3), -np.inf)
        np.minimum.at(lo0, caps.piece, tri0.min(1))
        np.maximum.at(hi0, caps.piece, tri0.max(1))
        group = _coplanar_groups(caps, nrm0, lo0, hi0, eps)
        order = np.lexsort((caps.piece, group[caps.piece]))
        G = int(group.max()) + 1 if K0 else 0
        gface = group[caps.piece][order]
        self.ptr = np.searchsorted(gface, np.arange(G + 1)).astype(np.int64)
        self.CF = np.ascontiguousarray(caps.faces[order])
        self.CM = np.ascontiguousarray(caps.mult[order])
        tri = self.CV[self.CF]
        self.face_lo = np.ascontiguousarray(tri.min(1))
        self.face_hi = np.ascontiguousarray(tri.max(1))
        e = caps.edges[order]
        self.E0 = np.ascontiguousarray(vertices[e[:, 0]])
        self.E1 = np.ascontiguousarray(vertices[e[:, 1]])
        self.EM = np.ascontiguousarray(caps.edge_mult[order])
        el = np.linalg.norm(self.E1 - self.E0, axis=1) * self.EM
        self.area = np.bincount(gface, weights=fa0[order], minlength=G)
        self.perimeter = np.bincount(gface, weights=el, minlength=G)
        self.cap_lo = np.full((G, 3), np.inf)
        self.cap_hi = np.full((G, 3), -np.inf)
        np.minimum.at(self.cap_lo, group, lo0)
        np.maximum.at(self.cap_hi, group, hi0)
        first = np.full(G, -1)
        for k in range(K0 - 1, -1, -1):
            first[group[k]] = k
        self.normal = np.ascontiguousarray(nrm0[first]) if G else np.zeros((0, 3))
        self.apex = np.ascontiguousarray(caps.apex[first]) if G else np.zeros((0, 3))
        # diameter: at most the box diagonal and twice the farthest corner from the apex
        far = np.zeros(G)
        np.maximum.at(far, gface, np.linalg.norm(tri - self.apex[gface][:, None, :], axis=2).max(1))
        self.diameter = np.minimum(np.linalg.norm(self.cap_hi - self.cap_lo, axis=1), 2.0 * far)
        flat = np.ones(G, bool)
        np.logical_and.at(flat, group, caps.near_flat)
        self.flat = np.ascontiguousarray(flat)
        # largest distance of a group's cap vertices from the group's plane
        corner_dev = np.abs(np.einsum("ijk,ik->ij", tri - self.apex[gface][:, None, :], self.normal[gface])).max(1)
        dev = np.zeros(G)
        np.maximum.at(dev, gface, corner_dev)
        self.flat_dev = np.ascontiguousarray(np.where(dev <= eps, 0.0, dev))
        self.eps = float(eps)
        self.total_area = float(fa0.sum())
        self.n_groups = G


def _coplanar_groups(caps, normal, lo, hi, eps):
    """Group index of each cap: nearly flat caps in one plane (normals parallel within 1e-9,
    apexes within 1e-3 of the caps' size of each other's plane) whose boxes meet, any two of
    opposite orientation (then the net coverage stays in {-1, 0, 1}).  Caps apart stay alone:
    each other's share of Delta is small there."""
    K = len(caps.apex)
    group = np.arange(K)
    flat = np.flatnonzero(caps.near_flat)
    for i_, i in enumerate(flat):
        for j in flat[i_ + 1:]:
            c = float(normal[i] @ normal[j])
            size = float(np.linalg.norm(hi[i] - lo[i]) + np.linalg.norm(hi[j] - lo[j]))
            if abs(c) < 1.0 - 1e-9 or abs(float(normal[i] @ (caps.apex[j] - caps.apex[i]))) > 1e-3 * size + eps:
                continue
            if np.any(lo[i] > hi[j]) or np.any(lo[j] > hi[i]):
                continue
            gi, gj = group[i], group[j]
            members = np.flatnonzero((group == gi) | (group == gj))
            if all(float(normal[a] @ normal[b]) < 0.0 or not _boxes_meet(lo, hi, a, b)
                   for a in members for b in members if a < b):
                group[group == gj] = gi
    return np.unique(group, return_inverse=True)[1]


def _boxes_meet(lo, hi, a, b):
    return not (np.any(lo[a] > hi[b]) or np.any(lo[b] > hi[a]))


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
            geo.flat, geo.area, geo.perimeter, geo.diameter, geo.normal, geo.apex, geo.flat_dev, geo.eps)
    G = len(geo.area)
    near_parts = _NearParts(G)
    for level in range(max_level + 1):
        n = len(centers)
        status, which = np.empty(n, np.int64), np.empty(n, np.int64)
        delta, w_rest, contrib = np.empty(n), np.empty(n), np.empty(n)
        kern.cap_cells(np.ascontiguousarray(centers), half, threshold, *args, status, which, delta, w_rest, contrib)
        cell_vol = (2 * half) ** 3
        last = level == max_level or 8 * int((status != 0).sum()) > max_cells
        # a cell near one flat cap is accepted with its closed-form part once that part is
        # within its share of ``enough`` (by the area it covers), or stops shrinking (a cell well
        # inside the cap's size, the other caps' value dominating Delta), or refinement stops
        near = status == 1
        small = half <= 0.25 * geo.diameter[np.maximum(which, 0)]
        share = 0.5 * enough * np.minimum((2 * half) ** 2, geo.area[np.maximum(which, 0)]) / max(geo.total_area, 1e-300)
        accept = near & ((contrib <= share) | ((delta <= 2.0 * w_rest) & small) | last)
        near_parts.add(centers, half, p, which, delta, contrib, accept)
        status[near & ~accept] = 2
        busy = centers[status == 2]
        if len(busy) == 0:
            break
        pending = float(contrib[status == 2].sum())
        if last or vol + near_parts.total() + pending + int(((status == 2) & ~near).sum()) * cell_vol <= enough:
            # stop: near cells with their closed-form parts, the others whole
            near_parts.add(centers, half, p, which, delta, contrib, (status == 2) & near)
            whole = (status == 2) & ~near
            dv, df, ds = _box_bounds(centers[whole], half, p, np.full(int(whole.sum()), cell_vol))
            vol, first, second = vol + dv, first + df, second + ds
            left = int(whole.sum())
            break
        half *= 0.5
        offs = np.array([[i, j, k] for i in (-1, 1) for j in (-1, 1) for k in (-1, 1)], float) * half
        centers = (busy[:, None, :] + offs[None]).reshape(-1, 3)
    dv, df, ds = near_parts.bounds(geo, kern, p)
    return vol + dv, first + df, second + ds, left


class _NearParts:
    """The accepted cells near each flat cap group: their summed closed-form parts, and their
    largest Delta; the bound of a group is the smaller of the sum over its cells and the
    whole-polygon bound for that Delta (both cover the same set)."""

    def __init__(self, G):
        self.vol = np.zeros(G)
        self.first = np.zeros((G, 3))
        self.second = np.zeros((G, 3, 3))
        self.delta = np.full(G, -1.0)

    def add(self, centers, half, p, which, delta, contrib, sel):
        if not sel.any():
            return
        g = which[sel]
        m = np.abs(centers[sel] - p) + half
        c = contrib[sel]
        np.add.at(self.vol, g, c)
        np.add.at(self.first, g, c[:, None] * m)
        np.add.at(self.second, g, c[:, None, None] * m[:, :, None] * m[:, None, :])
        np.maximum.at(self.delta, g, delta[sel])

    def total(self):
        return float(self.vol.sum())

    def bounds(self, geo, kern, p):
        vol, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
        for k in np.flatnonzero(self.delta >= 0):
            d = float(self.delta[k])
            dv = kern.flat_cap_volume(d, float(geo.area[k]), float(geo.perimeter[k]), float(geo.diameter[k]),
                                      float(geo.flat_dev[k]) + geo.eps, math.inf)
            if dv < self.vol[k]:
                h_in, r_max, h_max = kern.flat_cap_heights(d, float(geo.diameter[k]))
                grow = r_max + max(h_in, h_max) + geo.flat_dev[k] + geo.eps
                m = np.maximum(np.abs(geo.cap_lo[k] - grow - p), np.abs(geo.cap_hi[k] + grow - p))
                vol, first, second = vol + dv, first + dv * m, second + dv * np.outer(m, m)
            else:
                vol, first, second = vol + self.vol[k], first + self.first[k], second + self.second[k]
        return vol, first, second


def _box_bounds(centers, half, p, vols):
    """Bounds of the integrals of |1|, |y_i|, |y_i y_j| over parts (volumes ``vols``) of cubes."""
    m = np.abs(centers - p) + half          # max |y_i| over each cube
    return float(vols.sum()), vols @ m, np.einsum("i,ij,ik->jk", vols, m, m)
