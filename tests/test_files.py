"""The input-file rule (inertia._core.files): every path kind a user can give, answered at once.

Truth: the kind of each path as the test made it (a FIFO, a device, a socket, a folder, a
loop); each refusal names the path and the kind, with a stable code, and none blocks.
"""

from __future__ import annotations

import os
import socket

import pytest

from inertia._core.files import open_regular, read_regular
from inertia.errors import MeshFileError, RobotFileError


def _read(path, limit=2**20, error=MeshFileError):
    return read_regular(path, what="mesh file", limit=limit, error=error)


def test_a_regular_file_and_a_symlink_to_it_read_whole(tmp_path):
    (tmp_path / "a.stl").write_bytes(b"solid x\nendsolid x\n")
    os.symlink(tmp_path / "a.stl", tmp_path / "link.stl")
    assert _read(tmp_path / "a.stl") == _read(tmp_path / "link.stl") == b"solid x\nendsolid x\n"
    assert _read_empty(tmp_path) == b""


def _read_empty(tmp_path):
    (tmp_path / "empty.obj").write_bytes(b"")
    return _read(tmp_path / "empty.obj")


def test_a_fifo_is_refused_at_once_not_waited_on(tmp_path):
    fifo = tmp_path / "r.xml"
    os.mkfifo(fifo)
    with pytest.raises(RobotFileError, match=r"r\.xml: the robot file is a FIFO \(named pipe\), not a regular file") \
            as info:
        read_regular(fifo, what="robot file", limit=2**20, error=RobotFileError)
    assert info.value.code == "unreadable"


def test_devices_sockets_folders_and_loops_are_named(tmp_path):
    os.symlink("/dev/zero", tmp_path / "zero.urdf")
    with pytest.raises(MeshFileError, match="is a character device, not a regular file") as info:
        _read(tmp_path / "zero.urdf")
    assert info.value.code == "unreadable" and "zero.urdf" in str(info.value)
    with pytest.raises(MeshFileError, match="is a folder"):
        _read(tmp_path)
    os.symlink(tmp_path / "loop_b", tmp_path / "loop_a")
    os.symlink(tmp_path / "loop_a", tmp_path / "loop_b")
    with pytest.raises(MeshFileError, match="symlink loop"):
        _read(tmp_path / "loop_a")
    os.symlink(tmp_path / "gone.stl", tmp_path / "dangling.stl")
    with pytest.raises(MeshFileError, match=r"symlink to a path that does not exist") as info:
        _read(tmp_path / "dangling.stl")
    assert info.value.code == "not_found"
    with pytest.raises(MeshFileError, match="mesh file not found") as info:
        _read(tmp_path / "missing.stl")
    assert info.value.code == "not_found"
    sock_path = tmp_path / "s.obj"
    with socket.socket(socket.AF_UNIX) as sock:
        sock.bind(str(sock_path))
        with pytest.raises(MeshFileError, match="not a regular file|a socket"):
            _read(sock_path)


def test_a_file_over_the_cap_is_refused_with_its_size(tmp_path):
    big = tmp_path / "big.stl"
    big.write_bytes(b"\0" * (3 * 2**20))
    with pytest.raises(MeshFileError, match=r"is 3 MiB, more than the 2 MiB this reader accepts") as info:
        _read(big, limit=2 * 2**20)
    assert info.value.code == "too_large"
    fd, size = open_regular(big, limit=4 * 2**20, error=MeshFileError)
    os.close(fd)
    assert size == 3 * 2**20


@pytest.mark.skipif(os.geteuid() == 0, reason="root reads every file")
def test_a_file_without_read_permission_is_unreadable(tmp_path):
    p = tmp_path / "secret.stl"
    p.write_bytes(b"x")
    p.chmod(0)
    with pytest.raises(MeshFileError, match="cannot open the mesh file") as info:
        _read(p)
    assert info.value.code == "unreadable"
