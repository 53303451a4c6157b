"""Length units read at the edges (files, command line), and the plausibility checks that
catch a unit slip: a 30 mm part read in metres is 30 m across and weighs tons.

Inside the package everything is SI; a unit name is converted once, where it is read.
"""

from __future__ import annotations

import math

#: length unit name -> metres
LENGTH_UNITS = {"m": 1.0, "cm": 1e-2, "mm": 1e-3, "um": 1e-6, "in": 0.0254, "ft": 0.3048}

#: density used when neither a density nor a mass is given: water [kg/m^3]
DEFAULT_DENSITY = 1000.0

#: a body larger than this across [m] is "larger than a building" (a unit slip, usually)
LARGEST_PLAUSIBLE_M = 1000.0
#: a body smaller than this across [m] is "thinner than a hair" (about 70 um)
SMALLEST_PLAUSIBLE_M = 5e-5
#: densities outside this range [kg/m^3] are lighter than the lightest foams or denser than
#: osmium: usually a density given in g/cm^3 (2.7 for aluminium) instead of kg/m^3
DENSITY_RANGE = (10.0, 25_000.0)


def _suggest_unit(size_m: float, units: str) -> str | None:
    """The unit that would make a body read as ``size_m`` metres in ``units`` closest to 0.3 m."""
    if not size_m > 0 or units not in LENGTH_UNITS:
        return None
    raw = size_m / LENGTH_UNITS[units]  # the number in the file
    best = min((u for u in LENGTH_UNITS if u != units),
               key=lambda u: abs(math.log10(raw * LENGTH_UNITS[u] / 0.3)))
    new = raw * LENGTH_UNITS[best]
    return best if SMALLEST_PLAUSIBLE_M <= new <= LARGEST_PLAUSIBLE_M else None


def size_warnings(extent_m, units: str) -> list[str]:
    """Warnings when the largest extent (metres) is implausible for a body read in ``units``."""
    size = max((float(x) for x in extent_m), default=0.0)
    if not math.isfinite(size) or size <= 0:
        return []
    if SMALLEST_PLAUSIBLE_M <= size <= LARGEST_PLAUSIBLE_M:
        return []
    what = "larger than a building" if size > LARGEST_PLAUSIBLE_M else "thinner than a hair"
    text = f"the body is {size:.3g} m across with lengths read in {units}: {what}"
    better = _suggest_unit(size, units)
    if better:
        raw = size / LENGTH_UNITS[units]
        text += f"; if the file is in {better}, it is {raw * LENGTH_UNITS[better]:.3g} m (--units {better})"
    return [text + "; check --units"]


def density_warnings(density: float, *, shell: bool = False, from_mass: bool = False) -> list[str]:
    """Warnings when a solid's density [kg/m^3] is lighter than foam or denser than osmium.

    ``from_mass``: the density is the mean one of a given mass (then the mass or the units
    are suspect, not a density unit)."""
    if shell or density is None or not math.isfinite(density) or density <= 0:
        return []
    lo, hi = DENSITY_RANGE
    if lo <= density <= hi:
        return []
    what = ("lighter than the lightest foams (10 kg/m^3)" if density < lo
            else "denser than osmium (22,590 kg/m^3)")
    if from_mass:
        return [f"the mean density {density:.4g} kg/m^3 (the mass over the volume) is {what}; check the mass "
                "and the length units"]
    hint = (f"; densities are in kg/m^3 (if you meant {density:g} g/cm^3, that is {density * 1000:g} kg/m^3)"
            if density < lo else "; densities are in kg/m^3 (aluminium 2700, steel 7850)")
    return [f"the density {density:.4g} kg/m^3 is {what}{hint}"]
