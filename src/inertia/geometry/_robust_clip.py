"""Scalar kernels resolving the cut faces of :mod:`inertia.geometry.robust` (plain Python or numba).

Written once in scalar Python like :mod:`._robust_kernels` (compiled by :mod:`._robust_numba`).

On a face f, the winding number just in front of f (``w_front``, of the closed chain) is an
integer, constant except across the *traces* that other faces leave in f's plane:

* type 1, a *jump segment*: a cutter g crossing the plane (or standing on it with an edge,
  in front of f) leaves a segment; ``w_front`` changes by ``J = -m_g sign(nl . n_g)`` when
  moving across it towards the side of its in-plane normal ``nl = n_f x (P1 - P0)``;
* type 2, *coplanar*: a cutter g lying in f's plane (both within ``eps`` of the plane of the
  better shaped of the two, so that f and g agree) stacks on f
  where they overlap; the stack's net multiplicity is ``m_f + sum sigma_g m_g`` (sigma = +-1,
  same or opposite orientation) and the part is counted once, by its lowest face;
* type 3, *ambiguous*: grazing the plane, or f of zero area: pieces touching it are not
  resolved;
* type 0: no effect (touching at a point, standing on the plane behind f, or of zero area).

A piece (a triangle of f) is clipped by the lines of the traces that reach it into convex
cells of constant ``w_front`` and stack (exactly: no trace passes through a cell); each
cell's ``w_front`` comes from a walk from f's reference point, summing the jumps of the
segments crossed.  A walk passing within the tolerance of a segment's end, a type-3 trace,
or too many lines split the piece again (those are points: the unresolved area shrinks
fourfold per level).

The scalar style of :mod:`._robust_kernels` holds here too: loading a face's corners
relative to a point is written out where it is used (a helper returning a 9-tuple costs
measurably in the inner loops); ``duplicates`` lists those few lines.
"""

from __future__ import annotations

import math

import numpy as np

from ._robust_capk import solid_angle
from ._robust_topo import tetra_add

__all__ = ["classify_traces", "reference_points", "walk_pairs", "resolve_pieces", "winding_excluding"]

FOUR_PI = 4.0 * math.pi
#: The compiled twin replaces this with ``numba.prange`` (parallel loops); plain Python runs them in order.
prange = range
#: Most lines a piece is clipped by (more: split it).
LMAX = 16
#: Most cells of a clipped piece, and vertices of a cell.
CMAX = 160
PMAX = 3 + LMAX + 1


def _unit_normal(V, F, f, out):
    ux = V[F[f, 1], 0] - V[F[f, 0], 0]
    uy = V[F[f, 1], 1] - V[F[f, 0], 1]
    uz = V[F[f, 1], 2] - V[F[f, 0], 2]
    vx = V[F[f, 2], 0] - V[F[f, 0], 0]
    vy = V[F[f, 2], 1] - V[F[f, 0], 1]
    vz = V[F[f, 2], 2] - V[F[f, 0], 2]
    nx = uy * vz - uz * vy
    ny = uz * vx - ux * vz
    nz = ux * vy - uy * vx
    ln = math.sqrt(nx * nx + ny * ny + nz * nz)
    if ln > 0.0:
        out[0] = nx / ln
        out[1] = ny / ln
        out[2] = nz / ln
    else:
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
    return ln


def _coplanar(V, F, f, g, lf, lg, nf, ng, eps, d):
    """Faces f and g lie in one plane: all six corners within ``eps`` of the plane of the
    better shaped of the two (largest ``|n| / sum of squared edges``; ties: lower index),
    so that both faces decide alike."""
    qf = lf / _edge_squares(V, F, f)
    qg = lg / _edge_squares(V, F, g)
    h = f if (qf > qg or (qf == qg and f < g)) else g
    n = nf if h == f else ng
    for t in range(2):
        o = g if t == 0 else f
        for i in range(3):
            d[i] = (n[0] * (V[F[o, i], 0] - V[F[h, 0], 0]) + n[1] * (V[F[o, i], 1] - V[F[h, 0], 1])
                    + n[2] * (V[F[o, i], 2] - V[F[h, 0], 2]))
            if abs(d[i]) > eps:
                return False
    return True


def _edge_squares(V, F, f):
    s = 0.0
    for e in range(3):
        for c in range(3):
            x = V[F[f, (e + 1) % 3], c] - V[F[f, e], c]
            s += x * x
    return s


