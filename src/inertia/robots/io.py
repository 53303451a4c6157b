"""Which reader a robot file needs."""

from __future__ import annotations

from pathlib import Path

from .xmlsafe import RobotFileError, parse_xml

FORMATS = ("urdf", "sdf", "mjcf")
_BY_ROOT = {"robot": "urdf", "sdf": "sdf", "mujoco": "mjcf"}
_BY_EXT = {".urdf": "urdf", ".sdf": "sdf", ".world": "sdf", ".mjcf": "mjcf"}


def detect_format(path) -> str:
    """"urdf", "sdf" or "mjcf", from the extension or else the root element (``.xml``)."""
    p = Path(path)
    fmt = _BY_EXT.get(p.suffix.lower())
    if fmt:
        return fmt
    root = parse_xml(p).root.tag
    if root in _BY_ROOT:
        return _BY_ROOT[root]
    raise RobotFileError(f"{p}: not a robot file: root element <{root}> is none of <robot> (URDF), "
                         "<sdf> (SDF), <mujoco> (MJCF)")


def read_robot(path, *, format: str | None = None, search_paths=()):
    """Read a URDF, SDF or MJCF file into a :class:`~inertia.robots.model.RobotModel`."""
    from .mjcf import read_mjcf
    from .urdf_sdf import read_sdf, read_urdf

    fmt = format or detect_format(path)
    if fmt not in FORMATS:
        raise RobotFileError(f"unknown robot format {fmt!r}; use one of {', '.join(FORMATS)}")
    return {"urdf": read_urdf, "sdf": read_sdf, "mjcf": read_mjcf}[fmt](path, search_paths=search_paths)
