"""``inertia lagrangian``: equations of motion in Euler angles, derived symbolically.

Derives the accelerations of a rigid body whose attitude is given by an Euler-angle
sequence (rigid-body route ``E^T [J (E q'' + E' q') + w x J w] = E^T tau``, common
subexpressions eliminated) and prints them as Python, C, JSON or LaTeX of that form
(``latex-cse``); or prints the readable form, the Lagrangian, the mass matrix and the force
vector ``M(q) q'' = f(q, q')`` with textbook symbols, as LaTeX, Markdown or an offline HTML
page typeset by KaTeX.  sympy is imported only when the command runs.
"""

from __future__ import annotations

from . import _format as fmt

EPILOG = """\
examples:
  inertia lagrangian                                  (Z-Y-X, rotation only, readable LaTeX)
  inertia lagrangian --format html -o eom.html        (the same, typeset offline in a browser)
  inertia lagrangian --sequence ZXZ --format python
  inertia lagrangian --translation --gravity --format c -o eom.c
  inertia lagrangian --inertia diagonal --format json

model: R_world_body = R_a(q1) R_b(q2) R_c(q3) for sequence "abc" (intrinsic, scipy's upper-case
convention); coordinates in sequence order (Z-Y-X: psi, theta, phi = yaw, pitch, roll), after
x, y, z with --translation.  J is about the center of mass in body axes (negated products).
With --gravity the body turns about a fixed pivot at its origin, center of mass at c.
Singular (gimbal lock) where cos(q2) = 0 (Tait-Bryan) or sin(q2) = 0 (proper Euler): the
generated Python raises, the C function returns 1.

exit status: 0 on success, 1 on bad input, 2 on bad usage."""

HELP = "Euler-angle equations of motion (readable LaTeX, Markdown, HTML; Python, C, JSON), derived symbolically"
DESCRIPTION = ("Lagrange equations of a rigid body in Euler angles, solved for the accelerations without "
               "simplify or solve, common subexpressions eliminated, in under a second.")


def register(sub) -> None:
    p = fmt.add_command(sub, "lagrangian", HELP, DESCRIPTION, EPILOG, usage="[options]")
    p.add_argument("--sequence", default="ZYX", metavar="SEQ",
                   help="intrinsic Euler sequence: XYZ XZY YXZ YZX ZXY ZYX XYX XZX YXY YZY ZXZ ZYZ (default ZYX)")
    p.add_argument("--translation", action="store_true",
                   help="add the position of the body origin: a free 6-DOF body")
    p.add_argument("--gravity", action="store_true",
                   help="uniform gravity g (world axes) at a center of mass c (body axes)")
    p.add_argument("--inertia", choices=("full", "diagonal"), default="full",
                   help="general symmetric J (default) or principal axes along the body axes")
    p.add_argument("--format", choices=FORMATS, default="latex",
                   help="latex, markdown or html: the Lagrangian, the mass matrix M(q) and the force vector f "
                        "with textbook symbols (html typeset offline by KaTeX); latex-cse, python, c or json: "
                        "the common-subexpression form for code (default latex)")
    p.add_argument("-o", "--output", metavar="FILE", help="write to FILE (atomically) instead of stdout")
    p.set_defaults(func=run)


#: output formats: the readable ones first, then the CSE form for code
FORMATS = ("latex", "markdown", "html", "latex-cse", "python", "c", "json")


def run(args) -> int:
    from ..symbolic import derive

    eom = derive(args.sequence, translation=args.translation, gravity=args.gravity, inertia=args.inertia)
    text = {"latex": eom.latex, "markdown": eom.markdown, "html": lambda: _html(eom), "latex-cse": eom.cse_latex,
            "python": eom.python_code, "c": eom.c_code, "json": eom.to_json}[args.format]()
    if args.output:
        from .._core.atomic import write_text_atomic

        write_text_atomic(args.output, text.rstrip("\n") + "\n")
    else:

        fmt.emit(text)
    return 0


def _html(eom) -> str:
    from ..viz.equations_page import equations_html

    return equations_html(eom.document(), eom.readable_header(), eom.title())
