"""URDF and SDF readers (the two formats share their inertial and geometry vocabulary).

URDF: ``<link><inertial><origin xyz rpy/><mass value/><inertia ixx ixy ixz iyy iyz izz/>``
with the tensor elements in the frame of ``<origin>`` (rpy = fixed-axis roll, pitch, yaw:
``R = Rz(yaw) Ry(pitch) Rx(roll)``), and ``<collision>``/``<visual>`` geometry: ``box size``
(full edges), ``cylinder radius length`` (along z), ``sphere radius``, ``mesh filename
scale``.

SDF: ``<link><inertial><pose>x y z roll pitch yaw</pose><mass>``
``<inertia><ixx>...</inertia>``, and geometry ``<box><size>``, ``<cylinder><radius><length>``,
``<sphere><radius>``, ``<capsule>``, ``<ellipsoid><radii>``, ``<mesh><uri><scale>``; poses in
every form of :func:`~inertia.robots.sdf_frames.sdf_pose` (a shape's ``relative_to`` any frame of
its model; an inertial's only the link's, as libsdformat requires); ``<include>`` followed as
libsdformat follows it; links are ``<model>``'s children (not those of a plugin or a state).
URDF links are ``<robot>``'s children, as urdfdom reads them.

Both write products as tensor elements (``ixy = -sum m x y``): our convention.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np

from .model import Geometry, Inertial, Link, RobotModel
from .numbers import floats, rpy_matrix  # noqa: F401  (read from here by the other readers)
from .resolve import mesh_note, resolve_mesh
from .sdf_frames import sdf_models, sdf_pose, sdf_version
from .xmlsafe import RobotFileError, parse_robot_xml, read_robot_bytes


def _link_elements(doc, root):
    """``(element, Link, <inertial> or None)`` for every link of a URDF: the ``<link>`` children
    of ``<robot>``, as urdfdom reads them (a ``<link>`` inside ``<gazebo>``, a ``<plugin>``, a
    ``<transmission>`` or any other element is that element's business, not a link)."""
    for el in root.findall("link"):
        name = el.get("name") or f"<unnamed link at line {doc.line(el)}>"
        yield el, Link(name, doc.line(el), None, element=el), el.find("inertial")


def _add_shapes(link, el, parse) -> None:
    """Append every ``<collision>`` then ``<visual>`` shape of ``el`` that ``parse(element, role)`` reads."""
    for role in ("collision", "visual"):
        for g in el.findall(role):
            geom = parse(g, role)
            if geom is not None:
                link.geometries.append(geom)


def _inertia_matrix(ixx, iyy, izz, ixy, ixz, iyz) -> np.ndarray:
    return np.array([[ixx, ixy, ixz], [ixy, iyy, iyz], [ixz, iyz, izz]], dtype=float)


# ------------------------------------------------------------------------------------- URDF


#: URDF attributes urdfdom reads as one number (``strToDouble``: no whitespace after it) and as
#: a list of numbers split at spaces (a newline or tab between them is part of a number)
_URDF_ONE_NUMBER = frozenset(("value", "ixx", "ixy", "ixz", "iyy", "iyz", "izz", "radius", "length", "lower", "upper",
                              "effort", "velocity", "multiplier", "offset", "damping", "friction"))
_URDF_NUMBERS = frozenset(("xyz", "rpy", "size", "scale", "rgba"))


def _urdf_ros_numbers(doc, root) -> None:
    """Warn (``doc.notes``) of numbers urdfdom refuses although they read fine as XML.

    urdfdom, which ROS and Pinocchio read URDF with, converts a number with ``strToDouble``:
    whitespace after it ("1.5 ", a line break) fails ("is not a float"), and a list such as
    ``xyz`` is split at spaces only, so a line break or tab between two numbers fails too.
    Pinocchio then drops the link's inertial (mass 0) without failing.
    """
    from .edit import SourceEditor

    editor = None
    for top in [*root.findall("link"), *root.findall("joint")]:
        for el in top.iter():
            bad = [k for k, v in el.attrib.items() if k in _URDF_ONE_NUMBER and v != v.rstrip()]
            if any(k in _URDF_NUMBERS for k in el.attrib) and doc.start_byte(el) is not None:
                editor = editor or SourceEditor(doc)
                start, end, _ = editor.start_tag(el)
                tag = doc.source[start:end]
                if b"\n" in tag or b"\t" in tag or b"\r" in tag:
                    for k, (_, a, b) in editor.attributes(el).items():
                        pieces = doc.source[a:b].decode("utf-8", "replace").split(" ")
                        if k in _URDF_NUMBERS and any(p.strip() and p.lstrip() != p.split()[0] for p in pieces):
                            bad.append(k)  # a piece between spaces holds whitespace after its number
            for k in bad:
                doc.notes.append(("ros_unreadable_number", (
                    f"{doc.where(el)}: <{el.tag} {k}={el.get(k)!r}>: read here, but urdfdom (ROS, Pinocchio) refuses "
                    "it: whitespace after a number (a line break, a trailing space) is \"not a float\" there, and "
                    "Pinocchio then drops the link's inertial; write the numbers separated by single spaces")))


def read_urdf(path, *, search_paths=(), document=None) -> RobotModel:
    """The links, joints, inertials and geometries of a URDF file.

    ``search_paths``: folders that ``package://`` and relative mesh paths resolve against;
    ``document``: the file already parsed (e.g. expanded by xacro); read from ``path`` otherwise.
    """
    doc = document if document is not None else parse_robot_xml(path, "robot", "a URDF")
    root = doc.root
    _urdf_ros_numbers(doc, root)
    base = Path(path).resolve().parent
    links = []
    for el, link, inertial in _link_elements(doc, root):
        if inertial is not None:
            link.inertial = _urdf_inertial(doc, inertial)
        _add_shapes(link, el, lambda g, role: _urdf_geometry(doc, g, role, base, search_paths, link))
        links.append(link)
    return RobotModel(Path(path), "urdf", links, doc)


def _urdf_origin(doc, parent):
    origin = parent.find("origin")
    if origin is None:
        return np.eye(3), np.zeros(3)
    where = doc.where(origin)
    xyz = floats(origin.get("xyz", "0 0 0"), 3, where, "origin xyz")
    rpy = floats(origin.get("rpy", "0 0 0"), 3, where, "origin rpy")
    return rpy_matrix(*rpy), np.array(xyz)


def _urdf_inertial(doc, el) -> Inertial:
    where = doc.where(el)
    R, p = _urdf_origin(doc, el)
    m_el = el.find("mass")
    if m_el is None or m_el.get("value") is None:
        raise RobotFileError(f"{where}: <inertial> without <mass value=...>")
    mass = floats(m_el.get("value"), 1, doc.where(m_el), "mass value")[0]
    i_el = el.find("inertia")
    if i_el is None:
        raise RobotFileError(f"{where}: <inertial> without <inertia>")
    vals = {}
    for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"):
        if i_el.get(k) is None:  # urdfdom refuses it too: no silent zero
            raise RobotFileError(f"{doc.where(i_el)}: <inertia> has no {k}=...; URDF needs all six of "
                                 "ixx, iyy, izz, ixy, ixz, iyz")
        vals[k] = floats(i_el.get(k), 1, doc.where(i_el), f"inertia {k}")[0]
    return Inertial(mass, p, R, _inertia_matrix(**vals), doc.line(el), el)


def _urdf_geometry(doc, el, role, base, search_paths, link) -> Geometry | None:
    g = el.find("geometry")
    if g is None:  # urdfdom refuses it too
        raise RobotFileError(f"{doc.where(el)}: link {link.name!r}: <{role}> has no <geometry>")
    shapes = [c for c in g if isinstance(c.tag, str)]
    if not shapes:  # urdfdom refuses the file too
        raise RobotFileError(f"{doc.where(g)}: link {link.name!r}: {role} <geometry> holds no shape "
                             "(box, cylinder, sphere or mesh)")
    R, p = _urdf_origin(doc, el)
    shape = shapes[0]
    where = doc.where(shape)
    if shape.tag == "box":
        params = {"size": floats(shape.get("size"), 3, where, "box size")}
    elif shape.tag == "sphere":
        params = {"radius": floats(shape.get("radius"), 1, where, "sphere radius")[0]}
    elif shape.tag in ("cylinder", "capsule"):
        params = {"radius": floats(shape.get("radius"), 1, where, f"{shape.tag} radius")[0],
                  "length": floats(shape.get("length"), 1, where, f"{shape.tag} length")[0]}
    elif shape.tag == "mesh":
        uri = shape.get("filename") or ""
        scale = floats(shape.get("scale", "1 1 1"), 3, where, "mesh scale")
        found = resolve_mesh(uri, base, search_paths, where=f"{where}: link {link.name!r}")
        note = mesh_note(found, uri, base, f"{where}: {role} mesh")
        link.notes += [note] if note else []
        params = {"path": found, "uri": uri, "scale": scale, "unreadable": bool(note) and found is not None}
    else:
        link.notes.append(("unsupported_geometry", f"{where}: {role} geometry <{shape.tag}> is not supported"))
        return None
    return Geometry(shape.tag, params, R, p, role, doc.line(shape))


# ------------------------------------------------------------------------------------- SDF


def _text(el, tag, default=None):
    c = el.find(tag)
    return default if c is None or c.text is None else c.text


def _sdf_number(doc, parent, tag: str, default: float, what: str) -> float:
    """The number in ``parent``'s ``<tag>``; ``default`` (SDF's) only when there is no such element.

    An empty or non-numeric element is a RobotFileError naming it: SDF's default is for an
    absent element, never for a value that was meant and lost.
    """
    el = parent.find(tag)
    if el is None:
        return default
    where = f"{doc.where(el)}: {what}: <{tag}>"
    if not (el.text or "").strip():
        raise RobotFileError(f"{where} is empty; write its value (or remove the element for SDF's default)")
    return floats(el.text, 1, where, "the value")[0]


def read_sdf(path, *, search_paths=(), document=None) -> RobotModel:
    """The links, joints, inertials and geometries of an SDF model (``model://`` resolved next to
    the model folder and in ``search_paths``; ``document``: the file already parsed)."""
    doc = document if document is not None else parse_robot_xml(path, "sdf", "an SDF")
    root = doc.root
    base = Path(path).resolve().parent
    search = list(search_paths) + [base.parent]  # model://NAME resolves next to the model folder
    version = sdf_version(doc)
    _expand_sdf_includes(doc, base, search)
    models = sdf_models(root)
    links = []
    frames = _LinkFrames(doc)
    for el in [lk for m in models for lk in m.findall("link")]:
        name = el.get("name") or f"<unnamed link at line {doc.line(el)}>"
        link = Link(name, doc.line(el), None, element=el)
        inertial = el.find("inertial")
        if inertial is not None:
            rel, R, p = sdf_pose(doc, inertial, version)
            if rel not in (None, name):
                link.notes.append(("unsupported_pose", f"{doc.where(inertial)}: inertial pose relative_to={rel!r}: "
                                   "libsdformat refuses any frame but the link's (the inertial frame is always "
                                   "relative to the link); read as relative to the link"))
            mass = _sdf_number(doc, inertial, "mass", 1.0, f"link {name!r}")
            i_el = inertial.find("inertia")
            vals = {k: 0.0 for k in ("ixy", "ixz", "iyz")} | {k: 1.0 for k in ("ixx", "iyy", "izz")}  # SDF defaults
            if i_el is not None:
                for k in vals:
                    vals[k] = _sdf_number(doc, i_el, k, vals[k], f"link {name!r}")
            link.inertial = Inertial(mass, p, R, _inertia_matrix(**vals), doc.line(inertial), inertial)
        _add_shapes(link, el, lambda g, role: _sdf_geometry(doc, g, role, base, search, link, version, frames))
        links.append(link)
    return RobotModel(Path(path), "sdf", links, doc)


#: most ``<include>`` elements an SDF document may expand (a guard against include bombs)
MAX_SDF_INCLUDES = 10_000


def _expand_sdf_includes(doc, base: Path, search) -> None:
    """Replace each ``<include>`` of a ``<world>`` or ``<model>`` by the model it names, as
    libsdformat does: ``<uri>`` (``model://NAME``, or a path relative to the file's folder) is a
    model folder (its ``model.config`` names the SDF file of each version: the newest is read)
    or an SDF file; the include's ``<name>``, ``<pose>`` and ``<static>`` replace the model's.
    An include of something else (a light, an actor) adds no link and is dropped.  Included
    elements keep their own file and line for messages (``doc.included`` lists the files).
    """
    doc.included = getattr(doc, "included", [])
    pending = [(holder, c) for holder in [*doc.root.findall("world"), *sdf_models(doc.root)]
               for c in holder.findall("include")]
    while pending:
        holder, inc = pending.pop(0)
        if len(doc.included) >= MAX_SDF_INCLUDES:
            raise RobotFileError(f"{doc.where(inc)}: more than {MAX_SDF_INCLUDES} <include> elements; refused")
        uri = (inc.findtext("uri") or "").strip()
        where = f"{doc.where(inc)}: <include> of {uri or '(no uri)'!r}"
        target = _included_sdf(uri, base, search, where)
        sub = parse_robot_xml(target, "sdf", "an SDF")
        doc.merge(sub)
        doc.included.append(target)
        at = list(holder).index(inc)
        holder.remove(inc)
        model = sub.root.find("model")
        if model is None:
            continue
        if inc.find("name") is not None:
            model.set("name", (inc.findtext("name") or "").strip())
        for tag in ("static", "pose"):  # the include's own replace the model's
            if inc.find(tag) is not None:
                for old in model.findall(tag):
                    model.remove(old)
                model.insert(0, inc.find(tag))
        holder.insert(at, model)
        pending += [(m, c) for m in [model, *sdf_models(model)[1:]] for c in m.findall("include")]


def _included_sdf(uri: str, base: Path, search, where: str) -> Path:
    """The SDF file an ``<include><uri>`` names (see :func:`_expand_sdf_includes`)."""
    import re

    if uri.startswith("model://"):
        name, _, rest = uri[len("model://"):].partition("/")
        folders = [d / name / rest for d in [*map(Path, search), base, *base.parents]]
    elif "://" in uri:
        raise RobotFileError(f"{where}: only model:// and file paths are followed (nothing is fetched)")
    else:
        folders = [Path(uri) if Path(uri).is_absolute() else base / uri]
    found = next((f for f in folders if os.path.lexists(f)), None)
    if found is None:
        raise RobotFileError(f"{where}: not found (model:// is searched in each --package-path folder and the "
                             "file's parent folders)")
    if not found.is_dir():
        return found   # a file, or something the reader names (a FIFO, a dangling link)
    config = found / "model.config"
    if os.path.lexists(config):
        listed = re.findall(rb"""<sdf[^>]*version\s*=\s*["']([\d.]+)["'][^>]*>\s*([^<\s]+)\s*</sdf>""",
                            read_robot_bytes(config, "model.config"))
        if listed:
            _, file = max(listed, key=lambda v: tuple(int(x) for x in v[0].split(b".") if x.isdigit()))
            if os.path.lexists(found / file.decode()):
                return found / file.decode()
    if os.path.lexists(found / "model.sdf"):
        return found / "model.sdf"
    raise RobotFileError(f"{where}: the model folder {found} names no SDF file (model.config, model.sdf)")


class _LinkFrames:
    """Poses of a link's shapes given ``relative_to`` another frame: read in the link frame
    through the model's frame graph (built on first use)."""

    def __init__(self, doc):
        self.doc, self.frames = doc, None

    def in_link(self, link_el, rel: str, R, p):
        """``(R_link_shape, p_link_shape)`` of a pose ``(R, p)`` relative to frame ``rel``."""
        from .sdf_frames import sdf_frames

        if self.frames is None:
            self.frames = sdf_frames(self.doc)
        link = self.frames.links[id(link_el)]
        scope = link[: link.rfind("::") + 2] if "::" in link else ""
        R_l, p_l = self.frames.pose(link)
        R_f, p_f = self.frames.pose(self.frames.resolve_name(rel, scope, self.doc.where(link_el)))
        return R_l.T @ R_f @ R, R_l.T @ (R_f @ p + p_f - p_l)


def _sdf_geometry(doc, el, role, base, search, link, version, frames) -> Geometry | None:
    g = el.find("geometry")
    if g is None:  # required by the SDF specification
        raise RobotFileError(f"{doc.where(el)}: link {link.name!r}: <{role}> has no <geometry>")
    shapes = [c for c in g if isinstance(c.tag, str)]
    if not shapes:
        return None
    shape = shapes[0]
    rel, R, p = sdf_pose(doc, el, version)
    if rel not in (None, link.name):
        R, p = frames.in_link(link.element, rel, R, p)
    where = doc.where(shape)
    if shape.tag == "box":
        params = {"size": floats(_text(shape, "size"), 3, where, "box size")}
    elif shape.tag == "sphere":
        params = {"radius": floats(_text(shape, "radius"), 1, where, "sphere radius")[0]}
    elif shape.tag in ("cylinder", "capsule"):
        params = {"radius": floats(_text(shape, "radius"), 1, where, f"{shape.tag} radius")[0],
                  "length": floats(_text(shape, "length"), 1, where, f"{shape.tag} length")[0]}
    elif shape.tag == "ellipsoid":
        params = {"semi_axes": floats(_text(shape, "radii"), 3, where, "ellipsoid radii")}
    elif shape.tag == "mesh":
        uri = (_text(shape, "uri") or "").strip()
        scale = floats(_text(shape, "scale", "1 1 1"), 3, where, "mesh scale")
        found = resolve_mesh(uri, base, search, where=f"{where}: link {link.name!r}")
        note = mesh_note(found, uri, base, f"{where}: {role} mesh")
        link.notes += [note] if note else []
        params = {"path": found, "uri": uri, "scale": scale, "unreadable": bool(note) and found is not None}
    elif shape.tag in ("plane", "heightmap", "empty"):
        return None
    else:
        link.notes.append(("unsupported_geometry", f"{where}: {role} geometry <{shape.tag}> is not supported"))
        return None
    return Geometry(shape.tag, params, R, p, role, doc.line(shape))
