"""Safe XML reading for robot files: no entities, no network, line numbers kept.

Robot descriptions come from anywhere, so the parser refuses what XML attacks use:

* entity declarations in a DOCTYPE (the "billion laughs" expansion bomb, and external
  entities that read local files or URLs), and any reference to an external entity;
* external DTDs are never fetched (expat does not load them, and we do not ask it to).

It keeps what tools need: every element's line number (``Document.line(element)``) and
the comments, so a file written back loses nothing but formatting inside tags.
Standard library only (pyexpat builds the ``xml.etree.ElementTree`` tree).
"""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from pathlib import Path
from xml.parsers import expat

from .._core.errors import RobotFileError
from .._core.files import MAX_ROBOT_FILE_BYTES, read_regular


class Document:
    """A parsed XML file: the root element, the source path and each element's line."""

    def __init__(self, root: ET.Element, path: Path, lines: dict, *, source: bytes = b"",
                 starts: dict | None = None, ends: dict | None = None):
        self.root = root
        self.path = path
        self._lines = lines
        # the source bytes and, per element of this file, where its start tag and its end tag
        # begin (byte offsets): what :mod:`inertia.robots.edit` changes in place
        self.source = source
        self._starts = starts or {}
        self._ends = ends or {}
        self._files: dict[int, Path] = {}  # elements merged in from other files (MJCF <include>)
        self.notes: list[str] = []

    def merge(self, other: "Document") -> None:
        """Adopt the line numbers of ``other``'s elements (they keep pointing into its file)."""
        for el in other.root.iter():
            if id(el) in other._lines:
                self._lines[id(el)] = other._lines[id(el)]
                self._files[id(el)] = other._files.get(id(el), other.path)

    def start_byte(self, element) -> int | None:
        """Byte offset of the element's ``<`` in :attr:`source` (None: not from this file)."""
        return self._starts.get(id(element))

    def end_byte(self, element) -> int | None:
        """Byte offset of the element's end tag ``</`` in :attr:`source` (an empty element:
        its start tag's)."""
        return self._ends.get(id(element))

    def line(self, element) -> int | None:
        """1-based line of the element's start tag in the source (None for new elements)."""
        return self._lines.get(id(element))

    def where(self, element) -> str:
        """``file:line`` for messages."""
        line = self.line(element)
        path = self._files.get(id(element), self.path)
        return f"{path}:{line}" if line else str(path)


def _refuse(path, parser, what: str):
    raise RobotFileError(f"{path}:{parser.CurrentLineNumber}: refused: {what}. Robot files need no entities; "
                         "this is how XML entity-expansion bombs and external-entity attacks work, so the file "
                         "is not read.")


def parse_xml(path) -> Document:
    """Parse ``path`` safely (see the module docstring); :class:`RobotFileError` on any problem."""
    path = Path(path)
    return parse_xml_bytes(read_robot_bytes(path), path)


def read_robot_bytes(path, what: str = "robot file") -> bytes:
    """The bytes of a robot file (or a file it includes) by the input-file rule
    (:func:`inertia._core.files.read_regular`: a regular file, at most MAX_ROBOT_FILE_BYTES)."""
    return read_regular(path, what=what, limit=MAX_ROBOT_FILE_BYTES, error=RobotFileError)


def _relocated_declaration(data: bytes) -> tuple[bytes, bool]:
    """Blank out an XML declaration after leading comments or blank lines (expat refuses it there).

    Some real files (e.g. Gazebo models with a license header) put ``<?xml ...?>`` after a
    comment.  The declaration is replaced by spaces of the same length, so line and column
    numbers stay right, and the original bytes are still written back unchanged.
    """
    m = re.search(rb"<\?xml\s[^>]*\?>", data[:4096])
    if m is None or m.start() == 0:
        return data, False
    before = re.sub(rb"<!--.*?-->", b"", data[: m.start()], flags=re.S)
    if before.strip():
        return data, False
    return data[: m.start()] + b" " * (m.end() - m.start()) + data[m.end():], True


def parse_robot_xml(path, root_tag: str, format_name: str) -> Document:
    """:func:`parse_xml`, refusing a document whose root is not ``<root_tag>`` by name."""
    doc = parse_xml(path)
    if doc.root.tag != root_tag:
        raise RobotFileError(f"{doc.where(doc.root)}: not {format_name} file: the root element is <{doc.root.tag}>, "
                             f"not <{root_tag}>")
    return doc


