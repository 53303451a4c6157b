"""Text of a body's principal moments and axes, shared by ``props`` for meshes, primitives and
robots (and ``demo``).  Only the standard library is imported here."""

from __future__ import annotations

from . import _format as fmt

XYZ = ("x", "y", "z")


def degenerate_text(groups) -> str:
    """Readable report of repeated principal moments (``groups`` as from MassProperties.principal)."""
    groups = [tuple(g) for g in groups]
    if not groups:
        return "none: three distinct moments, principal axes unique up to sign"
    out = []
    for g in groups:
        names = " = ".join(f"I{k + 1}" for k in g)
        if len(g) == 3:
            out.append(f"{names}: every axis through the COM is principal (axes reported as the body axes)")
        else:
            other = ({0, 1, 2} - set(g)).pop() + 1
            out.append(f"{names}: any pair of perpendicular axes normal to axis {other} is principal "
                       f"(axes {g[0] + 1} and {g[1] + 1} are a deterministic choice)")
    return "; ".join(out)


def canonical_lines(props, *, title: str = "Principal moments and axes (canonical form)") -> list[str]:
    """Principal moments (ascending), radii of gyration, repeated-moment report, axes (det +1)."""
    pf = props.principal()
    lines = fmt.heading(title)
    lines += fmt.key_values([
        ("moments I1 <= I2 <= I3", fmt.vector(pf.moments) + " kg m^2"),
        ("radii of gyration", fmt.vector(props.radii_of_gyration) + " m"),
        ("repeated moments", degenerate_text(pf.degenerate)),
        ("principal frame", "origin at the COM, I_body = R diag(I1, I2, I3) R^T with"),
        ("axes", "R = R_body_principal (columns = principal axes, proper rotation, det +1):"),
    ])
    lines += fmt.matrix_lines(pf.R_body_principal, row_labels=XYZ, col_labels=("axis 1", "axis 2", "axis 3"),
                              indent=4, style="f")
    return lines
