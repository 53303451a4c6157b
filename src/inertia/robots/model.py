"""What the readers return: links with their declared inertial and their geometry.

Frames: every pose is in the **link frame** (URDF link, SDF link, MJCF body).
``Inertial.inertia_com`` is the declared tensor about the center of mass in the link axes
(negated products, ``L = I w``); ``Inertial.inertia_com_inertial`` is the same tensor as
written, in the inertial frame's axes (``inertia_com = R_link_inertial I R_link_inertial^T``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError


@dataclass
class Inertial:
    """A declared inertial: mass [kg], COM [m, link frame], tensor [kg m^2] and where it was written."""

    mass: float
    com_link: np.ndarray
    R_link_inertial: np.ndarray
    inertia_com_inertial: np.ndarray
    line: int | None = None
    element: object = None
    #: MJCF: how the tensor was written ("fullinertia" or "diaginertia"; MuJoCo judges them apart)
    form: str | None = None

    @property
    def inertia_com(self) -> np.ndarray:
        """The declared tensor about the COM in the link axes (kg m^2)."""
        R = self.R_link_inertial
        return R @ self.inertia_com_inertial @ R.T


@dataclass
class Geometry:
    """A collision or visual shape: ``kind`` with SI ``params``, pose in the link frame.

    kinds and params: box ``size`` (full edge lengths), sphere ``radius``, cylinder and
    capsule ``radius``, ``length`` (along the shape's z; capsule length excludes the caps),
    ellipsoid ``semi_axes``, mesh ``path`` (resolved, or None), ``uri`` (as written),
    ``scale`` (3,).  MJCF geoms may carry ``density`` [kg/m^3] or ``mass`` [kg].
    """

    kind: str
    params: dict
    R_link_geom: np.ndarray = field(default_factory=lambda: np.eye(3))
    p_link_geom: np.ndarray = field(default_factory=lambda: np.zeros(3))
    role: str = "collision"
    line: int | None = None
    density: float | None = None
    mass: float | None = None


@dataclass
class Joint:
    """A joint that moves its link relative to the parent link, in the **link frame**.

    ``kind`` is what the motion is: "hinge" (rotation by the value about ``axis`` through
    ``anchor``), "slide" (translation by the value along ``axis``), or a joint that is kept at
    its default configuration ("ball", "free", "floating", "planar", ...; ``type`` says which).
    The link is at its declared pose when the joint's value is ``default`` (MJCF's ``ref``,
    i.e. ``qpos0``; 0 in URDF and SDF).  ``mimic`` (URDF): ``(joint name, multiplier, offset)``,
    value = multiplier x that joint's value + offset.
    """

    name: str | None
    kind: str
    type: str
    axis: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    anchor: np.ndarray = field(default_factory=lambda: np.zeros(3))
    default: float = 0.0
    line: int | None = None
    mimic: tuple | None = None


@dataclass
class Link:
    """One link (URDF/SDF) or body (MJCF).

    Kinematics (filled by the MJCF reader, and for URDF and SDF by
    :func:`inertia.robots.tree.read_tree` when first needed): ``parent`` is the index of the
    parent link in :attr:`RobotModel.links` (None: attached to the world / the root),
    ``R_parent_link``/``p_parent_link`` the link's pose in the parent's frame with every joint
    at its default, ``joints`` the joints between them, applied in order.
    """

    name: str
    line: int | None
    inertial: Inertial | None
    geometries: list = field(default_factory=list)
    element: object = None
    notes: list = field(default_factory=list)  # reader warnings for this link (e.g. mesh not found)
    #: MJCF: the simulator takes this body's inertia from its geoms (no <inertial>, or
    #: inertiafromgeom="true"), so the check computes it from them
    inertia_from_geoms: bool = False
    parent: int | None = None
    R_parent_link: np.ndarray = field(default_factory=lambda: np.eye(3))
    p_parent_link: np.ndarray = field(default_factory=lambda: np.zeros(3))
    joints: list = field(default_factory=list)
    #: the name with its model's scope (SDF worlds and nested models: "model::link"), else None
    scoped_name: str | None = None
    #: MJCF: the ``<compiler>`` elements whose mass bounds apply to this body when they are not
    #: the file's own (a body an ``<attach>`` brings from another model), else None
    mjcf_compilers: list | None = None
    #: MJCF: geoms MuJoCo allows only in a static body (``type="plane"``), as ``file:line ...``
    static_only: list = field(default_factory=list)


@dataclass
class RobotModel:
    """A parsed robot file: its format ("urdf", "sdf", "mjcf"), links and the XML document."""

    path: object
    format: str
    links: list
    document: object = None
    #: the name of the frame the link poses end in ("world"; URDF: the root link's frame), set
    #: with the kinematics (None: not read yet)
    root_frame: str | None = None
    #: ``(Joint, child link name)`` of the joints that close kinematic loops (their child already
    #: has a parent joint): named in the check's notes, not used for the poses
    loop_joints: list = field(default_factory=list)

    def link(self, name: str) -> Link:
        """The link called ``name``; :class:`~inertia.errors.InputError` (also a KeyError) names the
        links there are when there is none."""
        for lk in self.links:
            if lk.name == name:
                return lk
        raise LinkNotFoundError(f"{self.path}: no link named {name!r}; the links are "
                                f"{', '.join(repr(lk.name) for lk in self.links) or 'none'}")


class LinkNotFoundError(InputError, KeyError):
    """No link of that name in the model (an :class:`~inertia.errors.InputError` and a ``KeyError``)."""

    code = "link_not_found"

    def __str__(self) -> str:          # KeyError would quote the message
        return str(self.args[0]) if self.args else ""
