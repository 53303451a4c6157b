"""sympy, imported on first use: ``inertia`` and ``inertia --help`` never load it."""

from __future__ import annotations

from .._core.errors import MissingDependencyError


def require_sympy():
    """The sympy module, or :class:`MissingDependencyError` naming the extra to install."""
    try:
        import sympy
    except ImportError:  # pragma: no cover - sympy is in the test extra
        raise MissingDependencyError(
            "the symbolic equations need sympy: pip install 'inertia[symbolic]'") from None
    return sympy
