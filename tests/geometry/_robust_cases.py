"""Generated imperfect meshes with independently known volume integrals (for the robust path).

Each generator returns ``(vertices, faces, truth)``, ``truth = (V, int x, int x x^T)`` about
the origin, of the solid the mesh describes, computed without the robust path:

* box unions by inclusion-exclusion (the intersection of boxes is a box), with corners on
  a coarse grid so that faces are often coplanar, touching or repeated;
* unions and differences of convex polyhedra from their convex hulls, the intersection of
  two convex polyhedra from scipy's half-space intersection (exact to rounding);
* closed meshes with holes punched by deleting faces whose loop is flat (one face, or a
  set of coplanar faces), which the generalised winding number closes flat.

Every case is moved by a random rigid motion (the truth moved exactly).  Used by
tests/geometry/test_robust.py and bench/robust.py (the accuracy/bound table).
"""

from __future__ import annotations

import itertools

import numpy as np
from scipy.optimize import linprog
from scipy.spatial import ConvexHull, HalfspaceIntersection
from scipy.spatial.transform import Rotation

from inertia.geometry.integrals import solid_integrals

BOX_FACES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                      [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
ORIGIN = np.zeros(3)


def box(lo, hi):
    """Closed outward box mesh (8 vertices, 12 faces)."""
    v = np.array([[x, y, z] for x in (lo[0], hi[0]) for y in (lo[1], hi[1]) for z in (lo[2], hi[2])], float)
    return v, BOX_FACES.copy()


def grid_box(lo, hi, n):
    """Closed outward box whose faces are n x n grids (flat holes can be punched)."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    verts, faces = [], []
    for axis in range(3):
        for side in (0, 1):
            u, w = (axis + 1) % 3, (axis + 2) % 3
            base = len(verts)
            for i in range(n + 1):
                for j in range(n + 1):
                    p = np.empty(3)
                    p[axis] = hi[axis] if side else lo[axis]
                    p[u] = lo[u] + (hi[u] - lo[u]) * i / n
                    p[w] = lo[w] + (hi[w] - lo[w]) * j / n
                    verts.append(p)
            for i in range(n):
                for j in range(n):
                    a, b = base + i * (n + 1) + j, base + (i + 1) * (n + 1) + j
                    quad = [[a, b, b + 1], [a, b + 1, a + 1]]
                    faces += quad if side else [q[::-1] for q in quad]
    v, f = np.array(verts), np.array(faces)
    key, inv = np.unique(np.round(v, 12), axis=0, return_inverse=True)
    return key, inv.ravel()[f]


def box_moments(lo, hi):
    """(volume, first (3,), second (3, 3)) of an axis-aligned box about the origin."""
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    L = np.maximum(hi - lo, 0.0)
    V = float(np.prod(L))
    c = 0.5 * (lo + hi)
    return V, V * c, V * np.outer(c, c) + np.diag(V * L * L / 12.0)


def union_moments(boxes):
    """Moments of a union of axis-aligned boxes by inclusion-exclusion."""
    V, F, S = 0.0, np.zeros(3), np.zeros((3, 3))
    for r in range(1, len(boxes) + 1):
        for sub in itertools.combinations(boxes, r):
            lo = np.max([b[0] for b in sub], axis=0)
            hi = np.min([b[1] for b in sub], axis=0)
            if np.any(hi <= lo):
                continue
            v, f, s = box_moments(lo, hi)
            sgn = (-1) ** (r + 1)
            V, F, S = V + sgn * v, F + sgn * f, S + sgn * s
    return V, F, S


def moved(moments, R, t):
    """Moments about the origin after x -> R x + t."""
    V, F, S = moments
    RF = R @ F
    return V, RF + V * t, R @ S @ R.T + np.outer(RF, t) + np.outer(t, RF) + V * np.outer(t, t)


def combine(*terms):
    """Signed sum of moment triples: ``combine((1, a), (-1, b))``."""
    return tuple(sum(s * m[i] for s, m in terms) for i in range(3))


def concat(*meshes):
    vs, fs, off = [], [], 0
    for v, f in meshes:
        vs.append(v)
        fs.append(f + off)
        off += len(v)
    return np.concatenate(vs), np.concatenate(fs)


def convex(points):
    """Outward convex hull mesh of points."""
    h = ConvexHull(points)
    f = h.simplices.copy()
    p = h.points
    c = p[h.vertices].mean(0)
    nrm = np.cross(p[f[:, 1]] - p[f[:, 0]], p[f[:, 2]] - p[f[:, 0]])
    flip = (nrm * (p[f].mean(1) - c)).sum(1) < 0
    f[flip] = f[flip][:, ::-1]
    return p, f


def hull(n, seed, r=1.0, c=(0.0, 0.0, 0.0)):
    """Random convex polyhedron (hull of n points on a sphere), outward faces."""
    rng = np.random.default_rng(seed)
    p = rng.normal(size=(n, 3))
    p /= np.linalg.norm(p, axis=1)[:, None]
    return convex(p * r + np.asarray(c))


def moments(mesh):
    return solid_integrals(*mesh, reference=ORIGIN)[:3]


def intersection_moments(a, b):
    """Moments of the intersection of two convex meshes (zero when they do not overlap)."""
    hs = np.concatenate([ConvexHull(a[0]).equations, ConvexHull(b[0]).equations])
    # Chebyshev centre: a point deep inside both
    norm = np.linalg.norm(hs[:, :3], axis=1)
    res = linprog(np.r_[0, 0, 0, -1], A_ub=np.c_[hs[:, :3], norm], b_ub=-hs[:, 3],
                  bounds=[(None, None)] * 3 + [(0, None)])
    if not res.success or res.x[3] < 1e-6:
        return 0.0, np.zeros(3), np.zeros((3, 3))
    pts = HalfspaceIntersection(hs, res.x[:3]).intersections
    return moments(convex(pts))


def _motion(rng):
    return Rotation.random(random_state=int(rng.integers(2**31))).as_matrix(), rng.uniform(-2, 2, 3)


def snapped_boxes(rng, k):
    """k boxes with corners on a grid of step 1/4: coplanar, touching and repeated faces are common."""
    out = []
    for _ in range(k):
        lo = rng.integers(-4, 3, 3) / 4.0
        out.append(np.array([lo, lo + rng.integers(1, 6, 3) / 4.0]))
    return out


def case_box_union(rng):
    """2-3 boxes merged by concatenation (overlapping, touching, coplanar faces)."""
    boxes = snapped_boxes(rng, int(rng.integers(2, 4)))
    return concat(*[box(*b) for b in boxes]), union_moments(boxes)


def case_convex_union(rng):
    """Two overlapping convex shells (or a shell and a rotated copy)."""
    a = hull(int(rng.integers(8, 40)), int(rng.integers(1 << 30)), r=rng.uniform(0.5, 1.0))
    if rng.random() < 0.5:
        R = Rotation.random(random_state=int(rng.integers(2**31))).as_matrix()
        b = (a[0] @ R.T + rng.uniform(-0.5, 0.5, 3), a[1].copy())
    else:
        b = hull(int(rng.integers(8, 40)), int(rng.integers(1 << 30)), r=rng.uniform(0.5, 1.0),
                 c=rng.uniform(-0.6, 0.6, 3))
    return concat(a, b), combine((1, moments(a)), (1, moments(b)), (-1, intersection_moments(a, b)))


def case_cavity(rng):
    """A hollow part: an inside-out copy of a shell, shrunk, inside it."""
    if rng.random() < 0.5:
        lo = rng.uniform(-1, 0, 3)
        hi = lo + rng.uniform(1, 2, 3)
        ilo = lo + rng.uniform(0.05, 0.3, 3) * (hi - lo)
        ihi = hi - rng.uniform(0.05, 0.3, 3) * (hi - lo)
        outer, inner = box(lo, hi), box(ilo, ihi)
    else:
        outer = hull(int(rng.integers(20, 80)), int(rng.integers(1 << 30)))
        c = outer[0].mean(0)
        inner = ((outer[0] - c) * rng.uniform(0.3, 0.8) + c, outer[1].copy())
    return concat(outer, (inner[0], inner[1][:, ::-1])), combine((1, moments(outer)), (-1, moments(inner)))


def case_flat_holes(rng):
    """A closed mesh with flat holes: single faces of a convex hull (no two sharing a vertex),
    or faces inside one side of a grid box (off its border; neighbouring ones make one
    hole, maybe non-convex).  Holes in one plane, apart from the rest: the generalised
    winding number closes them flat, up to the other holes' small share."""
    if rng.random() < 0.5:
        v, f = hull(int(rng.integers(30, 200)), int(rng.integers(1 << 30)))
        k = int(rng.integers(1, 6))
        picked, used = [], set()
        for i in rng.permutation(len(f)):
            if not used & set(f[i]):
                picked.append(i)
                used |= set(f[i])
            if len(picked) == k:
                break
        return (v, np.delete(f, picked, axis=0)), moments((v, f))
    n = int(rng.integers(3, 7))
    lo = rng.uniform(-1, 0, 3)
    hi = lo + rng.uniform(0.5, 2, 3)
    v, f = grid_box(lo, hi, n)
    axis, side = int(rng.integers(3)), int(rng.integers(2))
    c = v[f]
    on_side = np.all(np.abs(c[:, :, axis] - (hi if side else lo)[axis]) < 1e-9, axis=1)
    others = [a for a in range(3) if a != axis]
    inner = on_side & np.all([(c[:, :, a].min(1) > lo[a] + 1e-9) & (c[:, :, a].max(1) < hi[a] - 1e-9)
                              for a in others], axis=0)
    cand = np.flatnonzero(inner)
    drop = rng.choice(cand, size=int(rng.integers(1, len(cand) + 1)), replace=False)
    return (v, np.delete(f, drop, axis=0)), moments((v, f))


def case_curved_holes(rng):
    """A convex hull with a hole of 2-4 neighbouring faces whose loop is not flat: the
    generalised winding number spans it with a curved surface (not the faces removed); the
    truth given is the closed hull (the difference is the model's, not the error's)."""
    while True:
        v, f = hull(int(rng.integers(60, 200)), int(rng.integers(1 << 30)))
        picked = [int(rng.integers(len(f)))]
        while len(picked) < int(rng.integers(2, 5)):
            nb = [i for i in range(len(f)) if i not in picked
                  and any(len(set(f[i]) & set(f[j])) == 2 for j in picked)]
            picked.append(int(rng.choice(nb)))
        loop = np.setdiff1d(np.unique(f[picked]), [x for x in np.unique(f[picked])
                                                    if np.sum(np.isin(f, x).any(1)) == np.sum(np.isin(f[picked], x).any(1))])
        p = v[loop] - v[loop].mean(0)
        if len(loop) > 3 and np.linalg.svd(p, compute_uv=False)[-1] > 1e-6:
            return (v, np.delete(f, picked, axis=0)), moments((v, f))


CASES = {"box union": case_box_union, "convex union": case_convex_union, "cavity": case_cavity,
         "flat holes": case_flat_holes}
#: Not in CASES (the truth given is not the generalised-winding-number solid): reported apart.
OTHER_CASES = {"curved holes": case_curved_holes}


def random_case(rng, kind=None):
    """``(name, vertices, faces, truth)`` of one generated case under a random rigid motion."""
    name = kind or list(CASES)[int(rng.integers(len(CASES)))]
    (v, f), truth = {**CASES, **OTHER_CASES}[name](rng)
    R, t = _motion(rng)
    return name, v @ R.T + t, f, moved(truth, R, t)


def within_bound(res, truth, slack=1e-9):
    """True error <= bound (+ rounding slack relative to the magnitudes) for all integrals."""
    return error_ratio(res, truth, slack) <= 1.0


def error_ratio(res, truth, slack=1e-9):
    """Largest (|true - value| - slack) / bound over the integrals (<= 1: honest)."""
    V, F, S = truth
    scale = abs(V) + 1e-300
    worst = 0.0
    for val, tru, bnd, mag in ((res.volume, V, res.bound_volume, scale),
                               (res.first, F, res.bound_first, np.abs(F).max() + scale),
                               (res.second, S, res.bound_second, np.abs(S).max() + scale)):
        err = np.abs(np.asarray(val) - tru) - slack * mag
        ratio = np.where(err <= 0, 0.0, err / np.maximum(np.asarray(bnd, float), 1e-300))
        worst = max(worst, float(np.max(ratio)))
    return worst
