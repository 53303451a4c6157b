"""One row of the batch table per mesh file: its mass properties, or the named reason it failed.

Rows are plain dicts of JSON-able values (lists, not arrays), so they cross process
boundaries cheaply and go to Parquet, CSV or JSON Lines unchanged.  The numbers are those of
:func:`inertia.mesh_file_properties` with the same options, computed by the same functions.
"""

from __future__ import annotations

import functools
import os
import sys
import time
import warnings

from .._core.units import DEFAULT_DENSITY
from .sources import Job

#: the columns of the table, in order
COLUMNS = ("path", "size_bytes", "mtime_ns", "status", "reason", "message", "findings", "units", "density",
           "mass", "volume", "com", "inertia_com", "principal_moments", "R_body_principal", "n_vertices",
           "n_faces", "watertight", "winding_consistent", "elapsed_s", "options")

#: what each column holds (docs and --help)
COLUMN_DOCS = {
    "path": "absolute path of the mesh file",
    "size_bytes": "file size when read (with mtime_ns and path: the resume key)",
    "mtime_ns": "file modification time, ns since the epoch",
    "status": "ok | warning (result valid, see findings) | error (no result; see reason)",
    "reason": "error code (a key of inertia.errors.CODES): not_found, unreadable, malformed, empty, "
              "unsupported_format, non_finite, out_of_range, bad_index, open_edges, non_manifold_edges, "
              "inconsistent_winding, inverted, overlapping_shells, non_positive_volume, zero_area, not_orientable, "
              "invalid_mesh, invalid_input, invalid_inertia, missing_dependency, internal_error, "
              "crashed (the file's worker process was lost)",
    "message": "the full error message (empty when ok)",
    "findings": "list of findings {code, severity, message, where, values (JSON text)}: notes, accepted defects, "
                "the robust solid's bounds; for an error row, the defects behind it",
    "units": "length unit the file was read in",
    "density": "kg/m^3 used (mean density when mass was given)",
    "mass": "kg",
    "volume": "m^3",
    "com": "center of mass [x, y, z], m, file axes",
    "inertia_com": "inertia about the COM, 9 values row-major, kg m^2, negated products (L = I w)",
    "principal_moments": "ascending, kg m^2",
    "R_body_principal": "the principal axes, 9 values row-major (columns are the axes, det +1)",
    "n_vertices": "after merging duplicate vertices",
    "n_faces": "triangles",
    "watertight": "every edge used by exactly two faces",
    "winding_consistent": "shared edges traversed in opposite directions",
    "elapsed_s": "seconds to read and process the file",
    "options": "every option that shapes the row (units, density or mass as given, kind, on_defect, repair, "
               "robust_tol, self_crossing, inertia version); with path, size_bytes and mtime_ns: the resume key",
}

#: the options of a batch row: those of :func:`inertia.mesh_properties`
DEFAULT_OPTIONS = {"kind": "solid", "on_defect": "raise", "repair": None, "robust_tol": 1e-3, "robust_budget": None,
                   "self_crossing": "search"}


def options_key(job: Job, **options) -> str:
    """The ``options`` column: ``name=value`` pairs of everything that changes a row.

    A resumed run keeps an earlier row only when this key is the same (a run in other
    units, density, ... must not keep stale rows).
    """
    def num(x):
        return None if x is None else float(x)

    o = {**DEFAULT_OPTIONS, **options}
    robust = o["on_defect"] == "robust"
    return _options_text(str(job.units), num(job.density), num(job.mass), o["kind"], o["on_defect"], o["repair"],
                         float(o["robust_tol"]) if robust else None, o["self_crossing"])


@functools.lru_cache(maxsize=256)
def _options_text(units, density, mass, kind, on_defect, repair, robust_tol, self_crossing) -> str:
    """:func:`options_key`'s text (the same for every file of a run: made once)."""
    from .._core.version import __version__

    def num(x):
        return "" if x is None else repr(x)

    return (f"units={units} density={num(density)} mass={num(mass)} kind={kind} on_defect={on_defect} "
            f"repair={repair or ''} " + (f"robust_tol={robust_tol!r} " if robust_tol is not None else "")
            + f"self_crossing={self_crossing} version={__version__}")


def finding_cells(findings) -> list:
    """Findings as the table holds them: dicts of strings, ``values`` as JSON text."""
    import json

    out = []
    for f in findings:
        d = f.to_dict()
        d["values"] = json.dumps(d["values"])
        out.append(d)
    return out


def _empty_row(job: Job) -> dict:
    row = dict.fromkeys(COLUMNS)
    row.update(path=job.path, units=job.units, findings=[], reason="", message="")
    try:
        st = os.stat(job.path)
        row.update(size_bytes=int(st.st_size), mtime_ns=int(st.st_mtime_ns))
    except OSError:
        pass
    return row


def _with_flags(message: str) -> str:
    """A refusal's advice for both ways in: each keyword followed by the ``inertia batch`` option that
    does the same (``on_defect='warn'`` -> ``on_defect='warn' (--accept-defects)``)."""
    from ..massprops.mesh import REMEDY_FLAGS

    for api, cli in REMEDY_FLAGS.items():
        message = message.replace(api, f"{api} ({cli})")
    return message


def _reason_of(exc) -> str:
    """The row's ``reason``: the stable ``code`` of one of our errors (never its message text)."""
    from .._core.errors import InertiaError

    return exc.code if isinstance(exc, InertiaError) else "internal_error"


