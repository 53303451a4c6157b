"""Mass properties of whole mesh collections, locally or on a Dask cluster.

``inertia batch SOURCES... -o results.parquet`` on the command line; in Python
:func:`run_batch` (writes the table, resumable), :func:`mass_properties_table` (a pandas
DataFrame) and :func:`mass_properties_dask` (a lazy Dask DataFrame).  Dask, pandas and
pyarrow are imported only when used (``pip install "inertia[batch]"``).
"""

from __future__ import annotations

import importlib

_EXPORTS = {
    "run_batch": "run", "BatchSummary": "run", "make_chunks": "run",
    "mass_properties_table": "api", "mass_properties_dask": "api",
    "collect_jobs": "sources", "Job": "sources",
    "process_file": "record", "COLUMNS": "record", "COLUMN_DOCS": "record", "DEFAULT_DENSITY": "record",
    "read_frame": "output",
}

__all__ = sorted(_EXPORTS)


def __getattr__(name: str):
    mod = _EXPORTS.get(name)
    if mod is None:
        raise AttributeError(f"module 'inertia.batch' has no attribute {name!r}")
    value = getattr(importlib.import_module(f"{__name__}.{mod}"), name)
    globals()[name] = value
    return value


def __dir__():
    return __all__
