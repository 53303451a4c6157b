"""Area and second moments of an ellipsoid's surface, by graded Gauss-Legendre quadrature.

The surface of a triaxial ellipsoid has no elementary closed form (its area needs
incomplete elliptic integrals, its second moments more); this quadrature reaches rounding
for every aspect ratio, down to flat discs and needles (see the constants' notes).
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

__all__ = ["ellipsoid_surface_moments"]

_PI = math.pi


#: Gauss-Legendre nodes per panel of the ellipsoid-surface quadrature.  With the
#: panels graded so that each is no wider than its distance to the nearest
#: singularity, the error per panel is below rho^(-2n) with rho >= 4.6: 1e-26 at n = 20.
_ELLIPSOID_NODES_PER_PANEL = 20

#: At most this many halvings toward the singular end (first panel >= 2^-48 * pi/2,
#: about 6e-15 rad).  A singularity closer than that (aspect ratio below ~1e-14) is
#: left unresolved inside the first panel, whose whole contribution to the integrals
#: is O(panel width^2) ~ 1e-29 relative, far below rounding.
_ELLIPSOID_MAX_LEVELS = 48


@lru_cache(maxsize=1)
def _gauss_legendre_unit() -> tuple[np.ndarray, np.ndarray]:
    """Gauss-Legendre nodes and weights on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(_ELLIPSOID_NODES_PER_PANEL)
    return 0.5 * (x + 1.0), 0.5 * w


def _graded_rule(upper: float, delta: float) -> tuple[np.ndarray, np.ndarray]:
    """Composite Gauss-Legendre rule on [0, upper] with panels halving toward 0.

    The first panel is no wider than ``delta``, the distance of the integrand's
    nearest complex singularity from 0; every other panel is at least half as far
    from it as it is wide, so each panel converges geometrically.
    """
    if not math.isfinite(delta) or delta >= upper:
        levels = 0  # singularity far away (or none): one panel
    elif delta <= upper * 0.5 ** _ELLIPSOID_MAX_LEVELS:
        levels = _ELLIPSOID_MAX_LEVELS  # extreme aspect ratio: see _ELLIPSOID_MAX_LEVELS
    else:
        levels = int(math.ceil(math.log2(upper / delta)))
    edges = np.concatenate(([0.0], upper * 0.5 ** np.arange(levels, -1, -1)))
    x01, w01 = _gauss_legendre_unit()
    lo, width = edges[:-1, None], np.diff(edges)[:, None]
    return (lo + width * x01).ravel(), (width * w01).ravel()


def ellipsoid_surface_moments(a: float, b: float, c: float) -> tuple[float, np.ndarray]:
    """Area [m^2] and mean squares ``(int x^2 dA, int y^2 dA, int z^2 dA) / area`` [m^2] of the ellipsoid surface.

    Parametrise about the longest semi-axis p (middle q, shortest s):
    ``X_p = p cos t, X_q = q sin t cos f, X_s = s sin t sin f``; the area element is
    ``dA = sin t sqrt(q^2 s^2 cos^2 t + p^2 s^2 sin^2 t cos^2 f + p^2 q^2 sin^2 t sin^2 f) dt df``.
    Its zeros in the complex plane lie at ``t = i atanh(s / p)`` (closest, at f = pi/2)
    and ``f = i asinh(s / sqrt(q^2 - s^2))`` (closest, at t = pi/2), so the rules are
    graded toward t = 0 and f = 0.  Every integrand is even in each coordinate: integrate
    one octant (t, f in [0, pi/2]) and multiply by 8.  The integration runs on the
    ellipsoid scaled to p = 1 (then area x p^2, mean squares x p^2), so no
    intermediate overflows or underflows for any size.
    """
    order = np.argsort([-a, -b, -c], kind="stable")  # longest first
    scale = max(a, b, c)
    p, q, s = (float(v) / scale for v in np.array([a, b, c])[order])
    delta_t = math.atanh(s / p) if s < p else math.inf
    delta_f = math.asinh(s / math.sqrt((q - s) * (q + s))) if s < q else math.inf
    t, wt = _graded_rule(0.5 * _PI, delta_t)
    f, wf = _graded_rule(0.5 * _PI, delta_f)
    ct, st = np.cos(t)[:, None], np.sin(t)[:, None]
    cf, sf = np.cos(f)[None, :], np.sin(f)[None, :]
    dA = st * np.sqrt((q * s * ct) ** 2 + (p * s * st * cf) ** 2 + (p * q * st * sf) ** 2)
    W = 8.0 * wt[:, None] * wf[None, :] * dA
    area = float(W.sum())
    S_pqs = np.array([(W * (p * ct) ** 2).sum(), (W * (q * st * cf) ** 2).sum(), (W * (s * st * sf) ** 2).sum()])
    mean_sq = np.empty(3)
    mean_sq[order] = S_pqs / area  # back to the x, y, z order of the caller
    return area * scale * scale, mean_sq * (scale * scale)
