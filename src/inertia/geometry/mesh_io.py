"""Reading triangle meshes from files.

Supported: STL (ASCII and binary, including binary files whose 80-byte header begins with
"solid"), OBJ, PLY, OFF, GLB/GLTF (every mesh of the scene, with its node transform).

Binary STL, the common format of mesh datasets, is read here straight from its bytes (no
dependency; its per-face vertex copies are welded in one compiled pass over the records, with
the same result as the general route).  ASCII STL and OBJ are read by the compiled text
readers of :mod:`._text_readers` and PLY by :mod:`._ply` (no dependency), which name the file,
line and text of anything malformed.  OFF, glTF and COLLADA go through the optional dependency
trimesh, with ``process=False`` (trimesh changes nothing).  Every file, and every file a file
names, is read by the rule of :mod:`inertia._core.files` (a regular file, a size cap).  Text
(STL, OBJ, PLY, OFF, glTF) in UTF-8 with or without a byte-order mark, UTF-16 or UTF-32 is read
alike.  Then vertices closer than :data:`MERGE_RTOL` times the size of the mesh are merged, so
that files which repeat a vertex per face (STL) or per texture/normal seam (OBJ), or repeat it
with float noise such as ``-2.7e-16`` for ``0``, give a connected surface.  Coordinates
are then scaled to metres.
"""

from __future__ import annotations

import io
import os
import re
import warnings
from pathlib import Path

import numpy as np

from .._core.errors import InputError, MeshFileError
from .._core.files import MAX_MESH_FILE_BYTES, open_regular, read_regular
from .._core.optional import require
from .._core.units import LENGTH_UNITS
from .._ext import topology as _k
from .mesh_arrays import faces_in_range, validate_inputs

__all__ = ["load_mesh", "UNITS", "SUPPORTED_EXTENSIONS", "MERGE_RTOL"]

#: Length units accepted by ``units=``: metres per unit.
UNITS = LENGTH_UNITS  # name -> metres (one table: inertia._core.units)

#: File extensions read by :func:`load_mesh` -> trimesh file type.
SUPPORTED_EXTENSIONS = {".stl": "stl", ".obj": "obj", ".ply": "ply", ".off": "off",
                        ".glb": "glb", ".gltf": "gltf", ".dae": "dae"}

#: Vertices closer than MERGE_RTOL * (bounding-box diagonal) are merged on loading (or
#: closer than 64 ulps of the largest coordinate, when that is larger).  Far below the
#: resolution of float32 files (6e-8 relative), far above double rounding noise (1e-16
#: relative): on the shared test meshes distinct vertices are >= 2e-7 apart relative to
#: the diagonal and split copies <= 1e-16.
MERGE_RTOL = 1e-10

#: how :func:`load_mesh` makes triangles of OBJ polygons
POLYGONS = ("fan", "shorter", "mujoco")


def _import_trimesh():
    """Import trimesh, or raise MissingDependencyError saying how to install it."""
    return require("trimesh", "reading mesh files")


def _unit_factor(units) -> float:
    try:
        return UNITS[units]
    except (KeyError, TypeError):
        raise InputError(f"unknown length unit {units!r}; valid units: {', '.join(UNITS)}") from None


def _merge_close_vertices(vertices: np.ndarray, faces: np.ndarray, rtol: float):
    """Merge vertices within ``rtol`` of the mesh size; drop unreferenced ones.

    Exactly equal vertices are welded first; the rest is found among pairs within the
    tolerance (``rtol`` x the bounding-box diagonal, or 64 ulps of the largest coordinate when
    larger, capped at a quarter of the short face edges), joined transitively.  Each group
    takes the coordinates of its lowest-index member.  One compiled call (hash-table weld,
    grid-hash merge); a k-d tree where the grid cannot number its cells (a tolerance below
    1e-20 of the coordinates).
    """
    v, f = validate_inputs(vertices, faces)
    if not faces_in_range(f, len(v)):
        raise InputError(f"faces index vertices outside 0..{len(v) - 1}", code="bad_index")
    if len(f) == 0:
        return v[:0], f
    v, f, pending = _k.weld_and_merge(v, f, float(rtol))
    return _merge_on_tree(v, f, pending) if pending > 0 else (v, f)


