"""Polhodes: the path of the angular momentum seen from the body, on the sphere |m| = |L|.

``m = I omega`` in the principal frame keeps its length (torque-free) and the energy
``sum m_i^2 / I_i``, so it runs along the intersection of a sphere and an ellipsoid.  The
curves here come from the exact solution (a fan of initial conditions around the minor and
major axes), the separatrix in closed form; all are scaled to the unit sphere.  The plot and
the 3D page both draw them.
"""

from __future__ import annotations

import numpy as np


def fan(moments, *, angles=np.linspace(0.15, 1.45, 6), samples: int = 240) -> list[np.ndarray]:
    """Closed polhodes (n, 3) on the unit sphere around the minor and major axes (both poles)."""
    from ..dynamics.exact import ExactSolution

    I = np.asarray(moments, float)
    curves = []
    for a in angles:
        for sign in (1, -1):
            for axis in (0, 2):
                m0 = np.zeros(3)
                m0[axis] = sign * np.cos(a)
                m0[1] = np.sin(a)
                motion = ExactSolution(I, m0 / I, validate=False)
                if not np.isfinite(motion.period):      # a sphere or a steady spin: no curve to draw
                    continue
                m = motion.omega_body(np.linspace(0.0, motion.period, samples)) * I
                curves.append(m / np.linalg.norm(m, axis=1, keepdims=True))
    return curves


def separatrix(moments, samples: int = 241) -> list[np.ndarray]:
    """The two great-circle-like curves through the intermediate axis (2E = |L|^2 / I2):
    ``m3 = +-c m1`` with ``c^2 = (1/I1 - 1/I2) / (1/I2 - 1/I3)``, on the unit sphere."""
    I = np.asarray(moments, float)
    th = np.linspace(0, 2 * np.pi, samples)
    c = np.sqrt((1 / I[0] - 1 / I[1]) / (1 / I[1] - 1 / I[2]))
    m1 = np.cos(th) / np.sqrt(1 + c ** 2)
    return [np.stack([m1, np.sin(th), s * c * m1], axis=1) for s in (1, -1)]


def path(study) -> np.ndarray:
    """This spin's momentum in the principal frame over the study, on the unit sphere."""
    m = study.omega_exact * study.moments
    return m / np.linalg.norm(m, axis=1, keepdims=True)
