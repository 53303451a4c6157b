"""Mass properties of triangle meshes given as arrays (defect checks, then the exact kernel).

Policy: the mesh is checked first (:func:`inertia.geometry.checks.check_mesh`).  By
default any defect that makes the result wrong raises :class:`inertia.errors.MeshError`
naming every defect with its count and an example location; keyword options let the
caller choose otherwise:

* ``fix_orientation=True``: re-orient faces consistently per component and outward;
* ``shell=True``: a thin shell of uniform surface density (open surfaces allowed,
  orientation irrelevant);
* ``on_defect="warn"``: accept the remaining defects, with :class:`MeshDefectWarning`
  warnings that are also recorded in ``MassProperties.warnings``.

Empty meshes, non-finite coordinates and out-of-range indices are always refused (there is
nothing meaningful to compute), and so is a solid whose signed volume is not positive.
"""

from __future__ import annotations

import warnings

import numpy as np

from .._core.errors import InputError, MeshDefectWarning, MeshError
from .._core.tolerances import COORDINATE_LIMIT
from .._core.validation import resolve_mass
from ..geometry.checks import analyse_mesh
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

__all__ = ["mesh_properties", "validate_inputs", "MeshDefectWarning", "ON_DEFECT"]

#: Accepted values of ``on_defect``.
ON_DEFECT = ("raise", "warn")
#: Accepted values of ``self_crossing`` (see :func:`mesh_properties`).
SELF_CROSSING = ("search", "certificate")

# Nothing can be computed with these, whatever the options.
_FATAL = ("empty", "non_finite", "out_of_range", "bad_index")
# Defects of the closed-surface topology: they matter for a solid only.
_SOLID_ONLY = frozenset({"open_edges", "non_manifold_edges", "inconsistent_winding", "inverted", "overlapping_shells",
                         "self_intersecting", "self_crossing_unchecked"})
_ORIENTATION = frozenset({"inconsistent_winding", "inverted"})


def _check_mass_args(density, mass, what: str) -> None:
    """Fail early (before any mesh work) when not exactly one of density / mass is given."""
    if (density is None) == (mass is None):
        raise InputError(f"{what}: give exactly one of density= or mass=, got "
                         f"{'both' if density is not None else 'neither'}")


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


def _options_text(codes: set, *, shell: bool, fix_orientation: bool) -> str:
    """The sentence suggesting what the caller can do about ``codes``."""
    if codes & set(_FATAL):
        fixes = [text for code, text in _FATAL_FIX.items() if code in codes]
        return "Nothing can be computed from such a mesh: " + "; ".join(fixes) + "."
    opts = []
    if codes & _ORIENTATION and not fix_orientation:
        opts.append("fix_orientation=True to re-orient the faces consistently and outward")
    if codes & {"open_edges", "non_manifold_edges"} and not shell:
        opts.append("shell=True to treat the surface as a thin shell (density in kg/m^2; open surfaces allowed)")
    if not shell:
        opts.append("robust=True for the solid the surface most nearly bounds (generalised winding number), "
                    "with an error bound")
    opts.append("on_defect='warn' to accept the result with the defects recorded as warnings")
    how = [text for code, text in _REPAIR.items() if code in codes]
    opts.append("repair the mesh" + (f" ({', '.join(how)})" if how else ""))
    return "Options: " + "; ".join(opts) + "."


def _defect_error(what: str, defects, report, *, shell: bool, fix_orientation: bool, kind: str) -> MeshError:
    """One-paragraph MeshError naming each defect (code, count, example) and the options."""
    parts = "; ".join(f"{d.code}: {d.message}" for d in defects)
    codes = {d.code for d in defects}
    if codes & set(_FATAL):
        why = ""
    elif shell:
        why = " Duplicate faces count their area twice in a shell."
    elif codes == {"overlapping_shells"}:
        why = " The volume integrals of closed parts that overlap count the overlap twice."
    elif codes == {"self_intersecting"}:
        why = " The volume integrals of a surface that passes through itself count what it encloses twice."
    else:
        why = (" The volume integrals of a surface that is not closed and consistently outward-wound "
               "are wrong.")
    msg = (f"{what} cannot be used as {kind}: {parts}.{why} "
           f"{_options_text(codes, shell=shell, fix_orientation=fix_orientation)}")
    return MeshError(msg, report=report)


