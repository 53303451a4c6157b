"""Mass properties of triangle meshes: the mesh is checked, optionally repaired, then integrated.

Three orthogonal choices: ``kind`` (a ``"solid"`` or a thin ``"shell"``), ``repair``
(``"orient"`` re-winds the faces consistently and outward first) and ``on_defect``, what to do
with the defects left: ``"raise"`` a :class:`~inertia.errors.MeshError` naming each (default),
``"warn"`` and integrate anyway, or integrate the ``"robust"`` solid of the surface with an
error bound.  Whatever the choice, empty meshes, non-finite coordinates and bad indices are
refused, and so is a solid whose volume is not positive.
"""

from __future__ import annotations

import math
import warnings

import numpy as np

from .._core.errors import InputError, MeshDefectWarning, MeshError
from .._core.findings import Finding
from .._core.tolerances import COORDINATE_LIMIT, coordinate_precision
from .._core.validation import resolve_mass
from ..geometry.checks import analyse_mesh, clean_analysis
from ..geometry.integrals import (
    REFINE_KAPPA,
    central_from_floats,
    central_inertia,
    shell_integrals,
    solid_integrals,
    solid_sums_floats,
)
from ..geometry.mesh_arrays import compact_vertices, faces_in_range, validate_inputs
from ..geometry.mesh_io import MERGE_RTOL, load_mesh
from ..geometry.orient import orient_analysed

__all__ = ["mesh_properties", "mesh_file_properties"]

KINDS = ("solid", "shell")
ON_DEFECT = ("raise", "warn", "robust")
REPAIRS = (None, "orient")
#: each keyword the remedies of a refusal name, and the command-line option that does the same
REMEDY_FLAGS = {"repair='orient'": "--fix-orientation", "on_defect='warn'": "--accept-defects",
                "kind='shell'": "--shell", "on_defect='robust'": "--robust"}
SELF_CROSSING = ("search", "certificate")

# Nothing can be computed with these, whatever the options.
_FATAL = ("empty", "non_finite", "out_of_range", "bad_index")
# Defects of the closed-surface topology: they matter for a solid only.
_SOLID_ONLY = frozenset({"open_edges", "non_manifold_edges", "inconsistent_winding", "inverted", "overlapping_shells",
                         "self_intersecting", "self_crossing_unchecked"})
_ORIENTATION = frozenset({"inconsistent_winding", "inverted"})

#: what to do about each defect nothing can be computed with
_FATAL_FIX = {"empty": "give a mesh with at least one triangle",
              "non_finite": "remove or repair the NaN/inf vertices",
              "out_of_range": "give coordinates within +-1e60 (check the units)",
              "bad_index": "make every face index a valid vertex index (0 <= i < V; negative indices are not wrapped)"}
#: how to repair each topology defect
_REPAIR = {"open_edges": "close the holes, or merge near-coincident vertices as inertia.load_mesh does",
           "duplicate_faces": "remove the duplicate faces",
           "non_manifold_edges": "separate parts that share edges",
           "overlapping_shells": "join the overlapping parts into one closed surface (a boolean union)",
           "self_intersecting": "resolve the self-intersection (a boolean union of the shell with itself)"}


def _remedies(codes: set, *, kind: str, repair) -> tuple:
    """The ``(keyword, value)`` options that would give a result for a mesh with ``codes``."""
    if codes & set(_FATAL):
        return ()
    out = []
    if codes & _ORIENTATION and repair is None:
        out.append(("repair", "orient"))
    if codes & {"open_edges", "non_manifold_edges"} and kind == "solid":
        out.append(("kind", "shell"))
    if kind == "solid":
        out.append(("on_defect", "robust"))
    out.append(("on_defect", "warn"))
    return tuple(out)


_REMEDY_TEXT = {("repair", "orient"): "to re-wind the faces consistently and outward",
                ("kind", "shell"): "for a thin shell (density in kg/m^2; open surfaces allowed)",
                ("on_defect", "robust"): "for the solid the surface most nearly bounds (generalised winding number), "
                                         "with an error bound",
                ("on_defect", "warn"): "to accept the result with the defects recorded as findings"}


