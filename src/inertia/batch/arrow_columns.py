"""Arrow columns from Python values, built from NumPy buffers: without pandas.

``pyarrow.array`` imports pandas on its first call (to ask whether its argument is a pandas
object), a cost in the parent's CPU that the workers need.
These builders take the plain values of batch rows (``None`` for
missing; a float NaN also counts as missing, as ``from_pandas`` did, except inside lists)
and assemble each column with ``pyarrow.Array.from_buffers``.

Each returns None when a value is not of the plain kinds it knows (a pandas missing value,
a NumPy array inside a string column): the caller then takes the general route.
"""

from __future__ import annotations

import itertools

import numpy as np


def _validity(valid):
    """The validity bitmap of a column (None when nothing is missing) and its null count."""
    import pyarrow as pa

    missing = len(valid) - int(np.count_nonzero(valid))
    if missing == 0:
        return None, 0
    return pa.py_buffer(np.packbits(valid, bitorder="little")), missing


def _is_missing(v) -> bool:
    return v is None or (isinstance(v, float) and v != v)


def numbers(values, arrow_type, dtype):
    """An int64 or float64 column (``dtype`` the NumPy type); None for a value of another kind."""
    import pyarrow as pa

    n = len(values)
    fast = _all_plain(values, float if dtype is np.float64 else int, dtype)
    if fast is not None:                  # every value a plain float (or int): one NumPy conversion
        valid = fast == fast              # NaN is missing
        if dtype is np.float64 and not valid.all():
            fast[~valid] = 0.0
        bitmap, nulls = _validity(valid)
        return pa.Array.from_buffers(arrow_type, n, [bitmap, pa.py_buffer(fast)], null_count=nulls)
    data = np.zeros(n, dtype=dtype)
    valid = np.ones(n, dtype=bool)
    kinds = (int, np.integer) if dtype is np.int64 else (int, float, np.integer, np.floating)
    for k, v in enumerate(values):
        if _is_missing(v):
            valid[k] = False
        elif not _number(v, kinds, exact_ints=dtype is not np.int64):
            return None
        else:
            try:
                data[k] = v
            except (OverflowError, ValueError):
                return None
    bitmap, nulls = _validity(valid)
    return pa.Array.from_buffers(arrow_type, n, [bitmap, pa.py_buffer(data)], null_count=nulls)


def _all_plain(values, kind, dtype):
    """``values`` as a NumPy array when every one is exactly of type ``kind`` (``float`` or
    ``int``: not a bool, not a NumPy scalar, not missing) and fits ``dtype``; else None (the
    caller then looks at each value)."""
    if not set(map(type, values)) <= {kind}:
        return None
    try:
        return np.array(values, dtype=dtype)
    except OverflowError:
        return None


def _number(v, kinds, exact_ints: bool) -> bool:
    """``v`` is a number of ``kinds`` (never a bool); with ``exact_ints``, an integer only
    if a float64 holds it exactly (pyarrow refuses the others rather than round them)."""
    if isinstance(v, (bool, np.bool_)) or not isinstance(v, kinds):
        return False
    if exact_ints and isinstance(v, (int, np.integer)):
        return -2**53 <= int(v) <= 2**53
    return True


def booleans(values):
    """A bool column; None for a value of another kind."""
    import pyarrow as pa

    n = len(values)
    data = np.zeros(n, dtype=bool)
    valid = np.ones(n, dtype=bool)
    for k, v in enumerate(values):
        if _is_missing(v):
            valid[k] = False
        elif isinstance(v, (bool, np.bool_)):
            data[k] = v
        else:
            return None
    bitmap, nulls = _validity(valid)
    return pa.Array.from_buffers(pa.bool_(), n, [bitmap, pa.py_buffer(np.packbits(data, bitorder="little"))],
                                 null_count=nulls)


