"""The ``inertia`` command line: props, particles, demo, error messages and start-up imports.

Most tests run the CLI in-process (``inertia.cli.main.main(argv)`` with ``capsys``); a few
run it as a real subprocess, the way a user does.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import inertia
from inertia.cli.main import main


@pytest.fixture(scope="module")
def sample_obj(tmp_path_factory) -> Path:
    """An OBJ file in centimetres: the T-handle's display mesh (our own generator, 64 sides)."""
    from inertia.massprops.bodies import t_handle

    v, f = t_handle().display_mesh(sides=64)
    path = tmp_path_factory.mktemp("mesh") / "t_handle_cm.obj"
    lines = [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in v * 100.0] + [f"f {a+1} {b+1} {c+1}" for a, b, c in f]
    path.write_text("\n".join(lines) + "\n")
    return path


def run(capsys, *argv):
    """``(exit code, stdout, stderr)`` of ``inertia argv`` run in-process."""
    try:
        rc = main([str(a) for a in argv])
    except SystemExit as exc:  # argparse usage errors and --help
        rc = exc.code
    out, err = capsys.readouterr()
    return rc, out, err


def run_json(capsys, *argv) -> dict:
    rc, out, err = run(capsys, *argv, "--format", "json")
    assert rc == 0, err
    return json.loads(out)


def cli_command() -> list[str]:
    """The installed console script run by this interpreter, or an equivalent ``-c``."""
    script = Path(sys.executable).parent / "inertia"
    if script.is_file():
        return [sys.executable, str(script)]
    return [sys.executable, "-m", "inertia.cli.main"]


def inertia_of_points(m, r):
    """Mass, COM and central inertia (negated products) of point masses, written out here."""
    m, r = np.asarray(m, float), np.asarray(r, float)
    M = m.sum()
    c = m @ r / M
    d = r - c
    I = sum(mk * (dk @ dk * np.eye(3) - np.outer(dk, dk)) for mk, dk in zip(m, d))
    return M, c, I


# ---------------------------------------------------------------------------- props


def test_props_box_json_matches_closed_form(capsys):
    M, a, b, c = 2.0, 0.1, 0.2, 0.4
    d = run_json(capsys, "props", "box:0.1,0.2,0.4", "--mass", "2")
    expected = M / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])
    assert d["mass"] == pytest.approx(M, rel=1e-15)
    assert d["volume"] == pytest.approx(a * b * c, rel=1e-14)
    assert d["density"] == pytest.approx(M / (a * b * c), rel=1e-14)
    assert d["density_source"] == "from --mass"
    np.testing.assert_allclose(d["com"], 0.0, atol=1e-15)
    np.testing.assert_allclose(d["inertia_com"], expected, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(d["principal_moments"], sorted(np.diag(expected)), rtol=1e-14)
    assert d["principal_moments"] == sorted(d["principal_moments"])
    R = np.array(d["R_body_principal"])
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)
    np.testing.assert_allclose(R.T @ R, np.eye(3), atol=1e-12)
    np.testing.assert_allclose(R @ np.diag(d["principal_moments"]) @ R.T, expected, atol=1e-15)
    assert d["warnings"] == [] and d["validity"] == [] and d["physical"] is True
    assert d["degenerate_moments"] == []
    assert d["source"] == "box:0.1,0.2,0.4" and d["units"] == "m"


def test_props_degenerate_moments_reported(capsys):
    d = run_json(capsys, "props", "cylinder:0.1,1", "--mass", "3")
    assert d["degenerate_moments"] == [[1, 2]]  # slender rod-like cylinder: I2 = I3
    R = np.array(d["R_body_principal"])
    assert np.linalg.det(R) == pytest.approx(1.0, abs=1e-12)


def test_props_default_density_is_water_and_said(capsys):
    d = run_json(capsys, "props", "sphere:0.05")
    assert d["density"] == 1000.0 and d["density_source"] == "default"
    assert d["mass"] == pytest.approx(1000 * 4 / 3 * math.pi * 0.05 ** 3, rel=1e-14)
    rc, out, _ = run(capsys, "props", "sphere:0.05")
    assert rc == 0 and "1000 kg/m^3 (default" in out
    rc, out, _ = run(capsys, "props", "--help")
    assert rc == 0 and "1000 kg/m^3" in out


