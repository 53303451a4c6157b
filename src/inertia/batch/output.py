"""Tables of batch rows: pandas frames, part files, and the final Parquet / CSV / JSON Lines file.

Every file is written atomically (temporary file in the same folder, then ``os.replace``),
so an interrupted run leaves only whole part files behind.
"""

from __future__ import annotations

import json
import operator
import os
from pathlib import Path

from .._core.atomic import temp_beside
from .._core.errors import InputError
from .record import COLUMNS

FORMATS = ("parquet", "csv", "jsonl")
_LIST_COLUMNS = ("findings", "com", "inertia_com", "principal_moments", "R_body_principal")
#: the fields of a finding in the table (all text; ``values`` is JSON)
FINDING_FIELDS = ("code", "severity", "message", "where", "values")


def format_of(path, fmt: str | None = None) -> str:
    """The output format: ``fmt`` if given, else from the file extension (default parquet)."""
    if fmt is not None:
        if fmt not in FORMATS:
            raise InputError(f"unknown format {fmt!r}; use one of {', '.join(FORMATS)}")
        return fmt
    ext = Path(path).suffix.lower().lstrip(".")
    formats = {"parquet": "parquet", "pq": "parquet", "csv": "csv", "jsonl": "jsonl", "ndjson": "jsonl"}
    return formats.get(ext, "parquet")


_INT_COLUMNS = ("size_bytes", "mtime_ns", "n_vertices", "n_faces")
_FLOAT_COLUMNS = ("density", "mass", "volume", "elapsed_s")
_BOOL_COLUMNS = ("watertight", "winding_consistent")


def to_frame(rows):
    """A pandas DataFrame with the columns of :data:`COLUMNS`, in order."""
    import pandas as pd

    return _typed(pd.DataFrame(list(rows), columns=list(COLUMNS)))


def _typed(frame):
    """The column types of the table: nullable integers and booleans, float64 numbers."""
    for col in _INT_COLUMNS:
        frame[col] = frame[col].astype("Int64")
    for col in _FLOAT_COLUMNS:
        frame[col] = frame[col].astype("float64")
    for col in _BOOL_COLUMNS:
        frame[col] = frame[col].astype("boolean")
    return frame


def arrow_schema():
    import pyarrow as pa

    types = {c: pa.string() for c in COLUMNS}
    types.update({c: pa.int64() for c in _INT_COLUMNS})
    types.update({c: pa.float64() for c in _FLOAT_COLUMNS})
    types.update({c: pa.bool_() for c in _BOOL_COLUMNS})
    types.update({c: pa.list_(pa.float64()) for c in _LIST_COLUMNS})
    types["findings"] = pa.list_(pa.struct([(name, pa.string()) for name in FINDING_FIELDS]))
    return pa.schema([(c, types[c]) for c in COLUMNS])


def _null(v) -> bool:
    """None, NaN or a pandas missing value (plain values are decided without pandas)."""
    if v is None:
        return True
    if isinstance(v, float):
        return v != v
    if isinstance(v, (int, str)):
        return False
    return _isna(v)


def rows_to_table(rows):
    """Batch rows (dicts of plain values) as an Arrow table with the schema of the output.

    Column by column, without building a pandas frame: the part files are written on the
    client while the workers compute, so this must stay cheap.  Plain values go through
    :mod:`.arrow_columns` (NumPy buffers: pandas is never imported).
    """
    import pyarrow as pa

    from .arrow_columns import column

    schema = arrow_schema()
    arrays = []
    names = schema.names
    try:   # rows fresh from the workers hold every column: one pass, transposed
        by_column = list(zip(*map(operator.itemgetter(*names), rows))) if rows else [()] * len(names)
    except KeyError:
        by_column = [[row.get(name) for row in rows] for name in names]
    for field, values in zip(schema, by_column):
        values = list(values)
        built = column(values, field.type)
        if built is not None:
            arrays.append(built)
            continue
        try:  # rows fresh from the workers: plain values, None (or a NaN scalar) for missing
            # (from_pandas turns NaN into null; not for lists, whose NaN elements are values)
            arrays.append(pa.array(values, type=field.type, from_pandas=not pa.types.is_list(field.type)))
            continue
        except (pa.ArrowInvalid, pa.ArrowTypeError, TypeError, ValueError):
            pass  # rows read back from a table (pandas missing values, NumPy arrays)
        if pa.types.is_list(field.type):
            values = [None if v is None or (not isinstance(v, (list, tuple)) and _null(v)) else list(v)
                      for v in values]
        elif not pa.types.is_string(field.type):
            values = [None if _null(v) else v for v in values]
        arrays.append(pa.array(values, type=field.type))
    return pa.Table.from_arrays(arrays, schema=schema)


