"""Forward kinematics: the pose of every link of a robot file at a joint configuration.

A link's pose in the root frame is its parent's pose, times its declared pose in the parent
(every joint at its default), times the motion of its joints in order: a hinge turns the
link by ``value - default`` about its axis through its anchor, a slide moves it by
``value - default`` along its axis (both in the link frame).  This is MuJoCo's
``mj_kinematics`` for MJCF (``default`` = ``qpos0``, the joint's ``ref``) and the URDF/SDF
convention (default 0).  Ball, free, floating, planar and the other multi-axis joints stay at
their default: the link at its declared pose.

Values are SI: radians for hinges, metres for slides.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InputError
from .._core.rotations import quat_from_rotvec, quat_to_matrix

#: joint kinds that take a value
MOVING = ("hinge", "slide")


def _tree(model):
    from .tree import read_tree

    read_tree(model)
    return model


def joints_of(model) -> dict:
    """Named joints of the model: name -> (link index, :class:`~inertia.robots.model.Joint`)."""
    _tree(model)
    out = {}
    for i, lk in enumerate(model.links):
        for j in lk.joints:
            if j.name:
                out[j.name] = (i, j)
    return out


def configuration(model, joints=None) -> dict:
    """Every named hinge and slide joint's value: ``joints`` (name -> value) over the defaults.

    A name that is no joint of the model, a joint that takes no value (fixed, ball, free,
    ...) or one that mimics another is an :class:`~inertia.errors.InputError` naming it.
    """
    named = joints_of(model)
    values = {name: j.default for name, (_, j) in named.items() if j.kind in MOVING and j.mimic is None}
    for name, value in (joints or {}).items():
        if name not in named:
            movable = [n for n in values]
            listed = ", ".join(movable[:30]) + (f", ... ({len(movable)} in all)" if len(movable) > 30 else "")
            raise InputError(f"{model.path}: no joint named {name!r}; the joints that take a value are: "
                             f"{listed or 'none'}")
        j = named[name][1]
        if j.kind not in MOVING:
            what = "is fixed: it has no value" if j.kind == "fixed" else (
                f"is a {j.type} joint: only its default configuration is supported")
            raise InputError(f"{model.path}:{j.line}: joint {name!r} {what}")
        if j.mimic is not None:
            raise InputError(f"{model.path}:{j.line}: joint {name!r} mimics joint {j.mimic[0]!r} (value = "
                             f"{j.mimic[1]:g} x {j.mimic[0]} + {j.mimic[2]:g}); give {j.mimic[0]!r} a value instead")
        value = float(value)
        if not math.isfinite(value):
            raise InputError(f"joint {name!r}: the value must be finite, got {value!r}")
        values[name] = value
    for name, (_, j) in named.items():
        if j.kind in MOVING and j.mimic is not None:
            values[name] = _mimic_value(model, named, values, name)
    return values


def _mimic_value(model, named: dict, values: dict, name: str) -> float:
    """A mimic joint's value, following chains of mimics."""
    scale, offset, seen = 1.0, 0.0, {name}
    j = named[name][1]
    while j.mimic is not None:
        master, mult, off = j.mimic
        if master not in named:
            raise InputError(f"{model.path}:{j.line}: joint {j.name!r} mimics {master!r}, which is no joint "
                             "of this file")
        if master in seen:
            raise InputError(f"{model.path}:{j.line}: joints mimic each other in a cycle: {', '.join(sorted(seen))}")
        seen.add(master)
        scale, offset = scale * mult, offset + scale * off  # A = scale X + offset, X = mult Y + off
        j = named[master][1]
    return scale * values.get(j.name, j.default) + offset


def order(model) -> list:
    """Link indices, every parent before its children; an error names a cycle."""
    _tree(model)
    children: dict = {}
    for i, lk in enumerate(model.links):
        children.setdefault(lk.parent, []).append(i)
    out, stack = [], list(reversed(children.get(None, [])))
    while stack:
        i = stack.pop()
        out.append(i)
        stack.extend(reversed(children.get(i, [])))
    if len(out) != len(model.links):
        lost = [model.links[i].name for i in range(len(model.links)) if i not in set(out)]
        raise InputError(f"{model.path}: links {', '.join(map(repr, lost[:10]))} are not connected to the root: "
                         "their joints form a cycle")
    return out


def link_poses(model, joints=None):
    """``(poses, values)``: each link's ``(R_root_link, p_root_link)`` (list, in
    ``model.links`` order) at the configuration, and the configuration used (name -> value).

    ``joints``: name -> value [rad or m] for hinge and slide joints; the others take their
    default (MJCF ``qpos0``, URDF and SDF 0).  The root frame is ``model.root_frame``.
    """
    values = configuration(model, joints)
    poses: list = [None] * len(model.links)
    for i in order(model):
        lk = model.links[i]
        R0, p0 = (np.eye(3), np.zeros(3)) if lk.parent is None else poses[lk.parent]
        R, p = R0 @ lk.R_parent_link, R0 @ lk.p_parent_link + p0
        for j in lk.joints:
            if j.kind not in MOVING:
                continue
            d = values.get(j.name, j.default) - j.default if j.name else 0.0
            if d == 0.0:
                continue
            if j.kind == "slide":
                p = p + R @ (j.axis * d)
            else:  # rotate about the axis through the anchor: x -> anchor + Rj (x - anchor)
                Rj = quat_to_matrix(quat_from_rotvec(j.axis * d))
                p = p + R @ (j.anchor - Rj @ j.anchor)
                R = R @ Rj
        poses[i] = (R, p)
    return poses, values
