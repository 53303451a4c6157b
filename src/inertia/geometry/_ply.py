"""PLY files (ASCII, binary of either byte order): the vertices' x, y, z and the faces' vertex lists.

Read with NumPy (no dependency).  Anything malformed is refused by a MeshFileError naming the
header line, or the element, its row and (ASCII) the line of the file.  A polygon is fanned
from its first vertex, as trimesh does; other elements are read past and left out.
"""

from __future__ import annotations

import itertools
import re
import struct

import numpy as np

from .._core.errors import MeshFileError
from ._text_readers import utf8_text

_TYPES = {"char": "i1", "uchar": "u1", "short": "i2", "ushort": "u2", "int": "i4", "uint": "u4", "float": "f4",
          "double": "f8", "int8": "i1", "uint8": "u1", "int16": "i2", "uint16": "u2", "int32": "i4",
          "uint32": "u4", "float32": "f4", "float64": "f8"}
_ORDERS = {b"ascii": "", b"binary_little_endian": "<", b"binary_big_endian": ">"}
#: names of the faces' vertex list (exporters use both)
FACE_LISTS = ("vertex_indices", "vertex_index")


class _Element:
    def __init__(self, name: str, count: int, line: int):
        self.name, self.count, self.line = name, count, line
        self.props: list = []       # (name, numpy type, count type or None)

    def where(self, row: int) -> str:
        return f"element {self.name!r}, row {row + 1} of {self.count}"


