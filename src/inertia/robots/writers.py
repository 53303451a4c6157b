"""Ready-to-paste inertial blocks for URDF, MJCF and SDF.

All three take the tensor about the center of mass with *tensor elements* as products
(``ixy = -sum m x y``, our convention, so nothing is negated here).  The frame conventions:

* URDF ``<inertial><origin xyz rpy/>``: the COM in the link frame; the tensor in the axes of
  ``origin`` (we write ``rpy="0 0 0"``, so the link's axes);
* MJCF ``<inertial pos mass fullinertia="ixx iyy izz ixy ixz iyz"/>`` in the body's axes, or
  equivalently ``diaginertia`` (principal moments) with ``quat`` (w x y z) = the principal axes;
* SDF ``<inertial><pose>x y z 0 0 0</pose>``: the COM in the link frame, tensor in link axes.

Numbers are written with ``repr`` so that a block read back gives the same floats.
"""

from __future__ import annotations

import numpy as np

FORMATS = ("urdf", "mjcf", "sdf")


def _n(x) -> str:
    return repr(float(x))


def _vec(v) -> str:
    return " ".join(_n(x) for x in v)


def _elements(inertia) -> dict:
    I = np.asarray(inertia, float)
    return {"ixx": I[0, 0], "iyy": I[1, 1], "izz": I[2, 2], "ixy": I[0, 1], "ixz": I[0, 2], "iyz": I[1, 2]}


def matrix_to_quat(R) -> np.ndarray:
    """Scalar-first unit quaternion of a proper rotation matrix (w >= 0)."""
    from .._core.rotations import matrix_to_quat as m2q

    q = np.asarray(m2q(R), float)
    return q if q[0] >= 0 else -q


def inertial_block(props, fmt: str, *, indent: str = "") -> str:
    """The ``<inertial>`` element for ``props`` (a MassProperties in the link frame)."""
    e = _elements(props.inertia_com)
    c = props.com
    if fmt == "urdf":
        lines = ["<inertial>",
                 f'  <origin xyz="{_vec(c)}" rpy="0 0 0"/>',
                 f'  <mass value="{_n(props.mass)}"/>',
                 '  <inertia ' + " ".join(f'{k}="{_n(e[k])}"' for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
                 + "/>",
                 "</inertial>"]
    elif fmt == "sdf":
        lines = ["<inertial>",
                 f"  <pose>{_vec(c)} 0 0 0</pose>",
                 f"  <mass>{_n(props.mass)}</mass>",
                 "  <inertia>"]
        lines += [f"    <{k}>{_n(e[k])}</{k}>" for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
        lines += ["  </inertia>", "</inertial>"]
    elif fmt == "mjcf":
        moments, R = props.principal()
        full = " ".join(_n(e[k]) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
        lines = [f'<inertial pos="{_vec(c)}" mass="{_n(props.mass)}" fullinertia="{full}"/>',
                 f'<!-- equivalently: <inertial pos="{_vec(c)}" mass="{_n(props.mass)}" '
                 f'diaginertia="{_vec(moments)}" quat="{_vec(matrix_to_quat(R))}"/> -->']
    else:
        raise ValueError(f"unknown format {fmt!r}; use one of {FORMATS}")
    return "\n".join(indent + line for line in lines) + "\n"
