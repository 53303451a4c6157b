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
