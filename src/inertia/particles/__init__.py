"""Equivalent particle models of rigid bodies (six-point and minimal four-point).

See :mod:`inertia.particles.models`.  This layer builds on :mod:`inertia.massprops` and is
never imported by it.  Names are imported lazily.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_EXPORTS = {"ParticleModel": "models", "four_point_model": "models",
            "six_point_model": "models"}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ("models",))