def _defect_error(what: str, defects, report, *, kind: str, repair) -> MeshError:
    """One-paragraph MeshError naming each defect (code, count, example) and the options."""
    parts = "; ".join(f"{d.code}: {d.message}" for d in defects)
    codes = {d.code for d in defects}
    remedies = _remedies(codes, kind=kind, repair=repair)
    if codes & set(_FATAL):
        why = " Nothing can be computed from such a mesh: " + "; ".join(
            text for code, text in _FATAL_FIX.items() if code in codes) + "."
    else:
        if kind == "shell":
            why = " Duplicate faces count their area twice in a shell."
        elif codes == {"overlapping_shells"}:
            why = " The volume integrals of closed parts that overlap count the overlap twice."
        elif codes == {"self_intersecting"}:
            why = " The volume integrals of a surface that passes through itself count what it encloses twice."
        else:
            why = " The volume integrals of a surface that is not closed and consistently outward-wound are wrong."
        how = [text for code, text in _REPAIR.items() if code in codes]
        why += " Options: " + "; ".join([f"{k}={v!r} {_REMEDY_TEXT[(k, v)]}" for k, v in remedies]
                                        + ["repair the mesh" + (f" ({', '.join(how)})" if how else "")]) + "."
    noun = "a thin shell" if kind == "shell" else "a solid"
    return MeshError(f"{what} cannot be used as {noun}: {parts}.{why}", report=report, remedies=remedies)


def check_options(kind="solid", on_defect="raise", repair=None, self_crossing="search", density=None, mass=0.0,
                  what: str = "mesh") -> None:
    """Refuse unknown option values and the combinations that mean nothing, before any mesh work."""
    for name, value, allowed in (("kind", kind, KINDS), ("on_defect", on_defect, ON_DEFECT),
                                 ("repair", repair, REPAIRS), ("self_crossing", self_crossing, SELF_CROSSING)):
        if value not in allowed:
            raise InputError(f"{name} must be one of {allowed}, got {value!r}")
    if kind == "shell" and on_defect == "robust":
        raise InputError("on_defect='robust' integrates a solid; a thin shell (kind='shell') needs no closed "
                         "surface: use on_defect='raise' or 'warn'")
    if kind == "shell" and repair == "orient":
        raise InputError("repair='orient' winds a solid's faces outward; a thin shell's orientation does not "
                         "matter: leave repair=None")
    if (density is None) == (mass is None):
        raise InputError(f"{what}: give exactly one of density= or mass=, got "
                         f"{'both' if density is not None else 'neither'}")