def parse_xml_bytes(data: bytes, path="<string>") -> Document:
    """Parse XML bytes safely; ``path`` is used in messages."""
    path = Path(path) if not isinstance(path, Path) else path
    source = data
    data, relocated = _relocated_declaration(data)
    data, dashes = _comments_as_tinyxml2_reads_them(data)
    builder = ET.TreeBuilder(insert_comments=True)
    parser = expat.ParserCreate()
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    lines: dict[int, int] = {}
    starts: dict[int, int] = {}
    ends: dict[int, int] = {}
    stack: list = []

    def start(tag, attrs):
        el = builder.start(tag, attrs)
        lines[id(el)] = parser.CurrentLineNumber
        starts[id(el)] = parser.CurrentByteIndex
        stack.append(el)

    def end(tag):
        builder.end(tag)
        ends[id(stack.pop())] = parser.CurrentByteIndex

    def comment(text):
        if stack:  # comments outside the root are not part of the tree
            builder.comment(text)

    def entity_decl(name, is_param, value, base, system_id, public_id, notation):
        _refuse(path, parser, f"the document declares entity {name!r}")

    def external_ref(context, base, system_id, public_id):
        _refuse(path, parser, f"reference to an external entity ({system_id or public_id})")

    parser.ordered_attributes = False
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = builder.data
    parser.CommentHandler = comment
    parser.EntityDeclHandler = entity_decl
    parser.UnparsedEntityDeclHandler = lambda *a: _refuse(path, parser, "an unparsed entity declaration")
    parser.ExternalEntityRefHandler = external_ref
    trailing = None
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        root_end = max(ends.values()) if ends and not stack else None
        if root_end is not None and _ignored_after_root(data[root_end:]):
            # what follows the root element is what tinyxml2 (the parser of MuJoCo, urdfdom and
            # libsdformat) ignores: the file is read as they read it, with a warning
            trailing = exc.lineno
        else:
            raise _malformed(path, exc) from None
    except RobotFileError:
        raise
    except (LookupError, ValueError) as exc:  # an unknown or unusable encoding="..." (expat asks codecs)
        declared = re.search(rb"""encoding\s*=\s*["']([^"']*)""", data[:1024])
        name = declared.group(1).decode("ascii", "replace") if declared else "?"
        raise RobotFileError(f"{path}:{parser.CurrentLineNumber}: the XML declaration's encoding {name!r} "
                             f"cannot be used to read the file ({exc}); robot files are UTF-8") from None
    root = builder.close()
    doc = Document(root, path, lines, source=source, starts=starts, ends=ends)
    if relocated:
        doc.notes.append(("xml_declaration_moved", f"{path}: the XML declaration follows a comment or blank lines "
                          "(not allowed by XML); read anyway"))
    if dashes is not None:
        doc.notes.append(("comment_with_dashes", f"{path}:{dashes}: a comment holds '--' (a comment started inside "
                          "another?), which XML forbids; read as MuJoCo, urdfdom and libsdformat (tinyxml2) read it, "
                          "the comment ending at the first '-->'; other XML tools refuse the file"))
    if trailing is not None:
        doc.notes.append(("content_after_root", f"{path}:{trailing}: markup after the end of the root element "
                          f"<{root.tag}> (e.g. a stray end tag) is ignored, as MuJoCo, urdfdom and libsdformat "
                          "(tinyxml2) ignore it; other XML tools refuse the file: remove it"))
    return doc


def _comments_as_tinyxml2_reads_them(data: bytes) -> tuple[bytes, int | None]:
    """Comments holding ``--`` (XML forbids it; tinyxml2 ends a comment at the first ``-->``):
    the dashes inside become spaces, byte for byte (offsets and lines unchanged; the source is
    kept as it is).  Returns the data and the line of the first such comment (None: none)."""
    first = None

    def blank(m):
        nonlocal first
        body = m.group(1).replace(b"--", b"- ")
        if body.endswith(b"-"):
            body = body[:-1] + b" "
        if body != m.group(1) and first is None:
            first = data.count(b"\n", 0, m.start()) + 1
        return b"<!--" + body + b"-->"

    if b"<!--" not in data:
        return data, None
    out = re.sub(rb"<!--(.*?)-->", blank, data, flags=re.S)
    return (out, first) if first is not None else (data, None)


def _ignored_after_root(rest: bytes) -> bool:
    """What follows the root's end tag (``rest`` starts with it) is ignored by tinyxml2: it stops
    at a stray end tag (whatever follows), and reads further elements (no text) without using them."""
    after = re.sub(rb"^(?:\s|<!--.*?-->)*", b"", rest[rest.find(b">") + 1:], flags=re.S)
    return after.startswith(b"</") or not re.sub(rb"<[^<>]*>", b"", after).strip()


def _malformed(path, exc) -> RobotFileError:
    """The error for a document expat cannot read."""
    msg = expat.ErrorString(exc.code)
    if exc.code == expat.errors.codes.get(expat.errors.XML_ERROR_UNDEFINED_ENTITY):
        msg += " (entities are not supported in robot files)"
    return RobotFileError(f"{path}:{exc.lineno}: malformed XML: {msg} (column {exc.offset + 1})")
