"""The SOURCE argument of ``inertia props``, ``particles``, ``simulate``, ``flip`` and ``demo --mesh``.

SOURCE is either a mesh file (any format :func:`inertia.load_mesh` reads: STL, OBJ, PLY,
OFF, ...) or a primitive spec ``NAME:n1,n2,...`` such as ``box:0.1,0.2,0.4``.  The mass
comes from ``--mass`` (kg) or ``--density`` (kg/m^3); with neither, the density of water,
:data:`DEFAULT_DENSITY` = 1000 kg/m^3, is used and the output says so.

Lengths (mesh coordinates and primitive dimensions) are read in ``--units`` and converted
to metres; every result is in SI units.  The options themselves are in :mod:`._options`.
Only the standard library is imported at module level.
"""

from __future__ import annotations

import math
import os

from .._core.units import DEFAULT_DENSITY, LENGTH_UNITS


class PrimitiveSpec:
    """One primitive shape of the SOURCE grammar: its parameter names and how to build it.

    (A plain class, not a dataclass: importing :mod:`dataclasses` costs ~7 ms of the
    ``inertia --help`` start-up.)
    """

    def __init__(self, name: str, params: tuple, meaning: str, *, optional: int = 0, call: str = "args",
                 zero_ok: tuple = ()):
        self.name = name          # as written in SOURCE, e.g. "box"
        self.params = params      # parameter names as the user writes them, e.g. ("r", "h")
        self.meaning = meaning    # one line for --help and error messages
        self.optional = optional  # how many trailing parameters may be omitted
        self.call = call          # "args": f(*dims); "tuple": f(tuple(dims))
        self.zero_ok = zero_ok    # parameters that may be 0 (a capsule of length 0 is a sphere)

    @property
    def usage(self) -> str:
        req = self.params[: len(self.params) - self.optional]
        opt = self.params[len(self.params) - self.optional:]
        text = f"{self.name}:" + ",".join(req)
        if opt:
            text += "".join(f"[,{p}]" for p in opt)
        return text


PRIMITIVES = {
    p.name: p
    for p in (
        PrimitiveSpec("box", ("a", "b", "c"), "edge lengths along x, y, z", call="tuple"),
        PrimitiveSpec("sphere", ("r",), "radius"),
        PrimitiveSpec("ellipsoid", ("a", "b", "c"), "semi-axes along x, y, z", call="tuple"),
        PrimitiveSpec("cylinder", ("r", "h"), "radius, height along z"),
        PrimitiveSpec("cone", ("r", "h"), "base radius, height along z"),
        PrimitiveSpec("capsule", ("r", "l"), "radius, length of the cylindrical part along z",
                      zero_ok=("l",)),
        PrimitiveSpec("torus", ("R", "r"), "major radius (centre of tube), minor radius (tube); axis z"),
        PrimitiveSpec("tube", ("ro", "ri", "h"), "outer radius, inner radius, height along z"),
        PrimitiveSpec("spherical_shell", ("ro", "ri"), "outer radius, inner radius (omit for a thin shell)",
                      optional=1),
    )
}


class SourceInfo:
    """What was computed and how: echoed in every output so a reader can reproduce it.

    Attributes
    ----------
    source : str, the SOURCE text as given (or a label such as "built-in T-handle").
    kind : str, "mesh" or "primitive".
    units : str, input length unit.
    density : float, kg/m^3 (kg/m^2 for shells); the mean density when --mass was given.
    density_source : str, "default", "--density", "from --mass" or a label.
    shell : bool.
    primitive : str or None, primitive name.
    dimensions_m : tuple of float, primitive dimensions in metres.
    """

    def __init__(self, source: str, kind: str, units: str, density: float, density_source: str, *,
                 shell: bool = False, primitive=None, dimensions_m=()):
        self.source = source
        self.kind = kind
        self.units = units
        self.density = density
        self.density_source = density_source
        self.shell = shell
        self.primitive = primitive
        self.dimensions_m = tuple(dimensions_m)
        self.dimensions_text = ""   # an assembly's description (a primitive's comes from dimensions_m)
        self.mesh = None    # mesh files: {"n_vertices", "n_faces", "bbox_min", "bbox_max", "extents"} (m)
        self.notes = []     # unit-slip warnings (an implausible size or density)

    def dimensions(self, units) -> str:
        """A primitive's dimensions in ``units`` (an assembly's own description)."""
        from ._format import num

        if self.kind != "primitive":
            return self.dimensions_text
        spec = PRIMITIVES[self.primitive]
        return (", ".join(f"{p} = {num(v)}" for p, v in zip(spec.params, units.length(self.dimensions_m)))
                + f" {units.length_unit} ({spec.meaning})")

    def density_text(self, units) -> str:
        """E.g. ``1000 kg/m^3 (default: neither --mass nor --density given)``."""
        from ._format import num

        if self.density != self.density:  # NaN: a thin shell given by --mass (its area is not reported)
            return "n/a (thin shell given by --mass)"
        unit = f"{units.mass_unit}/{units.length_unit}^{2 if self.shell else 3}"
        d = f"{num(units.density(self.density, self.shell))} {unit}"
        if self.density_source == "default":
            return d + " (default: neither --mass nor --density given)"
        if self.density_source == "from --mass":
            return d + " (mean, from --mass)" if self.density < float("inf") else "beyond a double (mean, from --mass)"
        return d + f" ({self.density_source})"

    def to_dict(self, units) -> dict:
        out = {"source": self.source, "kind": self.kind, "units": self.units,
               "density": units.density(self.density, self.shell),
               "density_unit": f"{units.mass_unit}/{units.length_unit}^{2 if self.shell else 3}",
               "density_source": self.density_source, "shell": self.shell}
        if self.kind == "primitive":
            out["primitive"] = self.primitive
            out["dimensions"] = units.length(list(self.dimensions_m))
        if self.mesh is not None:
            out["mesh"] = {k: units.length(v) if k.startswith(("bbox", "extents")) else v
                           for k, v in self.mesh.items()}
        return out


