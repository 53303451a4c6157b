"""Write a corrected copy of a robot file: its inertials recomputed or made physical.

Two repairs, chosen per run:

* ``mode="geometry"``: every link with an inertial gets the mass properties of its own
  geometry (:func:`~inertia.robots.geometry.link_geometry_properties`; collision shapes, or
  visual ones with ``role="visual"`` or when there are no collision shapes), at the declared
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

import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .._core.errors import InputError
from .geometry import link_geometry_properties
from .io import read_robot
from .writers import format_number, format_vector, inertia_elements
from .xmlsafe import serialize

#: smallest principal moment the projection allows, relative to the trace
MIN_MOMENT_RTOL = 1e-6


def nearest_physical_inertia(inertia, *, min_rtol: float = MIN_MOMENT_RTOL) -> np.ndarray:
    """The physical tensor nearest to ``inertia`` in the Frobenius norm, with the same axes.

    Method: in the principal axes of the declared tensor, project the three moments onto
    the convex set ``{I_i >= min_rtol * trace, I_i + I_j >= I_k}`` (Euclidean projection,
    solved exactly as a 3-variable quadratic program with SLSQP); the axes are kept, so the
    result is the nearest physical tensor among those sharing the declared principal axes.
    A tensor that is already physical is returned unchanged.
    """
    from scipy.optimize import minimize

    from ..massprops.validity import check_inertia

    I = 0.5 * (np.asarray(inertia, float) + np.asarray(inertia, float).T)
    if not check_inertia(I):
        return I
    w, V = np.linalg.eigh(I)
    floor = min_rtol * max(abs(float(np.sum(w))), float(np.abs(w).max()), 1e-300)
    cons = [{"type": "ineq", "fun": (lambda x, i=i: x[i] - floor)} for i in range(3)]
    for i, j, k in ((0, 1, 2), (1, 2, 0), (2, 0, 1)):
        cons.append({"type": "ineq", "fun": (lambda x, i=i, j=j, k=k: x[i] + x[j] - x[k])})
    res = minimize(lambda x: float(np.sum((x - w) ** 2)), np.maximum(w, floor), jac=lambda x: 2 * (x - w),
                   constraints=cons, method="SLSQP", options={"ftol": 1e-15, "maxiter": 200})
    x = res.x
    # clean up SLSQP's last-digit residue so the result passes the validity check exactly
    x = np.maximum(x, floor)
    order = np.argsort(x)
    if x[order[0]] + x[order[1]] < x[order[2]]:
        x[order[2]] = x[order[0]] + x[order[1]]
    return (V * x) @ V.T


@dataclass
class FixReport:
    """What a fix changed: ``changed`` maps link name -> a one-line description."""

    output: str
    changed: dict = field(default_factory=dict)
    skipped: dict = field(default_factory=dict)


def _set_tensor(fmt: str, el, inertia, mass_scale: float) -> None:
    """Rewrite only the tensor of an inertial element, in its own (declared) axes."""
    e = inertia_elements(np.asarray(inertia) / mass_scale)
    if fmt == "urdf":
        i_el = el.find("inertia")
        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
            i_el.set(k, format_number(e[k]))
    elif fmt == "sdf":
        i_el = el.find("inertia")
        if i_el is None:
            i_el = ET.SubElement(el, "inertia")
        for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
            c = i_el.find(k)
            if c is None:
                c = ET.SubElement(i_el, k)
            c.text = format_number(e[k])
    elif "diaginertia" in el.attrib and max(abs(e["ixy"]), abs(e["ixz"]), abs(e["iyz"])) == 0:
        el.set("diaginertia", " ".join(format_number(e[k]) for k in ("ixx", "iyy", "izz")))
    else:
        el.attrib.pop("diaginertia", None)
        el.set("fullinertia", " ".join(format_number(e[k]) for k in ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")))


def _set_urdf(el, props, mass_scale: float) -> None:
    origin = el.find("origin")
    if origin is None:
        origin = ET.Element("origin")
        el.insert(0, origin)
    origin.set("xyz", format_vector(props.com))
    origin.set("rpy", "0 0 0")
    m = el.find("mass")
    m.set("value", format_number(props.mass / mass_scale))
    i_el = el.find("inertia")
    e = inertia_elements(props.inertia_com)
    for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
        i_el.set(k, format_number(e[k] / mass_scale))


def _set_sdf(el, props, mass_scale: float) -> None:
    pose = el.find("pose")
    if pose is None:
        pose = ET.Element("pose")
        el.insert(0, pose)
    pose.text = f"{format_vector(props.com)} 0 0 0"
    for a in list(pose.attrib):
        if a == "relative_to":
            del pose.attrib[a]
    m = el.find("mass")
    if m is None:
        m = ET.SubElement(el, "mass")
    m.text = format_number(props.mass / mass_scale)
    i_el = el.find("inertia")
    if i_el is None:
        i_el = ET.SubElement(el, "inertia")
    e = inertia_elements(props.inertia_com)
    for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz"):
        c = i_el.find(k)
        if c is None:
            c = ET.SubElement(i_el, k)
        c.text = format_number(e[k] / mass_scale)


def _set_mjcf(el, props, mass_scale: float) -> None:
    for a in ("quat", "euler", "axisangle", "xyaxes", "zaxis", "diaginertia", "fullinertia"):
        el.attrib.pop(a, None)
    e = inertia_elements(props.inertia_com)
    el.set("pos", format_vector(props.com))
    el.set("mass", format_number(props.mass / mass_scale))
    keys = ("ixx", "iyy", "izz", "ixy", "ixz", "iyz")
    el.set("fullinertia", " ".join(format_number(e[k] / mass_scale) for k in keys))


def fix_file(path, output=None, *, mode: str = "nearest", role: str | None = None, density: float | None = None,
             in_place: bool = False, search_paths=(), mesh_units: str = "m", mass_scale: float = 1.0) -> FixReport:
    """Write the corrected copy (see the module docstring); returns what changed.

    ``mass_scale`` is the file's mass unit in kg (1e-3 for grams): declared values are read
    and written in the file's units.
    """
    path = Path(path)
    if mode not in ("nearest", "geometry", "flip"):
        raise InputError(f"mode must be 'nearest', 'geometry' or 'flip', got {mode!r}")
    if in_place:
        if output is not None and Path(output).resolve() != path.resolve():
            raise InputError("give either -o OUT or --in-place, not both")
        output = path
    if output is None:
        raise InputError("give -o OUT for the corrected copy (or --in-place to replace the input)")
    output = Path(output)
    if output.resolve() == path.resolve() and not in_place:
        raise InputError(f"{output} is the input file: pass --in-place to overwrite it")
    model = read_robot(path, search_paths=search_paths)
    included = getattr(model.document, "included", [])
    if included:
        raise InputError(f"{path} includes other files ({', '.join(p.name for p in included)}); fix the file "
                         "that holds the inertials instead, so that no change is lost")
    if getattr(model.document, "generated_by", None) == "xacro":
        raise InputError(f"{path} is a xacro file: its inertials come from macros and arguments, so no fix can be "
                         "written back into it; fix its expanded file instead (xacro FILE > robot.urdf)")
    setter = {"urdf": _set_urdf, "sdf": _set_sdf, "mjcf": _set_mjcf}[model.format]
    report = FixReport(str(output))
    for link in model.links:
        inertial = link.inertial
        if inertial is None:
            continue
        mass = inertial.mass * mass_scale
        if mode == "flip":
            # only where the declared tensor is not physical and the flipped one is
            from ..massprops.validity import check_inertia
            from .check import flip_products

            own = inertial.inertia_declared * mass_scale
            flipped = flip_products(own)
            if check_inertia(own) and not check_inertia(flipped):
                report.changed[link.name] = "products of inertia negated (CAD sign -> tensor elements)"
                _set_tensor(model.format, inertial.element, flipped, mass_scale)
            continue
        if mode == "nearest":
            # the projection commutes with rotations: fix the tensor in its declared axes and
            # rewrite nothing else (COM, mass and frame stay as written)
            declared_own = inertial.inertia_declared * mass_scale
            fixed = nearest_physical_inertia(declared_own)
            if np.array_equal(fixed, 0.5 * (declared_own + declared_own.T)):
                continue
            before = np.array2string(np.linalg.eigvalsh(declared_own), precision=6)
            after = np.array2string(np.linalg.eigvalsh(fixed), precision=6)
            report.changed[link.name] = (f"principal moments {before} -> {after} kg m^2 "
                                         "(nearest physical, same axes)")
            _set_tensor(model.format, inertial.element, fixed, mass_scale)
            continue
        props, used, problems = link_geometry_properties(
            link, role=role, mass=None if density is not None else mass,
            density=density if density is not None else 1000.0, mesh_units=mesh_units)
        if props is None:
            report.skipped[link.name] = "; ".join(m for _, m in problems) or "no geometry"
            continue
        report.changed[link.name] = (f"from its {used} geometry: mass {props.mass:.6g} kg, COM "
                                     f"{np.round(props.com, 6).tolist()} m, moments "
                                     f"{np.array2string(props.principal()[0], precision=6)} kg m^2"
                                     + "".join(f"; note: {m}" for _, m in problems))
        setter(inertial.element, props, mass_scale)
    from .._core.atomic import write_bytes_atomic

    write_bytes_atomic(output, serialize(model.document))
    return report
