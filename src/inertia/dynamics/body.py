"""The rigid body of the 6-DOF transition function: mass, central inertia, principal frame."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError, InvalidInertiaError
from .._core.rotations import matrix_to_quat
from .._core.tolerances import PHYSICAL_RTOL, SYMMETRY_RTOL
from .._core.validation import as_float_array
from ..massprops.principal import principal_axes
from ..massprops.validity import check_inertia

__all__ = ["RigidBody", "BodyView", "check_body"]


def _validate_bodies(mass: np.ndarray, inertia: np.ndarray) -> None:
    """Raise InvalidInertiaError for the first non-physical body of a batch.

    A vectorised screen (symmetry, positive definiteness, triangle inequality with the
    tolerances of :mod:`inertia.massprops.validity`) finds the suspects; the per-body
    :func:`~inertia.massprops.validity.check_inertia` then words the message.
    """
    flat_I = inertia.reshape(-1, 3, 3)
    scale = np.abs(flat_I).max(axis=(-2, -1))
    asym = np.abs(flat_I - np.swapaxes(flat_I, -1, -2)).max(axis=(-2, -1))
    moments = np.linalg.eigvalsh(0.5 * (flat_I + np.swapaxes(flat_I, -1, -2)))
    tol = PHYSICAL_RTOL * np.maximum(np.abs(moments.sum(axis=-1)), np.finfo(float).tiny)
    suspect = ((asym > SYMMETRY_RTOL * np.maximum(scale, np.finfo(float).tiny)) | (moments[:, 0] <= tol)
               | (moments[:, 0] + moments[:, 1] - moments[:, 2] < -tol))
    for k in np.flatnonzero(suspect):
        violations = check_inertia(flat_I[k])
        if violations:
            index = tuple(int(i) for i in np.unravel_index(k, inertia.shape[:-2]))
            where = "" if inertia.ndim == 2 else f" (body {index})"
            raise InvalidInertiaError(f"inertia_com is not physical{where}: "
                                      + "; ".join(v.message for v in violations), findings=violations)


@dataclass(frozen=True, eq=False)
class RigidBody:
    """Mass and central inertia of a rigid body, as the transition function needs them.

    Parameters
    ----------
    mass : float or (...,) float, kg, positive.
    inertia_com : (3, 3) or (..., 3, 3) float, kg m^2, about the center of mass, in the body
        frame B (negated products, ``L_B = I @ omega_body``).  A general symmetric positive
        definite matrix; it need not be diagonal.
    validate : bool, keyword-only
        Check every body with :func:`inertia.massprops.validity.check_inertia` (positive mass,
        symmetric, positive definite, triangle inequality) and raise
        :class:`inertia.errors.InvalidInertiaError` listing the violations.  ``validate=False`` skips the
        check and silently accepts non-physical bodies.

    Attributes (derived)
    --------------------
    moments : (..., 3) float, kg m^2, principal moments, ascending.
    R_body_principal : (..., 3, 3) float, columns are the principal axes in B (proper rotation),
        in the canonical form of :mod:`inertia.massprops.principal` (the axes
        ``MassProperties.principal()`` reports for the same tensor).
    q_body_principal : (..., 4) float, the same rotation as a quaternion.
    principal_is_body : bool, True when P = B (diagonal inertia with an ascending diagonal):
        no frame change at all, so nothing is rounded by one.

    Leading dimensions describe a batch of bodies; they broadcast against the batch dimensions
    of the state.

    Examples
    --------
    >>> body = RigidBody(1.0, np.diag([0.0042, 0.0142, 0.0167]))
    >>> body.moments.shape, body.principal_is_body
    ((3,), True)
    >>> RigidBody(1.0, np.diag([0.0167, 0.0142, 0.0042])).moments.tolist()   # sorted ascending
    [0.0042, 0.0142, 0.0167]
    >>> RigidBody(np.ones(5), np.broadcast_to(np.eye(3), (5, 3, 3))).moments.shape
    (5, 3)
    """

    mass: np.ndarray
    inertia_com: np.ndarray
    validate: bool = field(default=True, repr=False, kw_only=True)
    moments: np.ndarray = field(init=False, repr=False)
    R_body_principal: np.ndarray = field(init=False, repr=False)
    q_body_principal: np.ndarray = field(init=False, repr=False)
    principal_is_body: bool = field(init=False, repr=False)

    def __post_init__(self):
        mass = as_float_array(self.mass, "mass", ())
        inertia = as_float_array(self.inertia_com, "inertia_com", (3, 3))
        if np.any(mass <= 0):
            bad = mass[mass <= 0].ravel()[0] if mass.ndim else float(mass)
            raise InputError(f"mass must be positive, got {bad!r} kg")
        try:
            np.broadcast_shapes(mass.shape, inertia.shape[:-2])
        except ValueError:
            raise InputError(f"mass {mass.shape} and inertia_com {inertia.shape} batch shapes do not "
                             f"broadcast") from None
        if self.validate:
            _validate_bodies(mass, inertia)
        # P = B when every tensor is diagonal and ascending: no frame change rounds anything
        off = inertia[..., [0, 0, 1], [1, 2, 2]]
        diag = np.diagonal(inertia, axis1=-2, axis2=-1)
        identity = not np.any(off) and bool(np.all(np.diff(diag, axis=-1) >= 0))
        moments, R_BP = principal_axes(inertia)
        if identity:
            q_BP = np.broadcast_to(np.array([1.0, 0.0, 0.0, 0.0]), moments.shape[:-1] + (4,)).copy()
        else:
            q_BP = matrix_to_quat(R_BP)
        for name, val in (("mass", mass), ("inertia_com", inertia), ("moments", moments),
                          ("R_body_principal", R_BP), ("q_body_principal", q_BP)):
            val = np.array(val, dtype=np.float64, copy=True)
            val.setflags(write=False)
            object.__setattr__(self, name, val)
        object.__setattr__(self, "principal_is_body", bool(identity))

    @classmethod
    def from_mass_properties(cls, props, *, validate: bool = True) -> "RigidBody":
        """The body of a :class:`inertia.massprops.MassProperties` value.

        Uses ``props.mass`` and ``props.inertia_com``: the body frame B of the state is the
        frame of ``props`` translated to the center of mass (same axes).  The frame origin of
        ``props`` sits at ``p_world - R_WB @ props.com`` in the world.
        """
        return cls(props.mass, props.inertia_com, validate=validate)

    @classmethod
    def from_principal_moments(cls, mass, moments, *, validate: bool = True) -> "RigidBody":
        """A body whose frame is principal: ``inertia_com = diag(moments)`` (..., 3) kg m^2."""
        moments = as_float_array(moments, "moments", (3,))
        return cls(mass, moments[..., :, None] * np.eye(3), validate=validate)

    @property
    def batch_shape(self) -> tuple:
        """Leading (batch) shape of the body: ``()`` for one body."""
        return np.broadcast_shapes(self.mass.shape, self.inertia_com.shape[:-2])


def check_body(body) -> RigidBody:
    """``body`` itself when it is a :class:`RigidBody`; an :class:`InputError` naming its type otherwise."""
    if not isinstance(body, RigidBody):
        raise InputError(f"body must be a RigidBody (mass, inertia_com), got {type(body).__name__}")
    return body


class BodyView:
    """The arrays of a RigidBody with ``extra_axes`` unit axes inserted after its batch axes.

    Lets a batch of bodies broadcast against states that carry extra trailing batch axes
    (the perturbation axes of :func:`jacobians`).
    """

    def __init__(self, body: RigidBody, extra_axes: int = 0):
        ins = (None,) * extra_axes
        self.mass = body.mass[(..., *ins)]
        self.moments = body.moments[(..., *ins, slice(None))]
        self.R_body_principal = body.R_body_principal[(..., *ins, slice(None), slice(None))]
        self.q_body_principal = body.q_body_principal[(..., *ins, slice(None))]
        self.principal_is_body = body.principal_is_body
