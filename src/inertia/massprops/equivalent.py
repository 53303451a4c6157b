"""Uniform solids (box, ellipsoid) with exactly the mass properties of a given body.

Every model in this module and in :mod:`inertia.particles.models` starts from the same
quantities.  In the principal frame P (origin at the COM, axes the principal axes, moments
ascending ``I1 <= I2 <= I3``) the central second-moment matrix of any mass distribution is
diagonal,

    S_P = sum m r r^T = diag(s1, s2, s3),    s_i = (I_j + I_k - I_i) / 2   [kg m^2],

because ``I = tr(S) 1 - S``.  Each ``s_i = sum m x_i^2`` is a sum of squares, so every real
body has ``s_i >= 0``.  This is the triangle inequality of the principal moments, and
why an equivalent model exists for every real body.  A model with mass M reproduces the tensor when its
own second moments equal ``s_i``:

* uniform box with full edge lengths ``b_i``: ``s_i = M b_i^2 / 12``, so
  ``b_i^2 = 12 s_i / M = 6/M (I_j + I_k - I_i)``  (``I_i = M/12 (b_j^2 + b_k^2)``);
* uniform solid ellipsoid with semi-axes ``a_i``: ``s_i = M a_i^2 / 5``, so
  ``a_i^2 = 5 s_i / M = 5/(2M) (I_j + I_k - I_i)``  (``I_i = M/5 (a_j^2 + a_k^2)``);
* six-point and four-point particle models: see :mod:`inertia.particles.models`.

Flat bodies.  A lamina (flat plate) has ``I1 + I2 = I3`` exactly, so ``s3 = 0``.  The
equivalent box is then a zero-thickness rectangle and the equivalent ellipsoid a
zero-thickness elliptical disc.  Both are accepted: their mass properties are still exact,
but their volume is 0 (so their density is undefined).  The tolerance is
``PHYSICAL_RTOL * |trace(I)|`` on the margin ``I_j + I_k - I_i``, the same one that
:mod:`inertia.massprops.validity` uses:

* a margin negative within the tolerance (rounding, typically ~1e-16 of the trace) is clipped
  to 0, so the dimension is exactly 0;
* a margin positive but within the tolerance is kept, so the dimension is tiny but not zero.
  The tensor is reproduced without the perturbation that snapping it to 0 would add;
* in both cases the body counts as flat: the model carries a warning that names the flat
  axis and gives the dimension.

No model exists, and :class:`inertia.errors.NoEquivalentModelError` is raised, when the mass
is not positive, the tensor is not symmetric, a margin ``I_j + I_k - I_i`` is negative beyond
the tolerance (a dimension would be imaginary), or the tensor is not positive definite (a
point or a rod, with a zero principal moment, is not a solid).  The message names every
violated condition and gives its numbers.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from fractions import Fraction

import numpy as np

from .._core.errors import InputError, NoEquivalentModelError
from .._core.findings import Finding
from .._core.tolerances import PHYSICAL_RTOL
from .._core.validation import as_rotation_matrix, as_vector3, frozen_array
from .principal import PrincipalFrame
from .properties import MassProperties
from .validity import check_inertia

__all__ = [
    "EquivalentBox",
    "EquivalentEllipsoid",
    "PrincipalSecondMoments",
    "equivalent_box",
    "equivalent_ellipsoid",
    "principal_second_moments",
]

# (i, j, k) with j < k: the margin I_j + I_k - I_i belongs to principal axis i
_AXIS_TRIPLES = ((0, 1, 2), (1, 0, 2), (2, 0, 1))

# violations after which the principal moments are meaningless: stop before computing them
_FATAL_CODES = ("non_positive_mass", "non_finite", "not_symmetric")


def _fmt(a) -> str:
    return "(" + ", ".join(f"{x:.6g}" for x in np.asarray(a, float).ravel()) + ")"


def _formula(symbol: str, factor: float, i: int, j: int, k: int) -> str:
    """Text of ``symbol_i^2 = factor/(2M) (I_j + I_k - I_i)``, simplified (e.g. ``b1^2 = 6/M (...)``)."""
    fr = Fraction(factor).limit_denominator(1000) / 2
    coef = f"{fr.numerator}/M" if fr.denominator == 1 else f"{fr.numerator}/({fr.denominator}M)"
    return f"{symbol}{i + 1}^2 = {coef} (I{j + 1} + I{k + 1} - I{i + 1})"


@dataclass(frozen=True, eq=False)
class PrincipalSecondMoments:
    """Central second moments of a body along its principal axes (shared by all equivalent models).

    Attributes
    ----------
    principal : PrincipalFrame
        The principal frame P of the body: moments, axes and origin in the original frame F.
    second_moments : (3,) float, kg m^2
        ``s_i = (I_j + I_k - I_i) / 2 = sum m x_i^2`` along principal axis i (P frame), in the
        order of the ascending moments.  Negative values within the tolerance are clipped to 0.
    margins : (3,) float, kg m^2
        The unclipped margins ``I_j + I_k - I_i`` (``= 2 s_i`` before clipping).
    flat_axes : tuple of int
        Principal axes (0-based) along which the body is flat within the tolerance
        (``margin <= tolerance``): a lamina has ``flat_axes == (2,)``.
    tolerance : float, kg m^2
        ``rtol * |trace(I)|``; a margin below ``-tolerance`` is a violation.
    """

    principal: PrincipalFrame
    second_moments: np.ndarray
    margins: np.ndarray
    flat_axes: tuple
    tolerance: float


def principal_second_moments(props: MassProperties, *, model: str = "equivalent model", symbol: str = "s",
                             factor: float = 1.0, rtol: float = PHYSICAL_RTOL) -> PrincipalSecondMoments:
    """Principal central second moments ``s_i = (I_j + I_k - I_i)/2``, or raise if a model cannot exist.

    Parameters
    ----------
    props : MassProperties
        The body; mass [kg], COM [m] and central inertia [kg m^2] in its frame F.
    model : str
        Name of the model, for the error message (``"no six-point model: ..."``).
    symbol, factor : str, float
        How the model's dimension follows from ``s_i``: ``symbol_i^2 = factor * s_i / M``
        (e.g. ``"d", 3`` for the six-point model, ``"b", 12`` for the box).  Only used to write
        the failed requirement and the value it would need into the message.
    rtol : float
        Relative tolerance on the margins and on positive definiteness (times ``|trace(I)|``).

    Returns
    -------
    PrincipalSecondMoments

    Raises
    ------
    inertia.errors.NoEquivalentModelError
        Mass not positive, tensor not symmetric or not positive definite, or a margin
        ``I_j + I_k - I_i < -tolerance``.  The message lists every violation with its numbers;
        ``.findings`` holds them.
    inertia.errors.InputError
        ``props`` is not a :class:`MassProperties`.
    """
    if not isinstance(props, MassProperties):
        raise InputError(f"{model}: expected a MassProperties, got {type(props).__name__}")
    others = [v for v in check_inertia(props.inertia_com, props.mass, props.com, rtol=rtol)
              if v.code != "triangle_inequality"]  # re-checked below, per axis, with the model's formula
    if any(v.code in _FATAL_CODES for v in others):
        raise NoEquivalentModelError(f"no {model}: " + "; ".join(v.message for v in others), findings=others)

    pf = props.principal()
    I_P = pf.moments  # ascending principal moments, kg m^2
    tol = rtol * max(abs(float(I_P.sum())), np.finfo(float).tiny)
    margins = np.empty(3)
    triangle: list[Finding] = []
    for i, j, k in _AXIS_TRIPLES:
        margins[i] = I_P[j] + I_P[k] - I_P[i]
        if margins[i] < -tol:
            need = factor * margins[i] / (2.0 * props.mass)
            triangle.append(Finding(
                "triangle_inequality",
                f"I{j + 1} + I{k + 1} - I{i + 1} = {margins[i]:.6g} < 0 (needs {_formula(symbol, factor, i, j, k)} "
                f"= {need:.6g} m^2 >= 0; principal moments {_fmt(I_P)} kg m^2 about the COM, tolerance {tol:.3g})",
                values={"axis": i, "margin": float(margins[i]), "moments": I_P.tolist(), "tolerance": tol}))
    if triangle or others:
        parts = [v.message for v in triangle]
        if triangle:
            parts[-1] += ", whereas every real mass distribution has I_j + I_k - I_i = 2 sum m x_i^2 >= 0"
        parts += [v.message for v in others]
        raise NoEquivalentModelError(f"no {model}: " + "; ".join(parts), findings=triangle + others)

    # within the tolerance: clip tiny negative margins (rounding) to an exactly flat axis
    s = 0.5 * np.clip(margins, 0.0, None)
    s.setflags(write=False)
    margins.setflags(write=False)
    flat = tuple(int(i) for i in range(3) if margins[i] <= tol)
    return PrincipalSecondMoments(pf, s, margins, flat, tol)


def flat_findings(sm: PrincipalSecondMoments, detail) -> tuple:
    """One ``flat_body`` finding per flat principal axis (zero or rounding-size extent);
    ``detail(i)`` says what that means for the model."""
    out = []
    for i in sm.flat_axes:
        j, k = (a for a in range(3) if a != i)
        out.append(Finding("flat_body", f"I{j + 1} + I{k + 1} - I{i + 1} = {sm.margins[i]:.3g} kg m^2 is zero "
                           f"within {sm.tolerance:.3g}; {detail(i)}",
                           values={"axis": i, "margin": float(sm.margins[i]), "tolerance": sm.tolerance}))
    return tuple(out)


@dataclass(frozen=True, eq=False)
class _EquivalentSolid:
    """Common part of the uniform equivalent solids (mass, pose of the principal frame, findings)."""

    mass: float
    dims: np.ndarray
    R_body_principal: np.ndarray
    p_body_com: np.ndarray
    frame: str = "body"
    findings: tuple = ()

    _kind = "solid"
    _dims_name = "dims"
    _moment_divisor = 1.0   # I_i = M / divisor (d_j^2 + d_k^2)
    _volume_factor = 1.0    # V = factor d1 d2 d3

    def __post_init__(self):
        m = float(self.mass)
        if not (math.isfinite(m) and m > 0):
            raise InputError(f"{self._kind}: mass must be positive and finite, got {self.mass!r}")
        dims = as_vector3(self.dims, self._dims_name)
        if np.any(dims < 0):
            raise InputError(f"{self._kind}: {self._dims_name} must be >= 0, got {dims.tolist()}")
        object.__setattr__(self, "mass", m)
        object.__setattr__(self, "dims", frozen_array(dims))
        object.__setattr__(self, "R_body_principal",
                           frozen_array(as_rotation_matrix(self.R_body_principal, "R_body_principal",
                                                           allow_batch=False)))
        object.__setattr__(self, "p_body_com", frozen_array(as_vector3(self.p_body_com, "p_body_com")))
        object.__setattr__(self, "findings", tuple(self.findings))

    # subclasses: principal moments and volume from the dimensions
    def principal_moments(self) -> np.ndarray:
        """Moments (3,) [kg m^2] about the centre along the solid's axes: ``M/k (d_j^2 + d_k^2)``."""
        d2 = self.dims ** 2
        return self.mass / self._moment_divisor * (d2.sum() - d2)

    @property
    def volume(self) -> float:
        """The solid's volume [m^3] (0 when flat)."""
        return float(self._volume_factor * np.prod(self.dims))

    @property
    def density(self) -> float:
        """Uniform density mass / volume [kg/m^3]; NaN for an exact lamina (zero volume)."""
        v = self.volume
        return self.mass / v if v > 0 else math.nan

    def mass_properties(self) -> MassProperties:
        """Mass properties of the solid in the original frame F, recomputed from its dimensions.

        Returns
        -------
        MassProperties
            ``mass`` [kg]; ``com = p_body_com`` [m, in F];
            ``inertia_com = R_body_principal diag(I_P) R_body_principal^T``
            [kg m^2, about the COM, axes of F]; ``volume`` [m^3] (0 for a lamina); frame ``frame``.
            Built with ``validate=False``: a uniform solid is physical by construction, and a
            lamina sits exactly on the triangle inequality.
        """
        R_body_principal = self.R_body_principal
        I_F = R_body_principal @ np.diag(self.principal_moments()) @ R_body_principal.T
        return MassProperties(self.mass, self.p_body_com, 0.5 * (I_F + I_F.T), frame=self.frame,
                              volume=self.volume, findings=self.findings, validate=False)

    def to_dict(self) -> dict:
        """Plain-Python dict (JSON-ready); lengths in m, mass in kg, axes as columns in ``frame``."""
        return {
            "kind": self._kind,
            "mass": self.mass,
            self._dims_name: self.dims.tolist(),
            "R_body_principal": self.R_body_principal.tolist(),
            "p_body_com": self.p_body_com.tolist(),
            "volume": self.volume,
            "frame": self.frame,
            "findings": [f.to_dict() for f in self.findings],
        }


