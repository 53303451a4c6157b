"""The command line agrees with itself: one spelling per option, shared blocks described once,
an example in every help that the command accepts, output units and the CAD convention against
closed forms, and ``<inertial>`` blocks written with the digits a user would write."""

from __future__ import annotations

import json
import re
import shlex

import numpy as np
import pytest

from inertia.cli import _options
from inertia.cli.main import COMMANDS, build_parser, sub_parsers
from tests.cli._run import run

PARSER = build_parser()
SUBS = sub_parsers(PARSER)


def options_of(parser) -> set:
    return {s for a in parser._actions for s in a.option_strings}


def help_of(name: str | None) -> str:
    return (SUBS[name] if name else PARSER).format_help()


# ---------------------------------------------------------------------------- one spelling


@pytest.mark.parametrize("command", ["props", "particles", "simulate", "flip", "demo", "batch", "check", "fix",
                                     "diff"])
def test_every_command_that_reads_mesh_lengths_spells_it_units(command):
    assert "--units" in options_of(SUBS[command]) and "--mesh-units" not in options_of(SUBS[command])


def test_no_option_is_spelt_two_ways():
    """An option keeps one meaning, metavar and default across the commands that share it."""
    seen: dict = {}
    for name, sub in SUBS.items():
        for a in sub._actions:
            for s in a.option_strings:
                seen.setdefault(s, set()).add((a.dest, tuple(a.choices or ())))
    # --format and --density differ by command on purpose (what a command can write or needs)
    varied = {s: v for s, v in seen.items() if len(v) > 1 and s not in ("--format", "-o", "--output", "--help", "-h")}
    assert not varied, varied


def test_a_wrong_option_is_refused_by_its_command_with_the_spelling_it_takes(capsys, tmp_path):
    rc, out, err = run(capsys, "check", tmp_path / "r.urdf", "--mesh-units", "mm")
    assert rc == 2 and out == ""
    assert err.startswith("usage: inertia check FILE [options]\n")
    assert "inertia check: error: unrecognized arguments: --mesh-units mm; did you mean --units instead of " \
           "--mesh-units?" in err
    rc, _, err = run(capsys, "props", "box:1,1,1", "--output-unit", "g,mm")   # a prefix is --output-units itself
    assert rc == 0
    rc, _, err = run(capsys, "props", "box:1,1,1", "--densty", "3")
    assert rc == 2 and "inertia props: error:" in err and "did you mean --density instead of --densty?" in err


# ---------------------------------------------------------------------------- helps


@pytest.mark.parametrize("command", [None] + [c for c in COMMANDS])
def test_every_help_has_examples_the_command_accepts(command):
    text = help_of(command)
    examples = text[text.index("\nexamples:\n"):].split("\n\n")[0].splitlines()[2:]
    assert examples, command
    for line in examples:
        argv = shlex.split(re.split(r"\s{2,}\(", line.strip())[0])[1:]   # the command, without its comment
        args, extras = PARSER.parse_known_args(argv)
        assert not extras and args.command == argv[0], line


def test_shared_blocks_are_described_once(capsys):
    """A shared option's help text is in ``inertia help TOPIC`` and in no command's help."""
    for topic, (_, add, _) in _options.TOPICS.items():
        rc, text, _ = run(capsys, "help", topic)
        assert rc == 0
        p = type(PARSER)(add_help=False)
        add(p, collapsed=False)
        for action in p._actions:
            if action.dest == "units":     # the robot commands show their one length option in full
                continue
            words = " ".join(action.help.split())[:40]
            assert words in " ".join(text.split()), (topic, action.option_strings)
            assert not any(words in " ".join(help_of(c).split()) for c in SUBS), (topic, action.option_strings)


def test_props_help_is_short_and_names_every_shared_block():
    text = help_of("props")
    assert len(text.splitlines()) <= 50
    for topic in ("source", "mesh", "output", "robot", "usd"):
        assert f"(inertia help {topic})" in text


def test_help_of_a_command_is_its_own_help(capsys):
    assert run(capsys, "help", "fix")[1] == help_of("fix")
    assert run(capsys, "help")[1] == help_of(None)


# ---------------------------------------------------------------------------- output units and convention


def test_output_units_give_a_box_in_grams_and_millimetres(capsys):
    rc, out, _ = run(capsys, "props", "box:0.1,0.2,0.4", "--mass", "2", "--output-units", "g,mm", "--format", "json")
    d = json.loads(out)
    m, (a, b, c) = 2000.0, (100.0, 200.0, 400.0)          # g, mm
    assert d["mass"] == pytest.approx(m, rel=1e-15) and d["volume"] == pytest.approx(a * b * c, rel=1e-15)
    np.testing.assert_allclose(np.diag(d["inertia_com"]), [m * (b * b + c * c) / 12, m * (a * a + c * c) / 12,
                                                           m * (a * a + b * b) / 12], rtol=1e-14)
    assert d["density"] == pytest.approx(m / (a * b * c), rel=1e-14) and d["density_unit"] == "g/mm^3"
    assert d["dimensions"] == pytest.approx([a, b, c], rel=1e-15)
    assert d["output_units"] == {"mass": "g", "length": "mm", "inertia": "g mm^2", "convention": "tensor"}
    rc, out, _ = run(capsys, "props", "box:0.1,0.2,0.4", "--mass", "2", "--output-units", "g,mm")
    assert "mass            2000 g" in out and "[g mm^2]" in out


