"""Faces of the closed chain, their cuts, patch windings and the refinement of cut faces.

Part of :mod:`inertia.geometry.robust` (see its docstring for the method); split off to
keep each module to one job; the kernels are :mod:`inertia._ext.robust`'s.
"""

from __future__ import annotations

import time

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from .._ext import robust as _k

#: A winding W_rest - m/2 this far from an integer is not trusted (the point is too close
#: to another sheet, or the kernel lost accuracy); the face or piece is refined instead.
INTEGER_TOL = 1e-3
#: Distances below this times a face's size count as touching in the cut-face kernels.
REL_TOL = 1e-9


class Pieces:
    """The closed chain (V, F, M) about p, with its cut faces found and refined."""

    def __init__(self, V, F, M, p, eps, cert, nbr, threads=0):
        self.cert, self.nbr = cert, nbr          # certified vertices, face across each manifold edge
        self.V = np.ascontiguousarray(V, dtype=np.float64)
        self.F = np.ascontiguousarray(F, dtype=np.int64)
        self.M = np.ascontiguousarray(M, dtype=np.float64)
        self.p, self.eps, self.threads = p, eps, threads
        self.cut = np.zeros(len(F), bool)
        self.n_cut_pairs = self.n_cut_faces = self.n_patches = 0
        self.w_min, self.w_max = 0.0, 1.0      # extreme windings seen on either side of a face

    def _seen(self, front, m):
        if len(front):
            self.w_min = min(self.w_min, float(front.min()))
            self.w_max = max(self.w_max, float((front + m).max()))

    # ------------------------------------------------------------------ cuts
    def find_cuts(self):
        """Pairs of faces that may cut each other (``cut_lists``): ``cut`` mask and CSR lists of cutters."""
        t = time.perf_counter()
        self.cut_ptr, self.cut_idx = _k.cut_lists(self.V, self.F, self.cert, self.eps, self.threads)
        self.cut = np.diff(self.cut_ptr) > 0
        self.n_cut_pairs, self.n_cut_faces = len(self.cut_idx) // 2, int(self.cut.sum())
        return {"cut_pairs": self.n_cut_pairs, "cut_faces": self.n_cut_faces,
                "certified_vertices": int(self.cert.sum()), "seconds_cuts": time.perf_counter() - t}

    # ------------------------------------------------------------------ patches
    def _winding_front(self, points, owner):
        """``W_rest - m/2`` at points on faces ``owner``; and whether it is near an integer."""
        W = _k.winding_rest(np.ascontiguousarray(points), np.ascontiguousarray(owner, dtype=np.int64),
                            self.V, self.F, self.M, self.threads)
        wf = W - 0.5 * self.M[owner]
        k = np.round(wf)
        return k, np.abs(wf - k) <= INTEGER_TOL

    def patch_weights(self):
        """Weights in {-1, 0, 1} of the uncut faces, their front windings, and the faces to refine."""
        F, uncut = self.F, ~self.cut
        lab, reps = _k.patch_reps(self.V, F, self.nbr, self.cut)
        n_all = len(reps)
        reps = reps[reps >= 0]
        self.n_patches = len(reps)
        kk, good = self._winding_front(self.V[F[reps]].mean(1), reps)
        self._seen(kk[good], self.M[reps[good]])
        wf_lab = np.full(n_all, np.nan)
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
        """Classify every cutter's trace in its face's plane (``classify_traces``)."""
        self.tr_type, self.tr_P, self.tr_J = _k.classify_traces(self.V, self.F, self.M, self.cut_ptr, self.cut_idx,
                                                                self.eps, self.threads)
        self.trace_args = (self.cut_ptr, self.cut_idx, self.tr_type, self.tr_P, self.tr_J)

    def _reference_windings(self, faces, stats):
        """Reference point and front winding of each face to refine: by walks from a known
        neighbour across a manifold edge (repeated until nothing changes), else by the full sum.

        Returns ``(ref (n, 3), w (n,), ok (n,))``.
        """
        n = len(faces)
        cut_ptr, cut_idx, tr_type, _, _ = self.trace_args
        ref, net, ok = _k.reference_points(self.V, self.F, self.M, faces, *self.trace_args, REL_TOL, self.threads)
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
            W = _k.winding_excluding(np.ascontiguousarray(ref[seeds]), faces[seeds], self.V, self.F, self.M, cut_ptr,
                                     cut_idx, tr_type, self.threads)
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
            jump, good = _k.walk_pairs(self.V, self.F, self.M, pairs, ref, slot, *self.trace_args, REL_TOL,
                                       self.threads)
            src = np.where(sa[idx] >= 0, w[np.maximum(sa[idx], 0)], self.wf[a[idx]])
            hit = np.flatnonzero(good)
            if len(hit) == 0:
                return rounds
            w[sb[idx[hit]]] = (src + jump)[hit]          # several neighbours: the last write wins

    @staticmethod
    def _seeds(left, slot, a, b):
        """One face (its row) per connected group of the faces ``left`` (rows) by manifold edges."""
        sa, sb = slot[a], slot[b]
        inside = np.zeros(int(slot.max()) + 1, bool)
        inside[left] = True
        e = (sa >= 0) & (sb >= 0)
        e &= inside[np.maximum(sa, 0)] & inside[np.maximum(sb, 0)]
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
        """Resolve the faces to refine piece by piece (``resolve_pieces``),
        splitting 1 -> 4 the pieces that could not be, until ``good_enough(values, bounds)``
        or a budget ends.  Faces of zero area add nothing and are left out.

        Returns ``(vol, first, second, bound_vol, bound_first, bound_second, stats)``, the
        integrals of the refined faces' boundary parts and the bounds of the unresolved pieces.
        """
        p = self.p
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
            status, pacc, pbnd, w_lo, w_hi = _k.resolve_pieces(
                np.ascontiguousarray(P), owner, rows, ref, w_ref, self.V, self.F, self.M, *self.trace_args, p, REL_TOL,
                self.threads)
            done = status == 0
            stats["pieces_resolved"] += int(done.sum())
            acc += pacc
            sliver += pbnd
            self.w_min, self.w_max = min(self.w_min, w_lo), max(self.w_max, w_hi)
            P, owner, rows = P[~done], owner[~done], rows[~done]
            val = unpacked_sums(acc)
            guess, bnd = _unresolved(np.concatenate([P, P_left]), p, sliver)
            stats["stopped_by"] = ("depth limit" if depth >= max_depth else "piece budget"
                                   if used + 4 * len(P) > max_pieces else "time budget"
                                   if deadline is not None and time.perf_counter() > deadline else None)
            if len(P) == 0 or stats["stopped_by"] or good_enough([a + b for a, b in zip(val, guess)], bnd):
                break
            depth += 1
            P, owner, rows = _split4(P), np.repeat(owner, 4), np.repeat(rows, 4)
        guess, bnd = _unresolved(np.concatenate([P, P_left]), p, sliver)
        val = [a + b for a, b in zip(unpacked_sums(acc), guess)]
        stats.update({"depth": depth, "pieces": used, "pieces_unresolved": len(P) + len(P_left)})
        return val[0], val[1], val[2], bnd[0], bnd[1], bnd[2], stats


