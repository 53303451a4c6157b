"""Mass properties of triangle meshes given as arrays (defect checks, then the exact kernel)."""

from __future__ import annotations

import numpy as np

from ..errors import InputError
from ._arrays import resolve_mass
from .mesh_kernel import central_inertia, shell_integrals, solid_integrals


def mesh_properties(vertices, faces, *, density=None, mass=None, shell=False, frame: str = "body"):
    """Mass properties of a triangle mesh.

    Parameters
    ----------
    vertices : (V, 3) float, m.
    faces : (F, 3) int, vertex indices, counter-clockwise seen from outside.
    density : float, kg/m^3 (kg/m^2 when ``shell``); or
    mass : float, kg (exactly one of the two).
    shell : bool, treat the surface as a thin shell of uniform surface density.
    """
    from .properties import MassProperties

    v = np.asarray(vertices, dtype=np.float64)
    f = np.asarray(faces)
    if shell:
        measure, first, second, r = shell_integrals(v, f)
        m, rho = resolve_mass(measure, density, mass, what="mesh shell", measure_name="area")
        com, inertia = central_inertia(measure, first, second, r, rho)
        return MassProperties(m, com, inertia, frame=frame)
    measure, first, second, r = solid_integrals(v, f)
    m, rho = resolve_mass(measure, density, mass, what="mesh solid")
    com, inertia = central_inertia(measure, first, second, r, rho)
    return MassProperties(m, com, inertia, frame=frame, volume=measure)