def _merge_on_tree(v: np.ndarray, f: np.ndarray, tol: float):
    """Merge the welded ``v, f`` within ``tol`` with a k-d tree (the grid's cells cannot be numbered)."""
    from scipy.spatial import cKDTree

    from .mesh_arrays import compact_vertices, connected_components

    if not float(np.abs(v).max()) / tol < 1e150:
        return v, f   # the tree's squared distances would overflow (the checks refuse such coordinates)
    if np.isfinite(tol * tol) and tol * tol > 0:
        pairs = cKDTree(v).query_pairs(tol, output_type="ndarray")
    else:  # tol^2 would overflow (or underflow) inside the tree: measure in units of tol
        pairs = cKDTree(v / tol).query_pairs(1.0, output_type="ndarray")
    if len(pairs) == 0:
        return v, f
    _, label = connected_components(len(v), pairs[:, 0], pairs[:, 1])
    lowest = np.unique(label, return_index=True)[1]      # each component's lowest vertex stands for it
    return compact_vertices(v, lowest[label][f])


def _scene_triangles(trimesh, loaded, path: Path):
    """(vertices, faces) of a Trimesh, or of every Trimesh of a Scene with node transforms applied."""
    if isinstance(loaded, trimesh.Trimesh):
        return np.asarray(loaded.vertices, dtype=np.float64), np.asarray(loaded.faces, dtype=np.int64)
    if not isinstance(loaded, trimesh.Scene):
        raise MeshFileError(f"{path}: holds no triangle mesh (trimesh read a {type(loaded).__name__})", code="empty")
    vs, fs, offset = [], [], 0
    for node in loaded.graph.nodes_geometry:
        T_scene_node, geom_name = loaded.graph[node]
        geom = loaded.geometry.get(geom_name)
        if not isinstance(geom, trimesh.Trimesh) or len(geom.faces) == 0:
            continue  # paths, point clouds: no triangles
        v = np.asarray(geom.vertices, dtype=np.float64)
        f = np.asarray(geom.faces, dtype=np.int64)
        T = np.asarray(T_scene_node, dtype=np.float64)
        v = v @ T[:3, :3].T + T[:3, 3]
        if np.linalg.det(T[:3, :3]) < 0:
            f = f[:, [0, 2, 1]]  # a mirroring transform turns the winding inside out: undo it
        vs.append(v)
        fs.append(f + offset)
        offset += len(v)
    if not fs:
        return np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    return np.concatenate(vs), np.concatenate(fs)


def stl_kind(p: Path) -> int:
    """The triangle count of a binary STL, or -1 for an ASCII STL; MeshFileError for neither.

    A binary STL is an 80-byte header, a uint32 triangle count N and 50 bytes per triangle,
    so its size is exactly 84 + 50 N.  A file of another size must be ASCII (``solid`` ...
    ``facet``); the header alone cannot tell, since binary headers may also start with "solid".
    A truncated (or padded) binary STL is refused by name instead of read as garbage.
    """
    fd, size = open_regular(p, what="mesh file", limit=MAX_MESH_FILE_BYTES, error=MeshFileError)
    with os.fdopen(fd, "rb") as fh:
        head = fh.read(1024)
    return _stl_kind_of(head, size, p)


def _stl_kind_of(head: bytes, size: int, p) -> int:
    """:func:`stl_kind` from the file's first 1024 bytes and its size (``p`` names it in errors)."""
    from ._text_readers import utf8_head

    if size == 0:
        raise MeshFileError(f"{p}: mesh file holds no triangles (empty file)", code="empty")
    text = utf8_head(head).lstrip().lower()
    ascii_like = text.startswith(b"solid") and (b"facet" in text or b"endsolid" in text or size < 1024)
    if size >= 84:
        n = int.from_bytes(head[80:84], "little")
        if 84 + 50 * n == size and not (ascii_like and text.isascii()):
            return n
    if ascii_like:
        return -1
    if size >= 84:
        n = int.from_bytes(head[80:84], "little")
        raise MeshFileError(f"{p}: malformed binary STL: its header announces {n} triangles "
                            f"({84 + 50 * n} bytes) but the file has {size} bytes (truncated or corrupt), "
                            "and it is not ASCII STL either", code="malformed")
    raise MeshFileError(f"{p}: malformed STL: {size} bytes is too short for binary STL and it is not ASCII STL",
                        code="malformed")


