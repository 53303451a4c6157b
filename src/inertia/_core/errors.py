"""Exception and warning types of the inertia package (public face: :mod:`inertia.errors`).

Every error the package raises on purpose derives from :class:`InertiaError`, so a caller
can catch them all with one ``except`` clause.  Each also derives from the closest built-in
type (``ValueError``, ``OSError``, ...) so that generic handlers work.

Each error carries a stable, machine-readable ``code`` (a short snake_case string): the
class's own code, or a more specific one given where it is raised (a mesh file that is
``"not_found"``, a mesh whose first defect is ``"open_edges"``).  Programs (the batch table's
``reason`` column among them) read the code, never the message text, which may be reworded.

=========================  ==========================================================
class                      codes
=========================  ==========================================================
InertiaError               ``inertia_error`` (base; not raised itself)
InputError                 ``invalid_input``, ``unwritable`` (an output path that cannot be written)
InvalidInertiaError        ``invalid_inertia``
NoEquivalentModelError     ``no_equivalent_model``
MeshError                  ``invalid_mesh``, ``non_positive_volume``, ``zero_area``,
                           ``not_orientable``, or the code of the mesh's first defect
                           (``open_edges``, ``inverted``, ... see ``MeshReport``)
MeshFileError              ``unreadable``, ``not_found``, ``empty``, ``malformed``,
                           ``unsupported_format``, ``too_large``
MissingDependencyError     ``missing_dependency``
IntegrationError           ``integration_failed``
RobotFileError             ``robot_file``
=========================  ==========================================================
"""

from __future__ import annotations

__all__ = ["InertiaError", "InputError", "InvalidInertiaError", "NoEquivalentModelError", "MeshError",
           "MeshFileError", "MissingDependencyError", "IntegrationError", "RobotFileError", "InertiaWarning",
           "MeshDefectWarning"]


class InertiaError(Exception):
    """Base class of every error raised on purpose by :mod:`inertia`.

    Attributes
    ----------
    code : str
        Stable machine-readable code (see the module docstring); the class's default unless a
        more specific one was given with ``code=``.
    """

    code = "inertia_error"

    def __init__(self, message: str = "", *, code: str | None = None):
        super().__init__(message)
        if code is not None:
            self.code = code


class InputError(InertiaError, ValueError):
    """An argument has the wrong shape, type or value (the message says which)."""

    code = "invalid_input"


class InvalidInertiaError(InertiaError, ValueError):
    """Mass properties that are not physical.

    Attributes
    ----------
    violations : list of inertia.massprops.validity.Violation
        Every violated condition, with its code, message and numbers.
    """

    code = "invalid_inertia"

    def __init__(self, message: str, violations=(), *, code: str | None = None):
        super().__init__(message, code=code)
        self.violations = list(violations)


class NoEquivalentModelError(InvalidInertiaError):
    """No equivalent particle model or uniform solid reproduces the given properties."""

    code = "no_equivalent_model"


class MeshError(InertiaError, ValueError):
    """A triangle mesh whose mass properties would be wrong or meaningless.

    Attributes
    ----------
    report : inertia.geometry.report.MeshReport or None
        The full defect report (every defect with counts and example locations).  Without a
        ``code=``, the code is that of the report's first error-level defect.
    """

    code = "invalid_mesh"

    def __init__(self, message: str, report=None, *, code: str | None = None):
        if code is None and report is not None:
            errors = [d.code for d in getattr(report, "errors", ())]
            code = errors[0] if errors else None
        super().__init__(message, code=code)
        self.report = report


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
