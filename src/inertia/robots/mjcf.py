"""MJCF (MuJoCo XML) reader: bodies with their declared inertial and their geoms.

Supported, following MuJoCo's compiler:

* ``<compiler angle="degree|radian" eulerseq="xyz" meshdir assetdir inertiafromgeom
  inertiagrouprange fitaabb>`` (MuJoCo's default angle unit is degrees; euler sequences with
  lower-case letters rotate with the frame, upper-case ones about fixed axes).  Every
  ``<compiler>`` of the model, those of included files too, is merged in document order and
  holds for the whole model (:func:`merged_compiler`); geoms outside ``inertiagrouprange``
  carry no mass; ``exactmeshinertia`` (removed from MJCF) is refused as MuJoCo refuses it;
* default classes (``<default class=...>``, nested, inherited), ``class`` on elements and
  ``childclass`` on bodies, for ``geom``, ``inertial`` and ``mesh`` attributes;
* orientations ``quat`` (w x y z), ``euler``, ``axisangle``, ``xyaxes``, ``zaxis``;
* ``<inertial pos quat mass diaginertia|fullinertia>`` where ``fullinertia`` is
  ``ixx iyy izz ixy ixz iyz`` (tensor elements, our convention);
* geoms ``sphere``, ``capsule``, ``cylinder``, ``ellipsoid``, ``box`` (half sizes, or
  ``fromto``) and ``mesh`` (asset ``file`` or ``vertex``/``face``, ``scale``, ``refpos``,
  ``refquat`` and ``inertia`` mode), each with ``density`` (default 1000 kg/m^3) or ``mass``;
  ``shellinertia`` primitives; primitives fitted to a mesh (``mesh`` on a primitive geom,
  ``<compiler fitaabb>``, ``fitscale``): see :mod:`inertia.robots.mujoco_inertia` for what
  the compiler computes from them.  Planes, height fields and SDF geoms carry no volume and
  are skipped;
* ``<include>``, ``<frame>``, ``<replicate>`` and ``<attach>`` (models from ``<asset><model>``,
  each read with its own compiler, defaults and meshes): see :mod:`inertia.robots.mjcf_compose`.
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import numpy as np

from .._core.errors import InertiaError
from .._core.rotations import quat_from_rotvec, quat_normalize, quat_to_matrix
from .mjcf_compose import MAX_ELEMENTS, Composer, Names
from .model import Geometry, Inertial, Joint, Link, RobotModel
from .resolve import mesh_note, resolve_mesh
from .urdf_sdf import floats
from .xmlsafe import RobotFileError, parse_robot_xml, parse_xml

_AXES = {"x": 0, "y": 1, "z": 2}


def _axis_rot(axis: int, angle: float) -> np.ndarray:
    c, s = math.cos(angle), math.sin(angle)
    R = np.eye(3)
    j, k = (axis + 1) % 3, (axis + 2) % 3
    R[j, j], R[j, k], R[k, j], R[k, k] = c, -s, s, c
    return R


def quat_matrix(q) -> np.ndarray:
    """Rotation matrix of an MJCF ``quat`` (w x y z), which MuJoCo normalises."""
    return quat_to_matrix(quat_normalize(q))


def _axis_angle_matrix(axis, angle: float) -> np.ndarray:
    """Rotation by ``angle`` [rad] about the unit vector ``axis``."""
    return quat_to_matrix(quat_from_rotvec(np.asarray(axis, float) * angle))


#: a direction shorter than this has no orientation (MuJoCo refuses it too, with its mjEPS)
_MIN_NORM = 1e-12


def _choice(el, attr: str, default: str, allowed: tuple, where: str) -> str:
    """``el``'s ``attr``, refused unless one of ``allowed`` (MuJoCo's keywords)."""
    value = el.get(attr, default) if el is not None else default
    if value not in allowed:
        raise RobotFileError(f"{where}: <compiler {attr}={value!r}>: {attr} must be one of "
                             f"{', '.join(repr(a) for a in allowed)}")
    return value


#: ``<compiler>`` attributes MuJoCo's schema refused in this version, and why
_REMOVED_COMPILER = {"exactmeshinertia": "MuJoCo 3.2 replaced it by <mesh inertia=\"exact\">; MuJoCo refuses the "
                                         "attribute (\"unrecognized attribute\")"}


def merged_compiler(elements) -> tuple[dict, dict]:
    """``(attributes, element that set each)`` of a model's ``<compiler>`` elements.

    MuJoCo reads every ``<compiler>`` of the model (those of included files too) before any
    other section, in document order, each setting only the attributes it gives: the last
    value of each attribute holds for the whole model, wherever the element stands.
    """
    attrs: dict = {}
    owner: dict = {}
    for el in elements:
        for k, v in el.attrib.items():
            attrs[k], owner[k] = v, el
    return attrs, owner


class _Compiler:
    """A model's compiler settings (see :func:`merged_compiler`); ``where(attr)`` names the
    element that set ``attr``."""

    def __init__(self, elements, doc, default_where: str):
        a, owner = merged_compiler(elements)
        self.where = lambda k: doc.where(owner[k]) if k in owner else default_where
        for k in _REMOVED_COMPILER:
            if k in a:
                raise RobotFileError(f"{self.where(k)}: <compiler {k}=...> is not MJCF any more: "
                                     f"{_REMOVED_COMPILER[k]}")
        self.degree = _choice(a, "angle", "degree", ("degree", "radian"), self.where("angle")) == "degree"
        seq = a.get("eulerseq", "xyz")
        if len(seq) != 3 or any(c.lower() not in _AXES for c in seq):
            raise RobotFileError(f"{self.where('eulerseq')}: compiler eulerseq {seq!r} must be three of x, y, z, "
                                 "X, Y, Z")
        self.eulerseq = seq
        self.meshdir = a.get("meshdir")
        self.assetdir = a.get("assetdir")
        self.inertiafromgeom = _choice(a, "inertiafromgeom", "auto", ("false", "true", "auto"),
                                       self.where("inertiafromgeom"))
        self.fitaabb = _choice(a, "fitaabb", "false", ("false", "true"), self.where("fitaabb")) == "true"
        text = a.get("inertiagrouprange", "0 5")
        lo, hi = floats(text, 2, self.where("inertiagrouprange"), "compiler inertiagrouprange")
        #: geoms whose group is outside this range carry no mass (MuJoCo's inertiagrouprange)
        self.inertiagroups = (lo, hi)

    def angle(self, v: float) -> float:
        return math.radians(v) if self.degree else v


def _unit(v, where: str, attr: str, text: str, part: str) -> np.ndarray:
    """``v`` scaled to unit length; RobotFileError naming ``attr`` when it has (nearly) none."""
    v = np.asarray(v, float)
    if not np.isfinite(v).all():
        raise RobotFileError(f"{where} {attr}={text!r}: {part} is not finite")
    s = float(np.abs(v).max()) if v.size else 0.0
    u = v / s if s > 0 else v          # scaled first: the norm of 1e200-sized entries stays finite
    n = float(np.linalg.norm(u))
    if not s * n > _MIN_NORM:
        raise RobotFileError(f"{where} {attr}={text!r}: {part} has zero length, so it gives no "
                             "orientation (MuJoCo refuses it too)")
    return u / n


def _euler_matrix(angles, comp: _Compiler) -> np.ndarray:
    """Rotation of MJCF ``euler`` angles (in the compiler's unit, about its ``eulerseq`` axes)."""
    R = np.eye(3)
    for ch, a in zip(comp.eulerseq, angles):
        Ri = _axis_rot(_AXES[ch.lower()], comp.angle(a))
        R = R @ Ri if ch.islower() else Ri @ R  # intrinsic (moving) vs extrinsic (fixed) axes
    return R


def _orientation(attrs: dict, comp: _Compiler, where: str) -> np.ndarray:
    """Rotation matrix of the element's orientation attributes; ``where`` names the element."""
    if "quat" in attrs:
        q = floats(attrs["quat"], 4, where, "quat")
        _unit(q, where, "quat", attrs["quat"], "the quaternion")
        return quat_matrix(q)
    if "axisangle" in attrs:
        v = floats(attrs["axisangle"], 4, where, "axisangle")
        return _axis_angle_matrix(_unit(v[:3], where, "axisangle", attrs["axisangle"], "the axis"),
                                  comp.angle(v[3]))
    if "euler" in attrs:
        return _euler_matrix(floats(attrs["euler"], 3, where, "euler"), comp)
    if "xyaxes" in attrs:
        v = floats(attrs["xyaxes"], 6, where, "xyaxes")
        x = _unit(v[:3], where, "xyaxes", attrs["xyaxes"], "the x axis")
        y_in = np.asarray(v[3:])
        y = y_in - x * (x @ y_in)
        if not np.linalg.norm(y) > 1e-10 * np.linalg.norm(y_in):  # parallel to x (rounding aside)
            y = np.zeros(3)
        y = _unit(y, where, "xyaxes", attrs["xyaxes"], "the y axis orthogonal to x")
        return np.column_stack([x, y, np.cross(x, y)])
    if "zaxis" in attrs:
        z = _unit(floats(attrs["zaxis"], 3, where, "zaxis"), where, "zaxis", attrs["zaxis"], "the z axis")
        # MuJoCo: the minimal rotation taking (0, 0, 1) to z
        c = z[2]
        axis = np.cross([0.0, 0.0, 1.0], z)
        s = np.linalg.norm(axis)
        if s < 1e-12:
            return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])
        return _axis_angle_matrix(axis / s, math.atan2(s, c))
    return np.eye(3)


