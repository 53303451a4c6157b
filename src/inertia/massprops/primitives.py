"""Closed-form mass properties of uniform primitive solids and thin shells.

Every function returns a :class:`~inertia.massprops.properties.MassProperties`
(mass [kg], center of mass [m] and inertia about the center of mass [kg m^2],
axes of the body frame) for a body of uniform density.  Each takes exactly one of

* ``mass=`` [kg], or
* ``density=`` [kg/m^3 for solids; kg/m^2, i.e. mass per unit area, for thin shells],

and, where it exists, ``kind="shell"`` for the *thin-shell* variant: uniform surface
density over the whole closed boundary surface (end caps and faces included).
Solids carry their ``volume`` [m^3]; shells have ``volume = NaN``.

Frames
------
All primitives are axis-aligned in the body frame.  Every primitive is centered at
the origin except the cone, whose base disc lies in the plane z = 0 with its apex at
z = +height.  Bodies of revolution have their axis along z; the torus ring lies in
the xy plane.

Sign convention
---------------
Inertia matrices hold negated products of inertia (``L = I @ omega``).  Every
primitive here has its body axes as principal axes, so the products are zero.

Sources
-------
Closed forms are cited next to the lines that use them.  "Wikipedia list" means
Wikipedia, "List of moments of inertia" (3-D table; entry named in quotes), which
agrees with the table of homogeneous solids in Meriam & Kraige, *Engineering
Mechanics: Dynamics* (appendix on mass moments of inertia).  Shell formulas
that the tables do not list are derived here by integrating over the surface
patches; each derivation is written out in a comment.  The thin-shell ellipsoid has
no elementary closed form and is integrated numerically (see :func:`ellipsoid`).
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_positive_scalar, as_vector3, resolve_mass
from .ellipsoid_surface import ellipsoid_surface_moments

__all__ = ["box", "sphere", "ellipsoid", "cylinder", "cone", "capsule", "torus", "tube", "spherical_shell"]

_PI = math.pi


# ----------------------------------------------------------------------------- input helpers
def _length(value, name: str, what: str, *, allow_zero: bool = False) -> float:
    """A finite positive length [m] (non-negative when ``allow_zero``); InputError names ``what`` and ``name``."""
    try:
        return as_positive_scalar(value, name, allow_zero=allow_zero)
    except InputError as exc:
        raise InputError(f"{what}: {exc}") from None


def _lengths3(value, name: str, what: str) -> tuple[float, float, float]:
    """Three finite positive lengths [m] from a sequence; InputError names the bad entry."""
    try:
        v = as_vector3(value, name)
    except InputError as exc:
        raise InputError(f"{what}: {exc}") from None
    for k, x in enumerate(v):
        if not x > 0:
            raise InputError(f"{what}: {name}[{k}] must be finite and positive, got {float(x)!r} (m)")
    return float(v[0]), float(v[1]), float(v[2])


def _is_shell(kind, what: str) -> bool:
    """``kind`` is ``"shell"`` (True) or ``"solid"`` (False); anything else is refused."""
    if kind in ("solid", "shell"):
        return kind == "shell"
    raise InputError(f"{what}: kind must be 'solid' or 'shell', got {kind!r}")


def _uniform_body(what: str, measure: float, com, gyration_sq, mass, density, *, shell: bool,
                  frame: str):
    """Mass properties of a uniform body from its size and per-unit-mass central moments.

    Parameters
    ----------
    measure : float, volume [m^3] (solid) or area [m^2] (shell).
    com : (3,) float, m, center of mass in the body frame.
    gyration_sq : (3,) float, m^2, ``(I_xx, I_yy, I_zz) / mass`` about the COM (products are zero).
    """
    from .properties import MassProperties

    m, _ = resolve_mass(measure, density, mass, what=what, measure_name="area" if shell else "volume")
    k2 = np.asarray(gyration_sq, dtype=np.float64)
    with np.errstate(over="ignore", under="ignore"):
        inertia = m * np.diag(k2)
    if not (np.all(np.isfinite(inertia)) and np.all(np.diag(inertia) > 0)):
        raise InputError(f"{what}: the inertia is out of float64 range (mass {m:.6g} kg, squared radii of "
                         f"gyration {k2.tolist()} m^2): rescale the units")
    return MassProperties(m, np.asarray(com, dtype=np.float64), inertia, frame=frame,
                          volume=math.nan if shell else measure)


# ----------------------------------------------------------------------------- box
def box(size, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform rectangular box (cuboid), centered at the origin, edges along the body axes.

    Parameters
    ----------
    size : sequence of 3 float, m
        Full edge lengths ``(a, b, c)`` along x, y, z (not half-lengths).
    mass : float, kg, optional
        Total mass.  Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 (surface density) for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin shell made of the six faces, uniform surface density.
    frame : str, default "body"
        Name recorded on the result.

    Returns
    -------
    MassProperties
        COM (3,) = 0; inertia (3, 3) kg m^2 about the COM, diagonal in the body axes;
        ``volume = a b c`` (NaN for the shell).

    Notes
    -----
    Solid: ``I_xx = m (b^2 + c^2) / 12`` and cyclic (Wikipedia list, "solid cuboid").
    Shell: with area ``A = 2 (ab + bc + ca)`` the second moment ``S_xx = int x^2 dA``
    sums the two faces normal to x (at ``x = +-a/2``: ``2 bc a^2 / 4``) and the four
    faces along x (``2 ac a^2 / 12 + 2 ab a^2 / 12``), so
    ``S_xx = a^2 (bc / 2 + a (b + c) / 6)`` and ``I_xx = sigma (S_yy + S_zz)``.

    Examples
    --------
    >>> p = box((1.0, 2.0, 3.0), mass=12.0)
    >>> p.inertia_com.shape, float(p.inertia_com[0, 0])
    ((3, 3), 13.0)
    """
    shell = _is_shell(kind, "box")
    what = "box shell" if shell else "box"
    a, b, c = _lengths3(size, "size", "box")
    if not shell:
        # Wikipedia list, "solid cuboid": I_xx = m (b^2 + c^2) / 12, cyclic.
        k2 = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 12.0
        return _uniform_body(what, a * b * c, np.zeros(3), k2, mass, density, shell=False, frame=frame)
    # Six faces, derived in the docstring: S_ii = d_i^2 (area of the two faces normal to i) / 4
    #   + d_i^2 (area of the four faces containing axis i) / 12.
    area = 2.0 * (a * b + b * c + c * a)
    S = np.array([a * a * (b * c / 2.0 + a * (b + c) / 6.0),
                  b * b * (a * c / 2.0 + b * (a + c) / 6.0),
                  c * c * (a * b / 2.0 + c * (a + b) / 6.0)]) / area
    k2 = np.array([S[1] + S[2], S[0] + S[2], S[0] + S[1]])
    return _uniform_body(what, area, np.zeros(3), k2, mass, density, shell=True, frame=frame)