@dataclass(frozen=True, eq=False)
class EquivalentBox(_EquivalentSolid):
    """Uniform rectangular box with the mass, COM and inertia tensor of a given body.

    Attributes
    ----------
    mass : float, kg.
    dims : (3,) float, m
        Full edge lengths ``(b1, b2, b3)`` along principal axes 1, 2, 3.  These are the columns
        of ``R_body_principal``, in the order of the ascending principal moments, so the
        edges are in descending order.  Also available as :attr:`size`.
    R_body_principal : (3, 3) float
        Proper rotation whose columns are the box axes (principal axes) expressed in frame F.
    p_body_com : (3,) float, m
        Box centre (the COM) in frame F.
    frame : str
        Name of F.
    findings : tuple of Finding
        ``flat_body`` when the box is a lamina (a zero edge, see :func:`equivalent_box`).
    """

    _kind = "box"
    _dims_name = "size"
    _moment_divisor = 12.0                 # I_i = M/12 (b_j^2 + b_k^2) about the centre, box axes
    _volume_factor = 1.0                   # b1 b2 b3

    size = property(lambda self: self.dims, doc="Full edge lengths (3,) [m] along principal axes 1, 2, 3 (``dims``).")


@dataclass(frozen=True, eq=False)
class EquivalentEllipsoid(_EquivalentSolid):
    """Uniform solid ellipsoid with the mass, COM and inertia tensor of a given body.

    The attributes of :class:`EquivalentBox`, with ``dims`` the semi-axes ``(a1, a2, a3)``
    along principal axes 1, 2, 3 (descending, also available as :attr:`semi_axes`) and
    ``findings`` holding ``flat_body`` when the ellipsoid is a flat disc (a zero semi-axis, see
    :func:`equivalent_ellipsoid`).
    """

    _kind = "ellipsoid"
    _dims_name = "semi_axes"
    _moment_divisor = 5.0                  # I_i = M/5 (a_j^2 + a_k^2) about the centre, ellipsoid axes
    _volume_factor = 4.0 / 3.0 * math.pi   # 4/3 pi a1 a2 a3

    semi_axes = property(lambda self: self.dims, doc="Semi-axes (3,) [m] along principal axes 1, 2, 3 (``dims``).")


