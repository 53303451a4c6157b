"""Reading input files: one rule for every reader.

An input is a regular file (a symlink to one is followed), opened without blocking and read
whole up to a size cap; anything else (a FIFO, a device, a socket, a folder, a symlink loop,
a file that vanished or cannot be opened) is refused with a message that names the path and
what it is, never a hang, an unbounded read or a "not found" for a path that exists.
"""

from __future__ import annotations

import errno
import mmap
import os
import stat

from .errors import InertiaError

#: a robot description (URDF, SDF, MJCF, xacro and their includes) larger than this is refused
MAX_ROBOT_FILE_BYTES = 256 * 2**20
#: a mesh file larger than this is refused (a binary STL of 80 million faces)
MAX_MESH_FILE_BYTES = 4 * 2**30
#: files up to this size are read into memory; larger ones are mapped (pages read as used)
MAP_BYTES = 16 * 2**20

_KINDS = ((stat.S_ISDIR, "a folder"), (stat.S_ISFIFO, "a FIFO (named pipe)"), (stat.S_ISCHR, "a character device"),
          (stat.S_ISBLK, "a block device"), (stat.S_ISSOCK, "a socket"))


def _refuse(error, path, why: str, code: str):
    raise error(f"{path}: {why}", code=code)


def open_regular(path, *, what: str = "file", limit: int, error=InertiaError) -> tuple[int, int]:
    """``(fd, size)`` of the regular file ``path``, opened read-only without blocking, or
    ``error`` (an :class:`InertiaError` subclass) naming the path: code ``not_found``,
    ``unreadable`` (not a regular file, no permission, a symlink loop) or ``too_large``."""
    path = os.fspath(path)
    try:
        fd = os.open(path, os.O_RDONLY | os.O_NONBLOCK | getattr(os, "O_CLOEXEC", 0))
    except FileNotFoundError:
        if os.path.islink(path):
            _refuse(error, path, f"the {what} is a symlink to a path that does not exist "
                                 f"({os.readlink(path)})", "not_found")
        _refuse(error, path, f"{what} not found", "not_found")
    except OSError as exc:
        if exc.errno == errno.ELOOP:
            _refuse(error, path, f"the {what} is a symlink loop", "unreadable")
        if exc.errno == errno.EISDIR:
            _refuse(error, path, f"the {what} is a folder, not a file", "unreadable")
        if exc.errno == errno.ENXIO:   # a socket, or a FIFO opened for writing only
            _refuse(error, path, f"the {what} is not a regular file (a socket or a device without a reader)",
                    "unreadable")
        _refuse(error, path, f"cannot open the {what} ({exc.strerror or exc})", "unreadable")
    try:
        st = os.fstat(fd)
        if not stat.S_ISREG(st.st_mode):
            kind = next((name for test, name in _KINDS if test(st.st_mode)), "not a regular file")
            _refuse(error, path, f"the {what} is {kind}, not a regular file: give the path of a file", "unreadable")
        if st.st_size > limit:
            _refuse(error, path, f"the {what} is {st.st_size / 2**20:.0f} MiB, more than the "
                                 f"{limit / 2**20:.0f} MiB this reader accepts", "too_large")
        os.set_blocking(fd, True)
        return fd, int(st.st_size)
    except BaseException:
        os.close(fd)
        raise


def read_regular(path, *, what: str = "file", limit: int, error=InertiaError, map_large: bool = False):
    """The bytes of the regular file ``path`` (see :func:`open_regular`): ``bytes``, or with
    ``map_large`` a read-only ``mmap`` for a file over :data:`MAP_BYTES`.  A file that shrinks
    or grows while read is refused (``unreadable``), never half read."""
    fd, size = open_regular(path, what=what, limit=limit, error=error)
    try:
        if map_large and size > MAP_BYTES:
            return mmap.mmap(fd, size, access=mmap.ACCESS_READ)
        chunks, got = [], 0
        while got <= size:
            chunk = os.read(fd, max(size - got, 0) + 1)
            if not chunk:
                break
            chunks.append(chunk)
            got += len(chunk)
        if got != size:
            _refuse(error, os.fspath(path), f"the {what} changed while it was read ({size} bytes, then {got})",
                    "unreadable")
        return b"".join(chunks)
    except OSError as exc:
        _refuse(error, os.fspath(path), f"cannot read the {what} ({exc.strerror or exc})", "unreadable")
    finally:
        os.close(fd)
