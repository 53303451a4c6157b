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


def format_number(x) -> str:
    return repr(float(x))


def format_vector(v) -> str:
    return " ".join(format_number(x) for x in v)


def inertia_elements(inertia) -> dict:
    I = np.asarray(inertia, float)
    return {"ixx": I[0, 0], "iyy": I[1, 1], "izz": I[2, 2], "ixy": I[0, 1], "ixz": I[0, 2], "iyz": I[1, 2]}


def matrix_to_quat(R) -> np.ndarray:
    """Scalar-first unit quaternion of a proper rotation matrix (w >= 0)."""
    from .._core.rotations import matrix_to_quat as m2q

    q = np.asarray(m2q(R), float)
    return q if q[0] >= 0 else -q


def inertial_block(props, fmt: str, *, indent: str = "") -> str:
    """The ``<inertial>`` element for ``props`` (a MassProperties in the link frame)."""
    e = inertia_elements(props.inertia_com)
    c = props.com
    if fmt == "urdf":
        lines = ["<inertial>",
                 f'  <origin xyz="{format_vector(c)}" rpy="0 0 0"/>',
                 f'  <mass value="{format_number(props.mass)}"/>',
                 '  <inertia ' + " ".join(f'{k}="{format_number(e[k])}"'
                                         for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"))
                 + "/>",
                 "</inertial>"]
    elif fmt == "sdf":
        lines = ["<inertial>",
                 f"  <pose>{format_vector(c)} 0 0 0</pose>",
                 f"  <mass>{format_number(props.mass)}</mass>",
                 "  <inertia>"]
        lines += [f"    <{k}>{format_number(e[k])}</{k}>" for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")]
        lines += ["  </inertia>", "</inertial>"]
    elif fmt == "mjcf":
        pf = props.principal()
        moments, R = pf.moments, pf.R_body_principal
        full = " ".join(format_number(e[k]) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz"))
        lines = [f'<inertial pos="{format_vector(c)}" mass="{format_number(props.mass)}" fullinertia="{full}"/>',
                 f'<!-- equivalently: <inertial pos="{format_vector(c)}" mass="{format_number(props.mass)}" '
                 f'diaginertia="{format_vector(moments)}" quat="{format_vector(matrix_to_quat(R))}"/> -->']
    else:
        from .._core.errors import InputError

        raise InputError(f"unknown format {fmt!r}; use one of {FORMATS}")
    return "\n".join(indent + line for line in lines) + "\n"
