"""Text and JSON of mass properties shared by ``props`` for meshes, primitives, robots and stages
(and ``demo`` and ``diff``).  Only the standard library is imported here."""

from __future__ import annotations

from . import _format as fmt

XYZ = ("x", "y", "z")


def degenerate_text(groups) -> str:
    """Readable report of repeated principal moments (``groups``: ``MassProperties.principal().degenerate``)."""
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


def canonical_lines(props, units=None, *, title: str = "Principal moments and axes (canonical form)") -> list[str]:
    """Principal moments (ascending), radii of gyration, repeated-moment report, axes (det +1)."""
    u = units or fmt.Units()
    pf = props.principal()
    lines = fmt.heading(title)
    lines += fmt.key_values([
        ("moments I1 <= I2 <= I3", f"{fmt.vector(u.moments(pf.moments))} {u.inertia_unit}"),
        ("radii of gyration", f"{fmt.vector(u.length(props.radii_of_gyration))} {u.length_unit}"),
        ("repeated moments", degenerate_text(pf.degenerate)),
        ("principal frame", "origin at the COM, I_body = R diag(I1, I2, I3) R^T with"),
        ("axes", "R = R_body_principal (columns = principal axes, proper rotation, det +1):"),
    ])
    lines += fmt.matrix_lines(pf.R_body_principal, row_labels=XYZ, col_labels=("axis 1", "axis 2", "axis 3"),
                              indent=4, style="f")
    return lines


def inertia_lines(props, u, *, heading: bool = True, axes: str = "body axes") -> list[str]:
    """The central inertia matrix, labelled (as its own section, or as a block of the previous one)."""
    products = "products positive: CAD convention" if u.convention == "cad" else "products negated: L = I w"
    text = f"Inertia about the center of mass [{u.inertia_unit}] ({axes}, {products})"
    lines = fmt.heading(text) if heading else ["  " + text[0].lower() + text[1:] + ":"]
    return lines + fmt.matrix_lines(u.inertia(props.inertia_com), row_labels=XYZ, col_labels=XYZ, style="e")


def body_dict(props, units) -> dict:
    """Mass, COM, inertia and principal moments and axes of a whole robot (or stage) in ``units``."""
    pf = props.principal()
    return {"mass": units.mass(props.mass), "com": units.length(props.com),
            "inertia_com": units.inertia(props.inertia_com), "principal_moments": units.moments(pf.moments),
            "R_body_principal": pf.R_body_principal}


def link_dict(link, units) -> dict:
    """A link's (or USD body's) ``to_dict()`` with its masses, positions and tensors in ``units``."""
    return converted(link.to_dict(), units)


def converted(d: dict, units) -> dict:
    """``d`` with its ``mass``, ``exact_mass``, ``com`` and ``inertia_com`` in ``units``."""
    convert = {"mass": units.mass, "exact_mass": units.mass, "com": units.length, "inertia_com": units.inertia}
    return {k: convert[k](v) if k in convert and v is not None else v for k, v in d.items()}


def links_table(links, units, what: str = "link") -> list[str]:
    """One row per link: mass, COM and where its inertial came from."""
    m, L = units.mass_unit, units.length_unit
    rows = [[lk.name, fmt.num(units.mass(lk.mass)), *(fmt.num(x) for x in units.length(lk.com)), lk.source]
            for lk in links]
    return fmt.table([what, f"mass [{m}]", f"com x [{L}]", f"com y [{L}]", f"com z [{L}]", "source"], rows)
