"""The readable equations as a document: titled blocks of display math, written as LaTeX
(``align*``), Markdown (``$$`` blocks) or, through :mod:`inertia.viz.equations_page`, an
offline HTML page typeset by KaTeX.

Symbols are the textbook ones: angles ``\\psi, \\theta, \\phi`` (or ``q_1, q_2, q_3``),
rates ``\\dot\\psi``, accelerations ``\\ddot\\psi``, inertia ``J_{xx}``..., body torque
``\\tau_x``..., world force ``F_x``..., gravity ``g_x``..., center of mass ``c_x``...
Every entry ``M_{ij} &= ...`` and ``f_{i} &= ...`` sits on one line of its own, so the
LaTeX can be read back entry by entry (the tests do, with sympy's LaTeX parser).
"""

from __future__ import annotations

from dataclasses import dataclass

from ._sympy import require_sympy


@dataclass(frozen=True)
class Block:
    """A titled piece of the document: ``text`` (plain prose) and ``rows`` of an ``align*``."""

    title: str
    text: str
    rows: tuple


def symbol_names(system) -> dict:
    """LaTeX names of the rates and accelerations (``\\dot{\\psi}``, ``\\ddot{q}_{1}``)."""
    sp = require_sympy()
    names = {}
    for q, qd, qdd in zip(system.coordinates, system.rates, system.accelerations):
        base, _, sub = sp.latex(q).partition("_")
        tail = f"_{sub}" if sub else ""
        names[qd] = rf"\dot{{{base}}}{tail}"
        names[qdd] = rf"\ddot{{{base}}}{tail}"
    return names


def _vector(entries) -> str:
    return r"\begin{pmatrix}" + r" \\ ".join(entries) + r"\end{pmatrix}"


def _matrix(rows) -> str:
    return r"\begin{pmatrix}" + r" \\ ".join(" & ".join(r) for r in rows) + r"\end{pmatrix}"


def blocks(form) -> list[Block]:
    """The document of a :class:`~.readable.ReadableForm`."""
    sp = require_sympy()
    s = form.system
    names = symbol_names(s)

    def tex(e) -> str:
        return sp.latex(e, symbol_names=names)

    q = ", ".join(tex(c) for c in s.coordinates)
    seq = s.sequence
    rot = "R = " + r"\,".join(rf"R_{{{axis}}}({tex(angle)})" for axis, angle in zip(seq, s.angles))
    out = [Block("Coordinates", "Intrinsic Euler angles (R maps body axes to world axes)"
                 + (", after the world position of the body origin." if s.translation else "."),
                 (rf"q &= ({q}), \qquad {rot}",))]
    w_rows = [rf"\omega_{{{a}}} &= {tex(e)}" for a, e in zip("xyz", form.omega)]
    out.append(Block("Body angular velocity", "\u03c9 = E(q) q\u0307 in body axes [rad/s].", tuple(w_rows)))
    out.append(Block("The Lagrangian", _energy_text(s), _energy_rows(s, form, tex)))
    n = s.n
    M_sym = [[_entry_name("M", i, j, form.M) for j in range(n)] for i in range(n)]
    f_sym = [f"f_{{{i + 1}}}" if form.f[i] != 0 else "0" for i in range(n)]
    acc = _vector([tex(a) for a in s.accelerations])
    out.append(Block("Equations of motion", "The Euler-Lagrange equations in matrix form: the mass matrix "
                     "M(q) = d\u00b2L/dq\u0307\u00b2 (symmetric) times the accelerations equals the force vector "
                     "f(q, q\u0307): generalized forces of the inputs and gravity, and the velocity terms.",
                     (rf"M(q)\,\ddot q &= f(q, \dot q), \qquad \ddot q = {acc}, \qquad "
                      rf"M = {_matrix(M_sym)}, \qquad f = {_vector(f_sym)}",)))
    rows = [row for i in range(n) for j in range(i, n) if form.M[i, j] != 0
            for row in entry_rows(f"M_{{{i + 1}{j + 1}}}", form.M[i, j], tex)]
    out.append(Block("Mass matrix", "The entries on and above the diagonal (M is symmetric).", tuple(rows)))
    rows = [row for i in range(n) if form.f[i] != 0 for row in entry_rows(f"f_{{{i + 1}}}", form.f[i], tex)]
    out.append(Block("Force vector", "Collected over the products of rates and over the inputs; a long entry "
                     "continues on the lines below it.", tuple(rows)))
    return out


