"""The kinematic tree of a URDF or SDF file: each link's parent, pose and joints.

Read when first needed (:func:`read_tree`), not by the readers: ``inertia check`` looks at
links one at a time and must not fail on a joint it does not use.  MJCF bodies nest, so the
MJCF reader records the same while it reads them.

URDF: ``<joint type>`` with ``<parent link>``, ``<child link>``, ``<origin xyz rpy>`` (the
child link's frame is the joint frame), ``<axis xyz>`` (default 1 0 0, in the joint frame)
and ``<mimic joint multiplier offset>``; one root link.  Types revolute and continuous
rotate, prismatic slides, fixed does not move, floating and planar stay at their default.

SDF: every link has its pose in the model frame (or ``relative_to`` another frame: links,
joints, ``<frame>`` elements, nested models); a joint's pose is relative to its child link,
its ``<axis><xyz>`` in the joint frame (``expressed_in`` another frame from SDF 1.7; in the
model frame with ``use_parent_model_frame`` in SDF 1.5 and 1.6, and always before 1.5).
Links no joint attaches are free bodies at their pose.  A lone ``<model>`` is expressed in
its own frame (its ``<pose>`` places it in some world); a ``<world>`` in the world frame.
Types revolute and continuous rotate, prismatic slides, fixed does not move; ball,
universal, revolute2, screw and gearbox stay at their default.
"""

from __future__ import annotations

import numpy as np

from .model import Joint
from .numbers import floats, rpy_matrix
from .sdf_frames import SdfFrames, sdf_frames
from .xmlsafe import RobotFileError

#: URDF joint type -> what it does (see :class:`~inertia.robots.model.Joint`)
URDF_KINDS = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slide", "fixed": "fixed",
              "floating": "floating", "planar": "planar"}
#: SDF joint type -> what it does
SDF_KINDS = {"revolute": "hinge", "continuous": "hinge", "prismatic": "slide", "fixed": "fixed", "ball": "ball",
             "universal": "universal", "revolute2": "revolute2", "screw": "screw", "gearbox": "gearbox"}


def read_tree(model) -> None:
    """Fill each link's ``parent``, ``R_parent_link``, ``p_parent_link`` and ``joints`` (and
    ``model.root_frame``) from a URDF or SDF document; MJCF models have them already."""
    if model.root_frame is not None:
        return
    if model.format == "urdf":
        _urdf_tree(model)
    elif model.format == "sdf":
        _sdf_tree(model)
    else:
        raise RobotFileError(f"{model.path}: no kinematic tree for format {model.format!r}")


def _unit_axis(xyz, where: str) -> np.ndarray:
    axis = np.asarray(xyz, float)
    n = float(np.linalg.norm(axis))
    if not n > 1e-12:
        raise RobotFileError(f"{where}: the joint axis {' '.join(f'{v:g}' for v in xyz)} has no direction")
    return axis / n


def _name_index(model) -> dict:
    index = {}
    for i, lk in enumerate(model.links):
        if lk.name in index:
            raise RobotFileError(f"{model.document.where(lk.element)}: a second link named {lk.name!r} (the first "
                                 f"is at line {model.links[index[lk.name]].line}); link names must be unique")
        index[lk.name] = i
    return index


# ------------------------------------------------------------------------------------- URDF


def _urdf_tree(model) -> None:
    doc = model.document
    index = _name_index(model)
    model.loop_joints = []
    by_child: dict = {}
    for el in doc.root.findall("joint"):
        where = f"{doc.where(el)}: joint {el.get('name')!r}"
        kind = URDF_KINDS.get(el.get("type"))
        if kind is None:
            raise RobotFileError(f"{where}: type={el.get('type')!r} must be one of {', '.join(URDF_KINDS)}")
        parent, child = (_urdf_link_ref(doc, el, tag, index, where) for tag in ("parent", "child"))
        if child in by_child:  # a kinematic loop (urdfdom reads it too): the first joint keeps the tree
            model.loop_joints.append((Joint(el.get("name"), kind, el.get("type"), line=doc.line(el)),
                                      model.links[child].name))
            continue
        by_child[child] = where
        link = model.links[child]
        link.parent = parent
        origin = el.find("origin")
        if origin is not None:
            ow = doc.where(origin)
            link.p_parent_link = np.array(floats(origin.get("xyz", "0 0 0"), 3, ow, "origin xyz"))
            link.R_parent_link = rpy_matrix(*floats(origin.get("rpy", "0 0 0"), 3, ow, "origin rpy"))
        axis_el = el.find("axis")
        xyz = floats(axis_el.get("xyz", "1 0 0") if axis_el is not None else "1 0 0", 3, where, "axis xyz")
        axis = _unit_axis(xyz, where) if kind in ("hinge", "slide") else np.array([1.0, 0.0, 0.0])
        link.joints = [Joint(el.get("name"), kind, el.get("type"), axis, np.zeros(3), 0.0, doc.line(el),
                             _mimic(doc, el.find("mimic"), where))]
    roots = [lk.name for lk in model.links if lk.parent is None]
    if not model.links:
        raise RobotFileError(f"{model.path}: the URDF holds no link")
    if len(roots) != 1:
        raise RobotFileError(f"{model.path}: a URDF has one root link (a link that is no joint's child); "
                             + (f"this one has {len(roots)}: {', '.join(map(repr, roots[:10]))}" if roots
                                else "here every link is a child: the joints form a cycle"))
    model.root_frame = f"root link {roots[0]!r}"


