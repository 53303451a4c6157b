"""Surfaces: reading mesh files, validating and welding arrays, topology checks and the
defect report, re-orienting faces, volume and surface integrals (NumPy and compiled twins),
and generated shapes.  The mass-properties call over all of it is
:func:`inertia.mesh_properties`.

Names are imported lazily: ``import inertia.geometry`` loads no NumPy until a name is used.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_MODULES = ("mesh_io", "mesh_arrays", "checks", "report", "orient", "integrals", "shapes")

# public name -> submodule that defines it
_EXPORTS = {
    "load_mesh": "mesh_io", "UNITS": "mesh_io", "SUPPORTED_EXTENSIONS": "mesh_io",
    "validate_inputs": "mesh_arrays", "weld_vertices": "mesh_arrays", "compact_vertices": "mesh_arrays",
    "check_mesh": "checks", "MeshReport": "report",
    "orient_faces": "orient",
    "solid_integrals": "integrals", "shell_integrals": "integrals", "central_inertia": "integrals",
    "box_edges": "shapes", "cylinder_mesh": "shapes", "merge_meshes": "shapes",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, _MODULES)
