"""Does a closed, consistently wound shell pass through itself?

A closed surface that crosses itself bounds a region twice (or with the wrong sign): the
divergence-theorem integrals then count it twice, silently (a box whose top is pushed
through its bottom has signed volume 500 where the solid's is 1000 - 2 x 250).
:mod:`inertia.geometry.checks` reports it as the defect ``self_intersecting``.

Two steps, cheapest first:

1. **A certificate** (:func:`star_certificate`), O(F): every face sees the body's center of
   mass strictly on its inner side, and a ray from the center crosses the surface once.  The
   radial projection from the center is then one-to-one, so no two faces can cross (a
   transversal crossing would put two faces on the rays near it).  Spheres, boxes,
   cylinders, ellipsoids and most compact parts pass here, at a few percent of the integrals'
   cost.
2. **The search** (:func:`first_crossing`) for the rest (a torus, a T-handle, an L-bracket).
   It first proves what it can cell by cell: in a grid of cells about four edges long, the
   faces whose boxes meet a cell are shown to project one-to-one along an axis (every face
   turned that way and the border one simple loop: the faces then cover each point at most
   once), so none of them can cross another there; cells it cannot prove are cut in 8 (twice).
   The faces of the parts still not proved are searched pair by pair: every pair whose boxes
   share a cell of a uniform grid (cells about one edge long) is tested once with the
   edge-through-triangle test of :func:`inertia.geometry.intersections.crossing`; pairs that
   share an edge cannot cross and are skipped, and so are pairs around a vertex whose fan of
   faces is proved flat.  Touching faces (a shared vertex, coplanar contact) are not crossings.

A crossing is then weighed (:func:`crossing_effect`): real exports carry tiny local ones
(wingnut.obj: one face poking 1e-3 of its size through three others, changing the volume by
3e-6) that no mass-properties user should be refused for.  The exact integrals are compared
with those of the solid the surface bounds once (the robust path, winding number >= 1/2, with
its error bound): below :data:`NEGLIGIBLE_RTOL` in volume, COM and inertia the crossing is a
note (``self_crossing_negligible``, with the figures), otherwise the defect
``self_intersecting``.

The certificate, the cell proof and the search are compiled (``inertia._ext.selfcross``).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._ext import selfcross as _k

#: the center must be farther than this times |a| from every face's plane (a the face's first
#: corner seen from the center): a face nearly edge-on to the center does not certify
STAR_RTOL = _k.STAR_RTOL
#: a shell the certificate cannot prove is searched up to this many faces (the search costs
#: several times the mass properties); larger ones get the note ``self_crossing_unchecked``
SEARCH_MAX_FACES = 200_000
#: crossings that change the volume, the COM and the inertia by less than this (relative; see
#: :func:`crossing_effect`) are a note (``self_crossing_negligible``), not an error
NEGLIGIBLE_RTOL = 1e-4
#: the robust solid's error bound asked for when weighing a crossing
EFFECT_TOL = 1e-5
#: ``face_twins`` not known: the search finds them
_NO_TWINS = np.empty((0, 3), dtype=np.int64)


def star_certificate(vertices, faces, center) -> bool:
    """True when the closed, consistently outward shell ``faces`` is star-shaped from
    ``center`` with a one-to-one radial projection: it then cannot cross itself."""
    return _k.star_certificate(np.ascontiguousarray(vertices, dtype=np.float64),
                               np.ascontiguousarray(faces, dtype=np.int64), np.asarray(center, dtype=np.float64))


@dataclass(frozen=True)
class Crossing:
    """Two faces of the shell that cross (``faces``), near ``point``."""

    faces: tuple
    point: np.ndarray


def first_crossing(vertices, faces, *, face_twins=None) -> Crossing | None:
    """The first pair of faces found crossing, or None.  ``face_twins`` (F, 3) int64, if
    known: the face across each edge, ``face_twins[t, k]`` across the edge from corner k
    to corner k + 1 (as the compiled clean-solid check finds them); else (None, or no rows)
    found here."""
    v = np.ascontiguousarray(vertices, dtype=np.float64)
    f = np.ascontiguousarray(faces, dtype=np.int64)
    if len(f) < 2:
        return None
    twins = _NO_TWINS if face_twins is None else np.ascontiguousarray(face_twins, dtype=np.int64)
    pair = _k.find_crossing(v, f, twins)
    if pair is None:
        return None
    return Crossing(pair, v[f[pair[0]]].mean(axis=0))


def crossing_effect(vertices, faces, exact) -> dict:
    """How much the crossings of a closed shell can change its mass properties: the
    integrals of the exact kernel (``exact`` = volume, first, second, reference) against
    those of the solid the surface bounds once (:func:`inertia.geometry.robust.robust_integrals`,
    the points of winding number >= 1/2), plus that solid's error bound.  Relative to natural
    scales: ``volume`` / V, ``com`` / radius of gyration, ``inertia`` (Frobenius) / |I|."""
    from .robust import derived_bounds, robust_integrals

    res = robust_integrals(vertices, faces, tol=EFFECT_TOL)
    vol, first, second, ref = exact
    d = ref - res.reference                      # exact integrals moved to the robust reference
    first_r = first + vol * d
    second_r = second + np.multiply.outer(first, d) + np.multiply.outer(d, first) + vol * np.multiply.outer(d, d)
    mine = derived_bounds(vol, first_r, second_r, 0.0, np.zeros(3), np.zeros((3, 3)))
    theirs = res.derived
    V = abs(res.volume)
    if not V > 0:   # the solid bounded once has no volume (e.g. swamped by a far vertex): no scale
        return {"volume": np.inf, "com": np.inf, "inertia": np.inf}
    C_e, C_r = mine["central_second"], theirs["central_second"]
    I_e, I_r = np.trace(C_e) * np.eye(3) - C_e, np.trace(C_r) * np.eye(3) - C_r
    k = np.sqrt(max(float(np.trace(C_r)), 0.0) / V)
    rel = res.bounds
    with np.errstate(all="ignore"):
        return {"volume": abs(vol - res.volume) / V + rel["volume"],
                "com": float(np.linalg.norm(first_r / vol - res.first / res.volume)) / k + rel["com"],
                "inertia": float(np.linalg.norm(I_e - I_r) / np.linalg.norm(I_r)) + rel["inertia"]}


def self_crossing(vertices, faces, center, *, max_faces: int | None = SEARCH_MAX_FACES, face_twins=None):
    """Whether the closed, consistently outward shell ``faces`` crosses itself: ``None`` (it
    does not: certified or searched), a :class:`Crossing`, or the string ``"unchecked"`` (not
    star-shaped from ``center`` and over ``max_faces`` faces; None: no limit).  ``center`` is
    a point well inside, the COM, for the certificate; ``face_twins``: see
    :func:`first_crossing`."""
    if star_certificate(vertices, faces, center):
        return None
    if max_faces is not None and len(faces) > max_faces:
        return "unchecked"
    return first_crossing(vertices, faces, face_twins=face_twins)
