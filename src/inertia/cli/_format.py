"""Output helpers of the command line: aligned text tables and JSON.

Only the standard library is imported here; arrays arrive as NumPy arrays or nested
lists and are read through ``tolist()`` / iteration, so this module never imports NumPy.
All numbers are printed with 6 significant digits in tables and full precision in JSON.
"""

from __future__ import annotations

import math
import sys

from ..geometry.report import plural  # noqa: F401 - "1 link", "2 links" (the mesh report's own; no NumPy)

#: significant digits of numbers in tables
DIGITS = 6


def _plain(value):
    """Nested Python lists/floats from NumPy arrays, NumPy scalars, tuples (for JSON)."""
    if hasattr(value, "tolist"):
        value = value.tolist()
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None  # JSON has no NaN/inf; null means "unknown"
    return value


def to_json(data: dict) -> str:
    """Strict JSON text (NaN and infinities become null), 2-space indent, with each list of
    numbers (a vector, a matrix row) kept on one line."""
    return _dump(_plain(data), 0)


def _dump(value, level: int) -> str:
    import json  # here, not at the top: keeps ``inertia --help`` start-up small

    pad, inner = "  " * level, "  " * (level + 1)
    if isinstance(value, dict):
        if not value:
            return "{}"
        items = [f"{inner}{json.dumps(k)}: {_dump(v, level + 1)}" for k, v in value.items()]
        return "{\n" + ",\n".join(items) + "\n" + pad + "}"
    if isinstance(value, list):
        if all(not isinstance(v, (dict, list)) for v in value):
            return "[" + ", ".join(json.dumps(v, allow_nan=False) for v in value) + "]"
        items = [inner + _dump(v, level + 1) for v in value]
        return "[\n" + ",\n".join(items) + "\n" + pad + "]"
    return json.dumps(value, allow_nan=False)


def num(x, digits: int = DIGITS) -> str:
    """One number with ``digits`` significant digits; NaN/None as 'n/a'; tiny values stay exact."""
    if x is None:
        return "n/a"
    x = float(x)
    if math.isnan(x):
        return "n/a"
    if x == 0:
        return "0"
    return f"{x:.{digits}g}"


def fixed_formatter(values, digits: int = DIGITS):
    """A fixed-point formatter for a group of numbers: ``digits`` significant digits for the
    largest magnitude and the same number of decimals for all (so columns line up)."""
    flat = [abs(float(x)) for x in _flatten(_plain(values)) if x is not None and math.isfinite(float(x))]
    big = max(flat + [0.0])
    decimals = digits - 1 - (math.floor(math.log10(big)) if big > 0 else 0)
    decimals = min(max(decimals, 0), 12)
    def text(x):
        if x is None or not math.isfinite(float(x)):
            return "n/a"
        s = f"{float(x):.{decimals}f}"
        return s[1:] if s.startswith("-") and not s.strip("-0.") else s   # no "-0.000000"

    return text


def _flatten(v):
    if isinstance(v, (list, tuple)):
        for x in v:
            yield from _flatten(x)
    else:
        yield v


def vector(v, digits: int = DIGITS) -> str:
    """``[a, b, c]`` with aligned signs."""
    items = [num(x, digits) for x in _plain(v)]
    return "[" + ", ".join(items) + "]"


def matrix_lines(M, *, row_labels=None, col_labels=None, digits: int = DIGITS, indent: int = 4,
                 style: str = "g") -> list[str]:
    """Lines of a matrix, columns right-aligned, optional row and column labels.

    ``style``: ``"g"`` shortest of fixed/exponent per entry, ``"e"`` exponent notation for all
    entries, ``"f"`` fixed point with decimals chosen for the largest entry.
    """
    M = _plain(M)
    if style == "e":
        f = lambda x: "0" if float(x) == 0 else f"{float(x):.{digits - 1}e}"  # noqa: E731
    elif style == "f":
        f = fixed_formatter(M, digits)
    else:
        f = lambda x: num(x, digits)  # noqa: E731
    rows = [[f(x) for x in row] for row in M]
    ncol = len(rows[0]) if rows else 0
    width = max([len(c) for r in rows for c in r] + [len(c) for c in (col_labels or [])] + [1])
    lab_w = max([len(str(r)) for r in (row_labels or [])] + [0])
    pad = " " * indent
    lines = []
    if col_labels:
        head = " " * lab_w + ("  " if lab_w else "") + "  ".join(str(c).rjust(width) for c in col_labels)
        lines.append(pad + head.rstrip())
    for k, r in enumerate(rows):
        label = (str(row_labels[k]).ljust(lab_w) + "  ") if row_labels else ""
        lines.append(pad + label + "  ".join(c.rjust(width) for c in r[:ncol]))
    return lines


def key_values(pairs, *, indent: int = 2) -> list[str]:
    """``name   value`` lines with the names padded to one width."""
    pairs = [(str(k), str(v)) for k, v in pairs]
    w = max([len(k) for k, _ in pairs] + [0])
    return [" " * indent + k.ljust(w) + "  " + v for k, v in pairs]


def heading(title: str) -> list[str]:
    """A section title underlined with dashes."""
    return ["", title, "-" * len(title)]


def table(header, rows, *, indent: int = 2) -> list[str]:
    """A text table: ``header`` (list of str) and ``rows`` (lists of str), columns aligned
    (text left, numbers right)."""
    rows = [[str(c) for c in r] for r in rows]
    cols = list(zip(*([list(header)] + rows))) if rows else [[h] for h in header]
    widths = [max(len(c) for c in col) for col in cols]

    def is_num(s: str) -> bool:
        try:
            float(s)
            return True
        except ValueError:
            return False

    # a column is numeric when all its data cells are numbers: right-align it, header included
    numeric = [bool(rows) and all(is_num(r[k]) or r[k] == "n/a" for r in rows) for k in range(len(widths))]

    def fmt_row(r):
        cells = [c.rjust(w) if right else c.ljust(w) for c, w, right in zip(r, widths, numeric)]
        return (" " * indent + "  ".join(cells)).rstrip()

    out = [fmt_row(list(header)), " " * indent + "  ".join("-" * w for w in widths)]
    out += [fmt_row(r) for r in rows]
    return out


def emit(lines_or_text, file=None) -> None:
    """Print lines (a list) or a text to stdout (or ``file``)."""
    text = lines_or_text if isinstance(lines_or_text, str) else "\n".join(lines_or_text)
    (file or sys.stdout).write(text.rstrip("\n") + "\n")




def add_command(sub, name: str, help: str, description: str, epilog: str):
    """A subcommand parser: one-line ``help``, ``description`` wrapped to the terminal's
    usual width, ``epilog`` (examples) kept as written."""
    import argparse
    import textwrap

    return sub.add_parser(name, help=help, description=textwrap.fill(description), epilog=epilog,
                          formatter_class=argparse.RawDescriptionHelpFormatter)