def equivalent_box(props: MassProperties, *, rtol: float = PHYSICAL_RTOL) -> EquivalentBox:
    """The uniform box with the same mass, COM and full inertia tensor as ``props``.

    Parameters
    ----------
    props : MassProperties
        The body: mass [kg], COM [m] and central inertia [kg m^2], expressed in frame F.
    rtol : float
        Tolerance on the triangle inequality and positive definiteness, times ``|trace(I)|``
        (default :data:`inertia._core.tolerances.PHYSICAL_RTOL`).

    Returns
    -------
    EquivalentBox
        ``size`` (3,) [m] full edge lengths along the principal axes (ascending moments, so
        descending edges), ``R_body_principal`` (3, 3) box axes as columns in F,
        ``p_body_com`` (3,) [m] centre in F; ``.mass_properties()`` reproduces ``props``.

    Raises
    ------
    inertia.errors.NoEquivalentModelError
        No box exists: a margin ``I_j + I_k - I_i`` is negative beyond the tolerance (an
        imaginary edge), or the mass is not positive, or the tensor is not symmetric or not
        positive definite.  The message names each violated inequality with its numbers.

    Notes
    -----
    ``b_i^2 = 6/M (I_j + I_k - I_i)`` from ``I_i = M/12 (b_j^2 + b_k^2)``.  An exactly flat body
    (``I1 + I2 = I3`` within the tolerance) gives ``b3 = 0``, a zero-thickness lamina.  It is
    accepted, its tensor is still reproduced exactly, its volume is 0, and a warning names the
    flat axis.  For repeated moments the box axes in the repeated plane follow the
    deterministic rule of :mod:`inertia.massprops.principal`.

    Examples
    --------
    >>> import numpy as np
    >>> from .properties import MassProperties
    >>> from .equivalent import equivalent_box
    >>> M, (a, b, c) = 2.0, (0.3, 0.2, 0.1)
    >>> I = M / 12 * np.diag([b*b + c*c, a*a + c*c, a*a + b*b])
    >>> box = equivalent_box(MassProperties(M, [1.0, 0.0, 0.0], I))
    >>> np.round(box.size, 12).tolist()
    [0.3, 0.2, 0.1]
    >>> box.mass_properties().isclose(MassProperties(M, [1.0, 0.0, 0.0], I))
    True
    """
    sm = principal_second_moments(props, model="equivalent box", symbol="b", factor=12.0, rtol=rtol)
    size = np.sqrt(12.0 * sm.second_moments / props.mass)  # b_i^2 = 12 s_i / M
    pf = sm.principal
    return EquivalentBox(props.mass, size, pf.R_body_principal, pf.p_body_com, frame=props.frame,
                         findings=flat_findings(sm, lambda i: f"the equivalent box is flat along principal "
                                                f"axis {i + 1} (b{i + 1} = {size[i]:.3g} m)"))


