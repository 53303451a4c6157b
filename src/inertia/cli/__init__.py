"""Command-line interface (``inertia``).  Modules here import only the standard library at
top level; the numerical layers are imported inside each command's ``run``."""
