"""Faces of the closed chain, their cuts, patch windings and the refinement of cut faces.

Part of :mod:`inertia.geometry.robust` (see its docstring for the method); split off to
keep each module to one job.  ``kern`` is :mod:`._robust_numba` or :mod:`._robust_kernels`.
"""

from __future__ import annotations

import time

import numpy as np

#: A winding W_rest - m/2 this far from an integer is not trusted (the point is too close
#: to another sheet, or the kernel lost accuracy); the face or piece is refined instead.
INTEGER_TOL = 1e-3


def tetra_sums(P, p, w):
    """``sum_i w_i`` of the signed tetrahedron integrals (p, P_i): ``(vol, first (3,), second (3, 3))``."""
    y = P - p
    a, b, c = y[:, 0], y[:, 1], y[:, 2]
    det = np.einsum("ij,ij->i", a, np.cross(b - a, c - a)) * w
    s = a + b + c
    vol = det.sum() / 6.0
    first = det @ s / 24.0
    second = (np.einsum("i,ij,ik->jk", det, a, a) + np.einsum("i,ij,ik->jk", det, b, b)
              + np.einsum("i,ij,ik->jk", det, c, c) + np.einsum("i,ij,ik->jk", det, s, s)) / 120.0
    return vol, first, second


def tetra_abs(P, p, w):
    """Bounds ``sum_i |w_i| int_tet |1|, |y_j|, |y_j y_k|`` (the tetrahedron (p, P_i) has p as a corner)."""
    y = P - p
    a, b, c = y[:, 0], y[:, 1], y[:, 2]
    vol = np.abs(np.einsum("ij,ij->i", a, np.cross(b - a, c - a))) / 6.0 * np.abs(w)
    m = np.abs(y).max(1)
    return vol.sum(), vol @ m, np.einsum("i,ij,ik->jk", vol, m, m)


