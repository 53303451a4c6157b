"""Numba kernels reading ASCII STL and OBJ text (optional; needs ``numba``).

Imported lazily by :mod:`inertia.geometry._text_readers`, which falls back to the line-by-line
reference parser of :mod:`inertia.geometry._text_reference` without numba; tests compare the
two on valid files and on mutated ones (same arrays, or the same error on the same line).

One pass over the bytes, no copy of the text.  Numbers are read exactly as ``strtod`` reads
them (correctly rounded): a decimal of at most 16 significant digits and an exponent within
+-22 is one exact integer times or divided by one exact power of ten, a single correctly
rounded operation (Clinger's fast path, which covers what CAD exporters write); up to 18
significant digits (the 17 of Python's ``repr``, which trimesh's exporter writes) go through
Eisel and Lemire's 128-bit algorithm; anything else valid (more digits, the rare cases that
algorithm leaves undecided, nan, inf) is left as a *slow token* whose byte range the caller
parses with NumPy.  Errors are returned as codes with the byte offset of the
line, never raised (the caller names file, line and text).
"""

from __future__ import annotations

import math

import numba as nb
import numpy as np
from numba import types
from numba.cpython.unsafe.numbers import leading_zeros
from numba.extending import intrinsic

# the status codes of the reference reader
from ._text_reference import (
    BAD_NUMBER,
    BAD_REF,
    EXTRA_TOKENS,
    FACET_SIZE,
    FEW_COORDS,
    FEW_REFS,
    INDEX_RANGE,
    OK,
    UNEXPECTED,
    ZERO_INDEX,
)

_JIT = dict(cache=True, nogil=True, boundscheck=False)

#: kernels whose cached machine code shows the module warm (:mod:`inertia._core.compiled`)
WARM_PROBE = ("read_ascii_stl", "read_obj")

#: exact powers of ten (10**22 is the largest one a float64 holds exactly)
_P10 = np.array([float(10**k) for k in range(23)])
_FAST_MANTISSA = 2**53


# ASCII STL keywords
_KW_OTHER, _KW_SOLID, _KW_ENDSOLID, _KW_FACET, _KW_ENDFACET, _KW_OUTER, _KW_ENDLOOP, _KW_VERTEX = range(8)

_NL, _CR, _SLASH, _BACKSLASH, _HASH = 10, 13, 47, 92, 35


@intrinsic
def _address(typingctx, array):
    """The data pointer of a uint8 array."""
    def codegen(context, builder, signature, args):
        return context.make_array(signature.args[0])(context, builder, args[0]).data

    return types.CPointer(types.uint8)(array), codegen


@nb.njit(inline="always", **_JIT)
def _borrowed(data):
    """``data`` seen through a view without a reference count (the caller keeps it alive).

    Every helper call that passes an array makes numba count a reference in and out of it,
    two atomic operations that the compiler cannot remove once the helper branches on the
    array's contents; for the byte-by-byte scans here that was 10x the work itself.
    """
    return nb.carray(_address(data), data.shape[0])


@nb.njit(inline="always", **_JIT)
def _blank(c):
    """Space, tab, CR, VT, FF: separators inside a line (LF ends it)."""
    return c == 32 or (9 <= c <= 13 and c != 10)


@nb.njit(inline="always", **_JIT)
def _digit(c):
    return 48 <= c <= 57


@nb.njit(inline="always", **_JIT)
def _continued(data, i, n):
    """Length of a line continuation (backslash, optional CR, LF) at ``i``, else 0."""
    if i < n and data[i] == _BACKSLASH:
        if i + 1 < n and data[i + 1] == _NL:
            return 2
        if i + 2 < n and data[i + 1] == _CR and data[i + 2] == _NL:
            return 3
    return 0


@nb.njit(inline="always", **_JIT)
def _skip_blanks(data, i, n, joins):
    """First position at or after ``i`` that is not a separator (``joins``: OBJ line continuations too)."""
    while i < n:
        c = data[i]
        if _blank(c):
            i += 1
        elif joins and c == _BACKSLASH:
            k = _continued(data, i, n)
            if k == 0:
                return i
            i += k
        else:
            return i
    return i


