"""Scalar kernel of the cap-region octree of :mod:`._robust_caps` (plain Python or numba).

Written once in scalar Python like :mod:`._robust_kernels` (compiled by
:mod:`._robust_numba`).  :func:`cap_cells` classifies octree cells for the set
``D = {x : |w_cap(x)| >= thr}`` (w_cap the winding number of the caps that close the
mesh boundary):

* status 0, *free*: no cap crosses the cell and ``|w_cap(c)| + rho |grad w_cap| < thr``
  (c the centre, rho the half diagonal; the gradient bounded by the Biot-Savart form of
  each cap's boundary loop, ``|grad w| <= sum_e m_e len_e / (4 pi d_e^2)``);
* status 1, *near one flat cap* (thr = 1/2 only): k a flat polygon covered once, and the
  other caps neither cross the cell nor reach it with a loop edge, and add at most
  ``Delta = |w_rest(c)| + rho |grad w_rest| < 1/10`` on the cell.  Then D meets the cell
  only where ``|w_k| >= 1/2 - Delta``, a thin layer around the polygon whose volume
  :func:`flat_cap_volume` bounds in closed form over the cell's shadow;
* status 2: refine (or count the cell whole at the last level).

The scalar style of :mod:`._robust_kernels` holds here too: loading a face's corners
relative to a point is written out where it is used (a helper returning a 9-tuple costs
measurably in the inner loops); ``duplicates`` lists those few lines.
"""

from __future__ import annotations

import math

__all__ = ["cap_cells", "flat_cap_volume", "flat_cap_heights", "solid_angle"]

FOUR_PI = 4.0 * math.pi
#: The compiled twin replaces this with ``numba.prange`` (parallel loops); plain Python runs them in order.
prange = range


def flat_cap_heights(delta, diameter):
    """``(h_in, r_max, h_max)`` of :func:`flat_cap_volume` for 0 <= delta < 1/4."""
    if delta <= 0.0:
        return 0.0, 0.0, 0.0
    b = 2.0 * delta / math.sqrt(1.0 - 4.0 * delta * delta)
    a = (1.0 - 2.0 * delta) / (2.0 * math.sqrt(delta * (1.0 - delta)))
    r_max = b * diameter / (a - b)
    return b * diameter, r_max, b * (r_max + diameter)


def flat_cap_volume(delta, area, perimeter, diameter, flat_tol, shadow):
    """Bound of the volume where ``|w_k| >= 1/2 - delta`` for a flat polygon k (area,
    perimeter, diameter; flat within ``flat_tol``), 0 <= delta < 1/10, over a region of the
    plane of area ``shadow`` (the shadow of an octree cell; inf for the whole polygon).

    Let x be at height h over the polygon's plane, with foot q.  ``b = 2 delta / sqrt(1 - 4 delta^2)``.

    * q in the polygon: the plane beyond distance ``diameter`` of q lies outside the polygon,
      so its solid angle misses at least ``2 pi h / sqrt(h^2 + diameter^2)``, and
      ``|w_k| >= 1/2 - delta`` needs ``|h| <= h_in = b diameter``;
    * q outside, at distance r: the polygon lies between the circles of radii r and
      ``r + diameter`` around q, so ``|w_k| <= h / (2 sqrt(h^2 + r^2))`` and
      ``|w_k| <= 1/2 - h / (2 sqrt(h^2 + (r + diameter)^2))``; both reach ``1/2 - delta``
      only for ``r <= r_max = b diameter / (a - b)``, ``a = (1 - 2 delta) / (2 sqrt(delta (1 - delta)))``,
      and ``|h| <= h_max = b (r_max + diameter)``.

    So the set lies in a layer over the polygon and a band around it (prisms, over at most
    ``shadow`` of the plane each); the polygon being flat only within ``flat_tol`` thickens
    both by that much.
    """
    h_in, r_max, h_max = flat_cap_heights(delta, diameter)
    return (2.0 * min(area, shadow) * (h_in + flat_tol)
            + 2.0 * min(perimeter * r_max + math.pi * r_max * r_max, shadow) * (h_max + flat_tol))


