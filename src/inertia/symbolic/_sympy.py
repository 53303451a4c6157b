"""sympy, imported on first use: ``inertia`` and ``inertia --help`` never load it."""

from __future__ import annotations

from .._core.optional import require


def require_sympy():
    """The sympy module, or :class:`MissingDependencyError` naming the extra to install."""
    return require("sympy", "the symbolic equations")
