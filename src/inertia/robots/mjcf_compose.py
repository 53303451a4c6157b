"""MJCF composition: what ``<frame>``, ``<replicate>`` and ``<attach>`` put inside a body, as
MuJoCo's compiler builds it.

* ``<frame pos orientation childclass>``: its contents, posed by the frame.
* ``<replicate count offset euler sep childclass>``: ``count`` copies of its contents.  Copy
  ``i`` has the orientation ``R(i * euler)`` and the position ``sum_{k<i} R(k * euler) @ offset``
  in the replicate's parent frame, as MuJoCo's parser computes them (the orientation from
  ``i * euler`` directly, with the model's angle unit and ``eulerseq``); every name in copy
  ``i`` gets the suffix ``sep`` + ``i`` written with as many digits as ``count`` has (nested
  replicates: the innermost suffix first).
* ``<attach model body|frame prefix>``: the named body (with its subtree) or frame (with its
  contents, at the frame's own pose) of the model asset ``model`` (``<asset><model name
  file>``), or that model's whole world body when neither is given, placed at the attach
  point with every name prefixed.  The attached elements keep their own model's meaning:
  its default classes, compiler (angle unit, ``eulerseq``, ``inertiafromgeom``, mass
  bounds...) and mesh assets (files under its own folder and ``meshdir``).  The world
  body's geoms join the body holding the ``<attach>``.  Without ``model`` the body or frame
  comes from the same model (self-attachment); it must be read before the ``<attach>`` and
  must not hold it.

The expansion is iterative (models nest thousands deep), bounded to :data:`MAX_ELEMENTS`
elements in all (a replicate or attach beyond it is refused by name, before it is
expanded), and an attach that would hold itself (directly or through other models) is
refused by name.  A *scope* is one model's meaning (see :class:`inertia.robots.mjcf`'s
reader): ``doc``, ``path``, ``orientation(attrs, where)``, ``euler(values)`` and
``model(name, where)`` (the scope of a model asset).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .urdf_sdf import floats
from .xmlsafe import RobotFileError

#: most elements an MJCF model may hold once its includes, replicates and attachments are
#: expanded (a guard against expansion bombs)
MAX_ELEMENTS = 1_000_000

#: MJCF elements that add bodies or mass this reader does not expand: refused by name (a
#: check that skipped them would call an incomplete model valid)
UNREAD = ("composite", "flexcomp")

#: what a body holds that the reader reads; a world body's geoms are static (not read)
BODY_CONTENTS = ("geom", "body", "joint", "freejoint")

#: elements whose ``childclass`` the elements inside them inherit
_CLASS_HOLDERS = ("body", "frame", "replicate")


class Names(NamedTuple):
    """How MuJoCo renames the elements of an attached or replicated subtree:
    ``prefix + name + suffix``; ``chain`` lists the attachments it is inside, as
    ``((file, kind, name), where)`` (to refuse cycles)."""

    prefix: str = ""
    suffix: str = ""
    chain: tuple = ()

    def __call__(self, name: str | None) -> str | None:
        return None if name is None else self.prefix + name + self.suffix


_PLAIN = Names()


class Item(NamedTuple):
    """One element of a body's contents: ``kind`` (its tag), the element, the scope (model)
    and names it belongs to, the default class it inherits, its frame's pose in the body."""

    kind: str
    element: object
    scope: object
    names: Names
    childclass: str
    R: np.ndarray
    p: np.ndarray


