"""Numba kernels for welding and for the common case of the mesh checks (optional; needs ``numba``).

Imported lazily by :mod:`inertia.geometry.checks` and :mod:`inertia.geometry.mesh_io`,
which fall back to their NumPy code when numba cannot be imported.  Three jobs, each a
single pass with an open-addressing hash table (linear probing, power-of-two capacity,
load factor <= 1/2), so their cost is O(n) with no sort:

* :func:`weld_map` -- the lowest index of a vertex with exactly the same coordinates
  (the same map as the NumPy ``checks._weld_map``);
* :func:`near_merge_map` -- the lowest index of each group of vertices joined by pairs at
  distance <= ``tol`` (the same groups as ``cKDTree.query_pairs`` + connected components);

Repetition here is deliberate: the kernels are written as flat scalar arithmetic (numba
compiles it to registers; a helper returning tuples, or a loop over the three coordinates,
costs measurably in the inner loops), so a few lines of the same shape recur between kernels
that differ in what they accumulate.  ``duplicates`` lists them; they stay.
"""

from __future__ import annotations

import numba as nb
import numpy as np

_JIT = dict(cache=True, nogil=True, boundscheck=False)

#: kernels whose cached machine code shows the module warm (:mod:`inertia._core.compiled`;
#: ``python -m inertia.cli.warmup`` compiles them last)
WARM_PROBE = ("weld_map",)

from .integrals import winding_numbers  # noqa: E402,F401 - compiled in inertia._ext.integrals


# union-find with the lowest index as root (C++: src/ext/integrals/union_find.hpp)
@nb.njit(**_JIT)
def find_root(parent, i):
    """Root of i, halving the path as it goes."""
    while parent[i] != i:
        parent[i] = parent[parent[i]]
        i = parent[i]
    return i


@nb.njit(**_JIT)
def union_low(parent, a, b):
    """Join the sets of a and b; the lower root becomes the root (so roots are group minima)."""
    ra = find_root(parent, a)
    rb = find_root(parent, b)
    if ra < rb:
        parent[rb] = ra
    elif rb < ra:
        parent[ra] = rb

#: merging never joins vertices farther apart than this fraction of the short face edges
MERGE_EDGE_FRACTION = 0.25
#: the near merge's grid cells are this many times its tolerance (a point's box of +- tol
#: leaves its cell with odds of about 6 / this)
NEAR_CELL_TOLS = 256.0

_M1 = np.uint64(0x9E3779B97F4A7C15)
_M2 = np.uint64(0xC2B2AE3D27D4EB4F)
_M3 = np.uint64(0x165667B19E3779F9)
_S29 = np.uint64(29)
_S32 = np.uint64(32)


@nb.njit(**_JIT)
def _capacity(n):
    """Power of two >= 4 n (and >= 16): the size of a table for n keys, filled a quarter at
    most.  Linear probing's runs lengthen fast with the load: a quarter against a half
    measured float32_apart 9.2 -> 6.8 ns a vertex and near_merge_map 13 -> 11 ns a point."""
    cap = 16
    while cap < 4 * n:
        cap *= 2
    return cap


@nb.njit(**_JIT)
def _mix3(a, b, c):
    """64-bit hash of three 64-bit words (multiply, xor, fold the high bits down)."""
    h = (a * _M1) ^ (b * _M2) ^ (c * _M3)
    h ^= h >> _S29
    h ^= h >> _S32
    return h


