"""The bottom layer: errors, rotations and quaternions, input validation, named tolerances,
atomic writes, lazy namespaces, the progress bar and the version.  It imports only NumPy,
SciPy and the standard library; every other package may import it (internal: the public
faces are :mod:`inertia.errors` and the top level)."""