# ----------------------------------------------------------------------------- sphere / ellipsoid
def sphere(radius, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform solid ball or thin spherical shell, centered at the origin.

    Parameters
    ----------
    radius : float, m
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin spherical shell (uniform surface density).
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; inertia ``k m r^2 * 1`` (isotropic) about the COM with ``k = 2/5`` (solid)
        or ``2/3`` (shell); ``volume = 4/3 pi r^3`` (NaN for the shell).

    Notes
    -----
    Wikipedia list, "solid sphere" (2/5 m r^2) and "thin spherical shell" (2/3 m r^2).

    Examples
    --------
    >>> float(sphere(1.0, mass=5.0).inertia_com[2, 2])
    2.0
    """
    shell = _is_shell(kind, "sphere")
    what = "sphere shell" if shell else "sphere"
    r = _length(radius, "radius", "sphere")
    if shell:
        # Wikipedia list, "thin-walled spherical shell": I = 2/3 m r^2.
        return _uniform_body(what, 4.0 * _PI * r * r, np.zeros(3), np.full(3, 2.0 / 3.0 * r * r),
                             mass, density, shell=True, frame=frame)
    # Wikipedia list, "solid sphere (ball)": I = 2/5 m r^2.
    return _uniform_body(what, 4.0 / 3.0 * _PI * r * r * r, np.zeros(3), np.full(3, 0.4 * r * r),
                         mass, density, shell=False, frame=frame)


def ellipsoid(semi_axes, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform solid ellipsoid or thin ellipsoidal shell, centered, semi-axes along x, y, z.

    Parameters
    ----------
    semi_axes : sequence of 3 float, m
        Semi-axes ``(a, b, c)`` along x, y, z (half the extents).
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin shell of uniform surface density over the ellipsoid surface.
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; diagonal inertia about the COM; ``volume = 4/3 pi a b c`` (NaN for the shell).

    Notes
    -----
    Solid: ``I_xx = m (b^2 + c^2) / 5`` and cyclic (Wikipedia list, "solid ellipsoid").

    Shell: the surface area and the second moments ``int x^2 dA`` of an ellipsoid
    have no elementary closed form (the area is an elliptic integral, Carlson's
    ``4 pi R_G(b^2 c^2, a^2 c^2, a^2 b^2)``).  They are computed by Gauss--Legendre
    quadrature in the angles of the parametrisation about the longest axis,
    ``x_p = p cos(t), x_q = q sin(t) cos(f), x_s = s sin(t) sin(f)`` (``p >= q >= s``),
    over one octant, with panels graded geometrically toward ``t = 0`` and ``f = 0``
    where the integrand has its nearest complex singularities (at distances about
    ``s / p`` and ``s / q``).  The result is accurate to about 1e-13 relative for any
    aspect ratio (checked against Carlson's ``R_G`` and adaptive quadrature in the tests).
    A sphere (``a = b = c``) reproduces ``2/3 m r^2`` to rounding.
    """
    shell = _is_shell(kind, "ellipsoid")
    what = "ellipsoid shell" if shell else "ellipsoid"
    a, b, c = _lengths3(semi_axes, "semi_axes", "ellipsoid")
    if not shell:
        # Wikipedia list, "solid ellipsoid": I_xx = m (b^2 + c^2) / 5, cyclic.
        k2 = np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 5.0
        return _uniform_body(what, 4.0 / 3.0 * _PI * a * b * c, np.zeros(3), k2, mass, density,
                             shell=False, frame=frame)
    area, S = ellipsoid_surface_moments(a, b, c)  # S: int x_i^2 dA / A, m^2
    k2 = np.array([S[1] + S[2], S[0] + S[2], S[0] + S[1]])
    return _uniform_body(what, area, np.zeros(3), k2, mass, density, shell=True, frame=frame)


# ----------------------------------------------------------------------------- cylinder, tube, cone
def cylinder(radius, height, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform solid circular cylinder or closed thin cylindrical shell; axis z, centered.

    Parameters
    ----------
    radius : float, m
    height : float, m
        Full length along z; the body spans ``-height/2 <= z <= height/2``.
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin closed shell: the lateral surface *and* both end discs, uniform surface density.
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; diagonal inertia about the COM; ``volume = pi r^2 h`` (NaN for the shell).

    Notes
    -----
    Solid: ``I_zz = m r^2 / 2``, ``I_xx = I_yy = m (3 r^2 + h^2) / 12`` (Wikipedia list,
    "solid cylinder").  Shell: sum of the lateral surface (``A = 2 pi r h``,
    ``int x^2 dA = pi r^3 h``, ``int z^2 dA = pi r h^3 / 6``) and two discs at ``z = +-h/2``
    (each ``A = pi r^2``, ``int x^2 dA = pi r^4 / 4``, ``int z^2 dA = pi r^2 h^2 / 4``).
    """
    shell = _is_shell(kind, "cylinder")
    what = "cylinder shell" if shell else "cylinder"
    r = _length(radius, "radius", "cylinder")
    h = _length(height, "height", "cylinder")
    if not shell:
        # Wikipedia list, "solid cylinder".
        k2 = np.array([(3.0 * r * r + h * h) / 12.0, (3.0 * r * r + h * h) / 12.0, 0.5 * r * r])
        return _uniform_body(what, _PI * r * r * h, np.zeros(3), k2, mass, density, shell=False, frame=frame)
    # Patches (derivation in the docstring): lateral + two end discs, A = 2 pi r (h + r);
    # per unit area  S_xx / A = (pi r^3 h + pi r^4 / 2) / A = r^2 (2h + r) / (4 (h + r)),
    #                S_zz / A = (pi r h^3 / 6 + pi r^2 h^2 / 2) / A = h^2 (h + 3r) / (12 (h + r)).
    area = 2.0 * _PI * r * (h + r)
    S_xx = r * r * (2.0 * h + r) / (4.0 * (h + r))
    S_zz = h * h * (h + 3.0 * r) / (12.0 * (h + r))
    k2 = np.array([S_xx + S_zz, S_xx + S_zz, 2.0 * S_xx])
    return _uniform_body(what, area, np.zeros(3), k2, mass, density, shell=True, frame=frame)


def tube(outer_radius, inner_radius, height, *, mass=None, density=None, kind: str = "solid",
         frame: str = "body"):
    """Uniform hollow circular cylinder (thick-walled tube); axis z, centered.

    Parameters
    ----------
    outer_radius : float, m
    inner_radius : float, m
        Radius of the bore, ``0 < inner_radius < outer_radius`` (use :func:`cylinder`
        for a tube without a bore).
    height, mass, density, frame
        As for :func:`cylinder`.
    kind : {"solid", "shell"}, default "solid"
        Thin closed shell over the whole boundary: outer and inner lateral surfaces and
        the two annular end faces, uniform surface density.

    Returns
    -------
    MassProperties
        COM = 0; diagonal inertia about the COM; ``volume = pi (r2^2 - r1^2) h`` (NaN for the shell).

    Notes
    -----
    Solid: ``I_zz = m (r1^2 + r2^2) / 2``, ``I_xx = I_yy = m (3 (r1^2 + r2^2) + h^2) / 12``
    (Wikipedia list, "thick-walled cylindrical tube with open ends").  Shell: lateral
    surfaces of radius r (``A = 2 pi r h``, ``int x^2 dA = pi r^3 h``,
    ``int z^2 dA = pi r h^3 / 6``) at ``r = r1, r2`` plus two annuli at ``z = +-h/2``
    (each ``A = pi (r2^2 - r1^2)``, ``int x^2 dA = pi (r2^4 - r1^4) / 4``).
    """
    shell = _is_shell(kind, "tube")
    what = "tube shell" if shell else "tube"
    r2 = _length(outer_radius, "outer_radius", "tube")
    r1 = _length(inner_radius, "inner_radius", "tube")
    h = _length(height, "height", "tube")
    if not r1 < r2:
        raise InputError(f"tube: inner_radius must be smaller than outer_radius, got inner_radius = {r1!r} m "
                         f">= outer_radius = {r2!r} m")
    if not shell:
        # Wikipedia list, "thick-walled cylindrical tube with open ends".
        s2 = r1 * r1 + r2 * r2
        k2 = np.array([(3.0 * s2 + h * h) / 12.0, (3.0 * s2 + h * h) / 12.0, 0.5 * s2])
        volume = _PI * (r2 - r1) * (r2 + r1) * h
        return _uniform_body(what, volume, np.zeros(3), k2, mass, density, shell=False, frame=frame)
    # Patches (derivation in the docstring): two lateral surfaces + two annuli; with the wall
    # thickness w = r2 - r1 the area is A = 2 pi (r1 + r2)(h + w) and, per unit area,
    #   S_xx / A = (pi (r1^3 + r2^3) h + pi (r2^2 - r1^2)(r1^2 + r2^2) / 2) / A
    #            = ((r1^2 - r1 r2 + r2^2) h + w (r1^2 + r2^2) / 2) / (2 (h + w)),
    #   S_zz / A = (pi (r1 + r2) h^3 / 6 + pi (r2^2 - r1^2) h^2 / 2) / A = h^2 (h + 3 w) / (12 (h + w)).
    w = r2 - r1
    area = 2.0 * _PI * (r1 + r2) * (h + w)
    S_xx = ((r1 * r1 - r1 * r2 + r2 * r2) * h + w * (r1 * r1 + r2 * r2) / 2.0) / (2.0 * (h + w))
    S_zz = h * h * (h + 3.0 * w) / (12.0 * (h + w))
    k2 = np.array([S_xx + S_zz, S_xx + S_zz, 2.0 * S_xx])
    return _uniform_body(what, area, np.zeros(3), k2, mass, density, shell=True, frame=frame)


def cone(radius, height, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform solid right circular cone or closed thin conical shell; axis z.

    Frame: the base disc lies in the plane ``z = 0`` centered on the z axis, the apex
    is at ``(0, 0, height)``.  The center of mass is therefore *not* at the origin:
    it is at ``(0, 0, height / 4)`` for the solid.

    Parameters
    ----------
    radius : float, m
        Radius of the base.
    height : float, m
        Distance from the base to the apex.
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin closed shell: the lateral (slanted) surface *and* the base disc.
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM ``(0, 0, z_c)``; diagonal inertia about the COM; ``volume = pi r^2 h / 3``
        (NaN for the shell).

    Notes
    -----
    Solid (Wikipedia list, "solid cone", about the apex ``I_xx = m (3 h^2 / 5 + 3 r^2 / 20)``,
    moved to the COM at ``3 h / 4`` from the apex): ``z_c = h / 4``,
    ``I_zz = 3 m r^2 / 10``, ``I_xx = I_yy = m (3 r^2 / 20 + 3 h^2 / 80)``.

    Shell, with slant ``s = sqrt(r^2 + h^2)`` and ``u = h - z`` the depth below the
    apex: the lateral surface has ``dA = 2 pi (r u / h)(s / h) du``, so ``A = pi r s``,
    ``int x^2 dA = pi r^3 s / 4``, ``int z dA = pi r s h / 3``, ``int z^2 dA = pi r s h^2 / 6``;
    the base adds ``A = pi r^2``, ``int x^2 dA = pi r^4 / 4`` at ``z = 0``.  Hence
    ``z_c = s h / (3 (s + r))``, ``I_zz = m r^2 / 2`` and
    ``I_xx = m (r^2 / 4 + s h^2 (s + 3 r) / (18 (s + r)^2))``.
    """
    shell = _is_shell(kind, "cone")
    what = "cone shell" if shell else "cone"
    r = _length(radius, "radius", "cone")
    h = _length(height, "height", "cone")
    if not shell:
        # Wikipedia list, "solid cone": about the apex I_xx = m (3/5 h^2 + 3/20 r^2), I_zz = 3/10 m r^2;
        # parallel axis to the COM (3h/4 below the apex): I_xx = m (3/20 r^2 + 3/80 h^2).
        k2_xx = 3.0 / 20.0 * r * r + 3.0 / 80.0 * h * h
        k2 = np.array([k2_xx, k2_xx, 0.3 * r * r])
        return _uniform_body(what, _PI * r * r * h / 3.0, np.array([0.0, 0.0, 0.25 * h]), k2, mass, density,
                             shell=False, frame=frame)
    # Lateral surface + base disc (derivation in the docstring).
    s = math.hypot(r, h)
    area = _PI * r * (s + r)
    z_c = s * h / (3.0 * (s + r))
    k2_xx = 0.25 * r * r + (s / (s + r)) * h * h * (s + 3.0 * r) / (18.0 * (s + r))
    k2 = np.array([k2_xx, k2_xx, 0.5 * r * r])
    return _uniform_body(what, area, np.array([0.0, 0.0, z_c]), k2, mass, density, shell=True, frame=frame)


# ----------------------------------------------------------------------------- capsule
def capsule(radius, length, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform capsule (cylinder with hemispherical ends); axis z, centered.

    Parameters
    ----------
    radius : float, m
        Radius of the cylinder and of both hemispheres.
    length : float, m
        Length of the cylindrical part, i.e. the distance between the hemisphere
        centers (``>= 0``; ``0`` gives a sphere).  Overall length ``length + 2 radius``.
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin shell over the closed surface (lateral cylinder + two hemispheres).
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; diagonal inertia about the COM; ``volume = pi r^2 L + 4/3 pi r^3`` (NaN for
        the shell).

    Notes
    -----
    Sum of a cylinder (mass ``m_c``) and two hemispheres (mass ``m_h`` each), with
    ``L`` the cylinder length and ``d`` the distance of a hemisphere's COM from its
    flat face (centroids: Meriam & Kraige's centroid tables, solid hemisphere ``3r/8``,
    hemispherical shell ``r/2``; the solid constant 83/320 = 0.259375 as in Kane & Levinson):

    * solid: ``d = 3r/8``; a hemisphere about its flat-face center has ``2/5 m_h r^2``
      about every axis (half a ball), so about its own COM the transverse moment is
      ``(2/5 - 9/64) m_h r^2 = 83/320 m_h r^2``; shifted to the capsule center by
      ``L/2 + 3r/8``: ``m_h (83/320 r^2 + (L/2 + 3r/8)^2) = m_h (2/5 r^2 + L^2/4 + 3 L r/8)``.
      ``I_zz = m_c r^2 / 2 + 2 (2/5) m_h r^2``; ``I_xx = m_c (3 r^2 + L^2) / 12 + 2 m_h (2/5 r^2 + L^2/4 + 3 L r/8)``.
    * shell: ``d = r/2``; a hemispherical shell has ``2/3 m_h r^2`` about its flat-face
      center, ``(2/3 - 1/4) m_h r^2 = 5/12 m_h r^2`` about its COM, so
      ``m_h (5/12 r^2 + (L/2 + r/2)^2) = m_h (2/3 r^2 + L^2/4 + L r/2)``; the open lateral
      cylinder has ``I_zz = m_c r^2``, ``I_xx = m_c (r^2/2 + L^2/12)``.
    """
    shell = _is_shell(kind, "capsule")
    what = "capsule shell" if shell else "capsule"
    r = _length(radius, "radius", "capsule")
    L = _length(length, "length", "capsule", allow_zero=True)
    if not shell:
        # Volume pi r^2 L (cylinder) + 2 * 2/3 pi r^3 (hemispheres) = pi r^2 (L + 4r/3); mass fractions
        # follow the volumes: f_c = L / (L + 4r/3) for the cylinder, f_h = (2r/3) / (L + 4r/3) per hemisphere.
        f_c, f_h = L / (L + 4.0 * r / 3.0), (2.0 * r / 3.0) / (L + 4.0 * r / 3.0)
        # Cylinder (Wikipedia list, "solid cylinder") + two hemispheres (parallel axis, see Notes):
        #   I_zz = m_c r^2 / 2 + 2 (2/5) m_h r^2
        #   I_xx = m_c (3 r^2 + L^2) / 12 + 2 m_h (83/320 r^2 + (L/2 + 3r/8)^2)
        #        = m_c (3 r^2 + L^2) / 12 + 2 m_h (2/5 r^2 + L^2/4 + 3 L r / 8)
        k2_zz = f_c * r * r / 2.0 + 2.0 * f_h * 0.4 * r * r
        k2_xx = f_c * (3.0 * r * r + L * L) / 12.0 + 2.0 * f_h * (83.0 / 320.0 * r * r + (L / 2.0 + 3.0 * r / 8.0) ** 2)
        volume = _PI * r * r * (L + 4.0 * r / 3.0)
        return _uniform_body(what, volume, np.zeros(3), np.array([k2_xx, k2_xx, k2_zz]), mass, density,
                             shell=False, frame=frame)
    # Area 2 pi r L (open lateral surface) + 2 * 2 pi r^2 (hemispherical shells) = 2 pi r (L + 2r);
    # area fractions f_c = L / (L + 2r), f_h = r / (L + 2r) per hemisphere.
    f_c, f_h = L / (L + 2.0 * r), r / (L + 2.0 * r)
    # Open thin cylinder (Wikipedia list, "thin-walled cylindrical tube with open ends": I_zz = m r^2,
    # transverse m (r^2/2 + L^2/12)) + two hemispherical shells (parallel axis, see Notes):
    #   I_xx(hemisphere) = m_h (5/12 r^2 + (L/2 + r/2)^2) = m_h (2/3 r^2 + L^2/4 + L r / 2).
    k2_zz = f_c * r * r + 2.0 * f_h * 2.0 / 3.0 * r * r
    k2_xx = f_c * (r * r / 2.0 + L * L / 12.0) + 2.0 * f_h * (5.0 / 12.0 * r * r + (L / 2.0 + r / 2.0) ** 2)
    area = 2.0 * _PI * r * (L + 2.0 * r)
    return _uniform_body(what, area, np.zeros(3), np.array([k2_xx, k2_xx, k2_zz]), mass, density,
                         shell=True, frame=frame)


# ----------------------------------------------------------------------------- torus
def torus(major_radius, minor_radius, *, mass=None, density=None, kind: str = "solid", frame: str = "body"):
    """Uniform solid ring torus or thin toroidal shell; ring in the xy plane, axis z, centered.

    Parameters
    ----------
    major_radius : float, m
        Distance ``R`` from the z axis to the center of the tube.
    minor_radius : float, m
        Radius ``a`` of the tube's circular cross-section, ``a <= R`` (``a = R`` is the
        horn torus; ``a > R`` would be a self-intersecting spindle torus and is refused).
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the solid; kg/m^2 for ``kind="shell"``.
    kind : {"solid", "shell"}, default "solid"
        Thin shell over the torus surface (uniform surface density).
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; diagonal inertia about the COM; ``volume = 2 pi^2 R a^2`` (NaN for the shell).

    Notes
    -----
    Solid (Wikipedia list, "solid torus"): ``I_zz = m (R^2 + 3 a^2 / 4)``,
    ``I_xx = I_yy = m (R^2 / 2 + 5 a^2 / 8)``.

    Shell, derived with ``rho = R + a cos v``, ``z = a sin v``,
    ``dA = a (R + a cos v) du dv``: ``A = 4 pi^2 R a``,
    ``int rho^2 dA = 4 pi^2 R a (R^2 + 3 a^2 / 2)``, ``int z^2 dA = 2 pi^2 R a^3``, so
    ``I_zz = m (R^2 + 3 a^2 / 2)``, ``I_xx = I_yy = m (R^2 / 2 + 5 a^2 / 4)``.
    """
    shell = _is_shell(kind, "torus")
    what = "torus shell" if shell else "torus"
    R = _length(major_radius, "major_radius", "torus")
    a = _length(minor_radius, "minor_radius", "torus")
    if a > R:
        raise InputError(f"torus: minor_radius must not exceed major_radius (a spindle torus intersects itself), "
                         f"got minor_radius = {a!r} m > major_radius = {R!r} m")
    if not shell:
        # Wikipedia list, "solid torus".
        k2 = np.array([R * R / 2.0 + 5.0 * a * a / 8.0, R * R / 2.0 + 5.0 * a * a / 8.0, R * R + 0.75 * a * a])
        return _uniform_body(what, 2.0 * _PI ** 2 * R * a * a, np.zeros(3), k2, mass, density,
                             shell=False, frame=frame)
    # Derived in the docstring (Pappus-type integration over the surface of revolution).
    k2 = np.array([R * R / 2.0 + 1.25 * a * a, R * R / 2.0 + 1.25 * a * a, R * R + 1.5 * a * a])
    return _uniform_body(what, 4.0 * _PI ** 2 * R * a, np.zeros(3), k2, mass, density, shell=True, frame=frame)


# ----------------------------------------------------------------------------- thick spherical shell
def spherical_shell(outer_radius, inner_radius=None, *, mass=None, density=None, frame: str = "body"):
    """Uniform hollow sphere: thick (between two radii) or, without ``inner_radius``, thin.

    Parameters
    ----------
    outer_radius : float, m
    inner_radius : float, m, optional
        Radius of the concentric spherical cavity, ``0 < inner_radius < outer_radius``.
        ``None`` (default) gives the thin shell of radius ``outer_radius``, the same as
        ``sphere(outer_radius, kind="shell")``.  Equal radii are refused (the thick shell
        would have no volume); use ``inner_radius=None`` for the thin-shell limit.
    mass : float, kg, optional
        Give exactly one of ``mass`` and ``density``.
    density : float, optional
        kg/m^3 for the thick shell; kg/m^2 for the thin shell (``inner_radius=None``).
    frame : str, default "body"

    Returns
    -------
    MassProperties
        COM = 0; isotropic inertia about the COM; ``volume = 4/3 pi (r2^3 - r1^3)``
        (NaN for the thin shell).

    Notes
    -----
    Thick shell: a ball of radius r2 minus a concentric ball of radius r1 at the same
    density (each ``2/5 m r^2``, Wikipedia list, "solid sphere (ball)"), so
    ``I = 2/5 m (r2^5 - r1^5) / (r2^3 - r1^3)``, evaluated without
    cancellation as ``2/5 m r2^2 (1 + t + t^2 + t^3 + t^4) / (1 + t + t^2)``,
    ``t = r1 / r2``.  It tends to the thin-shell ``2/3 m r^2`` as ``t -> 1``.
    """
    r2 = _length(outer_radius, "outer_radius", "spherical_shell")
    if inner_radius is None:
        return sphere(r2, mass=mass, density=density, kind="shell", frame=frame)
    r1 = _length(inner_radius, "inner_radius", "spherical_shell")
    if not r1 < r2:
        raise InputError(f"spherical_shell: inner_radius must be smaller than outer_radius, got inner_radius = "
                         f"{r1!r} m >= outer_radius = {r2!r} m (for a thin shell leave inner_radius=None)")
    t = r1 / r2
    # Ball minus cavity (Wikipedia list, "solid sphere (ball)", 2/5 m r^2 each, same density):
    # I / m = 2/5 (r2^5 - r1^5) / (r2^3 - r1^3), with the common factor (r2 - r1) divided out.
    k2 = 0.4 * r2 * r2 * (1.0 + t + t * t + t ** 3 + t ** 4) / (1.0 + t + t * t)
    # r2^3 - r1^3 = (r2 - r1)(r2^2 + r2 r1 + r1^2): no cancellation beyond the exact r2 - r1.
    volume = 4.0 / 3.0 * _PI * (r2 - r1) * (r2 * r2 + r2 * r1 + r1 * r1)
    return _uniform_body("spherical_shell", volume, np.zeros(3), np.full(3, k2), mass, density,
                         shell=False, frame=frame)