def strings(values):
    """A string column (UTF-8); None for a value of another kind."""
    import pyarrow as pa

    n = len(values)
    valid = np.ones(n, dtype=bool)
    lengths = np.zeros(n + 1, dtype=np.int64)
    if set(map(type, values)) <= {str}:   # none missing: encoded and measured in C loops
        parts = [v.encode("utf-8") for v in values]
        lengths[1:] = np.fromiter(map(len, parts), dtype=np.int64, count=n)
    else:
        parts = []
        for k, v in enumerate(values):
            if v is None:
                valid[k] = False
            elif isinstance(v, str):
                b = v.encode("utf-8")
                parts.append(b)
                lengths[k + 1] = len(b)
            else:
                return None
    offsets = np.cumsum(lengths)
    if offsets[-1] >= 2**31:
        return None                      # beyond 32-bit offsets: the general route (large strings)
    bitmap, nulls = _validity(valid)
    return pa.Array.from_buffers(pa.string(), n, [bitmap, pa.py_buffer(offsets.astype(np.int32)),
                                                  pa.py_buffer(b"".join(parts))], null_count=nulls)


def lists(values, arrow_type):
    """A list<float64>, list<string> or list<struct of strings> column (``arrow_type``);
    elements are kept as they are (a NaN inside a list is a value).  None for a value of
    another kind."""
    import pyarrow as pa

    n = len(values)
    valid = np.ones(n, dtype=bool)
    lengths = np.zeros(n + 1, dtype=np.int64)
    if set(map(type, values)) <= {list}:  # no row missing: lengths and elements in C loops
        lengths[1:] = np.fromiter(map(len, values), dtype=np.int64, count=n)
        flat = list(itertools.chain.from_iterable(values))
    else:
        flat = []
        for k, v in enumerate(values):
            if v is None:
                valid[k] = False
            elif isinstance(v, (list, tuple)):
                flat.extend(v)
                lengths[k + 1] = len(v)
            else:
                return None
    if pa.types.is_string(arrow_type.value_type):
        child = strings(flat)
    elif pa.types.is_struct(arrow_type.value_type):
        child = _string_structs(flat, arrow_type.value_type)
    else:
        child = _plain_floats(flat)
    if child is None:
        return None
    offsets = np.cumsum(lengths)
    bitmap, nulls = _validity(valid)
    return pa.Array.from_buffers(arrow_type, n, [bitmap, pa.py_buffer(offsets.astype(np.int32))],
                                 null_count=nulls, children=[child])


def _string_structs(values, struct_type):
    """A struct column whose fields are all strings, from dicts; None for a value of another kind."""
    import pyarrow as pa

    if not all(isinstance(v, dict) for v in values):
        return None
    fields = list(struct_type)
    children = [strings([v.get(f.name) for v in values]) for f in fields]
    if any(c is None for c in children):
        return None
    return pa.StructArray.from_arrays(children, fields=fields)


def _plain_floats(values):
    """float64 values, NaN kept (the elements of a list column); None for a non-number."""
    import pyarrow as pa

    data = _all_plain(values, float, np.float64)
    if data is None:
        kinds = (int, float, np.integer, np.floating)
        if not all(_number(v, kinds, exact_ints=True) for v in values):
            return None                   # None inside a list, bytes, bools...: the general route
        data = np.array(values, dtype=np.float64)
    return pa.Array.from_buffers(pa.float64(), len(data), [None, pa.py_buffer(data)])


def column(values, arrow_type):
    """The Arrow column of ``values`` for one of the output's types, or None (see the module)."""
    import pyarrow as pa

    if pa.types.is_list(arrow_type):
        return lists(values, arrow_type)
    if pa.types.is_string(arrow_type):
        return strings(values)
    if pa.types.is_boolean(arrow_type):
        return booleans(values)
    if pa.types.is_int64(arrow_type):
        return numbers(values, arrow_type, np.int64)
    if pa.types.is_float64(arrow_type):
        return numbers(values, arrow_type, np.float64)
    return None
