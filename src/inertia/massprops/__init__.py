"""Mass properties: the value type, tensor operations, principal axes and canonical form,
validity, primitives, point masses, assemblies, equivalent solids, ready-made bodies, and the
mass properties of meshes (over :mod:`inertia.geometry`).

Names are imported lazily: ``import inertia.massprops`` loads no NumPy until a name is used.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_MODULES = ("properties", "tensor", "principal", "validity", "primitives", "ellipsoid_surface",
            "assembly", "equivalent", "bodies", "mesh")

# public name -> submodule that defines it.  The primitives are at the top level
# (``inertia.box``) and in :mod:`.primitives`; the other tensor operations in :mod:`.tensor`,
# the validity helpers in :mod:`.validity`, the ready-made bodies in :mod:`.bodies`.
_EXPORTS = {
    "MassProperties": "properties", "point_masses": "properties", "Part": "assembly", "assemble": "assembly",
    "PrincipalFrame": "principal", "principal_axes": "principal", "check_inertia": "validity",
    "rotate_inertia": "tensor", "inertia_about_point": "tensor", "inertia_from_elements": "tensor",
    "elements_from_inertia": "tensor", "equivalent_box": "equivalent", "equivalent_ellipsoid": "equivalent",
    "mesh_properties": "mesh", "mesh_file_properties": "mesh",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
