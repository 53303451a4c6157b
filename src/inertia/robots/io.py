"""Which reader a robot file needs, and the inputs real repositories hold besides plain XML.

* ``.urdf``, ``.sdf``/``.world``, ``.mjcf``; ``.xml`` by its root element (``<robot>``,
  ``<sdf>``, ``<mujoco>``);
* ``*.xacro`` (``robot.urdf.xacro``): expanded by the ``xacro`` package (the ``xacro``
  extra), with ``$(arg NAME)`` from ``xacro_args`` and ``$(find PKG)`` looked up in the
  search folders (``--package-path``), the file's own folders and, with ROS sourced, the
  ament index.  Line numbers in messages are those of the expanded document, as
  ``xacro FILE`` prints it;
* the Gazebo 1.x format (root ``<gazebo version="1.x">``, before SDF 1.3) is refused by name.
"""

from __future__ import annotations

import os
import re
from contextlib import contextmanager
from pathlib import Path

from .xmlsafe import RobotFileError, parse_xml, parse_xml_bytes, read_robot_bytes

FORMATS = ("urdf", "sdf", "mjcf")
_BY_ROOT = {"robot": "urdf", "sdf": "sdf", "mujoco": "mjcf"}
_BY_EXT = {".urdf": "urdf", ".sdf": "sdf", ".world": "sdf", ".mjcf": "mjcf"}
_READERS = {"urdf": "read_urdf", "sdf": "read_sdf", "mjcf": "read_mjcf"}

#: a Gazebo 1.x root element, after the prolog (declaration, comments, blank lines)
_OLD_GAZEBO = re.compile(rb"""^(?:\s|<\?.*?\?>|<!--.*?-->)*<gazebo\b[^>]*?version\s*=\s*["']([^"']*)""", re.S)


def is_xacro(path) -> bool:
    return Path(path).suffix.lower() == ".xacro"


def detect_format(path) -> str:
    """"urdf", "sdf" or "mjcf", from the extension or else the root element (``.xml``)."""
    p = Path(path)
    fmt = _BY_EXT.get(p.suffix.lower())
    if fmt:
        return fmt
    return _format_of(parse_xml(p))


def _format_of(doc) -> str:
    root = doc.root.tag
    if root in _BY_ROOT:
        return _BY_ROOT[root]
    if root == "gazebo":
        raise _old_gazebo_error(doc.path, doc.root.get("version", "?"))
    raise RobotFileError(f"{doc.path}: not a robot file: root element <{root}> is none of <robot> (URDF), "
                         "<sdf> (SDF), <mujoco> (MJCF)")


def _refuse_old_gazebo(path: Path) -> None:
    m = _OLD_GAZEBO.match(read_robot_bytes(path)[:4096])
    if m:
        raise _old_gazebo_error(path, m.group(1).decode("ascii", "replace"))


def _old_gazebo_error(path, version: str) -> RobotFileError:
    return RobotFileError(f"{path}: this is the old Gazebo {version} format (root <gazebo version=\"{version}\">, "
                          "from before SDF 1.3), not SDF, and is not read; use the model's SDF file (a Gazebo model "
                          "folder's model.config names one per SDF version) or convert it to SDF 1.3 or later")


def read_robot(path, *, format: str | None = None, search_paths=(), xacro_args=None):
    """Read a URDF, SDF or MJCF file (or a ``.xacro`` that expands to one) into a
    :class:`~inertia.robots.model.RobotModel`.

    ``xacro_args``: ``{name: value}`` for the ``$(arg name)`` of a ``.xacro`` file.
    """
    from . import mjcf, urdf_sdf

    if format is not None and format not in FORMATS:
        raise RobotFileError(f"unknown robot format {format!r}; use one of {', '.join(FORMATS)}")
    document = None
    if is_xacro(path):
        document = expand_xacro(path, xacro_args, search_paths)
        fmt = format or _format_of(document)
    else:
        if xacro_args:
            raise RobotFileError(f"{path}: xacro arguments given, but this is not a .xacro file")
        fmt = format or detect_format(path)
        if fmt == "sdf":
            _refuse_old_gazebo(Path(path))
    reader = getattr(mjcf if fmt == "mjcf" else urdf_sdf, _READERS[fmt])
    return reader(path, search_paths=search_paths, document=document)


# ------------------------------------------------------------------------------------- xacro


