"""`inertia props` (placeholder until implemented)."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("props", help="(not yet implemented)")
    p.set_defaults(func=run)


def run(args) -> int:
    from inertia.errors import InertiaError

    raise InertiaError("'props' is not implemented yet")
