"""The precision a body's coordinates allow (issue: a torus read from a float32 STL had its two
equal moments called distinct, 1.9e-9 apart, and the demo made an 8-hour flip video for it)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import inertia
from inertia._core.tolerances import FLOAT32_ROUNDOFF, coordinate_precision


def _torus(R=1.0, r=0.3, n_major=64, n_minor=32):
    """A closed torus of quads split into triangles, outward (symmetric about z: I_xx = I_yy)."""
    u = 2 * np.pi * np.arange(n_major) / n_major
    w = 2 * np.pi * np.arange(n_minor) / n_minor
    U, W = np.meshgrid(u, w, indexing="ij")
    v = np.stack([(R + r * np.cos(W)) * np.cos(U), (R + r * np.cos(W)) * np.sin(U), r * np.sin(W)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a, b = i * n_minor + j, ((i + 1) % n_major) * n_minor + j
    c, d = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor, i * n_minor + (j + 1) % n_minor
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return v, f


def _binary_stl(path, v, f):
    tris = np.asarray(v)[np.asarray(f)].astype("<f4")
    rec = np.zeros(len(tris), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    rec["v"] = tris
    path.write_bytes(b"torus".ljust(80, b" ") + np.uint32(len(tris)).tobytes() + rec.tobytes())


def test_double_coordinates_allow_full_precision_and_float32_ones_their_rounding():
    v, _ = _torus()
    assert coordinate_precision(v, 0.7) == 0.0
    v32 = v.astype(np.float32).astype(float)
    assert coordinate_precision(v32, 0.7) == pytest.approx(4 * FLOAT32_ROUNDOFF * np.abs(v32).max() / 0.7)
    # float32 numbers in millimetres, converted to metres, are float32 data too
    mm = (v * 1000).astype(np.float32).astype(float) / 1000
    assert coordinate_precision(mm, 0.7) == pytest.approx(4 * FLOAT32_ROUNDOFF * np.abs(mm).max() / 0.7)
    assert coordinate_precision(np.full((4, 3), 1e300), 1.0) == 0.0      # beyond float32: double data


def test_a_float32_torus_has_two_equal_moments(tmp_path, capsys):
    from scipy.spatial.transform import Rotation

    from inertia.cli.main import main

    v, f = _torus()
    # turned and moved: float32 rounding of its coordinates then breaks the symmetry (~7e-9 apart)
    v = v @ Rotation.from_rotvec([0.3, -0.5, 0.7]).as_matrix().T + [0.2, 0.1, -0.3]
    p = tmp_path / "torus.stl"
    _binary_stl(p, v, f)
    props = inertia.mesh_file_properties(p, density=1000.0)
    m = props.principal().moments
    assert 1e-10 < abs(m[1] - m[0]) / m[1] < props.precision   # apart, but only by the data's rounding
    assert props.principal().rtol >= props.precision
    assert [list(g) for g in props.principal().degenerate] == [[0, 1]]
    assert main(["props", str(p), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["degenerate_moments"] == [[0, 1]]
    # the same torus in double precision: symmetric to rounding, the same verdict
    exact = inertia.mesh_properties(v, f, density=1000.0)
    assert exact.precision == 0.0 and [list(g) for g in exact.principal().degenerate] == [[0, 1]]
