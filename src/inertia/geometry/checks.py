"""Defect checks of triangle meshes, each reported by name with a count and an example location.

:func:`check_mesh` answers "will the volume integrals of this mesh be right?" before any
number is computed.  Every defect is a :class:`~inertia.errors.Finding` with a stable ``code``:

=======================  ===============================================================
code                     meaning
=======================  ===============================================================
``empty``                no vertices, no faces, or only zero-area faces
``non_finite``           a vertex coordinate is NaN or infinite
``out_of_range``         a coordinate beyond +-COORDINATE_LIMIT (1e60): the second moments
                         (size**5) would overflow float64
``bad_index``            a face index is negative or >= the number of vertices
``degenerate_faces``     zero (or ~zero) area faces, or faces repeating a vertex (a note:
                         they add nothing to the integrals, see below)
``duplicate_faces``      the same three vertices used by more than one face
``open_edges``           an edge used by only one face (the surface has holes)
``non_manifold_edges``   an edge used by more than two faces
``inconsistent_winding`` an edge traversed in the same direction by its two faces
``inverted``             a closed, consistently wound component whose signed volume has
                         the wrong sign (wound inward), not explained by nesting
``overlapping_shells``   two closed components whose volumes overlap (the integrals would
                         count the overlap twice): one's surface runs both inside and
                         outside the other, or their faces cross
                         (:mod:`inertia.geometry.intersections`)
``self_intersecting``    a closed component passes through itself: two of its faces
                         cross (:mod:`inertia.geometry.self_crossing`)
``self_crossing_negligible`` (a note) faces cross, but change the mass properties by
                         less than ``NEGLIGIBLE_RTOL`` (1e-4) against the solid the surface
                         bounds once (tiny slivers of real exports)
``self_crossing_unchecked`` (a note) a shell not star-shaped from its center of mass and
                         too large for the face-pair search (over ``SEARCH_MAX_FACES``)
=======================  ===============================================================

Vertices with exactly equal coordinates are welded before the topology checks (OBJ and STL
files split vertices at texture/normal seams or per face); indices in the report are the
caller's own, the lowest index of each welded group standing for the group.

Self-crossing is proved absent in one pass for a shell star-shaped from its center of mass, and
searched face pair by face pair otherwise, up to ``SEARCH_MAX_FACES`` faces (the search costs
10-50x the integrals); beyond that the report carries the note ``self_crossing_unchecked``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._core.tolerances import COORDINATE_LIMIT, DEGENERATE_AREA_RTOL
from .._ext import integrals as _k
from .integrals import solid_integrals, solid_sums_moments
from .intersections import overlapping_components, winding_numbers
from .mesh_arrays import connected_components, faces_in_range, validate_inputs, weld_map
from .report import MESH_CODES, MeshReport, fmt_point, mesh_finding, plural
from .self_crossing import NEGLIGIBLE_RTOL, SEARCH_MAX_FACES, Crossing, crossing_effect, self_crossing

_MAX_CONTAIN_POINTS = 6  # extreme vertices of a component tested for nesting in another

__all__ = ["check_mesh", "analyse_mesh", "clean_analysis", "MeshAnalysis"]



# ---------------------------------------------------------------------------------- analysis
@dataclass
class MeshAnalysis:
    """Everything :func:`check_mesh` learns, kept for :mod:`inertia.massprops.mesh` (internal)."""

    report: MeshReport
    faces_welded: np.ndarray | None = None       # (F, 3) representative indices (valid faces)
    topo: np.ndarray | None = None               # (F,) bool, face used in the edge topology
    labels: np.ndarray | None = None             # (F,) component of each face, -1 outside the topology
    n_components: int = 0
    pairs: np.ndarray | None = None              # (P, 3): face1, face2, 1 if same direction (2-face edges)
    comp_volume: np.ndarray | None = None        # (K,) signed volume per component
    inverted_components: np.ndarray = field(default_factory=lambda: np.zeros(0, dtype=np.int64))
    closed: bool = False
    labels_topo: np.ndarray | None = None        # (T,) component of each topology face
    #: a clean solid's volume sums from the compiled check (``inertia._ext.integrals.clean_solid``)
    solid_sums: np.ndarray | None = None


def _nesting_depth(vertices, faces_t, labels_t, K, comp_lo, comp_hi) -> np.ndarray:
    """How many other closed components enclose each component (0 for an outer body).

    A is taken to be inside B when A's bounding box lies within B's and the extreme
    vertices of A (min and max along each axis) all have |winding number of B| > 1/2.
    """
    depth = np.zeros(K, dtype=np.int64)
    if K < 2:
        return depth
    # extreme vertices of each component: argmin / argmax along each axis over its face corners
    corners = faces_t.ravel()
    corner_comp = np.repeat(labels_t, 3)
    pts = vertices[corners]
    extreme = np.empty((K, _MAX_CONTAIN_POINTS, 3))
    order_by_comp = np.argsort(corner_comp, kind="stable")
    starts = np.searchsorted(corner_comp[order_by_comp], np.arange(K + 1))
    for k in range(K):
        idx = order_by_comp[starts[k]:starts[k + 1]]
        P = pts[idx]
        for ax in range(3):
            extreme[k, 2 * ax] = P[np.argmin(P[:, ax])]
            extreme[k, 2 * ax + 1] = P[np.argmax(P[:, ax])]
    face_order = np.argsort(labels_t, kind="stable")
    fstarts = np.searchsorted(labels_t[face_order], np.arange(K + 1))
    for b in range(K):
        inside_box = np.all((comp_lo >= comp_lo[b]) & (comp_hi <= comp_hi[b]), axis=1)
        inside_box[b] = False
        cand = np.flatnonzero(inside_box)
        if len(cand) == 0:
            continue
        tri = vertices[faces_t[face_order[fstarts[b]:fstarts[b + 1]]]]
        w = winding_numbers(extreme[cand].reshape(-1, 3), tri).reshape(len(cand), _MAX_CONTAIN_POINTS)
        depth[cand[np.all(np.abs(w) > 0.5, axis=1)]] += 1
    return depth


def _analyse_clean(vertices: np.ndarray, faces: np.ndarray, welded: bool, weld_first: bool,
                   search: bool = True) -> MeshAnalysis | None:
    """The analysis of a mesh without any defect, from the compiled kernel (or of one clean
    shell but for a self-crossing: its report names it, ``solid_sums`` None); None otherwise.

    The kernel (``inertia._ext.integrals.clean_solid``, ``src/ext/integrals/clean_solid.hpp``)
    also returns the volume sums, kept in ``MeshAnalysis.solid_sums``.  With ``weld_first=False``
    the faces are tried as given first (most indexed meshes are welded already) and welded only
    when that fails; the report then counts no welded duplicates.
    """
    V = len(vertices)
    if V == 0 or len(faces) == 0:
        return None
    v = np.ascontiguousarray(vertices)
    # None: the welded faces, made only if the faces as given do not pass
    tries = [faces] if welded else [None] if weld_first else [faces, None]
    n_welded = 0
    for fw in tries:
        if fw is None:
            if not faces_in_range(faces, V):
                return None    # the full analysis names the bad indices (rep[-1] would wrap)
            rep = weld_map(v)
            fw = rep[faces]
            n_welded = int(V - np.count_nonzero(rep == np.arange(V)))
        fw = np.ascontiguousarray(fw)
        # the face across each edge, for the self-crossing check (noted by the kernel only if the
        # shell is not proved star-shaped in its pass; pages of an array not written cost nothing)
        twins = np.empty((len(fw) if search and len(fw) <= SEARCH_MAX_FACES else 0, 3), dtype=np.int64)
        out = _k.clean_solid(v, fw, DEGENERATE_AREA_RTOL, COORDINATE_LIMIT, twins)
        if out is not None:
            volume = out[0] / 6.0
            crossing = None if out[14] == 1.0 else _crossing_of(v, fw, out[11:14] + (out[1:4] / 24.0) / volume,
                                                                search, twins)
            if crossing == "unchecked":
                defects = (_unchecked_note(len(faces)),)
            elif crossing is None:
                defects = ()
            else:
                effect = crossing_effect(v, fw, (volume, *solid_sums_moments(out)[1:], out[11:14]))
                if max(effect.values()) > NEGLIGIBLE_RTOL:
                    # one clean shell but for its crossings: named here, not searched and weighed again
                    report = MeshReport((_intersecting_defect(crossing, effect, "the closed surface passes"),),
                                        V, len(faces), n_welded, 1, volume, 0.5 * out[10])
                    return MeshAnalysis(report, faces_welded=fw, n_components=1, comp_volume=np.array([volume]),
                                        closed=True)
                defects = (_negligible_note(crossing, effect),)
            report = MeshReport(defects, V, len(faces), n_welded, 1, volume, 0.5 * out[10])
            return MeshAnalysis(report, faces_welded=fw, n_components=1, comp_volume=np.array([volume]),
                                closed=True, solid_sums=out)
    return None


def _intersecting_defect(crossing, effect: dict, whole: str):
    """The defect ``self_intersecting`` for ``crossing`` (the first found), weighed by ``effect``;
    ``whole`` says what passes through itself."""
    a, b = crossing.faces
    figures = ", ".join(f"{k} {x:.1e}" for k, x in effect.items())
    off = (f"the integrals are off by up to {figures} (relative)" if all(np.isfinite(list(effect.values())))
           else "it has no volume in double precision (the integrals have no scale to compare)")
    return mesh_finding("self_intersecting", 1,
                        f"{whole} through itself (the integrals count the region it encloses twice, or negative), "
                        f"e.g. faces {a} and {b} cross near {fmt_point(crossing.point)}; against the solid it bounds "
                        f"once {off}",
                        {"faces": (a, b), "point": tuple(float(x) for x in crossing.point), "effect": effect})


def _negligible_note(crossing, effect: dict):
    a, b = crossing.faces
    figures = ", ".join(f"{k} {x:.1e}" for k, x in effect.items())
    return mesh_finding("self_crossing_negligible", 1,
                  f"faces {a} and {b} cross near {fmt_point(crossing.point)}, but the crossings change the mass "
                  f"properties by at most {figures} (relative; under {NEGLIGIBLE_RTOL:g}): the solid is taken as "
                        "given", {"faces": (a, b), "effect": dict(effect)})


def _crossing_of(vertices, faces, center, search: bool, face_twins=None):
    """:func:`.self_crossing.self_crossing` with the search up to SEARCH_MAX_FACES, or none
    (``self_crossing="certificate"``: a shell the certificate does not prove gets the note
    self_crossing_unchecked)."""
    return self_crossing(vertices, faces, center, max_faces=SEARCH_MAX_FACES if search else 0,
                         face_twins=face_twins)


def clean_analysis(vertices: np.ndarray, faces: np.ndarray, *, welded: bool = False,
                   weld_first: bool = False, search: bool = True) -> MeshAnalysis | None:
    """The analysis of a mesh without any defect (compiled check and sums in one pass, in
    ``solid_sums``); of one clean shell but for a self-crossing (its report names it;
    ``solid_sums`` None); or None when it cannot be checked that way: then
    :func:`analyse_mesh` names the defects."""
    return _analyse_clean(vertices, faces, welded, weld_first, search)


def _unchecked_note(n_faces: int):
    return mesh_finding("self_crossing_unchecked", 1,
                  f"not proven free of self-crossings: the shell ({plural(n_faces, 'face')}) is not star-shaped from "
                  f"its center of mass, and the face-pair search stops at {SEARCH_MAX_FACES} faces (0.2-0.6 us a "
                  "face); inertia.geometry.self_crossing.first_crossing runs it, on_defect='robust' integrates "
                  "any crossing",
                        {"n_faces": n_faces})


class _Defects(list):
    """The defects found so far; ``add`` appends one with its severity."""

    def add(self, code, count, message, example):
        self.append(mesh_finding(code, count, message, example))


def analyse_mesh(vertices: np.ndarray, faces: np.ndarray, *, welded: bool = False, full: bool = False,
                 weld_first: bool = True, self_crossing: str = "search") -> MeshAnalysis:
    """Run every check on validated arrays; see :func:`check_mesh`.

    ``welded=True`` promises that no two vertices have equal coordinates (as
    :func:`inertia.load_mesh` returns them), which skips the welding; ``weld_first=False``
    tries the faces as given before welding (see :func:`_analyse_clean`).  A mesh without any
    defect is recognised by the compiled clean-solid pass; ``full=True`` always
    runs the NumPy analysis, which also fills the face-adjacency fields that re-orienting needs.
    The passes, in order: empty, non-finite coordinates, indices, welding, face geometry,
    degenerate faces, then (on the valid faces) duplicates, edges, components, inversion.
    """
    if not full:
        clean = _analyse_clean(vertices, faces, welded, weld_first, self_crossing == "search")
        if clean is not None:
            return clean
    V, F = len(vertices), len(faces)
    defects = _Defects()
    if V == 0 or F == 0:                       # empty: nothing else can be checked
        defects.add("empty", 1, f"empty mesh: {V} vertices, {F} faces", {"n_vertices": V, "n_faces": F})
        return MeshAnalysis(MeshReport(tuple(defects), V, F))
    finite_v = _non_finite_pass(vertices, defects)
    valid = _index_pass(faces, V, defects)
    fv = np.where(valid[:, None], faces, 0)  # safe indices; invalid rows are masked everywhere below
    rep = np.arange(V, dtype=np.int64) if welded else weld_map(vertices)
    fw = rep[fv]
    n_welded = int(V - np.count_nonzero(rep == np.arange(V)))
    geo = valid & finite_v[fv].all(axis=1)
    twice_area, det, longest2 = _face_geometry(vertices, fv, geo)
    total_area = float(0.5 * twice_area.sum()) if finite_v.all() else math.nan
    collapsed = _degenerate_pass(faces, fw, valid, geo, twice_area, longest2, defects)
    # topology on valid, non-collapsed faces (zero-area faces with distinct corners stay:
    # removing them could open the surface)
    topo = valid & ~collapsed
    tidx = np.flatnonzero(topo)
    analysis = MeshAnalysis(MeshReport(), faces_welded=fw, topo=topo)
    signed_volume = math.nan
    if len(tidx):
        ft = fw[tidx]
        _duplicate_pass(ft, tidx, V, defects)
        edges = _EdgeGroups(ft, V)
        incons, closed_edges = _edge_pass(edges, vertices, tidx, defects)
        _component_pass(edges, tidx, F, det, analysis)
        analysis.closed = closed_edges and bool(geo[tidx].all())
        if analysis.closed:
            signed_volume = float(analysis.comp_volume.sum())
            if not len(incons):
                _inverted_pass(vertices, ft, tidx, analysis, defects)
                _overlap_pass(vertices, ft, tidx, analysis, defects)
                _self_crossing_pass(vertices, ft, tidx, analysis, defects, self_crossing == "search")
    defects.sort(key=lambda d: MESH_CODES.index(d.code))
    analysis.report = MeshReport(tuple(defects), V, F, n_welded, int(analysis.n_components), signed_volume,
                                 total_area)
    return analysis


def _non_finite_pass(vertices, defects) -> np.ndarray:
    """Vertices with NaN or inf coordinates, or beyond COORDINATE_LIMIT; returns the mask (V,)
    of usable vertices."""
    finite_v = np.isfinite(vertices).all(axis=1)
    with np.errstate(invalid="ignore"):
        in_range = (np.abs(vertices) <= COORDINATE_LIMIT).all(axis=1) | ~finite_v
    for code, mask, what in (("non_finite", ~finite_v, "NaN or infinite coordinates"),
                             ("out_of_range", ~in_range, f"a coordinate beyond +-{COORDINATE_LIMIT:.0e} (the second "
                              "moments, ~size**5, would overflow; check the units)")):
        if mask.any():
            bad = np.flatnonzero(mask)
            k = int(bad[0])
            defects.add(code, len(bad), f"{plural(len(bad), 'vertex', 'vertices')} with {what}, "
                        f"e.g. vertex {k} at {fmt_point(vertices[k])}",
                        {"vertex": k, "coords": (tuple(float(x) for x in vertices[k]),)})
    return finite_v & in_range


def _index_pass(faces, V: int, defects) -> np.ndarray:
    """Faces with an index outside ``0..V-1``; returns the valid-face mask (F,)."""
    bad_face = ((faces < 0) | (faces >= V)).any(axis=1)
    if bad_face.any():
        bad = np.flatnonzero(bad_face)
        k = int(bad[0])
        defects.add("bad_index", len(bad),
                    f"{plural(len(bad), 'face')} with a vertex index outside 0..{V - 1}, "
                    f"e.g. face {k} = {tuple(int(i) for i in faces[k])}",
                    {"face": k, "vertices": tuple(int(i) for i in faces[k])})
    return ~bad_face


def _face_geometry(vertices, fv, geo):
    """``(twice_area (F,), det (F,), longest2 (F,))`` of faces with finite corners, relative to
    the bbox center.

    ``det = a.(b x c)`` is six times the signed volume of the tetrahedron on the center;
    ``longest2`` is each face's longest edge squared (the scale of "zero area").
    """
    V = len(vertices)
    used = np.zeros(V, dtype=bool)
    used[fv[geo].ravel()] = True
    if used.any():
        lo, hi = vertices[used].min(axis=0), vertices[used].max(axis=0)
        ref = 0.5 * (lo + hi)
    else:
        ref = np.zeros(3)
    with np.errstate(invalid="ignore", over="ignore"):
        tri = vertices[fv] - ref
        a0 = tri[:, 0]
        e1, e2 = tri[:, 1] - a0, tri[:, 2] - a0
        nrm = np.empty_like(e1)                                   # twice the area vector e1 x e2
        nrm[:, 0] = e1[:, 1] * e2[:, 2] - e1[:, 2] * e2[:, 1]
        nrm[:, 1] = e1[:, 2] * e2[:, 0] - e1[:, 0] * e2[:, 2]
        nrm[:, 2] = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
        twice_area = np.where(geo, np.sqrt(np.einsum("ij,ij->i", nrm, nrm)), 0.0)
        det = np.where(geo, np.einsum("ij,ij->i", a0, nrm), 0.0)
        e3 = e2 - e1
        longest2 = np.maximum(np.maximum(np.einsum("ij,ij->i", e1, e1), np.einsum("ij,ij->i", e2, e2)),
                              np.einsum("ij,ij->i", e3, e3))
    return twice_area, det, longest2


def _degenerate_pass(faces, fw, valid, geo, twice_area, longest2, defects) -> np.ndarray:
    """Zero-area faces (a repeated vertex after welding, or area below the tolerance), and a
    mesh of nothing but those; returns the mask of faces repeating a vertex (F,)."""
    collapsed = valid & ((fw[:, 0] == fw[:, 1]) | (fw[:, 1] == fw[:, 2]) | (fw[:, 2] == fw[:, 0]))
    tiny = geo & (0.5 * twice_area <= DEGENERATE_AREA_RTOL * longest2)
    degenerate = collapsed | tiny
    if degenerate.any():
        bad = np.flatnonzero(degenerate)
        k = int(bad[0])
        why = "repeats a vertex" if collapsed[k] else f"has area {0.5 * twice_area[k]:.3g}"
        defects.add("degenerate_faces", len(bad),
                    f"{plural(len(bad), 'face')} of zero area ({int(collapsed.sum())} repeating a vertex after "
                    f"welding; area <= {DEGENERATE_AREA_RTOL:g} x its longest edge^2), e.g. face {k} = "
                    f"{tuple(int(i) for i in faces[k])} {why}",
                    {"face": k, "vertices": tuple(int(i) for i in faces[k]), "area": float(0.5 * twice_area[k])})
    if valid.any() and degenerate[valid].all():
        defects.add("empty", 1, f"empty mesh: all {int(valid.sum())} valid faces are degenerate (zero area)",
                    {"n_vertices": len(fw), "n_faces": len(faces)})
    return collapsed


def _duplicate_pass(ft, tidx, V: int, defects) -> None:
    """Faces with the same vertex set as another, either orientation (one int64 key when it fits)."""
    key3 = np.sort(ft, axis=1)
    if V < 2**21:
        k3 = (key3[:, 0] * V + key3[:, 1]) * V + key3[:, 2]
        if not np.any(np.diff(np.sort(k3)) == 0):
            return
    o3 = np.lexsort((key3[:, 2], key3[:, 1], key3[:, 0]))
    s3 = key3[o3]
    same_as_prev = np.all(s3[1:] == s3[:-1], axis=1)
    if same_as_prev.any():
        j = int(np.argmax(same_as_prev))
        fa, fb = sorted((int(tidx[o3[j]]), int(tidx[o3[j + 1]])))
        n_dup = int(same_as_prev.sum())
        defects.add("duplicate_faces", n_dup,
                    f"{plural(n_dup, 'duplicate face')} (same three vertices as another face), "
                    f"e.g. faces {fa} and {fb} both use vertices {tuple(int(i) for i in s3[j])}",
                    {"faces": (fa, fb), "vertices": tuple(int(i) for i in s3[j])})


class _EdgeGroups:
    """Half-edges grouped by undirected edge: ``h = 3 t + k`` goes from corner k to k+1 of face t."""

    def __init__(self, ft, V: int):
        self.src = src = ft.ravel()
        self.dst = dst = ft[:, [1, 2, 0]].ravel()
        key = np.minimum(src, dst) * np.int64(V) + np.maximum(src, dst)
        self.order = order = np.argsort(key, kind="stable")   # stable: examples list faces in index order
        self.skey = skey = key[order]
        self.start = start = np.flatnonzero(np.r_[True, skey[1:] != skey[:-1]])
        self.counts = np.diff(np.r_[start, len(skey)])
        self.first_h = order[start]
        forward = (src < dst)[order]                       # direction of each sorted half-edge
        self.n_forward = np.add.reduceat(forward.astype(np.int64), start)

    def example(self, e, vertices, tidx):
        """``(text, dict)`` naming edge group ``e``: its vertices, coordinates and faces."""
        h = int(self.first_h[e])
        i, j = int(self.src[h]), int(self.dst[h])
        hs = self.order[self.start[e]:self.start[e] + self.counts[e]]
        fl = tuple(int(tidx[x // 3]) for x in hs)
        text = f"edge ({i}, {j}) from {fmt_point(vertices[i])} to {fmt_point(vertices[j])}"
        return text, {"edge": (i, j), "coords": (tuple(float(x) for x in vertices[i]),
                                                  tuple(float(x) for x in vertices[j])), "faces": fl}


def _edge_pass(edges: _EdgeGroups, vertices, tidx, defects):
    """Open, non-manifold and inconsistently wound edges; returns ``(inconsistent groups, closed)``."""
    counts, n_forward = edges.counts, edges.n_forward
    open_e = np.flatnonzero(counts == 1)
    if len(open_e):
        text, ex = edges.example(open_e[0], vertices, tidx)
        defects.add("open_edges", len(open_e),
                    f"{plural(len(open_e), 'open edge')} (used by only one face: the surface has holes), "
                    f"e.g. {text} in face {ex['faces'][0]}", ex)
    nm_e = np.flatnonzero(counts > 2)
    if len(nm_e):
        text, ex = edges.example(nm_e[0], vertices, tidx)
        # balanced: traversed as often in each direction (e.g. two closed parts touching
        # along the edge); the surface is then still closed for the volume integrals
        n_bal = int(np.sum(2 * n_forward[nm_e] == counts[nm_e]))
        bal = (f"; all {n_bal} balanced (traversed equally often in both directions, as where closed "
               f"parts touch along an edge)" if n_bal == len(nm_e) else
               f"; {n_bal} of them balanced" if n_bal else "")
        ex["balanced"] = n_bal
        defects.add("non_manifold_edges", len(nm_e),
                    f"{plural(len(nm_e), 'non-manifold edge')} (used by more than two faces{bal}), "
                    f"e.g. {text} shared by {len(ex['faces'])} faces {ex['faces']}", ex)
    two = np.flatnonzero(counts == 2)
    incons = two[n_forward[two] != 1]
    if len(incons):
        text, ex = edges.example(incons[0], vertices, tidx)
        fl = ex["faces"]
        defects.add("inconsistent_winding", len(incons),
                    f"{plural(len(incons), 'edge')} with inconsistent winding (both faces traverse it in the "
                    f"same direction: some faces are flipped), e.g. {text} in faces {fl[0]} and {fl[1]}", ex)
    return incons, not (len(open_e) or len(nm_e))


def _component_pass(edges: _EdgeGroups, tidx, F: int, det, analysis) -> None:
    """Face pairs across 2-face edges, edge-connected components and their signed volumes."""
    order, start, counts = edges.order, edges.start, edges.counts
    two = np.flatnonzero(counts == 2)
    same_dir = (edges.n_forward[two] != 1)
    t1, t2 = order[start[two]] // 3, order[start[two] + 1] // 3
    pairs = np.stack([tidx[t1], tidx[t2], same_dir.astype(np.int64)], axis=1)
    # every face sharing an edge with another is connected (consecutive half-edges of a group)
    link = edges.skey[1:] == edges.skey[:-1]
    ga, gb = order[:-1][link] // 3, order[1:][link] // 3
    n_comp, lab_t = connected_components(len(tidx), ga, gb)
    labels = np.full(F, -1, dtype=np.int64)
    labels[tidx] = lab_t
    analysis.labels, analysis.n_components, analysis.pairs = labels, n_comp, pairs
    # signed volume per component (faces with finite corners; relative to the bbox center)
    analysis.comp_volume = np.bincount(lab_t, weights=det[tidx], minlength=n_comp) / 6.0
    analysis.labels_topo = lab_t


def _inverted_pass(vertices, ft, tidx, analysis, defects) -> None:
    """Closed, consistently wound components wound inward, allowing for nesting (a cavity is negative)."""
    n_comp, lab_t, comp_vol = analysis.n_components, analysis.labels_topo, analysis.comp_volume
    depth = np.zeros(n_comp, dtype=np.int64)
    if n_comp > 1:
        comp_lo, comp_hi = _component_boxes(vertices, ft, lab_t, n_comp)
        depth = _nesting_depth(vertices, ft, lab_t, n_comp, comp_lo, comp_hi)
    expected = np.where(depth % 2 == 0, 1.0, -1.0)
    inverted = np.flatnonzero(comp_vol * expected < 0)
    analysis.inverted_components = inverted
    if len(inverted):
        c = int(inverted[0])
        f0 = int(tidx[np.argmax(lab_t == c)])
        nested = " (nested inside another component, so it should be negative)" if depth[c] % 2 else ""
        whole = "the closed surface is" if n_comp == 1 else \
            f"{plural(len(inverted), 'component')} of {n_comp} {'is' if len(inverted) == 1 else 'are'}"
        defects.add("inverted", len(inverted),
                    f"{whole} wound inward (normals point in: signed volume has the wrong sign), "
                    f"e.g. component {c} containing face {f0}, signed volume {comp_vol[c]:.6g}{nested}",
                    {"component": c, "face": f0, "volume": float(comp_vol[c])})


def _overlap_pass(vertices, ft, tidx, analysis, defects) -> None:
    """Closed components whose volumes overlap (see :mod:`.intersections`)."""
    if analysis.n_components < 2 or len(analysis.inverted_components):
        return
    lab = analysis.labels_topo
    lo, hi = _component_boxes(vertices, ft, lab, analysis.n_components)
    found = overlapping_components(vertices, ft, lab, lo, hi)
    if found:
        a, b, point = found[0]
        defects.add("overlapping_shells", len(found),
                    f"{plural(len(found), 'pair')} of closed components overlap (the integrals would count the "
                    f"overlap twice), e.g. components {a} and {b} near {fmt_point(point)}",
                    {"components": (a, b), "point": tuple(float(x) for x in point)})


def _self_crossing_pass(vertices, ft, tidx, analysis, defects, search: bool = True) -> None:
    """Closed components that pass through themselves (see :mod:`.self_crossing`): an error,
    unless the crossings change the mass properties negligibly (a note)."""
    if len(analysis.inverted_components):
        return
    lab, K = analysis.labels_topo, analysis.n_components
    found, negligible, unchecked = [], [], 0
    order = np.argsort(lab, kind="stable")
    starts = np.searchsorted(lab[order], np.arange(K + 1))
    for k in range(K):
        rows = order[starts[k]:starts[k + 1]]
        fk = ft[rows]
        crossing = _crossing_of(vertices, fk, _volume_centroid(vertices, fk), search)
        if crossing is None:
            continue
        if crossing == "unchecked":
            unchecked += 1
            continue
        a, b = (int(tidx[rows[x]]) for x in crossing.faces)
        shown = Crossing((a, b), crossing.point)
        effect = crossing_effect(vertices, fk, solid_integrals(vertices, fk))
        (negligible if max(effect.values()) <= NEGLIGIBLE_RTOL else found).append((shown, effect))
    if found:
        whole = "the closed surface passes" if K == 1 else \
            f"{plural(len(found), 'closed component')} of {K} {'passes' if len(found) == 1 else 'pass'}"
        defect = _intersecting_defect(*found[0], whole)
        defects.add(defect.code, len(found), defect.message, defect.values["example"])
    elif negligible:
        note = _negligible_note(*negligible[0])
        defects.add(note.code, len(negligible), note.message, note.values["example"])
    if unchecked and not found:
        note = _unchecked_note(len(ft))
        defects.add(note.code, unchecked, note.message, note.values["example"])


def _volume_centroid(vertices, faces) -> np.ndarray:
    """Centroid of the solid a closed, outward shell bounds (tetrahedra on its box center)."""
    tri = vertices[faces]
    ref = 0.5 * (tri.reshape(-1, 3).min(axis=0) + tri.reshape(-1, 3).max(axis=0))
    tri = tri - ref
    det = np.einsum("ij,ij->i", tri[:, 0], np.cross(tri[:, 1], tri[:, 2]))
    total = det.sum()
    return ref + (det @ tri.sum(axis=1)) / (4.0 * total) if total > 0 else ref


def _component_boxes(vertices, ft, lab, K):
    """Bounding boxes (K, 3) lo and hi of the components (faces ``ft`` labelled ``lab``; each of
    0..K-1 labels a face): the faces sorted by component, reduced per run (cheaper than ufunc.at)."""
    order = np.argsort(lab, kind="stable")
    tri = vertices[ft[order]]
    starts = np.searchsorted(lab[order], np.arange(K))
    return np.minimum.reduceat(tri.min(axis=1), starts, axis=0), np.maximum.reduceat(tri.max(axis=1), starts, axis=0)


def check_mesh(vertices, faces) -> MeshReport:
    """Check a triangle mesh for every defect that would make its mass properties wrong.

    Parameters
    ----------
    vertices : (V, 3) float, any length unit.
    faces : (F, 3) int, vertex indices (float arrays of integral values are accepted).

    Returns
    -------
    MeshReport
        Each defect by code with a count and an example location (face index, vertex index,
        or edge as a vertex pair with coordinates).  ``.ok``, ``.watertight``,
        ``.winding_consistent``, ``.codes``, ``.summary()``.

    Raises
    ------
    InputError
        The arrays have the wrong shape or type (non-finite values and bad indices are
        reported as defects instead).

    Notes
    -----
    Vectorised: edges are keyed by their sorted vertex pair and grouped with one sort, so a
    100k-face mesh is checked in well under a second.  Exactly equal vertices are welded
    first.  An inward-wound component nested inside another (a cavity) is not ``inverted``:
    nesting is decided with the generalized winding number of the enclosing component.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> check_mesh(v, f).ok
    True
    >>> check_mesh(v, f[:3]).codes
    ('open_edges',)
    """
    v, f = validate_inputs(vertices, faces)
    return analyse_mesh(v, f).report


# ---------------------------------------------------------------------------------- orientation