class Composer:
    """Expands the contents of bodies; counts the elements of the expanded model."""

    def __init__(self, count: int = 0, limit: int | None = None):
        self.count = count
        self.limit = MAX_ELEMENTS if limit is None else limit
        self._sizes: dict = {}      # id(element) -> elements its contents expand into
        self._order: dict = {}      # id(document) -> (id(element) -> (index, parent))

    def contents(self, el, scope, names: Names, childclass: str, tags=BODY_CONTENTS):
        """The ``tags`` elements inside ``el`` (a body or world body) in MuJoCo's order, through
        any nesting of frames, replicates and attachments, as :class:`Item`."""
        stack = [(iter(list(el)), scope, names, childclass, np.eye(3), np.zeros(3), False)]
        while stack:
            children, scope, names, cc, R, p, replicated = stack[-1]
            child = next(children, None)
            if child is None:
                stack.pop()
                continue
            if not isinstance(child.tag, str):
                continue  # a comment
            if names == _PLAIN:  # elements inside replicates and attachments are counted by them
                self.count += 1
            tag = child.tag
            if tag in ("joint", "freejoint") and replicated:
                raise RobotFileError(f"{scope.doc.where(child)}: <{tag}> inside a <replicate> must be inside a body "
                                     "there (MuJoCo refuses a joint as a direct child of replicate)")
            if tag in tags:
                yield Item(tag, child, scope, names, cc, R, p)
            elif tag == "frame":
                where = f"{scope.doc.where(child)}: <frame>"
                R_f, p_f = scope.orientation(child.attrib, where), _pos(child, where, "pos")
                stack.append((iter(list(child)), scope, names, child.get("childclass", cc), R @ R_f, R @ p_f + p,
                              replicated))
            elif tag == "replicate":
                stack.extend(reversed(self._copies(child, scope, names, cc, R, p)))
            elif tag == "attach":
                kind, *rest = self._attach(child, scope, names, R, p)
                if kind == "body":
                    if "body" in tags:
                        yield Item("body", *rest)
                else:
                    stack.extend(reversed(rest))
            elif tag in UNREAD:
                raise RobotFileError(f"{scope.doc.where(child)}: <{tag}> is not read by this version of inertia "
                                     "(MuJoCo expands it into bodies and geoms whose mass properties would go "
                                     "unchecked); check the model after compiling it, e.g. from MuJoCo's saved XML "
                                     "(mj_saveLastXML)")

    # ------------------------------------------------------------------ replicate
    def _copies(self, rep, scope, names: Names, cc: str, R, p) -> list:
        """Stack entries of a ``<replicate>``'s copies, first copy first."""
        where = f"{scope.doc.where(rep)}: <replicate>"
        text = rep.get("count")
        try:
            count = int(text)
        except (TypeError, ValueError):
            raise RobotFileError(f"{where}: count={text!r} must be a positive whole number (MuJoCo requires "
                                 "it)") from None
        if count < 1:
            raise RobotFileError(f"{where}: count={text!r} must be positive")
        if names == _PLAIN:  # a replicate inside another, or inside an attachment, is counted by it
            self._reserve(self._size(rep), where, f"count={count}")
        offset = np.asarray(floats(rep.get("offset", "0 0 0"), 3, where, "offset"))
        euler = np.asarray(floats(rep.get("euler", "0 0 0"), 3, where, "euler"))
        sep, digits, inner_cc = rep.get("sep", ""), len(str(count)), rep.get("childclass", cc)
        out, pos = [], np.zeros(3)
        for i in range(count):
            R_i = scope.euler(i * euler)
            out.append((iter(list(rep)), scope, names._replace(suffix=f"{sep}{i:0{digits}d}" + names.suffix),
                        inner_cc, R @ R_i, R @ pos + p, True))
            pos = pos + R_i @ offset
        return out

    # ------------------------------------------------------------------ attach
    def _attach(self, el, scope, names: Names, R, p) -> tuple:
        """``("body", element, scope, names, childclass, R, p)`` for an attached body, else
        ``("frames", *stack entries)`` for a frame's or a world body's contents."""
        where = f"{scope.doc.where(el)}: <attach>"
        prefix, model = el.get("prefix"), el.get("model")
        if prefix is None:
            raise RobotFileError(f"{where} needs a prefix (MuJoCo requires it)")
        if el.get("body") is not None and el.get("frame") is not None:
            raise RobotFileError(f"{where}: give body or frame, not both")
        kind = "body" if el.get("body") is not None else "frame" if el.get("frame") is not None else "world"
        name = el.get(kind)
        if model is None:
            if kind == "world":
                raise RobotFileError(f"{where}: attaching from the same model (no model=...) needs body or frame")
            child = scope
            target = self._self_target(el, scope, kind, name, where)
        else:
            child = scope.model(model, where)
            target = None if kind == "world" else _named(child, kind, name, f"{where}: model {model!r}")
        key = (str(child.path), kind, name)
        outer = [w for k, w in names.chain if k == key]
        if outer:
            raise RobotFileError(f"{where}: attaching {kind} {name!r} of {child.path} here puts it inside itself (it "
                                 f"holds this <attach> since it is attached at {outer[0]}: an attach cycle); refused")
        inner = Names(names.prefix + prefix, names.suffix, names.chain + ((key, where),))
        if kind == "body":
            self._reserve(1 + self._size(target), where, f"body {name!r}")
            return ("body", target, child, inner, _inherited_class(self._index(child), target), R, p)
        if kind == "frame":
            self._reserve(1 + self._size(target), where, f"frame {name!r}")
            w = f"{child.doc.where(target)}: <frame>"
            R_f, p_f = child.orientation(target.attrib, w), _pos(target, w, "pos")
            cc = target.get("childclass") or _inherited_class(self._index(child), target)
            return ("frames", (iter(list(target)), child, inner, cc, R @ R_f, R @ p_f + p, False))
        worlds = child.doc.root.findall("worldbody")
        self._reserve(sum(1 + self._size(w) for w in worlds), where, f"model {model!r}")
        return ("frames", *((iter(list(w)), child, inner, "main", R, p, False) for w in worlds))

    def _self_target(self, el, scope, kind: str, name: str, where: str):
        """The body or frame a self-attachment names: read before the ``<attach>``, not holding it."""
        target = _named(scope, kind, name, where)
        index = self._index(scope)
        if index[id(target)][0] > index[id(el)][0]:
            raise RobotFileError(f"{where}: {kind} {name!r} ({scope.doc.where(target)}) comes after the <attach>; "
                                 "MuJoCo attaches only what it has read before")
        up = index[id(el)][1]
        while up is not None:
            if up is target:
                raise RobotFileError(f"{where}: {kind} {name!r} ({scope.doc.where(target)}) holds this <attach>: "
                                     "attaching it would put it inside itself (an attach cycle); refused")
            up = index[id(up)][1]
        return target

    # ------------------------------------------------------------------ sizes
    def _reserve(self, n: int, where: str, what: str) -> None:
        """Count the ``n`` elements an expansion adds, refused beyond the limit."""
        self.count += n
        if self.count > self.limit:
            raise RobotFileError(f"{where} ({what}): the expanded model would hold more than {self.limit} elements; "
                                 "refused")

    def _size(self, el) -> int:
        """Elements ``el``'s contents expand into (a replicate: its count times one frame and its
        contents; an attach inside counts as one here, and is bounded when it is expanded)."""
        if id(el) in self._sizes:
            return self._sizes[id(el)]
        order, stack = [], [el]
        while stack:
            e = stack.pop()
            if id(e) not in self._sizes:
                order.append(e)
                stack.extend(c for c in e if isinstance(c.tag, str))
        for e in reversed(order):  # children before their parents
            inner = sum(1 + self._sizes[id(c)] for c in e if isinstance(c.tag, str))
            self._sizes[id(e)] = (1 + inner) * _count_of(e) if e.tag == "replicate" else inner
        return self._sizes[id(el)]

    def _index(self, scope) -> dict:
        """id(element) -> (document order, parent element) in a scope's document."""
        key = id(scope.doc)
        if key not in self._order:
            root = scope.doc.root
            parents = {id(c): e for e in root.iter() for c in e}
            index = {id(e): (k, parents.get(id(e))) for k, e in enumerate(root.iter())}
            self._order[key] = (scope.doc, index)  # the document is kept: its ids stay valid
        return self._order[key][1]