def _collect_defaults(default_el, parent: dict, out: dict) -> None:
    """Class name -> {tag: attrs}, each class inheriting its parent's attributes.

    Parents before children, in document order, without recursion (classes nest deep).  A
    second top-level ``<default>`` adds to the first (MuJoCo keeps one "main" class)."""
    if not parent:
        parent = out.get(default_el.get("class", "main"), parent)
    stack = [(default_el, parent)]
    while stack:
        el, inherited = stack.pop()
        mine = {tag: dict(attrs) for tag, attrs in inherited.items()}
        for child in el:
            if isinstance(child.tag, str) and child.tag != "default":
                mine.setdefault(child.tag, {}).update(child.attrib)
        out[el.get("class", "main")] = mine
        stack.extend((child, mine) for child in reversed(el.findall("default")))


class _Scope:
    """One MJCF model's own meaning: its compiler, default classes, mesh and model assets.

    The main file has one; so has each model an ``<attach>`` brings in (MuJoCo compiles the
    attached elements with their own model's settings).  ``models`` is shared by all the
    scopes of a reading: resolved path -> scope, each file read once; the main document
    adopts the lines of the files it attaches (messages point into them) and lists them in
    ``included`` (``fix`` refuses such models, as for ``<include>``).
    """

    def __init__(self, doc, path, search_paths, models: dict, main_doc=None):
        self.doc, self.path = doc, Path(path)
        self.base = self.path.resolve().parent
        self.search_paths, self.models = search_paths, models
        self.main_doc = main_doc if main_doc is not None else doc
        models[self.path.resolve()] = self
        _expand_includes(doc, self.base, set())
        root = doc.root
        self.compilers = root.findall("compiler")
        self.comp = _Compiler(self.compilers, doc, str(path))
        self.defaults: dict = {}
        for d in root.findall("default"):
            _collect_defaults(d, {}, self.defaults)
        self.defaults.setdefault("main", {})
        mesh_dir = self.base / (self.comp.meshdir or self.comp.assetdir or "")
        self.meshes = {}
        self.assets = [m for asset in root.findall("asset") for m in asset.findall("model")]
        for asset in root.findall("asset"):
            for m in asset.findall("mesh"):
                attrs = dict(self.defaults.get(m.get("class", "main"), {}).get("mesh", {}))
                attrs.update(m.attrib)
                name, params = _mesh_asset(doc, m, attrs, mesh_dir, search_paths)
                if name is not None:
                    self.meshes[name] = params

    def attrs(self, el, tag: str, childclass: str) -> dict:
        """``el``'s attributes over those of its default class (``class``, else ``childclass``)."""
        cls = el.get("class", childclass)
        if cls not in self.defaults:
            raise RobotFileError(f"{self.doc.where(el)}: <{tag}> uses undefined default class {cls!r}")
        merged = dict(self.defaults[cls].get(tag, {}))
        merged.update(el.attrib)
        return merged

    def orientation(self, attrs: dict, where: str) -> np.ndarray:
        return _orientation(attrs, self.comp, where)

    def euler(self, angles) -> np.ndarray:
        return _euler_matrix(angles, self.comp)

    def model(self, name: str, where: str) -> "_Scope":
        """The scope of the model asset ``name`` (``<asset><model name file>``; without a name,
        the file's ``<mujoco model>``), read on first use."""
        for el in self.assets:
            named = el.get("name")
            if named == name or (named is None and self._file_scope(el).doc.root.get("model") == name):
                return self._file_scope(el)
        known = ", ".join(repr(el.get("name") or el.get("file")) for el in self.assets)
        raise RobotFileError(f"{where}: model {name!r} is not a model asset of {self.path} (<asset><model name=... "
                             f"file=.../>); {'the model assets are ' + known if known else 'it has none'}")

    def _file_scope(self, el) -> "_Scope":
        """The scope of a ``<model file>`` asset (relative to this model's folder, as in MuJoCo)."""
        where, target, exists = _file_named(self.doc, el, self.base)
        if target in self.models:
            return self.models[target]
        if not exists:
            raise RobotFileError(f"{where}: model file not found (relative to {self.base})")
        sub = parse_robot_xml(self.base / el.get("file"), "mujoco", "an MJCF")   # by the name given
        scope = _Scope(sub, target, self.search_paths, self.models, self.main_doc)
        self.main_doc.merge(sub)
        self.main_doc.included = [*getattr(self.main_doc, "included", []), target, *getattr(sub, "included", [])]
        return scope


