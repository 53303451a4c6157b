"""Minimal edits of an XML source: change numbers in place, never re-serialise the tree.

A repair must leave every byte it does not mean to change as it was (quoting, attribute
order, whitespace inside tags, line endings, comments, encoding).  The parser
(:func:`inertia.robots.xmlsafe.parse_xml_bytes`) records where each element's start tag
begins and where its end tag begins; :class:`SourceEditor` finds attribute values and
element text inside those spans and collects replacements, applied in one pass by
:meth:`SourceEditor.result`.

Only ASCII is ever inserted (numbers, attribute and element names), so the edits are valid in
any ASCII-compatible encoding (UTF-8, Latin-1, ...); UTF-16/32 sources are refused by name.
"""

from __future__ import annotations

import re

from .._core.errors import RobotFileError

_ATTR = re.compile(rb"""(\s+)([^\s=/>]+)(\s*=\s*)(?:"([^"]*)"|'([^']*)')""")


def _numbers(text: str):
    """The floats in ``text``, or None when it does not hold only numbers."""
    try:
        return [float(t) for t in text.split()]
    except ValueError:
        return None


def _format(values) -> str:
    return " ".join(repr(float(v)) for v in values)


class SourceEditor:
    """Replacements on the source bytes of a parsed :class:`~inertia.robots.xmlsafe.Document`."""

    def __init__(self, doc):
        self.doc = doc
        self.data: bytes = doc.source
        if self.data[:2] in (b"\xff\xfe", b"\xfe\xff") or self.data[:4] in (b"\x00\x00\xfe\xff", b"\xff\xfe\x00\x00"):
            raise RobotFileError(f"{doc.path}: a UTF-16/UTF-32 file cannot be edited in place; save it as UTF-8")
        self.newline = b"\r\n" if b"\r\n" in self.data else b"\n"
        self.edits: list[tuple[int, int, bytes]] = []

    # ---------------------------------------------------------------- spans
    def start_tag(self, el) -> tuple[int, int, bool]:
        """``(start, end, self_closing)`` of ``el``'s start tag (``end`` after its ``>``)."""
        start = self.doc.start_byte(el)
        if start is None:
            raise RobotFileError(f"{self.doc.where(el)}: <{el.tag}> has no place in the source to edit")
        i, quote = start + 1, None
        data = self.data
        while i < len(data):
            c = data[i:i + 1]
            if quote:
                if c == quote:
                    quote = None
            elif c in (b'"', b"'"):
                quote = c
            elif c == b">":
                return start, i + 1, data[i - 1:i] == b"/"
            i += 1
        raise RobotFileError(f"{self.doc.where(el)}: the start tag of <{el.tag}> does not end")

    def attributes(self, el) -> dict:
        """Attribute name -> ``(span_start, value_start, value_end)`` in the source."""
        start, end, closing = self.start_tag(el)
        tag = self.data[start:end]
        out = {}
        for m in _ATTR.finditer(tag, len(el.tag.encode()) + 1):
            g = 4 if m.group(4) is not None else 5
            out[m.group(2).decode("utf-8", "replace")] = (start + m.start(1), start + m.start(g), start + m.end(g))
        return out

    def inner(self, el) -> tuple[int, int] | None:
        """``(start, end)`` of the bytes between ``el``'s start and end tags (None if ``<el/>``)."""
        _, end, closing = self.start_tag(el)
        if closing:
            return None
        close = self.doc.end_byte(el)
        return end, close

    # ---------------------------------------------------------------- edits
    def set_attribute(self, el, name: str, value: str) -> None:
        """Replace the value of ``name`` (keeping its quotes), or add it at the tag's end."""
        attrs = self.attributes(el)
        if name in attrs:
            _, a, b = attrs[name]
            if self.data[a:b] != value.encode("ascii"):
                self.edits.append((a, b, value.encode("ascii")))
            return
        start, end, closing = self.start_tag(el)
        at = end - (2 if closing else 1)
        while at > start and self.data[at - 1:at].isspace():
            at -= 1
        self.edits.append((at, at, f' {name}="{value}"'.encode("ascii")))

    def set_numbers(self, el, name: str, values, *, default=None) -> None:
        """Set attribute ``name`` to the numbers ``values``, unless it already holds them
        (compared as floats, so ``"0"`` stays ``"0"``); an absent attribute whose ``default``
        equals ``values`` stays absent."""
        values = [float(v) for v in values]
        if name not in el.attrib:
            if default is not None and [float(v) for v in default] == values:
                return
        elif _numbers(el.attrib[name]) == values:
            return
        self.set_attribute(el, name, _format(values))

    def set_text_numbers(self, el, values) -> None:
        """Set a leaf element's text to the numbers ``values``, unless it already holds them."""
        values = [float(v) for v in values]
        if _numbers(el.text or "") != values:
            self.set_text(el, _format(values))

    def remove_attribute(self, el, name: str) -> None:
        attrs = self.attributes(el)
        if name in attrs:
            s, _, b = attrs[name]
            self.edits.append((s, b + 1, b""))  # through the closing quote

    def set_text(self, el, text: str) -> None:
        """Replace the text of a leaf element (its surrounding whitespace kept)."""
        span = self.inner(el)
        new = text.encode("ascii")
        if span is None:  # <ixx/>: becomes <ixx>text</ixx>
            start, end, _ = self.start_tag(el)
            tag = el.tag.encode()
            self.edits.append((start, end, b"<" + tag + b">" + new + b"</" + tag + b">"))
            return
        a, b = span
        body = self.data[a:b]
        lead = len(body) - len(body.lstrip())
        trail = len(body) - len(body.rstrip())
        if body.strip() != new:
            self.edits.append((a + lead, b - trail, new))

    def append_child(self, parent, xml: str) -> None:
        """Insert ``xml`` as the last child of ``parent``, on its own line, indented like
        the other children (or one step deeper than the parent)."""
        span = self.inner(parent)
        if span is None:
            raise RobotFileError(f"{self.doc.where(parent)}: <{parent.tag}/> is empty; cannot add <{xml}> to it")
        a, b = span
        indent = self._child_indent(parent, a)
        # after the last non-space byte before the end tag (keeps the end tag's own line)
        at = b
        while at > a and self.data[at - 1:at] in (b" ", b"\t", b"\r", b"\n"):
            at -= 1
        self.edits.append((at, at, self.newline + indent + xml.encode("ascii")))

    def _child_indent(self, parent, inner_start: int) -> bytes:
        children = [c for c in parent if isinstance(c.tag, str)]
        if children:
            pos = self.doc.start_byte(children[0])
            line_start = self.data.rfind(b"\n", 0, pos) + 1
            pad = self.data[line_start:pos]
            if not pad.strip():
                return pad
        start, _, _ = self.start_tag(parent)
        line_start = self.data.rfind(b"\n", 0, start) + 1
        pad = self.data[line_start:start]
        return (pad if not pad.strip() else b"") + b"  "

    # ---------------------------------------------------------------- result
    def result(self) -> bytes:
        """The source with every edit applied (edits must not overlap)."""
        out, last = [], 0
        for a, b, new in sorted(self.edits, key=lambda e: (e[0], e[1])):
            if a < last:
                raise RobotFileError(f"{self.doc.path}: overlapping edits at byte {a}")  # a bug, named
            out += [self.data[last:a], new]
            last = b
        out.append(self.data[last:])
        return b"".join(out)