def classify_traces(V, F, M, owner, cut_idx, eps, tr_type, tr_P, tr_J):
    """The trace of cutter ``cut_idx[k]`` in the plane of face ``owner[k]``, for every k.

    ``tr_type[k]`` as in the module docstring; ``tr_P[k]``: type 1 the segment (P0, P1, -),
    type 2 g's corners ordered counter-clockwise about f's normal; ``tr_J[k]``: type 1 the
    jump, type 2 ``sigma m_g``.
    """
    for k in prange(owner.shape[0]):
        nf = np.empty(3)
        ng = np.empty(3)
        dg = np.empty(3)
        df = np.empty(3)
        f = owner[k]
        g = cut_idx[k]
        tr_type[k] = 0
        tr_J[k] = 0.0
        lf = _unit_normal(V, F, f, nf)
        lg = _unit_normal(V, F, g, ng)
        if lg == 0.0:
            continue                      # no area: crossing it changes no winding
        if lf == 0.0:
            tr_type[k] = 3
            continue
        n_pos = 0
        n_neg = 0
        for i in range(3):
            dg[i] = (nf[0] * (V[F[g, i], 0] - V[F[f, 0], 0]) + nf[1] * (V[F[g, i], 1] - V[F[f, 0], 1])
                     + nf[2] * (V[F[g, i], 2] - V[F[f, 0], 2]))
            if dg[i] > eps:
                n_pos += 1
            elif dg[i] < -eps:
                n_neg += 1
        if _coplanar(V, F, f, g, lf, lg, nf, ng, eps, df):
            tr_type[k] = 2
            sig = 1.0 if nf[0] * ng[0] + nf[1] * ng[1] + nf[2] * ng[2] > 0.0 else -1.0
            for i in range(3):
                src = i if sig > 0.0 else 2 - i
                for c in range(3):
                    tr_P[k, i, c] = V[F[g, src], c] - dg[src] * nf[c]
            tr_J[k] = sig * M[g]
            continue
        n_on = 3 - n_pos - n_neg
        if not ((n_pos > 0 and n_neg > 0) or (n_on == 2 and n_pos == 1)):
            continue                      # point contact, or standing behind f: no jump
        # the segment: crossings of g's edges with the plane, and g's corners on it
        n = 0
        for i in range(3):
            if abs(dg[i]) <= eps and n < 2:
                for c in range(3):
                    tr_P[k, n, c] = V[F[g, i], c] - dg[i] * nf[c]
                n += 1
        for i in range(3):
            j = (i + 1) % 3
            if ((dg[i] > eps and dg[j] < -eps) or (dg[i] < -eps and dg[j] > eps)) and n < 2:
                s = dg[i] / (dg[i] - dg[j])
                for c in range(3):
                    tr_P[k, n, c] = V[F[g, i], c] + s * (V[F[g, j], c] - V[F[g, i], c])
                n += 1
        if n != 2:
            tr_type[k] = 3
            continue
        ex = tr_P[k, 1, 0] - tr_P[k, 0, 0]
        ey = tr_P[k, 1, 1] - tr_P[k, 0, 1]
        ez = tr_P[k, 1, 2] - tr_P[k, 0, 2]
        le = math.sqrt(ex * ex + ey * ey + ez * ez)
        if le <= eps:
            continue                      # a point: no line
        # in-plane normal nl = n_f x e; the jump when moving along nl
        lx = nf[1] * ez - nf[2] * ey
        ly = nf[2] * ex - nf[0] * ez
        lz = nf[0] * ey - nf[1] * ex
        s = (lx * ng[0] + ly * ng[1] + lz * ng[2]) / le
        if abs(s) <= 1e-9:
            tr_type[k] = 3                # g grazes the plane along the segment
            continue
        tr_type[k] = 1
        tr_J[k] = -M[g] if s > 0.0 else M[g]


# ---------------------------------------------------------------------------------- 2-D helpers
def _line_of(P0x, P0y, P0z, P1x, P1y, P1z, nf, out):
    """Unit in-plane normal of the line P0 -> P1 (n_f x e / |e|) into out; returns |e| (0: a point)."""
    ex = P1x - P0x
    ey = P1y - P0y
    ez = P1z - P0z
    le = math.sqrt(ex * ex + ey * ey + ez * ez)
    if not le > 0.0:
        out[0] = 0.0
        out[1] = 0.0
        out[2] = 0.0
        return 0.0
    lx = nf[1] * ez - nf[2] * ey
    ly = nf[2] * ex - nf[0] * ez
    lz = nf[0] * ey - nf[1] * ex
    out[0] = lx / le
    out[1] = ly / le
    out[2] = lz / le
    return le


