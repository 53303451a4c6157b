"""SDF's frames: the version, the pose of an element in every form the specification writes, the
models of a document, and the named frames of each model with their poses in the root frame
(``relative_to`` from SDF 1.7 on; before it each pose has its element's default frame, and
joints have a namespace of their own)."""

from __future__ import annotations

import math

import numpy as np

from .numbers import floats, rpy_matrix
from .xmlsafe import RobotFileError


def sdf_version(doc) -> float:
    """The ``<sdf version>`` as a number that orders versions (1.10 after 1.9); 1.7 when absent."""
    text = doc.root.get("version", "1.7")
    try:
        major, minor = (int(x) for x in text.split(".")[:2])
    except ValueError:
        raise RobotFileError(f"{doc.where(doc.root)}: <sdf version={text!r}> is not a version number") from None
    return major + minor / 100


def sdf_pose(doc, parent, version: float):
    """``(relative_to or None, R, p)`` of ``parent``'s ``<pose>``, in every form SDF writes it.

    ``x y z roll pitch yaw`` (radians; degrees with ``degrees="true"``) or, with
    ``rotation_format="quat_xyzw"``, ``x y z qx qy qz qw`` (SDF 1.9).  ``relative_to`` is
    SDF 1.7's: earlier versions have no such attribute (every pose is relative to its
    element's default frame), so it is not read there.
    """
    pose = parent.find("pose")
    if pose is None:
        return None, np.eye(3), np.zeros(3)
    where = f"{doc.where(pose)}: <pose>"
    fmt = pose.get("rotation_format", "euler_rpy")
    if fmt not in ("euler_rpy", "quat_xyzw"):
        raise RobotFileError(f"{where}: rotation_format={fmt!r} must be euler_rpy or quat_xyzw")
    v = floats(pose.text or "0 0 0 0 0 0", 7 if fmt == "quat_xyzw" else 6, where, "pose")
    if fmt == "quat_xyzw":
        from .._core.rotations import quat_normalize, quat_to_matrix

        if not any(v[3:]):
            raise RobotFileError(f"{where}: the quaternion {v[3:]} has zero length")
        R = quat_to_matrix(quat_normalize([v[6], v[3], v[4], v[5]]))
    else:
        degrees = pose.get("degrees", "false").strip().lower() in ("true", "1")
        R = rpy_matrix(*([math.radians(a) for a in v[3:]] if degrees else v[3:]))
    rel = pose.get("relative_to") if version >= 1.07 else None
    return rel or None, R, np.asarray(v[:3], float)


def sdf_models(root) -> list:
    """Every ``<model>`` of an SDF document (of its worlds, top-level, nested), in document order."""
    out, stack = [], [root]
    while stack:
        el = stack.pop()
        if el.tag == "model":
            out.append(el)
        stack.extend(reversed([c for c in el if c.tag in ("world", "model")]))
    return out