def solid_angle(V, F, f, px, py, pz):
    """Van Oosterom-Strackee solid angle of face f seen from p (positive from behind)."""
    ax = V[F[f, 0], 0] - px
    ay = V[F[f, 0], 1] - py
    az = V[F[f, 0], 2] - pz
    bx = V[F[f, 1], 0] - px
    by = V[F[f, 1], 1] - py
    bz = V[F[f, 1], 2] - pz
    cx = V[F[f, 2], 0] - px
    cy = V[F[f, 2], 1] - py
    cz = V[F[f, 2], 2] - pz
    la = math.sqrt(ax * ax + ay * ay + az * az)
    lb = math.sqrt(bx * bx + by * by + bz * bz)
    lc = math.sqrt(cx * cx + cy * cy + cz * cz)
    det = ax * (by * cz - bz * cy) + ay * (bz * cx - bx * cz) + az * (bx * cy - by * cx)
    den = la * lb * lc + (ax * bx + ay * by + az * bz) * lc + (bx * cx + by * cy + bz * cz) * la \
        + (cx * ax + cy * ay + cz * az) * lb
    return 2.0 * math.atan2(det, den)


def _box_distance(px, py, pz, lo, hi, i):
    dx = max(0.0, max(lo[i, 0] - px, px - hi[i, 0]))
    dy = max(0.0, max(lo[i, 1] - py, py - hi[i, 1]))
    dz = max(0.0, max(lo[i, 2] - pz, pz - hi[i, 2]))
    return math.sqrt(dx * dx + dy * dy + dz * dz)


def _segment_distance(px, py, pz, E0, E1, e):
    dx = E1[e, 0] - E0[e, 0]
    dy = E1[e, 1] - E0[e, 1]
    dz = E1[e, 2] - E0[e, 2]
    qx = px - E0[e, 0]
    qy = py - E0[e, 1]
    qz = pz - E0[e, 2]
    dd = dx * dx + dy * dy + dz * dz
    t = 0.0
    if dd > 0.0:
        t = min(1.0, max(0.0, (qx * dx + qy * dy + qz * dz) / dd))
    rx = qx - t * dx
    ry = qy - t * dy
    rz = qz - t * dz
    return math.sqrt(rx * rx + ry * ry + rz * rz)


