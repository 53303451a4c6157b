"""The exception and warning types of :mod:`inertia` (public names; defined in
:mod:`inertia._core.errors`).

Every error the package raises on purpose derives from :class:`InertiaError` and carries a
stable ``code``; catch them all with one ``except InertiaError``.
"""

from ._core.errors import *  # noqa: F401,F403
from ._core.errors import __all__  # noqa: F401