def _tilted_box(path, size, R, offset):
    corners = np.array([[x, y, z] for x in (-0.5, 0.5) for y in (-0.5, 0.5) for z in (-0.5, 0.5)]) * size
    v = corners @ R.T + offset
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    path.write_text("".join(f"v {x!r} {y!r} {z!r}\n" for x, y, z in v.tolist()) + "".join(f"f {a + 1} {b + 1} {c + 1}\n"
                                                                                 for a, b, c in faces))
    return path


def test_cad_convention_prints_positive_products_of_a_tilted_box(capsys, tmp_path):
    from scipy.spatial.transform import Rotation

    R = Rotation.from_euler("xyz", [20, 30, 40], degrees=True).as_matrix()
    size, rho = np.array([30.0, 20.0, 10.0]), 7850.0          # mm, kg/m^3
    path = _tilted_box(tmp_path / "tilted.obj", size, R, [5.0, 6.0, 7.0])
    m = rho * np.prod(size) * 1e-9 * 1e3                        # g
    a, b, c = size
    I_box = m / 12 * np.diag([b * b + c * c, a * a + c * c, a * a + b * b])   # g mm^2, in the box's axes
    tensor = R @ I_box @ R.T                                     # negated products (L = I w)
    cad = tensor * (2 * np.eye(3) - 1)                           # products positive: +sum m x y
    rc, out, _ = run(capsys, "props", path, "--units", "mm", "--density", rho, "--output-units", "g,mm",
                     "--convention", "cad", "--format", "json")
    d = json.loads(out)
    np.testing.assert_allclose(d["inertia_com"], cad, rtol=0, atol=1e-12 * np.abs(cad).max())
    np.testing.assert_allclose(d["principal_moments"], np.sort(np.diag(I_box)), rtol=1e-12)
    np.testing.assert_allclose(d["com"], [5.0, 6.0, 7.0], rtol=1e-13)
    assert d["output_units"]["convention"] == "cad" and "positive" in d["conventions"]


@pytest.mark.parametrize("argv", [["--format", "urdf", "--convention", "cad"], ["--format", "sdf", "--output-units",
                                                                                 "g,mm"]])
def test_blocks_for_robot_files_refuse_other_units(capsys, argv):
    rc, _, err = run(capsys, "props", "box:1,1,1", *argv)
    assert rc == 1 and "SI units and tensor elements" in err


@pytest.mark.parametrize("text", ["g", "g,parsec", "stone,m", "mm,g"])
def test_bad_output_units_are_named(capsys, text):
    rc, _, err = run(capsys, "props", "box:1,1,1", "--output-units", text)
    assert rc == 1 and f"--output-units {text!r} must read MASS,LENGTH" in err


def test_particles_demo_and_diff_print_in_the_output_units(capsys, tmp_path):
    si = json.loads(run(capsys, "particles", "box:0.1,0.2,0.4", "--mass", "2", "--format", "json")[1])
    g = json.loads(run(capsys, "particles", "box:0.1,0.2,0.4", "--mass", "2", "--format", "json",
                       "--output-units", "g,mm")[1])
    np.testing.assert_allclose(g["six_point"]["masses"], np.array(si["six_point"]["masses"]) * 1e3, rtol=1e-15)
    np.testing.assert_allclose(g["six_point"]["positions"], np.array(si["six_point"]["positions"]) * 1e3, rtol=1e-15)
    demo = json.loads(run(capsys, "demo", "--no-report", "--format", "json", "--output-units", "lb,in")[1])
    demo_si = json.loads(run(capsys, "demo", "--no-report", "--format", "json")[1])
    lb, inch = 0.45359237, 0.0254
    assert demo["mass_properties"]["mass"] == pytest.approx(demo_si["mass_properties"]["mass"] / lb, rel=1e-15)
    np.testing.assert_allclose(demo["equivalent_box"]["size"], np.array(demo_si["equivalent_box"]["size"]) / inch,
                               rtol=1e-15)
    urdf = tmp_path / "a.urdf"
    urdf.write_text('<robot name="r"><link name="l"><inertial><mass value="1.5"/><inertia ixx="0.1" iyy="0.1" '
                    'izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>')
    other = tmp_path / "b.urdf"
    other.write_text(urdf.read_text().replace("1.5", "2"))
    rc, out, _ = run(capsys, "diff", urdf, other, "--output-units", "g,m")
    assert rc == 1 and "(total mass 1500 vs 2000 g)" in out and "A: 1500 g, COM [0, 0, 0] m" in out


