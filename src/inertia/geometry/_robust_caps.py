"""Caps closing the boundary of the chain, for :mod:`inertia.geometry.robust`.

A triangle soup is treated as a 2-chain: every face carries an integer multiplicity (a
face listed twice counts twice, once the other way round cancels;
``dedupe_faces``).  Its *boundary* is the set of directed edges whose net
multiplicity is not zero (open edges, or edges where the winding is inconsistent;
``vertex_pass`` of :mod:`inertia._ext.robust`).  Closing each connected piece of that boundary with a
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

from .._ext import robust as _k


class Caps:
    """Caps closing the boundary: the boundary edges (multiplicity 1) split into simple
    cycles, each capped on its own; edges of higher multiplicity, piece by connected piece.

    A cycle whose fan from the mean of its vertices is a flat star (every fan triangle
    positive about the mean normal, angles adding up to one turn) is capped by that fan;
    otherwise a cycle flat within 1e-3 of its size and simple once projected on its plane
    by an ear-clipping triangulation (a flat polygon covered once); anything else by the fan.

    Attributes
    ----------
    apex : (K, 3) float, the mean of each piece's vertices (fan apex k has index ``n_vertices + k``).
    faces : (C, 3) int, cap faces (orientation opposite to the boundary edges).
    mult : (C,) float, their multiplicities.
    piece : (C,) int, the piece of each cap face.
    planar_simple : (K,) bool, the cap is a flat polygon covered once (``|w_cap| < 1/2`` off
        its plane).
    near_flat : (K,) bool, flat_dev : (K,) float, the same within ``flat_dev`` of a plane
        (at most 1e-3 of the cap's size).
    edges : (E, 2) int, edge_mult : (E,) float, edge_piece : (E,) int, the boundary edges.
    """

    def __init__(self, vertices, edges, emult, eps):
        nv = len(vertices)
        piece_of_edge, K = _pieces(edges, emult, nv)
        order = np.argsort(piece_of_edge, kind="stable")
        self.edges, self.edge_mult, self.edge_piece = edges[order], emult[order], piece_of_edge[order]
        edges, emult, piece_of_edge = self.edges, self.edge_mult, self.edge_piece
        cnt = np.bincount(piece_of_edge, minlength=K).astype(float)
        self.apex = np.stack([np.bincount(piece_of_edge, weights=vertices[edges[:, 0], c], minlength=K)
                              for c in range(3)], 1).reshape(K, 3) / np.maximum(cnt, 1)[:, None]
        fan = np.stack([nv + piece_of_edge, edges[:, 1], edges[:, 0]], 1).astype(np.int64)
        self.near_flat, self.flat_dev = np.zeros(K, bool), np.zeros(K)
        star = self._stars(vertices, fan)
        keep = star[piece_of_edge]
        faces, mult, piece = [fan[keep]], [emult[keep]], [piece_of_edge[keep]]
        bounds = np.searchsorted(piece_of_edge, np.arange(K + 1))
        for k in np.flatnonzero(~star):
            sel = slice(bounds[k], bounds[k + 1])
            tri = self._ear_cap(vertices, edges[sel], emult[sel], k)
            if tri is None:
                faces.append(fan[sel])
                mult.append(emult[sel])
                piece.append(piece_of_edge[sel])
            else:
                faces.append(tri)
                mult.append(np.ones(len(tri)))
                piece.append(np.full(len(tri), k))
        self.faces = np.concatenate(faces).astype(np.int64).reshape(-1, 3)
        self.mult = np.concatenate(mult)
        self.piece = np.concatenate(piece).astype(np.int64)
        self.planar_simple = self.near_flat & (self.flat_dev <= eps)

    def _stars(self, vertices, fan):
        """Pieces whose fan is a flat star (within 1e-3 of its size); sets ``near_flat``, ``flat_dev``."""
        K = len(self.apex)
        star = np.zeros(K, bool)
        a = self.apex[self.edge_piece]
        u = vertices[fan[:, 1]] - a
        v = vertices[fan[:, 2]] - a
        n = np.cross(u, v) * self.edge_mult[:, None]
        bounds = np.searchsorted(self.edge_piece, np.arange(K + 1))
        for k in range(K):
            sel = slice(bounds[k], bounds[k + 1])
            nk = n[sel].sum(0)
            ln = np.linalg.norm(nk)
            if ln == 0.0 or np.any(self.edge_mult[sel] != 1):
                continue
            nh = nk / ln
            pts = np.concatenate([u[sel], v[sel]])
            dev = float(np.abs(pts @ nh).max())
            if dev > 1e-3 * float(np.linalg.norm(pts.max(0) - pts.min(0))):
                continue                      # not flat
            s = n[sel] @ nh
            if np.any(s <= 0.0):
                continue                      # fan folds back: not a star around the apex
            # in-plane angles of the fan triangles must add up to one full turn
            un = u[sel] - np.outer(u[sel] @ nh, nh)
            vn = v[sel] - np.outer(v[sel] @ nh, nh)
            if abs(np.arctan2(s, np.einsum("ij,ij->i", un, vn)).sum() - 2.0 * math.pi) < 1e-6:
                star[k] = self.near_flat[k] = True
                self.flat_dev[k] = dev
        return star

    def _ear_cap(self, vertices, edges, emult, k):
        """Ear-clipped cap of piece k when it is one flat loop, simple in its plane; else None."""
        if np.any(emult != 1):
            return None
        nxt = dict(zip(edges[:, 0].tolist(), edges[:, 1].tolist()))
        if len(nxt) != len(edges):
            return None
        loop = [int(edges[0, 0])]
        while len(loop) <= len(edges):
            w = nxt.get(loop[-1])
            if w is None or w == loop[0]:
                break
            loop.append(w)
        if len(loop) != len(edges) or nxt.get(loop[-1]) != loop[0]:
            return None
        P = vertices[loop]
        c = P.mean(0)
        nrm = np.cross(P - c, np.roll(P, -1, axis=0) - c).sum(0)      # Newell
        ln = np.linalg.norm(nrm)
        if ln == 0.0:
            return None
        nrm /= ln
        dev = float(np.abs((P - c) @ nrm).max())
        if dev > 1e-3 * float(np.linalg.norm(P.max(0) - P.min(0))):
            return None
        e1 = np.cross(nrm, [1.0, 0.0, 0.0] if abs(nrm[0]) < 0.9 else [0.0, 1.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(nrm, e1)
        P2 = np.ascontiguousarray(np.stack([(P - c) @ e1, (P - c) @ e2], 1))
        out = _k.ear_clip(P2)
        if out is None:
            return None
        loop = np.asarray(loop)
        self.near_flat[k], self.flat_dev[k] = True, max(dev, float(np.abs((self.apex[k] - c) @ nrm)))
        return np.stack([loop[out[:, 0]], loop[out[:, 2]], loop[out[:, 1]]], 1)      # reversed


def _pieces(edges, emult, nv):
    """Piece of each boundary edge and the number of pieces: the edges of multiplicity 1 split
    into simple cycles (a vertex at most once per cycle), the others by connected piece."""
    piece = np.full(len(edges), -1, np.int64)
    ones = np.flatnonzero(emult == 1)
    out = {}
    for i in ones:
        out.setdefault(int(edges[i, 0]), []).append(int(i))
    K = 0
    for i0 in ones:
        if piece[i0] >= 0:
            continue
        # walk unused edges; a vertex met again closes a simple cycle, cut off the path
        path_v, path_e, where = [int(edges[i0, 0])], [], {int(edges[i0, 0]): 0}
        e = int(i0)
        while e is not None:
            out[int(edges[e, 0])].remove(e)
            piece[e] = -2
            path_e.append(e)
            w = int(edges[e, 1])
            if w in where:
                j = where[w]
                for ee in path_e[j:]:
                    piece[ee] = K
                K += 1
                for vv in path_v[j + 1:]:
                    del where[vv]
                path_v, path_e = path_v[:j + 1], path_e[:j]
            else:
                where[w] = len(path_v)
                path_v.append(w)
            nxt_e = out.get(path_v[-1])
            e = nxt_e[0] if nxt_e else None
        if path_e:            # cannot happen for a boundary (every vertex balanced): keep as one piece
            for ee in path_e:
                piece[ee] = K
            K += 1
    rest = np.flatnonzero(piece < 0)
    if len(rest):
        g = coo_matrix((np.ones(len(rest)), (edges[rest, 0], edges[rest, 1])), shape=(nv, nv))
        _, lab = connected_components(g, directed=False)
        _, inv = np.unique(lab[edges[rest, 0]], return_inverse=True)
        piece[rest] = K + inv
        K += int(inv.max()) + 1
    return piece, K


class CapGeometry:
    """The caps as the octree kernel (``cap_cells`` of :mod:`inertia._ext.robust`) reads them, in *groups*:
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
        group = _coplanar_groups(caps, nrm0, lo0, hi0, eps, self.CV)
        order = np.lexsort((caps.piece, group[caps.piece]))
        G = int(group.max()) + 1 if K0 else 0
        gface = group[caps.piece][order]
        self.ptr = np.searchsorted(gface, np.arange(G + 1)).astype(np.int64)
        self.CF = np.ascontiguousarray(caps.faces[order])
        self.CM = np.ascontiguousarray(caps.mult[order])
        tri = self.CV[self.CF]
        self.face_lo = np.ascontiguousarray(tri.min(1))
        self.face_hi = np.ascontiguousarray(tri.max(1))
        eorder = np.lexsort((caps.edge_piece, group[caps.edge_piece]))
        gedge = group[caps.edge_piece][eorder]
        self.edge_ptr = np.searchsorted(gedge, np.arange(G + 1)).astype(np.int64)
        e = caps.edges[eorder]
        self.E0 = np.ascontiguousarray(vertices[e[:, 0]])
        self.E1 = np.ascontiguousarray(vertices[e[:, 1]])
        self.EM = np.ascontiguousarray(caps.edge_mult[eorder])
        el = np.linalg.norm(self.E1 - self.E0, axis=1) * self.EM
        self.area = np.bincount(gface, weights=fa0[order], minlength=G)
        self.perimeter = np.bincount(gedge, weights=el, minlength=G)
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


def _coplanar_groups(caps, normal, lo, hi, eps, CV):
    """Group index of each cap: nearly flat caps in one plane (normals parallel within 1e-9,
    apexes within 1e-3 of the caps' size of each other's plane) whose boxes meet, any two of
    opposite orientation or with disjoint interiors (then the net coverage stays in
    {-1, 0, 1}).  Caps apart stay alone: each other's share of Delta is small there."""
    K = len(caps.apex)
    group = np.arange(K)
    flat = np.flatnonzero(caps.near_flat)
    diag = np.linalg.norm(hi - lo, axis=1)
    for i_, i in enumerate(flat):
        js = flat[i_ + 1:]
        size = diag[i] + diag[js]
        near = ((np.abs(normal[js] @ normal[i]) >= 1.0 - 1e-9)
                & (np.abs((caps.apex[js] - caps.apex[i]) @ normal[i]) <= 1e-3 * size + eps)
                & ~np.any(lo[js] > hi[i], axis=1) & ~np.any(lo[i] > hi[js], axis=1))
        for j, sz in zip(js[near], size[near]):
            gi, gj = group[i], group[j]
            members = np.flatnonzero((group == gi) | (group == gj))
            if all(float(normal[a] @ normal[b]) < 0.0 or not _boxes_meet(lo, hi, a, b)
                   or _interiors_disjoint(caps, CV, normal[a], a, b, 1e-9 * sz)
                   for a in members for b in members if a < b):
                group[group == gj] = gi
    return np.unique(group, return_inverse=True)[1]


def _boxes_meet(lo, hi, a, b):
    return not (np.any(lo[a] > hi[b]) or np.any(lo[b] > hi[a]))


def _interiors_disjoint(caps, CV, n, a, b, tol):
    """No triangle of cap a overlaps a triangle of cap b by more than ``tol`` (2-D separating
    axes, the edge normals of both triangles, in the plane of normal n)."""
    e1 = np.cross(n, [1.0, 0.0, 0.0] if abs(n[0]) < 0.9 else [0.0, 1.0, 0.0])
    e1 /= np.linalg.norm(e1)
    e2 = np.cross(n, e1)
    ta, tb = CV[caps.faces[caps.piece == a]], CV[caps.faces[caps.piece == b]]
    if len(ta) * len(tb) > 1_000_000:
        return False
    A = np.stack([ta @ e1, ta @ e2], -1)            # (Ta, 3, 2)
    B = np.stack([tb @ e1, tb @ e2], -1)            # (Tb, 3, 2)
    separated = np.zeros((len(A), len(B)), bool)
    for own, other, first in ((A, B, True), (B, A, False)):
        for k in range(3):
            d = own[:, (k + 1) % 3] - own[:, k]
            ax = np.stack([-d[:, 1], d[:, 0]], -1)
            ax /= np.maximum(np.linalg.norm(ax, axis=1), 1e-300)[:, None]
            p_own = np.einsum("tvc,tc->tv", own, ax)            # (To, 3)
            p_oth = np.einsum("svc,tc->tsv", other, ax)         # (To, Ts, 3)
            sep = ((p_oth.min(2) >= p_own.max(1)[:, None] - tol) | (p_oth.max(2) <= p_own.min(1)[:, None] + tol))
            separated |= sep if first else sep.T
    return bool(separated.all())


#: most cell-cap element pairs (cells x (cap faces + loop edges)) one octree examines: each costs a
#: solid angle or a distance, so a soup of thousands of loose triangles (as many caps) stops here
#: (its cells left count whole) instead of running for minutes; a mesh with a few holes never nears it
MAX_CAP_WORK = 200_000_000


def cap_region_bound(geo: CapGeometry, threshold, p, *, max_level=10, max_cells=200_000, enough=0.0, threads=0,
                     max_work=MAX_CAP_WORK, stop=None):
    """Upper bounds of ``int |1|, |y_i|, |y_i y_j|`` (y = x - p) over {x : |w_cap(x)| >= threshold}.

    Adaptive octree over the box around the caps outside which ``|w_cap| < threshold``
    (``|Omega| <= area / d^2``); ``cap_cells`` certifies cells free, or
    (threshold 1/2) bounds the part of a cell near a single flat cap in closed form.
    Cells left at the last level count whole; refinement also stops once the bound is at
    most ``enough``, after ``max_work`` cell-element pairs, or when ``stop(level)`` says so
    (a time budget; it may also report progress).

    Returns ``(volume bound, first (3,), second (3, 3), n_cells_left)``.
    """
    r = math.sqrt(geo.total_area / (4.0 * math.pi * threshold))
    lo, hi = geo.cap_lo.min(0) - r, geo.cap_hi.max(0) + r
    size = float((hi - lo).max())
    centers = (0.5 * (lo + hi))[None, :]
    half = 0.5 * size
    vol, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
    left = 0
    args = (geo.CV, geo.CF, geo.CM, geo.ptr, geo.face_lo, geo.face_hi, geo.E0, geo.E1, geo.EM, geo.edge_ptr,
            geo.flat, geo.area, geo.perimeter, geo.diameter, geo.normal, geo.apex, geo.flat_dev, geo.eps)
    G = len(geo.area)
    near_parts = _NearParts(G)
    per_cell, work = len(geo.CF) + len(geo.E0), 0
    for level in range(max_level + 1):
        status, which, delta, w_rest, contrib = _k.cap_cells(np.ascontiguousarray(centers), half, threshold, *args,
                                                             threads)
        work += len(centers) * per_cell
        cell_vol = (2 * half) ** 3
        n_next = 8 * int((status != 0).sum())
        last = (level == max_level or n_next > max_cells or work + n_next * per_cell > max_work
                or (stop is not None and stop(level)))
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
    dv, df, ds = near_parts.bounds(geo, p)
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

    def bounds(self, geo, p):
        vol, first, second = 0.0, np.zeros(3), np.zeros((3, 3))
        for k in np.flatnonzero(self.delta >= 0):
            d = float(self.delta[k])
            dv = _k.flat_cap_volume(d, float(geo.area[k]), float(geo.perimeter[k]), float(geo.diameter[k]),
                                    float(geo.flat_dev[k]) + geo.eps, math.inf)
            if dv < self.vol[k]:
                h_in, r_max, h_max = _k.flat_cap_heights(d, float(geo.diameter[k]))
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