def write_table_parquet(table, path) -> None:
    """Write an Arrow table to Parquet atomically."""
    import pyarrow.parquet as pq

    path, tmp = _atomic_target(path)
    try:
        pq.write_table(table, tmp)
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def write_rows_parquet(rows, path):
    """Write batch rows straight to Parquet, atomically; returns the Arrow table written."""
    table = rows_to_table(rows)
    write_table_parquet(table, path)
    return table


def _atomic_target(path):
    return os.fspath(path), temp_beside(path)


def write_frame(frame, path, fmt: str) -> None:
    """Write ``frame`` to ``path`` in ``fmt`` atomically."""
    path, tmp = _atomic_target(path)
    try:
        if fmt == "parquet":
            frame.to_parquet(tmp, index=False)
        elif fmt == "csv":
            out = frame.copy()
            for col in _LIST_COLUMNS:
                out[col] = [json.dumps(v) if v is not None and not _isna(v) else "" for v in out[col]]
            out.to_csv(tmp, index=False)
        elif fmt == "jsonl":
            with open(tmp, "w", encoding="utf-8") as fh:
                for rec in frame.to_dict("records"):
                    fh.write(json.dumps({k: _plain(v) for k, v in rec.items()}) + "\n")
        else:
            raise InputError(f"unknown format {fmt!r}")
        os.replace(tmp, path)
    except BaseException:
        if os.path.exists(tmp):
            os.unlink(tmp)
        raise


def _isna(v) -> bool:
    try:
        import pandas as pd

        return bool(pd.isna(v)) if not isinstance(v, (list, tuple)) else False
    except (TypeError, ValueError):
        return False


def _plain(v):
    import numpy as np

    if isinstance(v, np.ndarray):
        return [_plain(x) for x in v.tolist()]
    if isinstance(v, (list, tuple)):
        return [_plain(x) for x in v]
    if isinstance(v, np.generic):
        return v.item()
    if v is None or _isna(v):
        return None
    return v


def table_to_frame(table):
    """An Arrow table of batch rows as the pandas DataFrame :func:`read_frame` gives."""
    frame = table.to_pandas()
    for col in _LIST_COLUMNS:
        frame[col] = [None if v is None else list(v) for v in frame[col]]
    return _typed(frame)


def read_table(path, fmt: str | None = None):
    """Read a table of batch rows (any of the three formats) as an Arrow table of the output schema."""
    fmt = format_of(path, fmt)
    if fmt == "parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        table = pq.read_table(path)
        # a table of an older version lacks the columns added since: they are null
        table = pa.Table.from_arrays([table.column(c) if c in table.column_names else pa.nulls(len(table))
                                      for c in COLUMNS], names=list(COLUMNS))
    else:
        table = rows_to_table(read_frame(path, fmt).to_dict("records"))
    # one schema without metadata (pandas writes its own), so that tables concatenate
    return table.cast(arrow_schema()).replace_schema_metadata(None)


def read_frame(path, fmt: str | None = None):
    """Read a table written by :func:`write_frame` back into the same shape."""
    import pandas as pd

    fmt = format_of(path, fmt)
    if fmt == "parquet":
        import pyarrow.parquet as pq

        return table_to_frame(pq.read_table(path))
    if fmt == "csv":
        frame = pd.read_csv(path, dtype={"reason": str, "message": str}, keep_default_na=False,
                            na_values={c: [""] for c in COLUMNS if c not in ("reason", "message", "path")})
        for col in _LIST_COLUMNS:
            frame[col] = [json.loads(v) if isinstance(v, str) and v else None for v in frame[col]]
        return to_frame(frame.to_dict("records"))
    with open(path, encoding="utf-8") as fh:
        return to_frame([json.loads(line) for line in fh if line.strip()])
