"""Text mesh files: ASCII STL and OBJ read by the compiled readers of :mod:`inertia._ext.text`
(their grammar is written out in ``src/ext/text/``), and the encodings a text file comes in.

The readers give the arrays trimesh gives for the same file (its OBJ reader counts negative
indices from the end of the file, we from the line, as the OBJ specification says; it splits an
OBJ by material, we keep the file's order) and refuse a malformed file with a
:class:`~inertia.errors.MeshFileError` naming file, line and text.

A text file starting with a byte-order mark, or written in UTF-16 or UTF-32 (told by its mark
or by the zero bytes of its first character), is read as the same text in UTF-8; any other
byte (Latin-1 in a comment or a name) is read as it is: the grammars are ASCII.  OFF and
glTF, read by trimesh, are given to it in UTF-8 (:func:`utf8_for_trimesh`).
"""

from __future__ import annotations

import numpy as np

from .._core.errors import MeshFileError
from .._ext import text as _k

__all__ = ["read_text_mesh", "read_ascii_stl", "read_obj", "text_encoding", "utf8_head", "utf8_for_trimesh"]

# the error kinds of the compiled readers (src/ext/text/lexer.hpp)
BAD_NUMBER, FEW_COORDS, EXTRA_TOKENS, UNEXPECTED, FACET_SIZE, TRUNCATED = 1, 2, 3, 4, 5, 6
BAD_REF, ZERO_INDEX, FEW_REFS, INDEX_RANGE = 7, 8, 9, 10
#: where an ASCII STL keyword was found (the ``count`` of an UNEXPECTED or TRUNCATED error)
STL_PLACES = ("outside a solid", "inside a solid, outside a facet", "inside a facet")


def read_text_mesh(data: np.ndarray, path, ext: str, polygons: str = "fan") -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and faces (F, 3) int64 of the bytes ``data`` (uint8) of an ASCII STL
    (``ext`` ".stl") or OBJ file, in any of the encodings of :func:`text_encoding`."""
    fmt = "OBJ" if ext == ".obj" else "ASCII STL"
    text = utf8_text(data, path, fmt)
    return read_obj(text, path, polygons) if ext == ".obj" else read_ascii_stl(text, path)


def read_ascii_stl(data: np.ndarray, path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and faces (F, 3) int64 of ASCII STL bytes (uint8): ``vertices[faces]``
    are the file's facets, corner for corner (a corner repeating one read shortly before is
    stored once: the same surface, and after welding the same arrays)."""
    return _checked(_k.read_ascii_stl(data), data, path, "ASCII STL")


def read_obj(data: np.ndarray, path, polygons: str = "fan") -> tuple[np.ndarray, np.ndarray]:
    """Vertices (V, 3) float64 and triangles (F, 3) int64 (0-based) of OBJ bytes (uint8), polygons
    made triangles as ``polygons`` says (:func:`~inertia.geometry.mesh_io.load_mesh`)."""
    return _checked(_k.read_obj(data, ("fan", "shorter", "mujoco").index(polygons)), data, path, "OBJ")


def _checked(result, data: np.ndarray, path, fmt: str):
    """The arrays of a compiled reader's ``result``, or its error (kind, line number, start and
    end of the line, start and end of the offending word, a count) raised as MeshFileError."""
    vertices, faces, error = result
    if error is not None:
        kind, line, start, end, token_start, token_end, count = error
        text = bytes(data[start:min(end, start + 4096)])
        token = bytes(data[token_start:min(token_end, token_start + 4096)])
        raise MeshFileError(error_message(path, fmt, kind, line, text, token, count), code="malformed")
    return vertices, faces


