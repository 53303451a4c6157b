"""Euler-angle sequences: rotation matrices and the kinematic matrix ``E(q)``, symbolically.

A sequence ``"abc"`` (three letters from X, Y, Z, no two neighbours equal) names the
*intrinsic* rotation ``R_world_body = R_a(q1) R_b(q2) R_c(q3)``: first about the world axis
a, then about the new b, then about the newest c.  This is scipy's upper-case convention
(``Rotation.from_euler("ZYX", [q1, q2, q3])``).  The six Tait-Bryan sequences (three
different axes) and the six proper Euler sequences (first axis = last axis) make twelve.

The generalized coordinates are the angles in sequence order.  For the default ``"ZYX"``
they are ``(psi, theta, phi) = (yaw, pitch, roll)``: ``R = Rz(psi) Ry(theta) Rx(phi)``.

The body angular velocity is linear in the angle rates, ``omega_body = E(q) q'``, with
columns ``E = [R_c^T R_b^T e_a, R_c^T e_b, e_c]``.  ``E`` is singular (gimbal lock) where
the middle angle makes the first and last rotation axes line up: ``cos q2 = 0`` for
Tait-Bryan sequences and ``sin q2 = 0`` for proper Euler sequences; :func:`det_kinematic`
gives ``det E`` in that closed form.
"""

from __future__ import annotations

from .._core.errors import InputError
from ._sympy import require_sympy

_AXES = {"X": 0, "Y": 1, "Z": 2}

#: the twelve sequences: six Tait-Bryan, then six proper Euler
SEQUENCES = ("XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX", "XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ")

#: conventional angle names of some sequences (others get q1, q2, q3)
ANGLE_NAMES = {
    "ZYX": ("psi", "theta", "phi"),   # yaw, pitch, roll
    "ZXZ": ("phi", "theta", "psi"),   # classical Euler angles (precession, nutation, spin)
    "ZYZ": ("phi", "theta", "psi"),
}


def parse_sequence(sequence: str) -> str:
    """The canonical upper-case form of ``sequence``; :class:`InputError` if not one of the 12."""
    if not isinstance(sequence, str):
        raise InputError(f"Euler sequence must be a string such as 'ZYX', got {type(sequence).__name__}")
    seq = sequence.strip().upper().replace("-", "")
    if seq not in SEQUENCES:
        raise InputError(f"unknown Euler sequence {sequence!r}: use one of {', '.join(SEQUENCES)} "
                         "(intrinsic rotations, R = R_a(q1) R_b(q2) R_c(q3))")
    return seq


def is_tait_bryan(sequence: str) -> bool:
    """True for the six sequences with three different axes (roll-pitch-yaw type)."""
    seq = parse_sequence(sequence)
    return seq[0] != seq[2]


def angle_names(sequence: str) -> tuple[str, str, str]:
    """Names of the three angles, in sequence order."""
    seq = parse_sequence(sequence)
    return ANGLE_NAMES.get(seq, ("q1", "q2", "q3"))


def axis_rotation(axis: str, angle):
    """Symbolic 3x3 rotation by ``angle`` about the coordinate ``axis`` ("X", "Y" or "Z")."""
    sp = require_sympy()
    c, s = sp.cos(angle), sp.sin(angle)
    i = _AXES[axis]
    j, k = (i + 1) % 3, (i + 2) % 3
    R = sp.zeros(3, 3)
    R[i, i] = 1
    R[j, j], R[j, k] = c, -s
    R[k, j], R[k, k] = s, c
    return R


def rotation_matrix(sequence: str, q):
    """``R_world_body = R_a(q1) R_b(q2) R_c(q3)`` as a sympy Matrix (q: three sympy expressions)."""
    seq = parse_sequence(sequence)
    return axis_rotation(seq[0], q[0]) * axis_rotation(seq[1], q[1]) * axis_rotation(seq[2], q[2])


def _unit(axis: str):
    sp = require_sympy()
    e = sp.zeros(3, 1)
    e[_AXES[axis]] = 1
    return e


def kinematic_matrix(sequence: str, q):
    """``E(q)`` with ``omega_body = E(q) q'`` (columns: the three rotation axes in body axes)."""
    sp = require_sympy()
    seq = parse_sequence(sequence)
    Rb_T = axis_rotation(seq[1], q[1]).T
    Rc_T = axis_rotation(seq[2], q[2]).T
    cols = [Rc_T * (Rb_T * _unit(seq[0])), Rc_T * _unit(seq[1]), _unit(seq[2])]
    return sp.Matrix.hstack(*cols)


def _perm_sign(i: int, j: int, k: int) -> int:
    return {(0, 1, 2): 1, (1, 2, 0): 1, (2, 0, 1): 1}.get((i, j, k), -1)


def det_kinematic(sequence: str, q):
    """``det E(q)`` in closed form: ``s cos q2`` (Tait-Bryan) or ``s sin q2`` (proper Euler).

    Derivation: the columns are ``R_c^T R_b^T e_a``, ``R_c^T e_b``, ``e_c``; rotating all
    three by ``R_c`` leaves the determinant unchanged, giving
    ``det[R_b^T e_a, e_b, e_c]``.  For Tait-Bryan (a, b, c all different) the component of
    ``R_b^T e_a`` along ``e_a`` is ``cos q2`` and the sign is that of the permutation (a, b, c);
    for proper Euler (c = a) the component along the third axis d is ``+-sin q2``.
    The tests check this against the expanded determinant for all twelve sequences.
    """
    sp = require_sympy()
    seq = parse_sequence(sequence)
    a, b, c = (_AXES[ch] for ch in seq)
    if a != c:
        return _perm_sign(a, b, c) * sp.cos(q[1])
    d = 3 - a - b
    # R_b(q2)^T e_a has component along e_d of -sin q2 * (sign of the cyclic order b -> a -> d)
    comp_sign = -_perm_sign(b, a, d)
    return comp_sign * _perm_sign(d, b, a) * sp.sin(q[1])


def singular_function(sequence: str) -> tuple[str, int]:
    """``("cos"|"sin", sign)``: det E = sign * cos(q2) or sign * sin(q2)."""
    sp = require_sympy()
    q2 = sp.Symbol("q2")
    det = det_kinematic(sequence, (sp.Symbol("q1"), q2, sp.Symbol("q3")))
    trig = "cos" if det.has(sp.cos(q2)) else "sin"
    sign = 1 if float(det.subs(q2, 0.5)) > 0 else -1   # sin and cos are both positive at 0.5
    return trig, sign


def kinematic_matrix_inverse(sequence: str, q):
    """``E(q)^-1`` in closed form: the adjugate of E over the closed-form :func:`det_kinematic`.

    Nothing on the equations of motion is simplified: only the nine adjugate entries (each
    at most a few products of sines and cosines) go through ``trigsimp``, which folds the
    ``sin^2 + cos^2`` that the cofactors leave, and the determinant is replaced by its known
    one-term form.
    """
    sp = require_sympy()
    adj = kinematic_matrix(sequence, q).adjugate().applyfunc(sp.trigsimp)
    return adj / det_kinematic(sequence, q)
