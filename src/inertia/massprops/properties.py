"""The mass-properties value type.

Sign convention: the inertia matrix holds negated products of inertia
(``I_xy = -sum m x y``) so that angular momentum is ``L = I @ omega``.  Import and
export products in the positive (CAD) convention through
:meth:`MassProperties.from_elements` / :meth:`MassProperties.elements` with
``convention='cad'``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array, as_matrix3, as_rotation_matrix, as_vector3, frozen_array
from . import tensor as _t
from .principal import PrincipalFrame, principal_frame
from .validity import check_inertia, raise_if_invalid


@dataclass(frozen=True, eq=False)
class MassProperties:
    """Mass, center of mass and central inertia of a rigid body, in a named frame.

    Immutable: every operation returns a new value.

    Attributes
    ----------
    mass : float, kg.
    com : (3,) float, m, position of the center of mass from the frame origin, in the frame.
    inertia_com : (3, 3) float, kg m^2, inertia about the center of mass, axes of the frame,
        negated-product convention (``L = I @ omega``).
    frame : str
        Name of the frame the vectors are expressed in (bookkeeping only; ``"body"`` by default).
    volume : float, m^3
        Volume of the solid when known (NaN otherwise, e.g. for point masses or thin shells).
    findings : tuple of Finding
        What was found while computing the value (mesh notes, defects accepted on request, a
        robust solid's bounds).
    precision : float
        Relative precision of ``inertia_com`` that the input allows (0: exact input).  A mesh
        whose coordinates are float32 values carries about 1e-7; a robust result its error
        bound.  Principal moments closer than ``max(REPEATED_MOMENTS_RTOL, precision)`` times
        the largest count as repeated: the data cannot tell them apart.

    Construction validates by default (positive mass, finite, symmetric, positive definite,
    triangle inequality) and raises :class:`inertia.errors.InvalidInertiaError`; pass
    ``validate=False`` to build intermediate, non-physical values (e.g. a hole to subtract).
    """

    mass: float
    com: np.ndarray
    inertia_com: np.ndarray
    frame: str = "body"
    volume: float = math.nan
    findings: tuple = ()
    validate: bool = field(default=True, repr=False)
    precision: float = 0.0

    def __post_init__(self):
        try:
            mass = float(self.mass)
        except (TypeError, ValueError):
            raise InputError(f"mass must be a number, got {self.mass!r}") from None
        com = as_vector3(self.com, "com")
        inertia = as_matrix3(self.inertia_com, "inertia_com")
        object.__setattr__(self, "mass", mass)
        object.__setattr__(self, "com", frozen_array(com))
        object.__setattr__(self, "inertia_com", frozen_array(inertia))
        object.__setattr__(self, "volume", float(self.volume))
        object.__setattr__(self, "findings", tuple(self.findings))
        precision = float(self.precision)
        if not (0.0 <= precision < 1.0):
            raise InputError(f"precision must be a relative precision in [0, 1), got {self.precision!r}")
        object.__setattr__(self, "precision", precision)
        if not isinstance(self.frame, str):
            raise InputError(f"frame must be a string name, got {self.frame!r}")
        if self.validate:
            raise_if_invalid(inertia, mass, com)
        elif not math.isfinite(mass):
            raise InputError(f"mass must be finite, got {mass!r}")

    # ------------------------------------------------------------------ constructors
    @classmethod
    def _computed(cls, mass: float, com: np.ndarray, inertia: np.ndarray, *, frame: str = "body",
                  volume: float = math.nan, findings: tuple = (), precision: float = 0.0) -> "MassProperties":
        """Internal: a value this package has just computed (``com`` (3,) and ``inertia`` (3, 3)
        fresh float64 arrays, ``mass`` a float): validated for physics as every value is, without
        re-checking shapes and types (the per-call cost of a small mesh)."""
        raise_if_invalid(inertia, mass, com)
        obj = object.__new__(cls)
        com.setflags(write=False)
        inertia.setflags(write=False)
        for name, value in (("mass", float(mass)), ("com", com), ("inertia_com", inertia), ("frame", frame),
                            ("volume", float(volume)), ("findings", tuple(findings)), ("validate", True),
                            ("precision", float(precision))):
            object.__setattr__(obj, name, value)
        return obj

    @classmethod
    def from_point_masses(cls, masses, positions, *, frame: str = "body", validate: bool = True) -> "MassProperties":
        """Mass properties of point masses (N,) kg at positions (N, 3) m in ``frame``.

        One or two points (or collinear points) have a zero principal moment; pass
        ``validate=False`` to accept such a degenerate value.
        """
        m = as_float_array(masses, "masses", (), allow_batch=True)
        r = as_float_array(positions, "positions", (3,), allow_batch=True)
        if m.ndim != 1 or r.shape != (m.shape[0], 3):
            raise InputError(f"expected masses (N,) and positions (N, 3), got {m.shape} and {r.shape}")
        if m.size == 0:
            raise InputError("no point masses given")
        if np.any(m < 0):
            k = int(np.argmax(m < 0))
            raise InputError(f"point mass {k} is negative ({m[k]:.6g} kg)")
        M = float(m.sum())
        if M <= 0:
            raise InputError("point masses sum to zero")
        com = (m @ r) / M
        inertia = _t.point_mass_inertia(m, r - com)
        return cls(M, com, inertia, frame=frame, validate=validate)

    @classmethod
    def from_inertia_about(cls, mass, com, inertia_point, point, *, frame: str = "body",
                           validate: bool = True) -> "MassProperties":
        """Build from an inertia matrix given about ``point`` (not the COM): parallel axis to the COM."""
        m = float(mass)
        com = as_vector3(com, "com")
        point = as_vector3(point, "point")
        I_P = as_matrix3(inertia_point, "inertia_point")
        return cls(m, com, _t.inertia_about_com(I_P, m, com, point), frame=frame, validate=validate)

    @classmethod
    def from_elements(cls, mass, com, ixx, iyy, izz, ixy=0.0, ixz=0.0, iyz=0.0, *, convention: str = "tensor",
                      frame: str = "body", validate: bool = True) -> "MassProperties":
        """Build from moments and products about the COM; ``convention`` names the product sign
        (``'tensor'``: matrix entries as URDF/MJCF/SDF write them; ``'cad'``: positive products)."""
        I = _t.inertia_from_elements(ixx, iyy, izz, ixy, ixz, iyz, convention=convention)
        return cls(mass, com, I, frame=frame, validate=validate)

    # ------------------------------------------------------------------ queries
    def about(self, point) -> np.ndarray:
        """Inertia matrix (3, 3) [kg m^2] about ``point`` (3,) [m], axes of this frame (parallel axis)."""
        return _t.inertia_about_point(self.inertia_com, self.mass, self.com, as_vector3(point, "point"))

    @property
    def inertia_origin(self) -> np.ndarray:
        """Inertia matrix (3, 3) about the frame origin."""
        return self.about(np.zeros(3))

    def moment_about_axis(self, direction, point=None) -> float:
        """Moment of inertia [kg m^2] about the line through ``point`` (default: the COM) along ``direction``.

        Computes ``D^T I_com D + m |d_perp|^2`` with ``D`` the unit direction.
        """
        d = as_vector3(direction, "direction")
        p = None if point is None else as_vector3(point, "point")
        return float(_t.moment_about_line(self.inertia_com, self.mass, self.com, d, p))

    def elements(self, *, convention: str = "tensor", about=None) -> dict:
        """Moments and products (floats) about the COM (or ``about`` a point), in the named product convention."""
        I = self.inertia_com if about is None else self.about(about)
        return {k: float(v) for k, v in _t.elements_from_inertia(I, convention=convention).items()}

    def principal(self, *, rtol: float | None = None) -> PrincipalFrame:
        """The principal frame in canonical form: moments ascending, ``R_body_principal``,
        ``p_body_com`` and the repeated moments (see :mod:`inertia.massprops.principal`).

        ``rtol`` (default :attr:`moments_rtol`) decides which moments are repeated.
        """
        rtol = self.moments_rtol if rtol is None else rtol
        # the value is immutable (read-only arrays), so the decomposition is computed once
        cache = self.__dict__.setdefault("_principal_cache", {})
        pf = cache.get(rtol)
        if pf is None:
            pf = cache[rtol] = principal_frame(self.inertia_com, self.com, rtol)
        return pf

    @property
    def moments_rtol(self) -> float:
        """The relative tolerance under which principal moments count as repeated:
        ``REPEATED_MOMENTS_RTOL``, or the input's :attr:`precision` when coarser."""
        return max(REPEATED_MOMENTS_RTOL, self.precision)

    def check(self) -> list:
        """Every physical-validity violation (empty when valid); see :mod:`inertia.massprops.validity`."""
        return check_inertia(self.inertia_com, self.mass, self.com)

    def is_physical(self) -> bool:
        return not self.check()

    @property
    def density(self) -> float:
        """Mean density mass / volume [kg/m^3] (NaN when the volume is unknown)."""
        return self.mass / self.volume if self.volume and not math.isnan(self.volume) else math.nan

    @property
    def radii_of_gyration(self) -> np.ndarray:
        """Principal radii of gyration sqrt(I_k / m) [m], ascending with the moments."""
        return np.sqrt(np.clip(self.principal().moments, 0, None) / self.mass)

    # ------------------------------------------------------------------ transforms
    def _with_precision(self, precision: float) -> "MassProperties":
        """Internal: this value with ``precision`` (in [0, 1)), its other fields as they are:
        already checked, not checked again."""
        obj = object.__new__(type(self))
        obj.__dict__.update(self.__dict__)
        object.__setattr__(obj, "precision", float(precision))
        return obj

    def _replace(self, **kw) -> "MassProperties":
        args = dict(mass=self.mass, com=self.com, inertia_com=self.inertia_com, frame=self.frame,
                    volume=self.volume, findings=self.findings, validate=False, precision=self.precision)
        args.update(kw)
        return MassProperties(**args)

    def translated(self, offset) -> "MassProperties":
        """The same body moved by ``offset`` (3,) m: the COM moves, the central inertia does not."""
        return self._replace(com=self.com + as_vector3(offset, "offset"))

    def rotated(self, R) -> "MassProperties":
        """The same body rotated by ``R`` about the frame origin: ``com' = R com``, ``I' = R I R^T``."""
        R = as_rotation_matrix(R, "R", allow_batch=False)
        return self._replace(com=R @ self.com, inertia_com=_t.rotate_inertia(self.inertia_com, R))

    def transformed(self, R, t) -> "MassProperties":
        """Rotate by ``R`` about the origin, then translate by ``t`` (the pose of the body in the new frame)."""
        return self.rotated(R).translated(t)

    def expressed_in(self, frame: str, R_new_old, p_new_old=(0.0, 0.0, 0.0)) -> "MassProperties":
        """The same body expressed in another frame.

        ``R_new_old`` maps vectors of this frame into ``frame``; ``p_new_old`` is this frame's
        origin in ``frame`` [m].  So ``com_new = R_new_old @ com + p_new_old`` and
        ``I_new = R_new_old I R_new_old^T``.
        """
        out = self.transformed(R_new_old, as_vector3(p_new_old, "p_new_old"))
        return out._replace(frame=frame)

    def with_mass(self, mass) -> "MassProperties":
        """Same shape and mass distribution, scaled to a new total ``mass`` [kg]."""
        m = float(mass)
        if not (math.isfinite(m) and m > 0):
            raise InputError(f"mass must be positive and finite, got {mass!r}")
        return self._replace(mass=m, inertia_com=self.inertia_com * (m / self.mass))

    def with_findings(self, *findings) -> "MassProperties":
        """The same value with ``findings`` (:class:`~inertia.errors.Finding`) added."""
        return self._replace(findings=self.findings + tuple(findings))

    def __add__(self, other: "MassProperties") -> "MassProperties":
        """Combine two bodies expressed in the same frame (rigidly joined)."""
        if not isinstance(other, MassProperties):
            return NotImplemented
        return combine([self, other])

    # ------------------------------------------------------------------ export
    def to_dict(self) -> dict:
        """Plain-Python dict (JSON-ready): mass, volume, com, inertia_com, principal moments/axes, frame, findings."""
        pf = self.principal()
        return {
            "mass": self.mass,
            "volume": None if math.isnan(self.volume) else self.volume,
            "com": self.com.tolist(),
            "inertia_com": self.inertia_com.tolist(),
            "principal_moments": pf.moments.tolist(),
            "R_body_principal": pf.R_body_principal.tolist(),
            "frame": self.frame,
            "findings": [f.to_dict() for f in self.findings],
        }

    def __eq__(self, other):
        if not isinstance(other, MassProperties):
            return NotImplemented
        return (self.mass == other.mass and self.frame == other.frame and np.array_equal(self.com, other.com)
                and np.array_equal(self.inertia_com, other.inertia_com))

    def isclose(self, other: "MassProperties", *, rtol: float = 1e-12, atol: float = 0.0) -> bool:
        """Same mass, COM and inertia within tolerances (inertia compared relative to its largest entry)."""
        scale_I = max(np.abs(self.inertia_com).max(), np.abs(other.inertia_com).max())
        scale_c = max(np.abs(self.com).max(), np.abs(other.com).max(), math.sqrt(scale_I / max(self.mass, 1e-300)))
        return (math.isclose(self.mass, other.mass, rel_tol=rtol, abs_tol=atol)
                and np.allclose(self.com, other.com, rtol=0, atol=atol + rtol * scale_c)
                and np.allclose(self.inertia_com, other.inertia_com, rtol=0, atol=atol + rtol * scale_I))

    def __repr__(self) -> str:
        with np.printoptions(precision=6, suppress=False):
            return (f"MassProperties(mass={self.mass:.6g}, com={self.com}, inertia_com={self.inertia_com.tolist()}, "
                    f"frame={self.frame!r})")


def combine(bodies, signs=None, *, frame=None, allow_negative: bool = False, validate: bool = True):
    """Combine bodies expressed in the same frame.

    ``signs`` (+1 / -1 per body) subtracts removed material; negative signs require
    ``allow_negative=True``.  The result must have positive mass.
    """
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
    findings = tuple(w for b in bodies for w in b.findings)
    return MassProperties(M, com, 0.5 * (I + I.T), frame=frame or bodies[0].frame, volume=vol,
                          findings=findings, validate=validate, precision=max(b.precision for b in bodies))


def point_masses(masses, positions, *, frame: str = "body", validate: bool = True):
    """Mass properties of point masses (N,) kg at positions (N, 3) m.

    ``I_ij = sum_k m_k (|r_k|^2 delta_ij - r_ki r_kj)`` with r relative to the COM.
    Fewer than three non-collinear points give a zero principal moment, which fails
    validation unless ``validate=False``.  For the raw tensor about an arbitrary origin
    with batch dimensions use :func:`inertia.massprops.tensor.point_mass_inertia`.
    """
    return MassProperties.from_point_masses(masses, positions, frame=frame, validate=validate)
