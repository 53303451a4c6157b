"""Volume integrals of imperfect meshes (open, overlapping, self-intersecting) with an error bound.

The solid
---------
The solid of a triangle soup is ``Omega = {x : w(x) >= 1/2}``, w the generalised winding
number (Jacobson, Kavan, Sorkine-Hornung 2013, "Robust inside-outside segmentation
using generalized winding numbers").  On a closed, outward mesh it is the usual inside;
overlapping closed shells (w = 2 where they overlap) give their union; an inside-out
inner shell (w = 0 inside it) a cavity; a hole is spanned by the level set w = 1/2.

Method (exact where the mesh is clean, bounded where it is not)
--------------------------------------------------------------
1. *Closing.*  Faces are merged into a 2-chain with multiplicities; each connected piece
   of its boundary (open or inconsistently wound edges) is closed by a fan cap, giving
   a closed chain C' with integer winding number w' and ``w = w' - w_cap``.  Where
   ``|w_cap| < 1/2`` the sets {w >= 1/2} and {w' >= 1} coincide (w' is an integer).
   A single flat, simply covered cap has ``|w_cap| < 1/2`` off its plane, so a single
   flat hole costs nothing; otherwise the volume where ``|w_cap|`` may reach 1/2 is
   bounded by an octree (:func:`._robust_caps.cap_region_bound`) and enters the bound.
2. *Boundary of the solid by the divergence theorem.*  ``Omega' = {w' >= 1}`` is bounded
   by the parts of C' where the winding just in front of a face, w_f, and just behind it,
   ``w_f + m`` (m its multiplicity), straddle the threshold; there the face belongs to
   the boundary with weight ``[w_f + m >= 1] - [w_f >= 1]`` in {-1, 0, 1}.  Summing the
   exact signed-tetrahedron integrals (:mod:`.integrals`) of the faces with these
   weights gives the integrals over Omega' exactly.
3. *Where the weight is constant.*  On a face that no other face cuts, w_f is constant;
   it is the same on neighbours across a manifold, consistently wound edge (equal multiplicities), so it is
   evaluated once per connected patch: ``w_f = W_rest(centroid) - m/2``, W_rest the
   winding number of every other face (Van Oosterom-Strackee solid angles), which must
   then be within 1e-3 of an integer (else the patch is treated as cut).
4. *Cut faces* (found by a uniform-grid broad phase and conservative triangle-triangle tests,
   shared corners and edges handled exactly) are split 1 -> 4 recursively.  A piece no
   cutter touches gets its own weight as in 3; a piece still touched at the last level
   is *unresolved*: its weight lies in [0, 1] (or [-1, 0]), it enters with 1/2 (-1/2) and
   its bound is half its absolute tetrahedron integrals
   (``|int y_i| <= |V_tet| max |y_i|`` and so on, y = x - p).
   The winding of a piece is counted from a reference point on the same face by the
   signed crossings of its cutters (the full sum only where a crossing is borderline).
   Refinement stops when the bound meets ``tol`` or the piece budget is spent.

Error bound: the unresolved pieces (first order in the piece size, but only along the
curves where faces cross) plus the cap region of step 1, plus nothing else -- the exact
parts are accurate to rounding (:mod:`.integrals`' error analysis).  Geometric decisions
use a tolerance ``eps = 1e-10`` x the box diagonal and err towards "cut", so a wrong
decision needs rounding errors 10^5 times larger than double precision makes.

Ambiguity: ``ambiguous_volume`` bounds the volume where ``0.1 < w < 0.9`` (possible only
where ``|w_cap| > 0.1``, near holes): a measure of how much of the solid the mesh leaves
to the w = 1/2 convention.  Zero for closed meshes, whatever their overlaps.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from .._core.findings import Finding
from .._ext import robust as _k
from ._robust_caps import MAX_CAP_WORK, CapGeometry, Caps, cap_region_bound
from ._robust_pieces import Pieces, unpacked_sums
from .integrals import reference_point
from .mesh_arrays import validate_inputs, weld_map

__all__ = ["RobustResult", "robust_integrals"]

#: Winding numbers strictly between these count as ambiguous.
AMBIGUOUS_LOW, AMBIGUOUS_HIGH = 0.1, 0.9
#: Relative geometric tolerance of the intersection tests (times the box diagonal).
EPS_REL = 1e-10
#: Cut pieces are refined until their bound is this fraction of tol (or a budget ends).
REFINE_BELOW = 1e-3


@dataclass(frozen=True)
class RobustResult:
    """Integrals over the solid {w >= 1/2} of a triangle soup, with error bounds.

    Geometry units only (multiply by the density).  y = x - reference.

    Attributes
    ----------
    volume : float, ``int 1 dV`` (L^3).
    first : (3,) float, ``int y dV`` (L^4).
    second : (3, 3) float, ``int y y^T dV`` (L^5).
    reference : (3,) float, the point the integrals are about.
    bound_volume, bound_first (3,), bound_second (3, 3) :
        Absolute bounds of the errors (elementwise): ``|true - value| <= bound``.
    ambiguous_volume : float
        Upper bound of the volume where ``0.1 < w < 0.9`` (model ambiguity, not an error).
    converged : bool, the bounds meet ``tol`` (see :attr:`bounds`; :attr:`bound` is the largest
        of them, the bound reached).
    stopped_by : str or None, what ended the refinement short of ``tol``: "time budget", "piece
        budget", "depth limit" or "octree limit" (the cap region's cells); None when converged.
    findings : tuple of Finding, what was found, with the codes of
        :func:`inertia.geometry.check_mesh` (``duplicate_faces``, ``open_edges``,
        ``non_manifold_edges``, ``inconsistent_winding``, ``inverted``, ``overlapping_shells``
        for faces that cross) and ``undecided_windings``, ``bound_not_reached``.
    stats : dict, counts and timings.
    """

    volume: float
    first: np.ndarray
    second: np.ndarray
    reference: np.ndarray
    bound_volume: float
    bound_first: np.ndarray
    bound_second: np.ndarray
    ambiguous_volume: float
    converged: bool
    tol: float
    findings: tuple = ()
    stats: dict = field(default_factory=dict)
    derived: dict = field(default_factory=dict, repr=False)
    stopped_by: str | None = None

    @property
    def codes(self) -> tuple:
        """The codes of :attr:`findings`."""
        return tuple(f.code for f in self.findings)

    @property
    def bound(self) -> float:
        """The relative bound reached: the largest of :attr:`bounds` (inf: none)."""
        return _worst(self.bounds)

    @property
    def ambiguous_fraction(self) -> float:
        """``ambiguous_volume / |volume|`` (inf for a zero volume)."""
        return self.ambiguous_volume / abs(self.volume) if self.volume else math.inf

    @property
    def com(self) -> np.ndarray:
        """Center of mass (3,) of the uniform solid."""
        return self.reference + self.first / self.volume

    def central_second(self) -> np.ndarray:
        """``C = int (x - com)(x - com)^T dV`` (3, 3); inertia = density (tr C 1 - C)."""
        return self.derived["central_second"].copy()

    @property
    def bound_com(self) -> float:
        """Bound of ``|com error|`` (Euclidean)."""
        return self.derived["bound_com"]

    @property
    def bound_central_second(self) -> float:
        """Frobenius bound of the error of :meth:`central_second`."""
        return self.derived["bound_central_second"]

    @property
    def bounds(self) -> dict:
        """Relative error bounds: ``volume`` / |V|, ``com`` / radius of gyration, ``inertia``
        (``|I error|_F / |I|_F`` of the central inertia, any density)."""
        return dict(self.derived["relative"])

    @property
    def error_bound(self) -> float:
        """The largest of :attr:`bounds`: the relative precision of the result."""
        return max(self.derived["relative"].values())


def derived_bounds(vol, first, second, bv, bf, bs) -> dict:
    """COM, central second moment and their bounds from integrals about a point p near the body.

    With C = S - F F^T / V (about p), for perturbations dV, dF, dS bounded by bv, bf, bs:
    ``|dcom| <= (|bf| + |c| bv) / (|V| - bv)`` and
    ``|dC|_F <= |bs|_F + (2 |F| |bf| + |bf|^2) / (|V| - bv) + |F|^2 bv / (|V| (|V| - bv))``
    (from ``F'F'^T / V' - F F^T / V = (F'F'^T - F F^T) / V' + F F^T (1/V' - 1/V)``);
    the inertia ``tr(C) 1 - C`` errs by at most ``(sqrt(3) sqrt(3) + 1) |dC|_F = 4 |dC|_F``.
    Taken about p (the box center) rather than a far reference, where |F| would inflate them.
    """
    V = abs(vol)
    out = {"central_second": np.full((3, 3), np.nan), "bound_com": math.inf,
           "bound_central_second": math.inf,
           "relative": {"volume": math.inf, "com": math.inf, "inertia": math.inf}}
    if V == 0.0 or not np.isfinite(V):
        return out
    C = 0.5 * (second + second.T) - np.multiply.outer(first, first) / vol
    out["central_second"] = C
    k = math.sqrt(max(float(np.trace(C)), 0.0) / V)
    rel = {"volume": bv / V, "com": math.inf, "inertia": math.inf}
    if bv < V:
        nF, dF = float(np.linalg.norm(first)), float(np.linalg.norm(bf))
        bcom = (dF + nF / V * bv) / (V - bv)
        bC = float(np.linalg.norm(bs)) + (2 * nF * dF + dF * dF) / (V - bv) + nF * nF * bv / (V * (V - bv))
        out["bound_com"], out["bound_central_second"] = bcom, bC
        inertia = np.trace(C) * np.eye(3) - C
        nI = float(np.linalg.norm(inertia))
        rel["com"] = bcom / k if k > 0 else math.inf
        rel["inertia"] = 4.0 * bC / nI if nI > 0 else math.inf
    out["relative"] = rel
    return out


def _uncut_sums(pieces, p, stats):
    """Integrals about ``p`` of the faces no other face cuts, each patch weighted +-1 by one
    winding evaluation; returns ``(volume, first, second, number of undecided faces)``."""
    weights, _, n_uncertain = pieces.patch_weights()
    stats["patches"] = pieces.n_patches
    out = _k.weighted_sums(pieces.V, pieces.F, weights.astype(np.float64), p, pieces.threads)
    return unpacked_sums(out) + (n_uncertain,)


def robust_integrals(vertices, faces, reference=None, *, tol: float = 1e-3, max_pieces: int = 2_000_000,
                     max_depth: int = 30, time_budget: float | None = None, progress=None,
                     threads: int | None = None) -> RobustResult:
    """Volume integrals over {w >= 1/2} of any triangle soup, with an honest error bound.

    Parameters
    ----------
    vertices : (V, 3) float.  faces : (F, 3) int (any winding, open, overlapping...).
    reference : (3,) float, optional.  Point the integrals are about (default: box center).
    tol : float
        Target relative bound (volume / |V|, COM / radius of gyration, inertia / |I|).
    max_pieces : int, budget of face pieces examined while refining cut faces.
    max_depth : int, most 1 -> 4 splits of a cut face.
    time_budget : float, optional, seconds (default: none); the cap region's octree and the
        refinement stop (unconverged, ``stopped_by="time budget"``) once it is spent.
    progress : callable, optional, ``progress(fraction, bound)`` as the work goes on: the fraction
        done (0 to 1) and the relative bound reached so far (inf until one is known).
    threads : int, optional, threads of the compiled kernels (default: one per core); the
        result is the same, bit for bit, whatever their number.

    Returns
    -------
    RobustResult
    """
    t0 = time.perf_counter()
    if not (tol > 0):
        raise InputError(f"tol must be positive, got {tol!r}")
    if time_budget is not None and not (time_budget >= 0):
        raise InputError(f"time_budget must be a number of seconds >= 0, got {time_budget!r}")
    deadline = None if time_budget is None else t0 + time_budget
    tell = progress or (lambda fraction, bound: None)
    if threads is not None and not (isinstance(threads, (int, np.integer)) and threads >= 1):
        raise InputError(f"threads must be None or a positive integer, got {threads!r}")
    threads = int(threads or 0)
    v, f, mult, r, used, n_valid = _prepared(vertices, faces, reference)
    found = {}   # code -> message
    if (mult > 1).any():
        found["duplicate_faces"] = (f"{int((mult > 1).sum())} faces listed more than once with the same "
                                    "orientation (counted with multiplicity)")
    # every integral is taken about the box center p (one apex for all the pieces: the
    # weighted chain is closed only as a whole), then moved to the reference exactly
    vu = v[used]
    p = reference_point(vu)
    eps = EPS_REL * max(float(np.linalg.norm(vu.max(0) - vu.min(0))), 1e-300)
    caps, chain, cert, nbr = _closed_chain(v, f, mult, eps, threads)
    ne = len(caps.edges)
    stats = {"faces": len(faces), "boundary_edges": ne, "caps": len(caps.apex)}
    for code, n, what in zip(("open_edges", "inconsistent_winding", "non_manifold_edges"), caps.edge_kinds,
                             ("open", "inconsistently wound", "non-manifold")):
        if n:
            found[code] = (f"{n} {what} edges; the boundary ({ne} edges in {len(caps.apex)} loop(s)) is closed "
                           f"by caps ({int(caps.planar_simple.sum())} flat)")
    pieces = Pieces(*chain, p, eps, cert, nbr, threads)
    stats.update(pieces.find_cuts())
    if _mesh_faces_cross(pieces, len(f)):
        found["overlapping_shells"] = (f"{pieces.n_cut_pairs} pairs of faces cross or touch "
                                       f"({pieces.n_cut_faces} faces affected): self-intersections or overlapping "
                                       "shells")
    # 1. uncut faces: one winding evaluation per patch, then exact sums
    vol, first, second, n_uncertain = _uncut_sums(pieces, p, stats)
    if n_uncertain:
        found["undecided_windings"] = (f"{n_uncertain} faces whose side windings could not be decided "
                                       "(treated as unresolved)")
    tell(0.1, math.inf)
    # 2. cap region where {w >= 1/2} may differ from {w' >= 1}; ambiguity

    def stop(level):   # between the octree's levels: report, and end at the deadline
        tell(0.15 + 0.35 * (level + 1) / 11, math.inf)
        return deadline is not None and time.perf_counter() > deadline

    amb, (bv, bf, bs) = _cap_terms(caps, v, p, _volume_budget(vol, first, second, vu, p, 0.5 * tol), eps, stats,
                                   threads, stop)
    octree_left = stats.get("cap_cells_left", 0) > 0
    # 3. cut faces and uncertain patches: refine
    start = []

    def good_enough(val, extra):
        # the unresolved pieces shrink fourfold per level: go well below tol while cheap
        bound = _worst(derived_bounds(vol + val[0], first + val[1], second + val[2], bv + extra[0], bf + extra[1],
                                      bs + extra[2])["relative"])
        start.append(bound)   # progress: the orders of magnitude the bound has come towards the target
        target = REFINE_BELOW * tol
        span = math.log(start[0] / target) if target < start[0] < math.inf else 0.0
        gain = math.log(start[0] / bound) / span if span and 0 < bound < math.inf else 0.0
        tell(0.5 + 0.5 * min(max(gain, 0.0), 1.0), bound)
        return bound <= target

    rv, rf, rs, ev, ef, es, info = pieces.refine(good_enough, max_pieces, max_depth, deadline)
    vol, first, second = vol + rv, first + rf, second + rs
    bv, bf, bs = bv + ev, bf + ef, bs + es
    stats.update(info)
    if pieces.w_max >= 2:
        found["overlapping_shells"] = "; ".join(filter(None, (found.get("overlapping_shells"), (
            "regions of winding number >= 2: overlapping shells or repeated faces (counted once: union)"))))
    if pieces.w_min <= -1:
        found["inverted"] = "regions of negative winding number: inside-out shells outside the solid (counted as empty)"
    der = derived_bounds(vol, first, second, bv, bf, bs)
    ok = all(x <= tol for x in der["relative"].values())
    stopped_by = None
    if not ok:
        late = deadline is not None and time.perf_counter() > deadline
        stopped_by = info.get("stopped_by") or ("time budget" if late else "octree limit" if octree_left else None)
        found["bound_not_reached"] = (f"the error bound did not reach tol={tol:g}"
                                      + (f" (stopped by the {stopped_by})" if stopped_by else "") + ": "
                                      + ", ".join(f"{k} {x:.3g}" for k, x in der["relative"].items()))
    if r is not None:
        vol, first, second, bv, bf, bs = _moved(vol, first, second, bv, bf, bs, p - r)
        p = r
    stats["seconds"] = time.perf_counter() - t0
    if n_valid > len(f) and "duplicate_faces" not in found:
        found["duplicate_faces"] = f"{n_valid - len(f)} faces repeat or cancel another (counted once, or not at all)"
    order = ("duplicate_faces", "open_edges", "non_manifold_edges", "inconsistent_winding", "inverted",
             "overlapping_shells", "undecided_windings", "bound_not_reached")
    findings = tuple(Finding(code, found[code]) for code in order if code in found)
    res = RobustResult(float(vol), first, second, p.copy(), float(bv), bf, bs, float(amb), ok, tol, findings,
                       stats, der, stopped_by)
    tell(1.0, res.bound)
    return res


def _mesh_faces_cross(pieces, n_mesh: int) -> bool:
    """Two faces of the mesh (not of the caps) cross or touch."""
    return bool(np.any((np.repeat(np.arange(len(pieces.F)), np.diff(pieces.cut_ptr)) < n_mesh)
                       & (pieces.cut_idx < n_mesh)))


def _closed_chain(v, f, mult, eps, threads):
    """The caps and the closed chain ``(V, F, M)`` (mesh and caps), its certified vertices and
    the face across each manifold edge (``vertex_pass``): one pass over the mesh, then again
    over the vertices the caps touch."""
    nv, nf = len(v), len(f)
    cert, nbr = np.zeros(nv, np.bool_), np.full((nf, 3), -1, np.int64)
    edge_kinds, edges, emult = _k.vertex_pass(v, f, mult, np.arange(nv), cert, nbr, threads)
    caps = Caps(v, edges, emult, eps)
    caps.edge_kinds = edge_kinds
    if not len(edges):
        return caps, (v, f, mult), cert, nbr
    V = np.ascontiguousarray(np.concatenate([v, caps.apex]))
    F = np.ascontiguousarray(np.concatenate([f, caps.faces]))
    M = np.ascontiguousarray(np.concatenate([mult, caps.mult]))
    cert = np.concatenate([cert, np.zeros(len(caps.apex), np.bool_)])
    nbr = np.concatenate([nbr, np.full((len(caps.faces), 3), -1, np.int64)])
    touched = np.union1d(np.unique(edges), np.arange(nv, len(V)))
    _k.vertex_pass(V, F, M, touched, cert, nbr, threads)
    return caps, (V, F, M), cert, nbr


def _prepared(vertices, faces, reference):
    """Validated ``(vertices, faces, multiplicities, reference or None, used-vertex mask, number of
    faces with three distinct corners)``;
    exactly coincident vertices merged (no tolerance: the geometry is unchanged), so that
    repeated copies of faces are recognised as one face with a multiplicity."""
    v, f = validate_inputs(vertices, faces)
    if len(f) == 0:
        raise InputError("faces is empty: a mesh needs at least one triangle")
    if f.min() < 0 or f.max() >= len(v):
        raise InputError(f"a face holds a vertex index outside [0, {len(v)})")
    used = np.zeros(len(v), bool)
    used[f.ravel()] = True
    if not np.isfinite(v[used]).all():
        raise InputError("a vertex used by a face is not finite")
    r = None
    if reference is not None:
        r = np.asarray(reference, dtype=np.float64)
        if r.shape != (3,) or not np.isfinite(r).all():
            raise InputError(f"reference must be a finite (3,) point, got {reference!r}")
    fw = np.ascontiguousarray(weld_map(v)[f], dtype=np.int64)
    out, mult = _k.dedupe_faces(fw, len(v))
    if len(out) == 0:
        raise InputError("every face is degenerate or cancelled by an opposite copy: nothing to integrate")
    n_valid = int(np.count_nonzero((fw[:, 0] != fw[:, 1]) & (fw[:, 1] != fw[:, 2]) & (fw[:, 2] != fw[:, 0])))
    return np.ascontiguousarray(v), out, mult, r, used, n_valid


def _cap_terms(caps, v, p, enough, eps, stats, threads, stop=None):
    """``(ambiguous volume, (bound_volume, bound_first, bound_second))`` of the cap region
    (``stop(level)``: see :func:`cap_region_bound`)."""
    zero = (0.0, np.zeros(3), np.zeros((3, 3)))
    if not len(caps.apex):
        return 0.0, zero
    geo = CapGeometry(caps, v, eps)
    # an indicator, not an error: a coarse octree is enough
    amb = cap_region_bound(geo, AMBIGUOUS_LOW, p, max_level=4, max_cells=20_000, threads=threads,
                           max_work=MAX_CAP_WORK // 10)[0]
    if len(caps.apex) == 1 and caps.planar_simple[0]:
        return amb, zero
    cv, cf1, cs2, left = cap_region_bound(geo, 0.5, p, enough=enough, threads=threads, stop=stop)
    stats["cap_cells_left"] = left
    return amb, (cv, cf1, cs2)


def _moved(vol, first, second, bv, bf, bs, d):
    """Integrals and bounds about p moved to r = p - d: ``x - r = (x - p) + d`` (exact identities)."""
    Fd = np.multiply.outer(first, d)
    ad = np.abs(d)
    bFd = np.multiply.outer(bf, ad)
    return (vol, first + vol * d, second + Fd + Fd.T + vol * np.multiply.outer(d, d),
            bv, bf + bv * ad, bs + bFd + bFd.T + bv * np.multiply.outer(ad, ad))


def _volume_budget(vol, first, second, vertices, p, target):
    """The volume bound, placed as far from p as the mesh reaches, whose derived relative
    bounds (volume, COM, inertia) stay within ``target``: the octree's stopping point."""
    m = np.maximum(np.abs(vertices.min(0) - p), np.abs(vertices.max(0) - p))
    unit = 1e-6 * abs(vol)
    rel = derived_bounds(vol, first, second, unit, unit * m, unit * np.outer(m, m))["relative"]
    worst = max(rel.values())
    return target * unit / worst if worst > 0 and np.isfinite(worst) else 0.25 * target * abs(vol)


def _worst(relative: dict) -> float:
    """The largest relative bound (NaN counts as inf)."""
    return max(math.inf if x != x else x for x in relative.values())