def cap_cells(centers, half, thr, CV, CF, CM, face_ptr, face_lo, face_hi, E0, E1, EM, edge_ptr,
              flat, area, perimeter, diameter, normal, apex, flat_dev, eps, status, which, delta, w_rest, contrib):
    """Classify cubic cells (``centers`` (N, 3), half side ``half``); see the module docstring.

    Caps: faces ``CF`` (over vertices ``CV``, multiplicities ``CM``) of cap j are
    ``face_ptr[j]:face_ptr[j + 1]`` (boxes ``face_lo``, ``face_hi``); its loop edges
    ``E0 -> E1`` (multiplicities ``EM``) are ``edge_ptr[j]:edge_ptr[j + 1]``; ``flat[j]``,
    ``diameter`` as in :func:`flat_cap_volume`, ``normal`` (unit) and ``apex`` a point of
    its plane, ``flat_dev`` how far its vertices stray from that plane (0: within eps).
    A nearly flat cap (``flat_dev`` > 0) differs from the flat polygon below it by a strip
    along its loop (height ``flat_dev``) and a region within ``flat_dev`` of the plane; the
    strip adds at most ``flat_dev sum_e len_e / (4 pi (d_e - rho - flat_dev)^2)`` to Delta.
    The cap k of largest ``|w_k(c)| + rho |grad w_k|`` is the one a cell may be
    near; the others must neither cross the cell nor reach it with a loop edge.

    Status 1 cells get ``which`` = k, ``delta`` = Delta, ``w_rest`` = ``|w_rest(c)|`` and
    ``contrib`` the bound of :func:`flat_cap_volume` over the cell's shadow on k's plane
    (area ``(2 half)^2 (|n_x| + |n_y| + |n_z|)``, at most the cell's volume); a cell farther
    from k's plane than the layer of its Delta is free (status 0).
    """
    K = face_ptr.shape[0] - 1
    rho = half * math.sqrt(3.0)
    for i in prange(centers.shape[0]):
        px = centers[i, 0]
        py = centers[i, 1]
        pz = centers[i, 2]
        w_all = 0.0
        g_fin = 0.0
        n_inf = 0
        n_cross = 0
        nk = -1
        best = -1.0
        w_k = 0.0
        g_k = 0.0
        cross_k = False
        for j in range(K):
            w = 0.0
            cross = False
            for f in range(face_ptr[j], face_ptr[j + 1]):
                if _box_distance(px, py, pz, face_lo, face_hi, f) <= rho:
                    cross = True
                w += CM[f] * solid_angle(CV, CF, f, px, py, pz)
            w /= FOUR_PI
            g = _loop_gradient(px, py, pz, rho, E0, E1, EM, edge_ptr[j], edge_ptr[j + 1])
            w_all += w
            n_cross += cross
            if g == math.inf:
                n_inf += 1
            else:
                g_fin += g
            score = abs(w) + rho * g
            if cross or g == math.inf:
                score = math.inf
            if score > best or nk < 0:
                best = score
                nk = j
                w_k = w
                g_k = g
                cross_k = cross
        status[i] = 2
        which[i] = -1
        delta[i] = 0.0
        w_rest[i] = 0.0
        contrib[i] = 0.0
        if n_cross == 0 and n_inf == 0 and abs(w_all) + rho * g_fin < thr:
            status[i] = 0
            continue
        if thr != 0.5 or not flat[nk]:
            continue
        # the other caps: no crossing, no loop edge within the cell, and small
        if n_cross - cross_k > 0 or n_inf - (g_k == math.inf) > 0:
            continue
        d = abs(w_all - w_k) + rho * (g_fin - (g_k if g_k < math.inf else 0.0))
        if flat_dev[nk] > 0.0:
            d += flat_dev[nk] * _loop_gradient(px, py, pz, rho + flat_dev[nk], E0, E1, EM, edge_ptr[nk],
                                               edge_ptr[nk + 1])
        if d < 0.1:
            height = ((px - apex[nk, 0]) * normal[nk, 0] + (py - apex[nk, 1]) * normal[nk, 1]
                      + (pz - apex[nk, 2]) * normal[nk, 2])
            h_in, r_max, h_max = flat_cap_heights(d, diameter[nk])
            if abs(height) > rho + max(h_in, h_max) + flat_dev[nk] + eps:
                status[i] = 0
            else:
                status[i] = 1
                which[i] = nk
                delta[i] = d
                w_rest[i] = abs(w_all - w_k)
                side = 2.0 * half
                shadow = side * side * (abs(normal[nk, 0]) + abs(normal[nk, 1]) + abs(normal[nk, 2]))
                contrib[i] = min(side * side * side, flat_cap_volume(d, area[nk], perimeter[nk], diameter[nk],
                                                                     flat_dev[nk] + eps, shadow))


def _loop_gradient(px, py, pz, rho, E0, E1, EM, e_start, e_end):
    """Biot-Savart bound of ``|grad w|`` over the cell from loop edges e_start..e_end-1 (inf if one reaches it)."""
    g = 0.0
    for e in range(e_start, e_end):
        d = _segment_distance(px, py, pz, E0, E1, e) - rho
        if d <= 0.0:
            return math.inf
        lx = E1[e, 0] - E0[e, 0]
        ly = E1[e, 1] - E0[e, 1]
        lz = E1[e, 2] - E0[e, 2]
        g += EM[e] * math.sqrt(lx * lx + ly * ly + lz * lz) / (FOUR_PI * d * d)
    return g
