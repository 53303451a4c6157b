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
    assert res.findings == () and res.codes == ()


def test_single_flat_hole_is_exact():
    v, f = grid_box([0, 0, 0], [1, 2, 3], 4)
    exact = box_moments([0, 0, 0], [1, 2, 3])
    res = robust_integrals(v, np.delete(f, [5], axis=0), reference=ORIGIN)
    assert res.converged and res.bound_volume == 0.0
    assert within_bound(res, exact)
    assert res.ambiguous_volume > 0.0          # w is ambiguous near the hole
    assert res.codes == ("open_edges",) and "closed by caps" in res.findings[0].message


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
    assert "overlapping_shells" in res.codes
    assert "winding number >= 2" in next(d for d in res.findings if d.code == "overlapping_shells").message


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
    assert res.bounds["volume"] <= 3e-3 and res.error_bound == max(res.bounds.values()) <= 3e-3


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
    assert res.codes[-1] == "bound_not_reached"
    assert f"did not reach tol=1e-09 (stopped by the {res.stopped_by})" in res.findings[-1].message
    exact = solid_integrals(v, f, reference=ORIGIN)[0]
    assert abs(res.volume - exact) < 0.01 * exact
    # the bound reached is the largest relative bound, and the last progress report says it
    assert res.bound == max(res.bounds.values()) > 1e-9 and seen[-1] == (1.0, res.bound)
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
    assert any("stopped by the time budget" in d.message for d in res.findings)
    with pytest.raises(InputError, match="time_budget must be a number of seconds >= 0"):
        robust_integrals(v, f, time_budget=-1.0)


def test_a_converged_result_has_no_stop_and_reports_its_bound():
    _, v, f, truth = random_case(np.random.default_rng(0), "flat holes")
    seen = []
    res = robust_integrals(v, f, reference=ORIGIN, tol=1e-3,
                           progress=lambda fraction, bound: seen.append((fraction, bound)))
    assert res.converged and res.stopped_by is None and 0 < res.bound <= 1e-3 and within_bound(res, truth)
    assert seen[-1] == (1.0, res.bound) and [x for x, _ in seen] == sorted(x for x, _ in seen)


def test_derived_bounds_cover_com_and_inertia():
    b1, b2 = ([0, 0, 0], [1, 1, 1]), ([0.6, 0.2, 0.1], [1.4, 0.9, 1.8])
    v, f = concat(box(*b1), box(*b2))
    res = robust_integrals(v, f, tol=1e-2)
    V, F, S = union_moments([np.array(b1, float), np.array(b2, float)])
    com = F / V
    assert np.linalg.norm(res.com - com) <= res.bound_com + 1e-12
    C = S - V * np.outer(com, com)
    assert np.linalg.norm(res.central_second() - C) <= res.bound_central_second + 1e-12


def test_bad_inputs():
    v, f = box([0, 0, 0], [1, 1, 1])
    with pytest.raises(InputError):
        robust_integrals(v, f + 100)
    with pytest.raises(InputError):
        robust_integrals(v, np.zeros((0, 3), int))
    with pytest.raises(InputError):
        robust_integrals(v, f, tol=0.0)


@pytest.mark.parametrize("kind", list(CASES))
def test_bound_is_honest_on_generated_cases(kind):
    """The true error stays within the bound on generated cases of each kind (the full table,
    hundreds of cases, is bench/robust.py --table)."""
    rng = np.random.default_rng(20261125 + list(CASES).index(kind))
    worst = 0.0
    for n in range(25):
        name, v, f, truth = random_case(rng, kind)
        res = robust_integrals(v, f, reference=ORIGIN, tol=1e-3)
        ratio = error_ratio(res, truth)
        assert ratio <= 1.0, (kind, n, res.volume, truth[0], res.bound_volume, res.findings)
        worst = max(worst, ratio)
    print(f"{kind}: 25 cases, worst error / bound = {worst:.3g}")


def _digest(res):
    """SHA-256 of every number of a result (values, bounds, ambiguity, the counts in stats)."""
    h = hashlib.sha256()
    for x in (res.volume, res.first, res.second, res.reference, res.bound_volume, res.bound_first, res.bound_second,
              res.ambiguous_volume):
        h.update(np.ascontiguousarray(x, dtype=np.float64).tobytes())
    h.update(repr((res.converged, [(d.code, d.message) for d in res.findings],
                   sorted((k, x) for k, x in res.stats.items() if not k.startswith("seconds")))).encode())
    return h.hexdigest()