def _segment_vs_piece(P, A0x, A0y, A0z, A1x, A1y, A1z, nf, tol, nl):
    """Where the segment A0 -> A1 (in f's plane) stands with respect to the triangle P:
    0 its line does not enter P's interior (beyond tol), 1 it crosses P completely (no end
    inside, beyond tol), 2 its line crosses P but the segment does not reach it, 3 otherwise
    (an end in or near P).
    ``nl`` receives the line's unit in-plane normal."""
    le = _line_of(A0x, A0y, A0z, A1x, A1y, A1z, nf, nl)
    if le == 0.0:
        return 3
    ux = (A1x - A0x) / le
    uy = (A1y - A0y) / le
    uz = (A1z - A0z) / le
    pos = False
    neg = False
    tmin = math.inf
    tmax = -math.inf
    for i in range(3):
        d = nl[0] * (P[i, 0] - A0x) + nl[1] * (P[i, 1] - A0y) + nl[2] * (P[i, 2] - A0z)
        if d > tol:
            pos = True
        elif d < -tol:
            neg = True
        else:
            t = ux * (P[i, 0] - A0x) + uy * (P[i, 1] - A0y) + uz * (P[i, 2] - A0z)
            tmin = min(tmin, t)
            tmax = max(tmax, t)
        j = (i + 1) % 3
        dj = nl[0] * (P[j, 0] - A0x) + nl[1] * (P[j, 1] - A0y) + nl[2] * (P[j, 2] - A0z)
        if (d > tol and dj < -tol) or (d < -tol and dj > tol):
            s = d / (d - dj)
            t = (ux * (P[i, 0] + s * (P[j, 0] - P[i, 0]) - A0x) + uy * (P[i, 1] + s * (P[j, 1] - P[i, 1]) - A0y)
                 + uz * (P[i, 2] + s * (P[j, 2] - P[i, 2]) - A0z))
            tmin = min(tmin, t)
            tmax = max(tmax, t)
    if not (pos and neg):
        return 0                  # misses P, or touches it at a corner or along an edge only
    if tmax < -tol or tmin > le + tol:
        return 2
    if tmin > tol and tmax < le - tol:
        return 1
    return 3


def _point_side(nl, A0x, A0y, A0z, x, y, z):
    return nl[0] * (x - A0x) + nl[1] * (y - A0y) + nl[2] * (z - A0z)


def _walk(V, F, cut_ptr, tr_type, tr_P, tr_J, f, ax, ay, az, bx, by, bz, nf, tol):
    """Sum of the jumps of f's type-1 traces crossed going from a to b (both in f);
    returns (ok, jump): not ok when a crossing is within ``tol`` of an end of either segment,
    or the walk meets a type-3 trace's cutter."""
    jump = 0.0
    nl = np.empty(3)
    for k in range(cut_ptr[f], cut_ptr[f + 1]):
        t = tr_type[k]
        if t != 1:
            continue
        le = _line_of(tr_P[k, 0, 0], tr_P[k, 0, 1], tr_P[k, 0, 2], tr_P[k, 1, 0], tr_P[k, 1, 1], tr_P[k, 1, 2], nf, nl)
        da = _point_side(nl, tr_P[k, 0, 0], tr_P[k, 0, 1], tr_P[k, 0, 2], ax, ay, az)
        db = _point_side(nl, tr_P[k, 0, 0], tr_P[k, 0, 1], tr_P[k, 0, 2], bx, by, bz)
        if (da > tol and db > tol) or (da < -tol and db < -tol):
            continue
        if abs(da) <= tol or abs(db) <= tol:
            # an end of the walk on the trace's line: fine only if far from the segment
            ux = (tr_P[k, 1, 0] - tr_P[k, 0, 0]) / le
            uy = (tr_P[k, 1, 1] - tr_P[k, 0, 1]) / le
            uz = (tr_P[k, 1, 2] - tr_P[k, 0, 2]) / le
            ta = ux * (ax - tr_P[k, 0, 0]) + uy * (ay - tr_P[k, 0, 1]) + uz * (az - tr_P[k, 0, 2])
            tb = ux * (bx - tr_P[k, 0, 0]) + uy * (by - tr_P[k, 0, 1]) + uz * (bz - tr_P[k, 0, 2])
            if (ta < -tol and tb < -tol) or (ta > le + tol and tb > le + tol):
                continue
            return False, 0.0
        s = da / (da - db)
        ux = (tr_P[k, 1, 0] - tr_P[k, 0, 0]) / le
        uy = (tr_P[k, 1, 1] - tr_P[k, 0, 1]) / le
        uz = (tr_P[k, 1, 2] - tr_P[k, 0, 2]) / le
        t = (ux * (ax + s * (bx - ax) - tr_P[k, 0, 0]) + uy * (ay + s * (by - ay) - tr_P[k, 0, 1])
             + uz * (az + s * (bz - az) - tr_P[k, 0, 2]))
        if t < -tol or t > le + tol:
            continue
        if t <= tol or t >= le - tol:
            return False, 0.0
        jump += tr_J[k] if db > 0.0 else -tr_J[k]
    return True, jump


def _stack_at(cut_ptr, cut_idx, tr_type, tr_P, tr_J, f, x, y, z, nf, tol, M):
    """(net multiplicity, leader, ok) of the coplanar stack at the point (x, y, z) of f;
    not ok when the point is within ``tol`` of a coplanar cutter's edge."""
    net = M[f]
    leader = True
    nl = np.empty(3)
    for k in range(cut_ptr[f], cut_ptr[f + 1]):
        if tr_type[k] != 2:
            continue
        inside = True
        for e in range(3):
            a = e
            b = (e + 1) % 3
            le = _line_of(tr_P[k, a, 0], tr_P[k, a, 1], tr_P[k, a, 2], tr_P[k, b, 0], tr_P[k, b, 1], tr_P[k, b, 2],
                          nf, nl)
            d = _point_side(nl, tr_P[k, a, 0], tr_P[k, a, 1], tr_P[k, a, 2], x, y, z)
            if le == 0.0 or abs(d) <= tol:
                return net, leader, False
            if d < 0.0:
                inside = False
        if inside:
            net += tr_J[k]
            if cut_idx[k] < f:
                leader = False
    return net, leader, True


