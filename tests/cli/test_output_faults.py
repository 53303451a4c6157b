"""Outputs that fail: a full disk, a file-size limit, a reader that goes away.

Each command runs as a real process, as a user's would.  Truth: a write that cannot complete
is exit 1 with a message naming the output, never exit 0 with a cut file and never an
internal error (exit 3); a closed pipe (``inertia ... | head -1``) is a quiet exit 0.
"""

from __future__ import annotations

import os
import resource
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from tests._make import write_binary_stl

from .test_cli import cli_command


@pytest.fixture(scope="module")
def sphere(tmp_path_factory) -> Path:
    trimesh = pytest.importorskip("trimesh")
    m = trimesh.creation.icosphere(subdivisions=2)
    return write_binary_stl(tmp_path_factory.mktemp("mesh") / "sphere.stl", m.vertices[m.faces])


def _run(args, *, stdout=None, fsize=None, cwd=None):
    def limit():
        if fsize is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (fsize, fsize))
    return subprocess.run(cli_command() + [str(a) for a in args], stdout=stdout or subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, preexec_fn=limit, cwd=cwd, timeout=300)


URDF = ('<robot name="r"><link name="a"><inertial><mass value="1"/>'
        '<inertia ixx="1" iyy="1" izz="3" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>\n')

COMMANDS = [("props", "{mesh}", "--format", "json"), ("props", "{mesh}"), ("check", "{robot}"),
            ("simulate", "box:0.1,0.2,0.3", "--mass", "1", "--omega", "0,5,0.1", "--times", "0,1,2"),
            ("lagrangian", "--format", "python")]


@pytest.mark.skipif(not os.path.exists("/dev/full"), reason="no /dev/full on this system")
@pytest.mark.parametrize("args", COMMANDS, ids=lambda a: " ".join(a[:2]))
def test_stdout_to_a_full_device_is_a_named_error(sphere, args, tmp_path):
    (tmp_path / "r.urdf").write_text(URDF)
    args = [a.format(mesh=sphere, robot=tmp_path / "r.urdf") for a in args]
    with open("/dev/full", "w") as full:
        r = _run(args, stdout=full)
    assert r.returncode == 1, r.stderr
    assert "cannot write the output (No space left on device)" in r.stderr and "Traceback" not in r.stderr


def test_stdout_cut_by_a_file_size_limit_is_a_named_error(sphere, tmp_path):
    whole = _run(["props", sphere, "--format", "json"])
    assert whole.returncode == 0 and len(whole.stdout) > 1024
    with open(tmp_path / "out.json", "w") as fh:
        r = _run(["props", sphere, "--format", "json"], stdout=fh, fsize=1024)
    assert r.returncode == 1 and "cannot write the output (File too large)" in r.stderr, r.stderr


def test_a_reader_that_goes_away_ends_the_command_quietly(sphere):
    script = f"{' '.join(cli_command())} props {sphere} | head -1"
    r = subprocess.run(["bash", "-o", "pipefail", "-c", script], capture_output=True, text=True, timeout=300)
    assert r.stdout.startswith("Mass properties of") and r.stdout.count("\n") == 1
    assert r.returncode == 0 and r.stderr == "", r.stderr


def test_an_output_file_beyond_a_size_limit_is_refused_and_nothing_is_left(tmp_path):
    robot = tmp_path / "r.urdf"
    robot.write_text(URDF.replace("</robot>", "<!-- padding -->" * 200 + "</robot>"))
    out = tmp_path / "fixed.urdf"
    r = _run(["fix", robot, "-o", out], fsize=2048, cwd=tmp_path)
    assert r.returncode == 1 and "cannot write the output (File too large)" in r.stderr, r.stderr
    assert not out.exists() and sorted(p.name for p in tmp_path.iterdir()) == ["r.urdf"]


@pytest.mark.parametrize("ext", ["jsonl", "csv", "parquet"])
def test_a_batch_table_beyond_a_size_limit_is_refused_and_resumable(tmp_path, ext):
    pytest.importorskip("pyarrow")
    pytest.importorskip("pandas")
    trimesh = pytest.importorskip("trimesh")
    folder = tmp_path / "meshes"
    folder.mkdir()
    volumes = []
    for k in range(40):
        m = trimesh.creation.icosphere(subdivisions=1, radius=1 + k)
        write_binary_stl(folder / f"s{k:02d}.stl", m.vertices[m.faces])
        volumes.append(m.volume)
    out = tmp_path / f"out.{ext}"
    # the meshes (32 kB each) are read, but no table of their rows fits in 4 kB
    r = _run(["batch", folder, "-o", out, "--no-progress"], fsize=4096, cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    assert "cannot write the output" in r.stderr and "Traceback" not in r.stderr and "internal" not in r.stderr
    assert not out.exists()
    again = _run(["batch", folder, "-o", out, "--no-progress", "--resume"], cwd=tmp_path)
    assert again.returncode == 0, again.stderr
    from inertia.batch import read_frame

    table = read_frame(out)
    assert len(table) == 40 and set(table["status"]) == {"ok"}
    assert np.allclose(sorted(table["volume"]), sorted(volumes), rtol=1e-6)


def test_python_api_write_errors_are_our_error(tmp_path):
    from inertia._core.atomic import write_text_atomic
    from inertia.errors import InputError

    if not os.path.exists("/dev/full"):
        pytest.skip("no /dev/full")
    code = ("import resource, sys; resource.setrlimit(resource.RLIMIT_FSIZE, (100, 100));"
            "from inertia._core.atomic import write_text_atomic;"
            "from inertia.errors import InputError\n"
            "try:\n    write_text_atomic(sys.argv[1], 'x' * 1000)\n"
            "except InputError as e:\n    print(e.code, e)\n")
    r = subprocess.run([sys.executable, "-c", code, str(tmp_path / "big.txt")], capture_output=True, text=True)
    assert r.stdout.startswith("unwritable ") and "File too large" in r.stdout, r.stderr
    assert list(tmp_path.iterdir()) == []
    write_text_atomic(tmp_path / "ok.txt", "fine")
    assert (tmp_path / "ok.txt").read_text() == "fine" and InputError