@nb.njit(inline="always", **_JIT)
def _end_of_line(data, i, n, joins):
    """Position of the LF ending the line at ``i`` (``n`` at the end; ``joins``: LF after a backslash continues)."""
    while i < n:
        if data[i] == _NL:
            if not joins:
                return i
            j = i - 1
            if j >= 0 and data[j] == _CR:
                j -= 1
            if j < 0 or data[j] != _BACKSLASH:
                return i
        i += 1
    return n


@nb.njit(inline="always", **_JIT)
def _token_end(data, i, n, joins):
    """True when position ``i`` ends a token: a separator, LF, end of text (or a continuation)."""
    if i >= n:
        return True
    c = data[i]
    if c == _NL or _blank(c):
        return True
    return joins and _continued(data, i, n) > 0


@nb.njit(**_JIT)
def _word(data, i, n):
    """End of ``nan``, ``inf`` or ``infinity`` (any case) at ``i``, else -1."""
    if i + 3 > n:
        return -1
    a, b, c = data[i] | 32, data[i + 1] | 32, data[i + 2] | 32
    if a == 110 and b == 97 and c == 110:          # nan
        return i + 3
    if not (a == 105 and b == 110 and c == 102):   # inf
        return -1
    if i + 8 <= n and (data[i + 3] | 32) == 105 and (data[i + 4] | 32) == 110 and (data[i + 5] | 32) == 105 \
            and (data[i + 6] | 32) == 116 and (data[i + 7] | 32) == 121:   # inity
        return i + 8
    return i + 3


def _powers_of_five():
    """128-bit mantissas of 5**q (the most significant bit set), q = -342..308, as (high, low)
    uint64 words: truncated for q >= 0, rounded up for q < 0 (the table of Lemire's
    algorithm, computed here with Python's exact integers)."""
    hi = np.empty(651, dtype=np.uint64)
    lo = np.empty(651, dtype=np.uint64)
    for q in range(-342, 309):
        if q < 0:
            p5 = 5 ** -q
            z = (p5 - 1).bit_length()
            c = 2 ** (z + 127 if q >= -27 else 2 * z + 128) // p5 + 1
            while c >= 1 << 128:
                c //= 2
        else:
            c = 5 ** q
            while c < 1 << 127:
                c *= 2
            while c >= 1 << 128:
                c //= 2
        hi[q + 342], lo[q + 342] = c >> 64, c & (2**64 - 1)
    return hi, lo


_P5_HI, _P5_LO = _powers_of_five()
_U = np.uint64
_M32, _S32, _ONE, _LOW9 = _U(0xFFFFFFFF), _U(32), _U(1), _U(0x1FF)
_HIDDEN, _CARRY = _U(1 << 52), _U(1 << 53)


@nb.njit(inline="always", **_JIT)
def _mul128(a, b):
    """``(high, low)`` 64-bit words of the 128-bit product of two uint64."""
    a0, a1, b0, b1 = a & _M32, a >> _S32, b & _M32, b >> _S32
    p00, p01, p10 = a0 * b0, a0 * b1, a1 * b0
    mid = (p00 >> _S32) + (p01 & _M32) + (p10 & _M32)
    return a1 * b1 + (p01 >> _S32) + (p10 >> _S32) + (mid >> _S32), (p00 & _M32) | (mid << _S32)


@nb.njit(**_JIT)
def _eisel_lemire(w, q):
    """``(w * 10**q correctly rounded, True)`` for 0 < w < 2**63, or ``(0.0, False)`` when
    undecided (halfway cases, subnormals, overflow: strtod reads those).

    Lemire, "Number parsing at a gigabyte per second" (2021): the product of ``w`` and a
    128-bit approximation of 5**q decides the rounding unless its low bits are ambiguous.
    """
    if q < -342 or q > 308:
        return 0.0, False
    lz = leading_zeros(_U(w))
    i = _U(w) << _U(lz)
    upper, lower = _mul128(i, _P5_HI[q + 342])
    if (upper & _LOW9) == _LOW9 and lower + i < lower:
        high2, low2 = _mul128(i, _P5_LO[q + 342])
        middle = lower + high2
        if middle < lower:
            upper += _ONE
        if middle + _ONE == _U(0) and (upper & _LOW9) == _LOW9 and low2 + i < low2:
            return 0.0, False
        lower = middle
    upperbit = upper >> _U(63)
    mantissa = upper >> (upperbit + _U(9))
    lz += 1 - int(upperbit)
    if lower == _U(0) and (upper & _LOW9) == _U(0) and (mantissa & _U(3)) == _ONE:
        return 0.0, False   # exactly halfway: round to even needs the whole number
    mantissa = (mantissa + (mantissa & _ONE)) >> _ONE
    if mantissa >= _CARRY:
        mantissa = _HIDDEN
        lz -= 1
    exponent = (((152170 + 65536) * q) >> 16) + 1024 + 63 - lz
    if exponent < 1 or exponent > 2046:
        return 0.0, False
    return math.ldexp(float(mantissa), exponent - 1075), True