class SdfFrames:
    """The named frames of an SDF document and their poses in the root frame."""

    def __init__(self, doc):
        self.doc = doc
        self.version = sdf_version(doc)
        self.raw: dict = {}        # scoped name -> (relative_to scoped name or None, R, p, where)
        self.done: dict = {None: (np.eye(3), np.zeros(3))}
        self.joints: list = []     # (scope, element)
        self.links: dict = {}      # id(element) -> scoped name
        self.models: dict = {}     # scope -> model frame name

    def add_model(self, m, scope: str, parent_scope: str, parent_frame, placed: bool) -> None:
        """Record model ``m``'s frames under ``scope`` ("name::", "" for a lone model).

        A frame's ``relative_to`` is kept as ``(scope, name)`` until its pose is asked for
        (a name may refer to a frame declared further down)."""
        doc = self.doc
        frame = scope + "__model__"
        v = self.version
        rel, R, p = sdf_pose(doc, m, v) if placed else (None, np.eye(3), np.zeros(3))
        self.raw[frame] = ((parent_scope, rel) if rel else parent_frame, R, p, doc.where(m))
        self.models[scope] = frame
        for link in m.findall("link"):
            name = scope + link.get("name", "")
            rel, R, p = sdf_pose(doc, link, v)
            self.raw[name] = ((scope, rel) if rel else frame, R, p, doc.where(link))
            self.links[id(link)] = name
        for f in m.findall("frame") if v >= 1.07 else ():  # <frame> is SDF 1.7's
            rel, R, p = sdf_pose(doc, f, v)
            self.raw[self.unique(scope, f, "frame")] = ((scope, rel or f.get("attached_to") or "__model__"), R, p,
                                                        doc.where(f))
        for j in m.findall("joint"):
            rel, R, p = sdf_pose(doc, j, v)
            self.raw[self.joint_key(scope, j.get("name", ""), j)] = (
                (scope, rel or (j.findtext("child") or "").strip()), R, p, doc.where(j))
            self.joints.append((scope, j))
        for nested in m.findall("model"):
            inner = scope + nested.get("name", "") + "::"
            self.add_model(nested, inner, scope, frame, True)
            self.raw[scope + nested.get("name", "")] = (inner + "__model__", np.eye(3), np.zeros(3), doc.where(nested))

    def unique(self, scope: str, el, kind: str) -> str:
        """The scoped name of a frame-carrying element, refused when a link, joint or frame of the
        model already has it (SDF 1.7 puts them in one namespace; libsdformat refuses it too)."""
        name = scope + el.get("name", "")
        if name in self.raw:
            raise RobotFileError(f"{self.doc.where(el)}: {kind} {el.get('name')!r}: a link, joint or frame of this "
                                 f"model already has that name ({self.raw[name][3]}); from SDF 1.7 on they share one "
                                 "namespace, and libsdformat refuses the file")
        return name

    def joint_key(self, scope: str, name: str, el=None) -> str:
        """Where a joint's frame is kept: in the frames' namespace from SDF 1.7 on; before it
        (1.4 to 1.6) joints have a namespace of their own (a joint may share a link's name)."""
        if self.version < 1.07:
            return scope + name + "\x00joint"
        return self.unique(scope, el, "joint") if el is not None else scope + name

    def resolve_name(self, name: str, scope: str, where: str):
        """The scoped frame ``name`` means in ``scope`` ("world": None)."""
        if name == "world":
            return None
        full = scope + name
        if full in self.raw or full == scope + "__model__":
            return full
        raise RobotFileError(f"{where}: no frame named {name!r} (links, joints, frames and nested models of "
                             "this model)")

    def pose(self, name):
        """``(R_root_frame, p_root_frame)`` of a scoped frame, following ``relative_to``."""
        chain, seen = [], set()
        while name not in self.done:
            if name in seen:
                raise RobotFileError(f"{self.raw[name][3]}: the poses' relative_to form a cycle through "
                                     f"{', '.join(sorted(seen))}")
            seen.add(name)
            rel, R, p, where = self.raw[name]
            if isinstance(rel, tuple):
                rel = self.resolve_name(rel[1], rel[0], where) if rel[1] else rel[0] + "__model__"
            chain.append((name, rel, R, p))
            name = rel
        for frame, rel, R, p in reversed(chain):
            R0, p0 = self.done[rel]
            self.done[frame] = (R0 @ R, R0 @ p + p0)
        return self.done[chain[0][0]] if chain else self.done[name]


def sdf_frames(doc) -> SdfFrames:
    """The frames of every model of an SDF document (see :class:`SdfFrames`)."""
    frames = SdfFrames(doc)
    worlds = doc.root.findall("world")
    models = [m for w in worlds for m in w.findall("model")] if worlds else doc.root.findall("model")
    frames.lone = not worlds and len(models) == 1
    frames.top = models
    for m in models:
        frames.add_model(m, "" if frames.lone else m.get("name", "") + "::", "", None, not frames.lone)
    return frames
