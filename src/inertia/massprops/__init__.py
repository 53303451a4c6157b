"""Mass properties: the value type, tensor operations, principal axes and canonical form,
validity, primitives, point masses, assemblies, equivalent solids, ready-made bodies, and the
mass properties of meshes (over :mod:`inertia.geometry`).

Names are imported lazily: ``import inertia.massprops`` loads no NumPy until a name is used.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_MODULES = ("properties", "tensor", "principal", "validity", "primitives", "ellipsoid_surface",
            "assembly", "equivalent", "bodies", "mesh")

# public name -> submodule that defines it
_EXPORTS = {
    "MassProperties": "properties", "CanonicalForm": "properties", "combine": "properties",
    "point_mass_inertia": "tensor", "inertia_about_point": "tensor", "inertia_about_com": "tensor",
    "rotate_inertia": "tensor", "moment_about_line": "tensor", "inertia_from_elements": "tensor",
    "elements_from_inertia": "tensor",
    "principal_axes": "principal", "principal_frame": "principal", "PrincipalFrame": "principal",
    "principal_axes_batch": "principal", "degenerate_groups": "principal",
    "check_inertia": "validity", "is_physical": "validity",
    "raise_if_invalid": "validity", "as_principal_moments": "validity",
    "box": "primitives", "sphere": "primitives", "ellipsoid": "primitives", "cylinder": "primitives",
    "cone": "primitives", "capsule": "primitives", "torus": "primitives", "tube": "primitives",
    "spherical_shell": "primitives",
    "point_masses": "properties", "Part": "assembly", "assemble": "assembly",
    "equivalent_box": "equivalent", "equivalent_ellipsoid": "equivalent",
    "t_handle": "bodies", "BuiltBody": "bodies",
    "mesh_properties": "mesh", "mesh_file_properties": "mesh",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