def _near_type3(V, F, cut_ptr, cut_idx, tr_type, f, x, y, z, nf, tol):
    """The point lies within ``tol`` of the shadow, in f's plane, of a type-3 cutter."""
    nl = np.empty(3)
    for k in range(cut_ptr[f], cut_ptr[f + 1]):
        if tr_type[k] != 3:
            continue
        g = cut_idx[k]
        # shadow of g: its corners projected; inside (within tol) of all three edge lines
        # of either orientation
        s_pos = True
        s_neg = True
        for e in range(3):
            a = F[g, e]
            b = F[g, (e + 1) % 3]
            le = _line_of(V[a, 0], V[a, 1], V[a, 2], V[b, 0], V[b, 1], V[b, 2], nf, nl)
            if le == 0.0:
                return True
            d = _point_side(nl, V[a, 0], V[a, 1], V[a, 2], x, y, z)
            if d < -tol:
                s_pos = False
            if d > tol:
                s_neg = False
        if s_pos or s_neg:
            return True
    return False


def reference_points(V, F, faces, cut_ptr, cut_idx, tr_type, tr_P, tr_J, M, rel_tol, ref, net, ok):
    """A point of each face in ``faces`` away (``rel_tol`` x its size) from every trace: its
    centroid or another fixed barycentric point; ``net`` the stack's net multiplicity there."""
    for i in prange(faces.shape[0]):
        nf = np.empty(3)
        f = faces[i]
        _unit_normal(V, F, f, nf)
        size = 0.0
        for c in range(3):
            size = max(size, abs(V[F[f, 1], c] - V[F[f, 0], c]), abs(V[F[f, 2], c] - V[F[f, 0], c]))
        tol = rel_tol * size
        ok[i] = False
        for trial in range(16):
            # the centroid, then points of an additive recurrence (golden ratios): off the
            # medians and any rational line a symmetric mesh may draw
            w0 = 1.0 / 3.0
            w1 = 1.0 / 3.0
            if trial > 0:
                a = (0.5 + trial * 0.6180339887498949) % 1.0
                b = (0.5 + trial * 0.7548776662466927) % 1.0
                if a + b > 1.0:
                    a = 1.0 - a
                    b = 1.0 - b
                w0 = 0.05 + 0.9 * a
                w1 = 0.05 + 0.9 * b * (1.0 - a)
            w2 = 1.0 - w0 - w1
            x = w0 * V[F[f, 0], 0] + w1 * V[F[f, 1], 0] + w2 * V[F[f, 2], 0]
            y = w0 * V[F[f, 0], 1] + w1 * V[F[f, 1], 1] + w2 * V[F[f, 2], 1]
            z = w0 * V[F[f, 0], 2] + w1 * V[F[f, 1], 2] + w2 * V[F[f, 2], 2]
            if not _clear_of_traces(cut_ptr, tr_type, tr_P, f, x, y, z, nf, tol):
                continue
            if _near_type3(V, F, cut_ptr, cut_idx, tr_type, f, x, y, z, nf, tol):
                continue
            n, _, good = _stack_at(cut_ptr, cut_idx, tr_type, tr_P, tr_J, f, x, y, z, nf, tol, M)
            if not good:
                continue
            ref[i, 0] = x
            ref[i, 1] = y
            ref[i, 2] = z
            net[i] = n
            ok[i] = True
            break


def _clear_of_traces(cut_ptr, tr_type, tr_P, f, x, y, z, nf, tol):
    """The point is farther than ``tol`` from every type-1 segment of f."""
    for k in range(cut_ptr[f], cut_ptr[f + 1]):
        if tr_type[k] != 1:
            continue
        ex = tr_P[k, 1, 0] - tr_P[k, 0, 0]
        ey = tr_P[k, 1, 1] - tr_P[k, 0, 1]
        ez = tr_P[k, 1, 2] - tr_P[k, 0, 2]
        qx = x - tr_P[k, 0, 0]
        qy = y - tr_P[k, 0, 1]
        qz = z - tr_P[k, 0, 2]
        ee = ex * ex + ey * ey + ez * ez
        t = min(1.0, max(0.0, (qx * ex + qy * ey + qz * ez) / ee)) if ee > 0.0 else 0.0
        dx = qx - t * ex
        dy = qy - t * ey
        dz = qz - t * ez
        if dx * dx + dy * dy + dz * dz <= tol * tol:
            return False
    return True


def winding_excluding(pts, owner, V, F, M, cut_ptr, cut_idx, tr_type, out):
    """Generalised winding number at ``pts`` leaving out face ``owner[i]`` and its coplanar
    (type-2) cutters: the full sum, less the same terms for those faces."""
    for i in prange(pts.shape[0]):
        px = pts[i, 0]
        py = pts[i, 1]
        pz = pts[i, 2]
        o = owner[i]
        s = 0.0
        for f in range(F.shape[0]):
            if f != o:
                s += M[f] * solid_angle(V, F, f, px, py, pz)
        for k in range(cut_ptr[o], cut_ptr[o + 1]):
            if tr_type[k] == 2:
                s -= M[cut_idx[k]] * solid_angle(V, F, cut_idx[k], px, py, pz)
        out[i] = s / FOUR_PI


