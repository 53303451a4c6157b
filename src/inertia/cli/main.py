"""Entry point of the ``inertia`` command.

Each sub-command lives in its own module of this package, exposing ``register(subparsers)``.
Only the standard library is imported here so that ``inertia --help`` starts fast.
"""

from __future__ import annotations

import argparse
import importlib
import sys

#: each command as typed -> the module of this package that registers it, in --help's order
COMMANDS = {
    "props": "props",
    "particles": "particles",
    "demo": "demo",
    "simulate": "simulate",
    "flip": "flip",
    "lagrangian": "lagrangian",
    "batch": "batch",
    "check": "check",
    "fix": "fix",
    "warm-up": "warmup",
}


def build_parser(commands=tuple(COMMANDS)) -> argparse.ArgumentParser:
    """The parser of ``inertia`` with the sub-commands ``commands`` (all by default)."""
    from .._core.version import __version__

    parser = argparse.ArgumentParser(
        prog="inertia",
        description="Rigid-body mass properties and rotational dynamics (SI units; "
                    "inertia in the negated-product convention, L = I w).",
    )
    parser.add_argument("--version", action="version", version=f"inertia {__version__}")
    parser.add_argument("--debug", action="store_true", help="show Python tracebacks for errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in commands:
        importlib.import_module(f"inertia.cli.{COMMANDS[name]}").register(sub)
    return parser


def _pop_debug(argv: list[str]) -> tuple[list[str], bool]:
    """``--debug`` is accepted anywhere on the line (before a ``--`` that ends the options)."""
    end = argv.index("--") if "--" in argv else len(argv)
    debug = "--debug" in argv[:end]
    return [a for i, a in enumerate(argv) if not (i < end and a == "--debug")], debug


def main(argv=None) -> int:
    argv, debug = _pop_debug(list(sys.argv[1:] if argv is None else argv))
    # a line that names its command first needs that command's parser only (the others'
    # modules cost ~10 ms to import); anything else (--help, a typo) gets them all
    named = argv[0] if argv and argv[0] in COMMANDS else None
    parser = build_parser((named,) if named else tuple(COMMANDS))
    args = parser.parse_args(argv)
    args.debug = debug
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except KeyboardInterrupt:
        print("inertia: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        return 0
    except Exception as exc:  # noqa: BLE001 - the CLI turns every failure into a message
        if args.debug:
            raise
        from .._core.errors import InertiaError

        if isinstance(exc, InertiaError):
            print(f"inertia {args.command}: error: {exc}", file=sys.stderr)
            return 1
        print(f"inertia {args.command}: internal error ({type(exc).__name__}: {exc}). "
              f"Run again with --debug (anywhere on the command line) for the traceback "
              f"and please report it.", file=sys.stderr)
        return 3


def entry() -> None:
    """The ``inertia`` command."""
    sys.exit(main())


if __name__ == "__main__":
    entry()
