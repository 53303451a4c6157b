"""Output helpers of the command line: aligned text tables and JSON.

Only the standard library is imported here; arrays arrive as NumPy arrays or nested
lists and are read through ``tolist()`` / iteration, so this module never imports NumPy.
All numbers are printed with 6 significant digits in tables and full precision in JSON.
"""

from __future__ import annotations

import argparse
import math
import sys
import textwrap

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


def fix_report_lines(report, what: str, whats: str, fails: str) -> list[str]:
    """The lines every ``fix`` report shares: each changed item, each kept one with why, and, when
    the output still fails, ``fails`` (its head line) and each item still failing (``what`` and
    ``whats``: the item's noun, one and many)."""
    lines = [f"  {name}: {how}" for name, how in report.changed.items()]
    lines += [f"  {name}: kept ({why})" for name, why in report.skipped.items()]
    if report.remaining:
        lines.append(f"{report.output} {fails} ({plural(len(report.remaining), what, whats)}):")
        lines += [f"  {name}: {why}" for name, why in report.remaining.items()]
    return lines


def emit(lines_or_text, file=None) -> None:
    """Print lines (a list) or a text to stdout (or ``file``)."""
    text = lines_or_text if isinstance(lines_or_text, str) else "\n".join(lines_or_text)
    (file or sys.stdout).write(text.rstrip("\n") + "\n")


class Parser(argparse.ArgumentParser):
    """argparse with two habits of this CLI: a shared option block (a group with a ``topic``)
    is shown as one line of its option names, its full text being ``inertia help TOPIC``; and
    an unknown option is refused by the command it was given to, with the nearest spelling."""

    def format_help(self) -> str:
        f = self._get_formatter()
        f.add_usage(self.usage, self._actions, self._mutually_exclusive_groups)
        f.add_text(self.description)
        for group in self._action_groups:
            f.start_section(group.title)
            topic = getattr(group, "topic", None)
            if topic:
                names = ", ".join(option_synopsis(a) for a in group._group_actions)
                # the pointer kept on one line (no-break spaces, made plain below)
                pointer = f"(inertia help {topic})".replace(" ", "\xa0")
                f.add_text(textwrap.fill(f"{names} {pointer}", f._width - f._current_indent))
            else:
                f.add_text(group.description)
                f.add_arguments(group._group_actions)
            f.end_section()
        f.add_text(self.epilog)
        return f.format_help().replace("\xa0", " ")

    def unknown(self, extras) -> None:
        """Refuse ``extras`` (what the command did not recognise), naming the spelling it takes."""
        import difflib

        known = [s for a in self._actions for s in a.option_strings]
        hints = []
        for arg in extras:
            name = arg.split("=", 1)[0]
            near = RENAMED.get(name) or next(iter(difflib.get_close_matches(name, known, 1, 0.6)), None)
            if name.startswith("--") and near:
                hints.append(f"{near} instead of {name}?")
        self.error("unrecognized arguments: " + " ".join(extras) + ("; did you mean " + ", ".join(hints)
                                                                     if hints else ""))


#: options renamed so that one concept has one spelling in every command: old -> new
RENAMED = {"--mesh-units": "--units"}


def option_synopsis(action) -> str:
    """``--units UNIT`` or ``--self-crossing search|certificate``: an option as a list names it."""
    name = action.option_strings[-1]
    if action.nargs == 0:
        return name
    if action.choices:
        return f"{name} {'|'.join(map(str, action.choices))}"
    return f"{name} {action.metavar or action.dest.upper()}"


def add_command(sub, name: str, help: str, description: str, epilog: str, usage: str | None = None):
    """A subcommand parser: one-line ``help``, ``description`` wrapped to the terminal's
    usual width, ``epilog`` (examples) kept as written, ``usage`` after the command's name."""
    return sub.add_parser(name, help=help, description=textwrap.fill(description), epilog=epilog,
                          usage=f"%(prog)s {usage}" if usage else None,
                          formatter_class=argparse.RawDescriptionHelpFormatter)


#: mass unit name -> kg (the file's masses: --mass-units; printed masses: --output-units)
MASS_UNITS = {"kg": 1.0, "g": 1e-3, "lb": 0.45359237}