def error_message(path, fmt: str, kind: int, line: int, text: bytes, token: bytes, count: int) -> str:
    """``PATH, line N: malformed FMT: ...`` for an error of ``kind`` on ``line`` (whose ``text``
    is given), about ``token`` (or b"") and ``count`` (see the kinds above)."""
    text = text.strip().decode("utf-8", "replace")[:80]
    token = token.decode("utf-8", "replace")[:40]
    where = f"{path}, line {line}"
    if kind == ZERO_INDEX:   # worded as before the native reader (tests, users' scripts)
        return (f"{where}: face index 0 in {text!r}: OBJ vertex indices start at 1 "
                "(negative indices count back from the last vertex)")
    what = {
        BAD_NUMBER: f"malformed number {token!r}",
        FEW_COORDS: f"a vertex needs 3 coordinates, this one has {count}",
        EXTRA_TOKENS: f"unexpected {token!r} after the 3 coordinates of a vertex",
        UNEXPECTED: f"unexpected {token!r} {STL_PLACES[count % 3]}",
        FACET_SIZE: f"a facet with {count} vertices (facets are triangles)",
        TRUNCATED: f"the file ends {STL_PLACES[count % 3]} (no endsolid: truncated?)",
        BAD_REF: f"malformed face vertex {token!r} (v, v/vt, v/vt/vn or v//vn)",
        FEW_REFS: f"a face needs at least 3 vertices, this one has {count}",
        INDEX_RANGE: f"face vertex {token!r} names no vertex ({count} defined "
                     f"{'above it' if token.startswith('-') else 'in the file'})",
    }[kind]
    return f"{where}: malformed {fmt}: {what} in {text!r}"


# ---------------------------------------------------------------- encodings
#: byte-order marks, UTF-32's first (UTF-32 LE's starts as UTF-16 LE's)
_BOMS = ((b"\x00\x00\xfe\xff", "utf-32-be"), (b"\xff\xfe\x00\x00", "utf-32-le"), (b"\xef\xbb\xbf", "utf-8"),
         (b"\xff\xfe", "utf-16-le"), (b"\xfe\xff", "utf-16-be"))
#: the zero bytes of an ASCII character in UTF-32 and UTF-16 without a mark
_ZEROS = {(False, True, True, True): "utf-32-le", (True, True, True, False): "utf-32-be",
          (False, True): "utf-16-le", (True, False): "utf-16-be"}


def text_encoding(head: bytes) -> tuple[str, int]:
    """``(codec, length of the byte-order mark)`` of text starting with ``head`` (4 bytes or
    more): its byte-order mark, else UTF-32 or UTF-16 when its first character (ASCII in every
    mesh format) has their zero bytes, else UTF-8."""
    for bom, codec in _BOMS:
        if head.startswith(bom):
            return codec, len(bom)
    zeros = tuple(b == 0 for b in head[:4])
    return _ZEROS.get(zeros) or _ZEROS.get(zeros[:2], "utf-8"), 0


def utf8_head(head: bytes) -> bytes:
    """The first bytes of a file as UTF-8 text, for telling what the file is (no error)."""
    codec, bom = text_encoding(head)
    return head[bom:] if codec == "utf-8" else head[bom:].decode(codec, "ignore").encode("utf-8")


def utf8_text(data, path, fmt: str):
    """``data`` (bytes, or a uint8 array) as UTF-8 text of the same type: a UTF-8 byte-order mark
    skipped, UTF-16 and UTF-32 decoded; MeshFileError naming the encoding when they do not decode."""
    codec, bom = text_encoding(bytes(data[:4]))
    if codec == "utf-8":
        return data[bom:]
    try:
        text = bytes(data[bom:]).decode(codec).encode("utf-8")
    except UnicodeDecodeError as exc:
        raise MeshFileError(f"{path}: malformed {fmt}: the file starts as {codec.upper()} text but byte "
                            f"{bom + exc.start} does not decode ({exc.reason})", code="malformed") from None
    return np.frombuffer(text, dtype=np.uint8) if isinstance(data, np.ndarray) else text


def utf8_for_trimesh(data: bytes, path, ext: str) -> bytes:
    """The bytes of an OFF or glTF file as trimesh can read them: UTF-8 (:func:`utf8_text`), with
    bytes that are not UTF-8 (Latin-1 in a comment or a name) decoded as Latin-1."""
    text = utf8_text(data, path, ext[1:].upper().replace("GLTF", "glTF"))
    try:
        text.decode("utf-8")
    except UnicodeDecodeError:   # Latin-1 (every byte is a character), which trimesh's parsers refuse
        return text.decode("latin-1").encode("utf-8")
    return text