def _count_of(rep) -> int:
    """A replicate's count for the size bound (a bad one is refused when it is expanded)."""
    try:
        return max(int(rep.get("count")), 1)
    except (TypeError, ValueError):
        return 1


def _pos(el, where: str, attr: str) -> np.ndarray:
    return np.asarray(floats(el.get(attr, "0 0 0"), 3, where, attr))


def _named(scope, kind: str, name: str, where: str):
    """The first ``<body>`` or ``<frame>`` called ``name`` in a scope's world bodies (not inside a
    replicate, whose copies MuJoCo renames)."""
    for world in scope.doc.root.findall("worldbody"):
        stack = list(reversed(list(world)))
        while stack:
            e = stack.pop()
            if e.tag == kind and e.get("name") == name:
                return e
            if e.tag != "replicate":
                stack.extend(reversed(list(e)))
    raise RobotFileError(f"{where}: no {kind} named {name!r} in {scope.path} (bodies and frames inside "
                         "<replicate> or brought by <attach> are not looked up by their new names)")


def _inherited_class(index: dict, el) -> str:
    """The default class ``el`` inherits from the bodies, frames and replicates around it."""
    up = index[id(el)][1]
    while up is not None:
        if up.tag in _CLASS_HOLDERS and up.get("childclass") is not None:
            return up.get("childclass")
        up = index[id(up)][1]
    return "main"
