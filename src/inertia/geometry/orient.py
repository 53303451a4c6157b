"""Re-orienting faces: consistent winding per edge-connected component, then outward."""

from __future__ import annotations

import numpy as np

from .checks import MeshAnalysis, analyse_mesh
from .mesh_arrays import validate_inputs

__all__ = ["orient_analysed", "orient_faces"]


def _flip_parity_from_pairs(F: int, pairs: np.ndarray, labels: np.ndarray) -> np.ndarray:
    """Which faces to flip so every 2-face edge is traversed oppositely (BFS over face adjacency).

    A spanning forest of the face-adjacency graph is grown breadth first from the first face
    of each component (one call: a virtual root joins the components); a face is flipped when
    the parity of "same direction" edges on its tree path to the root is odd.  The path
    parities are accumulated by pointer jumping (log2(depth) vectorised passes).
    """
    from scipy.sparse import coo_matrix
    from scipy.sparse.csgraph import breadth_first_order

    flip = np.zeros(F, dtype=bool)
    if len(pairs) == 0:
        return flip
    a, b, par = pairs[:, 0], pairs[:, 1], pairs[:, 2]
    # keep one entry per face pair (two faces may share two edges in degenerate meshes; a
    # conflict there is caught by the re-check after flipping)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    _, keep = np.unique(lo * np.int64(F) + hi, return_index=True)
    a, b, par = a[keep], b[keep], par[keep]
    in_topo = np.flatnonzero(labels >= 0)
    comps, first = np.unique(labels[in_topo], return_index=True)
    roots = in_topo[first]
    root = F  # virtual root joined to the first face of every component, parity 0
    rows = np.concatenate([a, b, np.full(len(roots), root)])
    cols = np.concatenate([b, a, roots])
    data = np.concatenate([par + 1, par + 1, np.ones(len(roots), dtype=np.int64)])
    G = coo_matrix((data, (rows, cols)), shape=(F + 1, F + 1)).tocsr()
    order, pred = breadth_first_order(G, root, directed=True, return_predecessors=True)
    parent = pred.copy()
    parent[parent < 0] = np.arange(F + 1)[parent < 0]  # root and unreachable faces: own parent
    nodes = np.flatnonzero(parent != np.arange(F + 1))
    w = np.zeros(F + 1, dtype=np.int64)
    w[nodes] = np.asarray(G[parent[nodes], nodes]).ravel() - 1
    # pointer jumping: w[n] = parity of the path n -> anc[n]; the root has w = 0
    anc = parent
    while True:
        w = w ^ w[anc]
        nxt = anc[anc]
        if np.array_equal(nxt, anc):
            break
        anc = nxt
    flip[:] = w[:F].astype(bool)
    return flip


def orient_analysed(vertices: np.ndarray, faces: np.ndarray, analysis: MeshAnalysis, what: str = "mesh"):
    """Re-orient faces consistently per component, then outward; returns (faces, n_flipped, analysis).

    Closed meshes: a component is outward when its signed volume is positive, or negative
    when nested inside an odd number of others (a cavity).  Open meshes: every component
    is given a positive signed volume.
    """
    from .._core.errors import MeshError

    F = len(faces)
    out = faces.copy()
    flip = _flip_parity_from_pairs(F, analysis.pairs, analysis.labels)
    out[flip] = out[flip][:, [0, 2, 1]]
    an = analyse_mesh(vertices, out)
    bad = an.report.get("inconsistent_winding")
    if bad is not None:
        raise MeshError(f"{what} cannot be oriented consistently (a non-orientable surface, such as a Moebius "
                        f"strip, or faces that conflict across a shared edge): after re-orienting, {bad.message}.",
                        report=an.report, code="not_orientable")
    if an.closed:
        wrong = an.inverted_components
    elif an.comp_volume is not None:
        wrong = np.flatnonzero(an.comp_volume < 0)
    else:
        wrong = np.zeros(0, dtype=np.int64)
    if len(wrong):
        comp_flip = np.isin(an.labels, wrong)
        out[comp_flip] = out[comp_flip][:, [0, 2, 1]]
        flip ^= comp_flip
        an = analyse_mesh(vertices, out)
    return out, int(flip.sum()), an


def orient_faces(vertices, faces) -> tuple[np.ndarray, int]:
    """Re-orient faces consistently per edge-connected component, then outward.

    Parameters
    ----------
    vertices : (V, 3) float; faces : (F, 3) int.

    Returns
    -------
    faces : (F, 3) int64, the same triangles, some with two corners swapped.
    n_flipped : int, how many faces were flipped.

    Notes
    -----
    Breadth-first over the face adjacency (faces sharing an edge used by exactly two faces),
    flipping a face when its winding disagrees with its parent's across the shared edge; then
    each closed component is flipped if its signed volume is negative (positive when it is a
    cavity nested in another component).  Open components are made of positive signed volume.

    Raises
    ------
    MeshError
        A component is not orientable, or the mesh is empty, non-finite or has bad indices.
    """
    from .._core.errors import MeshError

    v, f = validate_inputs(vertices, faces)
    an = analyse_mesh(v, f, full=True)
    hard = [d for d in an.report.findings if d.code in ("empty", "non_finite", "out_of_range", "bad_index")]
    if hard:
        raise MeshError("cannot orient the mesh: " + "; ".join(f"{d.code}: {d.message}" for d in hard),
                        report=an.report)
    out, n, _ = orient_analysed(v, f, an)
    return out, n