@nb.njit(inline="always", **_JIT)
def parse_number(data, i, n):
    """``(value, end, status)`` of the decimal number at ``i``: status 0 exact, 1 a valid number
    left for ``strtod`` (value 0), 2 not a number.  The caller checks what follows ``end``.

    Up to 18 significant digits accumulate in an int64; the value is one correctly rounded
    operation when that is exact (Clinger), else Eisel-Lemire's; more digits, and the cases
    Eisel-Lemire leaves undecided, go to strtod.
    """
    neg = False
    if i < n and (data[i] == 45 or data[i] == 43):
        neg = data[i] == 45
        i += 1
    start = i
    while i < n and data[i] == 48:   # leading zeros
        i += 1
    mant = 0
    first = i
    while i < n and _digit(data[i]):
        mant = mant * 10 + (data[i] - 48)
        i += 1
    significant = i - first
    digits = i - start
    e10 = 0
    if i < n and data[i] == 46:
        i += 1
        start = i
        if significant == 0:
            while i < n and data[i] == 48:
                i += 1
        first = i
        while i < n and _digit(data[i]):
            mant = mant * 10 + (data[i] - 48)
            i += 1
        significant += i - first
        e10 = start - i
        digits += i - start
    elif digits == 0:   # no digit, no point: nan or inf?
        j = _word(data, i, n)
        return 0.0, (j if j >= 0 else i), (1 if j >= 0 else 2)
    if digits == 0:
        return 0.0, i, 2
    if i < n and (data[i] | 32) == 101:
        i += 1
        eneg = False
        if i < n and (data[i] == 45 or data[i] == 43):
            eneg = data[i] == 45
            i += 1
        ev = 0
        ed = 0
        while i < n and _digit(data[i]):
            if ev < 100000:
                ev = ev * 10 + (data[i] - 48)
            ed += 1
            i += 1
        if ed == 0:
            return 0.0, i, 2
        e10 += -ev if eneg else ev
    if mant == 0 and significant == 0:
        value = 0.0
    elif significant > 18:   # mant has wrapped
        return 0.0, i, 1
    elif mant <= _FAST_MANTISSA and -22 <= e10 <= 22:
        value = float(mant) * _P10[e10] if e10 >= 0 else float(mant) / _P10[-e10]
    else:
        value, ok = _eisel_lemire(mant, e10)
        if not ok:
            return 0.0, i, 1
    return (-value if neg else value), i, 0


@nb.njit(**_JIT)
def _grow_rows(a, rows):
    """``a`` with room for at least ``rows`` rows (doubling), the first rows kept."""
    b = np.empty((max(rows, 2 * a.shape[0]), a.shape[1]), dtype=a.dtype)
    b[:a.shape[0]] = a
    return b


@nb.njit(inline="always", **_JIT)
def _coordinate(data, i, n, joins):
    """The next number of a vertex line: ``(value, start, end, status)``; status FEW_COORDS at
    the end of the line, BAD_NUMBER, OK (value exact) or -1 (a slow token)."""
    i = _skip_blanks(data, i, n, joins)
    if i >= n or data[i] == _NL:
        return 0.0, i, i, FEW_COORDS
    value, end, status = parse_number(data, i, n)
    if status == 2 or not _token_end(data, end, n, joins):
        return 0.0, i, end, BAD_NUMBER
    return value, i, end, (OK if status == 0 else -1)