@nb.njit(**_JIT)
def _weld_groups(vertices):
    """Group the rows of ``vertices`` (V, 3) float64 by exactly equal coordinates.

    Returns ``(group, first, n_groups)``: ``group[i]`` numbers i's group in order of first
    appearance, ``first[g]`` is the lowest index in group g.  Non-finite rows are groups
    of their own; -0.0 equals 0.0 (compared as floats, hashed as ``x + 0.0``).

    The table holds group numbers, a slot for each row at least (it doubles if the groups
    fill half of it): linear probing's runs lengthen fast with the load, and a sparse table,
    never rebuilt on a soup, probes less (18.7 -> 16.1 ns a row on the benchmark's tori against a table
    of a quarter of the rows, an STL soup repeating each position about six times).
    Candidates are compared against a dense copy of each group's coordinates.
    """
    n = vertices.shape[0]
    group = np.empty(n, dtype=np.int64)
    first = np.empty(n, dtype=np.int64)
    coords = np.empty((n, 3), dtype=np.float64)
    hashes = np.empty(n, dtype=np.uint64)
    cap = _capacity(max(8, (n + 3) // 4))   # a slot per row at least: a soup repeats each position ~6 times
    mask = np.uint64(cap - 1)
    table = np.full(cap, -1, dtype=np.int64)
    word = np.empty(3, dtype=np.float64)
    bits = word.view(np.uint64)
    ng = 0
    for i in range(n):
        x = vertices[i, 0] + 0.0
        y = vertices[i, 1] + 0.0
        z = vertices[i, 2] + 0.0
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(z)):
            group[i] = ng
            first[ng] = i
            coords[ng, 0] = x
            coords[ng, 1] = y
            coords[ng, 2] = z
            hashes[ng] = 0
            ng += 1
            continue
        word[0] = x
        word[1] = y
        word[2] = z
        h = _mix3(bits[0], bits[1], bits[2])
        slot = h & mask
        while True:
            g = table[slot]
            if g < 0:
                table[slot] = ng
                group[i] = ng
                first[ng] = i
                coords[ng, 0] = x
                coords[ng, 1] = y
                coords[ng, 2] = z
                hashes[ng] = h
                ng += 1
                break
            if hashes[g] == h and coords[g, 0] == x and coords[g, 1] == y and coords[g, 2] == z:
                group[i] = g
                break
            slot = (slot + np.uint64(1)) & mask
        if 2 * ng > cap:  # keep the load <= 1/2: double the table and re-insert the groups
            cap *= 2
            mask = np.uint64(cap - 1)
            table = np.full(cap, -1, dtype=table.dtype)
            for g in range(ng):
                if hashes[g] == 0 and not np.isfinite(coords[g, 0] + coords[g, 1] + coords[g, 2]):
                    continue
                slot = hashes[g] & mask
                while table[slot] >= 0:
                    slot = (slot + np.uint64(1)) & mask
                table[slot] = g
    return group, first, ng


@nb.njit(**_JIT)
def weld_map(vertices):
    """``rep[i]``: the lowest index j with ``vertices[j] == vertices[i]`` (rows of (V, 3) float64).

    Non-finite rows map to themselves; -0.0 equals 0.0.
    """
    group, first, _ = _weld_groups(vertices)
    rep = np.empty(vertices.shape[0], dtype=np.int64)
    for i in range(vertices.shape[0]):
        rep[i] = first[group[i]]
    return rep


@nb.njit(**_JIT)
def weld_compact(vertices, faces):
    """Weld equal positions and drop unreferenced vertices, in one pass over each array.

    The result of ``compact_vertices(vertices, _weld_map(vertices)[faces])``: each group's
    coordinates are those of its lowest index, and the kept groups keep the order of their
    lowest indices.  ``faces`` must index ``vertices`` (checked by the caller).
    """
    group, first, ng = _weld_groups(vertices)
    nf = faces.shape[0]
    new_id = np.full(ng, -1, dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            new_id[group[faces[t, k]]] = 0
    kept = 0
    for g in range(ng):       # groups are numbered by their lowest index: order kept
        if new_id[g] == 0:
            new_id[g] = kept
            kept += 1
    out_v = np.empty((kept, 3), dtype=np.float64)
    for g in range(ng):
        j = new_id[g]
        if j >= 0:
            i = first[g]
            out_v[j, 0] = vertices[i, 0]
            out_v[j, 1] = vertices[i, 1]
            out_v[j, 2] = vertices[i, 2]
    out_f = np.empty((nf, 3), dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            out_f[t, k] = new_id[group[faces[t, k]]]
    return out_v, out_f


@nb.njit(**_JIT)
def near_merge_map(vertices, tol):
    """``rep[i]``: the lowest index of i's group, vertices joined when at distance <= ``tol``.

    Returns an empty array when the grid cannot index the coordinates (|x| / tol too large
    for int64, or non-finite values); the caller then uses its general method.

    Grid hashing with cells of side :data:`NEAR_CELL_TOLS` tol.  Each point is compared, as
    it is filed, with the points filed before it in its own cell; a point whose box
    [x - tol, x + tol] leaves its cell (one in about NEAR_CELL_TOLS / 6) is then also compared
    with the points of the other cells that box touches.  Two points within tol in different
    cells each have such a box, so every pair is seen.  (Merge tolerances are far below the
    spacing of distinct vertices, so cells rarely hold two points.)  The table of cells has four
    slots a point at least (:func:`_capacity`).
    """
    n = vertices.shape[0]
    side = NEAR_CELL_TOLS * tol
    inv = 1.0 / side
    limit = 2.0 ** 60
    cells = np.empty((n, 3), dtype=np.int64)
    for i in range(n):
        for k in range(3):
            q = np.floor(vertices[i, k] * inv)
            if not (abs(q) < limit):
                return np.empty(0, dtype=np.int64)
            cells[i, k] = np.int64(q)
    cap = _capacity(n)
    mask = np.uint64(cap - 1)
    head = np.full(cap, -1, dtype=np.int64)      # first point of the cell in this slot
    nxt = np.full(n, -1, dtype=np.int64)         # next point of the same cell
    parent = np.arange(n)
    tol2 = tol * tol
    margin = 1.0 + 1e-9   # a cell touched only through rounding is looked at too
    leaves = np.zeros(n, dtype=np.bool_)
    n_leave = 0
    for i in range(n):
        slot = _mix3(np.uint64(cells[i, 0]), np.uint64(cells[i, 1]), np.uint64(cells[i, 2])) & mask
        while True:
            j = head[slot]
            if j < 0:
                head[slot] = i
                break
            if cells[j, 0] == cells[i, 0] and cells[j, 1] == cells[i, 1] and cells[j, 2] == cells[i, 2]:
                while j >= 0:                    # the points of this cell filed before i
                    if _within(vertices, i, j, tol2):
                        union_low(parent, i, j)
                    j = nxt[j]
                nxt[i] = head[slot]
                head[slot] = i
                break
            slot = (slot + np.uint64(1)) & mask
        for k in range(3):
            if (np.floor((vertices[i, k] - tol * margin) * inv) != cells[i, k]
                    or np.floor((vertices[i, k] + tol * margin) * inv) != cells[i, k]):
                leaves[i] = True
                n_leave += 1
                break
    if n_leave > 0:
        lo = np.empty(3, dtype=np.int64)
        hi = np.empty(3, dtype=np.int64)
        for i in range(n):
            if not leaves[i]:
                continue
            for k in range(3):
                lo[k] = np.int64(np.floor((vertices[i, k] - tol * margin) * inv))
                hi[k] = np.int64(np.floor((vertices[i, k] + tol * margin) * inv))
            for c0 in range(lo[0], hi[0] + 1):
                for c1 in range(lo[1], hi[1] + 1):
                    for c2 in range(lo[2], hi[2] + 1):
                        if c0 == cells[i, 0] and c1 == cells[i, 1] and c2 == cells[i, 2]:
                            continue             # its own cell: done as it was filed
                        slot = _mix3(np.uint64(c0), np.uint64(c1), np.uint64(c2)) & mask
                        while True:
                            j = head[slot]
                            if j < 0:
                                break
                            if cells[j, 0] == c0 and cells[j, 1] == c1 and cells[j, 2] == c2:
                                while j >= 0:
                                    if _within(vertices, i, j, tol2):
                                        union_low(parent, i, j)
                                    j = nxt[j]
                                break
                            slot = (slot + np.uint64(1)) & mask
    rep = np.empty(n, dtype=np.int64)
    for i in range(n):
        rep[i] = find_root(parent, i)
    return rep


@nb.njit(**_JIT)
def _within(vertices, i, j, tol2):
    """Points i and j are at distance <= sqrt(tol2)."""
    d0 = vertices[i, 0] - vertices[j, 0]
    d1 = vertices[i, 1] - vertices[j, 1]
    d2 = vertices[i, 2] - vertices[j, 2]
    return d0 * d0 + d1 * d1 + d2 * d2 <= tol2


# One numeric kernel kept whole (146 lines, over the 80-line rule on purpose): its passes
# (indices, areas, edge hash, winding, one component, volume sign) share the hash tables and
# early exits of a single compiled loop nest; split into functions they would pass those
# tables around and lose the one-pass structure that makes the clean-mesh check O(n).
@nb.njit(**_JIT)
def compact(vertices, faces):
    """Drop unreferenced vertices and renumber the faces, keeping the vertices' order."""
    nv = vertices.shape[0]
    nf = faces.shape[0]
    new_id = np.full(nv, -1, dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            new_id[faces[t, k]] = 0
    kept = 0
    for i in range(nv):
        if new_id[i] == 0:
            new_id[i] = kept
            kept += 1
    out_v = np.empty((kept, 3), dtype=np.float64)
    for i in range(nv):
        j = new_id[i]
        if j >= 0:
            out_v[j, 0] = vertices[i, 0]
            out_v[j, 1] = vertices[i, 1]
            out_v[j, 2] = vertices[i, 2]
    out_f = np.empty((nf, 3), dtype=np.int64)
    for t in range(nf):
        for k in range(3):
            out_f[t, k] = new_id[faces[t, k]]
    return out_v, out_f


@nb.njit(**_JIT)
def weld_and_merge(vertices, faces, rtol):
    """``mesh_io._merge_close_vertices`` in one compiled call: weld, then merge within the tolerance.

    Returns ``(vertices, faces, done)``; ``done`` is False when the grid cannot index the
    coordinates, and the caller must then merge the returned (welded) arrays its general way.
    """
    v, f = weld_compact(vertices, faces)
    return _merge_near(v, f, rtol, False)


@nb.njit(**_JIT)
def _key_hash(k0, k1, k2):
    return _mix3(np.uint64(k0) | (np.uint64(k1) << _S32), np.uint64(k2), np.uint64(0x5BD1E995))


# One numeric kernel kept whole (86 lines): the weld of the STL's corner bits and the
# near-merge share one table in one compiled pass; it mirrors weld_and_merge step by step.
@nb.njit(**_JIT)
def stl_weld_and_merge(corners, rtol):
    """Weld the corners of a binary STL, then merge within the tolerance.

    ``corners``: (n, 3, 3) uint32, the bits of each triangle's float32 corner coordinates
    (a view into the file's records).  The same arrays as ``weld_and_merge`` applied to the
    float64 triangle soup (``vertices = corners.reshape(-1, 3)``, ``faces = arange(3 n)``),
    without building that soup: positions are keyed by their bits (equal floats have equal
    bits once -0.0 is folded onto 0.0; rows with a NaN or infinity stay alone, as in
    :func:`weld_map`), and each kept vertex is converted to float64 (exactly) from its first
    occurrence.  The table holds int32 group numbers, a slot for each corner at least (a
    load of 1/6 or less on a closed mesh): linear probing's runs lengthen fast with the load,
    and a sparse table, never rebuilt on a closed mesh, probes less (26 -> 19 ns a face on the
    benchmark's tori against a table of a quarter of the corners; 130 -> 123 ms on an
    icosphere of 1.3M faces).
    """
    n = corners.shape[0]
    m = 3 * n
    if m >= 2 ** 31:
        return np.empty((0, 3)), np.empty((0, 3), dtype=np.int64), False
    group = np.empty(m, dtype=np.int32)
    first = np.empty(m, dtype=np.int32)
    keys = np.empty((m, 3), dtype=np.uint32)
    cap = _capacity(max(8, (m + 3) // 4))   # a slot per corner at least: a closed mesh has ~m / 6 groups
    mask = np.uint64(cap - 1)
    table = np.full(cap, -1, dtype=np.int32)
    sign = np.uint32(0x80000000)
    expo = np.uint32(0x7F800000)
    ng = 0
    for t in range(n):
        for k in range(3):
            i = 3 * t + k
            k0 = corners[t, k, 0]
            k1 = corners[t, k, 1]
            k2 = corners[t, k, 2]
            if (k0 & expo) == expo or (k1 & expo) == expo or (k2 & expo) == expo:
                group[i] = ng             # NaN or infinity: a group of its own, not in the table
                first[ng] = i
                keys[ng, 0] = k0
                keys[ng, 1] = k1
                keys[ng, 2] = k2
                ng += 1
                continue
            if k0 == sign:
                k0 = np.uint32(0)
            if k1 == sign:
                k1 = np.uint32(0)
            if k2 == sign:
                k2 = np.uint32(0)
            slot = _key_hash(k0, k1, k2) & mask
            while True:
                g = table[slot]
                if g < 0:
                    table[slot] = ng
                    group[i] = ng
                    first[ng] = i
                    keys[ng, 0] = k0
                    keys[ng, 1] = k1
                    keys[ng, 2] = k2
                    ng += 1
                    break
                if keys[g, 0] == k0 and keys[g, 1] == k1 and keys[g, 2] == k2:
                    group[i] = g
                    break
                slot = (slot + np.uint64(1)) & mask
            if 2 * ng > cap:          # keep the load <= 1/2: double and re-insert the groups
                cap *= 2
                mask = np.uint64(cap - 1)
                table = np.full(cap, -1, dtype=np.int32)
                for g in range(ng):
                    if (keys[g, 0] & expo) == expo or (keys[g, 1] & expo) == expo or (keys[g, 2] & expo) == expo:
                        continue
                    slot = _key_hash(keys[g, 0], keys[g, 1], keys[g, 2]) & mask
                    while table[slot] >= 0:
                        slot = (slot + np.uint64(1)) & mask
                    table[slot] = g
    bits = np.empty(1, dtype=np.uint32)
    value = bits.view(np.float32)
    v = np.empty((ng, 3), dtype=np.float64)
    for g in range(ng):
        i = first[g]
        for c in range(3):
            bits[0] = corners[i // 3, i % 3, c]
            v[g, c] = np.float64(value[0])
    f = np.empty((n, 3), dtype=np.int64)
    for t in range(n):
        f[t, 0] = group[3 * t]
        f[t, 1] = group[3 * t + 1]
        f[t, 2] = group[3 * t + 2]
    return _merge_near(v, f, rtol, True)


#: float32 numbers of magnitude at least M are at least 2^-24 M apart; coordinates beyond
#: this many tolerances are thus more than 2 tolerances from any other float32 of that size
F32_APART_TOLS = 2.0 ** 26
#: :func:`float32_apart` compares the rows that share a key up to this many times the rows
#: (beyond, a key shared by many rows, the grid is cheaper)
F32_APART_COMPARES = 1


@nb.njit(**_JIT)
def float32_apart(v, tol, maxabs):
    """True when no two rows of ``v`` (finite float32 values, held as float64) are within
    ``tol`` of each other coordinate by coordinate; False when not shown.

    Two distinct float32 numbers of magnitude at least M differ by at least 2^-24 M (their
    spacing).  Let T = :data:`F32_APART_TOLS` tol.  If p and q are within tol in coordinate k
    and |p_k| >= T, then |q_k| >= T - tol > 2^25 tol, so p_k and q_k, if distinct, would differ
    by more than 2 tol: p_k = q_k.  So a near pair agrees on its *reduced* coordinates (those
    of magnitude >= T kept, the others 0), and rows whose reduced keys are all distinct hold no
    near pair.  One hash pass (``maxabs``: the largest |coordinate|, which scales the hash);
    rows with the same key (mirror images across a plane near 0: a quarter of the benchmark's
    tori) are compared, and apart by more than tol in a coordinate they are no near pair.  A
    near pair, or more than :data:`F32_APART_COMPARES` comparisons a row, returns False, and
    the caller merges on its grid.  About 7 ns a vertex (a table of four slots a row:
    :func:`_capacity`), against 11 for the grid's own pass (:func:`near_merge_map`)."""
    n = v.shape[0]
    big = F32_APART_TOLS * tol
    if not (big >= 2.0 ** -100 and big < np.inf and maxabs < np.inf):   # float32 subnormals: 2^-149 apart
        return False
    scale = 2.0 ** 30 / maxabs if maxabs > 0.0 else 0.0     # |reduced coordinate| x scale <= 2^30: an int
    cap = _capacity(n)
    mask = np.uint64(cap - 1)
    table = np.full(cap, -1, dtype=np.int32)
    compares = 0
    for i in range(n):
        a = v[i, 0]
        b = v[i, 1]
        c = v[i, 2]
        if abs(a) < big:
            a = 0.0
        if abs(b) < big:
            b = 0.0
        if abs(c) < big:
            c = 0.0
        slot = _mix3(np.uint64(np.int64(a * scale)), np.uint64(np.int64(b * scale)),
                     np.uint64(np.int64(c * scale))) & mask
        while True:
            j = table[slot]
            if j < 0:
                table[slot] = i
                break
            p = v[j, 0]
            q = v[j, 1]
            r = v[j, 2]
            if (p if abs(p) >= big else 0.0) == a and (q if abs(q) >= big else 0.0) == b \
                    and (r if abs(r) >= big else 0.0) == c:
                # the same key: apart if a coordinate differs by more than tol (the difference,
                # rounded to nearest, exceeds tol only if the exact one does: tol is a float)
                compares += 1
                if compares > F32_APART_COMPARES * n or not (
                        abs(p - v[i, 0]) > tol or abs(q - v[i, 1]) > tol or abs(r - v[i, 2]) > tol):
                    return False
            slot = (slot + np.uint64(1)) & mask
    return True


@nb.njit(**_JIT)
def _capped_by_edges(v, f, tol):
    """``tol``, at most MERGE_EDGE_FRACTION of the short edges of the faces (their 1st
    percentile): merging is for copies of a vertex, never for the mesh's own features, whatever
    its distance from the origin (mesh_io.edge_capped_tolerance is the NumPy twin)."""
    m = f.shape[0]
    shortest = np.inf
    for t in range(m):
        for k in range(3):
            a, b = f[t, k], f[t, (k + 1) % 3]
            d = (v[a, 0] - v[b, 0]) ** 2 + (v[a, 1] - v[b, 1]) ** 2 + (v[a, 2] - v[b, 2]) ** 2
            if d > 0.0 and d < shortest:
                shortest = d
    if not (tol > MERGE_EDGE_FRACTION * np.sqrt(shortest)):
        return tol                 # the common case: far below every edge
    lengths = np.empty(3 * m)
    n = 0
    for t in range(m):
        for k in range(3):
            a, b = f[t, k], f[t, (k + 1) % 3]
            d = np.sqrt((v[a, 0] - v[b, 0]) ** 2 + (v[a, 1] - v[b, 1]) ** 2 + (v[a, 2] - v[b, 2]) ** 2)
            if d > 0.0:
                lengths[n] = d
                n += 1
    short = np.sort(lengths[:n])[(n - 1) // 100]
    return min(tol, MERGE_EDGE_FRACTION * short)


@nb.njit(**_JIT)
def _merge_near(v, f, rtol, f32):
    """Second half of :func:`weld_and_merge`: merge the welded ``v, f`` within the tolerance.
    ``f32``: every coordinate is a float32 value (a binary STL's): first tried with
    :func:`float32_apart`, which proves most meshes need no merge in one hash pass."""
    n = v.shape[0]
    if n < 2 or not (rtol > 0.0):
        return v, f, True
    # the box in scalars (kept in registers: 4x faster than in arrays)
    lx = ly = lz = np.inf
    hx = hy = hz = -np.inf
    for i in range(n):
        x = v[i, 0]
        y = v[i, 1]
        z = v[i, 2]
        if not (np.isfinite(x) and np.isfinite(y) and np.isfinite(z)):
            return v, f, True          # non-finite coordinates: reported by the checks, not merged
        lx = min(lx, x)
        hx = max(hx, x)
        ly = min(ly, y)
        hy = max(hy, y)
        lz = min(lz, z)
        hz = max(hz, z)
    big = max(-lx, hx, -ly, hy, -lz, hz)
    ex = hx - lx
    ey = hy - ly
    ez = hz - lz
    scale = max(ex, ey, ez)
    if not np.isfinite(scale):
        return v, f, True           # coordinates near the float64 limit: nothing sensible to merge
    diag = 0.0
    if scale > 0.0:                 # scaled, so that squares of extents near 1e200 do not overflow
        diag = scale * np.sqrt((ex / scale) ** 2 + (ey / scale) ** 2 + (ez / scale) ** 2)
    tol = max(rtol * diag, 64.0 * np.finfo(np.float64).eps * big)
    if not (tol > 0.0):
        return v, f, True
    if not np.isfinite(tol):
        return v, f, True
    if f32 and n < 2 ** 31 and float32_apart(v, tol, big):
        return v, f, True           # no two vertices within tol (capping by the edges only lowers it)
    tol = _capped_by_edges(v, f, tol)
    rep = near_merge_map(v, tol)
    if rep.shape[0] == 0:
        return v, f, False
    changed = False
    for i in range(n):
        if rep[i] != i:
            changed = True
            break
    if not changed:
        return v, f, True
    fm = np.empty_like(f)
    for t in range(f.shape[0]):
        for k in range(3):
            fm[t, k] = rep[f[t, k]]
    v2, f2 = compact(v, fm)
    return v2, f2, True