def _read_binary_stl_merged(p: Path, n: int, merge_rtol: float, data: np.ndarray):
    """The ``n`` triangles of a binary STL (``data``: the file's bytes, uint8), welded and merged
    as :func:`_merge_close_vertices` merges the soup of their corners (float32 read exactly as
    float64), in one compiled pass over the file's records, without building that soup."""
    if len(data) != 84 + 50 * n:
        raise MeshFileError(f"{p}: malformed binary STL: the file changed size while being read", code="malformed")
    vertices, faces, pending = _k.stl_weld_and_merge(data, n, float(merge_rtol))
    return _merge_on_tree(vertices, faces, pending) if pending > 0 else (vertices, faces)


_COLLADA_UNIT = re.compile(rb"""<unit\b[^>]*?\bmeter\s*=\s*["']([^"']+)["']""")


def _collada_unit(data: bytes, p: Path) -> float:
    """Metres per unit of a COLLADA file (its bytes ``data``): its ``<asset><unit meter=...>`` (1 when absent)."""
    head = data[:65536]
    end = head.find(b"</asset>")
    m = _COLLADA_UNIT.search(head, 0, end if end >= 0 else len(head))
    if m is None:
        return 1.0
    try:
        meter = float(m.group(1))
    except ValueError:
        meter = float("nan")
    if not (meter > 0 and meter < float("inf")):
        raise MeshFileError(f"{p}: COLLADA <unit meter={m.group(1).decode('ascii', 'replace')!r}> is not a positive "
                            "number", code="malformed")
    return meter


def load_mesh(path, *, units: str = "m", merge_rtol: float = MERGE_RTOL,
              polygons: str = "fan") -> tuple[np.ndarray, np.ndarray]:
    """Read a triangle mesh file into arrays, in metres.

    Parameters
    ----------
    path : str or os.PathLike, a .stl, .obj, .ply, .off, .glb, .gltf or .dae (COLLADA) file;
        COLLADA coordinates are scaled by the file's ``<unit meter>`` (as Gazebo and RViz do),
        then by ``units``.
    units : str, the length unit of the file's coordinates: one of ``UNITS``
        ("m", "cm", "mm", "um", "in", "ft").
    merge_rtol : float, vertices closer than ``merge_rtol`` x the mesh size are merged
        (0: merge exactly equal vertices only).
    polygons : {"fan", "shorter", "mujoco"}, how an OBJ polygon becomes triangles: fanned from
        its first vertex (as trimesh does, the default; exact for a planar polygon), the same
        with quads split along their shorter diagonal, or as MuJoCo reads the file (its
        tinyobjloader: quads along the shorter diagonal, 5 to 100 vertices by its ear clipping,
        larger faces dropped, the first ``o``/``g`` group with triangles only, and the file's
        vertices as they are: none merged or dropped).

    Returns
    -------
    vertices : (V, 3) float64, m, unreferenced vertices dropped.
    faces : (F, 3) int64, vertex indices with the file's winding.

    Raises
    ------
    MeshFileError
        Missing file, unknown extension, unreadable or malformed content, no triangles.
    InputError
        Unknown ``units``.
    MissingDependencyError
        an OFF, glTF or COLLADA file and trimesh is not installed (``pip install "inertia[mesh]"``).
    """
    factor = _unit_factor(units)
    if polygons not in POLYGONS:
        raise InputError(f"polygons must be one of {', '.join(map(repr, POLYGONS))}, got {polygons!r}")
    p = Path(path)
    try:
        return _load_mesh(p, factor, merge_rtol, polygons)
    except MemoryError:
        size = _file_size(p)
        raise MeshFileError(f"{p}: too large to read in the memory available ({size / 2**30:.2g} GiB file; "
                            "reading needs a few times its size)", code="too_large") from None


def _file_size(p: Path) -> float:
    try:
        return float(p.stat().st_size)
    except OSError:
        return float("nan")


