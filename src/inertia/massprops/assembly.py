"""Assemblies: rigidly joined parts with poses combine into one set of mass properties."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_rotation_matrix, as_vector3
from .properties import MassProperties, combine


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


def assemble(parts, *, frame: str = "assembly", allow_negative: bool = False, validate: bool = True):
    """Mass properties of an assembly of :class:`Part` (or bare MassProperties at the identity pose).

    Parts with ``subtract=True`` remove material (a hole); they are refused unless
    ``allow_negative=True`` is given.  The result is validated (positive mass, positive
    definite, triangle inequality) unless ``validate=False``.
    """
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