#: the keywords, most frequent first, as one byte array; _KW_CODES[k] is the code of the k-th
_KW_TEXT = (b"vertex", b"facet", b"outer", b"endloop", b"endfacet", b"solid", b"endsolid")
_KW_CODES = np.array([_KW_VERTEX, _KW_FACET, _KW_OUTER, _KW_ENDLOOP, _KW_ENDFACET, _KW_SOLID, _KW_ENDSOLID])
_KW_BYTES = np.frombuffer(b"".join(_KW_TEXT), dtype=np.uint8)
_KW_START = np.cumsum([0] + [len(w) for w in _KW_TEXT])


@nb.njit(inline="always", **_JIT)
def _stl_keyword(data, i, j):
    """The ASCII STL keyword spelled (in any case) by ``data[i:j]``."""
    for k in range(_KW_CODES.shape[0]):
        s = _KW_START[k]
        if j - i == _KW_START[k + 1] - s:
            same = True
            for m in range(j - i):
                if (data[i + m] | 32) != _KW_BYTES[s + m]:
                    same = False
                    break
            if same:
                return _KW_CODES[k]
    return _KW_OTHER


#: the recently read corners an ASCII STL reader remembers (a direct-mapped table: 2**14 slots)
RECENT_BITS = 14
_K1, _K2, _K3 = np.uint64(0x9E3779B97F4A7C15), np.uint64(0xC2B2AE3D27D4EB4F), np.uint64(0x165667B19E3779F9)


@nb.njit(inline="always", **_JIT)
def _slot(a, b, c, shift):
    """Multiplicative hash of three 64-bit words: the high bits of the mixed products."""
    h = (a * _K1) ^ (b * _K2) ^ (c * _K3)
    return (h ^ (h >> np.uint64(29))) >> shift


# One kernel kept whole (90 lines): a flat loop over the lines is 5x faster than the same
# grammar split into functions that pass the output arrays around.
@nb.njit(**_JIT)
def read_ascii_stl(raw, out, faces, state):
    """Read the facets of an ASCII STL (or of a run of its lines) into ``out`` and ``faces``.

    A corner equal (as floats) to one of the recently read corners (a table of 2**14 slots
    by hash) is not stored again: its facet points at the earlier row.  STL repeats each
    vertex for every facet around it, mostly in nearby facets, so ``out`` holds about a
    sixth of the corners, in the order of their first appearance; welding it gives exactly
    what welding the corners as listed gives.  A corner with a number left for strtod is
    always stored.  ``state``: where the text starts, 0 outside a solid, 1 in a solid
    between facets (a chunk that starts at a ``facet`` line).  Returns ``(out, nv, faces,
    nf, slow, status, where, detail, state, last)``: ``out`` and ``faces`` (new arrays when
    they had to grow) hold ``nv`` vertices and ``nf`` facets; ``slow`` rows are ``(start,
    end, flat index into out)`` of numbers left for strtod; on an error, ``status``, the
    offset ``where`` of its line and its ``detail``; ``state`` where the text ends, and
    ``last`` the offset of the last line with a keyword.  Grammar: :mod:`._text_reference`.
    """
    data = _borrowed(raw)
    n = data.shape[0]
    slow = np.empty((16, 3), dtype=np.int64)
    recent = np.full(1 << RECENT_BITS, -1, dtype=np.int64)
    shift = np.uint64(64 - RECENT_BITS)   # the product's high bits: the low ones of round numbers are 0
    word = np.empty(3)
    bits = word.view(np.uint64)
    nv = nf = ns = 0
    fv = 0             # vertices of the open facet (state 2)
    i = 0
    last = 0
    while i < n:
        line = i
        i = _skip_blanks(data, i, n, False)
        if i >= n:
            break
        if data[i] == _NL:
            i += 1
            continue
        j = i
        while not _token_end(data, j, n, False):
            j += 1
        kw = _stl_keyword(data, i, j)
        last = line
        if kw == _KW_VERTEX:
            if state != 2 or fv >= 3:
                return out, nv, faces, nf, slow[:ns], (UNEXPECTED if state != 2 else FACET_SIZE), line, \
                    (state if state != 2 else fv + 1), state, last
            if nv == out.shape[0]:
                out = _grow_rows(out, nv + 1)
            if nf == faces.shape[0]:
                faces = _grow_rows(faces, nf + 1)
            i = j
            exact = True
            for k in range(3):
                value, start, i, status = _coordinate(data, i, n, False)
                if status > 0:
                    return out, nv, faces, nf, slow[:ns], status, line, (k if status == FEW_COORDS else start), \
                        state, last
                if status < 0:
                    exact = False
                    if ns == slow.shape[0]:
                        slow = _grow_rows(slow, ns + 1)
                    slow[ns, 0] = start
                    slow[ns, 1] = i
                    slow[ns, 2] = 3 * nv + k
                    ns += 1
                out[nv, k] = value
                word[k] = value + 0.0   # -0.0 hashes as 0.0 (they are equal)
            i = _skip_blanks(data, i, n, False)
            if i < n and data[i] != _NL:
                return out, nv, faces, nf, slow[:ns], EXTRA_TOKENS, line, i, state, last
            slot = _slot(bits[0], bits[1], bits[2], shift)
            r = recent[slot]
            if exact and r >= 0 and out[r, 0] == word[0] and out[r, 1] == word[1] and out[r, 2] == word[2]:
                faces[nf, fv] = r
            else:
                if exact:
                    recent[slot] = nv
                faces[nf, fv] = nv
                nv += 1
            fv += 1
            continue
        if kw == _KW_FACET and state == 1:
            state = 2
            fv = 0
        elif kw == _KW_ENDFACET and state == 2 and fv == 3:
            state = 1
            nf += 1
        elif ((kw == _KW_OUTER or kw == _KW_ENDLOOP) and state == 2) or (kw == _KW_SOLID and state == 0):
            state = max(state, 1)
        elif kw == _KW_ENDSOLID and state == 1:
            state = 0
        else:
            bad_size = kw == _KW_ENDFACET and state == 2
            return out, nv, faces, nf, slow[:ns], (FACET_SIZE if bad_size else UNEXPECTED), line, \
                (fv if bad_size else state), state, last
        i = _end_of_line(data, j, n, False) + 1
    return out, nv, faces, nf, slow[:ns], OK, 0, 0, state, last