def compute_mesh_properties(vertices, faces, *, density, mass, shell, fix_orientation, on_defect, frame, name,
                     stacklevel, with_report: bool = False, welded: bool = False, robust: bool = False,
                     robust_tol: float = 1e-3, self_crossing: str = "search"):
    """Implementation of :func:`mesh_properties` (``stacklevel`` points warnings at the caller).

    ``with_report=True`` returns ``(properties, report)``, the report of the mesh as checked
    (after any orientation fix), so batch callers need not analyse the mesh twice.
    ``welded=True``: the vertices are known distinct and all used (as :func:`load_mesh`
    returns them); skips the welding and the compaction.
    """
    from .properties import MassProperties

    what = f"mesh {name}" if name else "mesh"
    kind = "a thin shell" if shell else "a solid"
    if on_defect not in ON_DEFECT:
        raise InputError(f"on_defect must be one of {ON_DEFECT}, got {on_defect!r}")
    if self_crossing not in SELF_CROSSING:
        raise InputError(f"self_crossing must be one of {SELF_CROSSING}, got {self_crossing!r}")
    _check_mass_args(density, mass, what)
    v, f = validate_inputs(vertices, faces)

    if robust and not shell and not with_report and not fix_orientation:
        props = _robust_direct(v, f, welded, density=density, mass=mass, frame=frame, what=what, tol=robust_tol,
                               stacklevel=stacklevel + 1)
        if props is not None:
            return props
    analysis = analyse_mesh(v, f, welded=welded, weld_first=False, self_crossing=self_crossing)
    report = analysis.report
    if analysis.solid_sums is not None and not shell:   # a clean solid: its sums came with the check
        props = _clean_solid_properties(analysis.solid_sums, v, f, density=density, mass=mass, frame=frame,
                                        what=what, notes=_note_texts(report, what, shell))
        return (props, report) if with_report else props
    fatal = [d for d in report.defects if d.code in _FATAL]
    if fatal:
        raise _defect_error(what, fatal, report, shell=shell, fix_orientation=fix_orientation, kind=kind)

    notes: list[str] = []
    if fix_orientation and not shell and set(report.codes) & _ORIENTATION:
        f, n_flipped, analysis = orient_analysed(v, f, analysis, what)
        report = analysis.report
        notes.append(f"{what}: fix_orientation flipped {n_flipped} of {len(f)} faces")

    errors = [d for d in report.errors if not (shell and d.code in _SOLID_ONLY)]
    if errors and robust and not shell:
        props = _robust_properties(v, f, errors, density=density, mass=mass, frame=frame, what=what,
                                   tol=robust_tol, notes=notes, stacklevel=stacklevel + 1)
        return (props, report) if with_report else props
    if errors and on_defect == "raise":
        raise _defect_error(what, errors, report, shell=shell, fix_orientation=fix_orientation, kind=kind)
    for d in errors:  # on_defect == "warn": accepted on request, loudly
        text = f"{what}: {d.code} accepted (on_defect='warn'): {d.message}"
        warnings.warn(text, MeshDefectWarning, stacklevel=stacklevel)
        notes.append(text)
    # Degenerate (zero-area) faces are a note, not an error: the solid kernel weights every
    # term of a face by det = a.(b x c) = a.((b - a) x (c - a)), i.e. by its area vector, and
    # the shell kernel by its area, so a zero-area face contributes exactly nothing.  The
    # topology checks already skip faces that repeat a vertex and keep zero-area faces with
    # distinct corners, so the closedness verdict stands with them.  Recorded, not raised.
    notes += _note_texts(report, what, shell)

    # integrate over the referenced vertices only (unreferenced ones would move the
    # kernel's reference point and cost precision)
    vc, fc = (v, f) if welded else compact_vertices(v, f)
    if shell:
        area, first, second, r = shell_integrals(vc, fc)
        if not area > 0:
            raise MeshError(f"{what} has zero total area; a thin shell needs a surface.", report=report,
                            code="zero_area")
        m, rho = resolve_mass(area, density, mass, what=f"{what} (shell)", measure_name="area")
        com, inertia = central_inertia(area, first, second, r, rho, mass=m)
        props = MassProperties(m, com, inertia, frame=frame, warnings=tuple(notes))
        return (props, report) if with_report else props
    volume, first, second, r = solid_integrals(vc, fc)
    if not volume > 0:
        # refused even with on_defect="warn": a non-positive volume has no mass distribution
        hint = ("; fix_orientation=True re-orients an inward-wound closed mesh" if volume < 0 and not fix_orientation
                else "")
        raise MeshError(f"{what} has signed volume {volume:.6g} <= 0, so it does not enclose a solid "
                        f"(faces wound inward, or a flat or open surface){hint}.", report=report,
                        code="non_positive_volume")
    m, rho = resolve_mass(volume, density, mass, what=what)
    com, inertia = central_inertia(volume, first, second, r, rho, mass=m)
    props = MassProperties(m, com, inertia, frame=frame, volume=volume, warnings=tuple(notes))
    return (props, report) if with_report else props


