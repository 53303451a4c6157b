"""Every reader given every kind of path that is not a regular file (issue 34, items 4-5).

Truth: the kind of each path as the test made it (tests/special_paths.py).  Each reader family
(mesh files, the files a mesh names, robot files and every file they include, USD layers, batch
sources, manifests and configurations) answers at once (an alarm fails a hang) with a refusal
that names the path and what is there, and never "not found" for a path that exists.
"""

from __future__ import annotations

import importlib.util
import os
import re
import signal
import subprocess

import pytest

from tests.special_paths import EXPECTED, FAMILIES, KINDS, dependencies, make_special

from .cli.test_cli import cli_command


@pytest.fixture
def alarm():
    """A reader that blocks fails the test after 20 s instead of holding the run."""
    def hung(*_):
        raise TimeoutError("the reader blocked")
    old = signal.signal(signal.SIGALRM, hung)
    signal.alarm(20)
    yield
    signal.alarm(0)
    signal.signal(signal.SIGALRM, old)


@pytest.mark.parametrize("kind", KINDS)
@pytest.mark.parametrize("family", FAMILIES)
def test_every_reader_names_a_path_that_is_not_a_regular_file(tmp_path, family, kind, alarm):
    if kind == "unreadable" and os.geteuid() == 0:
        pytest.skip("root reads every file")
    for module in dependencies(family):
        if importlib.util.find_spec(module) is None:
            pytest.skip(f"needs {module}")
    name, setup, read = FAMILIES[family]
    if setup is not None:
        setup(tmp_path)
    special = tmp_path / name
    keep = make_special(kind, special)
    try:
        expected = EXPECTED.get((family, kind), KINDS[kind])
        if expected is None:   # the format gives the path a meaning of its own (see EXPECTED)
            return
        message = read(tmp_path)
    finally:
        if keep is not None:
            keep.close()
    assert re.search(expected, message), message
    assert special.name in message, message
    if kind not in ("vanished",):
        assert "not found" not in message and "No such file" not in message, message


CASES = [  # issue 34's commands: a FIFO and /dev/zero given to props, check, fix and batch
    ("check", "r.xml"), ("fix", "r.urdf", "-o", "o.urdf"), ("props", "m.stl"), ("props", "m.ply"),
    ("batch", "m.obj", "-o", "out.csv"),
]


@pytest.mark.parametrize("kind", ["fifo", "device"])
@pytest.mark.parametrize("args", CASES, ids=lambda a: " ".join(a[:2]))
def test_the_cli_refuses_a_fifo_or_a_device_at_once_by_name(tmp_path, args, kind):
    make_special(kind, tmp_path / args[1])
    r = subprocess.run(cli_command() + list(args), cwd=tmp_path, capture_output=True, text=True, timeout=60)
    words = KINDS[kind]
    if args[0] == "batch":   # the run goes on; the file's row names it
        assert r.returncode == 0, r.stderr
        assert re.search(words, (tmp_path / "out.csv").read_text())
    else:
        assert r.returncode in (1, 2), r.stderr
        assert f"{args[1]}: the " in r.stderr and re.search(words, r.stderr), r.stderr
    assert "Traceback" not in r.stderr and "internal error" not in r.stderr and "not found" not in r.stderr