@nb.njit(inline="always", **_JIT)
def _index(data, i, n):
    """``(value, end)`` of the signed integer at ``i`` (``end == i``: none; values capped at 2**62)."""
    neg = False
    j = i
    if j < n and (data[j] == 45 or data[j] == 43):
        neg = data[j] == 45
        j += 1
    v = 0
    k = j
    while k < n and _digit(data[k]):
        if v < 2**62:
            v = v * 10 + (data[k] - 48)
        k += 1
    if k == j:
        return 0, i
    return (-v if neg else v), k


@nb.njit(inline="always", **_JIT)
def _face_ref(data, i, n, nv, limit):
    """One ``v``, ``v/vt``, ``v/vt/vn`` or ``v//vn`` reference at ``i``.

    Returns ``(vertex index (0-based), end, status)``; negative indices count back from the
    ``nv`` vertices read so far; ``limit >= 0``: positive indices above it are out of range.
    """
    value, j = _index(data, i, n)
    if j == i:
        return 0, i, BAD_REF
    zero = value == 0
    for _ in range(2):
        if j >= n or data[j] != _SLASH:
            break
        j += 1
        other, k = _index(data, j, n)
        zero = zero or (k != j and other == 0)
        j = k
    if not _token_end(data, j, n, True) and data[j] != _HASH:
        return 0, i, BAD_REF
    if zero:
        return 0, i, ZERO_INDEX
    if value < 0:
        value = nv + value
        if value < 0:
            return 0, i, INDEX_RANGE
        return value, j, OK
    if limit >= 0 and value > limit:
        return 0, i, INDEX_RANGE
    return value - 1, j, OK


@nb.njit(inline="always", **_JIT)
def _obj_keyword(data, i, n):
    """118 (v), 102 (f) or 0: the keyword of the line whose first word is at ``i``."""
    if i < n and (data[i] == 118 or data[i] == 102) and _token_end(data, i + 1, n, True):
        return data[i]
    return 0


