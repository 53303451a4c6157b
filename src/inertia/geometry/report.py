"""The mesh report: what :func:`inertia.geometry.check_mesh` found, as findings in a fixed order."""

from __future__ import annotations

import math
from dataclasses import dataclass

from .._core.findings import Finding

__all__ = ["MESH_CODES", "MeshReport"]

#: the codes of a mesh report, in the order they are listed (severities: inertia.errors.CODES)
MESH_CODES = ("empty", "non_finite", "out_of_range", "bad_index", "degenerate_faces", "duplicate_faces",
              "open_edges", "non_manifold_edges", "inconsistent_winding", "inverted", "overlapping_shells",
              "self_intersecting", "self_crossing_unchecked", "self_crossing_negligible")


def mesh_finding(code: str, count: int, message: str, example: dict) -> Finding:
    """A mesh check's finding: ``values`` holds the ``count`` (vertices, faces, edges or components)
    and the ``example`` (the first occurrence: ``vertex``, ``face``, ``faces``, ``edge``,
    ``coords``, ``component``, plus numbers)."""
    return Finding(code, message, values={"count": int(count), "example": example})


def watertight(codes) -> bool:
    """Every edge is used by exactly two faces, for a mesh whose findings have ``codes``."""
    return not (set(codes) & {"empty", "non_finite", "bad_index", "open_edges", "non_manifold_edges"})


def winding_consistent(codes) -> bool:
    """Every shared edge is traversed in opposite directions, for a mesh whose findings have ``codes``."""
    return not (set(codes) & {"empty", "bad_index", "inconsistent_winding"})


@dataclass(frozen=True)
class MeshReport:
    """What :func:`inertia.geometry.check_mesh` found in a mesh.

    Attributes
    ----------
    findings : tuple of Finding, in the order of :data:`MESH_CODES`; severity ``"error"``
        (the solid integrals would be wrong) or ``"note"`` (harmless for them).
    n_vertices, n_faces : int, as given.
    n_welded : int, vertices merged into another of exactly equal position.
    n_components : int, edge-connected components (0 when the topology was not checked).
    volume : float, signed volume in the caller's units cubed (NaN when not closed).
    area : float, total surface area (NaN when coordinates are not finite).
    """

    findings: tuple = ()
    n_vertices: int = 0
    n_faces: int = 0
    n_welded: int = 0
    n_components: int = 0
    volume: float = math.nan
    area: float = math.nan

    @property
    def codes(self) -> tuple:
        """Codes of every finding (notes included)."""
        return tuple(d.code for d in self.findings)

    @property
    def errors(self) -> tuple:
        """The findings that make the mass properties of a closed solid wrong."""
        return tuple(d for d in self.findings if d.severity == "error")

    @property
    def ok(self) -> bool:
        """True when the mesh is a valid closed, consistently outward-wound solid.

        Notes (``degenerate_faces``) do not clear this flag: they leave the integrals exact.
        """
        return not self.errors

    @property
    def watertight(self) -> bool:
        """Every edge is used by exactly two faces (after welding), and the mesh could be checked."""
        return watertight(self.codes)

    @property
    def winding_consistent(self) -> bool:
        """Every edge shared by two faces is traversed in opposite directions by them."""
        return winding_consistent(self.codes)

    def get(self, code: str):
        """The finding with ``code``, or None."""
        for d in self.findings:
            if d.code == code:
                return d
        return None

    def count(self, code: str) -> int:
        """The count of finding ``code`` (0 when absent)."""
        d = self.get(code)
        return 0 if d is None else d.values["count"]

    def summary(self) -> str:
        """Several lines of text: the sizes, the flags, then one line per defect."""
        vol = "n/a (not closed)" if math.isnan(self.volume) else f"{self.volume:.9g}"
        lines = [f"mesh: {self.n_vertices} vertices ({self.n_welded} welded duplicates), {self.n_faces} faces, "
                 f"{self.n_components} components",
                 f"watertight: {'yes' if self.watertight else 'no'}; "
                 f"winding consistent: {'yes' if self.winding_consistent else 'no'}; signed volume: {vol}"]
        if not self.findings:
            lines.append("no defects")
        for d in self.findings:
            lines.append(f"- {d.code} ({d.severity}): {d.message}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


# ---------------------------------------------------------------------------------- formatting
def fmt_point(p) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in p) + ")"


def plural(n: int, word: str, plural: str | None = None) -> str:
    return f"{n} {word if n == 1 else (plural or word + 's')}"