def test_props_units_scale_primitive_dimensions(capsys):
    cm = run_json(capsys, "props", "sphere:5", "--units", "cm", "--density", "7850")
    m = run_json(capsys, "props", "sphere:0.05", "--density", "7850")
    assert cm["mass"] == pytest.approx(m["mass"], rel=1e-14)
    np.testing.assert_allclose(cm["inertia_com"], m["inertia_com"], rtol=1e-14)


@pytest.mark.parametrize("spec", ["cone:0.1,0.3", "capsule:0.1,0.2", "torus:0.3,0.1", "tube:0.1,0.05,0.3",
                                  "ellipsoid:0.1,0.2,0.3", "spherical_shell:0.1,0.09"])
def test_props_every_primitive_agrees_with_the_api(capsys, spec):
    d = run_json(capsys, "props", spec, "--mass", "1.5")
    name, nums = spec.split(":")
    dims = [float(x) for x in nums.split(",")]
    args = (tuple(dims),) if name in ("box", "ellipsoid") else dims
    p = getattr(inertia, name)(*args, mass=1.5)
    np.testing.assert_allclose(d["inertia_com"], p.inertia_com, rtol=1e-14, atol=1e-17)
    np.testing.assert_allclose(d["com"], p.com, atol=1e-15)


def test_props_table_is_readable(capsys):
    rc, out, err = run(capsys, "props", "box:0.1,0.2,0.4", "--mass", "2")
    assert rc == 0 and err == ""
    for text in ("mass            2 kg", "kg m^2", "I1 <= I2 <= I3", "det +1", "physical", "8.33333e-03"):
        assert text in out


def test_props_mesh_file_matches_api_on_same_arrays(capsys, sample_obj):
    d = run_json(capsys, "props", sample_obj, "--units", "cm", "--density", "7850")
    vertices, faces = inertia.load_mesh(sample_obj, units="cm")
    p = inertia.mesh_properties(vertices, faces, density=7850)
    assert d["mass"] == pytest.approx(p.mass, rel=1e-12)
    assert d["volume"] == pytest.approx(p.volume, rel=1e-12)
    np.testing.assert_allclose(d["com"], p.com, rtol=0, atol=1e-12 * 0.07)
    np.testing.assert_allclose(d["inertia_com"], p.inertia_com, rtol=0, atol=1e-12 * np.abs(p.inertia_com).max())
    moments = np.array(d["principal_moments"])
    assert np.all(np.diff(moments) > 0.1 * moments[-1])  # three clearly distinct moments
    assert np.linalg.det(np.array(d["R_body_principal"])) == pytest.approx(1.0, abs=1e-12)
    assert d["units"] == "cm" and d["kind"] == "mesh"


# ---------------------------------------------------------------------------- bad input


@pytest.mark.parametrize("argv, words", [
    (["props", "box:1,2"], ["box", "3 numbers", "got 2"]),
    (["props", "box:-1,1,1"], ["box", "a = -1", "positive"]),
    (["props", "box:x,1,1"], ["'x'", "not a number"]),
    (["props", "bx:1,2,3"], ["unknown primitive", "'bx'", "box:a,b,c"]),
    (["props", "sphere"], ["sphere", "needs its dimensions"]),
    (["props", "no_such_mesh.stl"], ["not found", "no_such_mesh.stl"]),
    (["props", "box:1,1,1", "--mass", "2", "--density", "3"], ["--mass", "--density", "not both"]),
    (["props", "box:1,1,1", "--density", "-5"], ["--density", "positive", "-5"]),
    (["props", "tube:0.1,0.2,1"], ["inner_radius", "outer_radius"]),
    (["props", "sphere:1", "--shell"], ["--shell", "kg/m^2"]),
    (["particles", "torus:0.1,0.3"], ["torus", "minor_radius"]),
    (["demo", "--mesh", "no_such_mesh.obj"], ["not found", "no_such_mesh.obj"]),
])
def test_bad_input_gives_message_not_traceback(capsys, argv, words):
    rc, out, err = run(capsys, *argv)
    assert rc == 1
    assert "Traceback" not in err and out == ""
    assert err.startswith(f"inertia {argv[0]}: error: ")
    for w in words:
        assert w in err, (w, err)


