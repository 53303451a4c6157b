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

import xml.etree.ElementTree as ET
from pathlib import Path
from xml.parsers import expat

from ..errors import InertiaError


class RobotFileError(InertiaError, ValueError):
    """A robot description file that cannot be read: unsafe, malformed or missing."""


class Document:
    """A parsed XML file: the root element, the source path and each element's line."""

    def __init__(self, root: ET.Element, path: Path, lines: dict, declaration: str | None,
                 prolog: tuple = (), epilog: tuple = ()):
        self.root = root
        self.path = path
        self._lines = lines
        self.declaration = declaration
        self.prolog, self.epilog = prolog, epilog  # comments outside the root element

    def line(self, element) -> int | None:
        """1-based line of the element's start tag in the source (None for new elements)."""
        return self._lines.get(id(element))

    def where(self, element) -> str:
        """``file:line`` for messages."""
        line = self.line(element)
        return f"{self.path}:{line}" if line else str(self.path)


def _refuse(path, parser, what: str):
    raise RobotFileError(f"{path}:{parser.CurrentLineNumber}: refused: {what}. Robot files need no entities; "
                         "this is how XML entity-expansion bombs and external-entity attacks work, so the file "
                         "is not read.")


def parse_xml(path) -> Document:
    """Parse ``path`` safely (see the module docstring); :class:`RobotFileError` on any problem."""
    path = Path(path)
    try:
        data = path.read_bytes()
    except FileNotFoundError:
        raise RobotFileError(f"{path}: file not found") from None
    except OSError as exc:
        raise RobotFileError(f"{path}: cannot read ({exc.strerror or exc})") from None
    return parse_xml_bytes(data, path)


def parse_xml_bytes(data: bytes, path="<string>") -> Document:
    """Parse XML bytes safely; ``path`` is used in messages."""
    path = Path(path) if not isinstance(path, Path) else path
    builder = ET.TreeBuilder(insert_comments=True)
    parser = expat.ParserCreate()
    parser.SetParamEntityParsing(expat.XML_PARAM_ENTITY_PARSING_NEVER)
    lines: dict[int, int] = {}
    declaration = []
    depth = [0]
    outside: dict[str, list] = {"prolog": [], "epilog": []}
    seen_root = [False]

    def start(tag, attrs):
        el = builder.start(tag, attrs)
        lines[id(el)] = parser.CurrentLineNumber
        depth[0] += 1
        seen_root[0] = True

    def end(tag):
        builder.end(tag)
        depth[0] -= 1

    def comment(text):
        if depth[0] == 0:  # TreeBuilder drops comments outside the root: keep them ourselves
            outside["epilog" if seen_root[0] else "prolog"].append(text)
        else:
            builder.comment(text)

    def entity_decl(name, is_param, value, base, system_id, public_id, notation):
        _refuse(path, parser, f"the document declares entity {name!r}")

    def external_ref(context, base, system_id, public_id):
        _refuse(path, parser, f"reference to an external entity ({system_id or public_id})")

    def xml_decl(version, encoding, standalone):
        declaration.append((version, encoding))

    parser.ordered_attributes = False
    parser.StartElementHandler = start
    parser.EndElementHandler = end
    parser.CharacterDataHandler = builder.data
    parser.CommentHandler = comment
    parser.EntityDeclHandler = entity_decl
    parser.UnparsedEntityDeclHandler = lambda *a: _refuse(path, parser, "an unparsed entity declaration")
    parser.ExternalEntityRefHandler = external_ref
    parser.XmlDeclHandler = xml_decl
    try:
        parser.Parse(data, True)
    except expat.ExpatError as exc:
        msg = expat.ErrorString(exc.code)
        if exc.code == expat.errors.codes.get(expat.errors.XML_ERROR_UNDEFINED_ENTITY):
            msg += " (entities are not supported in robot files)"
        raise RobotFileError(f"{path}:{exc.lineno}: malformed XML: {msg} (column {exc.offset + 1})") from None
    root = builder.close()
    decl = None
    if declaration:  # keep the declaration exactly as written
        head = data.lstrip()
        end = head.find(b"?>")
        decl = head[: end + 2].decode("utf-8", "replace") if head.startswith(b"<?xml") and end > 0 else None
    return Document(root, path, lines, decl, tuple(outside["prolog"]), tuple(outside["epilog"]))


def serialize(doc: Document) -> bytes:
    """The document as bytes (declaration kept if the source had one), comments included."""
    body = ET.tostring(doc.root, encoding="unicode", short_empty_elements=True)
    head = (doc.declaration + "\n") if doc.declaration else ""
    head += "".join(f"<!--{c}-->\n" for c in doc.prolog)
    tail = "".join(f"<!--{c}-->\n" for c in doc.epilog)
    return (head + body + "\n" + tail).encode("utf-8")