def walk_pairs(V, F, pairs, ref, face_slot, cut_ptr, tr_type, tr_P, tr_J, cut_idx, M, rel_tol, jump, ok):
    """Jumps of ``w_front`` from face a's point to face b's point across their common edge
    (a, b, u, v) = ``pairs[i]``: a's point -> edge midpoint on a, midpoint -> b's point on b.

    ``face_slot[f]`` indexes ``ref`` (-1: no point; then the centroid, for an uncut face).
    Not ok when a walk is borderline or the midpoint is near a trace of either face (then
    another sheet passes there and the front sides of a and b need not meet), or a coplanar
    stack covers the midpoint, unless a and b lie in one plane (the same orientation) with
    stacks of equal net multiplicity there (the stack then runs on across the edge).
    """
    for i in prange(pairs.shape[0]):
        nf = np.empty(3)
        na = np.empty(3)
        a = pairs[i, 0]
        b = pairs[i, 1]
        u = pairs[i, 2]
        v = pairs[i, 3]
        mx = 0.5 * (V[u, 0] + V[v, 0])
        my = 0.5 * (V[u, 1] + V[v, 1])
        mz = 0.5 * (V[u, 2] + V[v, 2])
        total = 0.0
        good = True
        extra_a = 0.0
        for leg in range(2):
            f = a if leg == 0 else b
            _unit_normal(V, F, f, nf)
            size = 0.0
            for c in range(3):
                size = max(size, abs(V[F[f, 1], c] - V[F[f, 0], c]), abs(V[F[f, 2], c] - V[F[f, 0], c]))
            tol = rel_tol * size
            s = face_slot[f]
            if s >= 0:
                x = ref[s, 0]
                y = ref[s, 1]
                z = ref[s, 2]
            else:
                x = (V[F[f, 0], 0] + V[F[f, 1], 0] + V[F[f, 2], 0]) / 3.0
                y = (V[F[f, 0], 1] + V[F[f, 1], 1] + V[F[f, 2], 1]) / 3.0
                z = (V[F[f, 0], 2] + V[F[f, 1], 2] + V[F[f, 2], 2]) / 3.0
            if not _clear_of_traces(cut_ptr, tr_type, tr_P, f, mx, my, mz, nf, tol):
                good = False
                break
            if _near_type3(V, F, cut_ptr, cut_idx, tr_type, f, mx, my, mz, nf, tol):
                good = False
                break
            n, _, g2 = _stack_at(cut_ptr, cut_idx, tr_type, tr_P, tr_J, f, mx, my, mz, nf, tol, M)
            if not g2:
                good = False
                break
            if leg == 0:
                extra_a = n - M[f]
                for c in range(3):
                    na[c] = nf[c]
            elif extra_a != 0.0 or n != M[f]:
                flat = nf[0] * na[0] + nf[1] * na[1] + nf[2] * na[2] > 1.0 - 1e-12
                if not (flat and n - M[f] == extra_a):
                    good = False
                    break
            if leg == 0:
                w_ok, j = _walk(V, F, cut_ptr, tr_type, tr_P, tr_J, f, x, y, z, mx, my, mz, nf, tol)
            else:
                w_ok, j = _walk(V, F, cut_ptr, tr_type, tr_P, tr_J, f, mx, my, mz, x, y, z, nf, tol)
            if not w_ok:
                good = False
                break
            total += j
        ok[i] = good
        jump[i] = total


# ---------------------------------------------------------------------------------- pieces
def _clip(cells, ncv, sides, n_cells, nl, L0x, L0y, L0z, bit, tol):
    """Split every cell by the line (unit in-plane normal nl through L0); the + part gets ``bit``."""
    n = n_cells
    tmp_d = np.empty(PMAX)
    for c in range(n_cells):
        m = ncv[c]
        has_pos = False
        has_neg = False
        for i in range(m):
            d = nl[0] * (cells[c, i, 0] - L0x) + nl[1] * (cells[c, i, 1] - L0y) + nl[2] * (cells[c, i, 2] - L0z)
            tmp_d[i] = d
            if d > tol:
                has_pos = True
            elif d < -tol:
                has_neg = True
        if not (has_pos and has_neg):
            if has_pos:
                sides[c] |= bit
            continue
        if n >= CMAX:
            return -1
        # the new cell n takes the + part, cell c keeps the - part
        npos = 0
        nneg = 0
        neg = np.empty((PMAX, 3))
        for i in range(m):
            j = (i + 1) % m
            di = tmp_d[i]
            dj = tmp_d[j]
            if di >= 0.0:
                for k in range(3):
                    cells[n, npos, k] = cells[c, i, k]
                npos += 1
            if di <= 0.0:
                for k in range(3):
                    neg[nneg, k] = cells[c, i, k]
                nneg += 1
            if (di > 0.0 and dj < 0.0) or (di < 0.0 and dj > 0.0):
                s = di / (di - dj)
                for k in range(3):
                    x = cells[c, i, k] + s * (cells[c, j, k] - cells[c, i, k])
                    cells[n, npos, k] = x
                    neg[nneg, k] = x
                npos += 1
                nneg += 1
            if npos >= PMAX or nneg >= PMAX:
                return -1
        for i in range(nneg):
            for k in range(3):
                cells[c, i, k] = neg[i, k]
        ncv[c] = nneg
        ncv[n] = npos
        sides[n] = sides[c] | bit
        n += 1
    return n