def read_mjcf(path, *, search_paths=(), document=None) -> RobotModel:
    """The bodies, inertials and geoms of an MJCF file, as MuJoCo's compiler reads them.

    ``search_paths``: folders for meshes and includes besides the file's; ``document``: the
    file already parsed (read from ``path`` otherwise).
    """
    doc = document if document is not None else parse_robot_xml(path, "mujoco", "an MJCF")
    main = _Scope(doc, path, search_paths, {})
    links = []
    worlds = doc.root.findall("worldbody")  # MuJoCo merges them all (includes often add one each)
    if not worlds:
        return RobotModel(Path(path), "mjcf", links, doc)
    composer = Composer(limit=MAX_ELEMENTS)

    def visit(body, scope, names, childclass, parent, R_pf, p_pf):
        """Read one body (not its children); returns its child bodies with what each inherits
        and the pose of the frames around them."""
        cc = body.get("childclass", childclass)
        name = names(body.get("name")) or f"body{len(links) + 1}"
        link = Link(name, doc.line(body), None, element=body, parent=parent)
        where = f"{scope.doc.where(body)}: body {name!r}: <body>"
        R_b = scope.orientation(body.attrib, where)  # refuses a degenerate frame
        p_b = np.asarray(floats(body.get("pos", "0 0 0"), 3, where, "pos"))
        link.R_parent_link, link.p_parent_link = R_pf @ R_b, R_pf @ p_b + p_pf
        comp = scope.comp
        inertial = body.find("inertial")
        if inertial is not None:
            where = f"{scope.doc.where(inertial)}: body {name!r}: <inertial>"
            link.inertial = _inertial(scope.attrs(inertial, "inertial", cc), comp, where, doc.line(inertial), inertial)
        children = []
        me = len(links)
        for it in composer.contents(body, scope, names, cc):
            if it.kind == "body":
                children.append((it.element, it.scope, it.names, it.childclass, me, it.R, it.p))
            elif it.kind in ("joint", "freejoint"):
                a = it.scope.attrs(it.element, "joint", it.childclass) if it.kind == "joint" else \
                    dict(it.element.attrib, type="free")
                a["name"] = it.names(a.get("name"))
                link.joints.append(_joint(it.scope.doc, a, it.element, it.scope.comp, it.R, it.p, name))
            else:
                _add_geom(link, it)
        has_mass_geoms = any(g.role == "collision" for g in link.geometries)
        link.inertia_from_geoms = has_mass_geoms and (
            comp.inertiafromgeom == "true" or (comp.inertiafromgeom == "auto" and link.inertial is None))
        if scope is not main:
            link.mjcf_compilers = scope.compilers  # an attached model's own mass bounds
        links.append(link)
        return children

    # depth first, parents before children, without recursion (models nest thousands deep)
    stack = [(it.element, it.scope, it.names, it.childclass, None, it.R, it.p) for world in reversed(worlds)
             for it in reversed(list(composer.contents(world, main, Names(), "main", ("body",))))]
    while stack:
        stack.extend(reversed(visit(*stack.pop())))
    return RobotModel(Path(path), "mjcf", links, doc, root_frame="world")


