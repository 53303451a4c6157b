"""OpenUSD stages (UsdPhysics): read each rigid body's mass properties, check them, repair them.

Needs usd-core (the ``usd`` extra: ``pip install 'inertia[usd]'``), imported on first use:
:mod:`.stage` reads the stage through usd-core, :mod:`.mass` applies UsdPhysics' precedence
rules, :mod:`.check` lists problems, :mod:`.write` writes MassAPI attributes back.
"""

from __future__ import annotations

from ..._core.lazy import lazy_namespace

_EXPORTS = {
    "read_stage": "stage", "is_usd_path": "stage", "USD_EXTENSIONS": "stage",
    "stage_mass_properties": "mass", "body_mass": "mass", "check_stage": "check", "fix_stage": "write",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ())
