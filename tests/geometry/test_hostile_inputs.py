"""Inputs that once crashed the process or passed as numbers: each is now refused by name.

The compiled kernels index without bounds checks, so every array they see must have been
validated in its final shape; these tests feed the shapes and values that slipped through.
"""

from __future__ import annotations

import subprocess
import sys

import numpy as np
import pytest

import inertia
from inertia.errors import InputError, MeshError, MeshFileError
from inertia.geometry import check_mesh

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def test_obj_whose_vertices_come_back_transposed_is_malformed_not_a_segfault(tmp_path):
    # a bare carriage return inside a vertex line: trimesh returns vertices of shape (3, 0)
    pytest.importorskip("trimesh")
    f = tmp_path / "t.obj"
    f.write_bytes(b"v \r1 2 3\nv 1 2\nv 1 2 3\nf 1 2 3\n")
    with pytest.raises(MeshFileError) as ei:
        inertia.load_mesh(f)
    assert ei.value.code == "malformed" and "t.obj" in str(ei.value) and "(3, 0)" in str(ei.value)
    # the whole process: exit 1 with one line, never a signal
    out = subprocess.run([sys.executable, "-m", "inertia.cli.main", "props", str(f)], capture_output=True,
                         text=True, timeout=120)
    assert out.returncode == 1 and "malformed" in out.stderr and "Traceback" not in out.stderr


@pytest.mark.parametrize("bad", [[[0, 1, 7]], [[-1, 1, 2]]])
def test_out_of_range_indices_never_reach_a_compiled_kernel(bad):
    faces = np.vstack([TET_F, bad])
    with pytest.raises(InputError) as ei:
        inertia.geometry.weld_vertices(TET_V, faces)
    assert ei.value.code == "bad_index"
    assert "bad_index" in check_mesh(TET_V, faces).codes
    from inertia.geometry.checks import analyse_mesh

    # welded=True skips the weld; the index range is still checked before the kernel
    assert "bad_index" in analyse_mesh(TET_V, faces, welded=True).report.codes


@pytest.mark.parametrize("scale", [1e61, 1e200, 1e300])
def test_coordinates_whose_moments_overflow_are_out_of_range_not_zero_area(scale):
    # truth: the tetrahedron's second moments grow as scale**5, beyond float64 here
    report = check_mesh(TET_V * scale, TET_F)
    assert report.codes == ("out_of_range",)
    with pytest.raises(MeshError) as ei:
        inertia.mesh_properties(TET_V * scale, TET_F, density=1.0)
    assert ei.value.code == "out_of_range" and "units" in str(ei.value)


def test_largest_representable_scale_still_gives_exact_numbers():
    # truth: the unit tetrahedron's volume 1/6, scaled by s**3 (s = 1e50, inside the limit)
    s = 1e50
    p = inertia.mesh_properties(TET_V * s, TET_F, density=1.0)
    assert p.mass == pytest.approx(s**3 / 6, rel=1e-12)
    assert np.all(np.isfinite(p.inertia_com))
