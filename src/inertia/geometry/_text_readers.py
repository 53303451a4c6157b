"""Native readers of the text mesh formats ASCII STL and OBJ (no trimesh).

The grammar is written out in :mod:`._text_reference` (the plain-Python reader used without
numba); with numba, :mod:`._text_numba` reads the same grammar in one compiled pass and the
numbers it leaves (more than 16 significant digits, large exponents, nan, inf) are read by
NumPy's ``strtod`` in one call.  Both give the arrays trimesh gives for the same file (its
OBJ reader counts negative indices from the end of the file, we from the line, as the OBJ
specification says; it splits an OBJ by material, we keep the file's order) and refuse a
malformed file with a :class:`~inertia.errors.MeshFileError` naming file, line and text.
"""

from __future__ import annotations

import ctypes
import os
import re
import warnings
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from .._core.compiled import ahead_of_time_kernels
from .._core.errors import MeshFileError
from . import _text_reference as ref

__all__ = ["read_ascii_stl", "read_obj", "text_kernels", "prepare"]

def text_kernels(size: int = 1 << 30):
    """The compiled readers (:mod:`._text_numba`), or None for the reference reader (numba
    missing, or the rule of :func:`inertia.geometry.mesh_arrays.compiled_kernels` for a file
    of ``size`` bytes: the reference reads ~20 MB/s, about 3x the NumPy mesh path's cost a face)."""
    from .mesh_arrays import compiled_kernels

    return compiled_kernels("inertia.geometry._text_numba", size // 12)


#: below this size a text file is read by the reference reader until the compiled reader of
#: its format has been used in this process: loading it (from numba's cache) takes about
#: 0.15 s, in which the reference reads about 3 MB
EAGER_BYTES = 1 << 20
_compiled_used: set[str] = set()


def _kernels_for(size: int, compiled: bool | None, fmt: str):
    """The compiled readers for a file of ``size`` bytes of format ``fmt``, or None for the
    reference.  Small files wait for the compiled reader to be loaded unless it comes from
    the ahead-of-time library (:mod:`inertia._core.aot`), which costs nothing to load."""
    if compiled is False:
        return None
    if (compiled is None and size < EAGER_BYTES and fmt not in _compiled_used
            and ahead_of_time_kernels("inertia.geometry._text_numba") is None):
        return None
    kernels = text_kernels(1 << 30 if compiled else size)
    if kernels is None and compiled:
        try:
            from . import _text_numba as kernels
        except ImportError:
            return None
    if kernels is not None:
        _compiled_used.add(fmt)
    return kernels


def prepare(formats) -> None:
    """Load the compiled readers of ``formats`` ("obj", "ascii_stl") now (a process that will
    read many small files, or the parent of workers); without numba, nothing."""
    samples = {"obj": (read_obj, b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n"),
               "ascii_stl": (read_ascii_stl, b"solid\nfacet\nouter loop\nvertex 0 0 0\nvertex 1 0 0\n"
                                             b"vertex 0 1 0\nendloop\nendfacet\nendsolid\n")}
    for fmt in formats:
        if fmt in samples and text_kernels(1 << 30) is not None:
            reader, text = samples[fmt]
            reader(np.frombuffer(text, dtype=np.uint8), "sample", compiled=True)


def read_ascii_stl(data: np.ndarray, path, compiled: bool | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and faces (F, 3) int64 of an ASCII STL: ``vertices[faces]``
    are the file's facets, corner for corner.

    ``data``: the file's bytes as a uint8 array; ``compiled``: force (True) or avoid (False)
    the numba reader (default: numba when installed, for a small file once that reader has
    been used in this process, see :data:`EAGER_BYTES`).  The reference reader lists every
    corner (``faces = arange(3 F)``); the compiled one stores a corner once when it repeats
    one read shortly before (see ``_text_numba.read_ascii_stl``): the same surface, and after
    welding the same arrays.
    """
    kernels = _kernels_for(len(data), compiled, "ascii_stl")
    if kernels is None:
        v, err = ref.read_ascii_stl(bytes(data))
        f = np.arange(len(v) - len(v) % 3, dtype=np.int64).reshape(-1, 3)   # (after an error: whole facets)
    else:
        v, f, err = _parallel_stl(data, kernels) or _sequential_stl(data, kernels)
    if err is not None:
        raise MeshFileError(error_message(path, err, "ASCII STL"), code="malformed")
    return v, f


#: bytes per vertex and per facet allowed for in the output (exporters write about 85 per corner
#: and 260 per facet; a sixth of the corners are new vertices); the kernel grows them if needed
_STL_BYTES_PER_VERTEX = 256
_STL_BYTES_PER_FACET = 192
#: a file this large is read in chunks by several threads (the kernel releases the GIL)
PARALLEL_BYTES = 32 * 2**20
_FACET_LINE = re.compile(rb"\n[ \t\r\v\f]*facet[ \t\r\v\f\n]", re.I)


def _stl_room(size: int) -> tuple[int, int]:
    """Rows to allocate for the vertices and facets of ``size`` bytes of ASCII STL."""
    return size // _STL_BYTES_PER_VERTEX + 16, size // _STL_BYTES_PER_FACET + 16


def _sequential_stl(data: np.ndarray, kernels):
    """``(vertices, faces, TextError or None)`` in one compiled pass."""
    rows_v, rows_f = _stl_room(len(data))
    out, nv, faces, nf, slow, status, where, detail, state, last = kernels.read_ascii_stl(
        data, np.empty((rows_v, 3)), np.empty((rows_f, 3), dtype=np.int64), 0)
    if status == ref.OK and state != 0:
        status, where, detail = ref.TRUNCATED, last, state
    v = out[:nv]
    _fill_slow(v, data, slow, kernels)
    return v, faces[:nf], (None if status == ref.OK else _kernel_error(data, status, where, detail, obj=False))


def _stl_chunks(data: np.ndarray, parts: int) -> list[int]:
    """Offsets splitting ``data`` into up to ``parts`` runs of lines, each after the first
    starting at a ``facet`` line (where a valid file is inside a solid, between facets)."""
    bounds = [0]
    for k in range(1, parts):
        start = max(k * len(data) // parts, bounds[-1])
        m = _FACET_LINE.search(bytes(data[start:start + 2**16]))
        if m is not None:
            bounds.append(start + m.start() + 1)
    return bounds + [len(data)]


def _parallel_stl(data: np.ndarray, kernels):
    """:func:`_sequential_stl` by several threads on chunks of a large file, into one pair of
    arrays; None (the caller reads it in one pass) for a small file, one thread, or anything
    unusual: an error, a chunk that does not end between facets, outputs that had to grow."""
    threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    bounds = _stl_chunks(data, min(threads, 8, len(data) // PARALLEL_BYTES))
    if len(bounds) < 3:
        return None
    if getattr(kernels, "holds_gil", False):   # the ahead-of-time library: numba's reader runs in threads
        from .mesh_arrays import compiled_kernels

        kernels = compiled_kernels("inertia.geometry._text_numba", len(data) // 12, ahead_of_time=False)
        if kernels is None:
            return None
    room = np.array([_stl_room(b - a) for a, b in zip(bounds, bounds[1:])])
    first = np.concatenate([[[0, 0]], np.cumsum(room, axis=0)])
    big_v, big_f = np.empty((first[-1, 0], 3)), np.empty((first[-1, 1], 3), dtype=np.int64)

    def chunk(k):
        return kernels.read_ascii_stl(data[bounds[k]:bounds[k + 1]], big_v[first[k, 0]:first[k + 1, 0]],
                                      big_f[first[k, 1]:first[k + 1, 1]], min(k, 1))

    with ThreadPoolExecutor(len(room)) as pool:
        results = list(pool.map(chunk, range(len(room))))
    ends = [1] * (len(room) - 1) + [0]
    if any(r[5] != ref.OK or r[8] != end or len(r[0]) != nv or len(r[2]) != nf
           for r, end, (nv, nf) in zip(results, ends, room)):
        return None
    done_v = done_f = 0
    slows = []
    for k, r in enumerate(results):   # close the gaps: rows move down (memmove copes with overlap)
        nv, nf, slow = r[1], r[3], r[4].copy()
        ctypes.memmove(big_v[done_v:].ctypes.data, big_v[first[k, 0]:].ctypes.data, nv * 24)
        ctypes.memmove(big_f[done_f:].ctypes.data, big_f[first[k, 1]:].ctypes.data, nf * 24)
        big_f[done_f:done_f + nf] += done_v
        slow[:, :2] += bounds[k]
        slow[:, 2] += 3 * done_v
        slows.append(slow)
        done_v += nv
        done_f += nf
    v = big_v[:done_v]
    _fill_slow(v, data, np.concatenate(slows), kernels)
    return v, big_f[:done_f], None


def read_obj(data: np.ndarray, path, compiled: bool | None = None, quads: str = "fan") -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and triangles (F, 3) int64 (0-based) of an OBJ (see :func:`read_ascii_stl`).

    Polygons are fanned from their first vertex (as trimesh does); with ``quads="shorter"`` a
    quadrilateral is split along its shorter diagonal instead (as MuJoCo's OBJ reader does: the
    two differ on a quad that is not planar)."""
    kernels = _kernels_for(len(data), compiled, "obj")
    raw = bytes(data) if kernels is None else None

    def parse(limit):
        if kernels is None:
            return ref.read_obj(raw, limit)
        v, f, slow, largest, status, where, detail, q = kernels.read_obj(data, limit)
        _fill_slow(v, data, slow, kernels)
        err = None if status == ref.OK else _kernel_error(data, status, where, detail, obj=True)
        if err is not None and err.kind == ref.INDEX_RANGE:   # as the reference counts
            err = ref.TextError(err.kind, err.line, err.text, err.token,
                                len(v) if err.token.startswith(b"-") else limit)
        return v, f, largest, err, q

    v, f, largest, err, q = parse(-1)
    if err is None and largest > len(v):   # a positive index beyond the last vertex: find its line
        err = parse(len(v))[3]
    if err is not None:
        raise MeshFileError(error_message(path, err, "OBJ"), code="malformed")
    if quads == "shorter" and len(q):
        _split_quads_shorter(v, f, q)
    return v, f


def _split_quads_shorter(v: np.ndarray, f: np.ndarray, q: np.ndarray) -> None:
    """Re-split in place each quadrilateral a b c d fanned as (a b c), (a c d) along its shorter
    diagonal: (a b d), (b c d) when |b - d| <= |a - c| (MuJoCo's rule: ties take b-d)."""
    a, b, c, d = f[q, 0], f[q, 1], f[q, 2], f[q + 1, 2]
    d_ac = np.einsum("ij,ij->i", v[a] - v[c], v[a] - v[c])
    d_bd = np.einsum("ij,ij->i", v[b] - v[d], v[b] - v[d])
    flip = ~(d_ac < d_bd)
    t0, t1 = q[flip], q[flip] + 1
    f[t0] = np.stack([a[flip], b[flip], d[flip]], axis=1)
    f[t1] = np.stack([b[flip], c[flip], d[flip]], axis=1)


def _fill_slow(v: np.ndarray, data: np.ndarray, slow: np.ndarray, kernels) -> None:
    """Read the numbers the kernel left (``slow`` rows: start, end, flat index) with NumPy's strtod."""
    slow = slow[slow[:, 2] < v.size]   # after an error: not the numbers of the line refused
    if len(slow) == 0:
        return
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        values = np.fromstring(kernels.gather_tokens(data, slow), dtype=np.float64, sep=" ")
    if len(values) != len(slow):  # the kernel checked every token's syntax: cannot happen
        raise MeshFileError(f"text reader: strtod read {len(values)} of {len(slow)} numbers whose syntax "
                            "was checked (please report the file)", code="unreadable")
    v.reshape(-1)[slow[:, 2]] = values


#: a token: up to a separator or LF; in OBJ also up to a line continuation, and in a face up to a comment
_STL_TOKEN = re.compile(rb"\S*")
_OBJ_TOKEN = re.compile(rb"(?:[^\s\\]|\\(?!\r?\n))*")
_REF_TOKEN = re.compile(rb"(?:[^\s\\#]|\\(?!\r?\n))*")
#: kinds whose ``detail`` is the offset of a token (others: a count)
_TOKEN_KINDS = (ref.BAD_NUMBER, ref.EXTRA_TOKENS, ref.BAD_REF, ref.ZERO_INDEX, ref.INDEX_RANGE)
_CHUNK = 1 << 24


def _kernel_error(data: np.ndarray, kind: int, where: int, detail: int, obj: bool) -> ref.TextError:
    """The :class:`TextError` of a kernel's status (``where``: the offset of the line)."""
    line = 1 + sum(int(np.count_nonzero(data[k:min(k + _CHUNK, where)] == 10)) for k in range(0, where, _CHUNK))
    end = where
    while end < len(data):
        k = bytes(data[end:end + 4096]).find(b"\n")
        if k >= 0:
            end += k
            break
        end += 4096
    text = bytes(data[where:min(end, len(data))])
    token, count = b"", int(detail)
    if kind in _TOKEN_KINDS:
        pattern = _STL_TOKEN if not obj else _REF_TOKEN if kind in (ref.BAD_REF, ref.ZERO_INDEX,
                                                                   ref.INDEX_RANGE) else _OBJ_TOKEN
        token = pattern.match(bytes(data[detail:detail + 4096])).group(0)
    elif kind == ref.UNEXPECTED:
        token = text.split()[0]
    return ref.TextError(kind, line, text, token, count)


def error_message(path, err: ref.TextError, fmt: str) -> str:
    """``PATH, line N: ...`` for a :class:`TextError` of a ``fmt`` ("ASCII STL" or "OBJ") file."""
    text = err.text.strip().decode("utf-8", "replace")[:80]
    token = err.token.decode("utf-8", "replace")[:40]
    where = f"{path}, line {err.line}"
    if err.kind == ref.ZERO_INDEX:   # worded as before the native reader (tests, users' scripts)
        return (f"{where}: face index 0 in {text!r}: OBJ vertex indices start at 1 "
                "(negative indices count back from the last vertex)")
    what = {
        ref.BAD_NUMBER: f"malformed number {token!r}",
        ref.FEW_COORDS: f"a vertex needs 3 coordinates, this one has {err.count}",
        ref.EXTRA_TOKENS: f"unexpected {token!r} after the 3 coordinates of a vertex",
        ref.UNEXPECTED: f"unexpected {token!r} {ref.STL_PLACES[err.count % 3]}",
        ref.FACET_SIZE: f"a facet with {err.count} vertices (facets are triangles)",
        ref.TRUNCATED: f"the file ends {ref.STL_PLACES[err.count % 3]} (no endsolid: truncated?)",
        ref.BAD_REF: f"malformed face vertex {token!r} (v, v/vt, v/vt/vn or v//vn)",
        ref.FEW_REFS: f"a face needs at least 3 vertices, this one has {err.count}",
        ref.INDEX_RANGE: f"face vertex {token!r} names no vertex ({err.count} defined "
                         f"{'above it' if token.startswith('-') else 'in the file'})",
    }[err.kind]
    return f"{where}: malformed {fmt}: {what} in {text!r}"