def read_ply(data, path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and triangles (F, 3) int64 of the bytes of a PLY file."""
    data = bytes(utf8_text(data, path, "PLY"))
    order, elements, start, n_lines = _header(data, path)
    if order:
        vertices, lists = _binary_body(data, start, elements, order, path)
    else:
        vertices, lists = _ascii_body(data, start, elements, path, n_lines)
    if vertices is None:
        raise MeshFileError(f"{path}: malformed PLY: the header declares no vertex element", code="malformed")
    return vertices, _fan(*lists, len(vertices), path) if lists else np.zeros((0, 3), np.int64)


def _header(data: bytes, path):
    """``(byte order: "" for ASCII, elements, offset of the body, header lines)``."""
    order, elements, pos, n = None, [], 0, 0
    while True:
        end = data.find(b"\n", pos)
        if end < 0:
            raise MeshFileError(f"{path}: malformed PLY: the header has no end_header line (truncated?)",
                                code="malformed")
        n, line, pos = n + 1, data[pos:end].strip(), end + 1
        words = line.split()

        def bad(what):
            text = line.decode("utf-8", "replace")[:80]
            return MeshFileError(f"{path}, line {n}: malformed PLY header: {what} in {text!r}", code="malformed")

        if n == 1:
            if line != b"ply":
                raise MeshFileError(f"{path}: malformed PLY: the file does not start with the line 'ply'",
                                    code="malformed")
            continue
        key = words[0] if words else b""
        if key in (b"comment", b"obj_info", b""):
            continue
        if key == b"end_header":
            break
        if key == b"format":
            if len(words) != 3 or words[1] not in _ORDERS:
                raise bad("the format must read 'format ascii|binary_little_endian|binary_big_endian 1.0'")
            order = _ORDERS[words[1]]
        elif key == b"element":
            if len(words) != 3 or not words[2].isdigit():
                raise bad("an element needs a name and a count ('element vertex 8')")
            if any(e.name == words[1].decode("utf-8", "replace") for e in elements):
                raise bad("a second element of this name")
            elements.append(_Element(words[1].decode("utf-8", "replace"), int(words[2]), n))
        elif key == b"property":
            if not elements:
                raise bad("a property before any element")
            prop = _property(words, bad)
            if any(prop[0] == name for name, _, _ in elements[-1].props):
                raise bad(f"a second property {prop[0]!r} in element {elements[-1].name!r}")
            elements[-1].props.append(prop)
        else:
            raise bad(f"unknown keyword {key.decode('utf-8', 'replace')!r}")
    if order is None:
        raise MeshFileError(f"{path}: malformed PLY: the header has no format line", code="malformed")
    vertex = next((e for e in elements if e.name == "vertex"), None)
    for c in "xyz" if vertex is not None else ():
        if not any(name == c and ct is None for name, _, ct in vertex.props):
            raise MeshFileError(f"{path}, line {vertex.line}: malformed PLY header: element 'vertex' has no "
                                f"property {c!r}", code="malformed")
    return order, elements, pos, n


def _property(words, bad):
    text = [w.decode("utf-8", "replace") for w in words]
    if len(words) == 3 and text[1] in _TYPES:
        return text[2], _TYPES[text[1]], None
    if len(words) == 5 and text[1] == "list" and text[3] in _TYPES and _TYPES.get(text[2], "f")[0] in "iu":
        return text[4], _TYPES[text[3]], _TYPES[text[2]]
    raise bad("a property reads 'property TYPE NAME' or 'property list COUNT_TYPE TYPE NAME' "
              f"(types: {', '.join(_TYPES)})")


def _face_list(el: _Element, path):
    """Index of the faces' vertex-list property of element ``el`` (``face``)."""
    lists = [i for i, (_, _, ct) in enumerate(el.props) if ct is not None]
    named = [i for i in lists if el.props[i][0] in FACE_LISTS]
    if named or len(lists) == 1:
        return (named or lists)[0]
    raise MeshFileError(f"{path}, line {el.line}: malformed PLY header: element 'face' has no vertex list "
                        f"({' or '.join(FACE_LISTS)})", code="malformed")


# --------------------------------------------------------------------------------- ASCII
def _ascii_body(data: bytes, start: int, elements, path, n_header: int):
    """``(vertices (V, 3), faces' (flat indices, counts, element) or None)`` of an ASCII body."""
    tokens = data[start:].split()
    at, vertices, lists = 0, None, None

    def bad(i, el, row, what):
        found = next(itertools.islice(re.finditer(rb"\S+", data[start:]), i, None), None)
        line = n_header + 1 + data.count(b"\n", start, start + found.start() if found else len(data))
        return MeshFileError(f"{path}, line {line}: malformed PLY: {el.where(row)}: {what}", code="malformed")

    for el in elements:
        width = _row_width(tokens, at, el)
        if width is None:       # lists of varying length, or too few values: row by row
            starts, at = _walk(tokens, at, el, bad)
        else:
            starts, at = at + width * np.arange(el.count), at + width * el.count
        if el.name not in ("vertex", "face") or not el.props:
            continue
        pos, counts = starts, {}
        places = {}
        for name, _, ct in el.props:       # each property's token per row
            places[name] = pos
            counts[name] = np.array([int(tokens[p]) for p in pos], np.int64) if ct else 0
            pos = pos + 1 + counts[name]
        rows = np.arange(el.count)
        if el.name == "vertex":
            vertices = np.stack([_numbers(tokens, places[c], rows, np.float64, el, bad) for c in "xyz"], 1)
        else:
            name = el.props[_face_list(el, path)][0]
            k = counts[name]
            first = np.cumsum(k) - k
            idx = np.repeat(places[name] + 1 - first, k) + np.arange(int(k.sum()))
            lists = (_numbers(tokens, idx, np.repeat(rows, k), np.int64, el, bad), k, el)
    if at < len(tokens):
        if not elements:
            raise MeshFileError(f"{path}: malformed PLY: the header declares no element", code="malformed")
        el = elements[-1]
        raise bad(at, el, el.count - 1, f"values after the last row ({tokens[at][:40].decode('utf-8', 'replace')!r} "
                                        "first): the header's counts do not match the data")
    return vertices, lists


def _row_width(tokens, at: int, el: _Element):
    """The number of values in each row of ``el`` when every list has its length in the first row
    (checked at each row's count) and the values suffice, else None."""
    width, counts = 0, []
    for _, _, ct in el.props:
        if ct is not None:
            if at + width >= len(tokens) or not tokens[at + width].isdigit():
                return None
            counts.append((width, tokens[at + width]))
            width += int(tokens[at + width])
        width += 1
    if at + width * el.count > len(tokens):
        return None
    for pos, tok in counts:
        if any(t != tok for t in tokens[at + pos:at + pos + el.count * width:width]):
            return None
    return width


def _walk(tokens, at: int, el: _Element, bad):
    """``(row starts (token indices), the index after the last row)`` of ``el``, row by row."""
    starts = np.empty(el.count, np.int64)
    for row in range(el.count):
        starts[row] = at
        for name, _, ct in el.props:
            if at >= len(tokens):
                raise bad(at, el, row, f"the file ends before {name!r} (truncated, or fewer values than the header "
                                       "declares)")
            if ct is not None:
                if not tokens[at].isdigit():
                    raise bad(at, el, row, f"the length of list {name!r} must be a count, got "
                                           f"{tokens[at][:40].decode('utf-8', 'replace')!r}")
                at += int(tokens[at])
            at += 1
    if at > len(tokens):
        raise bad(len(tokens), el, el.count - 1, "the file ends inside the last row (truncated?)")
    return starts, at


def _numbers(tokens, idx, rows, dtype, el, bad):
    """The tokens at ``idx`` (rows ``rows`` of ``el``) as ``dtype``; MeshFileError at the first bad one."""
    words = [tokens[i] for i in idx]
    try:
        return np.asarray(words, dtype=np.bytes_).astype(dtype) if words else np.zeros(0, dtype)
    except (ValueError, OverflowError):
        for j, w in enumerate(words):
            try:
                np.asarray([w]).astype(dtype)
            except (ValueError, OverflowError):
                kind = "an integer" if dtype == np.int64 else "a number"
                raise bad(int(idx[j]), el, int(rows[j]), f"{w[:40].decode('utf-8', 'replace')!r} is not {kind}") \
                    from None
        raise


# --------------------------------------------------------------------------------- binary
_STRUCT = {"i1": "b", "u1": "B", "i2": "h", "u2": "H", "i4": "i", "u4": "I"}


def _binary_body(data: bytes, start: int, elements, order: str, path):
    """``(vertices (V, 3), faces' (flat indices, counts, element) or None)`` of a binary body."""
    at, vertices, lists = start, None, None
    for el in elements:
        values, at = _binary_rows(data, at, el, order, path)
        if el.name == "vertex":
            vertices = np.stack([values[c].astype(np.float64) for c in "xyz"], 1)
        elif el.name == "face" and el.props:
            flat, counts = values[el.props[_face_list(el, path)][0]]
            if flat.dtype.kind == "f" and not np.all(flat == np.round(flat)):
                row = int(np.searchsorted(np.cumsum(counts), np.argmax(flat != np.round(flat)), side="right"))
                raise MeshFileError(f"{path}: malformed binary PLY: {el.where(row)}: a vertex index is not an "
                                    "integer", code="malformed")
            lists = (flat.astype(np.int64), counts, el)
    if at != len(data):
        raise MeshFileError(f"{path}: malformed binary PLY: its elements take {at - start} bytes after the header, "
                            f"the file holds {len(data) - start} (truncated, or the header's counts are wrong)",
                            code="malformed")
    return vertices, lists


def _binary_rows(data: bytes, at: int, el: _Element, order: str, path):
    """``({property: values (n,), or (flat values, counts) for a list}, the offset after ``el``)``."""
    def short(row):
        return MeshFileError(f"{path}: malformed binary PLY: {el.where(row)}: the file ends inside it "
                             "(truncated, or the header's counts are wrong)", code="malformed")

    fields = []
    for i, (name, t, ct) in enumerate(el.props):     # a row's layout, with the first row's list lengths
        if ct is None:
            fields.append((name, order + t))
            continue
        pos = at + np.dtype(fields).itemsize if fields else at
        if el.count and pos + int(ct[1]) > len(data):
            raise short(0)
        k = int(np.frombuffer(data, order + ct, 1, pos)[0]) if el.count else 0
        fields += [(f"#{i}", order + ct), (name, order + t, (k,))]
    dt = np.dtype(fields) if fields else np.dtype([])
    end = at + el.count * dt.itemsize
    if end <= len(data):
        rows = np.frombuffer(data, dt, el.count, at)
        lists = [(i, name) for i, (name, _, ct) in enumerate(el.props) if ct]
        if all(np.all(rows[f"#{i}"] == rows[f"#{i}"][:1]) for i, _ in lists):
            out = {name: rows[name] for name, _, _ in el.props}
            for i, name in lists:
                out[name] = (out[name].ravel(), np.full(el.count, out[name].shape[1], np.int64))
            return out, end
    out = {name: ([], []) for name, _, _ in el.props}     # lists of varying length: row by row
    for row in range(el.count):
        for name, t, ct in el.props:
            k = 1
            if ct is not None:
                if at + int(ct[1]) > len(data):
                    raise short(row)
                k = struct.unpack_from(order + _STRUCT[ct], data, at)[0]
                at += int(ct[1])
            if at + k * int(t[1]) > len(data):
                raise short(row)
            out[name][0].append(np.frombuffer(data, order + t, k, at))
            out[name][1].append(k)
            at += k * int(t[1])
    values = {name: np.concatenate(v) if v else np.zeros(0, t) for (name, t, _), (v, _) in zip(el.props, out.values())}
    return {name: (values[name], np.array(out[name][1], np.int64)) if ct else values[name]
            for name, _, ct in el.props}, at


# --------------------------------------------------------------------------------- faces
def _fan(flat, counts, el: _Element, n_vertices: int, path):
    """Triangles (F, 3) of the polygons ``flat`` (vertex indices, ``counts`` per polygon), each
    fanned from its first vertex; MeshFileError naming the row of a polygon that is not one."""
    bad = np.flatnonzero(counts < 3)
    if len(bad):
        raise MeshFileError(f"{path}: malformed PLY: {el.where(int(bad[0]))}: a face needs at least 3 vertices, "
                            f"this one has {int(counts[bad[0]])}", code="malformed")
    out = (flat < 0) | (flat >= n_vertices)
    if out.any():
        j = int(np.argmax(out))
        row = int(np.searchsorted(np.cumsum(counts), j, side="right"))
        raise MeshFileError(f"{path}: malformed PLY: {el.where(row)}: vertex index {int(flat[j])} is outside "
                            f"0..{n_vertices - 1} ({n_vertices} vertices)", code="malformed")
    n_tri = counts - 2
    poly = np.repeat(np.arange(len(counts)), n_tri)
    k = np.arange(int(n_tri.sum())) - np.repeat(np.cumsum(n_tri) - n_tri, n_tri)
    base = (np.cumsum(counts) - counts)[poly]
    return np.stack([flat[base], flat[base + k + 1], flat[base + k + 2]], 1)
