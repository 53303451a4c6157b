"""`inertia particles` (placeholder until implemented)."""

from __future__ import annotations


def register(sub) -> None:
    p = sub.add_parser("particles", help="(not yet implemented)")
    p.set_defaults(func=run)


def run(args) -> int:
    from inertia.errors import InertiaError

    raise InertiaError("'particles' is not implemented yet")
