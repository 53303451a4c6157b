"""Transitional: the numba kernels that mesh_arrays.topology_kernels still hands to the mesh
checks (``clean_solid``) and to intersections (``winding_numbers``), until the integrals family
is ported.  Welding and merging are in :mod:`inertia._ext.topology`.  Delete at that merge.
"""

from ._shell_numba import find_root, union_low, winding_numbers  # noqa: F401
from ._solid_numba import clean_solid, closed_single_shell  # noqa: F401

WARM_PROBE = ("clean_solid",)