def equivalent_ellipsoid(props: MassProperties, *, rtol: float = PHYSICAL_RTOL) -> EquivalentEllipsoid:
    """The uniform solid ellipsoid with the same mass, COM and full inertia tensor as ``props``.

    ``props`` and ``rtol`` as for :func:`equivalent_box`.

    Returns
    -------
    EquivalentEllipsoid
        ``semi_axes`` (3,) [m] along the principal axes (ascending moments, so descending
        semi-axes), ``R_body_principal`` (3, 3) axes as columns in F, ``p_body_com`` (3,) [m]
        centre in F; ``.mass_properties()`` reproduces ``props``.

    Raises
    ------
    inertia.errors.NoEquivalentModelError
        As :func:`equivalent_box`: no ellipsoid exists for an unphysical tensor.

    Notes
    -----
    ``a_i^2 = 5/(2M) (I_j + I_k - I_i)`` from ``I_i = M/5 (a_j^2 + a_k^2)``.  An exactly flat body
    gives ``a3 = 0``, a zero-thickness elliptical disc with zero volume.  It is accepted with a ``flat_body`` finding.

    Examples
    --------
    The equivalent ellipsoid of a uniform ellipsoid is that ellipsoid:

    >>> from .primitives import ellipsoid
    >>> e = equivalent_ellipsoid(ellipsoid((0.5, 0.2, 0.1), mass=3.0))
    >>> [round(float(x), 12) for x in e.semi_axes], e.mass
    ([0.5, 0.2, 0.1], 3.0)
    """
    sm = principal_second_moments(props, model="equivalent ellipsoid", symbol="a", factor=5.0, rtol=rtol)
    semi = np.sqrt(5.0 * sm.second_moments / props.mass)  # a_i^2 = 5 s_i / M
    pf = sm.principal
    return EquivalentEllipsoid(props.mass, semi, pf.R_body_principal, pf.p_body_com, frame=props.frame,
                               findings=flat_findings(sm, lambda i: f"the equivalent ellipsoid is flat along "
                                                      f"principal axis {i + 1} (a{i + 1} = {semi[i]:.3g} m)"))
