"""A unit slip shows: `inertia props` prints the mesh's size and counts, and warns when the
size or the density implies a body no one makes (a 30 mm part read in metres)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from inertia._core.units import density_warnings, size_warnings
from inertia.cli.main import main

TET_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
TET_F = [(1, 3, 2), (1, 2, 4), (1, 4, 3), (2, 3, 4)]


def _tet(path, scale):
    v = TET_V * scale
    path.write_text("".join(f"v {float(x)!r} {float(y)!r} {float(z)!r}\n" for x, y, z in v) + "".join(f"f {a} {b} {c}\n" for a, b, c in TET_F))
    return path


def _props(capsys, *argv):
    code = main(["props", *map(str, argv), "--format", "json"])
    out, err = capsys.readouterr()
    return code, json.loads(out), err


def test_size_and_counts_are_in_the_json_and_the_table(tmp_path, capsys):
    f = _tet(tmp_path / "t.obj", 30.0)
    code, d, _ = _props(capsys, f, "--units", "mm")
    assert code == 0
    # truth: the file's coordinates times 1e-3
    assert d["mesh"]["n_vertices"] == 4 and d["mesh"]["n_faces"] == 4
    assert np.allclose(d["mesh"]["extents"], [0.03] * 3) and np.allclose(d["mesh"]["bbox_max"], [0.03] * 3)
    assert d["warnings"] == []
    assert main(["props", str(f), "--units", "mm"]) == 0
    table = capsys.readouterr().out
    assert "4 vertices, 4 faces" in table and "[0.03, 0.03, 0.03] m" in table


def test_a_millimetre_part_read_in_metres_is_flagged_with_the_unit_that_fits(tmp_path, capsys):
    f = _tet(tmp_path / "t.obj", 3000.0)          # a 3 m part... or a 3 mm part's file read in m? 3 km
    code, d, err = _props(capsys, f, "--density", "2700")
    assert code == 0
    (w,) = d["warnings"]
    assert "larger than a building" in w and "--units mm" in w and "3 m" in w
    assert "warning" in err and "--units mm" in err


def test_a_micrometre_body_is_flagged_as_thinner_than_a_hair(tmp_path, capsys):
    f = _tet(tmp_path / "t.obj", 0.02)            # 20 um across if read in mm
    _, d, _ = _props(capsys, f, "--units", "mm")
    assert any("thinner than a hair" in w for w in d["warnings"])


@pytest.mark.parametrize("density, phrase", [(2.7, "2700 kg/m^3"), (78500.0, "osmium")])
def test_a_density_in_the_wrong_unit_is_flagged(tmp_path, capsys, density, phrase):
    f = _tet(tmp_path / "t.obj", 30.0)
    _, d, _ = _props(capsys, f, "--units", "mm", "--density", density)
    assert any(phrase in w for w in d["warnings"])


def test_plausible_bodies_raise_no_warning():
    # truth: real bodies, from a 0.1 mm watch screw to a 300 m ship hull, aluminium to tungsten
    for size in (1e-4, 0.03, 2.0, 300.0):
        assert size_warnings([size, size / 2, size / 3], "m") == []
    for rho in (15.0, 1000.0, 2700.0, 19300.0):
        assert density_warnings(rho) == []
    assert density_warnings(2.7, shell=True) == []   # kg/m^2 for a shell: any value