def test_bad_usage_is_argparse_error(capsys):
    rc, _, err = run(capsys, "props", "box:1,1,1", "--density", "abc")
    assert rc == 2 and "--density" in err and "Traceback" not in err


def test_open_mesh_is_refused_with_file_and_edges_named(capsys, meshes):
    path = meshes.path("teapot_open.stl")
    rc, out, err = run(capsys, "props", path)
    assert rc == 1 and out == "" and "Traceback" not in err
    assert "teapot_open.stl" in err
    assert "open" in err and "edge" in err
    assert "--accept-defects" in err  # says how to go on anyway


def test_open_mesh_accepted_on_request_carries_warnings(capsys, meshes):
    path = meshes.path("teapot_open.stl")
    rc, out, err = run(capsys, "props", path, "--accept-defects", "--format", "json")
    if rc != 0:  # the open teapot may still have no meaningful volume: then a clean error
        assert rc == 1 and "Traceback" not in err
        return
    d = json.loads(out)
    assert any("open" in w for w in d["warnings"])
    assert err.startswith("inertia props: warning: ") and "Traceback" not in err and "warnings.warn" not in err


CUBE_VERTICES = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
CUBE_FACES_OUT = [(1, 3, 2), (1, 4, 3), (5, 6, 7), (5, 7, 8), (1, 2, 6), (1, 6, 5),
                  (4, 8, 7), (4, 7, 3), (1, 5, 8), (1, 8, 4), (2, 3, 7), (2, 7, 6)]  # OBJ, 1-based, outward


def write_box_obj(path: Path, size, *, inward: bool = False) -> Path:
    """A box mesh of edge lengths ``size`` with corner at the origin, as an OBJ file."""
    lines = [f"v {x * size[0]} {y * size[1]} {z * size[2]}" for x, y, z in CUBE_VERTICES]
    lines += [f"f {a} {c} {b}" if inward else f"f {a} {b} {c}" for a, b, c in CUBE_FACES_OUT]
    path.write_text("\n".join(lines) + "\n")
    return path


def test_mesh_units_and_orientation(capsys, tmp_path):
    size = (10.0, 20.0, 40.0)  # mm
    expected = inertia.box((0.01, 0.02, 0.04), density=2700)
    out = run_json(capsys, "props", write_box_obj(tmp_path / "box.obj", size), "--units", "mm", "--density", "2700")
    assert out["mass"] == pytest.approx(expected.mass, rel=1e-12)
    np.testing.assert_allclose(out["com"], [0.005, 0.01, 0.02], rtol=1e-12)
    np.testing.assert_allclose(out["inertia_com"], expected.inertia_com, rtol=1e-12, atol=1e-20)

    inward = write_box_obj(tmp_path / "inward.obj", size, inward=True)
    rc, _, err = run(capsys, "props", inward, "--units", "mm")
    assert rc == 1 and "inward.obj" in err and "inverted" in err and "--fix-orientation" in err
    assert "Traceback" not in err
    fixed = run_json(capsys, "props", inward, "--units", "mm", "--density", "2700", "--fix-orientation")
    np.testing.assert_allclose(fixed["inertia_com"], out["inertia_com"], rtol=1e-12, atol=1e-20)
    assert any("flipped" in w for w in fixed["warnings"])


# ---------------------------------------------------------------------------- particles