@nb.njit(**_JIT)
def _obj_sizes(raw):
    """Upper bounds of the vertices and triangles of an OBJ: its v lines, and the words of
    each f line (before a comment) minus two."""
    data = _borrowed(raw)
    n = data.shape[0]
    nv = nt = 0
    i = 0
    while i < n:
        i = _skip_blanks(data, i, n, True)
        kw = _obj_keyword(data, i, n)
        if kw == 118:
            nv += 1
        elif kw == 102:
            words = 0
            i += 1
            while True:
                i = _skip_blanks(data, i, n, True)
                if i >= n or data[i] == _NL or data[i] == _HASH:
                    break
                words += 1
                while not _token_end(data, i, n, True) and data[i] != _HASH:
                    i += 1
            nt += max(0, words - 2)
        i = _end_of_line(data, i, n, True) + 1
    return nv, nt


# One kernel kept whole (84 lines), for the reason given above read_ascii_stl.
@nb.njit(**_JIT)
def read_obj(raw, limit):
    """Vertices and triangles of an OBJ: ``(vertices, faces, slow, largest, status, line_offset,
    detail, quads)`` (``quads``: the first of the two triangles of each quadrilateral).

    Grammar: :mod:`._text_reference`.  ``largest``: the largest vertex index + 1 of the faces
    (a face may name a vertex defined further down); ``limit >= 0`` refuses positive indices
    above it (the caller's second pass, to find the line of an index beyond the last vertex).
    """
    data = _borrowed(raw)
    n = data.shape[0]
    cap_v, cap_t = _obj_sizes(data)
    verts = np.empty((cap_v, 3))
    faces = np.empty((cap_t, 3), dtype=np.int64)
    slow = np.empty((16, 3), dtype=np.int64)
    quads = np.empty(cap_t, dtype=np.int64)
    nv = nf = ns = nq = 0
    largest = 0
    i = 0
    while i < n:
        line = i
        i = _skip_blanks(data, i, n, True)
        kw = _obj_keyword(data, i, n)
        if kw == 118 and nv < cap_v:
            i += 1
            for k in range(3):
                value, start, i, status = _coordinate(data, i, n, True)
                if status > 0:
                    return verts[:nv], faces[:nf], slow[:ns], largest, status, line, \
                        (k if status == FEW_COORDS else start), quads[:nq]
                if status < 0:
                    if ns == slow.shape[0]:
                        slow = _grow_rows(slow, ns + 1)
                    slow[ns, 0] = start
                    slow[ns, 1] = i
                    slow[ns, 2] = 3 * nv + k
                    ns += 1
                verts[nv, k] = value
            nv += 1
        elif kw == 102:
            first = second = -1
            count = 0
            start_face = nf
            i += 1
            while True:
                i = _skip_blanks(data, i, n, True)
                if i >= n or data[i] == _NL or data[i] == _HASH:
                    break
                idx, end, status = _face_ref(data, i, n, nv, limit)
                if status != OK:
                    return verts[:nv], faces[:nf], slow[:ns], largest, status, line, i, quads[:nq]
                i = end
                largest = max(largest, idx + 1)
                if count == 0:
                    first = idx
                elif count >= 2 and nf < cap_t:
                    faces[nf, 0] = first
                    faces[nf, 1] = second
                    faces[nf, 2] = idx
                    nf += 1
                second = idx
                count += 1
            if count < 3:
                return verts[:nv], faces[:nf], slow[:ns], largest, FEW_REFS, line, count, quads[:nq]
            if count == 4:
                quads[nq] = start_face
                nq += 1
        i = _end_of_line(data, i, n, True) + 1
    return verts[:nv], faces[:nf], slow[:ns], largest, OK, 0, 0, quads[:nq]


@nb.njit(**_JIT)
def gather_tokens(raw, slow):
    """The slow tokens' bytes, space-separated, in one buffer (for NumPy's strtod)."""
    data = _borrowed(raw)
    total = 0
    for r in range(slow.shape[0]):
        total += slow[r, 1] - slow[r, 0] + 1
    buf = np.empty(total, dtype=np.uint8)
    p = 0
    for r in range(slow.shape[0]):
        for k in range(slow[r, 0], slow[r, 1]):
            buf[p] = data[k]
            p += 1
        buf[p] = 32
        p += 1
    return buf