def _load_mesh(p: Path, factor: float, merge_rtol: float, polygons: str = "fan"):
    """:func:`load_mesh` after the units are known (MemoryError is named by the caller)."""
    ext = p.suffix.lower()
    if ext not in SUPPORTED_EXTENSIONS:
        raise MeshFileError(f"{p}: unsupported mesh file extension {ext!r}; supported: "
                            f"{', '.join(SUPPORTED_EXTENSIONS)}", code="unsupported_format")
    data = read_regular(p, what="mesh file", limit=MAX_MESH_FILE_BYTES, error=MeshFileError, map_large=True)
    n_binary = _stl_kind_of(bytes(data[:1024]), len(data), p) if ext == ".stl" else -1
    if n_binary > 0:  # the common case of datasets: read directly (no trimesh needed)
        vertices, faces = _read_binary_stl_merged(p, n_binary, merge_rtol, np.frombuffer(data, np.uint8))
        return (vertices * factor if factor != 1.0 else vertices), faces
    elif n_binary == 0:
        vertices, faces = np.zeros((0, 3)), np.zeros((0, 3), dtype=np.int64)
    elif ext in (".stl", ".obj"):  # ASCII STL and OBJ: compiled text readers
        from ._text_readers import read_text_mesh

        vertices, faces = read_text_mesh(np.frombuffer(data, np.uint8), p, ext, polygons)
    elif ext == ".ply":
        from ._ply import read_ply

        vertices, faces = read_ply(data, p)
    else:
        vertices, faces = _trimesh_arrays(bytes(data), p, ext)
        if ext == ".dae":   # COLLADA coordinates are in its <unit meter>
            factor *= _collada_unit(bytes(data), p)
    for name, arr in (("vertex", vertices), ("face", faces)):
        if np.ndim(arr) != 2 or np.shape(arr)[1] != 3:
            raise MeshFileError(f"{p}: malformed {name} data: the reader returned an array of shape "
                                f"{np.shape(arr)}, not (N, 3)", code="malformed")
    try:  # the final shapes: every check below, and every kernel after, sees these arrays
        vertices, faces = validate_inputs(vertices, faces)
    except InputError as exc:
        raise MeshFileError(f"{p}: malformed mesh data ({exc})", code="malformed") from None
    if len(faces) == 0 or len(vertices) == 0:
        raise MeshFileError(f"{p}: mesh file holds no triangles", code="empty")
    if not faces_in_range(faces, len(vertices)):
        raise MeshFileError(f"{p}: face indices outside 0..{len(vertices) - 1} "
                            f"(min {int(faces.min())}, max {int(faces.max())})", code="malformed")
    if ext != ".obj" or polygons != "mujoco":
        vertices, faces = _merge_close_vertices(vertices, faces, merge_rtol)
    return vertices * factor, faces


def _trimesh_arrays(data: bytes, p: Path, ext: str):
    """(vertices, faces) of an OFF, glTF/GLB or COLLADA file (its bytes ``data``) read by trimesh,
    the files it names (buffers, textures) read by the same rule as the file itself."""
    trimesh = _import_trimesh()
    if ext == ".dae":  # trimesh reads COLLADA through pycollada
        require("collada", "reading COLLADA (.dae) meshes")
    if ext in (".off", ".gltf"):  # text in UTF-16/32 or with Latin-1 bytes: made UTF-8 for trimesh
        from ._text_readers import utf8_for_trimesh

        data = utf8_for_trimesh(data, p, ext)
    try:
        # trimesh's parsers cast and scale without guarding against overflow or NaN; what
        # they return is checked here (shapes, indices) and by the mesh checks (non-finite
        # and out-of-range coordinates), so their NumPy warnings are noise to the caller
        with warnings.catch_warnings(), np.errstate(all="ignore"):
            warnings.simplefilter("ignore", RuntimeWarning)
            loaded = trimesh.load(io.BytesIO(data), file_type=SUPPORTED_EXTENSIONS[ext], process=False,
                                  resolver=_checked_resolver(trimesh, p))
            return _scene_triangles(trimesh, loaded, p)
    except MeshFileError:
        raise
    except Exception as exc:  # trimesh raises many types on malformed files
        raise MeshFileError(f"{p}: cannot read mesh file ({type(exc).__name__}: {exc})") from exc


def _checked_resolver(trimesh, p: Path):
    """trimesh's resolver of the files beside ``p``, each read as :func:`read_regular` reads (no FIFO,
    device or unbounded read)."""
    class Checked(trimesh.resolvers.FilePathResolver):
        def get(self, name):
            what = f"file {name!r} that {p.name} names"
            for candidate in (name.strip(), name.strip().lstrip("/"), os.path.split(name)[-1]):
                path = os.path.join(self.parent, candidate)
                if os.path.lexists(path):   # what is there, by name, before trimesh's rule (nothing outside)
                    data = read_regular(path, what=what, limit=MAX_MESH_FILE_BYTES, error=MeshFileError)
                    self.absolute(candidate)
                    return bytes(data)
            raise MeshFileError(f"{os.path.join(self.parent, name.strip())}: the {what} was not found",
                                code="not_found")

    return Checked(str(p))