def _add_geom(link, it) -> None:
    """Add the geom of contents item ``it`` to ``link`` (posed in the body frame)."""
    scope = it.scope
    geom = _geom(scope.doc, scope.attrs(it.element, "geom", it.childclass), it.element, scope.comp, scope.meshes, link)
    if geom is not None:
        geom.R_link_geom = it.R @ geom.R_link_geom
        geom.p_link_geom = it.R @ geom.p_link_geom + it.p
        link.geometries.append(geom)


def _inertial(a: dict, comp: _Compiler, where: str, line, element) -> Inertial:
    """The body's declared inertial from its (class-merged) attributes ``a``."""
    mass = floats(a.get("mass"), 1, where, "inertial mass")[0] if "mass" in a else None
    if mass is None:
        raise RobotFileError(f"{where} needs a mass")
    pos = np.asarray(floats(a.get("pos", "0 0 0"), 3, where, "inertial pos"))
    R = _orientation(a, comp, where)
    if "fullinertia" in a:
        ixx, iyy, izz, ixy, ixz, iyz = floats(a["fullinertia"], 6, where, "fullinertia")
        I = np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]])
    elif "diaginertia" in a:
        I = np.diag(floats(a["diaginertia"], 3, where, "diaginertia"))
    else:
        raise RobotFileError(f"{where} needs diaginertia or fullinertia")
    return Inertial(mass, pos, R, I, line, element, "fullinertia" if "fullinertia" in a else "diaginertia")