def _cell_area_centroid(cells, ncv, c, nf, out):
    """Signed area (about nf) and centroid (into out) of the convex polygon cell c."""
    m = ncv[c]
    cx = 0.0
    cy = 0.0
    cz = 0.0
    area = 0.0
    for i in range(1, m - 1):
        ux = cells[c, i, 0] - cells[c, 0, 0]
        uy = cells[c, i, 1] - cells[c, 0, 1]
        uz = cells[c, i, 2] - cells[c, 0, 2]
        vx = cells[c, i + 1, 0] - cells[c, 0, 0]
        vy = cells[c, i + 1, 1] - cells[c, 0, 1]
        vz = cells[c, i + 1, 2] - cells[c, 0, 2]
        a = 0.5 * (nf[0] * (uy * vz - uz * vy) + nf[1] * (uz * vx - ux * vz) + nf[2] * (ux * vy - uy * vx))
        area += a
        cx += a * (cells[c, 0, 0] + cells[c, i, 0] + cells[c, i + 1, 0]) / 3.0
        cy += a * (cells[c, 0, 1] + cells[c, i, 1] + cells[c, i + 1, 1]) / 3.0
        cz += a * (cells[c, 0, 2] + cells[c, i, 2] + cells[c, i + 1, 2]) / 3.0
    if area != 0.0:
        out[0] = cx / area
        out[1] = cy / area
        out[2] = cz / area
    return area


def _add_cell(cells, ncv, c, weight, p, acc):
    """acc (10,) += weight x the tetrahedron sums (apex p) of the fan triangles of cell c."""
    for i in range(1, ncv[c] - 1):
        tetra_add(acc, weight, cells[c, 0, 0] - p[0], cells[c, 0, 1] - p[1], cells[c, 0, 2] - p[2],
                  cells[c, i, 0] - p[0], cells[c, i, 1] - p[1], cells[c, i, 2] - p[2],
                  cells[c, i + 1, 0] - p[0], cells[c, i + 1, 1] - p[1], cells[c, i + 1, 2] - p[2])


def resolve_pieces(P, owner, slot, ref, w_ref, V, F, M, cut_ptr, cut_idx, tr_type, tr_P, tr_J, p, rel_tol,
                   status, acc, bnd, w_seen):
    """Resolve pieces ``P`` (N, 3, 3) of faces ``owner`` (``slot``: the row of ``ref``/``w_ref``).

    ``status[i]``: 0 resolved (its cells' boundary weights times their tetrahedron sums are
    added to ``acc[i]`` (10,); slivers left undecided add their absolute sums to ``bnd[i]``
    (13,: volume, first (3), second (9))), 1 to split.  ``w_seen[i]``: (min front, max back)
    winding met.
    """
    for i in prange(P.shape[0]):
        status[i] = _resolve_one(P, i, owner[i], slot[i], ref, w_ref, V, F, M, cut_ptr, cut_idx, tr_type, tr_P,
                                 tr_J, p, rel_tol, acc, bnd, w_seen)