def _urdf_link_ref(doc, el, tag: str, index: dict, where: str) -> int:
    ref = el.find(tag)
    name = ref.get("link") if ref is not None else None
    if name is None:
        raise RobotFileError(f"{where}: needs <{tag} link=\"...\"/>")
    if name not in index:
        raise RobotFileError(f"{where}: {tag} link {name!r} is not a link of this file")
    return index[name]


def _mimic(doc, el, where: str):
    if el is None:
        return None
    master = el.get("joint")
    if not master:
        raise RobotFileError(f"{where}: <mimic> needs joint=\"...\"")
    mult = floats(el.get("multiplier", "1"), 1, doc.where(el), "mimic multiplier")[0]
    offset = floats(el.get("offset", "0"), 1, doc.where(el), "mimic offset")[0]
    return (master, mult, offset)


# ------------------------------------------------------------------------------------- SDF


def _sdf_tree(model) -> None:
    doc = model.document
    frames = sdf_frames(doc)
    models, lone = frames.top, frames.lone
    index = {}
    for i, lk in enumerate(model.links):
        name = frames.links.get(id(lk.element))
        if name is None:
            raise RobotFileError(f"{doc.where(lk.element)}: link {lk.name!r} is not inside a <model>")
        index[name] = i
        lk.scoped_name = name if "::" in name else None
        lk.R_parent_link, lk.p_parent_link = frames.pose(name)
    version = frames.version
    model.loop_joints = []
    for scope, el in frames.joints:
        _sdf_joint(model, frames, index, scope, el, version)
    model.root_frame = f"model {models[0].get('name')!r}" if lone else "world"


def _sdf_joint(model, frames: SdfFrames, index: dict, scope: str, el, version: float) -> None:
    doc = frames.doc
    where = f"{doc.where(el)}: joint {el.get('name')!r}"
    kind = SDF_KINDS.get(el.get("type"))
    if kind is None:
        raise RobotFileError(f"{where}: type={el.get('type')!r} must be one of {', '.join(SDF_KINDS)}")
    ends = []
    for tag in ("parent", "child"):
        text = (el.findtext(tag) or "").strip()
        name = frames.resolve_name(text, scope, where) if text else None
        if name is not None and name not in index:
            raise RobotFileError(f"{where}: {tag} {text!r} is not a link of this model")
        if name is None and tag == "child":
            raise RobotFileError(f"{where}: needs a <child> link")
        ends.append(None if name is None else index[name])
    parent, child = ends
    link = model.links[child]
    if link.joints:  # a kinematic loop: the link keeps its first joint, this one is named in the report
        model.loop_joints.append((Joint(scope + el.get("name", ""), kind, el.get("type"), line=doc.line(el)),
                                  link.name))
        return
    R_rc, p_rc = frames.pose(frames.links[id(link.element)])
    R_rj, p_rj = frames.pose(frames.joint_key(scope, el.get("name", "")))
    axis = np.array([0.0, 0.0, 1.0])
    if kind in ("hinge", "slide"):
        axis = R_rc.T @ _sdf_axis(frames, el, scope, version, R_rj, where)
    link.joints = [Joint(scope + el.get("name", ""), kind, el.get("type"), axis, R_rc.T @ (p_rj - p_rc), 0.0,
                         doc.line(el))]
    if parent is not None:  # the pose relative to the parent link, at the default configuration
        R_rp, p_rp = frames.pose(frames.links[id(model.links[parent].element)])
        link.parent = parent
        link.R_parent_link, link.p_parent_link = R_rp.T @ R_rc, R_rp.T @ (p_rc - p_rp)


def _sdf_axis(frames: SdfFrames, el, scope: str, version: float, R_rj, where: str) -> np.ndarray:
    """The joint axis in the root frame, from ``<axis><xyz>`` and the version's rule."""
    doc = frames.doc
    axis_el = el.find("axis")
    xyz_el = axis_el.find("xyz") if axis_el is not None else None
    xyz = _unit_axis(floats(xyz_el.text if xyz_el is not None else "0 0 1", 3, where, "axis xyz"), where)
    if version >= 1.07:
        expressed = xyz_el.get("expressed_in") if xyz_el is not None else None
        if not expressed:
            return R_rj @ xyz
        return frames.pose(frames.resolve_name(expressed, scope, doc.where(xyz_el)))[0] @ xyz
    in_model = version < 1.05 or (axis_el.findtext("use_parent_model_frame") or "").strip() in ("true", "1")
    return (frames.pose(frames.models[scope])[0] if in_model else R_rj) @ xyz