# ---------------------------------------------------------------------------- parsing


def _input_error(msg: str):
    from .._core.errors import InputError

    return InputError(msg)


def _known() -> str:
    return ", ".join(p.usage for p in PRIMITIVES.values())


def _looks_like_spec_name(name: str) -> bool:
    # a word of 2+ letters/underscores (so "C:\\x" drive letters and paths are not specs)
    return len(name) >= 2 and name.replace("_", "").isalpha()


def classify_source(text: str):
    """``("mesh", path)`` or ``("primitive", PrimitiveSpec, numbers)``; raises InputError/MeshFileError.

    An existing file always wins, so a mesh file named ``box:1,2,3`` can still be read.
    """
    if not text or not text.strip():
        raise _input_error("SOURCE is empty: give a mesh file or a primitive spec such as box:0.1,0.2,0.4")
    text = text.strip()
    if os.path.lexists(text) and not os.path.isdir(text):   # a FIFO, a device...: the reader says what it is
        return ("mesh", text)
    name, sep, rest = text.partition(":")
    key = name.strip().lower()
    if sep and key in PRIMITIVES:
        spec = PRIMITIVES[key]
        return ("primitive", spec, _parse_numbers(text, spec, rest))
    if sep and _looks_like_spec_name(name.strip()) and not any(c in name for c in "/\\."):
        raise _input_error(f"unknown primitive {name.strip()!r} in SOURCE {text!r}; known primitives: {_known()}")
    if not sep and key in PRIMITIVES:
        spec = PRIMITIVES[key]
        raise _input_error(f"primitive {key!r} needs its dimensions: {spec.usage} ({spec.meaning}), "
                           f"e.g. {key}:" + ",".join(["0.1"] * (len(spec.params) - spec.optional)))
    if os.path.isdir(text):
        raise _mesh_file_error(f"SOURCE {text!r} is a directory, not a mesh file")
    raise _mesh_file_error(f"mesh file not found: {text!r} (SOURCE must be an existing mesh file or a "
                           f"primitive spec; known primitives: {_known()})")


def _mesh_file_error(msg: str):
    from .._core.errors import MeshFileError

    return MeshFileError(msg)


def _parse_numbers(text: str, spec: PrimitiveSpec, rest: str) -> list:
    parts = [s.strip() for s in rest.split(",")] if rest.strip() else []
    n_max = len(spec.params)
    n_min = n_max - spec.optional
    if not (n_min <= len(parts) <= n_max):
        want = str(n_max) if n_min == n_max else f"{n_min} or {n_max}"
        raise _input_error(f"{text!r}: {spec.name} takes {want} number{'s' if n_max > 1 else ''} "
                           f"({spec.usage}: {spec.meaning}), got {len(parts)}")
    values = []
    for pname, s in zip(spec.params, parts):
        try:
            v = float(s)
        except ValueError:
            raise _input_error(f"{text!r}: {spec.name} parameter {pname} = {s!r} is not a number "
                               f"({spec.usage}: {spec.meaning})") from None
        if not math.isfinite(v):
            raise _input_error(f"{text!r}: {spec.name} parameter {pname} = {s} must be finite")
        if v < 0 or (v == 0 and pname not in spec.zero_ok):
            raise _input_error(f"{text!r}: {spec.name} parameter {pname} = {s} must be positive "
                               f"({spec.usage}: {spec.meaning})")
        values.append(v)
    return values


