"""Where a ``.usda`` layer's prims, metadata and attribute values sit in its text, to edit them in place.

This is a locator for the writer, not a reader: values are always read through usd-core, and
every edit made here is checked afterwards by importing the edited text with usd-core
(:func:`layer_signature`).  The scanner knows the text format's lexical rules (comments,
strings, asset paths, ``<paths>``, bracket nesting, statements ending at a line break) and the
shape of prim statements (``def|over|class [Type] "name" (metadata) { ... }``, variant sets).
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

from ..._core.errors import RobotFileError

_TOKEN = re.compile(r'''
    (?P<comment>\#[^\n]*)
  | (?P<string>"""[\s\S]*?"""|\'\'\'[\s\S]*?\'\'\'|"(?:\\.|[^"\\\n])*"|'(?:\\.|[^'\\\n])*')
  | (?P<asset>@@@[\s\S]*?@@@|@[^@\n]*@)
  | (?P<path><[^<>\n]*>)
  | (?P<open>[({\[])
  | (?P<close>[)}\]])
  | (?P<punct>[=,;&])
  | (?P<atom>[^\s()\[\]{}=,;&"'@<#]+)
''', re.X)


@dataclass
class Prop:
    """A property statement: its first token, the span of its default value (None: no ``=``) and its end."""

    start: int
    value: tuple | None
    end: int


@dataclass
class PrimText:
    """A prim statement's pieces (character offsets into the text)."""

    header: int                  # the def/over/class keyword
    name_end: int                # just after the quoted name
    meta: tuple | None           # (open paren, close paren) of its metadata
    body: tuple                  # ({, })
    props: dict = field(default_factory=dict)     # name -> Prop (default-value statements)
    last_prop_end: int | None = None
    child_start: int | None = None                 # the first child prim statement


def _tokens(text: str):
    out = []
    for m in _TOKEN.finditer(text):
        kind = m.lastgroup
        if kind != "comment":
            out.append((kind, m.start(), m.end(), m.group()))
    return out


class _Scanner:
    def __init__(self, text: str):
        self.text = text
        self.toks = _tokens(text)
        self.i = 0
        self.prims: dict = {}

    def _group_end(self, i: int) -> int:
        """Index of the token closing the bracket opened at token ``i``."""
        depth = 0
        for j in range(i, len(self.toks)):
            kind = self.toks[j][0]
            if kind == "open":
                depth += 1
            elif kind == "close":
                depth -= 1
                if depth == 0:
                    return j
        raise RobotFileError("unbalanced brackets")

    def _newline_before(self, j: int) -> bool:
        return "\n" in self.text[self.toks[j - 1][2]:self.toks[j][1]] if j > 0 else True

    def layer(self) -> dict:
        if self.i < len(self.toks) and self.toks[self.i][3] == "(":
            self.i = self._group_end(self.i) + 1
        self._statements("", top=True)
        return self.prims

    def _statements(self, parent: str, top: bool = False, prim: PrimText | None = None) -> None:
        while self.i < len(self.toks):
            kind, s, e, text = self.toks[self.i]
            if kind == "close" and text == "}":
                return
            if text in ("def", "over", "class"):
                if prim is not None and prim.child_start is None:
                    prim.child_start = s
                self._prim(parent)
            elif text == "variantSet" and not top:
                self._variant_set(parent)
            else:
                self._property(prim)

    def _prim(self, parent: str) -> None:
        header = self.toks[self.i][1]
        self.i += 1
        while self.toks[self.i][0] != "string":      # the optional type name
            self.i += 1
        name = self.toks[self.i][3].strip("\"'")
        name_end = self.toks[self.i][2]
        self.i += 1
        meta = None
        if self.toks[self.i][3] == "(":
            j = self._group_end(self.i)
            meta = (self.toks[self.i][1], self.toks[j][1])
            self.i = j + 1
        if self.toks[self.i][3] != "{":
            raise RobotFileError(f"prim {name!r}: expected {{")
        open_at = self.toks[self.i][1]
        path = f"{parent}/{name}" if not parent.endswith("}") else f"{parent}{name}"
        prim = PrimText(header, name_end, meta, (open_at, -1))
        self.prims[path] = prim
        self.i += 1
        self._statements(path, prim=prim)
        prim.body = (open_at, self.toks[self.i][1])
        self.i += 1

    def _variant_set(self, parent: str) -> None:
        self.i += 1
        set_name = self.toks[self.i][3].strip("\"'")
        self.i += 2                                    # the name and "="
        self.i += 1                                    # {
        while self.toks[self.i][3] != "}":
            variant = self.toks[self.i][3].strip("\"'")
            self.i += 1
            if self.toks[self.i][3] == "(":
                self.i = self._group_end(self.i) + 1
            self.i += 1                                # {
            self._statements(f"{parent}{{{set_name}={variant}}}")
            self.i += 1                                # }
        self.i += 1

    def _property(self, prim: PrimText | None) -> None:
        start_i = self.i
        start = self.toks[self.i][1]
        words, value = [], None
        while self.i < len(self.toks):
            kind, s, e, text = self.toks[self.i]
            if self.i > start_i and self._newline_before(self.i):
                break
            if kind == "close" and text == "}":
                break
            if kind == "punct" and text == "=" and value is None:
                j = self.i + 1
                end_j = self._group_end(j) if self.toks[j][0] == "open" else j
                value = (self.toks[j][1], self.toks[end_j][2])
                self.i = end_j + 1
                continue
            if kind == "open":
                self.i = self._group_end(self.i) + 1
                continue
            if kind == "atom" and value is None:
                words.append(text)
            self.i += 1
        end = self.toks[self.i - 1][2]
        if prim is not None:
            if words:
                prim.props[words[-1]] = Prop(start, value, end)
            if prim.child_start is None:
                prim.last_prop_end = end


def scan(text: str) -> dict:
    """``{prim spec path: PrimText}`` of a ``.usda`` text (ValueError when it is not one this scanner follows)."""
    try:
        return _Scanner(text).layer()
    except IndexError:
        raise RobotFileError("the text ends inside a statement") from None


def line_start(text: str, pos: int) -> int:
    return text.rfind("\n", 0, pos) + 1


def indent_at(text: str, pos: int) -> str:
    start = line_start(text, pos)
    return re.match(r"[ \t]*", text[start:]).group()


def layer_signature(layer) -> list:
    """Every spec of an Sdf layer with every field, as sorted text: two layers with the same
    signature hold the same opinions (field order aside)."""
    from pxr import Sdf

    out = []

    def visit(path):
        spec = layer.GetObjectAtPath(path)
        if spec is None:
            return
        fields = sorted((k, repr(spec.GetInfo(k))) for k in spec.ListInfoKeys())
        out.append((str(path), fields))

    layer.Traverse(Sdf.Path.absoluteRootPath, visit)
    return sorted(out)