#: an entry longer than this (characters of LaTeX) continues on further lines, term by term
LINE_CHARS = 170


def entry_rows(name: str, expr, tex) -> list[str]:
    """``name &= expr`` as align rows: the terms packed greedily into lines of at most
    :data:`LINE_CHARS` characters, continuation lines starting ``&\\quad``."""
    sp = require_sympy()
    terms = [tex(t) for t in sp.sympify(expr).as_ordered_terms()]
    lines, current = [], ""
    for t in terms:
        piece = t if not current else (f"- {t[1:].lstrip()}" if t.startswith("-") else f"+ {t}")
        if current and len(current) + len(piece) > LINE_CHARS:
            lines.append(current)
            current = piece
        else:
            current = f"{current} {piece}".strip()
    lines.append(current)
    return [f"{name} &= {lines[0]}"] + [rf"&\quad {line}" for line in lines[1:]]


def _entry_name(letter: str, i: int, j: int, M) -> str:
    if M[i, j] == 0:
        return "0"
    a, b = min(i, j), max(i, j)
    return f"{letter}_{{{a + 1}{b + 1}}}"


def _energy_text(s) -> str:
    text = "L = T - V. T: kinetic energy, "
    if s.translation:
        text += "rotation about the center of mass plus the translation of the center of mass (velocity v_c)"
    elif s.gravity:
        text += "rotation about the pivot: about the center of mass, plus the center of mass moving at omega x c"
    else:
        text += "rotation about the center of mass"
    return text + "; V: " + ("potential energy of gravity, -m g . (R c" + (" + p)." if s.translation else ").")
                             if s.gravity else "none (no gravity).")


def _energy_rows(s, form, tex) -> tuple:
    sp = require_sympy()
    wx, wy, wz = sp.symbols("omega_x omega_y omega_z")
    w = sp.Matrix([wx, wy, wz])
    T_rot = sp.expand((w.T * s.J * w)[0, 0] / 2)
    rows = [r"L &= T - V"]
    t = tex(T_rot)
    if s.translation:
        t += r" + \tfrac{1}{2}\, m \left\lvert v_c \right\rvert^{2}, \qquad v_c = \dot p + R\,(\omega \times c)"
    elif s.gravity:
        t += r" + \tfrac{1}{2}\, m \left\lvert \omega \times c \right\rvert^{2}"
    rows.append(rf"T &= {t}")
    rows.append(rf"V &= {tex(form.V)}")
    return tuple(rows)


def to_latex(doc: list[Block], header: list[str]) -> str:
    """A LaTeX fragment: ``%`` comment lines, then one ``align*`` per block."""
    out = [f"% {line}" for line in header]
    for b in doc:
        out += [f"% {b.title}: {b.text}", "\\begin{align*}", " \\\\\n".join(b.rows), "\\end{align*}"]
    return "\n".join(out) + "\n"


def to_markdown(doc: list[Block], header: list[str], title: str) -> str:
    """Markdown with ``$$`` display math (``aligned``), as GitHub, VS Code and Pandoc render it."""
    out = [f"# {title}", ""] + [f"{line}  " for line in header] + [""]
    for b in doc:
        out += [f"## {b.title}", "", b.text, "", "$$", "\\begin{aligned}", " \\\\\n".join(b.rows),
                "\\end{aligned}", "$$", ""]
    return "\n".join(out)
