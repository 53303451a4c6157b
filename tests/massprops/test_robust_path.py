"""The opt-in robust path of the public calls (``on_defect="robust"``, ``--robust``): an imperfect
solid gets a number with an error bound instead of a refusal.

Truth: closed forms (the unit cube) and the exact kernel on the closed mesh before holes
were punched into it; the bound must cover the true error.
"""

from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

import inertia
from inertia.errors import MeshDefectWarning, MeshError

CUBE_V = np.array([[x, y, z] for x in (0, 1) for y in (0, 1) for z in (0, 1)], float)
CUBE_F = np.array([(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
                   (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)])


def test_an_open_cube_is_refused_by_default_and_the_refusal_offers_robust():
    with pytest.raises(MeshError) as ei:
        inertia.mesh_properties(CUBE_V, CUBE_F[:-2], density=1000.0)
    assert ei.value.code == "open_edges" and "on_defect='robust'" in str(ei.value)
    assert ("on_defect", "robust") in ei.value.remedies


def test_an_open_cube_gets_the_closed_cube_with_a_bound_and_a_warning():
    with pytest.warns(MeshDefectWarning, match=r"robust solid \(.*\) of a mesh with open_edges"):
        p = inertia.mesh_properties(CUBE_V, CUBE_F[:-2], density=1000.0, on_defect="robust")
    # closed form: m = rho a^3, COM at the centre, I = m a^2 / 6 on the diagonal
    assert p.mass == pytest.approx(1000.0, rel=1e-12)
    assert np.allclose(p.com, 0.5, atol=1e-12)
    assert np.allclose(p.inertia_com, np.eye(3) * 1000.0 / 6, atol=1e-9)
    robust, open_edges = p.findings
    assert (robust.code, robust.severity, open_edges.code, open_edges.severity) == (
        "robust_solid", "warning", "open_edges", "warning")
    assert set(robust.values["bounds"]) == {"volume", "com", "inertia"}
    assert robust.values["error_bound"] == max(robust.values["bounds"].values())


def test_a_closed_mesh_takes_the_exact_path_bit_for_bit():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        a = inertia.mesh_properties(CUBE_V, CUBE_F, density=7.0, on_defect="robust")
    b = inertia.mesh_properties(CUBE_V, CUBE_F, density=7.0)
    assert a.mass == b.mass and np.array_equal(a.inertia_com, b.inertia_com) and a.findings == b.findings == ()


@pytest.mark.parametrize("seed", range(6))
def test_holes_punched_in_a_sphere_stay_within_the_stated_bound(seed):
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=3, radius=0.1)
    v, f = np.asarray(sphere.vertices), np.asarray(sphere.faces)
    truth = inertia.mesh_properties(v, f, density=1000.0)           # the closed polyhedron
    rng = np.random.default_rng(seed)
    holes = rng.choice(len(f), size=1 + seed, replace=False)
    keep = np.setdiff1d(np.arange(len(f)), holes)
    with pytest.warns(MeshDefectWarning):
        p = inertia.mesh_properties(v, f[keep], density=1000.0, on_defect="robust", robust_tol=1e-4)
    bounds = next(x for x in p.findings if x.code == "robust_solid").values["bounds"]
    assert abs(p.mass / truth.mass - 1) <= max(bounds["volume"], 1e-12)
    assert np.linalg.norm(p.inertia_com - truth.inertia_com) / np.linalg.norm(truth.inertia_com) <= max(
        bounds["inertia"], 1e-12)
    assert p.precision == bounds["inertia"]


