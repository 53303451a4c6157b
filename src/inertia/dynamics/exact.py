"""Exact torque-free motion of a rigid body: angular velocity and attitude in closed form.

For a free rigid body with principal moments ``I1 <= I2 <= I3`` the body angular velocity
is a Jacobi elliptic function of time and the attitude follows from one incomplete elliptic
integral of the third kind (Jacobi 1849; Landau & Lifshitz, *Mechanics* §37).  This module
evaluates that solution at any time for the cost of one call, whatever the time: the
elliptic functions are reduced by their periods and the attitude angle is split into whole
half periods plus a remainder, so ``t = 1e6 s`` costs the same as ``t = 1 s``.

Regimes (:attr:`ExactSolution.regime`):

``"minor_axis"``
    kinetic energy above the separatrix (``2T > G^2/I2``): the angular momentum circulates
    about the minor axis e1 (smallest moment).
``"major_axis"``
    energy below the separatrix: circulation about the major axis e3.
``"separatrix"``
    ``2T = G^2/I2`` exactly: hyperbolic functions, the motion tends to a spin about +-e2.
``"symmetric_top"``
    two equal moments: trigonometric (regular precession).
``"sphere"``
    three equal moments: constant angular velocity.
``"steady_spin"``
    the angular velocity lies exactly along a principal axis: constant.
``"rest"``
    zero angular velocity.

Formulas (``m_body = I w`` the body angular momentum, ``G = |m_body|``, ``2T = m_body . w``,
``D_j = G^2 - 2T I_j`` computed without cancellation)::

    u = lam t + u0
    major: w1 = A cn(u|m), w2 = s B sn(u|m), w3 = s C dn(u|m),   s = sign w3
    minor: w3 = A cn(u|m), w2 = s B sn(u|m), w1 = s C dn(u|m),   s = sign w1

with ``A, B, C, lam, m`` given in ``EllipticMotion``.  The attitude is written as

    R_WB(t) = R_WB(0) P(m0)^T Rot(d, psi(t)) P(m(t))

where ``d = s e3`` (major) or ``s e1`` (minor) is the body axis that the angular momentum
never leaves the hemisphere of, ``P(m)`` is the minimal rotation taking ``m/G`` onto ``d``
(never singular because ``m.d > 0``), and::

    psi(t) = (G/I_d) t + s_c G (I3 - I1) / (lam I1 I3) [J(u) - J(u0)]
    J(u)   = Pi(n; am u | m) - a / sqrt(1 - n) * atan(sqrt(1 - n) tan(am u))   (continuous branch)

with ``a = |m_d|max / G``, ``n = -a^2 m / (1 - a^2)`` (depends only on the moments, always
negative) and ``s_c = +1`` (major) or ``-1`` (minor).  This gauge is well conditioned up
to the separatrix (the basis {m, dm/dt, m x dm/dt} of Celledoni et al. is not).

Sources: Landau & Lifshitz §37; Celledoni, Fassò, Säfström & Zanna, SIAM J. Sci. Comput.
30 (2008) 2084, with the corrections of P. Leroy ("On an Article by Celledoni et al.",
Principia); van Zon & Schofield, J. Comput. Phys. 225 (2007) 145.  The parametrisation
and every sign were re-derived and checked against DOP853 (``tests/dynamics/test_exact.py``);
see ``docs/exact-solution.md`` for the derivation and the measured accuracy.

Conventions: SI units (rad/s, kg m^2, s); quaternions scalar first ``(w, x, y, z)``;
``q_world_body`` maps body to world coordinates; ``omega_body`` is expressed in the body
frame.  The moments may be given in any order: the body frame is then re-labelled
internally by a proper rotation (a signed permutation) and the results are returned in
the body frame as given.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InputError
from .._core.rotations import matrix_to_quat, quat_conjugate, quat_multiply, quat_to_matrix
from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array, as_unit_quat
from ..massprops.principal import principal_axes
from ..massprops.validity import as_principal_moments
from .exact_motions import (
    ConstantMotion,
    EllipticMotion,
    SeparatrixMotion,
    SymmetricTopMotion,
    axis_angle_quat,
    deltas,
    minimal_rotation_quat,
)

__all__ = [
    "exact_solution",
    "ExactSolution",
    "FreeBody",
    "REGIMES",
]

#: The regimes :class:`ExactSolution` distinguishes (its ``regime`` attribute).
REGIMES = ("minor_axis", "major_axis", "separatrix", "symmetric_top", "sphere", "steady_spin", "rest")



# ============================================================================ input checks
def _as_times(t) -> np.ndarray:
    try:
        ta = np.asarray(t, dtype=float)
    except (TypeError, ValueError):
        raise InputError(f"t must be a number or an array of times in s, got {t!r}") from None
    if not np.all(np.isfinite(ta)):
        bad = ta[~np.isfinite(ta)].ravel()[0]
        raise InputError(f"t must hold finite times in s, got {bad!r}")
    return ta


# ============================================================================ public class
class ExactSolution:
    """Exact torque-free motion of one rigid body, constants precomputed; evaluate with :meth:`at`.

    Parameters
    ----------
    moments : (3,) float, kg m^2
        Principal moments of inertia about the center of mass, in the body axes x, y, z
        (the inertia matrix is ``diag(moments)`` in the body frame).  Any order; they must
        describe a physical body (positive, ``I1 + I2 >= I3``).
    omega0_body : (3,) float, rad/s
        Initial angular velocity in the body frame.
    q0_world_body : (4,) float
        Initial attitude, unit quaternion ``(w, x, y, z)``, body -> world.  Default identity.
    validate : bool, keyword-only
        Refuse moments that violate the triangle inequality (default).  ``False`` accepts
        any positive moments (textbook test bodies); positivity is always required.
    equal_rtol : float, keyword-only
        Moments closer than ``equal_rtol * I3`` are treated as equal
        (:data:`REPEATED_MOMENTS_RTOL`).

    Attributes
    ----------
    regime : str
        One of :data:`REGIMES`.
    period : float, s
        Period of ``omega_body(t)`` (the polhode period ``4 K(m) / lam``); ``inf`` on the
        separatrix (never returns); NaN when ``omega_body`` is constant.
    rate : float, 1/s
        ``lam`` of ``u = lam t + u0`` (elliptic regimes), the growth rate on the separatrix,
        ``|Omega|`` for the symmetric top, NaN otherwise.
    parameter, complementary_parameter : float
        ``m`` and ``1 - m`` of the elliptic functions (NaN outside the elliptic regimes; the
        separatrix has ``m = 1``).
    rotation_per_period : float, rad
        Angle ``DeltaPsi`` of ``R(t + T) = Rot(L_world, DeltaPsi) R(t)`` (elliptic regimes;
        ``2 pi`` times the rotation number, not reduced mod 2 pi), NaN otherwise.
    energy : float, J
        Kinetic energy ``1/2 w . I w``.
    angular_momentum_norm : float, kg m^2/s
        ``G = |I w|``.
    angular_momentum_world : (3,) float, kg m^2/s
        The conserved spatial angular momentum ``R_WB I w``.

    Notes
    -----
    The cost of :meth:`at` does not depend on ``t``: elliptic functions are reduced by their
    period and the attitude angle is split into whole half periods plus a remainder.  The
    accuracy degrades only as ``eps * |t| / period`` (the rounding of ``t`` itself).

    Examples
    --------
    >>> body = ExactSolution([1.0, 2.0, 3.0], [0.01, 1.0, 0.0])
    >>> body.regime, round(body.period / 2, 10)
    ('minor_axis', 20.7546097647)
    >>> q, w = body.at([0.0, 1.0, 1e6])
    >>> q.shape, w.shape
    ((3, 4), (3, 3))
    >>> body.at(2.5)[1].shape
    (3,)
    """

    def __init__(self, moments, omega0_body, q0_world_body=(1.0, 0.0, 0.0, 0.0), *,
                 validate: bool = True, equal_rtol: float = REPEATED_MOMENTS_RTOL):
        I_B = as_principal_moments(moments, validate=validate, allow_batch=False)
        w0_B = as_float_array(omega0_body, "omega0_body", (3,), allow_batch=False)
        q0 = as_unit_quat(q0_world_body, "q0_world_body", allow_batch=False)
        self.moments = I_B
        self.omega0_body = w0_B
        self.q0_world_body = q0

        # internal principal frame P: moments ascending, R_BP the signed permutation that sorts them
        I, R_BP = principal_axes(np.diag(I_B))
        self._R_BP = R_BP
        self._q_BP = matrix_to_quat(R_BP)
        w0 = R_BP.T @ w0_B
        self._I = I
        m0 = I * w0
        self.energy = 0.5 * float(m0 @ w0)
        self.angular_momentum_norm = G = float(np.linalg.norm(m0))
        self.angular_momentum_world = quat_to_matrix(q0) @ (I_B * w0_B)
        self._q_WP0 = quat_multiply(q0, self._q_BP)

        # not defined for every regime: NaN until the regime below sets them
        self.rate = self.parameter = self.complementary_parameter = math.nan
        self.rotation_per_period = self.period = math.nan
        self._motion = None

        scale = I[2]
        eq01 = I[1] - I[0] <= equal_rtol * scale
        eq12 = I[2] - I[1] <= equal_rtol * scale
        D = deltas(I, m0 / G) if G > 0 else (0.0, 0.0, 0.0)
        if G == 0.0:
            self.regime = "rest"
            self._motion = ConstantMotion(w0)
        elif eq01 and eq12:
            self.regime = "sphere"
            self._motion = ConstantMotion(w0)
        elif eq01 or eq12:
            s_axis = 2 if eq01 else 0
            pair = (0, 1) if eq01 else (1, 2)
            I_t = 0.5 * (I[pair[0]] + I[pair[1]])
            transverse = np.delete(w0, s_axis)
            if not np.any(transverse) or w0[s_axis] == 0.0:
                self.regime = "steady_spin"
                self._motion = ConstantMotion(w0)
            else:
                self.regime = "symmetric_top"
                top = SymmetricTopMotion(I, w0, s_axis, I_t)
                self._motion = top
                self.rate = abs(top.Omega)
                self.period = 2.0 * math.pi / abs(top.Omega)
        elif D[0] == 0.0 or D[2] == 0.0 or (w0[0] == 0.0 and w0[2] == 0.0):
            # exactly along a principal axis (D1 = 0: e1; D3 = 0: e3; m1 = m3 = 0: e2)
            self.regime = "steady_spin"
            self._motion = ConstantMotion(w0)
        elif D[1] == 0.0:
            self.regime = "separatrix"
            sep = SeparatrixMotion(I, w0, G, D)
            self._motion = sep
            self.rate = abs(sep.lam)
            self.parameter, self.complementary_parameter = 1.0, 0.0
            self.period = math.inf
        else:
            ell = EllipticMotion(I, w0, G=G, D=D, major=D[1] > 0)
            self.regime = "major_axis" if ell.major else "minor_axis"
            self._motion = ell
            self.rate = ell.lam
            self.parameter = ell.m
            self.complementary_parameter = ell.mc
            self.period = ell.period
            self.rotation_per_period = ell.rotation_per_period
        if isinstance(self._motion, (EllipticMotion, SeparatrixMotion)):
            # q_WP(t) = q_WP0 p(m0)^* Rot(d, psi(t)) p(m(t)): the constant left factor
            self._q_left = quat_multiply(self._q_WP0,
                                         quat_conjugate(minimal_rotation_quat(m0 / G, self._motion.d)))

    # ---------------------------------------------------------------- evaluation
    def _omega_q_principal(self, t):
        mot = self._motion
        if isinstance(mot, (EllipticMotion, SeparatrixMotion)):
            w, psi = mot.omega_psi(t)
            mvec = self._I * w
            n_hat = mvec / np.linalg.norm(mvec, axis=-1, keepdims=True)
            p = minimal_rotation_quat(n_hat, mot.d)
            q = quat_multiply(quat_multiply(self._q_left, axis_angle_quat(mot.d, psi)), p)
        else:
            w = mot.omega(t)
            q = quat_multiply(self._q_WP0, mot.quat_from_start(t))
        return w, q

    def at(self, t):
        """Attitude and angular velocity at time(s) ``t``.

        Parameters
        ----------
        t : (...) float, s
            Times (any real, any shape); ``t = 0`` is the initial state.

        Returns
        -------
        q_world_body : (..., 4) float
            Unit quaternions, body -> world.  Continuous in t and equal to
            ``q0_world_body`` at ``t = 0`` (not sign-canonicalised).
        omega_body : (..., 3) float, rad/s
            Angular velocity in the body frame.
        """
        ta = _as_times(t)
        w_P, q_WP = self._omega_q_principal(ta)
        w_B = w_P @ self._R_BP.T
        q_WB = quat_multiply(q_WP, quat_conjugate(self._q_BP))
        return q_WB, w_B

    __call__ = at

    def omega_body(self, t) -> np.ndarray:
        """Angular velocity (..., 3) [rad/s] in the body frame at times ``t`` (...)."""
        return self.at(t)[1]

    def q_world_body(self, t) -> np.ndarray:
        """Attitude quaternions (..., 4), body -> world, at times ``t`` (...)."""
        return self.at(t)[0]

    def R_world_body(self, t) -> np.ndarray:
        """Attitude matrices (..., 3, 3), ``v_W = R_WB v_B``, at times ``t`` (...)."""
        return quat_to_matrix(self.at(t)[0])

    def psi(self, t) -> np.ndarray:
        """Angle [rad] of the rotation about the angular momentum in the minimal gauge.

        Defined for the elliptic and separatrix regimes only (``psi(0) = 0``): the angle of
        ``Rot(d, psi)`` in ``R(t) = R0 P(m0)^T Rot(d, psi) P(m(t))``.  Provided for checks
        against published values; NaN in the other regimes.
        """
        ta = _as_times(t)
        if isinstance(self._motion, (EllipticMotion, SeparatrixMotion)):
            return self._motion.psi(ta)
        return np.full(ta.shape, math.nan)

    @property
    def flip_interval(self) -> float:
        """Time [s] between successive sign changes of the intermediate-axis angular velocity.

        ``period / 2 = 2 K(m) / lam`` in the elliptic regimes; ``inf`` when that component
        never changes sign (separatrix, steady spin); NaN when the body has no unique
        intermediate axis (two or three equal moments) or is at rest.
        """
        if self.regime in ("minor_axis", "major_axis"):
            return 0.5 * self.period
        I1, I2, I3 = self._I
        distinct = I2 - I1 > REPEATED_MOMENTS_RTOL * I3 and I3 - I2 > REPEATED_MOMENTS_RTOL * I3
        if self.regime in ("separatrix", "steady_spin") and distinct:
            return math.inf
        return math.nan

    def flip_times(self, t_start: float, t_end: float) -> np.ndarray:
        """Times in ``[t_start, t_end]`` at which the intermediate-axis component of omega is zero.

        Exact: ``sn(lam t + u0) = 0`` at ``t_k = (2 K k - u0) / lam``.  Empty outside the
        elliptic regimes.
        """
        mot = self._motion
        if not isinstance(mot, EllipticMotion):
            return np.empty(0)
        t0, t1 = float(t_start), float(t_end)
        k0 = math.ceil((mot.lam * t0 + mot.u0) / (2.0 * mot.K))
        k1 = math.floor((mot.lam * t1 + mot.u0) / (2.0 * mot.K))
        ks = np.arange(k0, k1 + 1, dtype=float)
        return (2.0 * mot.K * ks - mot.u0) / mot.lam

    def __repr__(self) -> str:
        return (f"ExactSolution(moments={self.moments.tolist()}, omega0_body={self.omega0_body.tolist()}, "
                f"regime={self.regime!r}, period={self.period:.12g})")


#: Alias: the exact solution *is* the free body's motion.
FreeBody = ExactSolution


def exact_solution(moments, omega0_body, t, q0_world_body=(1.0, 0.0, 0.0, 0.0), *, validate: bool = True):
    """Exact torque-free attitude and angular velocity of a rigid body at times ``t``.

    Parameters
    ----------
    moments : (3,) float, kg m^2
        Principal moments about the center of mass in the body axes (any order).
    omega0_body : (3,) float, rad/s
        Initial angular velocity in the body frame.
    t : (...) float, s
        Times at which to evaluate (any shape, any real values).
    q0_world_body : (4,) float
        Initial attitude ``(w, x, y, z)``, body -> world (default identity).
    validate : bool, keyword-only
        ``False`` accepts positive moments that violate the triangle inequality.

    Returns
    -------
    q_world_body : (..., 4) float
    omega_body : (..., 3) float, rad/s

    See :class:`ExactSolution` (which precomputes the constants for repeated calls).

    Examples
    --------
    >>> q, w = exact_solution([1, 2, 3], [0.01, 1, 0], np.linspace(0, 10, 5))
    >>> q.shape, w.shape
    ((5, 4), (5, 3))
    >>> exact_solution([1, 2, 3], [0.01, 1, 0], 1e6)[1].shape
    (3,)
    """
    return ExactSolution(moments, omega0_body, q0_world_body, validate=validate).at(t)
