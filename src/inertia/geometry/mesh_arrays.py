"""Mesh arrays: input validation, exact welding of equal vertices, compaction.

Every function here returns arrays that the compiled kernels may read: validated in their
final shape (``(V, 3)`` finite-or-not float64, ``(F, 3)`` int64 indices in range are checked
by the analysis, not here).  The numba kernels of :mod:`._topology_numba` are twins of the
NumPy code (tests/geometry/test_mesh_fast_paths.py compares them).
"""

from __future__ import annotations

import numpy as np

from .._core import compiled as _compiled
from .._core.errors import InputError

__all__ = ["validate_inputs", "topology_kernels", "weld_map", "weld_map_numpy", "weld_vertices", "compact_vertices"]


def validate_inputs(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Coerce ``vertices`` to float64 (V, 3) and ``faces`` to int64 (F, 3), or raise InputError.

    Non-finite coordinates and out-of-range indices are *not* refused here: they are mesh
    defects (``non_finite``, ``bad_index``) reported by :func:`check_mesh`.  Float face arrays
    are accepted when every value is integral.  Empty inputs become (0, 3) arrays.
    """
    if (type(vertices) is np.ndarray and type(faces) is np.ndarray and vertices.dtype == np.float64
            and faces.dtype == np.int64 and vertices.ndim == 2 and faces.ndim == 2 and vertices.shape[1] == 3
            and faces.shape[1] == 3 and vertices.size and faces.size):
        return vertices, faces           # the common case, already in final form
    try:
        v = np.asarray(vertices, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise InputError(f"vertices must be a numeric (V, 3) array, got {type(vertices).__name__}: {exc}") from None
    if v.size == 0:
        v = v.reshape(0, 3)
    if v.ndim != 2 or v.shape[1] != 3:
        raise InputError(f"vertices must have shape (V, 3), got {v.shape}")

    f = np.asarray(faces)
    if f.size == 0:
        f = np.zeros((0, 3), dtype=np.int64)
    if f.dtype == bool or not (np.issubdtype(f.dtype, np.integer) or np.issubdtype(f.dtype, np.floating)):
        raise InputError(f"faces must be an integer (F, 3) array of vertex indices, got dtype {f.dtype}")
    if f.ndim != 2 or f.shape[1] != 3:
        hint = " (triangulate polygons first)" if f.ndim == 2 and f.shape[1] > 3 else ""
        raise InputError(f"faces must have shape (F, 3){hint}, got {f.shape}")
    if np.issubdtype(f.dtype, np.floating):
        bad = ~np.isfinite(f) | (f != np.round(f)) | (np.abs(f) > 2.0**62)
        if bad.any():
            k = tuple(int(i) for i in np.argwhere(bad)[0])
            raise InputError(f"faces must hold integer vertex indices; faces[{k[0]}, {k[1]}] = {float(f[k])!r} "
                             f"({int(bad.sum())} non-integral values)")
    elif f.dtype == np.uint64 and f.size and f.max() > np.iinfo(np.int64).max:
        raise InputError(f"faces hold an index too large for int64: {int(f.max())}")
    return v, f.astype(np.int64, copy=False)


def faces_in_range(faces: np.ndarray, n_vertices: int) -> bool:
    """True when every index of ``faces`` (validated, (F, 3) int64) is in 0..n_vertices-1.

    The compiled kernels index without bounds checks: every call that hands them faces asks
    this first, on the arrays in their final shape.
    """
    return len(faces) == 0 or (int(faces.min()) >= 0 and int(faces.max()) < n_vertices)


# ---------------------------------------------------------------------------------- compiled path
# False: run as if numba were not installed (tests set it); None: ask the rule of
# :mod:`inertia._core.compiled` on each call
_topology_state = None


def compiled_kernels(module_name: str, work: int = 0, ahead_of_time: bool = True):
    """The compiled kernel module ``module_name`` of this layer, or None for the NumPy path:
    None when ``_topology_state`` is False (tests run "as if numba were not installed"),
    else as :func:`inertia._core.compiled.kernels` decides (numba missing, a small job in a
    process without numba, a cold cache)."""
    if _topology_state is False:
        return None
    return _compiled.kernels(module_name, work=work, ahead_of_time=ahead_of_time)


def topology_kernels(work: int = 0):
    """The numba welding/topology kernels (:mod:`._topology_numba`), or None for the NumPy path
    (:func:`compiled_kernels`; ``work`` is the job's size in faces).  They give the same answers
    as the NumPy code here, in O(n) hash passes instead of sorts; tests compare the two.
    """
    return compiled_kernels("inertia.geometry._topology_numba", work)


# ---------------------------------------------------------------------------------- welding
def weld_map(vertices: np.ndarray) -> np.ndarray:
    """``rep[i]``: the lowest index of a vertex with exactly the coordinates of vertex i.

    Non-finite vertices map to themselves; ``+ 0.0`` folds -0.0 onto 0.0.  Compiled: one
    hash-table pass.  NumPy: the rows are grouped by a 64-bit hash of their bits (one sort);
    equal hashes are confirmed by comparing the rows, and a collision falls back to a
    lexicographic sort.
    """
    kernels = topology_kernels(len(vertices))
    if kernels is not None:
        return kernels.weld_map(np.ascontiguousarray(vertices, dtype=np.float64))
    return weld_map_numpy(vertices)


def weld_map_numpy(vertices: np.ndarray) -> np.ndarray:
    """NumPy version of :func:`weld_map`."""
    n = len(vertices)
    rep = np.arange(n, dtype=np.int64)
    fin = np.flatnonzero(np.isfinite(vertices).all(axis=1))
    if len(fin) < 2:
        return rep
    v = np.ascontiguousarray(vertices[fin] + 0.0)
    bits = v.view(np.uint64).reshape(-1, 3)
    h = (bits[:, 0] * np.uint64(0x9E3779B97F4A7C15)) ^ (bits[:, 1] * np.uint64(0xC2B2AE3D27D4EB4F)) \
        ^ (bits[:, 2] * np.uint64(0x165667B19E3779F9))
    h ^= h >> np.uint64(29)
    order = np.argsort(h, kind="stable")               # stable: equal rows stay in index order
    s = v[order]
    same_row = np.all(s[1:] == s[:-1], axis=1)
    hs = h[order]
    if np.any((hs[1:] == hs[:-1]) & ~same_row):        # hash collision: sort the rows themselves
        order = np.lexsort((v[:, 2], v[:, 1], v[:, 0]))  # lexsort is stable too
        s = v[order]
        same_row = np.all(s[1:] == s[:-1], axis=1)
    new_run = np.r_[True, ~same_row]
    run_id = np.cumsum(new_run) - 1
    first = fin[order[new_run]]
    rep[fin[order]] = first[run_id]
    return rep


def weld_vertices(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices of exactly equal coordinates and drop unreferenced vertices.

    Returns ``(vertices (V', 3) float64, faces (F, 3) int64)``, vertices in order of first
    use by the original indices.  An index outside ``vertices`` is an InputError.
    """
    v, f = validate_inputs(vertices, faces)
    if len(f) == 0:
        return v[:0], f
    if not faces_in_range(f, len(v)):
        raise InputError(f"faces index vertices outside 0..{len(v) - 1} "
                         f"(min {int(f.min())}, max {int(f.max())})", code="bad_index")
    kernels = topology_kernels(len(f))
    if kernels is not None:
        return kernels.weld_compact(np.ascontiguousarray(v), np.ascontiguousarray(f))
    rep = weld_map(v)
    fw = rep[f]
    return compact_vertices(v, fw)


def compact_vertices(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop unreferenced vertices and renumber the faces, keeping the vertices' order.

    The same result as ``np.unique(faces, return_inverse=True)`` in O(V + F), without a sort.
    """
    used = np.zeros(len(vertices), dtype=bool)
    used[faces.ravel()] = True
    new_index = np.cumsum(used, dtype=np.int64) - 1
    return vertices[used], new_index[faces]


# ---------------------------------------------------------------------------------- graphs
def connected_components(n: int, a, b) -> tuple[int, np.ndarray]:
    """``(count, labels (n,))`` of the undirected graph on nodes ``0..n-1`` with edges
    ``a[i] - b[i]``; components are numbered in order of their lowest node, as
    ``scipy.sparse.csgraph.connected_components`` numbers them (tests compare the two).

    Pure NumPy (a one-shot command on a small mesh need not import scipy.sparse, 0.15 s):
    each round hooks the higher root of every edge still joining two trees onto the lower one,
    then jumps pointers until every node points at its root; the roots are the lowest nodes.
    """
    parent = np.arange(n, dtype=np.int64)
    a = np.asarray(a, dtype=np.int64).ravel()
    b = np.asarray(b, dtype=np.int64).ravel()
    while len(a):
        ra, rb = parent[a], parent[b]
        apart = ra != rb
        if not apart.any():
            break
        a, b, ra, rb = a[apart], b[apart], ra[apart], rb[apart]
        np.minimum.at(parent, np.maximum(ra, rb), np.minimum(ra, rb))
        while True:
            jumped = parent[parent]
            if np.array_equal(jumped, parent):
                break
            parent = jumped
    roots, labels = np.unique(parent, return_inverse=True)
    return len(roots), labels.reshape(-1)


def pairs_within_groups(items: np.ndarray, starts: np.ndarray, counts: np.ndarray) -> tuple[list, list]:
    """Every pair ``(items[s + i], items[s + j])``, ``i < j``, inside each run ``s, counts``
    of ``items`` (grouped by a sort): two lists of arrays (one pair of arrays per run length)."""
    first, second = [], []
    for c in np.unique(counts[counts > 1]):
        s = starts[counts == c]
        ii, jj = np.triu_indices(c, 1)
        first.append(items[s[:, None] + ii].ravel())
        second.append(items[s[:, None] + jj].ravel())
    return first, second


#: the 13 neighbour offsets of a grid cell with (dz, dy, dx) > 0 lexicographically (with the
#: cell itself, every unordered pair of neighbouring cells once)
_HALF_OFFSETS = np.array([(dx, dy, dz) for dz in (-1, 0, 1) for dy in (-1, 0, 1) for dx in (-1, 0, 1)
                          if (dz, dy, dx) > (0, 0, 0)], dtype=np.int64)


def near_pairs(vertices: np.ndarray, tol: float) -> np.ndarray | None:
    """Pairs ``(i < j)`` of vertices at most ``tol`` apart, (P, 2) int64: the pairs of
    ``scipy.spatial.cKDTree.query_pairs`` (tests compare them), by a grid of cells at least
    ``tol`` wide in pure NumPy (no scipy import for a small mesh).  None when the coordinates are too
    far from the origin in units of ``tol`` to number the cells (the caller uses the tree)."""
    v = np.asarray(vertices, dtype=np.float64)
    n = len(v)
    if n < 2 or not tol > 0:
        return np.zeros((0, 2), dtype=np.int64)
    lo = v.min(axis=0)
    with np.errstate(over="ignore", invalid="ignore"):
        q = (v - lo) / tol                       # coordinates in units of tol
        extent = float(q.max()) if np.all(np.isfinite(q)) else np.inf
    if not extent < 1e15:
        return None                      # too far out in units of tol to number: the tree
    # cells at least tol wide, and at most 2^20 a side (a tolerance far below the spacing of
    # the points leaves them one to a cell either way)
    width = max(1.0, extent / (2.0**20 - 4))
    cell = np.floor(q / width).astype(np.int64)
    key = (cell[:, 2] << 42) | (cell[:, 1] << 21) | cell[:, 0]
    order = np.argsort(key, kind="stable")
    skey = key[order]
    starts = np.flatnonzero(np.r_[True, skey[1:] != skey[:-1]])
    counts = np.diff(np.r_[starts, n])
    ukey = skey[starts]
    first, second = pairs_within_groups(order, starts, counts)   # within a cell: every pair of its points
    # between a cell and each of 13 neighbours: every point of one with every point of the other
    ucell = np.stack([ukey & (2**21 - 1), (ukey >> 21) & (2**21 - 1), ukey >> 42], axis=1)
    for off in _HALF_OFFSETS:
        nb = ucell + off
        ok = np.all(nb >= 0, axis=1)
        nkey = (nb[:, 2] << 42) | (nb[:, 1] << 21) | nb[:, 0]
        pos = np.searchsorted(ukey, nkey)
        hit = ok & (pos < len(ukey))
        hit[hit] = ukey[pos[hit]] == nkey[hit]
        a, b = np.flatnonzero(hit), pos[hit]
        if not len(a):
            continue
        na, nbc = counts[a], counts[b]
        rep = na * nbc
        ia = np.repeat(starts[a], rep) + (np.arange(rep.sum()) - np.repeat(np.cumsum(rep) - rep, rep)) // \
            np.repeat(nbc, rep)
        ib = np.repeat(starts[b], rep) + (np.arange(rep.sum()) - np.repeat(np.cumsum(rep) - rep, rep)) % \
            np.repeat(nbc, rep)
        first.append(order[ia])
        second.append(order[ib])
    if not first:
        return np.zeros((0, 2), dtype=np.int64)
    i, j = np.concatenate(first), np.concatenate(second)
    d = q[i] - q[j]
    close = np.einsum("ij,ij->i", d, d) <= 1.0
    pairs = np.stack([np.minimum(i, j), np.maximum(i, j)], axis=1)[close]
    return pairs[np.lexsort((pairs[:, 1], pairs[:, 0]))]