# ---------------------------------------------------------------------------- numbers written into files


def _significant(text: str) -> int:
    mantissa = text.lstrip("-").split("e")[0].replace(".", "").lstrip("0")
    return len(mantissa)


def test_an_inertial_block_carries_six_significant_digits(capsys, tmp_path):
    from inertia.robots import read_robot

    rc, block, _ = run(capsys, "props", "cylinder:0.0123456789,0.1", "--density", "2700", "--format", "urdf")
    numbers = re.findall(r'"([^"]+)"', block)
    assert all(_significant(x) <= 6 for n in numbers for x in n.split()), block
    path = tmp_path / "r.urdf"
    path.write_text(f'<robot name="r"><link name="l">{block}</link></robot>')
    back = read_robot(path).link("l").inertial
    r, h = 0.0123456789, 0.1
    m = 2700 * np.pi * r * r * h
    assert back.mass == pytest.approx(m, rel=5e-6)
    np.testing.assert_allclose(np.diag(back.inertia_com), [m * (3 * r * r + h * h) / 12] * 2 + [m * r * r / 2],
                               rtol=5e-6)


def test_a_block_near_the_triangle_inequality_keeps_the_digits_that_keep_it_physical(capsys, tmp_path):
    """A plate 1 m square and 10 um thick: I1 + I2 - I3 = m c^2 / 6, 1.7e-11 of I3; six digits
    would break the inequality, so the block carries more, and check of the written file passes."""
    from inertia.massprops.validity import is_physical

    m, c = 1.0, 1e-5
    moments = [m * (1 + c * c) / 12, m * (1 + c * c) / 12, m * 2 / 12]
    six = [float(f"{x:.6g}") for x in moments]
    assert six[0] + six[1] < six[2]                      # six digits would break the triangle inequality
    rc, block, _ = run(capsys, "props", f"box:1,1,{c}", "--mass", m, "--format", "urdf")
    values = dict(re.findall(r'(i[xyz]{2})="([^"]+)"', block))
    assert max(_significant(v) for v in values.values()) > 6
    ixx, iyy, izz = (float(values[k]) for k in ("ixx", "iyy", "izz"))
    assert ixx + iyy >= izz and is_physical(np.diag([ixx, iyy, izz]), m)
    np.testing.assert_allclose([ixx, iyy, izz], moments, rtol=5e-6)
    path = tmp_path / "plate.urdf"
    path.write_text(f'<robot name="r"><link name="l">{block}</link></robot>')
    rc, out, _ = run(capsys, "check", path)
    assert rc == 0 and "0 errors" in out


# ---------------------------------------------------------------------------- check: missing meshes

LINK = ('<link name="{name}"><inertial><mass value="1"/><inertia ixx="0.4" iyy="0.4" izz="0.4" ixy="0" ixz="0" '
        'iyz="0"/></inertial><visual><geometry><mesh filename="{uri}"/></geometry></visual>'
        '<collision><geometry><mesh filename="{uri}"/></geometry></collision></link>')


def test_missing_meshes_are_one_line_per_package_with_one_hint(capsys, tmp_path):
    links = [LINK.format(name=f"l{i}", uri=f"package://arm_description/meshes/l{i}.stl") for i in range(3)]
    links += [LINK.format(name="hand", uri="meshes/hand.stl")]
    joints = [f'<joint name="j{i}" type="revolute"><parent link="l{i}"/><child link="{c}"/><axis xyz="0 0 1"/>'
              '<limit lower="-1" upper="1" effort="1" velocity="1"/></joint>' for i, c in ((0, "l1"), (1, "l2"),
                                                                                          (2, "hand"))]
    path = tmp_path / "arm.urdf"
    path.write_text('<robot name="arm">' + "".join(links + joints) + "</robot>")
    rc, out, _ = run(capsys, "check", path)
    lines = out.splitlines()
    assert rc == 0 and lines[0].endswith("0 errors, 8 warnings")
    assert lines[1:] == [
        "  warning mesh_not_found: 3 meshes of 3 links not found in package://arm_description (e.g. l0.stl); "
        "their geometry comparisons are skipped",
        f"  warning mesh_not_found: 1 mesh of 1 link not found in {tmp_path / 'meshes'} (e.g. hand.stl); "
        "their geometry comparisons are skipped",
        "  hint: --package-path DIR adds a folder to search for package:// and model:// meshes; --verbose lists "
        "each missing mesh"]
    rc, out, _ = run(capsys, "check", path, "--verbose")
    assert sum("warning mesh_not_found" in line for line in out.splitlines()) == 8
    d = json.loads(run(capsys, "check", path, "--format", "json")[1])
    assert sum(w["code"] == "mesh_not_found" for lk in d["links"] for w in lk["findings"]) == 8
