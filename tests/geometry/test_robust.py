"""Robust integrals over {w >= 1/2}: agreement with closed forms within the reported bound.

Every input is generated here (tests/geometry/_robust_cases.py): boxes (closed-form moments;
unions by inclusion-exclusion, the intersection of boxes being a box), random convex hulls
(exact integrals from inertia.geometry.integrals, intersections of two by half-spaces), holes
punched by deleting faces, inside-out inner shells, overlapping and crossing shells, all
under random rigid motions.
"""

from __future__ import annotations

import hashlib
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from inertia.errors import InputError
from inertia.geometry.integrals import solid_integrals
from inertia.geometry.robust import robust_integrals
from tests.geometry._robust_cases import (
    CASES,
    ORIGIN,
    box,
    box_moments,
    concat,
    error_ratio,
    grid_box,
    hull,
    moved,
    random_case,
    union_moments,
    within_bound,
)


def test_closed_mesh_is_exact():
    v, f = hull(400, 1, c=(0.3, -0.2, 0.1))
    exact = solid_integrals(v, f, reference=ORIGIN)[:3]
    res = robust_integrals(v, f, reference=ORIGIN)
    assert res.converged and res.bound_volume == 0.0 and res.ambiguous_volume == 0.0
    assert within_bound(res, exact)
    assert res.defects == ()


def test_single_flat_hole_is_exact():
    v, f = grid_box([0, 0, 0], [1, 2, 3], 4)
    exact = box_moments([0, 0, 0], [1, 2, 3])
    res = robust_integrals(v, np.delete(f, [5], axis=0), reference=ORIGIN)
    assert res.converged and res.bound_volume == 0.0
    assert within_bound(res, exact)
    assert res.ambiguous_volume > 0.0          # w is ambiguous near the hole
    assert any("boundary" in d for d in res.defects)


@pytest.mark.parametrize("k", [2, 3, 5])
def test_holes_punched(k):
    v, f = grid_box([0, 0, 0], [1, 2, 3], 6)
    rng = np.random.default_rng(k)
    drop = rng.choice(len(f), size=k, replace=False)
    exact = box_moments([0, 0, 0], [1, 2, 3])
    res = robust_integrals(v, np.delete(f, drop, axis=0), reference=ORIGIN, tol=1e-2)
    assert within_bound(res, exact)
    assert res.bound_volume < 0.05 * exact[0]


def test_holes_in_convex_hull():
    v, f = hull(600, 3)
    exact = solid_integrals(v, f, reference=ORIGIN)[:3]
    res = robust_integrals(v, np.delete(f, [0, 300], axis=0), reference=ORIGIN, tol=1e-2)
    assert within_bound(res, exact)


def test_overlapping_cubes_union():
    b1, b2 = ([0, 0, 0], [1, 1, 1]), ([0.5, 0.25, 0.3], [1.5, 1.25, 1.3])
    v, f = concat(box(*b1), box(*b2))
    res = robust_integrals(v, f, reference=ORIGIN)
    truth = union_moments([np.array(b1, float), np.array(b2, float)])
    assert res.converged
    assert within_bound(res, truth)
    assert abs(res.volume - truth[0]) <= 1e-3 * truth[0]
    assert any("winding number >= 2" in d for d in res.defects)


def test_identical_copies_count_once():
    v, f = box([0, 0, 0], [1, 2, 3])
    vv, ff = concat((v, f), (v, f))
    res = robust_integrals(vv, ff, reference=ORIGIN)
    assert res.bound_volume == 0.0 and within_bound(res, box_moments([0, 0, 0], [1, 2, 3]))


def test_inside_out_inner_shell_is_a_cavity():
    outer, inner = ([0, 0, 0], [2, 2, 2]), ([0.5, 0.5, 0.5], [1.5, 1.2, 1.0])
    vi, fi = box(*inner)
    v, f = concat(box(*outer), (vi, fi[:, ::-1]))
    res = robust_integrals(v, f, reference=ORIGIN)
    truth = tuple(a - b for a, b in zip(box_moments(*outer), box_moments(*inner)))
    assert res.converged and res.bound_volume == 0.0
    assert within_bound(res, truth)


