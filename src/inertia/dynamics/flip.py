"""The intermediate-axis (Dzhanibekov) flip and the stability of steady spin about each axis.

A body spun about its intermediate principal axis (moment ``I2`` of ``I1 < I2 < I3``)
periodically turns over: the angular momentum, seen from the body, runs from near ``+e2``
to near ``-e2`` and back.  In the exact solution the intermediate-axis component is
``w2 = s B sn(lam t + u0 | m)``, so successive sign changes are half a polhode period apart::

    flip interval  T/2 = 2 K(m) / lam
    near the separatrix (k' = sqrt(1 - m) -> 0):  T/2 ~ (2 / lam) ln(4 / k')

The interval grows only logarithmically as the initial wobble shrinks (``k'`` is of the
order of the wobble angle), which is why the flip is so easy to see.  Worked example:
``I = (1, 2, 3)``, ``w0 = (0.01, 1, 0)`` flips every 20.7546097647 s (the log
approximation gives 20.7541775282 s).

Flip detection in a sampled trajectory (:func:`detect_flips`) uses a Schmitt trigger on
the body-frame direction of the angular momentum, ``n2 = m2 / |m|`` with ``m = I w``: a flip
is a passage from ``n2 >= +threshold`` to ``n2 <= -threshold`` (or back), and its time is
the zero crossing of ``n2`` inside that passage.  The hysteresis makes the count immune to
jitter near ``n2 = 0`` and ignores small wobbles about the minor or major axis, which also
change the sign of ``w2`` but are not flips.  With ``threshold=0`` every sign change counts.

Linear stability (:func:`axis_stability`): linearising ``I dw/dt = (I w) x w`` about
``w = Omega e_j`` (k, l the other two axes) gives the eigenvalues::

    0,  +-Omega sqrt((I_j - I_k)(I_l - I_j) / (I_k I_l))

real (a saddle: unstable) for the intermediate axis, purely imaginary (a centre: stable,
and Lyapunov stable by the energy-Casimir argument) for the minor and major axes.

Sources: Landau & Lifshitz, *Mechanics* §37; Ashbaugh, Chicone & Cushman, "The twisting
tennis racket", J. Dyn. Diff. Eq. 3 (1991); ``shared/notes/free-rigid-body.md`` §3-4.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.tolerances import REPEATED_MOMENTS_RTOL
from .._core.validation import as_float_array
from ..massprops.validity import as_principal_moments
from .exact import ExactSolution

__all__ = [
    "flip_interval",
    "flip_interval_approx",
    "flip_times",
    "detect_flips",
    "Flips",
    "intermediate_axis",
    "axis_stability",
    "AxisStability",
    "euler_jacobian",
    "unstable_axis",
]


# ============================================================================ prediction
def flip_interval(moments, omega0_body, *, validate: bool = True) -> float:
    """Predicted time [s] between successive flips: ``2 K(m) / lam`` (half the polhode period).

    Parameters
    ----------
    moments : (3,) float, kg m^2
        Principal moments in the body axes (any order).
    omega0_body : (3,) float, rad/s
        Initial angular velocity in the body frame.
    validate : bool
        ``False`` accepts positive moments violating the triangle inequality.

    Returns
    -------
    float
        Seconds between sign changes of the intermediate-axis component of ``omega_body``.
        ``inf`` when it never changes sign (exactly on the separatrix, or a steady spin);
        NaN when there is no unique intermediate axis (two equal moments) or no motion.

    Examples
    --------
    >>> round(flip_interval([1, 2, 3], [0.01, 1, 0]), 10)
    20.7546097647
    """
    return ExactSolution(moments, omega0_body, validate=validate).flip_interval


def flip_interval_approx(moments, omega0_body, *, order: int = 0, validate: bool = True) -> float:
    """Near-separatrix approximation of the flip interval [s].

    ``order=0``: ``(2 / lam) ln(4 / k')``; ``order=1`` adds the next term of
    ``K(m) = ln(4/k') + (k'^2/4)(ln(4/k') - 1) + O(k'^4 ln k')``, with ``k' = sqrt(1 - m)``
    and ``lam`` the exact rate of the elliptic solution.  The relative error of order 0 is
    about ``k'^2 / 4``: 2e-5 for the worked example (20.7541775282 vs 20.7546097647).
    NaN outside the elliptic regimes.
    """
    if order not in (0, 1):
        raise InputError(f"order must be 0 or 1, got {order!r}")
    sol = ExactSolution(moments, omega0_body, validate=validate)
    if sol.regime not in ("minor_axis", "major_axis"):
        return sol.flip_interval
    kp = math.sqrt(sol.complementary_parameter)
    log_term = math.log(4.0 / kp)
    K = log_term if order == 0 else log_term + 0.25 * kp * kp * (log_term - 1.0)
    return 2.0 * K / sol.rate


def flip_times(moments, omega0_body, t_end: float, t_start: float = 0.0, *, validate: bool = True) -> np.ndarray:
    """Exact times in ``[t_start, t_end]`` [s] at which the intermediate-axis angular velocity is zero.

    These are the flip instants of the exact solution (``sn(lam t + u0) = 0``); empty
    outside the elliptic regimes.

    Examples
    --------
    >>> flip_times([1, 2, 3], [0.01, 1, 0], 60.0).round(6).tolist()
    [10.377305, 31.131915, 51.886524]
    """
    return ExactSolution(moments, omega0_body, validate=validate).flip_times(t_start, t_end)


# ============================================================================ detection
@dataclass(frozen=True)
class Flips:
    """Flips found in a sampled trajectory by :func:`detect_flips`.

    Attributes
    ----------
    times : (k,) float, s
        Zero crossings of ``n2 = m2/|m|`` (linear interpolation between samples).
    directions : (k,) int
        ``+1`` for a flip from ``-e2`` to ``+e2`` (``n2`` increasing), ``-1`` for the reverse.
    axis : int
        Index (0, 1, 2) of the intermediate axis in the body frame.
    threshold : float
        The hysteresis level used.
    """

    times: np.ndarray
    directions: np.ndarray
    axis: int
    threshold: float

    @property
    def intervals(self) -> np.ndarray:
        """(k - 1,) times [s] between successive flips."""
        return np.diff(self.times)

    def __len__(self) -> int:
        return len(self.times)


def intermediate_axis(moments) -> int:
    """Index (0, 1, 2) of the intermediate principal moment; InputError when two moments are equal."""
    I = as_principal_moments(moments, validate=False, allow_batch=False)
    order = np.argsort(I, kind="stable")
    lo, mid, hi = I[order]
    if mid - lo <= REPEATED_MOMENTS_RTOL * hi or hi - mid <= REPEATED_MOMENTS_RTOL * hi:
        raise InputError(f"moments = ({', '.join(f'{x:.6g}' for x in I)}) have no unique intermediate axis "
                         f"(two moments are equal), so there is no intermediate-axis flip")
    return int(order[1])


def detect_flips(t, omega_body, moments, *, threshold: float = 0.5) -> Flips:
    """Find the intermediate-axis flips in a sampled trajectory.

    Definition: with ``n2 = m2 / |m|`` (``m = I w`` in the body frame, index 2 = the
    intermediate axis), a flip is a passage from ``n2 >= +threshold`` to ``n2 <= -threshold``
    or back (hysteresis, so jitter near zero counts once and small wobbles about the minor
    or major axis, with ``|n2| < threshold``, count never).  The flip time is the last zero
    crossing of ``n2`` before the far level is reached, located on the cubic through the
    four samples around it (linear interpolation at the ends of the record).

    Parameters
    ----------
    t : (N,) float, s
        Strictly increasing sample times.
    omega_body : (N, 3) float, rad/s
        Angular velocity in the body frame at ``t``.
    moments : (3,) float, kg m^2
        Principal moments in the body axes (any order); they pick the intermediate axis.
    threshold : float in [0, 1)
        Hysteresis level on ``n2`` (default 0.5: the angular momentum must come within 60
        degrees of each pole).  ``0`` counts every sign change.

    Returns
    -------
    Flips

    Examples
    --------
    >>> from .exact import exact_solution
    >>> ts = np.linspace(0.0, 100.0, 2001)
    >>> _, w = exact_solution([1, 2, 3], [0.01, 1, 0], ts)
    >>> flips = detect_flips(ts, w, [1, 2, 3])
    >>> len(flips), flips.intervals.round(4).tolist()
    (5, [20.7546, 20.7546, 20.7546, 20.7546])
    """
    k = intermediate_axis(moments)
    I = as_principal_moments(moments, validate=False, allow_batch=False)
    ta = as_float_array(t, "t", (), allow_batch=True)
    if ta.ndim != 1:
        raise InputError(f"t must have shape (N,), got {ta.shape}")
    w = as_float_array(omega_body, "omega_body", (3,))
    if w.shape != (len(ta), 3):
        raise InputError(f"omega_body must have shape (N, 3) = ({len(ta)}, 3) to match t, got {w.shape}")
    if len(ta) > 1 and not np.all(np.diff(ta) > 0):
        i = int(np.argmin(np.diff(ta)))
        raise InputError(f"t must be strictly increasing, got t[{i}] = {ta[i]!r} >= t[{i + 1}] = {ta[i + 1]!r}")
    th = float(threshold)
    if not (0.0 <= th < 1.0):
        raise InputError(f"threshold must lie in [0, 1) (a level of m2/|m|), got {threshold!r}")
    m = w * I
    norm = np.linalg.norm(m, axis=-1)
    with np.errstate(invalid="ignore", divide="ignore"):
        n2 = np.where(norm > 0, m[:, k] / np.where(norm > 0, norm, 1.0), 0.0)
    # Schmitt trigger: +1 at/above +th, -1 at/below -th, 0 in between (keeps the last level)
    level = np.where(n2 >= th, 1, np.where(n2 <= -th, -1, 0))
    at_level = np.flatnonzero(level)
    empty = Flips(np.empty(0), np.empty(0, dtype=int), k, th)
    if at_level.size < 2:
        return empty
    lv = level[at_level]
    change = np.flatnonzero(lv[1:] != lv[:-1]) + 1       # positions in at_level
    if change.size == 0:
        return empty
    arrive = at_level[change]                            # first sample at the new level
    positive = n2 >= 0.0
    crossings = np.flatnonzero(positive[1:] != positive[:-1])   # sign flips between c and c + 1
    last = crossings[np.searchsorted(crossings, arrive, side="left") - 1]
    times = np.array([_crossing_time(ta, n2, int(c)) for c in last])
    return Flips(times=times, directions=lv[change].astype(int), axis=k, threshold=th)


def _crossing_time(t, y, c: int) -> float:
    """Zero of ``y`` between samples ``c`` and ``c + 1`` (signs differ there).

    Cubic through the samples ``c - 1 .. c + 2`` when they exist (error O(h^4)), else the
    linear interpolant; the cubic's root is only taken if it lies in the bracket.
    """
    a, b = y[c], y[c + 1]
    t_lin = t[c] if a == b else t[c] + (t[c + 1] - t[c]) * a / (a - b)
    if c < 1 or c + 2 >= len(t):
        return float(t_lin)
    ts = t[c - 1:c + 3] - t[c]
    coef = np.polyfit(ts, y[c - 1:c + 3], 3)
    h = ts[2]
    roots = np.roots(coef)
    real = roots[np.abs(roots.imag) <= 1e-12 * max(h, 1.0)].real
    inside = real[(real >= 0.0) & (real <= h)]
    if inside.size == 0:
        return float(t_lin)
    return float(t[c] + inside[np.argmin(np.abs(inside - (t_lin - t[c])))])


# ============================================================================ stability
@dataclass(frozen=True)
class AxisStability:
    """Linear stability of steady spin about one principal axis.

    Attributes
    ----------
    axis : int
        Body axis index (0, 1, 2), in the order the moments were given.
    moment : float, kg m^2
    eigenvalues : (3,) complex, 1/s
        ``(0, +r, -r)``: eigenvalues of the linearised Euler equations.
    growth_rate : float, 1/s
        Largest real part (``> 0`` only for the intermediate axis).
    frequency : float, rad/s
        Nutation angular frequency (imaginary part) of a stable axis, else 0.
    classification : str
        ``"unstable"`` (real pair: saddle), ``"stable"`` (imaginary pair: centre; Lyapunov
        stable for the minor and major axes), ``"marginal"`` (zero pair: two equal moments
        or zero rate).
    """

    axis: int
    moment: float
    eigenvalues: np.ndarray
    growth_rate: float
    frequency: float
    classification: str


def euler_jacobian(moments, omega_body) -> np.ndarray:
    """Jacobian (..., 3, 3) [1/s] of ``dw/dt = I^-1 ((I w) x w)`` at ``omega_body`` (..., 3).

    ``J = I^-1 ([I w]_x - [w]_x I)`` (both factors of the cross product varied).
    """
    I = as_principal_moments(moments, validate=False, allow_batch=False)
    w = as_float_array(omega_body, "omega_body", (3,))
    Iw = w * I

    def skew(v):
        z = np.zeros(v.shape[:-1])
        return np.stack([np.stack([z, -v[..., 2], v[..., 1]], -1),
                         np.stack([v[..., 2], z, -v[..., 0]], -1),
                         np.stack([-v[..., 1], v[..., 0], z], -1)], -2)

    return (skew(Iw) - skew(w) * I) / I[:, None]


def axis_stability(moments, rate: float = 1.0, *, validate: bool = True) -> tuple[AxisStability, ...]:
    """Linear stability of steady spin at ``rate`` [rad/s] about each principal axis.

    Parameters
    ----------
    moments : (3,) float, kg m^2
        Principal moments in the body axes (any order).
    rate : float, rad/s
        Spin rate ``Omega`` (its sign does not matter).

    Returns
    -------
    tuple of three AxisStability, one per body axis in the given order.

    Examples
    --------
    >>> [s.classification for s in axis_stability([1, 2, 3])]
    ['stable', 'unstable', 'stable']
    >>> round(axis_stability([1, 2, 3])[1].growth_rate, 13)
    0.5773502691896
    """
    I = as_principal_moments(moments, validate=validate, allow_batch=False)
    try:
        Omega = abs(float(rate))
    except (TypeError, ValueError):
        raise InputError(f"rate must be a number (spin rate in rad/s), got {rate!r}") from None
    if not math.isfinite(Omega):
        raise InputError(f"rate must be finite (spin rate in rad/s), got {rate!r}")
    scale = float(I.max())
    out = []
    for j in range(3):
        k, l = (j + 1) % 3, (j + 2) % 3
        f1, f2 = I[j] - I[k], I[l] - I[j]
        p = f1 * f2 / (I[k] * I[l])
        degenerate = min(abs(f1), abs(f2)) <= REPEATED_MOMENTS_RTOL * scale
        r = Omega * math.sqrt(abs(p))
        if degenerate or Omega == 0.0:
            eig = np.zeros(3, dtype=complex)
            kind, growth, freq = "marginal", 0.0, 0.0
        elif p > 0:
            eig = np.array([0.0, r, -r], dtype=complex)
            kind, growth, freq = "unstable", r, 0.0
        else:
            eig = np.array([0.0, 1j * r, -1j * r], dtype=complex)
            kind, growth, freq = "stable", 0.0, r
        out.append(AxisStability(axis=j, moment=float(I[j]), eigenvalues=eig, growth_rate=growth,
                                 frequency=freq, classification=kind))
    return tuple(out)


def unstable_axis(moments) -> int | None:
    """Body axis index (0, 1, 2) of the unstable (intermediate) axis, or None if no axis is unstable."""
    for s in axis_stability(moments, 1.0, validate=False):
        if s.classification == "unstable":
            return s.axis
    return None