def test_particles_json_reproduce_mass_com_and_tensor(capsys, sample_obj):
    d = run_json(capsys, "particles", sample_obj, "--units", "cm", "--density", "7850")
    I_body = np.array(d["inertia_com"])
    for key, n in (("six_point", 6), ("four_point", 4)):
        model = d[key]
        m, r = np.array(model["masses"]), np.array(model["positions"])
        assert m.shape == (n,) and r.shape == (n, 3)
        M, c, I = inertia_of_points(m, r)
        assert M == pytest.approx(d["mass"], rel=1e-13)
        np.testing.assert_allclose(c, d["com"], rtol=0, atol=1e-13)
        np.testing.assert_allclose(I, I_body, rtol=0, atol=1e-12 * np.abs(I_body).max())


def test_particles_table(capsys):
    rc, out, err = run(capsys, "particles", "box:0.1,0.2,0.4", "--mass", "2")
    assert rc == 0 and err == ""
    assert "Six-point model" in out and "Four-point model" in out
    assert out.count("0.333333") == 6 and out.count("  0.5  ") == 4


# ---------------------------------------------------------------------------- demo


def _t_handle_by_hand(rho=7850.0):
    """The demo's T-handle from the cylinder formulas (bar 80 x 12 mm along x, stem 50 x 10 mm on +y)."""
    r1, l1, r2, l2 = 0.006, 0.08, 0.005, 0.05
    m1, m2 = rho * np.pi * r1**2 * l1, rho * np.pi * r2**2 * l2
    c2 = r1 + l2 / 2
    M = m1 + m2
    yc = m2 * c2 / M
    bar_end = m1 * (3 * r1**2 + l1**2) / 12
    stem_end = m2 * (3 * r2**2 + l2**2) / 12
    shift = m1 * yc**2 + m2 * (c2 - yc)**2
    return M, np.array([0.0, yc, 0.0]), np.sort([m1 * r1**2 / 2 + stem_end + shift, bar_end + m2 * r2**2 / 2,
                                                 bar_end + stem_end + shift])


def test_demo_runs_with_no_arguments_and_prints_the_moments(capsys):
    rc, out, err = run(capsys, "demo", "--no-report")
    assert rc == 0 and err == ""
    _, _, moments = _t_handle_by_hand()
    for k in range(3):
        assert f"{moments[k]:.6g}" in out
    for title in ("1. Mass properties", "2. Canonical form", "3. Validity", "4. Six-point model",
                  "5. Four-point model", "6. Equivalent uniform solids", "7. Spin about the intermediate axis",
                  "steel T-handle"):
        assert title in out


def test_demo_json_and_options(capsys, sample_obj):
    d = run_json(capsys, "demo", "--no-report")
    assert d["body"]["kind"] == "assembly" and d["body"]["density"] == pytest.approx(7850.0, rel=1e-14)
    mass = d["mass_properties"]["mass"]
    M, com, moments = _t_handle_by_hand()
    assert mass == pytest.approx(M, rel=1e-14)
    np.testing.assert_allclose(d["mass_properties"]["com"], com, atol=1e-16)
    np.testing.assert_allclose(d["mass_properties"]["principal_moments"], moments, rtol=1e-13)
    assert sum(d["six_point"]["masses"]) == pytest.approx(mass, rel=1e-14)
    assert np.prod(d["equivalent_box"]["size"]) > 0
    alu = run_json(capsys, "demo", "--density", "2700", "--no-report")
    assert alu["mass_properties"]["mass"] == pytest.approx(mass * 2700 / 7850, rel=1e-12)
    heavy = run_json(capsys, "demo", "--mass", "0.5", "--no-report")
    assert heavy["mass_properties"]["mass"] == pytest.approx(0.5, rel=1e-14)
    np.testing.assert_allclose(heavy["mass_properties"]["principal_moments"], moments * 0.5 / M, rtol=1e-13)
    own = run_json(capsys, "demo", "--mesh", sample_obj, "--units", "mm", "--mass", "0.01", "--no-report")
    assert own["body"]["units"] == "mm" and own["mass_properties"]["mass"] == pytest.approx(0.01)


def test_demo_refuses_mesh_options_without_a_mesh(capsys):
    rc, _, err = run(capsys, "demo", "--units", "mm", "--no-report")
    assert rc == 1 and "--units applies to --mesh FILE only" in err


# ---------------------------------------------------------------------------- as a real process


