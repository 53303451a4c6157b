"""Python API of the batch: the table as a pandas DataFrame, or lazily as a Dask DataFrame."""

from __future__ import annotations

from .._core.optional import require
from .output import to_frame
from .record import COLUMNS, process_chunk
from .run import execute
from .sources import Job, collect_jobs


def _jobs_from(sources, density, mass, units):
    if isinstance(sources, (list, tuple)) and sources and all(isinstance(j, Job) for j in sources):
        return list(sources)
    return collect_jobs(list(sources) if not isinstance(sources, (str, bytes)) else [sources],
                        density=density, mass=mass, units=units)


def mass_properties_table(sources, *, density=None, mass=None, units: str = "m", kind: str = "solid",
                          on_defect: str = "raise", repair: str | None = None, robust_tol: float = 1e-3,
                          robust_budget: float | None = None, self_crossing: str = "search",
                          scheduler="synchronous", n_workers: int | None = None, chunk_files: int | None = None):
    """One row per mesh file (columns: :data:`inertia.batch.record.COLUMNS`) as a pandas DataFrame.

    ``sources``: paths, folders, globs or manifests (as ``inertia batch``), or a list of
    :class:`Job`.  ``scheduler``: ``"synchronous"`` (default, this process), ``"threads"``
    (a thread per core here: see :mod:`inertia.batch.run`), ``"cluster"`` (a local Dask
    cluster), a ``"tcp://..."`` address or a ``distributed.Client``.  The mesh options are
    those of :func:`inertia.mesh_properties`.  Bad files are rows with ``status == "error"``
    and a ``reason``; nothing is written to disk.
    """
    from ..massprops.mesh import check_options

    require("pandas", "a mass-properties table")
    check_options(kind, on_defect, repair, self_crossing)
    jobs = _jobs_from(sources, density, mass, units)
    options = {"kind": kind, "on_defect": on_defect, "repair": repair, "robust_tol": robust_tol,
               "robust_budget": robust_budget, "self_crossing": self_crossing}
    rows = execute(jobs, options=options, scheduler=scheduler, n_workers=n_workers, chunk_files=chunk_files)
    return to_frame(rows)


def mass_properties_dask(sources, *, density=None, mass=None, units: str = "m", kind: str = "solid",
                         on_defect: str = "raise", repair: str | None = None, robust_tol: float = 1e-3,
                         robust_budget: float | None = None, self_crossing: str = "search",
                         files_per_partition: int = 16):
    """The same table as a lazy ``dask.dataframe.DataFrame`` (for results larger than memory).

    ``sources`` may also be a ``dask.bag.Bag`` of paths or a Dask DataFrame with a ``path``
    column (and optional ``density``, ``mass``, ``units``).  Nothing runs until you compute
    or write it (e.g. ``.to_parquet(folder)``), on whatever scheduler is active.
    """
    db = require("dask.bag", "a lazy Dask table")
    dd = require("dask.dataframe", "a lazy Dask table")

    from ..massprops.mesh import check_options

    check_options(kind, on_defect, repair, self_crossing)
    options = {"kind": kind, "on_defect": on_defect, "repair": repair, "robust_tol": robust_tol,
               "robust_budget": robust_budget, "self_crossing": self_crossing}
    default = Job("", density, mass, units)
    if isinstance(sources, dd.DataFrame):
        bag = sources.to_bag(format="dict").map(lambda rec: _job_from_record(rec, default))
    elif isinstance(sources, db.Bag):
        bag = sources.map(lambda p: Job(str(p), density, mass, units))
    else:
        jobs = _jobs_from(sources, density, mass, units)
        bag = db.from_sequence(jobs, partition_size=files_per_partition)
    rows = bag.map_partitions(lambda part: process_chunk(list(part), options))
    meta = to_frame([])
    return rows.to_dataframe(meta=meta[list(COLUMNS)])


def _job_from_record(rec: dict, default: Job) -> Job:
    import math

    def num(key):
        v = rec.get(key)
        return None if v is None or (isinstance(v, float) and math.isnan(v)) else float(v)

    density, mass = num("density"), num("mass")
    if density is None and mass is None:
        density, mass = default.density, default.mass
    units = rec.get("units")
    units = default.units if units is None or (isinstance(units, float) and math.isnan(units)) else str(units)
    return Job(str(rec["path"]), density, mass, units)
