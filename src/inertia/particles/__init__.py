"""Equivalent particle models of rigid bodies (six-point and minimal four-point).

See :mod:`inertia.particles.models`.  This layer builds on :mod:`inertia.massprops` and is
never imported by it.
"""

from __future__ import annotations

from .models import TETRAHEDRON_SIGNS, ParticleModel, four_point_model, six_point_model

__all__ = ["ParticleModel", "TETRAHEDRON_SIGNS", "four_point_model", "six_point_model"]
