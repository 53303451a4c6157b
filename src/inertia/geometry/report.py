"""The mesh defect report: defect codes and their severity, :class:`Defect`, :class:`MeshReport`."""

from __future__ import annotations

import math
from dataclasses import dataclass, field

__all__ = ["SEVERITY", "Defect", "MeshReport", "fmt_point", "plural"]


#: Severity of each code for a closed solid: "error" makes the solid integrals wrong
#: (or impossible), "note" does not.
SEVERITY = {
    "empty": "error",
    "non_finite": "error",
    "out_of_range": "error",
    "bad_index": "error",
    "degenerate_faces": "note",
    "duplicate_faces": "error",
    "open_edges": "error",
    "non_manifold_edges": "error",
    "inconsistent_winding": "error",
    "inverted": "error",
    "overlapping_shells": "error",
    "self_intersecting": "error",
    "self_crossing_unchecked": "note",
    "self_crossing_negligible": "note",
}



@dataclass(frozen=True)
class Defect:
    """One kind of defect found in a mesh.

    Attributes
    ----------
    code : str, stable name (see the module docstring).
    count : int, how many (vertices, faces, edges or components; the message says which).
    message : str, one sentence with the count and the example location.
    example : dict, the first occurrence: keys among ``vertex``, ``face``, ``faces``, ``edge``
        (vertex index pair), ``coords`` (tuple of (x, y, z)), ``component``, plus numbers.
    severity : str, ``"error"`` (solid integrals wrong) or ``"note"`` (harmless for the integrals).
    """

    code: str
    count: int
    message: str
    example: dict = field(default_factory=dict, compare=False, hash=False)
    severity: str = "error"


@dataclass(frozen=True)
class MeshReport:
    """Result of :func:`check_mesh`.

    Attributes
    ----------
    defects : tuple of Defect, in a fixed order (the order of the codes table).
    n_vertices, n_faces : int, as given.
    n_welded : int, vertices merged into another of exactly equal position.
    n_components : int, edge-connected components (0 when the topology was not checked).
    volume : float, signed volume in the caller's units cubed (NaN when not closed).
    area : float, total surface area (NaN when coordinates are not finite).
    """

    defects: tuple = ()
    n_vertices: int = 0
    n_faces: int = 0
    n_welded: int = 0
    n_components: int = 0
    volume: float = math.nan
    area: float = math.nan

    @property
    def codes(self) -> tuple:
        """Codes of every defect found (notes included)."""
        return tuple(d.code for d in self.defects)

    @property
    def errors(self) -> tuple:
        """Defects that make the mass properties of a closed solid wrong."""
        return tuple(d for d in self.defects if d.severity == "error")

    @property
    def ok(self) -> bool:
        """True when the mesh is a valid closed, consistently outward-wound solid.

        Notes (``degenerate_faces``) do not clear this flag: they leave the integrals exact.
        """
        return not self.errors

    @property
    def watertight(self) -> bool:
        """Every edge is used by exactly two faces (after welding), and the mesh could be checked."""
        return not (set(self.codes) & {"empty", "non_finite", "bad_index", "open_edges", "non_manifold_edges"})

    @property
    def winding_consistent(self) -> bool:
        """Every edge shared by two faces is traversed in opposite directions by them."""
        return not (set(self.codes) & {"empty", "bad_index", "inconsistent_winding"})

    def get(self, code: str):
        """The :class:`Defect` with ``code``, or None."""
        for d in self.defects:
            if d.code == code:
                return d
        return None

    def count(self, code: str) -> int:
        """The count of defect ``code`` (0 when absent)."""
        d = self.get(code)
        return 0 if d is None else d.count

    def summary(self) -> str:
        """Several lines of text: the sizes, the flags, then one line per defect."""
        vol = "n/a (not closed)" if math.isnan(self.volume) else f"{self.volume:.9g}"
        lines = [f"mesh: {self.n_vertices} vertices ({self.n_welded} welded duplicates), {self.n_faces} faces, "
                 f"{self.n_components} components",
                 f"watertight: {'yes' if self.watertight else 'no'}; "
                 f"winding consistent: {'yes' if self.winding_consistent else 'no'}; signed volume: {vol}"]
        if not self.defects:
            lines.append("no defects")
        for d in self.defects:
            lines.append(f"- {d.code} ({d.severity}): {d.message}")
        return "\n".join(lines)

    def __str__(self) -> str:
        return self.summary()


# ---------------------------------------------------------------------------------- inputs


# ---------------------------------------------------------------------------------- formatting
def fmt_point(p) -> str:
    return "(" + ", ".join(f"{float(x):.6g}" for x in p) + ")"


def plural(n: int, word: str, plural: str | None = None) -> str:
    return f"{n} {word if n == 1 else (plural or word + 's')}"
