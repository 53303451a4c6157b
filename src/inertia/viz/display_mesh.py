"""The body as the pictures draw it: its mesh in the principal frame, decimated when large.

Pictures need the shape, not the exact surface, so a mesh over :data:`MAX_DISPLAY_FACES`
faces is reduced by vertex clustering (vertices in one grid cell merged at their mean,
collapsed and repeated faces dropped) until it fits; the mass properties are always those
of the full body.  Each face also carries the index of its connected part (shells sharing
no vertex), so a body assembled from several solids can be drawn in several colours.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: the most faces the video, the 3D page and the plots draw; larger meshes are decimated
MAX_DISPLAY_FACES = 20_000


@dataclass(frozen=True)
class DisplayMesh:
    """``vertices`` (V, 3) m in the principal frame (COM at the origin), ``faces`` (F, 3),
    ``part`` (F,) connected-part index of each face, ``source_faces`` the face count of the
    mesh it was made from, ``decimated`` whether it has fewer faces than that."""

    vertices: np.ndarray
    faces: np.ndarray
    part: np.ndarray
    source_faces: int

    @property
    def decimated(self) -> bool:
        return len(self.faces) < self.source_faces

    @property
    def radius(self) -> float:
        """Largest distance of a vertex from the center of mass [m]."""
        return float(np.sqrt((self.vertices ** 2).sum(axis=1).max()))

    def note(self) -> str:
        """One sentence for a page saying what is drawn ('' when the mesh is drawn whole)."""
        if not self.decimated:
            return ""
        return (f"The mesh has {self.source_faces:,} faces; it is drawn decimated to {len(self.faces):,} "
                "(vertex clustering) for display. Every number comes from the full mesh.")


def cluster_decimate(vertices, faces, max_faces: int) -> tuple[np.ndarray, np.ndarray]:
    """Vertex-clustering decimation to at most ``max_faces`` faces (winding kept)."""
    V = np.asarray(vertices, float)
    F = np.asarray(faces, np.int64)
    if len(F) <= max_faces:
        return V, F
    lo = V.min(axis=0)
    extent = float((V.max(axis=0) - lo).max()) or 1.0
    cells = max(2.0, np.sqrt(max_faces / 2.0))    # a closed surface cut by n^3 cells keeps ~ c n^2 faces
    while True:          # ends: cells shrink by >= 3 % a round, and one cell leaves no face at all
        key = np.floor((V - lo) / (extent / cells)).astype(np.int64)
        _, cluster = np.unique(key, axis=0, return_inverse=True)
        cluster = cluster.ravel()
        n = int(cluster.max()) + 1
        count = np.bincount(cluster, minlength=n).astype(float)
        W = np.stack([np.bincount(cluster, weights=V[:, k], minlength=n) for k in range(3)], axis=1) / count[:, None]
        G = cluster[F]
        keep = (G[:, 0] != G[:, 1]) & (G[:, 1] != G[:, 2]) & (G[:, 0] != G[:, 2])
        G = G[keep]
        _, first = np.unique(np.sort(G, axis=1), axis=0, return_index=True)
        G = G[np.sort(first)]
        if len(G) <= max_faces:
            used, G = np.unique(G, return_inverse=True)
            return W[used], G.reshape(-1, 3)
        cells *= 0.97 * np.sqrt(max_faces / len(G))


def split_long_edges(vertices, faces, max_edge: float, *, max_faces: int = 60_000):
    """Bisect every edge longer than ``max_edge`` until none is (or ``max_faces`` is reached).

    Both faces of an edge get the same midpoint, so the mesh stays conforming; a face with one
    long edge becomes two triangles, with two long edges three, with three four, winding kept.
    The painter's algorithm of the video needs it: a long sliver's mean depth says little
    about which parts of it are in front.
    """
    V = np.asarray(vertices, float)
    F = np.asarray(faces, np.int64)
    ring = np.array([[0, 1], [1, 2], [2, 0]])
    while len(F) < max_faces:
        key = np.sort(F[:, ring], axis=2).reshape(-1, 2)
        edges, inv = np.unique(key, axis=0, return_inverse=True)
        long = np.linalg.norm(V[edges[:, 0]] - V[edges[:, 1]], axis=1) > max_edge
        if not long.any():
            break
        mid = np.full(len(edges), -1, np.int64)
        mid[long] = len(V) + np.arange(int(long.sum()))
        V = np.vstack([V, 0.5 * (V[edges[long, 0]] + V[edges[long, 1]])])
        M = mid[inv.ravel()].reshape(-1, 3)        # midpoint of edge i (vertex i -> i+1), or -1
        F = np.vstack([F[(M >= 0).sum(axis=1) == 0]] + [_split(V, F, M, n) for n in (1, 2, 3)])
    return V, F


def _split(V, F, M, n: int) -> np.ndarray:
    """The faces of ``F`` with ``n`` split edges, cut into ``n + 1`` triangles each (with two,
    the quadrilateral left beside the corner triangle is cut along its shorter diagonal)."""
    rows = np.flatnonzero((M >= 0).sum(axis=1) == n)
    if n == 3:
        f, m = F[rows], M[rows]
        return np.vstack([np.stack(t, axis=1) for t in ((f[:, 0], m[:, 0], m[:, 2]), (m[:, 0], f[:, 1], m[:, 1]),
                                                        (m[:, 2], m[:, 1], f[:, 2]), (m[:, 0], m[:, 1], m[:, 2]))])
    # roll each face so that its split edges come first: (a, b) long, then (b, c) if n == 2
    start = np.argmax(M[rows] >= 0, axis=1) if n == 1 else (np.argmin(M[rows] >= 0, axis=1) + 1) % 3
    idx = (start[:, None] + np.arange(3)) % 3
    a, b, c = (F[rows[:, None], idx]).T
    m_ab, m_bc = (M[rows[:, None], idx])[:, :2].T
    if n == 1:
        tris = ((a, m_ab, c), (m_ab, b, c))
        return np.vstack([np.stack(t, axis=1) for t in tris])
    short = np.linalg.norm(V[a] - V[m_bc], axis=1) <= np.linalg.norm(V[m_ab] - V[c], axis=1)
    one = np.where(short, a, m_ab)      # the diagonal: a - m_bc, or m_ab - c
    tris = ((m_ab, b, m_bc), (a, m_ab, np.where(short, m_bc, c)), (one, m_bc, c))
    return np.vstack([np.stack(t, axis=1) for t in tris])


def face_parts(n_vertices: int, faces) -> np.ndarray:
    """Connected-part index (0, 1, ...) of each face, parts numbered by their first face."""
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import connected_components

    F = np.asarray(faces, np.int64)
    rows = np.concatenate([F[:, 0], F[:, 1]])
    cols = np.concatenate([F[:, 1], F[:, 2]])
    graph = coo_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_vertices, n_vertices))
    _, label = connected_components(graph, directed=False)
    face_label = label[F[:, 0]]
    _, first = np.unique(face_label, return_index=True)
    rank = np.empty(label.max() + 1, np.int64)
    rank[face_label[np.sort(first)]] = np.arange(len(first))
    return rank[face_label]


def display_mesh(props, mesh, *, max_faces: int = MAX_DISPLAY_FACES) -> DisplayMesh | None:
    """The mesh ``(vertices (V, 3) m body frame, faces)`` moved into the principal frame of
    ``props`` (COM at the origin) and decimated to ``max_faces``; None without a mesh."""
    if mesh is None:
        return None
    V, F = np.asarray(mesh[0], float), np.asarray(mesh[1], np.int64)
    V_principal = (V - props.com) @ props.principal().R_body_principal
    Vd, Fd = cluster_decimate(V_principal, F, max_faces)
    return DisplayMesh(Vd, Fd, face_parts(len(Vd), Fd), len(F))
