"""The body as the pictures draw it: decimation keeps the shape and the winding, edge
splitting keeps the surface exactly, parts are found."""

from __future__ import annotations

import numpy as np
import pytest

from inertia.viz.display_mesh import MAX_DISPLAY_FACES, cluster_decimate, display_mesh, face_parts, split_long_edges
from tests.viz._helpers import t_handle


def _icosphere(levels: int, radius: float = 1.0):
    """A closed, outward-wound sphere mesh with 20 * 4**levels faces (1 -> 4 splits)."""
    t = (1 + 5 ** 0.5) / 2
    V = np.array([[-1, t, 0], [1, t, 0], [-1, -t, 0], [1, -t, 0], [0, -1, t], [0, 1, t], [0, -1, -t], [0, 1, -t],
                  [t, 0, -1], [t, 0, 1], [-t, 0, -1], [-t, 0, 1]], float)
    F = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11], [1, 5, 9], [5, 11, 4], [11, 10, 2],
                  [10, 7, 6], [7, 1, 8], [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9], [4, 9, 5],
                  [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])
    for _ in range(levels):
        V, F = split_long_edges(V, F, 0.0, max_faces=len(F) * 4)   # every edge is "long": a full 1 -> 4 split
    return radius * V / np.linalg.norm(V, axis=1, keepdims=True), F


def _volume(V, F):
    return np.einsum("ij,ij->i", V[F[:, 0]], np.cross(V[F[:, 1]], V[F[:, 2]])).sum() / 6


def _closed_and_consistent(F):
    directed = set(map(tuple, F[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2).tolist()))
    return len(directed) == 3 * len(F) and all((b, a) in directed for a, b in directed)


def test_decimation_keeps_the_shape_under_the_limit():
    V, F = _icosphere(5)                       # 20,480 faces
    assert len(F) > MAX_DISPLAY_FACES
    Vd, Fd = cluster_decimate(V, F, 2000)
    assert 500 < len(Fd) <= 2000
    r = np.linalg.norm(Vd, axis=1)
    assert r.max() <= 1 + 1e-12 and r.min() > 0.97          # still on the unit sphere (cluster means sag slightly)
    assert _volume(Vd, Fd) == pytest.approx(4 / 3 * np.pi, rel=0.03)   # winding kept: positive volume


def test_display_mesh_is_in_the_principal_frame_and_says_when_decimated():
    body = t_handle()
    props = body.props
    V, F = body.display_mesh()
    d = display_mesh(props, (V, F))
    R = props.principal().R_body_principal
    np.testing.assert_allclose(d.vertices, (V - props.com) @ R, atol=1e-15)
    assert not d.decimated and d.note() == "" and sorted(set(d.part.tolist())) == [0, 1]   # bar and stem
    small = display_mesh(props, (V, F), max_faces=200)
    assert small.decimated and len(small.faces) <= 200 and "384 faces" in small.note()


def test_split_long_edges_keeps_the_surface():
    V, F = t_handle().display_mesh()
    limit = 0.3 * np.linalg.norm(V, axis=1).max()
    V2, F2 = split_long_edges(V, F, limit)
    edges = V2[F2[:, [[0, 1], [1, 2], [2, 0]]]]
    assert np.linalg.norm(edges[:, :, 0] - edges[:, :, 1], axis=2).max() <= limit
    assert _closed_and_consistent(F2)                       # conforming: no crack, winding kept
    assert _volume(V2, F2) == pytest.approx(_volume(V, F), rel=1e-13)
    assert np.array_equal(np.bincount(face_parts(len(V2), F2)) > 0, [True, True])
