"""Atomic writes: the target is either the old file or the whole new one, never a mix."""

import os
import stat

import pytest

from inertia._core.atomic import write_bytes_atomic, write_text_atomic


def test_writes_whole_file_and_leaves_no_temporary(tmp_path):
    target = tmp_path / "out.txt"
    write_text_atomic(target, "hello\n")
    assert target.read_text() == "hello\n"
    assert os.listdir(tmp_path) == ["out.txt"]


def test_replacing_keeps_permissions(tmp_path):
    target = tmp_path / "script.sh"
    target.write_text("old")
    target.chmod(0o750)
    write_text_atomic(target, "new")
    assert target.read_text() == "new"
    assert stat.S_IMODE(target.stat().st_mode) == 0o750


def test_failed_write_leaves_the_old_file(tmp_path):
    target = tmp_path / "keep.bin"
    target.write_bytes(b"old")

    with pytest.raises(TypeError):
        write_bytes_atomic(target, object())  # not bytes: the write fails midway
    assert target.read_bytes() == b"old"
    assert os.listdir(tmp_path) == ["keep.bin"]
