"""Faces of the closed chain, their cuts, patch windings and the refinement of cut faces.

Part of :mod:`inertia.geometry.robust` (see its docstring for the method); split off to
keep each module to one job.  ``kern`` is :mod:`._robust_numba` or :mod:`._robust_kernels`.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

#: A winding W_rest - m/2 this far from an integer is not trusted (the point is too close
#: to another sheet, or the kernel lost accuracy); the face or piece is refined instead.
INTEGER_TOL = 1e-3
#: Distances below this times a face's size count as touching in the cut-face kernels.
REL_TOL = 1e-9


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

    def __init__(self, V, F, M, p, kern, eps, cert, nbr):
        self.cert, self.nbr = cert, nbr          # certified vertices, face across each manifold edge
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
        """Pairs of faces that may cut each other: ``cut`` mask and CSR lists of cutters."""
        t = time.perf_counter()
        nf = len(self.F)
        cert = self.cert
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
                "certified_vertices": int(cert.sum()), "seconds_cuts": time.perf_counter() - t}

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
        self.n_patches_all = k.patch_labels(self.nbr, self.cut, lab)
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
        self.wf = wf
        self.uncut = uncut & ~uncertain
        self.refine_faces = np.flatnonzero(self.cut | uncertain)
        return weights, wf, int(uncertain.sum())

    # ------------------------------------------------------------------ refinement
    def _traces(self):
        """Classify every cutter's trace in its face's plane (:func:`._robust_clip.classify_traces`)."""
        n = len(self.cut_idx)
        owner = np.repeat(np.arange(len(self.F)), np.diff(self.cut_ptr))
        self.tr_type = np.zeros(n, np.int64)
        self.tr_P = np.zeros((n, 3, 3))
        self.tr_J = np.zeros(n)
        self.kern.classify_traces(self.V, self.F, self.M, owner, self.cut_idx, self.eps, self.tr_type, self.tr_P,
                                  self.tr_J)
        self.trace_args = (self.cut_ptr, self.cut_idx, self.tr_type, self.tr_P, self.tr_J)

    def _reference_windings(self, faces, stats):
        """Reference point and front winding of each face to refine: by walks from a known
        neighbour across a manifold edge (repeated until nothing changes), else by the full sum.

        Returns ``(ref (n, 3), w (n,), ok (n,))``.
        """
        k, n = self.kern, len(faces)
        cut_ptr, cut_idx, tr_type, tr_P, tr_J = self.trace_args
        ref, net, ok = np.zeros((n, 3)), np.zeros(n), np.zeros(n, np.bool_)
        k.reference_points(self.V, self.F, faces, cut_ptr, cut_idx, tr_type, tr_P, tr_J, self.M, REL_TOL, ref, net, ok)
        slot = np.full(len(self.F), -1, np.int64)
        slot[faces] = np.arange(n)
        w = np.full(n, np.nan)
        # known front windings: uncut faces (at their centroids), then resolved faces
        known_face = ~np.isnan(self.wf)
        a, b, u, v = self._adjacency()
        rounds, full, tried = 0, 0, np.zeros(n, bool)
        while True:
            rounds += self._walk_rounds(a, b, u, v, slot, known_face, ref, w, ok)
            # the walks stalled: one full sum per group of faces still unknown (then walk on)
            left = np.flatnonzero(ok & np.isnan(w) & ~tried)
            if len(left) == 0:
                break
            seeds = self._seeds(left, slot, a, b)
            tried[seeds] = True
            full += len(seeds)
            W = np.empty(len(seeds))
            k.winding_excluding(np.ascontiguousarray(ref[seeds]), faces[seeds], self.V, self.F, self.M, cut_ptr,
                                cut_idx, tr_type, W)
            wf = W - 0.5 * net[seeds]
            kk = np.round(wf)
            good = np.abs(wf - kk) <= INTEGER_TOL
            w[seeds[good]] = kk[good]
        stats["reference_walk_rounds"] = rounds
        stats["reference_full_sums"] = full
        ok &= ~np.isnan(w)
        return ref, np.nan_to_num(w), ok

    def _walk_rounds(self, a, b, u, v, slot, known_face, ref, w, ok):
        """Walks across manifold edges from faces of known front winding to unknown ones, until
        none is left to try; returns the number of rounds."""
        cut_ptr, cut_idx, tr_type, tr_P, tr_J = self.trace_args
        rounds = 0
        while True:
            sa, sb = slot[a], slot[b]
            ka = np.where(sa >= 0, ~np.isnan(w[np.maximum(sa, 0)]), known_face[a])
            want = (sb >= 0) & ka & np.isnan(w[np.maximum(sb, 0)]) & ok[np.maximum(sb, 0)]
            want &= (sa < 0) | ok[np.maximum(sa, 0)]
            idx = np.flatnonzero(want)
            if len(idx) == 0:
                return rounds
            rounds += 1
            pairs = np.ascontiguousarray(np.stack([a[idx], b[idx], u[idx], v[idx]], 1))
            jump, good = np.zeros(len(idx)), np.zeros(len(idx), np.bool_)
            self.kern.walk_pairs(self.V, self.F, pairs, ref, slot, cut_ptr, tr_type, tr_P, tr_J, cut_idx, self.M,
                                 REL_TOL, jump, good)
            src = np.where(sa[idx] >= 0, w[np.maximum(sa[idx], 0)], self.wf[a[idx]])
            hit = np.flatnonzero(good)
            if len(hit) == 0:
                return rounds
            w[sb[idx[hit]]] = (src + jump)[hit]          # several neighbours: the last write wins

    @staticmethod
    def _seeds(left, slot, a, b):
        """One face (its row) per connected group of the faces ``left`` (rows) by manifold edges."""
        rows = np.full(len(slot), -1, np.int64)
        sa, sb = slot[a], slot[b]
        inside = np.zeros(int(slot.max()) + 1, bool)
        inside[left] = True
        e = (sa >= 0) & (sb >= 0)
        e &= inside[np.maximum(sa, 0)] & inside[np.maximum(sb, 0)]
        del rows
        n = int(slot.max()) + 1
        g = coo_matrix((np.ones(int(e.sum())), (sa[e], sb[e])), shape=(n, n))
        _, lab = connected_components(g, directed=False)
        lab_left = lab[left]
        _, first = np.unique(lab_left, return_index=True)
        return left[first]

    def _adjacency(self):
        """Both directions of the manifold edges joining faces: ``(a, b, u, v)`` (edge u-v)."""
        fa, e = np.nonzero(self.nbr >= 0)
        fb = self.nbr[fa, e]
        return fa, fb, self.F[fa, e], self.F[fa, (e + 1) % 3]

    def refine(self, good_enough, max_pieces, max_depth, deadline):
        """Resolve the faces to refine piece by piece (:func:`._robust_clip.resolve_pieces`),
        splitting 1 -> 4 the pieces that could not be, until ``good_enough(values, bounds)``
        or a budget ends.  Faces of zero area add nothing and are left out.

        Returns ``(vol, first, second, bound_vol, bound_first, bound_second, stats)``, the
        integrals of the refined faces' boundary parts and the bounds of the unresolved pieces.
        """
        p, k = self.p, self.kern
        stats = {"depth": 0, "pieces": 0, "pieces_resolved": 0, "pieces_unresolved": 0}
        acc = np.zeros(10)
        faces = self.refine_faces
        faces = faces[np.any(np.cross(self.V[self.F[faces, 1]] - self.V[self.F[faces, 0]],
                                      self.V[self.F[faces, 2]] - self.V[self.F[faces, 0]]) != 0, axis=1)]
        if len(faces) == 0:
            z = np.zeros(3), np.zeros((3, 3))
            return 0.0, z[0], z[1], 0.0, z[0], z[1], stats
        self._traces()
        ref, w_ref, ok = self._reference_windings(faces, stats)
        stats["faces_without_reference"] = int((~ok).sum())
        slot = np.flatnonzero(ok)
        P = self.V[self.F[faces[slot]]]
        owner, rows = faces[slot], slot
        # faces without a reference winding stay whole and unresolved
        P_left = self.V[self.F[faces[~ok]]]
        used, depth = 0, 0
        sliver = np.zeros(13)          # slivers left undecided inside resolved pieces
        while len(P):
            used += len(P)
            status = np.empty(len(P), np.int64)
            pacc = np.zeros((len(P), 10))
            pbnd = np.zeros((len(P), 13))
            w_seen = np.empty((len(P), 2))
            w_seen[:, 0], w_seen[:, 1] = np.inf, -np.inf
            k.resolve_pieces(np.ascontiguousarray(P), owner, rows, ref, w_ref, self.V, self.F, self.M,
                             *self.trace_args, p, REL_TOL, status, pacc, pbnd, w_seen)
            done = status == 0
            stats["pieces_resolved"] += int(done.sum())
            acc += pacc[done].sum(0)
            sliver += pbnd[done].sum(0)
            if done.any():
                self.w_min = min(self.w_min, float(w_seen[done, 0].min()))
                self.w_max = max(self.w_max, float(w_seen[done, 1].max()))
            P, owner, rows = P[~done], owner[~done], rows[~done]
            val = unpacked_sums(acc)
            half = np.full(len(P) + len(P_left), 0.5)
            allP = np.concatenate([P, P_left])
            bnd = _plus_sliver(tetra_abs(allP, p, half), sliver)
            guess = tetra_sums(allP, p, half)
            out_of_budget = (depth >= max_depth or used + 4 * len(P) > max_pieces
                             or (deadline is not None and time.perf_counter() > deadline))
            if len(P) == 0 or out_of_budget or good_enough([a + b for a, b in zip(val, guess)], bnd):
                break
            depth += 1
            P, owner, rows = _split4(P), np.repeat(owner, 4), np.repeat(rows, 4)
        allP = np.concatenate([P, P_left])
        half = np.full(len(allP), 0.5)
        bnd = _plus_sliver(tetra_abs(allP, p, half), sliver)
        val = [a + b for a, b in zip(unpacked_sums(acc), tetra_sums(allP, p, half))]
        stats.update({"depth": depth, "pieces": used, "pieces_unresolved": len(allP)})
        return val[0], val[1], val[2], bnd[0], bnd[1], bnd[2], stats


def _plus_sliver(bnd, sliver):
    """Bounds (volume, first, second) plus the slivers' (13,: volume, first (3), second (9))."""
    return bnd[0] + sliver[0], bnd[1] + sliver[1:4], bnd[2] + sliver[4:13].reshape(3, 3)


def unpacked_sums(out):
    """(volume, first (3,), second (3, 3)) from 10 sums (see :func:`._robust_topo.weighted_sums`)."""
    xx, yy, zz, xy, xz, yz = out[4:10] / 120.0
    return (float(out[0]) / 6.0, out[1:4] / 24.0, np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))


def _split4(P):
    """Each triangle (N, 3, 3) into its 4 midpoint triangles (4N, 3, 3), same orientation."""
    a, b, c = P[:, 0], P[:, 1], P[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    out = np.stack([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
                    np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)], 1)
    return out.reshape(-1, 3, 3)