#: MJCF joint types and what they do to the body (hinge and slide move by their value)
_JOINT_KINDS = {"hinge": "hinge", "slide": "slide", "ball": "ball", "free": "free"}


def _joint(doc, a: dict, el, comp: _Compiler, R_f, p_f, body: str) -> Joint:
    """A ``<joint>`` (or ``<freejoint>``, ``a["type"] == "free"``) from its class-merged
    attributes, its anchor and axis in the body frame (through the ``<frame>`` around it)."""
    name = a.get("name")
    where = f"{doc.where(el)}: body {body!r}: joint {name or '(unnamed)'!r}"
    kind = a.get("type", "hinge")
    if kind not in _JOINT_KINDS:
        raise RobotFileError(f"{where}: type={kind!r} must be one of {', '.join(_JOINT_KINDS)}")
    pos = np.asarray(floats(a.get("pos", "0 0 0"), 3, where, "pos"))
    text = a.get("axis", "0 0 1")
    axis = _unit(floats(text, 3, where, "axis"), where, "axis", text, "the axis") if kind in ("hinge", "slide") \
        else np.array([0.0, 0.0, 1.0])
    ref = floats(a.get("ref", "0"), 1, where, "ref")[0]
    if kind == "hinge":
        ref = comp.angle(ref)
    elif kind != "slide":
        ref = 0.0
    return Joint(name, _JOINT_KINDS[kind], kind, R_f @ axis, R_f @ pos + p_f, ref, doc.line(el))