def _resolve_mass_options(args, *, shell: bool, thin: str = "--shell"):
    """``(density, mass, density_source)`` from --density/--mass, with the default density."""
    density = getattr(args, "density", None)
    mass = getattr(args, "mass", None)
    if density is not None and mass is not None:
        raise _input_error(f"give either --mass or --density, not both (got --mass {mass:g} and --density {density:g})")
    if density is not None and not (math.isfinite(density) and density > 0):
        raise _input_error(f"--density must be a positive number of {'kg/m^2' if shell else 'kg/m^3'}, "
                           f"got {density:g}")
    if mass is not None and not (math.isfinite(mass) and mass > 0):
        raise _input_error(f"--mass must be a positive number of kg, got {mass:g}")
    if density is None and mass is None:
        if shell:
            raise _input_error(f"{thin} needs --mass (kg) or --density (kg/m^2, surface density): the default "
                               "1000 kg/m^3 is a volume density and does not apply to a thin shell")
        return DEFAULT_DENSITY, None, "default"
    if density is not None:
        return density, None, "--density"
    return None, mass, "from --mass"


# ---------------------------------------------------------------------------- loading


def load_source(args, *, source: str | None = None):
    """Compute the mass properties of SOURCE with the options in ``args``.

    Returns ``(props, info)``: a :class:`inertia.MassProperties` (SI units, frame of the
    mesh file or of the primitive) and a :class:`SourceInfo`.
    """
    text = args.source if source is None else source
    units = getattr(args, "units", "m") or "m"
    if units not in LENGTH_UNITS:
        raise _input_error(f"--units {units!r} is not one of {', '.join(LENGTH_UNITS)}")
    shell = bool(getattr(args, "shell", False))
    fix = bool(getattr(args, "fix_orientation", False))
    accept = bool(getattr(args, "accept_defects", False))
    robust = bool(getattr(args, "robust", False))
    robust_tol = float(getattr(args, "robust_tol", 1e-3) or 1e-3)
    robust_budget = getattr(args, "robust_budget", None)
    if robust_budget is not None and not (math.isfinite(robust_budget) and robust_budget > 0):
        raise _input_error(f"--robust-budget must be a positive number of seconds, got {robust_budget!r}")
    if robust_budget is not None and not robust:
        raise _input_error("--robust-budget applies with --robust only")
    if not (math.isfinite(robust_tol) and robust_tol > 0):
        raise _input_error(f"--robust-tol must be a positive number, got {robust_tol!r}")
    self_crossing = getattr(args, "self_crossing", "search") or "search"
    kind = classify_source(text)
    # a spherical_shell without inner radius is a thin shell: its density is per area
    thin_sphere = kind[0] == "primitive" and kind[1].name == "spherical_shell" and len(kind[2]) == 1
    if thin_sphere and shell:
        raise _input_error(f"{text!r} is already a thin shell (no inner radius given): drop --shell")
    density, mass, dsrc = _resolve_mass_options(
        args, shell=shell or thin_sphere, thin=f"the thin shell {text!r}" if thin_sphere else "--shell")
    command = f"inertia {getattr(args, 'command', None) or ''}".rstrip()
    if kind[0] == "mesh":
        props, stats = _load_mesh(kind[1], density=density, mass=mass, units=units, shell=shell,
                                  fix_orientation=fix, accept_defects=accept, command=command,
                                  robust=robust, robust_tol=robust_tol, robust_budget=robust_budget,
                                  self_crossing=self_crossing)
        info = SourceInfo(source=text, kind="mesh", units=units, density=0.0, density_source=dsrc, shell=shell)
        info.mesh = stats
    else:
        for flag, on in (("--fix-orientation", fix), ("--accept-defects", accept), ("--robust", robust)):
            if on:
                raise _input_error(f"{flag} applies to mesh files only, not to the primitive {text!r}")
        spec, numbers = kind[1], kind[2]
        dims = [v * LENGTH_UNITS[units] for v in numbers]
        props = _build_primitive(text, spec, dims, density=density, mass=mass, shell=shell)
        info = SourceInfo(source=text, kind="primitive", units=units, density=0.0, density_source=dsrc,
                          shell=shell or thin_sphere, primitive=spec.name, dimensions_m=tuple(dims))
    info.density = _effective_density(props, density, mass, info.shell)
    _unit_slip_notes(info, command)
    return props, info


