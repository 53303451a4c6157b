"""The equations of motion as a person reads them: ``M(q) q'' = f(q, q')`` and the Lagrangian.

The CSE form of :class:`~.equations.EquationsOfMotion` is for code generation; this module
writes the same dynamics the way a textbook does, with standard symbols (``\\dot\\psi``,
``\\ddot\\theta``):

* the Lagrangian ``L = T - V``: ``T = 1/2 omega^T J omega`` (plus ``1/2 m |v_c|^2`` with
  translation), the body angular velocity ``omega = E(q) q'`` component by component, and
  ``V = -m g . R c`` with gravity;
* the mass matrix ``M(q) = d^2 L / dq'^2`` and the force vector ``f = Q + dL/dq - (d^2 L /
  dq' dq) q'`` of the Euler-Lagrange equations ``M(q) q'' = f(q, q')``.

They are built from their structure, not by differentiating: about the body origin o (the
center of mass without gravity or translation, the pivot with gravity, the body origin
with translation) ``J_o = J + m (|c|^2 1 - c c^T)``, and

    M_aa = E^T J_o E,   f_a = E^T [tau + c x R^T (F + m g) - J_o E' q'_a - omega x J_o omega]
    M_pp = m 1,   M_pa = -m R [c]x E,
    f_p = F + m g + m R [c]x E' q'_a - m R (omega x (omega x c))      (translation)

(``a``: the angles, ``p``: the position).  Each entry is expanded into a polynomial in
sines and cosines, collected over the rate products and the inputs, and each coefficient
is made compact cheaply: ``sin^2 + cos^2 = 1`` is applied per angle in whichever direction
leaves fewer terms (a polynomial remainder), and ``trigsimp`` runs on small coefficients
only.  Nothing is ever passed to ``simplify``.  The tests check ``M^-1 f`` against the CSE
form, ``M`` and ``f`` against the Lagrangian differentiated by sympy, and the LaTeX, parsed
back, against both.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ._sympy import require_sympy
from .rigid import pivot_inertia
from .system import EulerAngleSystem


@dataclass
class ReadableForm:
    """``M (n, n)``, ``f (n, 1)``: ``M(q) q'' = f``; ``omega`` (3, 1) the body angular velocity
    in the rates; ``T``, ``V`` the kinetic and potential energy; ``v_com`` (3, 1) the world
    velocity of the center of mass (translation only, else None)."""

    system: EulerAngleSystem
    M: object
    f: object
    omega: object
    T: object
    V: object
    v_com: object

    @property
    def lagrangian(self):
        return self.T - self.V


def _cross_matrix(c):
    sp = require_sympy()
    return sp.Matrix([[0, -c[2], c[1]], [c[2], 0, -c[0]], [-c[1], c[0], 0]])


def readable_form(system: EulerAngleSystem) -> ReadableForm:
    """``M``, ``f``, ``omega``, ``T`` and ``V`` of ``system``, each entry compact."""
    sp = require_sympy()
    s = system
    nt = len(s.position)
    angle_rates = sp.Matrix(s.rates[nt:])
    w = s.omega_body
    J = pivot_inertia(s) if not s.translation else _origin_inertia(s)
    Edot_qd = s.rate_of(s.E) * angle_rates
    load = s.force_world + (s.mass * s.g if s.gravity else sp.zeros(3, 1))
    tau = s.torque_body + (s.com.cross(s.R.T * load) if s.has_com else sp.zeros(3, 1))
    M_aa = s.E.T * J * s.E
    f_a = s.E.T * (tau - J * Edot_qd - w.cross(J * w))
    if s.translation:
        cx = _cross_matrix(s.com)
        M_pa = -s.mass * s.R * cx * s.E
        M = sp.Matrix(sp.BlockMatrix([[s.mass * sp.eye(3), M_pa], [M_pa.T, M_aa]]))
        f_p = load + s.mass * s.R * cx * Edot_qd - s.mass * s.R * w.cross(w.cross(s.com))
        f = sp.Matrix.vstack(f_p, f_a)
    else:
        M, f = M_aa, f_a
    inner = tuple(s.parameters)
    M = M.applyfunc(lambda e: arrange(e, s.angles, (), inner))
    f = f.applyfunc(lambda e: arrange(e, s.angles, tuple(s.rates) + tuple(s.inputs) + _g(s), inner))
    omega = w.applyfunc(lambda e: arrange(e, s.angles, tuple(s.rates), ()))
    T, V, v_com = _energies(s, w)
    return ReadableForm(s, M, f, omega, T, V, v_com)


def _g(s) -> tuple:
    return tuple(s.g) if s.gravity else ()


def _origin_inertia(s):
    """Inertia about the body origin, ``J + m (|c|^2 1 - c c^T)`` (translation: the origin is
    not the center of mass)."""
    sp = require_sympy()
    c = s.com
    return s.J + s.mass * ((c.T * c)[0, 0] * sp.eye(3) - c * c.T)


def _energies(s, w):
    sp = require_sympy()
    T = (w.T * s.J * w)[0, 0] / 2 if s.translation else (w.T * pivot_inertia(s) * w)[0, 0] / 2
    v_com = None
    if s.translation:
        v_com = sp.Matrix(s.rates[:3]) + s.R * w.cross(s.com)
        T = T + s.mass * (v_com.T * v_com)[0, 0] / 2
    V = -s.mass * (s.g.T * s.com_world())[0, 0] if s.gravity else sp.S.Zero
    V = arrange(V, s.angles, tuple(s.g) + tuple(s.position), tuple(s.parameters)) if s.gravity else V
    return T, V, v_com


def arrange(expr, angles, outer, inner):
    """``expr`` (a polynomial in the sines and cosines of ``angles`` and in other symbols) as
    ``sum_k key_k * c_k * trig_k * (sum_j inner_j * trig_kj)``: grouped by the monomials of the
    ``outer`` symbols (rates, inputs), inside each group by those of the ``inner`` symbols
    (inertia, mass, center of mass); each trigonometric coefficient shortened (:func:`shorten`),
    and the group's common number ``c_k`` and trigonometric factor ``trig_k`` taken out.
    Polynomial arithmetic over the rationals: fast, and never simplify."""
    sp = require_sympy()
    e = sp.sympify(expr)
    if e == 0:
        return sp.S.Zero
    trig = [f(a) for a in angles for f in (sp.sin, sp.cos)]
    others = sorted(e.free_symbols - set(angles), key=sp.default_sort_key)
    poly = sp.Poly(e, *trig, *others, domain="QQ")
    nt = len(trig)
    is_outer = [g in set(outer) for g in others]
    groups: dict = {}
    for exps, coeff in poly.as_dict().items():
        oe = exps[nt:]
        key = tuple(x if o else 0 for x, o in zip(oe, is_outer))
        sub = tuple(0 if o else x for x, o in zip(oe, is_outer))
        groups.setdefault(key, {}).setdefault(sub, {})[exps[:nt] + (0,) * nt] = coeff
    gens = trig + [f(2 * a) for a in angles for f in (sp.sin, sp.cos)]
    out = sp.S.Zero
    for key in sorted(groups, reverse=True):
        parts = {sub: shorten(t, len(angles)) for sub, t in groups[key].items()}
        parts = {sub: t for sub, t in parts.items() if t}
        if parts:
            out += _monomial(others, key) * _factored(parts, others, gens)
    return out


def _factored(parts: dict, others, gens):
    """``c * trig * sum_j inner_j * t_j`` with the common number c and trig monomial pulled out."""
    sp = require_sympy()
    every = [(te, c) for t in parts.values() for te, c in t.items()]
    common = tuple(min(te[i] for te, _ in every) for i in range(len(gens)))
    numbers = [sp.Rational(c) for _, c in every]
    content = math.gcd(*[int(n.p) for n in numbers]) if all(n.q == 1 for n in numbers) else 1
    if all(n < 0 for n in numbers):
        content = -content
    total = sp.S.Zero
    for sub in sorted(parts, reverse=True):
        t = parts[sub]
        total += _monomial(others, sub) * sp.Add(*(sp.Rational(c) / content * _monomial(
            gens, tuple(a - b for a, b in zip(te, common))) for te, c in t.items()))
    return content * _monomial(gens, common) * total


def _monomial(gens, exps):
    sp = require_sympy()
    return sp.Mul(*(g ** k for g, k in zip(gens, exps) if k))


def shorten(terms: dict, n_angles: int) -> dict:
    """A trigonometric polynomial ``{exponents: coefficient}`` over the generators
    ``sin a1, cos a1, ..., sin 2a1, cos 2a1, ...`` made shorter: ``sin^2 + cos^2 = 1`` per angle
    in whichever direction leaves fewer terms, then the double angles ``2 sin a cos a = sin 2a``
    and ``cos^2 a - sin^2 a = cos 2a`` where a term or a pair of terms has that form."""
    best = {k: v for k, v in terms.items() if v}
    for a in list(range(n_angles)) * 2:          # twice: a reduction in one angle can pair terms in another
        options = [best] + [_reduce(best, 2 * a + i) for i in (0, 1)]
        best = min(options, key=len)
        best = _double_angle(best, a, n_angles)
    return best


def _reduce(terms: dict, slot: int) -> dict:
    """Replace the square of generator ``slot`` (sin or cos of one angle) by one minus the
    square of its partner until no power above one is left."""
    partner = slot + 1 if slot % 2 == 0 else slot - 1
    out: dict = {}
    todo = list(terms.items())
    while todo:
        exps, c = todo.pop()
        if exps[slot] < 2:
            out[exps] = out.get(exps, 0) + c
            continue
        lower = list(exps)
        lower[slot] -= 2
        todo.append((tuple(lower), c))
        lower[partner] += 2
        todo.append((tuple(lower), -c))
    return {k: v for k, v in out.items() if v}


def _double_angle(terms: dict, a: int, n_angles: int) -> dict:
    """``k X sin a cos a -> k/2 X sin 2a``; ``k X cos^2 a - k X sin^2 a -> k X cos 2a``."""
    si, ci, s2, c2 = 2 * a, 2 * a + 1, 2 * n_angles + 2 * a, 2 * n_angles + 2 * a + 1
    out = dict(terms)
    for exps, c in terms.items():
        if exps not in out:
            continue
        e = list(exps)
        if exps[si] == 1 and exps[ci] == 1:
            e[si] = e[ci] = 0
            e[s2] += 1
            del out[exps]
            _add(out, tuple(e), c / 2)
        elif exps[ci] == 2 and exps[si] == 0:
            e[ci], e[si] = 0, 2
            twin = tuple(e)
            if out.get(twin) == -c:
                del out[exps], out[twin]
                e[si] = 0
                e[c2] += 1
                _add(out, tuple(e), c)
    return out


def _add(d: dict, key, value) -> None:
    v = d.get(key, 0) + value
    if v:
        d[key] = v
    else:
        d.pop(key, None)
