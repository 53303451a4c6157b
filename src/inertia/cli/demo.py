"""`inertia demo` (placeholder until implemented)."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("demo", help="(not yet implemented)")
    p.set_defaults(func=run)


def run(args) -> int:
    from inertia.errors import InertiaError

    raise InertiaError("'demo' is not implemented yet")