def test_cli_robust_turns_the_refusal_into_a_number_with_its_bound(tmp_path, capsys):
    from inertia.cli.main import main

    f = tmp_path / "open.stl"   # binary STL: read natively (no optional dependency)
    tris = CUBE_V[CUBE_F[:-2]].astype("<f4")
    records = np.zeros(len(tris), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    records["v"] = tris
    f.write_bytes(b"open cube".ljust(80, b" ") + np.uint32(len(tris)).tobytes() + records.tobytes())
    assert main(["props", str(f)]) == 1
    assert "--robust" in capsys.readouterr().err
    assert main(["props", str(f), "--robust", "--format", "json"]) == 0
    out, err = capsys.readouterr()
    d = json.loads(out)
    assert d["mass"] == pytest.approx(1000.0, rel=1e-12) and "relative error bounds" in err
    assert any("robust solid" in w for w in d["warnings"])


def test_robust_is_refused_for_primitives(capsys):
    from inertia.cli.main import main

    assert main(["props", "box:1,1,1", "--robust"]) == 1
    assert "--robust applies to mesh files only" in capsys.readouterr().err


def _binary_stl(path, v, f):
    tris = np.asarray(v)[np.asarray(f)].astype("<f4")
    records = np.zeros(len(tris), dtype=[("n", "<f4", (3,)), ("v", "<f4", (3, 3)), ("a", "<u2")])
    records["v"] = tris
    path.write_bytes(b"mesh".ljust(80, b" ") + np.uint32(len(tris)).tobytes() + records.tobytes())


def _holed_sphere(subdivisions=3, holes=4):
    trimesh = pytest.importorskip("trimesh")
    sphere = trimesh.creation.icosphere(subdivisions=subdivisions, radius=0.1)
    v, f = np.asarray(sphere.vertices, np.float32).astype(float), np.asarray(sphere.faces)
    return v, f, f[holes:]


def test_cli_json_gives_the_bounds_as_numbers_and_they_hold_against_the_closed_sphere(tmp_path, capsys):
    from inertia.cli.main import main

    v, closed, holed = _holed_sphere()
    _binary_stl(tmp_path / "closed.stl", v, closed)
    _binary_stl(tmp_path / "holed.stl", v, holed)
    assert main(["props", str(tmp_path / "closed.stl"), "--format", "json"]) == 0
    truth = json.loads(capsys.readouterr().out)
    assert "error_bound" not in truth and truth["findings"] == []     # an exact result states no bound
    assert main(["props", str(tmp_path / "holed.stl"), "--robust", "--robust-tol", "1e-4", "--format", "json"]) == 0
    d = json.loads(capsys.readouterr().out)
    b = d["bounds"]
    assert set(b) == {"volume", "com", "inertia"} and d["error_bound"] == max(b.values())
    assert abs(d["volume"] / truth["volume"] - 1) <= max(b["volume"], 1e-12)
    I, I0 = np.array(d["inertia_com"]), np.array(truth["inertia_com"])
    assert np.linalg.norm(I - I0) / np.linalg.norm(I0) <= max(b["inertia"], 1e-12)
    robust = next(f for f in d["findings"] if f["code"] == "robust_solid")
    assert robust["values"]["error_bound"] == d["error_bound"] and robust["severity"] == "warning"


def test_a_robust_budget_stops_the_refinement_and_says_the_bound_it_reached(tmp_path, capsys):
    from inertia.cli.main import main

    v, _, holed = _holed_sphere(subdivisions=4, holes=5)
    _binary_stl(tmp_path / "holed.stl", v, holed)
    # a target the refinement cannot reach in a millisecond: the result still comes, with its bound
    assert main(["props", str(tmp_path / "holed.stl"), "--robust", "--robust-tol", "1e-9",
                 "--robust-budget", "0.001", "--format", "json"]) == 0
    out, err = capsys.readouterr()
    d = json.loads(out)
    assert d["robust_converged"] is False and d["error_bound"] > 1e-9 and np.isfinite(d["error_bound"])
    assert "NOT within robust_tol 1e-09 (stopped by the time budget)" in err


@pytest.mark.parametrize("argv, said", [
    (["--robust", "--robust-budget", "0"], "--robust-budget must be a positive number of seconds"),
    (["--robust", "--robust-budget", "nan"], "--robust-budget must be a positive number of seconds"),
    (["--robust-budget", "5"], "--robust-budget applies with --robust only"),
    (["--robust", "--robust-tol", "-1"], "--robust-tol must be a positive number")])
def test_robust_budget_and_tol_are_checked(tmp_path, capsys, argv, said):
    from inertia.cli.main import main

    _binary_stl(tmp_path / "cube.stl", CUBE_V, CUBE_F)
    assert main(["props", str(tmp_path / "cube.stl"), *argv]) == 1
    assert said in capsys.readouterr().err


def test_progress_reports_a_growing_fraction_and_ends_at_the_stated_bound():
    v, _, holed = _holed_sphere()
    calls = []
    with pytest.warns(MeshDefectWarning):
        p = inertia.mesh_properties(v, holed, density=1.0, on_defect="robust",
                                    robust_progress=lambda fraction, bound: calls.append((fraction, bound)))
    fractions = [c[0] for c in calls]
    assert len(calls) >= 2 and fractions == sorted(fractions) and 0 <= fractions[0] and fractions[-1] == 1.0
    robust = next(x for x in p.findings if x.code == "robust_solid")
    assert calls[-1][1] == robust.values["error_bound"]
