"""Mesh references in robot files to paths on disk.

* plain paths: relative to the robot file's folder (or, for MJCF, to ``meshdir``);
* ``package://NAME/rest``: looked up as ``DIR/NAME/rest`` and ``DIR/rest`` for each
  search folder given (``--package-path``), then the robot file's parents (a package's
  folder usually holds the file);
* ``model://NAME/rest`` (SDF): ``DIR/NAME/rest`` for each search folder, then the parents;
* ``file://`` URIs: the local path.

Nothing is fetched from a network.  A reference that cannot be found resolves to None and
the caller reports it; one that names something other than a file (a FIFO, a device, a folder,
a dangling link) resolves to its path, which the mesh reader refuses by name.
"""

from __future__ import annotations

import os
from pathlib import Path
from urllib.parse import unquote, urlparse

from .._core.errors import RobotFileError


def resolve_mesh(uri: str, base_dir: Path, search_paths=(), *, where: str = "") -> Path | None:
    """The path ``uri`` names, where something is, or None.

    A name the operating system cannot look up at all (too long, a NUL byte) is a
    :class:`RobotFileError` whose message starts with ``where`` (the element's ``file:line``).
    """
    uri = uri.strip()
    try:
        return _resolve(uri, base_dir, search_paths)
    except (OSError, ValueError) as exc:
        reason = getattr(exc, "strerror", None) or str(exc)
        raise RobotFileError(f"{where or base_dir}: mesh file name {uri!r} cannot be looked up ({reason})") from None


def _resolve(uri: str, base_dir: Path, search_paths) -> Path | None:
    search = [Path(p) for p in search_paths]
    if uri.startswith(("package://", "model://")):
        scheme, rest = uri.split("://", 1)
        name, _, tail = rest.partition("/")
        parents = [base_dir, *base_dir.parents]
        candidates = []
        for d in search + parents:
            candidates.append(d / name / tail)
            if scheme == "package":
                candidates.append(d / tail)
        return next((c for c in candidates if c.is_file()), None) or next(
            (c for c in candidates if _present(c) and not c.is_dir()), None)
    if uri.startswith("file://"):
        p = Path(unquote(urlparse(uri).path))
    elif "://" in uri:
        return None  # http(s) and friends: never fetched
    else:
        p = Path(uri) if Path(uri).is_absolute() else base_dir / uri
    return p if _present(p) else None


def _present(p: Path) -> bool:
    """Whether something is at ``p`` (a dangling link too); OSError for a name that cannot be looked up."""
    try:
        os.lstat(p)
    except (FileNotFoundError, NotADirectoryError):
        return False
    return True


def mesh_note(found, uri: str, base_dir: Path, what: str, hint: str | None = None):
    """The reader's ``(code, message)`` for the mesh reference ``uri`` that resolved to ``found``:
    ``mesh_not_found`` when nothing is there, ``mesh_unreadable`` when what is there is not a file
    the mesh reader opens (a FIFO, a device, a folder, a dangling link, no permission), else None.
    ``what`` starts the message (``file:line: visual mesh``)."""
    from .._core.files import MAX_MESH_FILE_BYTES, open_regular

    if found is None:
        return "mesh_not_found", f"{what} {uri!r} not found ({hint or not_found_hint(uri, base_dir)})"
    try:
        os.close(open_regular(found, what="mesh file", limit=MAX_MESH_FILE_BYTES, error=RobotFileError)[0])
    except RobotFileError as exc:
        return "mesh_unreadable", f"{what} {uri!r}: {exc}"
    return None


def not_found_hint(uri: str, base_dir: Path) -> str:
    """Where ``uri`` was looked for, for the 'not found' message (a package:// hint only for
    package:// URIs)."""
    uri = uri.strip()
    if uri.startswith("package://"):
        return "package:// is searched in each --package-path folder and the file's parent folders"
    if uri.startswith("model://"):
        return "model:// is searched next to the model folder and in each --package-path folder"
    if uri.startswith("file://"):
        return "no such local file"
    if "://" in uri:
        return "network URIs are never fetched"
    return f"looked for {Path(uri) if Path(uri).is_absolute() else base_dir / uri}"