def test_subprocess_props_and_error():
    cmd = cli_command()
    ok = subprocess.run(cmd + ["props", "box:0.1,0.2,0.4", "--mass", "2", "--format", "json"],
                        capture_output=True, text=True, timeout=60)
    assert ok.returncode == 0, ok.stderr
    assert json.loads(ok.stdout)["inertia_com"][0][0] == pytest.approx(2 / 12 * (0.04 + 0.16), rel=1e-14)
    bad = subprocess.run(cmd + ["props", "box:1,2"], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 1 and "Traceback" not in bad.stderr and "box" in bad.stderr


def test_a_process_ends_with_its_whole_output_and_exit_code():
    """The command skips the interpreter's teardown (os._exit): what it printed must still
    arrive whole, beyond a pipe's buffer, and its exit code be the command's."""
    cmd = cli_command()
    argv = ["simulate", "--moments", "1,2,3", "--omega", "0.1,2,0.1", "--duration", "200", "--step", "0.01",
            "--every", "2", "--method", "exact", "--format", "csv"]
    out = subprocess.run(cmd + argv, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert len(out.stdout) > 2**16 and len(lines) == 1 + 200 / 0.02 + 1   # header, t = 0 .. 200
    assert lines[-1].split(",")[0] in ("200", "200.0") and out.stdout.endswith("\n")
    bad = subprocess.run(cmd + ["simulate", "--moments", "1,2", "--omega", "1,0,0"], capture_output=True,
                         text=True, timeout=60)
    assert bad.returncode == 1 and "moments" in bad.stderr and "Traceback" not in bad.stderr


def test_help_does_not_import_numerical_libraries():
    probe = ("import contextlib, io, sys\n"
             "from inertia.cli.main import COMMANDS, main\n"
             "for argv in [['--help']] + [[c, '--help'] for c in COMMANDS]:\n"
             "    with contextlib.redirect_stdout(io.StringIO()):\n"
             "        try:\n"
             "            main(argv)\n"
             "        except SystemExit:\n"
             "            pass\n"
             "print(sorted(m for m in ('numpy', 'scipy', 'trimesh') if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[]"


def test_demo_needs_no_mesh_reader(capsys, monkeypatch, tmp_path):
    from inertia.errors import MissingDependencyError
    from inertia.geometry import mesh_io

    with_trimesh = run_json(capsys, "demo", "--no-report")

    def no_trimesh():
        raise MissingDependencyError("trimesh is not installed (simulated)")

    monkeypatch.setattr(mesh_io, "_import_trimesh", no_trimesh)
    off = tmp_path / "t.off"
    off.write_text("OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n")
    rc, _, err = run(capsys, "props", str(off))
    assert rc == 1 and "trimesh" in err  # OFF, PLY and glTF files do need trimesh
    without = run_json(capsys, "demo", "--no-report")
    a, b = with_trimesh["mass_properties"], without["mass_properties"]
    assert b["mass"] == pytest.approx(a["mass"], rel=1e-13)
    np.testing.assert_allclose(b["inertia_com"], a["inertia_com"], rtol=0, atol=1e-13 * max(map(max, a["inertia_com"])))


def test_thin_shell_json_is_strict_json(capsys):
    rc, out, err = run(capsys, "props", "sphere:0.1", "--shell", "--mass", "1", "--format", "json")
    assert rc == 0, err
    assert "NaN" not in out
    d = json.loads(out)
    assert d["volume"] is None and d["density"] is None and d["shell"] is True
    assert d["inertia_com"][0][0] == pytest.approx(2 / 3 * 0.1 ** 2, rel=1e-14)  # thin spherical shell


def test_demo_without_report_loads_no_pictures():
    # the flip numbers come from inertia.dynamics; --no-report must not import viz or matplotlib
    probe = ("import contextlib, io, sys\n"
             "from inertia.cli.main import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n"
             "    assert main(['demo', '--no-report']) == 0\n"
             "print(sorted(m for m in sys.modules if m == 'matplotlib' or m.startswith('inertia.viz')))\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120, check=True)
    assert out.stdout.strip() == "[]"