def _resolve_one(P, i, f, s, ref, w_ref, V, F, M, cut_ptr, cut_idx, tr_type, tr_P, tr_J, p, rel_tol, acc, bnd,
                 w_seen):
    """One piece of :func:`resolve_pieces`: 0 resolved, 1 to split.

    The piece is clipped by the full line of every trace that reaches it (a jump segment
    ending inside the piece too: its line beyond the end only splits cells of equal
    winding; a coplanar triangle is the intersection of three half-planes).  Each cell's
    ``w_front`` comes from a walk from the reference point (or from a cell already
    known); a borderline walk, a type-3 trace, or too many lines: split the piece.

    One kernel that reads better whole (its phases share the piece's lines and cells).
    """
    nf = np.empty(3)
    nl = np.empty(3)
    _unit_normal(V, F, f, nf)
    size = 0.0
    for c in range(3):
        size = max(size, abs(V[F[f, 1], c] - V[F[f, 0], c]), abs(V[F[f, 2], c] - V[F[f, 0], c]))
    tol = rel_tol * size
    Pi = P[i]
    n_tr = cut_ptr[f + 1] - cut_ptr[f]
    # 1. the lines reaching the piece
    lines = np.empty((LMAX, 6))          # L0 (3), nl (3)
    nlines = 0
    side_fixed = np.zeros((n_tr, 3), np.int64)    # coplanar edge line missing the piece: side +1 / -1
    line_of = np.full((n_tr, 3), -1, np.int64)
    flip = np.zeros((n_tr, 3), np.bool_)
    for k in range(cut_ptr[f], cut_ptr[f + 1]):
        t = tr_type[k]
        if t == 0:
            continue
        if t == 3:
            if _piece_near_type3(V, F, cut_idx[k], Pi, nf, tol):
                return 1
            continue
        for e in range(1 if t == 1 else 3):
            a = e if t == 2 else 0
            b = (e + 1) % 3 if t == 2 else 1
            r = _segment_vs_piece(Pi, tr_P[k, a, 0], tr_P[k, a, 1], tr_P[k, a, 2], tr_P[k, b, 0], tr_P[k, b, 1],
                                  tr_P[k, b, 2], nf, tol, nl)
            if t == 1 and (r == 0 or r == 2):
                continue                  # the segment misses the piece
            if t == 2 and r == 0:
                d = 0.0
                for q in range(3):
                    dq = _point_side(nl, tr_P[k, a, 0], tr_P[k, a, 1], tr_P[k, a, 2], Pi[q, 0], Pi[q, 1], Pi[q, 2])
                    if abs(dq) > abs(d):
                        d = dq
                side_fixed[k - cut_ptr[f], e] = 1 if d > 0.0 else -1
                continue
            same = _same_line(lines, nlines, nl, tr_P[k, a, 0], tr_P[k, a, 1], tr_P[k, a, 2], tol)
            if same != 0:
                # a line already there (a shared edge): the same bit, maybe the other way round
                line_of[k - cut_ptr[f], e] = abs(same) - 1
                flip[k - cut_ptr[f], e] = same < 0
                continue
            if nlines >= LMAX:
                return 1
            for c in range(3):
                lines[nlines, c] = tr_P[k, a, c]
                lines[nlines, 3 + c] = nl[c]
            line_of[k - cut_ptr[f], e] = nlines
            nlines += 1
    # 2. cells
    cells = np.empty((CMAX, PMAX, 3))
    ncv = np.zeros(CMAX, np.int64)
    sides = np.zeros(CMAX, np.int64)
    for q in range(3):
        for c in range(3):
            cells[0, q, c] = Pi[q, c]
    ncv[0] = 3
    n_cells = 1
    for li in range(nlines):
        for c in range(3):
            nl[c] = lines[li, 3 + c]
        n_cells = _clip(cells, ncv, sides, n_cells, nl, lines[li, 0], lines[li, 1], lines[li, 2], 1 << li, 0.0)
        if n_cells < 0:
            return 1
    # 3. each cell's w_front by a walk (from the reference point, else from a known cell)
    cen = np.empty((n_cells, 3))
    w_cell = np.empty(n_cells)
    known = np.zeros(n_cells, np.bool_)
    live = np.zeros(n_cells, np.bool_)
    tiny = tol * tol
    areas = np.empty(n_cells)
    piece_area = 0.0
    for c in range(n_cells):
        areas[c] = _cell_area_centroid(cells, ncv, c, nf, cen[c])
        live[c] = areas[c] > tiny
        piece_area += abs(areas[c])
        if not live[c] and ncv[c] >= 3:
            _add_cell_abs(cells, ncv, c, p, bnd[i])       # a crumb from the clipping: bounded
    for c in range(n_cells):
        if not live[c]:
            continue
        # any point inside the cell will do: the centroid, else points towards its corners
        # (a symmetric mesh may line the centroid up with a trace's end)
        for trial in range(ncv[c] + 1):
            if trial == 0:
                qx = cen[c, 0]
                qy = cen[c, 1]
                qz = cen[c, 2]
            else:
                qx = 0.7 * cen[c, 0] + 0.3 * cells[c, trial - 1, 0]
                qy = 0.7 * cen[c, 1] + 0.3 * cells[c, trial - 1, 1]
                qz = 0.7 * cen[c, 2] + 0.3 * cells[c, trial - 1, 2]
            ok, jmp = _walk(V, F, cut_ptr, tr_type, tr_P, tr_J, f, ref[s, 0], ref[s, 1], ref[s, 2], qx, qy, qz,
                            nf, tol)
            if ok:
                w_cell[c] = w_ref[s] + jmp
                known[c] = True
                break
    for c in range(n_cells):
        if not live[c] or known[c]:
            continue
        for d in range(n_cells):
            if known[d]:
                ok, jmp = _walk(V, F, cut_ptr, tr_type, tr_P, tr_J, f, cen[d, 0], cen[d, 1], cen[d, 2], cen[c, 0],
                                cen[c, 1], cen[c, 2], nf, tol)
                if ok:
                    w_cell[c] = w_cell[d] + jmp
                    known[c] = True
                    break
        if not known[c]:
            if areas[c] > 1e-9 * piece_area:
                return 1
            # a sliver along a trace (its centroid within the tolerance of it): weight in
            # [-1, 1], taken as 0, bounded by its whole tetrahedron sums
            _add_cell_abs(cells, ncv, c, p, bnd[i])
            live[c] = False
    # 4. each cell's stack and weight
    for c in range(n_cells):
        if not live[c]:
            continue
        w = w_cell[c]
        net = M[f]
        leader = True
        for k in range(cut_ptr[f], cut_ptr[f + 1]):
            if tr_type[k] != 2:
                continue
            inside = True
            for e in range(3):
                li = line_of[k - cut_ptr[f], e]
                if li >= 0:
                    inside = inside and (((sides[c] >> li) & 1) == 1) != flip[k - cut_ptr[f], e]
                else:
                    inside = inside and side_fixed[k - cut_ptr[f], e] > 0
            if inside:
                net += tr_J[k]
                if cut_idx[k] < f:
                    leader = False
        w_seen[i, 0] = min(w_seen[i, 0], w)
        w_seen[i, 1] = max(w_seen[i, 1], w + net)
        if not leader:
            continue
        weight = (1.0 if w + net >= 1.0 else 0.0) - (1.0 if w >= 1.0 else 0.0)
        if weight != 0.0:
            _add_cell(cells, ncv, c, weight, p, acc[i])
    return 0