def _note_texts(report, what: str, shell: bool) -> list:
    """The report's notes as recorded warnings (what each means for the result)."""
    out = []
    for d in report.defects:
        if d.severity != "note" or (shell and d.code in _SOLID_ONLY):
            continue
        if d.code == "degenerate_faces":
            out.append(f"{what}: {d.code} ignored (zero area adds nothing to the integrals): {d.message}")
        else:
            out.append(f"{what}: {d.code}: {d.message}")
    return out


def _clean_solid_properties(sums, v, f, *, density, mass, frame, what, notes=()):
    """Mass properties from the volume sums of the compiled check (``clean_solid``'s ``out``);
    a lopsided body (see :mod:`inertia.geometry.integrals`, error analysis item 4) is
    integrated again about its COM, as :func:`solid_integrals` does."""
    from .properties import MassProperties

    volume, first, second, r, kappa = solid_sums_floats(sums)
    if kappa > REFINE_KAPPA:
        vc, fc = compact_vertices(v, f)
        volume, first, second, r = solid_integrals(vc, fc)
        first, second, r = first.tolist(), second.tolist(), r.tolist()
    m, rho = resolve_mass(volume, density, mass, what=what)   # refuses a volume that is not positive and finite
    com, inertia = central_from_floats(volume, first, second, r, rho, m)
    return MassProperties._computed(m, com, inertia, frame=frame, volume=volume, warnings=tuple(notes))


def _robust_direct(v, f, welded, *, density, mass, frame, what, tol, stacklevel):
    """``robust=True`` without the full analysis (it costs as much as the robust solid): a
    clean solid takes the exact path; a mesh with nothing fatal (indices in range, finite
    coordinates within the limit) goes to the robust solid, whose own pass names the defects;
    None otherwise (the full analysis then names the fatal ones)."""
    from ..geometry.checks import clean_analysis

    clean = clean_analysis(v, f, welded=welded)
    if clean is not None and clean.solid_sums is not None:
        return _clean_solid_properties(clean.solid_sums, v, f, density=density, mass=mass, frame=frame, what=what,
                                       notes=_note_texts(clean.report, what, False))
    if not len(f) or not faces_in_range(f, len(v)):
        return None
    with np.errstate(invalid="ignore"):
        if not np.all(np.abs(v) <= COORDINATE_LIMIT):
            return None
    return _robust_properties(v, f, None, density=density, mass=mass, frame=frame, what=what, tol=tol, notes=[],
                              stacklevel=stacklevel + 1)


def _robust_properties(v, f, errors, *, density, mass, frame, what, tol, notes, stacklevel):
    """The solid {w >= 1/2} of an imperfect mesh (:func:`inertia.geometry.robust.robust_integrals`),
    with its error bound and its defects recorded in the warnings."""
    from ..geometry.robust import robust_integrals
    from .properties import MassProperties

    if not (tol > 0):
        raise InputError(f"robust_tol must be positive, got {tol!r}")
    res = robust_integrals(v, f, tol=tol)
    volume = float(res.volume)
    if not volume > 0:
        raise MeshError(f"{what}: the robust solid (generalised winding number >= 1/2) is empty: the surface "
                        f"encloses no volume ({'; '.join(res.defects) or 'no defect named'}).",
                        code="non_positive_volume")
    m, rho = resolve_mass(volume, density, mass, what=what)
    com, inertia = central_inertia(volume, np.asarray(res.first, float), np.asarray(res.second, float),
                                   np.asarray(res.reference, float), rho, mass=m)
    rel = {k: float(x) for k, x in res.relative_bounds.items()}
    bounds = ", ".join(f"{k} {x:.2g}" for k, x in rel.items())
    codes = ", ".join(sorted({d.code for d in errors} if errors is not None else set(res.codes)))
    text = (f"{what}: robust solid for a mesh with {codes} (the points of generalised winding number >= 1/2"
            f"{'; ' + '; '.join(res.defects) if res.defects else ''}); relative error bounds: {bounds}")
    if not res.converged:
        text += f"; NOT within robust_tol {tol:g} (the refinement budget ran out)"
    warnings.warn(text, MeshDefectWarning, stacklevel=stacklevel)
    return MassProperties(m, com, inertia, frame=frame, volume=volume, warnings=tuple(notes) + (text,))