def _expand_includes(doc, base: Path, seen: set) -> None:
    """Replace each ``<include file=.../>`` by the children of that file's ``<mujoco>`` root.

    As in MuJoCo, paths are relative to the main model's folder, and a file may be included
    only once (which also rules out cycles and an exponential fan-out of includes); ``seen``
    holds files already taken.  The expanded model holds at most :data:`MAX_ELEMENTS`
    elements.  Included elements keep their own file and line for messages (``doc.included``
    lists the files).  Nested includes are expanded without recursion.
    """
    doc.included = getattr(doc, "included", [])
    first = {Path(doc.path).resolve(): None} | {s: None for s in seen}  # file -> where it was included
    count = sum(1 for _ in doc.root.iter())
    pending = list(reversed(_includes_in(doc.root)))  # a stack: document order
    while pending:
        parent, child = pending.pop()
        target, sub = _included(doc, child, base, first)
        count += sum(1 for _ in sub.root.iter()) - 2  # its <mujoco> root replaces the <include>
        if count > MAX_ELEMENTS:
            raise RobotFileError(f"{doc.where(child)}: <include file={child.get('file')!r}>: the expanded "
                                 f"model would hold more than {MAX_ELEMENTS} elements; refused")
        first[target] = doc.where(child)
        doc.merge(sub)
        doc.included.append(target)
        at = list(parent).index(child)
        parent.remove(child)
        for k, c in enumerate(list(sub.root)):
            parent.insert(at + k, c)
        found = [pair for c in sub.root for pair in _includes_in(c, parent)]
        pending.extend(reversed(found))


def _includes_in(el, parent=None) -> list:
    """``(parent, include)`` for ``el`` and every ``<include>`` inside it, in document order."""
    parents = {id(c): p for p in el.iter() for c in p}
    return [(parents.get(id(c), parent), c) for c in el.iter() if c.tag == "include"]


def _file_named(doc, el, base: Path):
    """``(where, resolved path, whether it is a file)`` of the ``file`` an ``<include>`` or
    ``<model>`` names, relative to ``base``; RobotFileError when it has none or cannot be looked up."""
    file = el.get("file")
    where = f"{doc.where(el)}: <{el.tag} file={file!r}>"
    if not file:
        raise RobotFileError(f"{doc.where(el)}: <{el.tag}> needs a file attribute")
    try:   # exists: anything at the path (a FIFO or a dangling link too: the reader names what it is)
        named = base / file
        exists = os.path.lexists(named)
        try:
            return where, named.resolve(), exists
        except RuntimeError:   # a symlink loop: its own path stands for it
            return where, Path(os.path.abspath(named)), exists
    except (OSError, ValueError) as exc:
        raise RobotFileError(f"{where}: the file name cannot be looked up "
                             f"({getattr(exc, 'strerror', None) or exc})") from None


def _included(doc, child, base: Path, first: dict):
    """``(path, Document)`` of the file an ``<include>`` names, refused if already included."""
    where, target, exists = _file_named(doc, child, base)
    if target in first:
        before = ("is the file being read (a cycle)" if first[target] is None
                  else f"was already included at {first[target]}")
        raise RobotFileError(f"{where}: {target} {before}; a file may be included only once (MuJoCo refuses "
                             "it twice too)")
    if not exists:
        raise RobotFileError(f"{where}: included file {child.get('file')!r} not found (relative to {base})")
    sub = parse_xml(base / child.get("file"))   # by the name given: a refusal names it
    if sub.root.tag != "mujoco":
        raise RobotFileError(f"{sub.where(sub.root)}: an included MJCF file must have a <mujoco> root, "
                             f"not <{sub.root.tag}>")
    return target, sub


