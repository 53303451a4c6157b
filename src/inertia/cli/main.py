"""Entry point of the ``inertia`` command.

Each sub-command lives in its own module of this package, exposing ``register(subparsers)``.
Only the standard library is imported here so that ``inertia --help`` starts fast.
"""

from __future__ import annotations

import argparse
import errno
import importlib
import io
import os
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
    "diff": "diff",
    "help": "main",
}

EPILOG = """\
examples:
  inertia demo                                        (a tour on a steel T-handle, no files needed)
  inertia props part.stl --units mm --density 2700    (mass, COM, inertia, principal axes)
  inertia props part.stl --units mm --output-units g,mm --convention cad
  inertia check robot.urdf --package-path ~/ws/src    (every inertial problem, by link and line)
  inertia help mesh                                   (the options every mesh command shares)

Every command says more with --help; shared options are described once by inertia help TOPIC
(topics: source, mesh, output, robot, usd); docs/cli.md has them all.  SI units throughout unless
--output-units says otherwise."""


def build_parser(commands=tuple(COMMANDS)) -> argparse.ArgumentParser:
    """The parser of ``inertia`` with the sub-commands ``commands`` (all by default)."""
    from .._core.version import __version__
    from ._format import Parser

    parser = Parser(
        prog="inertia",
        description="Rigid-body mass properties and rotational dynamics (SI units; inertia in the\n"
                    "negated-product convention, L = I w).",
        epilog=EPILOG, formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    parser.add_argument("--version", action="version", version=f"inertia {__version__}")
    parser.add_argument("--debug", action="store_true", help="show Python tracebacks for errors")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for name in commands:
        importlib.import_module(f"inertia.cli.{COMMANDS[name]}").register(sub)
    return parser


def sub_parsers(parser) -> dict:
    """Command name -> its parser."""
    return next(a.choices for a in parser._actions if isinstance(a, argparse._SubParsersAction))


def register(sub) -> None:
    """``inertia help [COMMAND | TOPIC]``."""
    from ._format import add_command
    from ._options import TOPICS

    p = add_command(sub, "help", "a command's help, or a shared option block's (TOPIC)",
                    "Without an argument, this list of commands; with a command, its --help; with a "
                    "TOPIC, the options that several commands share, described once.",
                    "examples:\n  inertia help props\n  inertia help mesh", usage="[COMMAND | TOPIC]")
    p.add_argument("topic", nargs="?", metavar="COMMAND | TOPIC",
                   choices=[c for c in COMMANDS if c != "help"] + list(TOPICS),
                   help="a command, or one of the topics " + ", ".join(TOPICS))
    p.set_defaults(func=_help)


def _help(args) -> int:
    from ._options import TOPICS, topic_help

    if args.topic in TOPICS:
        sys.stdout.write(topic_help(args.topic))
        return 0
    parser = build_parser((args.topic,) if args.topic else tuple(COMMANDS))
    (sub_parsers(parser)[args.topic] if args.topic else parser).print_help()
    return 0


def _pop_debug(argv: list[str]) -> tuple[list[str], bool]:
    """``--debug`` is accepted anywhere on the line (before a ``--`` that ends the options)."""
    end = argv.index("--") if "--" in argv else len(argv)
    debug = "--debug" in argv[:end]
    return [a for i, a in enumerate(argv) if not (i < end and a == "--debug")], debug


class _WholeWrites(io.RawIOBase):
    """A file descriptor whose every write is whole or an OSError: a write cut short by a
    file-size limit raises (EFBIG) instead of being dropped by Python's buffered stdout."""

    def __init__(self, fd: int):
        super().__init__()
        self.fd = fd

    def writable(self) -> bool:
        return True

    def fileno(self) -> int:
        return self.fd

    def write(self, data) -> int:
        view = memoryview(data).cast("B")
        done = 0
        while done < len(view):
            done += os.write(self.fd, view[done:])
        return done


def _checked_stdout() -> None:
    """Replace ``sys.stdout`` (a real file descriptor only) by the same stream over :class:`_WholeWrites`."""
    out = sys.stdout
    try:
        fd = out.fileno()
    except (AttributeError, OSError, ValueError):
        return                    # a test's capture or an embedding: left alone
    out.flush()
    sys.stdout = io.TextIOWrapper(io.BufferedWriter(_WholeWrites(fd)), encoding=out.encoding, errors=out.errors,
                                  line_buffering=out.line_buffering)


def main(argv=None) -> int:
    argv, debug = _pop_debug(list(sys.argv[1:] if argv is None else argv))
    # a line that names its command first needs that command's parser only (the others'
    # modules cost ~10 ms to import); anything else (--help, a typo) gets them all
    named = argv[0] if argv and argv[0] in COMMANDS else None
    parser = build_parser((named,) if named else tuple(COMMANDS))
    args, extras = parser.parse_known_args(argv)
    if extras:    # refused by the command they were given to, with its usage, not the top level's
        (sub_parsers(parser).get(getattr(args, "command", None)) or parser).unknown(extras)
    args.debug = debug
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        code = int(args.func(args) or 0)
        sys.stdout.flush()        # a write that fails is this command's failure, not the exit's
        return code
    except KeyboardInterrupt:
        print("inertia: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:       # the reader went away (inertia ... | head): nothing more to say
        _stdout_to_devnull()
        return 0
    except Exception as exc:  # noqa: BLE001 - the CLI turns every failure into a message
        from .._core.errors import InertiaError

        if isinstance(exc, OSError) and not isinstance(exc, InertiaError) and exc.errno in _OUTPUT_ERRNOS:
            _stdout_to_devnull()
            print(f"inertia {args.command}: error: cannot write the output ({exc.strerror}); it is incomplete",
                  file=sys.stderr)
            return 1
        if args.debug:
            raise
        if isinstance(exc, InertiaError):
            print(f"inertia {args.command}: error: {exc}", file=sys.stderr)
            return 1
        print(f"inertia {args.command}: internal error ({type(exc).__name__}: {exc}). "
              f"Run again with --debug (anywhere on the command line) for the traceback "
              f"and please report it.", file=sys.stderr)
        return 3


#: errors of a write that the user's system can cause: full disk, file-size limit, quota, I/O
_OUTPUT_ERRNOS = {errno.ENOSPC, errno.EFBIG, errno.EDQUOT, errno.EIO, errno.EPIPE}


def _stdout_to_devnull() -> None:
    """Point stdout at /dev/null, so the interpreter's last flush has nowhere to fail."""
    try:
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        os.close(devnull)
    except (OSError, ValueError):
        pass


def entry() -> None:
    """The ``inertia`` command."""
    _checked_stdout()
    sys.exit(main())


if __name__ == "__main__":
    entry()
