"""Assemblies: rigidly joined parts with poses combine into one set of mass properties."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from . import tensor as _t
from .._core.validation import as_rotation_matrix, as_vector3


@dataclass(frozen=True)
class Part:
    """A part of an assembly: its mass properties (in the part's own frame P) and the pose of P
    in the assembly frame A.

    Attributes
    ----------
    props : MassProperties in frame P.
    R_assembly_part : (3, 3) proper rotation, maps P coordinates into A (default identity).
    p_assembly_part : (3,) m, origin of P in A (default zero).
    subtract : bool
        Remove this part (a hole, a pocket): its mass counts negatively.  Must be asked for.
    name : str, for messages.
    """

    props: object
    R_assembly_part: np.ndarray = field(default_factory=lambda: np.eye(3))
    p_assembly_part: np.ndarray = field(default_factory=lambda: np.zeros(3))
    subtract: bool = False
    name: str = ""

    def in_assembly(self):
        R = as_rotation_matrix(self.R_assembly_part, f"part {self.name!r} R_assembly_part", allow_batch=False)
        p = as_vector3(self.p_assembly_part, f"part {self.name!r} p_assembly_part")
        return self.props.transformed(R, p)


def combine(bodies, signs=None, *, frame=None, allow_negative: bool = False, validate: bool = True):
    """Combine bodies expressed in the same frame.

    ``signs`` (+1 / -1 per body) subtracts removed material; negative signs require
    ``allow_negative=True``.  The result must have positive mass.
    """
    from .properties import MassProperties

    bodies = list(bodies)
    if not bodies:
        raise InputError("nothing to combine: no parts given")
    signs = np.ones(len(bodies)) if signs is None else np.asarray(signs, float)
    if np.any(signs < 0) and not allow_negative:
        raise InputError("a part with negative mass (subtract=True) needs allow_negative=True")
    frames = {b.frame for b in bodies}
    if len(frames) > 1 and frame is None:
        raise InputError(f"parts are expressed in different frames {sorted(frames)}; express them in one frame first")
    m = np.array([b.mass for b in bodies]) * signs
    M = float(m.sum())
    if not (M > 0 and math.isfinite(M)):
        raise InputError(f"assembly mass must be positive, got {M:.6g} kg (removed parts outweigh the rest?)")
    coms = np.array([b.com for b in bodies])
    com = (m @ coms) / M
    I = np.zeros((3, 3))
    for sgn, b in zip(signs, bodies):
        # each part's inertia about the common COM (parallel axis), signed
        I += sgn * _t.inertia_about_point(b.inertia_com, b.mass, b.com, com)
    vols = np.array([b.volume for b in bodies]) * signs
    vol = float(vols.sum()) if np.all(np.isfinite(vols)) else math.nan
    warnings = tuple(w for b in bodies for w in b.warnings)
    return MassProperties(M, com, 0.5 * (I + I.T), frame=frame or bodies[0].frame, volume=vol,
                          warnings=warnings, validate=validate)


def assemble(parts, *, frame: str = "assembly", allow_negative: bool = False, validate: bool = True):
    """Mass properties of an assembly of :class:`Part` (or bare MassProperties at the identity pose).

    Parts with ``subtract=True`` remove material (a hole); they are refused unless
    ``allow_negative=True`` is given.  The result is validated (positive mass, positive
    definite, triangle inequality) unless ``validate=False``.
    """
    from .properties import MassProperties

    bodies, signs = [], []
    for k, p in enumerate(parts):
        if isinstance(p, MassProperties):
            p = Part(p, name=str(k))
        if not isinstance(p, Part):
            raise InputError(f"part {k} must be a Part or MassProperties, got {type(p).__name__}")
        if p.subtract and not allow_negative:
            raise InputError(f"part {p.name or k} is marked subtract=True: pass allow_negative=True to remove material")
        bodies.append(p.in_assembly()._replace(frame=frame))
        signs.append(-1.0 if p.subtract else 1.0)
    return combine(bodies, signs, frame=frame, allow_negative=allow_negative, validate=validate)
