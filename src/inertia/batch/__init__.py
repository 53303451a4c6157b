"""Mass properties of whole mesh collections, locally or on a Dask cluster.

``inertia batch SOURCES... -o results.parquet`` on the command line; in Python
:func:`run_batch` (writes the table, resumable), :func:`mass_properties_table` (a pandas
DataFrame) and :func:`mass_properties_dask` (a lazy Dask DataFrame).  Dask, pandas and
pyarrow are imported only when used (``pip install "inertia[batch]"``).
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

_EXPORTS = {
    "run_batch": "run", "BatchSummary": "run",
    "mass_properties_table": "api", "mass_properties_dask": "api",
    "collect_jobs": "sources", "Job": "sources",
    "process_file": "record", "COLUMNS": "record",
    "read_frame": "output",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ())