def _same_line(lines, nlines, nl, x, y, z, tol):
    """1 + index of a line among ``lines[:nlines]`` equal to the line through (x, y, z) with unit
    normal nl (negative: opposite normal), 0 if none."""
    for li in range(nlines):
        c = lines[li, 3] * nl[0] + lines[li, 4] * nl[1] + lines[li, 5] * nl[2]
        if abs(c) < 1.0 - 1e-12:
            continue
        d = lines[li, 3] * (x - lines[li, 0]) + lines[li, 4] * (y - lines[li, 1]) + lines[li, 5] * (z - lines[li, 2])
        if abs(d) <= tol:
            return li + 1 if c > 0.0 else -(li + 1)
    return 0


def _add_cell_abs(cells, ncv, c, p, out):
    """out (13,) += bounds of the tetrahedron integrals (apex p) of the fan triangles of cell c:
    |V|, |V| max|y_j|, |V| max|y_j| max|y_k| (y = x - p; its largest |y_j| is at a corner)."""
    m = ncv[c]
    for i in range(1, m - 1):
        ax = cells[c, 0, 0] - p[0]
        ay = cells[c, 0, 1] - p[1]
        az = cells[c, 0, 2] - p[2]
        bx = cells[c, i, 0] - p[0]
        by = cells[c, i, 1] - p[1]
        bz = cells[c, i, 2] - p[2]
        cx = cells[c, i + 1, 0] - p[0]
        cy = cells[c, i + 1, 1] - p[1]
        cz = cells[c, i + 1, 2] - p[2]
        vol = abs(ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)) / 6.0
        mx = max(abs(ax), max(abs(bx), abs(cx)))
        my = max(abs(ay), max(abs(by), abs(cy)))
        mz = max(abs(az), max(abs(bz), abs(cz)))
        out[0] += vol
        out[1] += vol * mx
        out[2] += vol * my
        out[3] += vol * mz
        out[4] += vol * mx * mx
        out[5] += vol * mx * my
        out[6] += vol * mx * mz
        out[7] += vol * my * mx
        out[8] += vol * my * my
        out[9] += vol * my * mz
        out[10] += vol * mz * mx
        out[11] += vol * mz * my
        out[12] += vol * mz * mz


def _piece_near_type3(V, F, g, Pi, nf, tol):
    """Does the piece come within ``tol`` of the shadow of face g in f's plane?  (Separating
    axes of the two projected triangles; True when none separates.)"""
    nl = np.empty(3)
    for t in range(2):
        for e in range(3):
            if t == 0:
                a0 = V[F[g, e], 0]
                a1 = V[F[g, e], 1]
                a2 = V[F[g, e], 2]
                b0 = V[F[g, (e + 1) % 3], 0]
                b1 = V[F[g, (e + 1) % 3], 1]
                b2 = V[F[g, (e + 1) % 3], 2]
            else:
                a0 = Pi[e, 0]
                a1 = Pi[e, 1]
                a2 = Pi[e, 2]
                b0 = Pi[(e + 1) % 3, 0]
                b1 = Pi[(e + 1) % 3, 1]
                b2 = Pi[(e + 1) % 3, 2]
            le = _line_of(a0, a1, a2, b0, b1, b2, nf, nl)
            if le == 0.0:
                continue
            lo1 = math.inf
            hi1 = -math.inf
            lo2 = math.inf
            hi2 = -math.inf
            for q in range(3):
                d1 = _point_side(nl, a0, a1, a2, V[F[g, q], 0], V[F[g, q], 1], V[F[g, q], 2])
                d2 = _point_side(nl, a0, a1, a2, Pi[q, 0], Pi[q, 1], Pi[q, 2])
                lo1 = min(lo1, d1)
                hi1 = max(hi1, d1)
                lo2 = min(lo2, d2)
                hi2 = max(hi2, d2)
            if lo1 > hi2 + tol or lo2 > hi1 + tol:
                return False
    return True
