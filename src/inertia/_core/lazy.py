"""Lazy package namespaces (PEP 562): names resolve to their module on first use, so
importing a package loads no NumPy (or sympy, Dask, ...) until a name is needed."""

from __future__ import annotations

import importlib


def lazy_namespace(package: str, exports: dict, submodules=()):
    """``(__getattr__, __dir__, __all__)`` for ``package``.

    ``exports`` maps a public name to the submodule (relative to ``package``, or absolute
    when it contains a dot after ``inertia``) that defines it; ``submodules`` are reachable as
    attributes without an explicit import.
    """
    names = sorted(exports)

    def __getattr__(name: str):
        if name in submodules:
            return importlib.import_module(f"{package}.{name}")
        mod = exports.get(name)
        if mod is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        target = mod if mod.startswith("inertia.") else f"{package}.{mod}"
        value = getattr(importlib.import_module(target), name)
        setattr(importlib.import_module(package), name, value)
        return value

    def __dir__():
        return sorted(set(names) | set(submodules))

    return __getattr__, __dir__, names