def _mesh_properties(vertices, faces, *, density, mass, kind, on_defect, repair, frame, name, robust_tol,
                     robust_budget, self_crossing, stacklevel, welded=False, robust_progress=None):
    """:func:`mesh_properties` (``stacklevel`` points warnings at the caller; ``welded``: the
    vertices are distinct and all used, as :func:`load_mesh` returns them)."""
    what = f"mesh {name}" if name else "mesh"
    check_options(kind, on_defect, repair, self_crossing, density, mass, what)
    if on_defect == "robust" and not (robust_tol > 0):
        raise InputError(f"robust_tol must be positive, got {robust_tol!r}")
    v, f = validate_inputs(vertices, faces)
    where = name or ""

    def done(props):
        # a radius of gyration no larger than the largest: the precision errs on the coarse side
        I = props.inertia_com
        precision = coordinate_precision(v, math.sqrt(max(I[0, 0], I[1, 1], I[2, 2]) / props.mass))
        return props._with_precision(precision) if precision > props.precision else props

    if on_defect == "robust" and repair is None and kind == "solid":
        props = _robust_direct(v, f, welded, density=density, mass=mass, frame=frame, what=what, where=where,
                               tol=robust_tol, budget=robust_budget, progress=robust_progress,
                               stacklevel=stacklevel + 1)
        if props is not None:
            return done(props)
    analysis = analyse_mesh(v, f, welded=welded, weld_first=False, self_crossing=self_crossing)
    report = analysis.report
    if analysis.solid_sums is not None and kind == "solid":   # a clean solid: its sums came with the check
        return done(_clean_solid(analysis.solid_sums, v, f, density=density, mass=mass, frame=frame, what=what,
                                 findings=_notes(report, where, kind)))
    fatal = [d for d in report.findings if d.code in _FATAL]
    if fatal:
        raise _defect_error(what, fatal, report, kind=kind, repair=repair)

    findings: list = []
    if repair == "orient" and set(report.codes) & _ORIENTATION:
        f, n_flipped, analysis = orient_analysed(v, f, analysis, what)
        report = analysis.report
        findings.append(Finding("orientation_repaired", f"repair='orient' flipped {n_flipped} of {len(f)} faces",
                                where=where, values={"flipped": n_flipped, "faces": len(f)}))

    errors = [d for d in report.errors if not (kind == "shell" and d.code in _SOLID_ONLY)]
    if errors and on_defect == "robust":
        return done(_robust_solid(v, f, density=density, mass=mass, frame=frame, what=what, where=where,
                                  tol=robust_tol, budget=robust_budget, progress=robust_progress,
                                  findings=findings, stacklevel=stacklevel + 1))
    if errors and on_defect == "raise":
        raise _defect_error(what, errors, report, kind=kind, repair=repair)
    for d in errors:  # on_defect == "warn": accepted on request, loudly
        accepted = d.replace(severity="warning", where=where)
        warnings.warn(f"{what}: {d.code} accepted (on_defect='warn'): {d.message}", MeshDefectWarning,
                      stacklevel=stacklevel)
        findings.append(accepted)
    # Zero-area faces are a note, not an error: every term of the kernels is weighted by the
    # face's area (vector), so they contribute exactly nothing.
    findings += _notes(report, where, kind)

    # integrate over the referenced vertices only (unreferenced ones would move the
    # kernel's reference point and cost precision)
    vc, fc = (v, f) if welded else compact_vertices(v, f)
    from .properties import MassProperties

    if kind == "shell":
        area, first, second, r = shell_integrals(vc, fc)
        if not area > 0:
            raise MeshError(f"{what} has zero total area; a thin shell needs a surface.", report=report,
                            code="zero_area")
        m, rho = resolve_mass(area, density, mass, what=f"{what} (shell)", measure_name="area")
        com, inertia = central_inertia(area, first, second, r, rho, mass=m)
        return done(MassProperties(m, com, inertia, frame=frame, findings=tuple(findings)))
    volume, first, second, r = solid_integrals(vc, fc)
    if not volume > 0:
        # refused even with on_defect="warn": a non-positive volume has no mass distribution
        hint = "; repair='orient' re-winds an inward-wound closed mesh" if volume < 0 and repair is None else ""
        raise MeshError(f"{what} has signed volume {volume:.6g} <= 0, so it does not enclose a solid "
                        f"(faces wound inward, or a flat or open surface){hint}.", report=report,
                        code="non_positive_volume")
    m, rho = resolve_mass(volume, density, mass, what=what)
    com, inertia = central_inertia(volume, first, second, r, rho, mass=m)
    return done(MassProperties(m, com, inertia, frame=frame, volume=volume, findings=tuple(findings)))


def _notes(report, where: str, kind: str) -> list:
    """The report's notes, located (a shell's notes about solid topology are dropped)."""
    return [d.replace(where=where) for d in report.findings
            if d.severity == "note" and not (kind == "shell" and d.code in _SOLID_ONLY)]


def _clean_solid(sums, v, f, *, density, mass, frame, what, findings=()):
    """Mass properties from the volume sums of the compiled check; a body far from the
    kernel's reference point is integrated again about its COM (see :mod:`inertia.geometry.integrals`)."""
    from .properties import MassProperties

    volume, first, second, r, kappa = solid_sums_floats(sums)
    if kappa > REFINE_KAPPA:
        vc, fc = compact_vertices(v, f)
        volume, first, second, r = solid_integrals(vc, fc)
        first, second, r = first.tolist(), second.tolist(), r.tolist()
    m, rho = resolve_mass(volume, density, mass, what=what)   # refuses a volume that is not positive and finite
    com, inertia = central_from_floats(volume, first, second, r, rho, m)
    return MassProperties._computed(m, com, inertia, frame=frame, volume=volume, findings=tuple(findings))


