"""Turn the SOURCES of a batch (files, folders, globs, manifests) into a list of jobs.

A job is one mesh file with its own options: density, mass and units.  Manifests (``.csv``,
``.parquet``) have a ``path`` column and optional ``density``, ``mass`` and ``units``
columns, and relative paths are read relative to the manifest's folder.  Folders are
searched recursively for the mesh extensions that :func:`inertia.load_mesh` reads.
"""

from __future__ import annotations

import glob
import io
import math
import os
import stat
from dataclasses import dataclass, field
from pathlib import Path

from .._core.errors import InputError
from .._core.files import MAX_MESH_FILE_BYTES, read_regular
from ..geometry.mesh_io import SUPPORTED_EXTENSIONS, UNITS

MANIFEST_EXTENSIONS = (".csv", ".parquet")


@dataclass(frozen=True)
class Job:
    """One file to process. ``density`` [kg/m^3] or ``mass`` [kg] (not both); ``units`` of the file.

    ``size``: its size in bytes when collected (a hint for balancing the work; not part of
    the job's identity).
    """

    path: str
    density: float | None = None
    mass: float | None = None
    units: str = "m"
    size: int | None = field(default=None, compare=False, repr=False)


def _is_glob(text: str) -> bool:
    return any(ch in text for ch in "*?[")


def _mesh_files_under(folder) -> list[tuple[str, int | None]]:
    """(path, size) of every mesh file under ``folder``, sorted, recursively (one scandir per folder).

    Every path found with a mesh extension is a job, also when it cannot be read (a dangling
    or looping symlink, no permission): its row then names the error.  A subfolder that
    cannot be listed is an error here, naming it (its files would silently be missing).
    """
    out = []
    stack = [os.fspath(folder)]
    while stack:
        top = stack.pop()
        try:
            entries = sorted(os.scandir(top), key=lambda e: e.name)
        except OSError as exc:
            raise InputError(f"{top}: cannot list this folder ({exc.strerror or exc}); "
                             "its mesh files would be missing from the table") from None
        subdirs = []
        for entry in entries:
            try:
                if entry.is_dir(follow_symlinks=False):  # as os.walk: do not follow linked folders
                    subdirs.append(entry.path)
                    continue
            except OSError:
                pass
            if os.path.splitext(entry.name)[1].lower() not in SUPPORTED_EXTENSIONS:
                continue
            try:
                if entry.is_dir():  # a linked folder named like a mesh: not a file
                    continue
                size = entry.stat().st_size
            except OSError:  # looping or dangling link: a row that says so
                size = None
            out.append((entry.path, size))
        stack.extend(reversed(subdirs))
    return out


def _optional_float(value, column: str, where: str):
    if value is None:
        return None
    try:
        x = float(value)
    except (TypeError, ValueError):
        if str(value).strip() == "":
            return None
        raise InputError(f"{where}: column {column!r} must be a number, got {value!r}") from None
    if math.isnan(x):
        return None
    if not (math.isfinite(x) and x > 0):
        raise InputError(f"{where}: column {column!r} must be finite and positive, got {value!r}")
    return x


def read_manifest(path, *, default: Job) -> list[Job]:
    """Jobs listed in a CSV or Parquet manifest (see the module docstring)."""
    import pandas as pd

    path = Path(path)
    data = io.BytesIO(read_regular(path, what="manifest", limit=MAX_MESH_FILE_BYTES, error=InputError))
    try:
        table = pd.read_parquet(data) if path.suffix.lower() == ".parquet" else pd.read_csv(data, dtype=object)
    except Exception as exc:  # pandas/pyarrow raise many types on malformed files
        raise InputError(f"{path}: cannot read manifest ({type(exc).__name__}: {exc})") from None
    if "path" not in table.columns:
        raise InputError(f"{path}: manifest needs a 'path' column (has: {', '.join(map(str, table.columns))})")
    jobs = []
    base = path.parent
    for i, row in enumerate(table.to_dict("records")):
        where = f"{path}, row {i + 2 if path.suffix.lower() == '.csv' else i}"
        p = row.get("path")
        if p is None or (isinstance(p, float) and math.isnan(p)) or str(p).strip() == "":
            raise InputError(f"{where}: empty path")
        p = Path(str(p))
        if not p.is_absolute():
            p = base / p
        density = _optional_float(row.get("density"), "density", where)
        mass = _optional_float(row.get("mass"), "mass", where)
        if density is not None and mass is not None:
            raise InputError(f"{where}: give density or mass, not both")
        units = row.get("units")
        units = default.units if units is None or (isinstance(units, float) and math.isnan(units)) else str(units)
        if units not in UNITS:
            raise InputError(f"{where}: unknown units {units!r}; use one of {', '.join(UNITS)}")
        if density is None and mass is None:
            density, mass = default.density, default.mass
        jobs.append(Job(str(p), density, mass, units))
    return jobs


def collect_jobs(sources, *, density=None, mass=None, units: str = "m") -> list[Job]:
    """Jobs for every SOURCE, in order, without duplicates (first mention wins).

    Each source is a file, a folder (recursive), a glob pattern or a manifest.  A source
    that names nothing (missing path, glob without matches, empty folder) is an
    :class:`InputError`: a typo should not pass as an empty dataset.  A named mesh file that
    turns out unreadable (or not a file: a FIFO, a device) is not an error here; it becomes an
    error row when processed.
    """
    if units not in UNITS:
        raise InputError(f"unknown units {units!r}; use one of {', '.join(UNITS)}")
    if density is not None and mass is not None:
        raise InputError("give --density or --mass, not both")
    default = Job("", density, mass, units)
    if isinstance(sources, (str, os.PathLike)):
        sources = [sources]
    jobs: list[Job] = []
    seen: set[str] = set()

    def add(job: Job, size: int | None = None, key: str | None = None) -> None:
        key = key or os.path.abspath(job.path)   # key given: the path is absolute and normal already
        if key not in seen:
            seen.add(key)
            jobs.append(Job(key, job.density, job.mass, job.units, size))

    for src in sources:
        text = os.fspath(src)
        try:
            mode_size = os.stat(text)
            mode, size = mode_size.st_mode, mode_size.st_size
        except OSError:   # a dangling or looping link is something (its row says what), not a typo
            mode, size = (stat.S_IFLNK if os.path.lexists(text) else 0), None
        if stat.S_ISDIR(mode):
            found = _mesh_files_under(os.path.abspath(text))   # names joined to a normal path stay normal
            if not found:
                raise InputError(f"{text}: folder holds no mesh files ({', '.join(SUPPORTED_EXTENSIONS)})")
            for f, fsize in found:
                add(default, fsize, f)
        elif mode and os.path.splitext(text)[1].lower() in MANIFEST_EXTENSIONS:
            for job in read_manifest(Path(text), default=default):   # a FIFO, a device...: refused by name
                add(job)
        elif mode:   # a file, or what is not one (a FIFO, a device, a link to nothing): its row says which
            add(Job(text, density, mass, units), size if stat.S_ISREG(mode) else None)
        elif _is_glob(text):
            matches = sorted(glob.glob(text, recursive=True))
            files = [m for m in matches if not os.path.isdir(m)]
            if not files:
                raise InputError(f"{text}: pattern matches no files")
            for f in files:
                add(Job(f, density, mass, units))
        else:
            raise InputError(f"{text}: no such file or folder")
    return jobs
