"""inertia: rigid-body mass properties and rotational dynamics.

Conventions: SI units; inertia matrices hold negated products (``L = I @ omega``);
quaternions are scalar-first ``(w, x, y, z)``; ``R_world_body`` maps body to world
coordinates.

The top level holds what a newcomer types first: the value type, the primitives, meshes,
assemblies, the validity check, the particle models, the equivalent solids and the main
errors.  Everything else lives in the subpackages, which follow the data flow:
:mod:`inertia.geometry` (mesh files, checks, integrals) -> :mod:`inertia.massprops` (tensor
operations, principal axes, canonical form, validity) -> :mod:`inertia.particles`,
:mod:`inertia.dynamics`, :mod:`inertia.symbolic` -> :mod:`inertia.robots` -> :mod:`inertia.control` ->
:mod:`inertia.viz` -> :mod:`inertia.batch`; :mod:`inertia.errors` has every error type.

Public names are imported lazily (PEP 562) so that ``import inertia`` and the
command line start without loading NumPy until a name is used.
"""

from __future__ import annotations

from ._core.lazy import lazy_namespace
from ._core.version import __version__

# public name -> module that defines it
_EXPORTS = {
    # the errors a caller meets most (all of them: inertia.errors)
    "InertiaError": "inertia._core.errors",
    "InputError": "inertia._core.errors",
    "InvalidInertiaError": "inertia._core.errors",
    "MeshError": "inertia._core.errors",
    "MeshFileError": "inertia._core.errors",
    # the value type, validity, point masses and assemblies
    "MassProperties": "inertia.massprops.properties",
    "check_inertia": "inertia.massprops.validity",
    "point_masses": "inertia.massprops.properties",
    "Part": "inertia.massprops.assembly",
    "assemble": "inertia.massprops.assembly",
    # primitives
    "box": "inertia.massprops.primitives",
    "sphere": "inertia.massprops.primitives",
    "ellipsoid": "inertia.massprops.primitives",
    "cylinder": "inertia.massprops.primitives",
    "cone": "inertia.massprops.primitives",
    "capsule": "inertia.massprops.primitives",
    "torus": "inertia.massprops.primitives",
    "tube": "inertia.massprops.primitives",
    "spherical_shell": "inertia.massprops.primitives",
    # meshes
    "mesh_properties": "inertia.massprops.mesh",
    "mesh_file_properties": "inertia.massprops.mesh",
    "load_mesh": "inertia.geometry.mesh_io",
    # equivalent solids and particle models
    "equivalent_box": "inertia.massprops.equivalent",
    "equivalent_ellipsoid": "inertia.massprops.equivalent",
    "six_point_model": "inertia.particles.models",
    "four_point_model": "inertia.particles.models",
}

# capability sub-packages, reachable as attributes (``inertia.dynamics``) without an import
_SUBPACKAGES = ("errors", "geometry", "massprops", "particles", "dynamics", "symbolic", "robots", "control", "viz",
                "batch")


__getattr__, __dir__, _names = lazy_namespace(__name__, _EXPORTS, _SUBPACKAGES)
__all__ = _names + ["__version__"]