def _robust_direct(v, f, welded, *, density, mass, frame, what, where, tol, budget, progress, stacklevel):
    """``on_defect="robust"`` without the full analysis (it costs as much as the robust solid):
    a clean solid takes the exact path; a mesh with nothing fatal goes to the robust solid,
    whose own pass names the defects; None otherwise (the full analysis then names the fatal ones)."""
    clean = clean_analysis(v, f, welded=welded)
    if clean is not None and clean.solid_sums is not None:
        return _clean_solid(clean.solid_sums, v, f, density=density, mass=mass, frame=frame, what=what,
                            findings=_notes(clean.report, where, "solid"))
    if not len(f) or not faces_in_range(f, len(v)):
        return None
    with np.errstate(invalid="ignore"):
        if not np.all(np.abs(v) <= COORDINATE_LIMIT):
            return None
    return _robust_solid(v, f, density=density, mass=mass, frame=frame, what=what, where=where, tol=tol,
                         budget=budget, progress=progress, findings=[], stacklevel=stacklevel + 1)


def _robust_solid(v, f, *, density, mass, frame, what, where, tol, budget, findings, stacklevel, progress=None):
    """The solid {w >= 1/2} of an imperfect mesh (:func:`inertia.geometry.robust.robust_integrals`):
    its findings, and one ``robust_solid`` finding carrying the bounds; ``precision`` is the
    inertia's bound."""
    from ..geometry.robust import robust_integrals
    from .properties import MassProperties

    res = robust_integrals(v, f, tol=tol, time_budget=budget, progress=progress)
    volume = float(res.volume)
    if not volume > 0:
        raise MeshError(f"{what}: the robust solid (generalised winding number >= 1/2) is empty: the surface "
                        f"encloses no volume ({'; '.join(d.message for d in res.findings) or 'no defect named'}).",
                        code="non_positive_volume")
    m, rho = resolve_mass(volume, density, mass, what=what)
    com, inertia = central_inertia(volume, np.asarray(res.first, float), np.asarray(res.second, float),
                                   np.asarray(res.reference, float), rho, mass=m)
    bounds = res.bounds
    text = (f"robust solid (the points of generalised winding number >= 1/2) of a mesh with "
            f"{', '.join(res.codes) or 'no defect'}; relative error bounds: "
            + ", ".join(f"{k} {x:.2g}" for k, x in bounds.items()))
    if not res.converged:
        text += f"; NOT within robust_tol {tol:g} (stopped by the {res.stopped_by or 'refinement budget'})"
    warnings.warn(f"{what}: {text}", MeshDefectWarning, stacklevel=stacklevel)
    robust = Finding("robust_solid", text, where=where,
                     values={"error_bound": res.error_bound, "bounds": bounds, "tol": tol, "converged": res.converged,
                             "stopped_by": res.stopped_by,
                             "ambiguous_volume": res.ambiguous_volume})
    found = [d.replace(severity="warning", where=where) for d in res.findings]
    # the inertia's relative bound is the result's precision (a bound of 1/2 or more says nothing)
    return MassProperties(m, com, inertia, frame=frame, volume=volume, findings=tuple(findings) + (robust, *found),
                          precision=min(bounds["inertia"], 0.5))