def _crossing_shells_with_holes():
    """Two overlapping convex shells of 2,000 faces each with holes punched, and a slab pierced by
    36 pins (more trace lines than one piece takes: split): caps, cut faces, pieces refined,
    enough work for every kernel to share it among threads."""
    (va, fa), (vb, fb) = hull(1000, 11), hull(1000, 12, c=(0.6, 0.1, -0.2))
    pins = [box([3.1 + 0.3 * i, 0.1 + 0.3 * j, 0.5], [3.2 + 0.3 * i, 0.2 + 0.3 * j, 1.5]) for i in range(6) for j in range(6)]
    return concat((va, np.delete(fa, [0, 500], axis=0)), (vb, np.delete(fb, [7], axis=0)), box([3, 0, 0], [5, 2, 1]),
                  *pins)


DETERMINISM_CALL = "robust_integrals(v, f, reference=ORIGIN, tol=1e-4, max_pieces=200_000, threads={threads})"


@pytest.mark.parametrize("threads", [2, 3])
def test_same_bits_twice_and_on_any_number_of_threads(threads):
    v, f = _crossing_shells_with_holes()
    one = robust_integrals(v, f, reference=ORIGIN, tol=1e-4, max_pieces=200_000, threads=1)
    assert one.stats["pieces"] > 256 and one.stats["depth"] >= 1 and one.stats["caps"] == 3
    again = robust_integrals(v, f, reference=ORIGIN, tol=1e-4, max_pieces=200_000, threads=1)
    many = robust_integrals(v, f, reference=ORIGIN, tol=1e-4, max_pieces=200_000, threads=threads)
    assert _digest(one) == _digest(again) == _digest(many)


def test_same_bits_in_a_fresh_process():
    v, f = _crossing_shells_with_holes()
    here = _digest(robust_integrals(v, f, reference=ORIGIN, tol=1e-4, max_pieces=200_000))
    code = ("from tests.geometry.test_robust import _crossing_shells_with_holes, _digest, ORIGIN, robust_integrals\n"
            "v, f = _crossing_shells_with_holes()\n"
            f"print(_digest({DETERMINISM_CALL.format(threads=None)}))")
    root = Path(__file__).resolve().parents[2]
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=root, check=True)
    assert out.stdout.strip() == here


def test_threads_must_be_positive():
    v, f = box([0, 0, 0], [1, 1, 1])
    with pytest.raises(InputError, match="threads must be None or a positive integer, got 0"):
        robust_integrals(v, f, threads=0)


def test_kernels_check_every_index_from_outside():
    """The compiled kernels refuse indices and lengths that do not fit, naming the array."""
    from inertia._ext import robust as k

    v, f = box([0, 0, 0], [1, 1, 1])
    m = np.ones(len(f))
    cert, nbr = np.zeros(len(v), bool), np.full((len(f), 3), -1)
    with pytest.raises(InputError, match=r"faces\[2, 1\] = 8 names no vertex"):
        k.dedupe_faces(np.where(np.arange(36).reshape(12, 3) == 7, 8, f), len(v))
    with pytest.raises(InputError, match=r"verts\[1\] = 9 is outside \[0, 8\)"):
        k.vertex_pass(v, f, m, np.array([0, 9]), cert, nbr, 1)
    with pytest.raises(InputError, match="multiplicities has length 3, expected 12"):
        k.vertex_pass(v, f, m[:3], np.arange(8), cert, nbr, 1)
    with pytest.raises(InputError, match=r"nbr\[5\] = 12 is outside \[-1, 12\)"):
        k.patch_reps(v, f, np.where(np.arange(36).reshape(12, 3) == 5, 12, nbr), np.zeros(len(f), bool))
    ptr, idx = np.zeros(13, np.int64), np.zeros(0, np.int64)
    with pytest.raises(InputError, match="cut_ptr must run from 0 to 0"):
        k.classify_traces(v, f, m, ptr + 1, idx, 1e-9, 1)
    with pytest.raises(InputError, match=r"owner\[0\] = 12 is outside \[0, 12\)"):
        k.winding_excluding(v[:1], np.array([12]), v, f, m, ptr, idx, idx, 1)
