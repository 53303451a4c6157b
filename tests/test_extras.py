"""Without an optional extra, each feature that needs it says which extra to install.

The absence is simulated (``sys.modules[name] = None`` makes ``import name`` fail), so these
tests run, and can fail, in every environment; ``.ci/run`` also runs the core suite in a
virtual environment that has no extras at all.
"""

from __future__ import annotations

import sys

import numpy as np
import pytest

import inertia
from inertia.errors import MissingDependencyError


def _hide(monkeypatch, *modules):
    for name in modules:
        for key in [k for k in sys.modules if k == name or k.startswith(name + ".")]:
            monkeypatch.setitem(sys.modules, key, None)
        monkeypatch.setitem(sys.modules, name, None)


def _ascii_stl(path):
    tri = ["solid t"]
    for a, b, c in ([0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]):
        tri.append(" facet normal 0 0 0\n  outer loop")
        verts = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
        tri += [f"   vertex {x} {y} {z}" for x, y, z in verts[[a, b, c]]]
        tri.append("  endloop\n endfacet")
    path.write_text("\n".join(tri + ["endsolid t"]) + "\n")
    return path


def _off(path):
    """A tetrahedron as OFF, a format read through trimesh (ASCII STL and OBJ are read natively)."""
    path.write_text("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
    return path


def _assert_names_extra(excinfo, extra):
    err = excinfo.value
    assert isinstance(err, inertia.errors.InertiaError) and err.code == "missing_dependency"
    assert f"inertia[{extra}]" in str(err), str(err)


def test_reading_a_text_mesh_without_trimesh_names_the_mesh_extra(monkeypatch, tmp_path):
    f = _off(tmp_path / "t.off")
    _hide(monkeypatch, "trimesh")
    with pytest.raises(MissingDependencyError) as ei:
        inertia.load_mesh(f)
    _assert_names_extra(ei, "mesh")
    # truth: the unit tetrahedron's volume 1/6, read without trimesh from ASCII STL
    assert inertia.mesh_file_properties(_ascii_stl(tmp_path / "t.stl"), density=1.0).volume == pytest.approx(1 / 6)


def test_symbolic_without_sympy_names_the_symbolic_extra(monkeypatch):
    from inertia.symbolic import derive

    _hide(monkeypatch, "sympy")
    with pytest.raises(MissingDependencyError) as ei:
        derive("ZYX")
    _assert_names_extra(ei, "symbolic")


def test_plots_without_matplotlib_name_the_viz_extra(monkeypatch):
    from inertia.viz.plots import pyplot

    _hide(monkeypatch, "matplotlib")
    with pytest.raises(MissingDependencyError) as ei:
        pyplot()
    _assert_names_extra(ei, "viz")


@pytest.mark.parametrize("missing, output", [("pandas", "out.csv"), ("pyarrow", "out.parquet")])
def test_batch_without_its_extra_names_the_batch_extra_and_writes_nothing(monkeypatch, tmp_path, missing, output):
    from inertia.batch import run_batch

    _ascii_stl(tmp_path / "t.stl")
    out = tmp_path / output   # a Parquet output needs pyarrow only (pandas: CSV, JSON Lines, DataFrames)
    _hide(monkeypatch, missing)
    with pytest.raises(MissingDependencyError) as ei:
        run_batch([str(tmp_path)], out, scheduler="synchronous", progress=False)
    _assert_names_extra(ei, "batch")
    assert not out.exists()


def test_batch_cluster_without_distributed_names_the_batch_extra(monkeypatch, tmp_path):
    from inertia.batch import mass_properties_table

    _ascii_stl(tmp_path / "t.stl")
    _hide(monkeypatch, "distributed")
    with pytest.raises(MissingDependencyError) as ei:
        mass_properties_table([str(tmp_path)], scheduler="cluster")
    _assert_names_extra(ei, "batch")


def test_cli_without_trimesh_exits_with_a_one_line_error_naming_the_extra(monkeypatch, tmp_path, capsys):
    from inertia.cli.main import main

    f = _off(tmp_path / "t.off")
    _hide(monkeypatch, "trimesh")
    code = main(["props", str(f)])
    err = capsys.readouterr().err
    assert code != 0 and "inertia[mesh]" in err and "Traceback" not in err and len(err.strip().splitlines()) == 1
