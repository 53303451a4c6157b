"""Write a corrected copy of a robot file: its inertials recomputed or made physical.

Two repairs, chosen per run:

* ``mode="geometry"``: each link whose inertial is not physical (every link with an inertial
  with ``links="all"``) gets the mass properties of its own geometry
  (:func:`~inertia.robots.geometry.link_geometry_properties`; collision shapes, or visual ones
  with ``role="visual"`` or when there are no collision shapes), at the declared
  mass, or at ``density`` [kg/m^3] (the mass then follows from the volume).  Links whose
  geometry cannot be used keep their inertial and are reported.
* ``mode="nearest"`` (default): only links whose tensor is not physical change, to
  :func:`nearest_physical_inertia` of the declared one.
* ``mode="flip"``: only links whose tensor is not physical but becomes physical with its
  products negated get them negated (products copied from CAD with the wrong sign).

The output is written atomically; the input is only replaced with ``in_place=True``.
Everything else in the file (comments, other elements, attribute order) is kept; only the
inertial's own elements and attributes are rewritten.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .._core.tolerances import SIMULATOR_MIN_VALUE
from .check import flip_products, inertia_violations
from .edit import SourceEditor
from .geometry import link_geometry_properties
from .io import read_robot
from .writers import format_number, format_vector, inertia_elements

#: smallest principal moment the projection allows, relative to the trace (and never below
#: :data:`~inertia._core.tolerances.SIMULATOR_MIN_VALUE`, the least MuJoCo accepts); the
#: repaired moments also keep this margin inside each triangle inequality (I_i + I_j - I_k), so
#: the result is inside the physical set, not on its boundary where rounding can undo it
MIN_MOMENT_RTOL = 1e-6


def below_floor(inertia) -> bool:
    """The tensor's smallest principal moment is below what simulators accept for a moving
    body (:data:`~inertia._core.tolerances.SIMULATOR_MIN_VALUE` kg m^2)."""
    I = np.asarray(inertia, float)
    with np.errstate(all="ignore"):
        return not bool(np.linalg.eigvalsh(0.5 * (I + I.T))[0] >= SIMULATOR_MIN_VALUE)


def nearest_physical_inertia(inertia, *, min_rtol: float = MIN_MOMENT_RTOL) -> np.ndarray:
    """The physical tensor nearest to ``inertia`` in the Frobenius norm, with the same axes.

    Method: in the principal axes of the declared tensor, project the three moments onto
    the convex set ``{I_i >= floor, I_i + I_j - I_k >= floor}`` with ``floor = max(min_rtol *
    trace, SIMULATOR_MIN_VALUE)``: a stated margin inside the physical cone.  The set is a
    polyhedron, so the projection is the projection onto the affine hull of one of its faces:
    every subset of active constraints is tried (64
    small least-squares problems) and the nearest feasible candidate kept, exact to rounding.
    The axes are kept, so the result is the nearest physical tensor among those sharing the
    declared principal axes.  A tensor that is already physical is returned unchanged.
    """
    I = 0.5 * (np.asarray(inertia, float) + np.asarray(inertia, float).T)
    if not inertia_violations(I):
        return I
    w, V = np.linalg.eigh(I)
    floor = max(min_rtol * max(abs(float(np.sum(w))), float(np.abs(w).max())), SIMULATOR_MIN_VALUE)
    x = _project_moments(w, floor)
    # the candidates meet their active constraints to rounding: make them hold exactly
    x = np.maximum(x, floor)
    order = np.argsort(x)
    if x[order[0]] + x[order[1]] - x[order[2]] < floor:
        x[order[2]] = x[order[0]] + x[order[1]] - floor
    return (V * x) @ V.T


#: the constraints a x >= b of repaired moments: x_i >= floor and x_i + x_j - x_k >= floor
_PHYSICAL_A = np.array([[1, 0, 0], [0, 1, 0], [0, 0, 1], [1, 1, -1], [1, -1, 1], [-1, 1, 1]], float)


def _project_moments(w, floor: float) -> np.ndarray:
    """Euclidean projection of ``w`` onto ``{x_i >= floor, x_i + x_j - x_k >= floor}`` by active sets."""
    import itertools

    A = _PHYSICAL_A
    b = np.full(6, floor)
    scale = max(float(np.abs(w).max()), floor)
    best, best_d = None, np.inf
    for k in range(4):   # at most 3 independent constraints are active at a point in 3D
        for act in itertools.combinations(range(6), k):
            x = w.copy()
            if act:
                Aa, ba = A[list(act)], b[list(act)]
                G = Aa @ Aa.T
                if abs(np.linalg.det(G)) < 1e-12:
                    continue
                x = w - Aa.T @ np.linalg.solve(G, Aa @ w - ba)
            if np.all(A @ x - b >= -1e-12 * scale):
                d = float(np.sum((x - w) ** 2))
                if d < best_d:
                    best, best_d = x, d
    return best


@dataclass
class FixReport:
    """What a fix changed: ``changed`` maps link name -> a one-line description."""

    output: str
    changed: dict = field(default_factory=dict)
    skipped: dict = field(default_factory=dict)
    #: the output is byte-identical to the input (nothing needed changing)
    identical: bool = False
    #: link name -> why it is still invalid in the output
    remaining: dict = field(default_factory=dict)


def _tensor_numbers(fmt: str, inertia, mass_scale: float) -> dict:
    e = inertia_elements(np.asarray(inertia, float) / mass_scale)
    return {k: e[k] for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}


def _set_tensor(ed: SourceEditor, fmt: str, el, inertia, mass_scale: float) -> None:
    """Rewrite only the tensor of an inertial element, in its own (declared) axes."""
    e = _tensor_numbers(fmt, inertia, mass_scale)
    if fmt == "urdf":
        _urdf_inertia(ed, el, e)
    elif fmt == "sdf":
        _sdf_inertia(ed, el, e)
    else:
        _mjcf_inertia(ed, el, e)


def _urdf_inertia(ed: SourceEditor, el, e: dict) -> None:
    i_el = el.find("inertia")
    if i_el is None:
        ed.append_child(el, "<inertia " + " ".join(f'{k}="{format_number(v)}"' for k, v in e.items()) + "/>")
        return
    for k, v in e.items():
        ed.set_numbers(i_el, k, [v])


def _sdf_inertia(ed: SourceEditor, el, e: dict) -> None:
    i_el = el.find("inertia")
    if i_el is None:
        ed.append_child(el, "<inertia>" + "".join(f"<{k}>{format_number(v)}</{k}>" for k, v in e.items())
                        + "</inertia>")
        return
    for k, v in e.items():
        c = i_el.find(k)
        if c is None:
            ed.append_child(i_el, f"<{k}>{format_number(v)}</{k}>")
        else:
            ed.set_text_numbers(c, [v])


def _mjcf_inertia(ed: SourceEditor, el, e: dict) -> None:
    diagonal = max(abs(e["ixy"]), abs(e["ixz"]), abs(e["iyz"])) == 0
    if "diaginertia" in el.attrib and diagonal:
        ed.set_numbers(el, "diaginertia", [e["ixx"], e["iyy"], e["izz"]])
        return
    ed.remove_attribute(el, "diaginertia")
    ed.set_numbers(el, "fullinertia", [e[k] for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")])


def _set_urdf(ed: SourceEditor, el, props, mass_scale: float) -> None:
    origin = el.find("origin")
    if origin is None:
        ed.append_child(el, f'<origin xyz="{format_vector(props.com)}" rpy="0 0 0"/>')
    else:
        ed.set_numbers(origin, "xyz", props.com)
        ed.set_numbers(origin, "rpy", [0.0, 0.0, 0.0], default=[0.0, 0.0, 0.0])
    m = el.find("mass")
    if m is None:
        ed.append_child(el, f'<mass value="{format_number(props.mass / mass_scale)}"/>')
    else:
        ed.set_numbers(m, "value", [props.mass / mass_scale])
    _urdf_inertia(ed, el, _tensor_numbers("urdf", props.inertia_com, mass_scale))


def _set_sdf(ed: SourceEditor, el, props, mass_scale: float) -> None:
    pose = el.find("pose")
    if pose is None:
        ed.append_child(el, f"<pose>{format_vector(props.com)} 0 0 0</pose>")
    else:
        for a in ("relative_to", "degrees", "rotation_format"):
            ed.remove_attribute(pose, a)
        ed.set_text_numbers(pose, [*props.com, 0.0, 0.0, 0.0])
    m = el.find("mass")
    if m is None:
        ed.append_child(el, f"<mass>{format_number(props.mass / mass_scale)}</mass>")
    else:
        ed.set_text_numbers(m, [props.mass / mass_scale])
    _sdf_inertia(ed, el, _tensor_numbers("sdf", props.inertia_com, mass_scale))


def _set_mjcf(ed: SourceEditor, el, props, mass_scale: float) -> None:
    for a in ("quat", "euler", "axisangle", "xyaxes", "zaxis"):
        ed.remove_attribute(el, a)
    ed.set_numbers(el, "pos", props.com)
    ed.set_numbers(el, "mass", [props.mass / mass_scale])
    _mjcf_inertia(ed, el, _tensor_numbers("mjcf", props.inertia_com, mass_scale))


def _output_path(path: Path, output, in_place: bool) -> Path:
    if in_place:
        if output is not None and Path(output).resolve() != path.resolve():
            raise InputError("give either -o OUT or --in-place, not both")
        output = path
    if output is None:
        raise InputError("give -o OUT for the corrected copy (or --in-place to replace the input)")
    output = Path(output)
    if output.resolve() == path.resolve() and not in_place:
        raise InputError(f"{output} is the input file: pass --in-place to overwrite it")
    return output


def _moments(I) -> str:
    return np.array2string(np.linalg.eigvalsh(0.5 * (I + I.T)), precision=6)


def _fix_flip(ed, fmt, inertial, own, mass_scale, report, name) -> None:
    """Negate the products where the declared tensor is not physical and the flipped one is."""
    flipped = flip_products(own)
    if inertia_violations(own) and not inertia_violations(flipped) and not below_floor(flipped):
        report.changed[name] = "products of inertia negated (CAD sign -> tensor elements)"
        _set_tensor(ed, fmt, inertial.element, flipped, mass_scale)
        return inertial.mass * mass_scale, flipped
    return None


def _fix_nearest(ed, fmt, inertial, own, mass_scale, report, name) -> None:
    """The nearest physical tensor in the declared axes; COM, mass and frame stay as written.

    A tensor below the simulators' floor (zero, or rounding noise) has no meaningful nearest
    tensor: the link is skipped with the reason, never written as 1e-41 kg m^2."""
    if inertial.mass <= 0 and not np.any(own):
        return None  # a massless frame (mass 0, tensor 0): an idiom, nothing to fix
    w = np.linalg.eigvalsh(0.5 * (own + own.T))
    if float(np.max(np.abs(w))) < SIMULATOR_MIN_VALUE:
        report.skipped[name] = (f"its tensor is zero or rounding noise (largest moment {float(np.max(np.abs(w))):.3g} "
                                f"kg m^2, below {SIMULATOR_MIN_VALUE:g}, the least MuJoCo accepts for a moving "
                                "body): no nearest tensor means anything; recompute it with --from-geometry or "
                                "declare it")
        return None
    fixed = nearest_physical_inertia(own)
    if np.array_equal(fixed, 0.5 * (own + own.T)):
        return None
    report.changed[name] = (f"principal moments {_moments(own)} -> {_moments(fixed)} kg m^2 "
                            "(nearest physical, same axes)")
    _set_tensor(ed, fmt, inertial.element, fixed, mass_scale)
    return inertial.mass * mass_scale, fixed


def _declared_valid(own, mass: float) -> bool:
    """A declared inertial that needs no repair: positive mass, a physical tensor above the floor,
    or the massless-frame idiom (mass 0, tensor 0)."""
    if mass == 0 and not np.any(own):
        return True
    return mass > 0 and not inertia_violations(own) and not below_floor(own)


def _fix_geometry(ed, setter, link, mass, report, *, role, density, mesh_units, mass_scale) -> None:
    props, used, problems = link_geometry_properties(
        link, role=role, mass=None if density is not None else mass,
        density=density if density is not None else 1000.0, mesh_units=mesh_units)
    if props is None:
        report.skipped[link.name] = "; ".join(m for _, m in problems) or "no geometry"
        return None
    report.changed[link.name] = (f"from its {used} geometry: mass {props.mass:.6g} kg, COM "
                                 f"{np.round(props.com, 6).tolist()} m, moments "
                                 f"{np.array2string(props.principal().moments, precision=6)} kg m^2"
                                 + "".join(f"; note: {m}" for _, m in problems))
    setter(ed, link.inertial.element, props, mass_scale)
    return props.mass, props.inertia_com


class _Elsewhere:
    """An editor for inertials of other files (an MJCF ``<include>`` or ``<attach>``): it edits
    nothing, and records that a change was asked for."""

    def __init__(self):
        self.asked = False

    def __getattr__(self, name):
        def record(*args, **kwargs):
            self.asked = True
        return record


def fix_file(path, output=None, *, mode: str = "nearest", role: str | None = None, density: float | None = None,
             in_place: bool = False, search_paths=(), mesh_units: str = "m", mass_scale: float = 1.0,
             links: str = "invalid") -> FixReport:
    """Write the corrected copy (see the module docstring); returns what changed.

    The output is the input's bytes with only the changed numbers (or inertial elements)
    replaced; with nothing to change it is identical (``report.identical``).  Whether the
    output is valid is :func:`~inertia.robots.check.check_model`'s judgement of it (its
    errors), the same as ``inertia check`` of the written file: ``report.remaining`` maps each
    link it still finds errors in (and ``"(file)"`` for the file as a whole) to them.
    ``mass_scale`` is the file's mass unit in kg (1e-3 for grams): declared values are read
    and written in the file's units.  ``links``: ``"invalid"`` (default) changes only links whose
    declared inertial is not physical (or below the simulators' floor); ``"all"`` (geometry mode
    only) recomputes every link with an inertial.
    """
    path = Path(path)
    if mode not in ("nearest", "geometry", "flip"):
        raise InputError(f"mode must be 'nearest', 'geometry' or 'flip', got {mode!r}")
    if links not in ("invalid", "all"):
        raise InputError(f"links must be 'invalid' or 'all', got {links!r}")
    if links == "all" and mode != "geometry":
        raise InputError("links='all' recomputes valid inertials from geometry: it needs mode='geometry'")
    output = _output_path(path, output, in_place)
    model = read_robot(path, search_paths=search_paths)
    if getattr(model.document, "generated_by", None) == "xacro":
        raise InputError(f"{path} is a xacro file: its inertials come from macros and arguments, so no fix can be "
                         "written back into it; fix its expanded file instead (xacro FILE > robot.urdf)")
    ed = SourceEditor(model.document)
    setter = {"urdf": _set_urdf, "sdf": _set_sdf, "mjcf": _set_mjcf}[model.format]
    report = FixReport(str(output))
    edited: set = set()
    elsewhere: list = []
    for link in model.links:
        inertial = link.inertial
        if inertial is None or id(inertial.element) in edited:
            continue    # an MJCF <replicate> copies one <inertial>: it is fixed once, for every copy
        edited.add(id(inertial.element))
        own, mass = inertial.inertia_com_inertial * mass_scale, inertial.mass * mass_scale
        this = ed if model.document.start_byte(inertial.element) is not None else _Elsewhere()
        if mode == "flip":
            _fix_flip(this, model.format, inertial, own, mass_scale, report, link.name)
        elif mode == "nearest":
            _fix_nearest(this, model.format, inertial, own, mass_scale, report, link.name)
        elif links == "all" or not _declared_valid(own, mass):
            _fix_geometry(this, setter, link, mass, report, role=role, density=density,
                          mesh_units=mesh_units, mass_scale=mass_scale)
        if this is not ed and this.asked:
            elsewhere.append(f"{link.name!r} ({model.document.where(inertial.element)})")
    if elsewhere:
        raise InputError(f"{path}: the inertials to fix are in files it includes or attaches: "
                         f"{', '.join(elsewhere[:5])}{' ...' if len(elsewhere) > 5 else ''}; fix the file that holds "
                         "them instead, so that no change is lost")
    data = ed.result()
    report.identical = data == model.document.source
    report.remaining = _output_errors(model, data, path, search_paths, mesh_units, mass_scale)
    from .._core.atomic import write_bytes_atomic

    write_bytes_atomic(output, data)
    return report


def _output_errors(model, data: bytes, path: Path, search_paths, mesh_units: str, mass_scale: float) -> dict:
    """``inertia check``'s errors on the output ``data``, read as if it stood at ``path`` (its
    meshes and includes where the input's are): link name (``"(file)"``) -> messages."""
    from . import mjcf, urdf_sdf
    from .check import check_model
    from .xmlsafe import parse_xml_bytes

    doc = parse_xml_bytes(data, path)
    reader = {"urdf": urdf_sdf.read_urdf, "sdf": urdf_sdf.read_sdf, "mjcf": mjcf.read_mjcf}[model.format]
    fixed = reader(path, search_paths=search_paths, document=doc)
    for link in fixed.links:
        if link.inertial is not None and mass_scale != 1.0:
            link.inertial.mass *= mass_scale
            link.inertial.inertia_com_inertial = link.inertial.inertia_com_inertial * mass_scale
    found = check_model(fixed, mesh_units=mesh_units, warnings=False)
    out = {"(file)": "; ".join(str(e) for e in found.errors)} if found.errors else {}
    for lk in found.links:
        if lk.errors:
            out[lk.name] = "; ".join(f"{e.code}: {e}" for e in lk.errors)
    return out