def _reraise_interrupt(exc: BaseException) -> None:
    """Raise the KeyboardInterrupt (or SystemExit) that ``exc`` was caused by, if any.

    A Ctrl-C that lands while an extension returns surfaces as ``SystemError: ... returned a
    result with an exception set``, caused by the KeyboardInterrupt: it must stop the run, not
    become an error row for a good file.
    """
    seen, cur = set(), exc
    while cur is not None and id(cur) not in seen:
        seen.add(id(cur))
        if isinstance(cur, (KeyboardInterrupt, SystemExit)):
            raise cur
        cur = cur.__cause__ or cur.__context__


def process_file(job: Job, **options) -> dict:
    """The row for one job (``options``: those of :func:`inertia.mesh_properties`, see
    :data:`DEFAULT_OPTIONS`).  Never raises for a bad file: the row says what went wrong."""
    from .._core.errors import InertiaError
    from ..geometry.mesh_io import load_mesh
    from ..geometry.report import watertight, winding_consistent
    from ..massprops.mesh import mesh_properties

    t0 = time.perf_counter()
    row = _empty_row(job)
    row["options"] = options_key(job, **options)
    density, mass = job.density, job.mass
    if density is None and mass is None:
        density = DEFAULT_DENSITY
    try:
        vertices, faces = load_mesh(job.path, units=job.units)
        row.update(n_vertices=int(len(vertices)), n_faces=int(len(faces)))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # accepted defects are recorded in props.findings
            props = mesh_properties(vertices, faces, density=density, mass=mass, name=job.path,
                                    **{**DEFAULT_OPTIONS, **options})
        pf = props.principal()
        codes = {f.code for f in props.findings}
        row.update(
            status="warning" if props.findings else "ok",
            findings=finding_cells(props.findings),
            density=float(density) if density is not None else float(props.mass / props.volume),
            mass=float(props.mass), volume=float(props.volume),
            com=props.com.tolist(), inertia_com=props.inertia_com.ravel().tolist(),
            principal_moments=pf.moments.tolist(), R_body_principal=pf.R_body_principal.ravel().tolist(),
            watertight=watertight(codes), winding_consistent=winding_consistent(codes),
        )
    except InertiaError as exc:
        _reraise_interrupt(exc)
        report = getattr(exc, "report", None)
        if report is not None:
            row.update(watertight=report.watertight, winding_consistent=report.winding_consistent,
                       n_faces=int(report.n_faces))
        row.update(status="error", reason=_reason_of(exc), message=_with_flags(str(exc)),
                   findings=finding_cells(exc.findings))
    except Exception as exc:  # noqa: BLE001 - one bad file must not stop a dataset run
        _reraise_interrupt(exc)
        row.update(status="error", reason="internal_error", message=f"{type(exc).__name__}: {exc}")
    row["elapsed_s"] = time.perf_counter() - t0
    return row


def crashed_row(job: Job, error=None, options: dict | None = None) -> dict:
    """The row of a file whose processing was lost with its worker process (``reason="crashed"``)."""
    row = _empty_row(job)
    row["options"] = options_key(job, **(options or {}))
    what = f" ({type(error).__name__}: {error})" if error is not None else ""
    row.update(status="error", reason="crashed",
               message=f"{job.path}: processing this file ended its worker process{what}; "
                       "no result (please report the file)")
    return row


def process_chunk(jobs, options: dict) -> list[dict]:
    """Rows for a list of jobs (the unit of work sent to a Dask worker)."""
    return [process_file(job, **options) for job in jobs]


#: glibc's mallopt settings of a process that runs files: freed memory up to this much is kept
#: for the next file (M_TRIM_THRESHOLD; M_TOP_PAD grows the heap in 16 MiB steps) and blocks
#: below 32 MiB come from the heap (M_MMAP_THRESHOLD), instead of each file's arrays being
#: mapped, returned and faulted in again (Dask's workers return memory past 64 KiB).
KEPT_FREE_BYTES = 128 * 2**20


@functools.cache   # once per process (a forked child inherits the settings with the cache)
def keep_freed_memory() -> None:
    """On Linux with glibc, once per process: keep freed memory for the next file (see
    :data:`KEPT_FREE_BYTES`; a worker process then holds at most that much beyond its live
    arrays).  Page faults take a lock per process, which serialises threads; on an external
    Dask cluster of 2 single-thread workers, 2,000 small STL ran 1.3x faster (bench/batch.py)."""
    if not sys.platform.startswith("linux"):
        return
    try:
        import ctypes

        mallopt = ctypes.CDLL("libc.so.6").mallopt
        mallopt(-1, KEPT_FREE_BYTES)   # M_TRIM_THRESHOLD
        mallopt(-2, 16 * 2**20)        # M_TOP_PAD
        mallopt(-3, 32 * 2**20)        # M_MMAP_THRESHOLD
    except (OSError, AttributeError):   # not glibc
        pass


def process_packed(payload: bytes) -> bytes:
    """:func:`process_chunk` with its arguments and its rows pickled into one bytes object each.

    This is the Dask task.  Dask moves a bytes object as one opaque frame, while it inspects
    a list of dicts element by element, at a cost in worker CPU per task.
    """
    import pickle

    keep_freed_memory()
    jobs, options = pickle.loads(payload)
    return pickle.dumps(process_chunk(jobs, options), protocol=pickle.HIGHEST_PROTOCOL)

