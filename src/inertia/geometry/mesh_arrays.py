"""Mesh arrays: input validation, exact welding of equal vertices, compaction, graph components.

Every function here returns arrays that the compiled kernels may read: validated in their
final shape (``(V, 3)`` finite-or-not float64, ``(F, 3)`` int64 indices in range are checked
by the analysis, not here).  Welding, compaction and components run in the compiled core
(:mod:`inertia._ext.topology`).
"""

from __future__ import annotations

import numpy as np

from .._core.errors import InputError
from .._ext import topology as _k

__all__ = ["validate_inputs", "weld_map", "weld_vertices", "compact_vertices", "connected_components"]


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
        v = np.asarray(vertices)
        real = not (v.dtype == bool or np.issubdtype(v.dtype, np.complexfloating))
        v = np.asarray(v, dtype=np.float64) if real else v
    except (TypeError, ValueError) as exc:
        raise InputError(f"vertices must be a numeric (V, 3) array, got {type(vertices).__name__}: {exc}") from None
    if not real:   # never cut to 0/1 or to the real part
        kind = "booleans" if v.dtype == bool else "complex values"
        raise InputError(f"vertices must hold real numbers, got {kind} (dtype {v.dtype})")
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
    """True when every index of ``faces`` (validated, (F, 3) int64) is in 0..n_vertices-1: asked
    before any kernel is handed faces, so that the caller's own error names the problem (the
    kernels check again, and refuse by position)."""
    return len(faces) == 0 or (int(faces.min()) >= 0 and int(faces.max()) < n_vertices)


# ---------------------------------------------------------------------------------- welding
def weld_map(vertices: np.ndarray) -> np.ndarray:
    """``rep[i]``: the lowest index of a vertex with exactly the coordinates of vertex i.

    Non-finite vertices map to themselves; -0.0 equals 0.0.  One hash-table pass.
    """
    return _k.weld_map(np.ascontiguousarray(vertices, dtype=np.float64))


def weld_vertices(vertices, faces) -> tuple[np.ndarray, np.ndarray]:
    """Merge vertices of exactly equal coordinates and drop unreferenced vertices.

    Returns ``(vertices (V', 3) float64, faces (F, 3) int64)``, vertices in order of first
    use by the original indices, each group with the coordinates of its lowest index.  An
    index outside ``vertices`` is an InputError.
    """
    v, f = validate_inputs(vertices, faces)
    if len(f) == 0:
        return v[:0], f
    if not faces_in_range(f, len(v)):
        raise InputError(f"faces index vertices outside 0..{len(v) - 1} "
                         f"(min {int(f.min())}, max {int(f.max())})", code="bad_index")
    return _k.weld_compact(v, f)


def compact_vertices(vertices: np.ndarray, faces: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Drop unreferenced vertices and renumber the faces, keeping the vertices' order (the
    result of ``np.unique(faces, return_inverse=True)``, in O(V + F))."""
    return _k.compact(np.ascontiguousarray(vertices, dtype=np.float64), np.ascontiguousarray(faces, dtype=np.int64))


# ---------------------------------------------------------------------------------- graphs
def connected_components(n: int, a, b) -> tuple[int, np.ndarray]:
    """``(count, labels (n,))`` of the undirected graph on nodes ``0..n-1`` with edges
    ``a[i] - b[i]``; components are numbered in order of their lowest node, as
    ``scipy.sparse.csgraph.connected_components`` numbers them."""
    a = np.ascontiguousarray(a, dtype=np.int64).ravel()
    b = np.ascontiguousarray(b, dtype=np.int64).ravel()
    return _k.connected_components(int(n), a, b)


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
