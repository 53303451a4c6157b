"""Exception types of the inertia package.

Every error the package raises on purpose derives from :class:`InertiaError`, so a
caller can catch them all with one ``except`` clause.  Each also derives from the
closest built-in type (``ValueError``, ``OSError``) so that generic handlers work.
"""

from __future__ import annotations

__all__ = ['InertiaError', 'InputError', 'InvalidInertiaError', 'NoEquivalentModelError', 'MeshError', 'MeshFileError', 'MissingDependencyError', 'IntegrationError', 'InertiaWarning', 'MeshDefectWarning']


class InertiaError(Exception):
    """Base class of every error raised on purpose by :mod:`inertia`."""


class InputError(InertiaError, ValueError):
    """An argument has the wrong shape, type or value (the message says which)."""


class InvalidInertiaError(InertiaError, ValueError):
    """Mass properties that are not physical.

    Attributes
    ----------
    violations : list of inertia.massprops.validity.Violation
        Every violated condition, with its code, message and numbers.
    """

    def __init__(self, message: str, violations=()):
        super().__init__(message)
        self.violations = list(violations)


class NoEquivalentModelError(InvalidInertiaError):
    """No equivalent particle model or uniform solid reproduces the given properties."""


class MeshError(InertiaError, ValueError):
    """A triangle mesh whose mass properties would be wrong or meaningless.

    Attributes
    ----------
    report : inertia.geometry.checks.MeshReport or None
        The full defect report (every defect with counts and example locations).
    """

    def __init__(self, message: str, report=None):
        super().__init__(message)
        self.report = report


class MeshFileError(InertiaError, OSError):
    """A mesh file that cannot be read (missing, unsupported format, malformed)."""


class MissingDependencyError(InertiaError, ImportError):
    """An optional dependency needed for this feature is not installed."""


class IntegrationError(InertiaError, ArithmeticError):
    """The numerical solution stopped being finite (the method diverged at this step size)."""


class InertiaWarning(UserWarning):
    """Base class of the warnings the package issues on purpose."""


class MeshDefectWarning(InertiaWarning):
    """A mesh defect accepted on request (``on_defect="warn"``)."""


# Public home of these types: tracebacks and pickles name ``inertia.errors.X``.
for _cls in list(globals().values()):
    if isinstance(_cls, type) and _cls.__name__ in __all__:
        _cls.__module__ = "inertia.errors"
del _cls
