"""inertia: rigid-body mass properties and rotational dynamics.

Conventions: SI units; inertia matrices hold negated products (``L = I @ omega``);
quaternions are scalar-first ``(w, x, y, z)``; ``R_world_body`` maps body to world
coordinates.

Public names are imported lazily (PEP 562) so that ``import inertia`` and the
command line start without loading NumPy until a name is used.
"""

from __future__ import annotations

from ._core.lazy import lazy_namespace
from ._core.version import __version__

# public name -> module that defines it
_EXPORTS = {
    # errors
    "InertiaError": "inertia.errors",
    "InputError": "inertia.errors",
    "InvalidInertiaError": "inertia.errors",
    "NoEquivalentModelError": "inertia.errors",
    "MeshError": "inertia.errors",
    "MeshFileError": "inertia.errors",
    "MissingDependencyError": "inertia.errors",
    "IntegrationError": "inertia.errors",
    "InertiaWarning": "inertia.errors",
    "MeshDefectWarning": "inertia.errors",
    # value type and core functions
    "MassProperties": "inertia.massprops.properties",
    "CanonicalForm": "inertia.massprops.properties",
    "point_masses": "inertia.massprops.point_masses",
    "principal_axes": "inertia.massprops.principal",
    "principal_frame": "inertia.massprops.principal",
    "check_inertia": "inertia.massprops.validity",
    "is_physical": "inertia.massprops.validity",
    "Violation": "inertia.massprops.validity",
    "point_mass_inertia": "inertia.massprops.tensor",
    "inertia_about_point": "inertia.massprops.tensor",
    "inertia_about_com": "inertia.massprops.tensor",
    "rotate_inertia": "inertia.massprops.tensor",
    "moment_about_line": "inertia.massprops.tensor",
    "inertia_from_elements": "inertia.massprops.tensor",
    "elements_from_inertia": "inertia.massprops.tensor",
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
    "check_mesh": "inertia.geometry.checks",
    "MeshReport": "inertia.geometry.checks",
    "load_mesh": "inertia.geometry.mesh_io",
    "mesh_file_properties": "inertia.massprops.mesh",
    # equivalents
    "equivalent_box": "inertia.massprops.equivalent",
    "equivalent_ellipsoid": "inertia.massprops.equivalent",
    # particle models
    "ParticleModel": "inertia.particles.models",
    "six_point_model": "inertia.particles.models",
    "four_point_model": "inertia.particles.models",
}

# capability sub-packages, reachable as attributes (``inertia.dynamics``) without an import
_SUBPACKAGES = ("errors", "geometry", "massprops", "particles", "dynamics", "symbolic", "robots", "viz", "batch")


__getattr__, __dir__, _names = lazy_namespace(__name__, _EXPORTS, _SUBPACKAGES)
__all__ = _names + ["__version__"]