def _unit_slip_notes(info, command: str) -> None:
    """Warn (stderr and ``info.notes``) when the size or density implies a unit slip."""
    import sys

    from .._core.units import density_warnings, size_warnings

    extent = info.mesh["extents"] if info.mesh is not None else info.dimensions_m
    info.notes = size_warnings(extent, info.units) + density_warnings(
        info.density, shell=info.shell, from_mass=info.density_source == "from --mass")
    for note in info.notes:
        print(f"{command}: warning: {note}", file=sys.stderr)


def _effective_density(props, density, mass, shell) -> float:
    if density is not None:
        return float(density)
    if shell:
        return math.nan  # area is not kept on MassProperties
    vol = props.volume
    return props.mass / vol if vol and math.isfinite(vol) and vol > 0 else math.nan


def cli_text(message: str) -> str:
    """A library message with its keyword advice (``kind='shell'``) written as CLI options (``--shell``)."""
    from ..massprops.mesh import REMEDY_FLAGS

    for api, cli in REMEDY_FLAGS.items():
        message = message.replace(api, cli)
    return message


def _load_mesh(path, *, density, mass, units, shell, fix_orientation, accept_defects, command="inertia",
               robust=False, robust_tol=1e-3, robust_budget=None, self_crossing="search"):
    import sys
    import warnings

    from .._core.errors import InertiaError
    from ..geometry.mesh_io import load_mesh
    from ..massprops.mesh import mesh_properties

    try:
        vertices, faces = load_mesh(path, units=units)
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            props = mesh_properties(vertices, faces, density=density, mass=mass,
                                    kind="shell" if shell else "solid",
                                    repair="orient" if fix_orientation else None,
                                    on_defect="robust" if robust else "warn" if accept_defects else "raise",
                                    frame="body", name=str(path), robust_tol=robust_tol,
                                    robust_budget=robust_budget, self_crossing=self_crossing,
                                    robust_progress=_robust_progress(command, robust_tol) if robust else None)
    except InertiaError as exc:
        msg = cli_text(str(exc).rstrip())
        if os.path.basename(path) not in msg:
            msg = f"{path}: {msg}"
        raise _with_message(exc, msg) from None
    # accepted defects are in props.findings (and so in the output); repeat them on stderr,
    # where a reader of piped JSON still sees them, as one line each and without source lines
    for w in caught:
        print(f"{command}: warning: {cli_text(str(w.message))}", file=sys.stderr)
    lo, hi = vertices.min(axis=0), vertices.max(axis=0)
    stats = {"n_vertices": int(len(vertices)), "n_faces": int(len(faces)), "bbox_min": lo.tolist(),
             "bbox_max": hi.tolist(), "extents": (hi - lo).tolist()}
    return props, stats


def _robust_progress(command: str, tol: float):
    """A progress hook for the robust refinement: one rewritten line on stderr when it is a terminal
    (nothing otherwise, so logs and pipes stay clean), cleared when the work ends."""
    import sys
    import time

    if not sys.stderr.isatty():
        return None
    last = [0.0]

    def show(fraction: float, bound: float) -> None:
        now = time.monotonic()
        if fraction < 1.0 and now - last[0] < 0.2:
            return
        last[0] = now
        said = f"error bound {bound:.2g}" if math.isfinite(bound) else "no bound yet"
        line = f"{command}: robust solid: {100 * fraction:3.0f}% done, {said} (target {tol:g})"
        sys.stderr.write("\r" + line + ("\r" + " " * len(line) + "\r" if fraction >= 1.0 else ""))
        sys.stderr.flush()

    return show


def _build_primitive(text, spec: PrimitiveSpec, dims, *, density, mass, shell):
    from .._core.errors import InertiaError
    from ..massprops import primitives

    fn = getattr(primitives, spec.name)
    kw = {"density": density} if density is not None else {"mass": mass}
    if shell:
        kw["kind"] = "shell"
    pos = (tuple(dims),) if spec.call == "tuple" else tuple(dims)
    try:
        return fn(*pos, **kw)
    except InertiaError as exc:
        raise _prefixed(exc, f"{text!r}: ") from None
    except TypeError as exc:
        if shell and "kind" in str(exc):
            raise _input_error(f"{text!r}: --shell is not available for {spec.name}") from None
        raise


def _prefixed(exc, prefix: str):
    """The same error type with ``prefix`` before its message (extra attributes kept)."""
    return _with_message(exc, prefix + str(exc))


def _with_message(exc, message: str):
    """The same error type with another message; attributes such as ``report`` are kept."""
    try:
        new = type(exc)(message)
    except TypeError:
        return exc
    new.__dict__.update(exc.__dict__)
    return new
