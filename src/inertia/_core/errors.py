"""Exception and warning types of the inertia package (public face: :mod:`inertia.errors`).

Every error the package raises on purpose derives from :class:`InertiaError` (catch them all
with one ``except``) and from the closest built-in type (``ValueError``, ``OSError``, ...).
Each carries a stable ``code`` from the one registry of codes,
:data:`inertia.errors.CODES`, which the findings of every check share: the class's own code, or
a more specific one (a mesh file that is ``not_found``, a mesh whose first defect is
``open_edges``).  ``findings`` holds the :class:`~inertia.errors.Finding` objects behind it.
Programs read the code, never the message text.
"""

from __future__ import annotations

from .findings import CODES, Finding

__all__ = ["CODES", "Finding", "InertiaError", "InputError", "InvalidInertiaError", "NoEquivalentModelError",
           "MeshError", "MeshFileError", "MissingDependencyError", "IntegrationError", "RobotFileError",
           "InertiaWarning", "MeshDefectWarning"]


class InertiaError(Exception):
    """Base class of every error raised on purpose by :mod:`inertia`.

    Attributes
    ----------
    code : str
        A key of :data:`CODES`: the class's default unless a more specific one was given.
    findings : tuple of Finding
        The facts behind the error (empty when the message says all).
    """

    code = "inertia_error"
    findings: tuple = ()

    def __init__(self, message: str = "", *, code: str | None = None, findings=()):
        super().__init__(message)
        if code is not None:
            self.code = code
        if findings:
            self.findings = tuple(findings)


class InputError(InertiaError, ValueError):
    """An argument has the wrong shape, type or value (the message says which)."""

    code = "invalid_input"


class InvalidInertiaError(InertiaError, ValueError):
    """Mass properties that are not physical; ``findings`` holds every violated condition."""

    code = "invalid_inertia"


class NoEquivalentModelError(InvalidInertiaError):
    """No equivalent particle model or uniform solid reproduces the given properties."""

    code = "no_equivalent_model"


class MeshError(InertiaError, ValueError):
    """A triangle mesh whose mass properties would be wrong or meaningless.

    Attributes
    ----------
    report : inertia.geometry.MeshReport or None
        The full report of the mesh; ``findings`` are its errors, and without a ``code=`` the
        code is the first one's.
    remedies : tuple of (str, str)
        The ``(keyword, value)`` pairs of :func:`inertia.mesh_properties` that would give a
        result, e.g. ``(("repair", "orient"), ("on_defect", "warn"))``.
    """

    code = "invalid_mesh"

    def __init__(self, message: str, report=None, *, code: str | None = None, remedies=()):
        errors = tuple(getattr(report, "errors", ()))
        super().__init__(message, code=code or (errors[0].code if errors else None), findings=errors)
        self.report = report
        self.remedies = tuple(remedies)


class MeshFileError(InertiaError, OSError):
    """A mesh file that cannot be read (missing, unsupported format, malformed, empty)."""

    code = "unreadable"


class MissingDependencyError(InertiaError, ImportError):
    """An optional dependency needed for this feature is not installed (the message names the extra)."""

    code = "missing_dependency"


class IntegrationError(InertiaError, ArithmeticError):
    """A step failed: the solution stopped being finite, or an implicit step did not converge."""

    code = "integration_failed"


class RobotFileError(InertiaError, ValueError):
    """A robot description file that cannot be read: unsafe, malformed or missing."""

    code = "robot_file"


class InertiaWarning(UserWarning):
    """Base class of the warnings the package issues on purpose."""


class MeshDefectWarning(InertiaWarning):
    """A mesh defect accepted on request (``on_defect="warn"``)."""


# Public home of these types: tracebacks and pickles name ``inertia.errors.X``.
for _cls in list(globals().values()):
    if isinstance(_cls, type) and _cls.__name__ in __all__:
        _cls.__module__ = "inertia.errors"
del _cls