def _unresolved(P, p, sliver):
    """Unresolved pieces P (N, 3, 3), weight 1/2 each (their weight lies in [0, 1] or [-1, 0]):
    their integrals, and half their absolute ones plus the slivers' (13,) as the bound."""
    sums, bound = _k.piece_sums(np.ascontiguousarray(P, dtype=np.float64).reshape(-1, 3, 3), p, 0.5)
    b = bound + sliver
    return unpacked_sums(sums), (float(b[0]), b[1:4], b[4:13].reshape(3, 3))


def unpacked_sums(out):
    """(volume, first (3,), second (3, 3)) from 10 sums (``weighted_sums`` of :mod:`inertia._ext.robust`)."""
    xx, yy, zz, xy, xz, yz = out[4:10] / 120.0
    return (float(out[0]) / 6.0, out[1:4] / 24.0, np.array([[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]]))


def _split4(P):
    """Each triangle (N, 3, 3) into its 4 midpoint triangles (4N, 3, 3), same orientation."""
    a, b, c = P[:, 0], P[:, 1], P[:, 2]
    ab, bc, ca = 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)
    out = np.stack([np.stack([a, ab, ca], 1), np.stack([ab, b, bc], 1),
                    np.stack([ca, bc, c], 1), np.stack([ab, bc, ca], 1)], 1)
    return out.reshape(-1, 3, 3)