def _fitted(a: dict, kind: str, meshes: dict, comp, where: str):
    """MuJoCo's fit of a primitive geom to its ``mesh``: ``(size, R_geom_fit, p_geom_fit)``."""
    from .geometry import mujoco_mesh_arrays
    from .mujoco_inertia import fit_primitive

    name = a["mesh"]
    if name not in meshes:
        raise InertiaError("it is not a mesh asset")
    params = meshes[name]
    v, f = mujoco_mesh_arrays(params)
    fitscale = floats(a.get("fitscale", "1"), 1, where, "fitscale")[0]
    return fit_primitive(kind, v, f, params["mujoco_inertia"], fitaabb=comp.fitaabb, fitscale=fitscale)


def _mesh_asset(doc, m, attrs: dict, mesh_dir: Path, search_paths):
    """``(name, params)`` of a ``<mesh>`` asset (file or ``vertex``/``face`` lists), MuJoCo's
    ``inertia`` mode, ``scale``, ``refpos`` and ``refquat`` included."""
    from .mujoco_inertia import MESH_INERTIA_MODES

    where = f"{doc.where(m)}: <mesh>"
    mode = attrs.get("inertia", "legacy")
    if mode not in MESH_INERTIA_MODES:
        raise RobotFileError(f"{where} inertia={mode!r} must be one of {', '.join(MESH_INERTIA_MODES)}")
    params = {"scale": floats(attrs.get("scale", "1 1 1"), 3, where, "mesh scale"), "mujoco_inertia": mode,
              "refpos": floats(attrs.get("refpos", "0 0 0"), 3, where, "mesh refpos"),
              "refquat": floats(attrs.get("refquat", "1 0 0 0"), 4, where, "mesh refquat"), "where": where}
    file = attrs.get("file")
    if file is not None:
        params.update(uri=file, path=resolve_mesh(file, mesh_dir, search_paths, where=doc.where(m)))
        return attrs.get("name") or Path(file).stem, params
    if "vertex" not in attrs:
        return None, params  # a mesh without shape (MuJoCo refuses it when a geom uses it)
    v = np.asarray(floats(attrs["vertex"], None, where, "mesh vertex"), float)
    if v.size < 12 or v.size % 3:
        raise RobotFileError(f"{where} vertex: needs at least 4 vertices of 3 numbers each, got {v.size} numbers")
    params.update(uri=None, path=None, vertices=v.reshape(-1, 3))
    if "face" in attrs:
        f = np.asarray(floats(attrs["face"], None, where, "mesh face"))
        if f.size % 3 or not np.all(f == np.round(f)) or np.any(f < 0) or np.any(f >= len(params["vertices"])):
            raise RobotFileError(f"{where} face: needs triples of vertex indices 0..{len(params['vertices']) - 1}")
        params["faces"] = f.astype(np.int64).reshape(-1, 3)
    if attrs.get("name") is None:
        raise RobotFileError(f"{where}: a mesh given by its vertices needs a name")
    return attrs["name"], params