class Units:
    """How printed numbers are expressed: ``--output-units MASS,LENGTH`` (kg,m by default) and
    ``--convention`` of the products of inertia (``tensor``: the negated products, L = I w;
    ``cad``: positive products, as CAD programs list them).  Each method takes SI values."""

    def __init__(self, mass: str = "kg", length: str = "m", convention: str = "tensor"):
        from .._core.units import LENGTH_UNITS

        self.mass_unit, self.length_unit, self.convention = mass, length, convention
        self.kg, self.m = MASS_UNITS[mass], LENGTH_UNITS[length]

    @classmethod
    def from_args(cls, args) -> "Units":
        """From ``--output-units`` and ``--convention`` (SI and tensor when the command has neither)."""
        from .._core.errors import InputError
        from .._core.units import LENGTH_UNITS

        text = getattr(args, "output_units", None) or "kg,m"
        mass, sep, length = text.replace(" ", "").partition(",")
        if not sep or mass not in MASS_UNITS or length not in LENGTH_UNITS:
            raise InputError(f"--output-units {text!r} must read MASS,LENGTH with MASS one of "
                             f"{'|'.join(MASS_UNITS)} and LENGTH one of {'|'.join(LENGTH_UNITS)}, e.g. g,mm")
        return cls(mass, length, getattr(args, "convention", None) or "tensor")

    @property
    def si(self) -> bool:
        return self.kg == 1.0 and self.m == 1.0 and self.convention == "tensor"

    @property
    def inertia_unit(self) -> str:
        return f"{self.mass_unit} {self.length_unit}^2"

    @property
    def density_unit(self) -> str:
        return f"{self.mass_unit}/{self.length_unit}^3"

    def mass(self, x):
        return _scaled(x, 1.0 / self.kg)

    def length(self, x):
        return _scaled(x, 1.0 / self.m)

    def volume(self, x):
        return _scaled(x, self.m ** -3)

    def density(self, x, per_area: bool = False):
        return _scaled(x, self.m ** (2 if per_area else 3) / self.kg)

    def moments(self, x):
        """Principal moments (the same whatever the product convention)."""
        return _scaled(x, 1.0 / (self.kg * self.m ** 2))

    def inertia(self, I):
        """A 3 x 3 tensor about the COM, its products positive under ``cad``."""
        I = [[v / (self.kg * self.m ** 2) for v in row] for row in _as_list(I)]
        if self.convention == "cad":
            I = [[v if i == j else -v for j, v in enumerate(row)] for i, row in enumerate(I)]
        return I

    def to_dict(self) -> dict:
        return {"mass": self.mass_unit, "length": self.length_unit, "inertia": self.inertia_unit,
                "convention": self.convention}

    def conventions(self) -> str:
        """The sentence of the JSON's ``conventions`` about units and products."""
        products = ("products of inertia positive (CAD convention: Ixy = +sum m x y)" if self.convention == "cad"
                    else "products of inertia negated (L = I w)")
        return f"{self.mass_unit}, {self.length_unit}, {self.inertia_unit}; {products}"


def _scaled(x, factor: float):
    """``x`` (a number, None or a nested list or array of numbers) times ``factor``."""
    x = _as_list(x)
    if x is None:
        return None
    if isinstance(x, list):
        return [_scaled(v, factor) for v in x]
    return x * factor


def _as_list(x):
    """Nested lists from an array or tuple (NaN kept, unlike :func:`_plain`)."""
    if hasattr(x, "tolist"):
        x = x.tolist()
    return [_as_list(v) for v in x] if isinstance(x, (list, tuple)) else x


def short_digits(mass, inertia) -> int:
    """Significant digits to write a mass and tensor with: 6, the figure a user would write,
    or as many more as keep the written values physical (a tensor near the triangle-inequality
    boundary can round across it)."""
    from ..massprops.validity import is_physical

    def rounded(x, digits):
        return [[float(f"{v:.{digits}g}") for v in row] for row in _as_list(x)]

    if not is_physical(inertia, mass):
        return 6                  # no number of digits makes it physical
    return next(d for d in range(6, 18) if is_physical(rounded(inertia, d), float(f"{mass:.{d}g}")))


def inertial_block(props, kind: str) -> str:
    """The library's ``<inertial>`` block (:func:`inertia.robots.writers.inertial_block`) with
    each number at :func:`short_digits` significant digits instead of repr's 17."""
    import re

    from ..robots.writers import inertial_block as block

    digits = short_digits(props.mass, props.inertia_com)

    def short(m) -> str:
        x = float(m.group())
        return "0" if x == 0 else f"{x:.{digits}g}"

    return re.sub(r"(?<![\w.])-?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?(?![\w.])", short, block(props, kind))