def parse_xacro_args(items) -> dict:
    """``["name:=value", ...]`` (xacro's own syntax) -> ``{name: value}``."""
    out = {}
    for item in items or ():
        name, sep, value = str(item).partition(":=")
        if not sep or not name.strip():
            raise RobotFileError(f"xacro argument {item!r} must read NAME:=VALUE")
        out[name.strip()] = value
    return out


def expand_xacro(path, args=None, search_paths=()):
    """The :class:`~inertia.robots.xmlsafe.Document` a ``.xacro`` file expands to.

    Needs the ``xacro`` package (``pip install 'inertia[xacro]'``).  Its errors (an undefined
    argument, a missing include, a package not found) are RobotFileErrors naming the file.
    """
    from .._core.optional import require

    xacro = require("xacro", "reading .xacro files")
    path = Path(path)
    read_robot_bytes(path)   # a FIFO, a device, a folder: refused before xacro opens it
    missing: list = []  # packages $(find) did not find (xacro wraps the error we raise)
    try:
        with _packages(path.resolve(), search_paths, missing), _checked_open(xacro):
            dom = xacro.process_file(str(path.resolve()), mappings=dict(args or {}))
        text = dom.toprettyxml(indent="  ")
    except RobotFileError as exc:   # a file xacro includes or loads, refused by the input-file rule
        raise RobotFileError(f"{path}: xacro could not expand the file: {exc}") from None
    except Exception as exc:  # noqa: BLE001 - xacro raises many types; each becomes one message
        if missing:
            raise RobotFileError(f"{path}: $(find {missing[0]}): package {missing[0]!r} not found; give the folder "
                                 "that holds it (or the package folder itself) with --package-path") from None
        raise RobotFileError(f"{path}: xacro could not expand the file: {_xacro_message(exc)}") from None
    doc = parse_xml_bytes(text.encode("utf-8"), Path(f"{path} (as expanded by xacro)"))
    doc.generated_by = "xacro"  # the bytes are xacro's output, not the file's: never written back
    return doc


def _xacro_message(exc) -> str:
    msg = str(exc).strip() or type(exc).__name__
    undefined = re.search(r"[Uu]ndefined substitution argument (\S+)", msg)
    if undefined:
        msg += f" (give it with --xacro-arg {undefined.group(1)}:=VALUE)"
    return msg


@contextmanager
def _packages(path: Path, search_paths, missing: list):
    """xacro's ``$(find PKG)`` looks in the search folders and the file's own folders first;
    a package found nowhere is appended to ``missing``."""
    import xacro.substitution_args as sa

    original = sa._eval_find

    def find(pkg: str) -> str:
        for d in [Path(s) for s in search_paths]:
            if (d / pkg).is_dir():
                return str(d / pkg)
            if d.name == pkg and d.is_dir():
                return str(d)
        for parent in path.parents:
            if parent.name == pkg or _package_name(parent) == pkg:
                return str(parent)
        try:
            return original(pkg)
        except Exception:  # noqa: BLE001 - no ROS (ament_index_python missing) or not indexed
            missing.append(pkg)
            raise

    sa._eval_find = find
    try:
        yield
    finally:
        sa._eval_find = original


@contextmanager
def _checked_open(xacro):
    """xacro's own file reads (the file, its includes, ``load_yaml``) by the input-file rule: its
    module's ``open`` reads a file whole through :func:`read_robot_bytes` (a missing file keeps
    xacro's own error, for ``optional`` includes)."""
    import builtins
    import io

    def checked(file, mode="r", *args, **kwargs):
        if "r" not in mode or "+" in mode or not os.path.lexists(file):
            return builtins.open(file, mode, *args, **kwargs)
        return io.BytesIO(read_robot_bytes(file, "file xacro reads"))   # XML and YAML parsers read bytes

    xacro.open = checked
    try:
        yield
    finally:
        del xacro.open


def _package_name(folder: Path) -> str | None:
    """The ``<name>`` of the ROS ``package.xml`` in ``folder``, or None."""
    manifest = folder / "package.xml"
    if not os.path.lexists(manifest):
        return None
    try:
        m = re.search(rb"<name>\s*([^<\s]+)\s*</name>", read_robot_bytes(manifest, "package.xml")[:65536])
    except RobotFileError:
        return None
    return m.group(1).decode("utf-8", "replace") if m else None