class Pieces:
    """The closed chain (V, F, M) about p, with its cut faces found and refined."""

    def __init__(self, V, F, M, p, kern, eps):
        self.V = np.ascontiguousarray(V, dtype=np.float64)
        self.F = np.ascontiguousarray(F, dtype=np.int64)
        self.M = np.ascontiguousarray(M, dtype=np.float64)
        self.p, self.kern, self.eps = p, kern, eps
        self.cut = np.zeros(len(F), bool)
        self.n_cut_pairs = self.n_cut_faces = self.n_patches = 0
        self.w_min, self.w_max = 0.0, 1.0      # extreme windings seen on either side of a face

    def _seen(self, front, m):
        if len(front):
            self.w_min = min(self.w_min, float(front.min()))
            self.w_max = max(self.w_max, float((front + m).max()))

    # ------------------------------------------------------------------ cuts
    def find_cuts(self):
        """Pairs of faces that may cut each other: ``cut`` mask and CSR lists of cutters;
        also the manifold edges that join faces into patches (:func:`._robust_topo.vertex_pass`)."""
        t = time.perf_counter()
        k, V, F, nf = self.kern, self.V, self.F, len(self.F)
        ptr = np.empty(len(V) + 1, np.int64)
        idx = np.empty(3 * nf, np.int64)
        k.vertex_faces(F, len(V), False, ptr, idx)
        cert = np.zeros(len(V), np.bool_)
        self.joins = np.empty(3 * nf, np.int64)
        k.vertex_pass(V, F, self.M, ptr, idx, cert, self.joins)
        self.star_idx = idx
        t_cert = time.perf_counter() - t
        pairs = self._grid_pairs(cert)
        if len(pairs):
            nf1 = np.int64(nf + 1)
            pairs = np.unique(pairs[:, 0] * nf1 + pairs[:, 1])
            pairs = np.stack([pairs // nf1, pairs % nf1], 1)
        both = np.concatenate([pairs, pairs[:, ::-1]])
        both = both[np.lexsort((both[:, 1], both[:, 0]))]
        self.cut_ptr = np.searchsorted(both[:, 0], np.arange(nf + 1)).astype(np.int64)
        self.cut_idx = np.ascontiguousarray(both[:, 1])
        self.cut[both[:, 0]] = True
        self.n_cut_pairs, self.n_cut_faces = len(pairs), int(self.cut.sum())
        return {"cut_pairs": self.n_cut_pairs, "cut_faces": self.n_cut_faces,
                "certified_vertices": int(cert.sum()), "seconds_vertices": t_cert,
                "seconds_cuts": time.perf_counter() - t}

    def _grid_pairs(self, cert):
        """Candidate pairs from two uniform grids: a fine one (cell twice the median face box)
        for the faces spanning at most 4 cells per axis, a coarse one for pairs with the rest."""
        V, F = self.V, self.F
        lo, hi = np.empty((len(F), 3)), np.empty((len(F), 3))
        self.kern.face_boxes(V, F, lo, hi)
        d = hi - lo
        ext = np.maximum(np.maximum(d[:, 0], d[:, 1]), d[:, 2])
        origin = np.array([lo[:, c].min() for c in range(3)])
        span_all = max(float(hi[:, c].max() - origin[c]) for c in range(3)) or 1.0
        cell = max(2.0 * float(np.median(ext)), span_all / 1e6, 1e-300)
        origin -= 2.0 * self.eps
        small = np.ascontiguousarray(ext <= 4.0 * cell)
        found = []
        modes = [(0, cell)]
        if not small.all():
            modes.append((1, max(float(ext[~small].max()) / 4.0, span_all / 1e6)))
        for mode, c in modes:
            out = np.empty((len(F) // 4 + 16, 2), np.int64)
            n = self.kern.grid_pairs(V, F, lo, hi, small, cert, mode, origin, c, self.eps, out)
            if n > len(out):
                out = np.empty((n, 2), np.int64)
                self.kern.grid_pairs(V, F, lo, hi, small, cert, mode, origin, c, self.eps, out)
            found.append(out[:n])
        return np.concatenate(found)

    # ------------------------------------------------------------------ patches
    def _winding_front(self, points, owner):
        """``W_rest - m/2`` at points on faces ``owner``; and whether it is near an integer."""
        W = np.empty(len(points))
        self.kern.winding_rest(np.ascontiguousarray(points), np.ascontiguousarray(owner, dtype=np.int64),
                               self.V, self.F, self.M, W)
        wf = W - 0.5 * self.M[owner]
        k = np.round(wf)
        return k, np.abs(wf - k) <= INTEGER_TOL

    def patch_weights(self):
        """Weights in {-1, 0, 1} of the uncut faces, their front windings, and the faces to refine."""
        F, nf, k = self.F, len(self.F), self.kern
        uncut = ~self.cut
        lab = np.empty(nf, np.int64)
        self.n_patches_all = k.patch_labels(self.star_idx, self.joins, self.cut, lab)
        reps = np.empty(self.n_patches_all, np.int64)
        k.patch_reps(self.V, F, lab, uncut, reps)
        reps = reps[reps >= 0]
        self.n_patches = len(reps)
        kk, good = self._winding_front(self.V[F[reps]].mean(1), reps)
        self._seen(kk[good], self.M[reps[good]])
        wf_lab = np.full(self.n_patches_all, np.nan)
        wf_lab[lab[reps]] = np.where(good, kk, np.nan)
        wf = np.where(uncut, wf_lab[lab], np.nan)
        uncertain = uncut & np.isnan(wf)
        safe = np.nan_to_num(wf)
        weights = np.where(np.isnan(wf), 0, (safe + self.M >= 1).astype(int) - (safe >= 1).astype(int))
        self.uncut = uncut & ~uncertain
        self.refine_faces = np.flatnonzero(self.cut | uncertain)
        return weights, wf, int(uncertain.sum())

    # ------------------------------------------------------------------ refinement
    def _piece_windings(self, cen, own):
        """Front windings at piece centroids: by crossings from a reference point on the same
        face (:func:`._robust_kernels.crossing_windings`), the full sum where that is uncertain."""
        k = np.zeros(len(cen))
        good = np.zeros(len(cen), bool)
        if not hasattr(self, "ref_w"):
            self.ref_pt = np.zeros((len(self.F), 3))
            self.ref_w = np.zeros(len(self.F))
            self.has_ref = np.zeros(len(self.F), bool)
        # one full evaluation for each face without a reference point yet
        need = np.flatnonzero(~self.has_ref[own])
        if len(need):
            _, first = np.unique(own[need], return_index=True)
            sel = need[first]
            ks, gs = self._winding_front(cen[sel], own[sel])
            k[sel], good[sel] = ks, gs
            ok = sel[gs]
            self.ref_pt[own[ok]] = cen[ok]
            self.ref_w[own[ok]] = ks[gs]
            self.has_ref[own[ok]] = True
            done = np.zeros(len(cen), bool)
            done[sel] = True
        else:
            done = np.zeros(len(cen), bool)
        rest = np.flatnonzero(~done & self.has_ref[own])
        if len(rest):
            w = np.empty(len(rest))
            okc = np.empty(len(rest), np.bool_)
            self.kern.crossing_windings(np.ascontiguousarray(cen[rest]), np.ascontiguousarray(own[rest]),
                                        self.ref_pt, self.ref_w, self.cut_ptr, self.cut_idx, self.V, self.F,
                                        self.M, 1e-9, w, okc)
            k[rest[okc]], good[rest[okc]] = w[okc], True
            done[rest[okc]] = True
        left = np.flatnonzero(~done)
        if len(left):
            k[left], good[left] = self._winding_front(cen[left], own[left])
        return k, good

    def refine(self, good_enough, max_pieces, max_depth, deadline):
        """Split the faces to refine 1 -> 4 until ``good_enough(bounds)`` or a budget ends.

        Returns ``(vol, first, second, bound_vol, bound_first, bound_second, stats)``, the
        integrals of the refined faces' boundary parts and the bounds of the unresolved pieces.
        """
        p = self.p
        val = [0.0, np.zeros(3), np.zeros((3, 3))]
        owner = self.refine_faces
        P = self.V[self.F[owner]]
        used, depth, clean_n = 0, 0, 0
        B, scratch = np.empty((3, 3)), np.empty(8)
        bnd = (0.0, np.zeros(3), np.zeros((3, 3)))
        while len(P):
            used += len(P)
            clean = np.empty(len(P), np.bool_)
            self.kern.pieces_clean(np.ascontiguousarray(P), owner, self.cut_ptr, self.cut_idx, self.V, self.F,
                                   self.eps, B, scratch, clean)
            idx = np.flatnonzero(clean)
            k, good = self._piece_windings(P[idx].mean(1), owner[idx])
            done = idx[good]
            clean_n += len(done)
            if len(done):
                kd, md = k[good], self.M[owner[done]]
                self._seen(kd, md)
                w = (kd + md >= 1).astype(float) - (kd >= 1).astype(float)
                for i, x in enumerate(tetra_sums(P[done], p, w)):
                    val[i] = val[i] + x
            rest = np.ones(len(P), bool)
            rest[done] = False
            P, owner = P[rest], owner[rest]
            # unresolved if we stop now: weight in [0, 1] (m >= 1), taken as 1/2 +- 1/2
            half = np.full(len(P), 0.5)
            bnd = tetra_abs(P, p, half)
            guess = tetra_sums(P, p, half)
            out_of_budget = (depth >= max_depth or used + 4 * len(P) > max_pieces
                             or (deadline is not None and time.perf_counter() > deadline))
            if len(P) == 0 or out_of_budget or good_enough([a + b for a, b in zip(val, guess)], bnd):
                val = [a + b for a, b in zip(val, guess)]
                break
            depth += 1
            P, owner = _split4(P), np.repeat(owner, 4)
        stats = {"depth": depth, "pieces": used, "pieces_clean": clean_n, "pieces_unresolved": len(P)}
        return val[0], val[1], val[2], bnd[0], bnd[1], bnd[2], stats


def _split4(P):
    """Each triangle (N, 3, 3) into its 4 midpoint triangles (4N, 3, 3), same orientation."""
    a, b, c = P[:, 0], P[:, 1], P[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    out = np.stack([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
                    np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)], 1)
    return out.reshape(-1, 3, 3)
