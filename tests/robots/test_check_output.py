"""What `inertia check` prints: one summary line for a model with nothing wrong, one message
per missing mesh, hints that fit the reference, the detail levels and correct plurals."""

from __future__ import annotations

import pytest

from inertia.cli.main import main

GOOD_LINK = ('  <link name="{name}">\n    <inertial><mass value="1"/>'
             '<inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>\n'
             '    <visual><geometry>{geometry}</geometry></visual>\n  </link>\n')


FIXED = '  <joint name="j" type="fixed"><parent link="{parent}"/><child link="{child}"/></joint>\n'


def _urdf(tmp_path, *links, name="r.urdf"):
    path = tmp_path / name
    path.write_text('<robot name="r">\n' + "".join(links) + "</robot>\n")
    return path


def _check(capsys, *argv):
    code = main(["check", *map(str, argv)])
    return code, capsys.readouterr().out.splitlines()


def test_a_model_with_nothing_wrong_prints_one_line_with_plurals(tmp_path, capsys):
    # a 1 m sphere of 1 kg has moments 0.4: declare that, so nothing disagrees
    link = GOOD_LINK.replace('0.1', '0.4').format(name="ball", geometry='<sphere radius="1"/>')
    code, lines = _check(capsys, _urdf(tmp_path, link))
    assert code == 0
    assert lines == [f"{tmp_path / 'r.urdf'} (URDF, 1 link): 0 errors, 0 warnings"]


def test_notes_are_summarised_and_listed_with_verbose(tmp_path, capsys):
    """An open mesh leaves the comparison undone: a note, counted on the summary line and
    summarised in one line; --verbose lists it."""
    trimesh = pytest.importorskip("trimesh")
    box = trimesh.creation.box()
    box.faces = box.faces[:-1]                       # open
    box.export(tmp_path / "open.stl")
    links = [GOOD_LINK.format(name=f"l{i}", geometry='<mesh filename="open.stl"/>') for i in range(2)]
    path = _urdf(tmp_path, *links, FIXED.format(parent="l0", child="l1"))
    code, lines = _check(capsys, path)
    assert code == 0
    assert lines[0].endswith("(URDF, 2 links): 0 errors, 0 warnings, 2 notes")
    assert len(lines) == 2 and "geometry comparisons skipped" in lines[1] and "in 2 links" in lines[1]
    code, verbose = _check(capsys, path, "--verbose")
    assert sum("note geometry_unusable" in line for line in verbose) == 2
    assert all("'open.stl' is not a closed" in line for line in verbose if "note geometry_unusable" in line)
    assert _check(capsys, path, "--quiet")[1] == lines[:1]


def test_one_missing_mesh_is_one_message_with_the_hint_that_fits(tmp_path, capsys):
    links = [GOOD_LINK.format(name="a", geometry='<mesh filename="meshes/gone.stl"/>'),
             GOOD_LINK.format(name="b", geometry='<mesh filename="package://pkg/gone.stl"/>'),
             FIXED.format(parent="a", child="b")]
    code, lines = _check(capsys, _urdf(tmp_path, *links), "--verbose")
    assert code == 0
    found = [line for line in lines if "gone.stl" in line]
    assert len(found) == 2, lines                                        # one per mesh, no extra note
    plain, package = found
    assert "looked for" in plain and str(tmp_path / "meshes" / "gone.stl") in plain
    assert "package://" not in plain.split("not found", 1)[1]            # no package hint for a plain path
    assert "--package-path" in package
    assert all("geometry comparison skipped" in line for line in found)


def test_errors_only_and_quiet(tmp_path, capsys):
    bad = ('  <link name="bad">\n    <inertial><mass value="1"/>'
           '<inertia ixx="1" iyy="1" izz="3" ixy="0" ixz="0" iyz="0"/></inertial>\n  </link>\n')
    warn = GOOD_LINK.format(name="w", geometry='<mesh filename="gone.stl"/>')
    path = _urdf(tmp_path, bad, warn, FIXED.format(parent="bad", child="w"))
    code, lines = _check(capsys, path)
    assert code == 1 and lines[0].endswith("(URDF, 2 links): 1 error, 1 warning")
    assert any("error triangle_inequality" in line for line in lines)
    assert any("warning mesh_not_found" in line for line in lines)
    code, errors = _check(capsys, path, "--errors-only")
    assert code == 1 and not any("warning" in line for line in errors[1:])
    assert any("error triangle_inequality" in line for line in errors)
    code, quiet = _check(capsys, path, "-q")
    assert code == 1 and quiet == lines[:1]