def test_crossing_boxes_rotated():
    """A plus-shaped self-intersecting soup of three crossing bars, rigidly moved."""
    bars = [([-1.5, -0.3, -0.2], [1.5, 0.3, 0.2]), ([-0.25, -1.2, -0.3], [0.25, 1.2, 0.3]),
            ([-0.2, -0.2, -1.0], [0.2, 0.2, 1.0])]
    R = Rotation.from_euler("xyz", [0.3, -0.7, 1.1]).as_matrix()
    t = np.array([0.4, -0.3, 2.0])
    v, f = concat(*[box(*b) for b in bars])
    res = robust_integrals(v @ R.T + t, f, reference=ORIGIN, tol=3e-3)
    truth = moved(union_moments([np.array(b, float) for b in bars]), R, t)
    assert within_bound(res, truth)
    assert res.relative_bounds["volume"] <= 3e-3


def test_bound_budget_reported():
    """A hole that is not flat (two neighbouring faces removed) leaves a first-order cap
    region: tol = 1e-9 is out of reach, and the result says so."""
    v, f = hull(200, 4)
    a = 0
    b = next(i for i in range(1, len(f)) if len(set(f[a]) & set(f[i])) == 2)
    seen = []
    res = robust_integrals(v, np.delete(f, [a, b], axis=0), reference=ORIGIN, tol=1e-9,
                           progress=lambda fraction, bound: seen.append((fraction, bound)))
    assert not res.converged and res.stopped_by in ("octree limit", "depth limit", "piece budget")
    assert any(f"did not reach tol=1e-09 (stopped by the {res.stopped_by})" in d for d in res.defects)
    exact = solid_integrals(v, f, reference=ORIGIN)[0]
    assert abs(res.volume - exact) < 0.01 * exact
    # the bound reached is the largest relative bound, and the last progress report says it
    assert res.bound == max(res.relative_bounds.values()) > 1e-9 and seen[-1] == (1.0, res.bound)
    fractions = [x for x, _ in seen]
    assert fractions == sorted(fractions) and 0 < fractions[0] and len(seen) >= 3


def _loose_triangles(n, seed=0):
    rng = np.random.default_rng(seed)
    tri = rng.uniform(-1, 1, (n, 1, 3)) + rng.normal(scale=0.1, size=(n, 3, 3))
    return tri.reshape(-1, 3), np.arange(3 * n).reshape(-1, 3)


def test_a_soup_of_loose_triangles_is_bounded_in_work_and_honest():
    """2,000 loose triangles (as many caps) once took minutes in the cap region's octree (every
    cell against every cap); its work is now capped.  Truth: a triangle bounds no volume, and
    w reaches 1/2 only on the triangles, so the solid is empty."""
    import time

    v, f = _loose_triangles(2000)
    t0 = time.process_time()
    res = robust_integrals(v, f, tol=1e-3)
    assert time.process_time() - t0 < 60
    assert abs(res.volume) <= res.bound_volume and not res.converged and res.stopped_by == "octree limit"


def test_a_time_budget_ends_the_work_and_says_so():
    v, f = _loose_triangles(400)
    res = robust_integrals(v, f, tol=1e-3, time_budget=0.0)
    assert res.stopped_by == "time budget" and not res.converged and abs(res.volume) <= res.bound_volume
    assert any("stopped by the time budget" in d for d in res.defects)
    with pytest.raises(InputError, match="time_budget must be a number of seconds >= 0"):
        robust_integrals(v, f, time_budget=-1.0)


def test_a_converged_result_has_no_stop_and_reports_its_bound():
    _, v, f, truth = random_case(np.random.default_rng(0), "flat holes")
    seen = []
    res = robust_integrals(v, f, tol=1e-3, progress=lambda fraction, bound: seen.append((fraction, bound)))
    assert res.converged and res.stopped_by is None and 0 < res.bound <= 1e-3 and within_bound(res, truth)
    assert seen[-1] == (1.0, res.bound) and [x for x, _ in seen] == sorted(x for x, _ in seen)