def mesh_properties(vertices, faces, *, density=None, mass=None, kind: str = "solid", on_defect: str = "raise",
                    repair: str | None = None, frame: str = "body", name: str | None = None,
                    robust_tol: float = 1e-3, robust_budget: float | None = None, robust_progress=None,
                    self_crossing: str = "search"):
    """Mass properties of a triangle mesh, checked for defects first.

    Parameters
    ----------
    vertices : (V, 3) float, m, in the frame ``frame``.
    faces : (F, 3) int, vertex indices, counter-clockwise seen from outside.
    density : float, kg/m^3 (kg/m^2 for a shell); or
    mass : float, kg (exactly one of the two).
    kind : {"solid", "shell"}
        ``"shell"``: a thin shell of uniform surface density (open surfaces and any winding allowed).
    on_defect : {"raise", "warn", "robust"}
        What to do with the defects that would make the result wrong: raise
        :class:`~inertia.errors.MeshError` (default); accept them (a :class:`MeshDefectWarning`,
        and each defect in ``findings`` as a warning); or integrate the solid of points whose
        generalised winding number is at least 1/2 (solids only), with relative error bounds
        refined below ``robust_tol``, in a ``robust_solid`` finding and in ``precision``.
    repair : {None, "orient"}
        ``"orient"``: re-wind the faces consistently per component and outward first (solids only).
    frame : str, name of the frame of ``vertices``.
    name : str, optional, how messages and findings name the mesh (e.g. its file path).
    robust_tol : float, the relative bound the robust solid aims at (default 1e-3).
    robust_budget : float, optional, seconds the robust refinement may take (default: no limit);
        when it runs out the result carries the bound reached (``robust_solid`` finding).
    robust_progress : callable, optional, ``robust_progress(fraction, bound)`` while the robust
        refinement runs: the fraction of the work done and the relative bound reached so far.
    self_crossing : {"search", "certificate"}
        How a closed shell is shown not to pass through itself: ``"search"`` proves it in one
        pass when it is star-shaped from its COM and otherwise tests face pairs (up to 200,000
        faces); ``"certificate"`` only tries the proof, and notes ``self_crossing_unchecked``.

    Returns
    -------
    MassProperties
        SI units in ``frame``; ``volume`` NaN for shells; ``findings`` (notes, accepted
        defects, repairs, the robust solid's bounds); ``precision``, the relative precision
        the input allows (float32 coordinates, a robust bound).

    Raises
    ------
    MeshError
        The mesh has defects (``.report`` is the full :class:`~inertia.geometry.MeshReport`,
        ``.remedies`` the options that would give a result).
    InputError
        Wrong shapes or types, both or neither of density and mass, an unknown option or a
        combination that means nothing (a shell with ``on_defect="robust"`` or ``repair``).

    Notes
    -----
    The integrals are exact for a closed, consistently outward-wound surface (divergence
    theorem; Eberly, "Polyhedral mass properties").

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> p = mesh_properties(v, f, density=6.0)
    >>> round(p.mass, 12), p.com.shape, p.inertia_com.shape
    (1.0, (3,), (3, 3))
    """
    return _mesh_properties(vertices, faces, density=density, mass=mass, kind=kind, on_defect=on_defect,
                            repair=repair, frame=frame, name=name, robust_tol=robust_tol,
                            robust_budget=robust_budget, self_crossing=self_crossing, stacklevel=3,
                            robust_progress=robust_progress)


def mesh_file_properties(path, *, density=None, mass=None, units: str = "m", kind: str = "solid",
                         on_defect: str = "raise", repair: str | None = None, frame: str = "body",
                         merge_rtol: float = MERGE_RTOL, robust_tol: float = 1e-3, robust_budget: float | None = None,
                         robust_progress=None, self_crossing: str = "search"):
    """Mass properties of the triangle mesh in a file: :func:`inertia.load_mesh` (``units``,
    ``merge_rtol``), then :func:`mesh_properties` (the other options); messages name the file.

    ``density`` is kg/m^3 (kg/m^2 for a shell) whatever the file's ``units``: coordinates are
    converted to metres first.  Returns MassProperties in the file's frame, SI units.
    """
    vertices, faces = load_mesh(path, units=units, merge_rtol=merge_rtol)
    return _mesh_properties(vertices, faces, density=density, mass=mass, kind=kind, on_defect=on_defect,
                            repair=repair, frame=frame, name=str(path), robust_tol=robust_tol,
                            robust_budget=robust_budget, self_crossing=self_crossing, stacklevel=3,
                            welded=merge_rtol > 0, robust_progress=robust_progress)
