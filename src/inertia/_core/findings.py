"""One report type for every check, and one registry of codes shared with the errors.

A :class:`Finding` is one fact a check found: a stable ``code`` from :data:`CODES`, a
``severity`` (``"error"``: the result would be wrong or is refused; ``"warning"``: valid but
suspect; ``"note"``: harmless, said for completeness), a readable ``message``, ``where`` it was
found (a file and line, a link, a mesh) and the numbers behind it in ``values``.  Mass
properties, mesh reports, robust results, robot checks and batch rows all carry findings; the
error types carry the same codes, so one fact has one code wherever it is met.
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["CODES", "SEVERITIES", "Finding"]

SEVERITIES = ("error", "warning", "note")

#: every code the package reports or raises -> (default severity, what it means)
CODES = {
    # -- errors raised (InertiaError and its family; the batch table's ``reason``)
    "inertia_error": ("error", "base code of the package's errors (not raised itself)"),
    "invalid_input": ("error", "an argument has the wrong shape, type or value"),
    "unwritable": ("error", "an output path cannot be written"),
    "output_busy": ("error", "another batch run is writing the same output"),
    "invalid_inertia": ("error", "mass properties that are not physical"),
    "no_equivalent_model": ("error", "no particle model or uniform solid reproduces the properties"),
    "invalid_mesh": ("error", "a mesh whose mass properties would be wrong"),
    "non_positive_volume": ("error", "a solid mesh encloses no positive volume"),
    "zero_area": ("error", "a thin shell has no area"),
    "not_orientable": ("error", "faces cannot be wound consistently (a Moebius strip)"),
    "unreadable": ("error", "a file cannot be read (not a regular file, no permission)"),
    "not_found": ("error", "a file does not exist"),
    "malformed": ("error", "a file does not follow its format"),
    "unsupported_format": ("error", "a file format no reader handles"),
    "too_large": ("error", "a file larger than its reader accepts"),
    "missing_dependency": ("error", "an optional dependency is not installed"),
    "integration_failed": ("error", "an integration step failed (not finite, not converged)"),
    "robot_file": ("error", "a robot description that cannot be read"),
    "link_not_found": ("error", "no link of that name in the model"),
    "internal_error": ("error", "an unexpected failure (a bug: please report it)"),
    "crashed": ("error", "the worker process of a batch file was lost"),
    # -- physical validity of mass properties
    "non_positive_mass": ("error", "mass not positive (or not finite)"),
    "non_finite": ("error", "a NaN or infinite number (a coordinate, an inertia entry, a COM)"),
    "not_symmetric": ("error", "inertia matrix not symmetric"),
    "not_positive_definite": ("error", "a principal moment not positive"),
    "triangle_inequality": ("error", "principal moments with I1 + I2 < I3"),
    "flat_body": ("warning", "a principal axis with no extent: the equivalent model is flat there"),
    # -- meshes (in this order in a mesh report)
    "empty": ("error", "no vertices, no faces (or an empty file)"),
    "out_of_range": ("error", "a coordinate beyond 1e60: the second moments would overflow"),
    "bad_index": ("error", "a face index outside the vertex array"),
    "degenerate_faces": ("note", "zero-area faces: they add nothing to the integrals"),
    "duplicate_faces": ("error", "the same three vertices used by more than one face"),
    "open_edges": ("error", "an edge used by one face only (holes)"),
    "non_manifold_edges": ("error", "an edge used by more than two faces"),
    "inconsistent_winding": ("error", "an edge traversed in the same direction by its two faces"),
    "inverted": ("error", "a closed component wound inward"),
    "overlapping_shells": ("error", "closed components whose volumes overlap"),
    "self_intersecting": ("error", "a closed component passes through itself"),
    "self_crossing_negligible": ("note", "faces cross, but change the mass properties by less than 1e-4"),
    "self_crossing_unchecked": ("note", "a shell too large for the self-crossing search and not proven free of it"),
    "orientation_repaired": ("note", "faces re-wound consistently and outward (repair='orient')"),
    "robust_solid": ("warning", "the solid of generalised winding number >= 1/2 of an imperfect mesh, with bounds"),
    "bound_not_reached": ("warning", "the robust solid's error bound did not reach its target within the budget"),
    "undecided_windings": ("note", "robust solid: faces whose side windings stayed undecided (bounded)"),
    # -- robot files: the declared inertials and the tree
    "massless_moving_link": ("error", "a link that moves, with no mass on it or welded to it"),
    "below_simulator_floor": ("error", "a moving body's mass or moment below 1e-15 (MuJoCo's mjMINVAL)"),
    "plane_in_moving_body": ("error", "a plane geom in a moving MJCF body"),
    "no_links": ("error", "a robot file with no link"),
    "joints_unreadable": ("error", "joints that cannot be read (the tree checks did not run)"),
    "compiler_repairs_inertia": ("warning", "an invalid inertial MuJoCo's <compiler> options repair"),
    "static_degenerate_inertia": ("warning", "a zero moment on a body welded to the world (MuJoCo compiles it)"),
    "com_outside_geometry": ("warning", "the COM lies outside the link's shapes"),
    "geometry_mismatch": ("warning", "the declared tensor disagrees with the link's own geometry"),
    "legacy_mesh_inertia": ("warning", "MuJoCo's legacy mesh inertia differs from the exact solid"),
    "implausible_inertia": ("warning", "a radius of gyration far below the link's size"),
    "mesh_not_found": ("warning", "a mesh file the robot names cannot be found"),
    "mesh_unreadable": ("warning", "a mesh reference that is no file the mesh reader opens (FIFO, device, folder)"),
    "mujoco_refuses_mesh": ("error", "a mesh MuJoCo's compiler refuses, so the model does not load"),
    "unsupported_geometry": ("warning", "a shape the reader cannot use"),
    "unsupported_pose": ("warning", "a pose the reader cannot resolve"),
    "ros_unreadable_number": ("warning", "a number ROS tools cannot parse (the reader did)"),
    "xml_declaration_moved": ("warning", "an XML declaration after a comment or blank lines"),
    "comment_with_dashes": ("warning", "an XML comment holding '--'"),
    "content_after_root": ("warning", "markup after the root element"),
    "geometry_unusable": ("note", "shapes that cannot be integrated: the comparison with them is skipped"),
    "mesh_reader_message": ("note", "a mesh file's reader complained, but read the triangles"),
    "mesh_overlapping_shells": ("note", "a mesh whose closed parts overlap, summed as the simulator sums it"),
    "inertial_ignored": ("note", "a declared inertial MuJoCo replaces by its geoms' (inertiafromgeom)"),
    "no_bodies": ("note", "an MJCF file without bodies (an include fragment, a scene)"),
    "kinematic_loop": ("note", "joints that close a kinematic loop"),
    "sdf_default_inertial": ("note", "an SDF link without inertial: Gazebo uses 1 kg, 1 kg m^2"),
    # -- OpenUSD stages
    "negative_mass": ("error", "an authored mass below 0 (read as not set)"),
    "non_unit_principal_axes": ("error", "a principalAxes quaternion whose norm is not 1"),
    "mass_fallback": ("error", "a dynamic body without mass or collider: UsdPhysics' default 1 kg"),
    "inertia_below_usd_tolerance": ("warning", "a diagonalInertia usd-core reads as not set"),
    "mass_without_inertia": ("warning", "a mass authored without a diagonalInertia"),
    "inertia_without_mass": ("warning", "a diagonalInertia authored without a mass"),
    "default_density": ("warning", "the mass comes from colliders at the default 1000 kg/m^3"),
    "hull_differs": ("warning", "PhysX's approximation of a mesh differs from the mesh"),
    "mass_api_not_applied": ("warning", "mass attributes without PhysicsMassAPI (ignored)"),
    "mesh_not_solid": ("warning", "a mesh collider that bounds no solid (its hull stands in)"),
    "missing_units": ("warning", "metersPerUnit or kilogramsPerUnit not authored"),
    "mass_on_non_physics_prim": ("warning", "PhysicsMassAPI on a prim physics ignores"),
}


def _plain(value):
    """``value`` with tuples as lists and NumPy scalars and arrays as Python numbers (JSON-ready)."""
    if isinstance(value, dict):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if hasattr(value, "tolist"):
        return value.tolist()
    return value


@dataclass(frozen=True)
class Finding:
    """One fact a check found.

    Attributes
    ----------
    code : str, a key of :data:`CODES` (stable: programs read it, never the message).
    message : str, one sentence with the numbers, without the location.
    severity : str, ``"error"``, ``"warning"`` or ``"note"`` (default: the code's own).
    where : str, the location (``file:line``, a link, a mesh name); empty when not known.
    values : dict, the numbers behind the message (JSON-ready).
    """

    code: str
    message: str
    severity: str = ""
    where: str = ""
    values: dict = field(default_factory=dict, compare=False)

    def __post_init__(self):
        entry = CODES.get(self.code)
        if entry is None:   # a programming error: every code is registered once, above
            raise KeyError(f"finding code {self.code!r} is not in inertia._core.findings.CODES")
        if not self.severity:
            object.__setattr__(self, "severity", entry[0])
        elif self.severity not in SEVERITIES:
            raise ValueError(f"severity must be one of {SEVERITIES}, got {self.severity!r}")

    def __str__(self) -> str:
        return f"{self.where}: {self.message}" if self.where else self.message

    def to_dict(self) -> dict:
        """``{code, severity, message, where, values}``, JSON-ready."""
        return {"code": self.code, "severity": self.severity, "message": self.message, "where": self.where,
                "values": _plain(self.values)}

    def replace(self, **changes) -> "Finding":
        """A copy with some fields changed (e.g. ``severity="warning"`` for a defect accepted on request)."""
        out = {"code": self.code, "message": self.message, "severity": self.severity, "where": self.where,
               "values": self.values}
        out.update(changes)
        return Finding(**out)
