"""Atomic file writes: a temporary file in the target's folder, flushed, then renamed over it.

A reader never sees a half-written file, and an interrupted write leaves the old file (or
nothing) in place.  Standard library only.
"""

from __future__ import annotations

import os
import tempfile

from .errors import InputError


def output_folder(path) -> str:
    """The folder of the output ``path``, created if missing; InputError (code ``unwritable``)
    naming the path when it cannot be (a regular file in the way, no permission)."""
    path = os.fspath(path)
    if os.path.isdir(path):
        raise InputError(f"{path}: is a folder; give the output a file name", code="unwritable")
    folder = os.path.dirname(os.path.abspath(path))
    try:
        os.makedirs(folder, exist_ok=True)
    except OSError as exc:
        block = folder
        while block and not os.path.exists(block) and os.path.dirname(block) != block:
            block = os.path.dirname(block)
        why = (f"{block} is a file, not a folder" if os.path.exists(block) and not os.path.isdir(block)
               else f"cannot make the folder {folder} ({exc.strerror or exc})")
        raise InputError(f"{path}: cannot write the output there: {why}", code="unwritable") from None
    return folder


def temp_beside(path) -> str:
    """A new, empty temporary file in the folder of ``path`` (closed; the caller writes it)."""
    folder = output_folder(path)
    try:
        fd, tmp = tempfile.mkstemp(prefix="." + os.path.basename(os.fspath(path)) + ".", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise InputError(f"{os.fspath(path)}: cannot write the output there ({exc.strerror or exc})",
                         code="unwritable") from None
    os.close(fd)
    return tmp


def replace_with_temp(tmp, path) -> None:
    """Move the finished temporary ``tmp`` over ``path``, with the permissions a plainly
    written file would have (those of the file it replaces, else 0666 less the umask; the
    temporary's own are 0600)."""
    path = os.fspath(path)
    if os.path.exists(path):  # keep the permissions of a file being replaced
        os.chmod(tmp, os.stat(path).st_mode & 0o7777)
    else:
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
    os.replace(tmp, path)


def write_bytes_atomic(path, data: bytes) -> None:
    """Write ``data`` to ``path`` atomically (same-folder temp file + ``os.replace``)."""
    path = os.fspath(path)
    tmp = temp_beside(path)
    fd = os.open(tmp, os.O_WRONLY)
    try:
        with os.fdopen(fd, "wb") as fh:
            fh.write(data)
            fh.flush()
            os.fsync(fh.fileno())
        replace_with_temp(tmp, path)
    except BaseException as exc:
        try:
            os.unlink(tmp)
        except FileNotFoundError:
            pass
        if isinstance(exc, OSError):   # a full disk, a file-size limit, a vanished folder
            raise InputError(f"{path}: cannot write the output ({exc.strerror or exc}); nothing was written",
                             code="unwritable") from None
        raise


def remove_stale_temps(path) -> int:
    """Remove the temporary files an interrupted atomic write of ``path`` left behind.

    Only a killed process (``kill -9``, power loss) leaves them: every other exit removes its
    own.  Call it before writing ``path`` again; returns how many were removed.
    """
    path = os.fspath(path)
    folder = os.path.dirname(os.path.abspath(path))
    prefix = "." + os.path.basename(path) + "."
    removed = 0
    try:
        names = os.listdir(folder)
    except OSError:
        return 0
    for name in names:
        if name.startswith(prefix) and name.endswith(".tmp") and len(name) == len(prefix) + 8 + 4:
            try:
                os.unlink(os.path.join(folder, name))
                removed += 1
            except OSError:
                pass
    return removed


def write_text_atomic(path, text: str, encoding: str = "utf-8") -> None:
    """Write ``text`` to ``path`` atomically (see :func:`write_bytes_atomic`)."""
    write_bytes_atomic(path, text.encode(encoding))