def _geom(doc, a, el, comp, meshes, link) -> Geometry | None:
    where = f"{doc.where(el)}: body {link.name!r}: <geom>"
    kind = a.get("type", "sphere")
    if kind == "plane":  # MuJoCo refuses it in a body that moves (the tree checks say so)
        link.static_only.append(f"{where} type=\"plane\"")
    if kind in ("plane", "hfield", "sdf"):
        return None
    size = floats(a.get("size", ""), None, where, "geom size")
    R = _orientation(a, comp, where)
    p = np.asarray(floats(a.get("pos", "0 0 0"), 3, where, "geom pos"))
    density = floats(a["density"], 1, where, "geom density")[0] if "density" in a else 1000.0
    mass = floats(a["mass"], 1, where, "geom mass")[0] if "mass" in a else None
    if "fromto" in a and kind in ("capsule", "cylinder", "box", "ellipsoid"):
        ft = np.asarray(floats(a["fromto"], 6, where, "fromto"))
        if not size:
            raise RobotFileError(f"{where}: a {kind} given by fromto still needs its radius in size")
        a0, a1 = ft[:3], ft[3:]
        p = (a0 + a1) / 2
        axis = a1 - a0
        _unit(axis, where, "fromto", a["fromto"], "the segment between its end points")
        half = np.linalg.norm(axis) / 2
        R = _orientation({"zaxis": " ".join(repr(float(x)) for x in axis)}, comp, where)
        if kind in ("capsule", "cylinder"):
            size = [size[0], half]
        else:
            size = [size[0], size[1] if len(size) > 1 else size[0], half]
    need = {"sphere": 1, "capsule": 2, "cylinder": 2, "ellipsoid": 3, "box": 3}
    if kind in need and a.get("mesh") is not None:  # a primitive fitted to a mesh: MuJoCo sets its size
        if "fromto" in a:
            raise RobotFileError(f"{where}: fromto cannot be used with a mesh (MuJoCo refuses it too)")
        try:
            size, R_fit, p_fit = _fitted(a, kind, meshes, comp, where)
        except InertiaError as exc:
            link.notes.append(("geometry_unusable", f"{where}: {kind} fitted to mesh {a.get('mesh')!r}: {exc}"))
            return Geometry(kind, {"error": f"{kind} fitted to mesh {a.get('mesh')!r}: {exc}"}, R, p,
                            "collision", doc.line(el), density=density, mass=mass)
        p, R = p + R @ p_fit, R @ R_fit
    if kind in need and len(size) < need[kind]:
        raise RobotFileError(f"{where}: {kind} geom needs {need[kind]} size values, got {len(size)}")
    if kind == "sphere":
        params = {"radius": size[0]}
    elif kind in ("capsule", "cylinder"):
        params = {"radius": size[0], "length": 2 * size[1]}
    elif kind == "ellipsoid":
        params = {"semi_axes": size[:3]}
    elif kind == "box":
        params = {"size": [2 * s for s in size[:3]]}
    elif kind == "mesh":
        name = a.get("mesh")
        if name not in meshes:
            link.notes.append(("mesh_not_found", f"{where}: geom mesh {name!r} is not a mesh asset"))
            return None
        if a.get("shellinertia", "false") == "true":
            raise RobotFileError(f"{where}: shellinertia does not apply to mesh geoms; set inertia=\"shell\" on "
                                 f"the mesh asset {name!r} (MuJoCo refuses it too)")
        params = meshes[name]
        note = mesh_note(params["path"], params["uri"], None, f"{where}: mesh {name!r} file", "meshdir") \
            if params.get("uri") is not None else None
        link.notes += [note] if note else []
        params["unreadable"] = bool(note) and params.get("path") is not None
    else:
        link.notes.append(("unsupported_geometry", f"{where}: geom type {kind!r} is not supported"))
        return None
    if kind in need and a.get("shellinertia", "false") == "true":
        params["shell"] = True  # hollow: density per unit area (MuJoCo's shellinertia)
    group = floats(a.get("group", "0"), 1, where, "geom group")[0]
    lo, hi = comp.inertiagroups
    if (mass is None and density == 0) or mass == 0 or not lo <= group <= hi:
        # no mass in MuJoCo (a visual geom, or one outside <compiler inertiagrouprange>), but
        # its shape still describes the body: kept for the checks as a "visual" shape of
        # uniform density
        return Geometry(kind, params, R, p, "visual", doc.line(el))
    return Geometry(kind, params, R, p, "collision", doc.line(el), density=density, mass=mass)