def mesh_properties(vertices, faces, *, density=None, mass=None, shell=False, fix_orientation=False,
                    on_defect="raise", frame: str = "body", name: str | None = None, robust: bool = False,
                    robust_tol: float = 1e-3, self_crossing: str = "search"):
    """Mass properties of a triangle mesh, checked for defects first.

    Parameters
    ----------
    vertices : (V, 3) float, m, in the frame ``frame``.
    faces : (F, 3) int, vertex indices, counter-clockwise seen from outside (float arrays of
        integral values are accepted).
    density : float, kg/m^3 (kg/m^2 when ``shell``); or
    mass : float, kg (exactly one of the two).
    shell : bool
        Treat the surface as a thin shell of uniform surface density: open surfaces and
        any orientation are allowed.  Empty meshes, NaN/inf coordinates, bad indices and
        duplicate faces are still refused.
    fix_orientation : bool
        Re-orient the faces consistently per edge-connected component (breadth-first over
        the face adjacency) and outward (positive signed volume; cavities nested in another
        component inward).  Raises MeshError when a component is not orientable.
    on_defect : {"raise", "warn"}
        ``"raise"`` (default): a defect that makes the result wrong raises MeshError.
        ``"warn"``: accept it; a :class:`MeshDefectWarning` is issued and the text is
        recorded in the result's ``warnings``.  A solid of non-positive volume is refused
        either way.
    frame : str, name of the frame of ``vertices`` (bookkeeping).
    name : str, optional, how messages name the mesh (e.g. its file path).
    robust : bool
        Opt-in answer for an imperfect solid (open, non-manifold, inconsistently wound,
        overlapping or self-intersecting): the solid is the set of points whose generalised
        winding number is at least 1/2 (:func:`inertia.geometry.robust.robust_integrals`),
        integrated with an error bound refined below ``robust_tol`` (relative, for the volume,
        the COM and the inertia).  A warning names the defects and the bounds, which are also
        in ``warnings``.  A closed, consistently wound mesh takes the exact path either way.
    robust_tol : float, the relative bound to reach (default 1e-3).
    self_crossing : {"search", "certificate"}
        How a closed shell is shown not to pass through itself: ``"search"`` (default) proves
        it in the integrals' pass when it is star-shaped from its center of mass, and
        otherwise tests face pairs (up to 200,000 faces; 10-50x the cost of the integrals);
        ``"certificate"`` only tries the proof, and a shell it does not prove gets the note
        ``self_crossing_unchecked`` in ``warnings`` (for bulk work where that cost matters).

    Returns
    -------
    MassProperties
        ``mass`` kg, ``com`` (3,) m, ``inertia_com`` (3, 3) kg m^2 about the COM in ``frame``
        (negated products), ``volume`` m^3 (NaN for shells), ``warnings`` (notes and
        accepted defects).

    Raises
    ------
    MeshError
        The mesh has defects (``.report`` holds the full :class:`MeshReport`).
    InputError
        Wrong array shapes or types, both or neither of density/mass, bad ``on_defect``.

    Notes
    -----
    Degenerate (zero-area) faces are recorded in ``warnings`` but never raise: they add
    nothing to the integrals.  The integrals are exact for a closed, consistently
    outward-wound surface (divergence theorem; Eberly, "Polyhedral mass properties").

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    >>> f = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> p = mesh_properties(v, f, density=6.0)
    >>> round(p.mass, 12), p.com.shape, p.inertia_com.shape
    (1.0, (3,), (3, 3))
    """
    return compute_mesh_properties(vertices, faces, density=density, mass=mass, shell=shell,
                            fix_orientation=fix_orientation, on_defect=on_defect, frame=frame, name=name,
                            stacklevel=3, robust=robust, robust_tol=robust_tol, self_crossing=self_crossing)


def mesh_file_properties(path, *, density=None, mass=None, units: str = "m", shell: bool = False,
                         fix_orientation: bool = False, on_defect: str = "raise", frame: str = "body",
                         merge_rtol: float = MERGE_RTOL, robust: bool = False, robust_tol: float = 1e-3,
                         self_crossing: str = "search"):
    """Mass properties of the triangle mesh in a file (see :func:`inertia.geometry.mesh_io.load_mesh` and
    :func:`inertia.massprops.mesh.mesh_properties` for the parameters).

    ``density`` is kg/m^3 (kg/m^2 with ``shell=True``) whatever ``units`` the file uses:
    coordinates are converted to metres first.  MeshError messages and recorded warnings
    name the file.

    Returns
    -------
    MassProperties in frame ``frame`` (the file's coordinate frame), SI units.
    """
    from ..massprops.mesh import compute_mesh_properties

    vertices, faces = load_mesh(path, units=units, merge_rtol=merge_rtol)
    # stacklevel 3: warnings point at the caller of mesh_file_properties
    return compute_mesh_properties(vertices, faces, density=density, mass=mass, shell=shell,
                            fix_orientation=fix_orientation, on_defect=on_defect, frame=frame,
                            name=str(path), stacklevel=3, welded=merge_rtol > 0, robust=robust,
                            robust_tol=robust_tol, self_crossing=self_crossing)
