"""Optional dependencies, imported on first use, with one error that names the extra.

Every feature beyond NumPy and SciPy lives behind an extra of ``pyproject.toml``; a
feature whose module is missing raises :class:`~inertia.errors.MissingDependencyError`
(code ``missing_dependency``) saying what needs it and what to install, never a bare
``ImportError`` or ``ModuleNotFoundError``.
"""

from __future__ import annotations

import importlib

from .errors import MissingDependencyError

#: top-level module -> the extra of ``pyproject.toml`` that installs it
EXTRA_OF = {
    "trimesh": "mesh",
    "collada": "mesh",
    "xacro": "xacro",
    "sympy": "symbolic",
    "matplotlib": "viz",
    "PIL": "viz",
    "imageio": "viz",
    "imageio_ffmpeg": "viz",
    "dask": "batch",
    "distributed": "batch",
    "pandas": "batch",
    "pyarrow": "batch",
    "pxr": "usd",
}


def require(module: str, needed_for: str):
    """Import ``module`` (dotted names allowed) or raise MissingDependencyError.

    ``needed_for`` completes the sentence "<needed_for> needs <package>", e.g.
    ``"reading mesh files"``.
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        top = module.split(".")[0]
        missing = (getattr(exc, "name", None) or top).split(".")[0]
        extra = EXTRA_OF.get(missing, EXTRA_OF.get(top))
        hint = f"pip install 'inertia[{extra}]'" if extra else f"pip install {missing}"
        raise MissingDependencyError(f"{needed_for} needs {missing}, which is not installed: {hint}") from None
