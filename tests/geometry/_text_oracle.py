"""The grammar of ASCII STL and OBJ, read line by line in plain Python: a test oracle.

The compiled readers (``src/ext/text/``) scan bytes and read numbers by Clinger's fast path
or ``std::from_chars``; this reads the same grammar with ``bytes.split`` and Python's
``float()``, a second method.  The tests compare the two on valid and mutated files: the
same arrays, or the same :class:`TextError` (kind, line, token, count).

Lines end at LF (a CR before it is a separator like space, tab, VT and FF).  Numbers are
decimal (``[+-]digits[.digits][e[+-]digits]``, ``.5`` and ``5.`` included) or ``nan``,
``inf``, ``infinity`` in any case, read correctly rounded (as ``strtod``).

ASCII STL, keywords in any case, one per line; what follows ``solid``, ``facet``,
``outer``, ``endloop``, ``endfacet`` and ``endsolid`` on their line is not read (names,
normals)::

    solid NAME
      facet normal nx ny nz
        outer loop
          vertex x y z      (three per facet, nothing after the coordinates)
        endloop
      endfacet
    endsolid NAME           (then another solid, or the end of the file)

OBJ: ``v x y z [...]`` (the first three numbers; w or colours are not read) and ``f`` lines
of at least three ``v``, ``v/vt``, ``v/vt/vn`` or ``v//vn`` references (1-based, or negative:
``-1`` is the last vertex defined above the line, as the OBJ specification says; texture
and normal indices are checked for syntax and for 0 only).  Polygons are fanned from their
first vertex.  A ``#`` ends a face line.  A backslash ending a line joins the next one.
Every other line (``vt``, ``vn``, ``o``, ``g``, ``usemtl``, ``s``, ``l``, comments ...) is
skipped.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

import numpy as np

# error kinds (src/ext/text/lexer.hpp numbers them alike)
OK, BAD_NUMBER, FEW_COORDS, EXTRA_TOKENS, UNEXPECTED, FACET_SIZE, TRUNCATED = 0, 1, 2, 3, 4, 5, 6
BAD_REF, ZERO_INDEX, FEW_REFS, INDEX_RANGE = 7, 8, 9, 10

#: where an ASCII STL keyword was found (the ``count`` of an UNEXPECTED or TRUNCATED error)
STL_PLACES = ("outside a solid", "inside a solid, outside a facet", "inside a facet")

_REF = re.compile(rb"([+-]?\d+)(?:/([+-]?\d+)?(?:/([+-]?\d+)?)?)?\Z")


@dataclass(frozen=True)
class TextError:
    """Where and why a text mesh file is malformed: ``line`` counts from 1; ``text`` is that
    physical line; ``token`` the offending word (or b""); ``count`` a number the kind needs
    (coordinates or references found, vertices in a facet, an STL place, vertices defined)."""

    kind: int
    line: int
    text: bytes
    token: bytes = b""
    count: int = 0


def logical_lines(data, joins: bool):
    """``(line number, first physical line, logical line)`` of ``data`` (bytes); with
    ``joins``, a backslash before the LF (or CR LF) joins the next line, read as a space."""
    if not joins or b"\\" not in data:   # no continuation: the lines as they are
        for number, line in enumerate(data.split(b"\n")[:data.count(b"\n") + (not data.endswith(b"\n"))], 1):
            yield number, line, line
        return
    n, start, number = len(data), 0, 1
    while start < n:
        end = _find_lf(data, start)
        first = line = data[start:end]
        first_number = number
        while joins and end < n and _continues(line):
            start, number = end + 1, number + 1
            end = _find_lf(data, start)
            line = _without_backslash(line) + b" " + data[start:end]
        yield first_number, first, line
        start, number = end + 1, number + 1


def _find_lf(data: bytes, start: int) -> int:
    end = data.find(b"\n", start)
    return len(data) if end < 0 else end


def _continues(line: bytes) -> bool:
    return line.endswith(b"\\") or line.endswith(b"\\\r")


def _without_backslash(line: bytes) -> bytes:
    return line[:-2] if line.endswith(b"\r") else line[:-1]


def _coordinates(tokens, number, first, out):
    """Append the first three numbers of ``tokens`` to ``out``; a TextError, or None."""
    for k in range(3):
        if k >= len(tokens):
            return TextError(FEW_COORDS, number, first, count=k)
        if b"_" in tokens[k]:   # float() reads the grammar's numbers, and digits with underscores
            return TextError(BAD_NUMBER, number, first, tokens[k])
        try:
            out.append(float(tokens[k]))
        except ValueError:
            return TextError(BAD_NUMBER, number, first, tokens[k])
    return None


def read_ascii_stl(data):
    """``(corners (3F, 3) float64, TextError or None)``: the grammar in the module docstring."""
    out: list[float] = []
    state, corners, last = 0, 0, (0, b"")
    for number, first, line in logical_lines(data, joins=False):
        tokens = line.split()
        if not tokens:
            continue
        kw = tokens[0].lower()
        last = (number, first)
        if kw == b"vertex":
            if state != 2:
                return _rows(out), TextError(UNEXPECTED, number, first, tokens[0], state)
            if corners >= 3:
                return _rows(out), TextError(FACET_SIZE, number, first, count=corners + 1)
            err = _coordinates(tokens[1:], number, first, out)
            if err is None and len(tokens) > 4:
                err = TextError(EXTRA_TOKENS, number, first, tokens[4])
            if err is not None:
                del out[len(out) - len(out) % 3:]
                return _rows(out), err
            corners += 1
        elif kw == b"facet" and state == 1:
            state, corners = 2, 0
        elif kw == b"endfacet" and state == 2:
            if corners != 3:
                return _rows(out), TextError(FACET_SIZE, number, first, count=corners)
            state = 1
        elif kw in (b"outer", b"endloop") and state == 2:
            pass
        elif (kw == b"solid" and state == 0) or (kw == b"endsolid" and state == 1):
            state = 1 - state
        else:
            return _rows(out), TextError(UNEXPECTED, number, first, tokens[0], state)
    if state != 0:
        return _rows(out), TextError(TRUNCATED, last[0], last[1], count=state)
    return _rows(out), None


def _rows(values) -> np.ndarray:
    return np.array(values, dtype=np.float64).reshape(-1, 3)


def _face(tokens, n_vertices: int, limit: int, number, first, out, quads=None):
    """Fan the references ``tokens`` into ``out`` (flat triples; the first triangle of each
    quadrilateral listed in ``quads``); a TextError, or None."""
    refs = []
    for tok in tokens:
        if tok.isdigit():   # the common case, a plain positive index
            v = int(tok)
            if v == 0:
                return TextError(ZERO_INDEX, number, first, tok)
        else:
            m = _REF.match(tok)
            if m is None:
                return TextError(BAD_REF, number, first, tok)
            if any(g is not None and int(g) == 0 for g in m.groups()):
                return TextError(ZERO_INDEX, number, first, tok)
            v = int(m.group(1))
        if v < 0:
            v += n_vertices
            if v < 0:
                return TextError(INDEX_RANGE, number, first, tok, n_vertices)
        elif 0 <= limit < v:
            return TextError(INDEX_RANGE, number, first, tok, limit)
        else:
            v -= 1
        refs.append(v)
    if len(refs) < 3:
        return TextError(FEW_REFS, number, first, count=len(refs))
    if len(refs) == 4 and quads is not None:
        quads.append(len(out) // 3)
    for k in range(1, len(refs) - 1):
        out += (refs[0], refs[k], refs[k + 1])
    return None


def read_obj(data, limit: int = -1):
    """``(vertices, faces, largest positive index, TextError or None, quads)``: the grammar in
    the module docstring; ``limit >= 0`` refuses positive indices above it; ``quads`` the index
    of the first of the two triangles of each quadrilateral."""
    coords: list[float] = []
    faces: list[int] = []
    quads: list[int] = []
    err = None
    for number, first, line in logical_lines(data, joins=True):
        tokens = line.split()
        if not tokens or tokens[0] not in (b"v", b"f"):
            continue
        if tokens[0] == b"v":
            err = _coordinates(tokens[1:], number, first, coords)
            if err is not None:
                del coords[len(coords) - len(coords) % 3:]
        else:
            head = line.split(b"#", 1)[0].split()
            err = _face(head[1:], len(coords) // 3, limit, number, first, faces, quads)
        if err is not None:
            break
    f = np.array(faces, dtype=np.int64).reshape(-1, 3)
    return _rows(coords), f, (int(f.max()) + 1 if len(f) else 0), err, np.array(quads, dtype=np.int64)
