"""Derived equations of motion in Euler angles, and everything made from them.

:func:`derive` builds the accelerations by route (b) (:mod:`.rigid`), eliminates common
subexpressions once, and returns an :class:`EquationsOfMotion` that exports them as

* a fast NumPy function (:meth:`EquationsOfMotion.numeric`, batched over leading axes, with
  a gimbal-lock check at run time),
* Python source (:meth:`~EquationsOfMotion.python_code`), C source
  (:meth:`~EquationsOfMotion.c_code`), LaTeX (:meth:`~EquationsOfMotion.latex`) and a
  JSON-ready dict (:meth:`~EquationsOfMotion.to_dict`).

Gimbal lock: ``det E`` is ``+-cos q2`` (Tait-Bryan) or ``+-sin q2`` (proper Euler).  Where it
vanishes the angle rates are undefined for a general angular velocity.  The numeric
function raises :class:`GimbalLockError` when ``|det E| <`` :data:`GIMBAL_LOCK_TOL` and warns
(:class:`GimbalLockWarning`) when ``|det E| <`` :data:`GIMBAL_WARN_TOL`, where the mass matrix
has a condition number above ~1e6.  Bodies that may turn through those attitudes should use
quaternions (:mod:`inertia.dynamics`).
"""

from __future__ import annotations

import json
import math
import warnings

import numpy as np

from .._core.errors import InertiaError, InertiaWarning, InputError
from .._core.validation import as_float_array, as_symmetric_matrix3
from ._sympy import require_sympy
from .rigid import accelerations as _rigid_accelerations
from .rigid import lagrangian as _rigid_lagrangian
from .rotations import singular_function
from .system import EulerAngleSystem

#: |det E| below which the numeric function refuses the state (E^-1 overflows to garbage)
GIMBAL_LOCK_TOL = 1e-8
#: |det E| below which it warns: cond(M) ~ 1/det(E)^2 exceeds 1e6
GIMBAL_WARN_TOL = 1e-3


class GimbalLockError(InertiaError, ArithmeticError):
    """The Euler angles are at (or numerically at) their singular attitude."""


class GimbalLockWarning(InertiaWarning):
    """The Euler angles are close to their singular attitude; accuracy is being lost."""


def _count_ops(replacements, reduced) -> int:
    sp = require_sympy()
    return int(sum(sp.count_ops(e) for _, e in replacements) + sum(sp.count_ops(e) for e in reduced))


class EquationsOfMotion:
    """Accelerations ``q'' = f(q, q', parameters, inputs)`` of a body in Euler angles.

    Attributes
    ----------
    system : EulerAngleSystem
        The symbols (coordinates, rates, parameters, inputs) and the model options.
    accelerations : sympy Matrix (n, 1)
        ``q''`` before common-subexpression elimination.
    replacements, reduced :
        The CSE form: ``replacements`` is a list of ``(symbol, expression)`` evaluated in
        order, ``reduced`` the n output expressions in terms of them.
    """

    def __init__(self, system: EulerAngleSystem):
        sp = require_sympy()
        self.system = system
        self.accelerations = _rigid_accelerations(system)
        self.replacements, self.reduced = sp.cse(list(self.accelerations),
                                                 symbols=sp.numbered_symbols("x"), order="none")
        self._numeric = None
        self._readable = None

    # ------------------------------------------------------------------ facts

    @property
    def count_ops(self) -> int:
        """sympy ``count_ops`` of the CSE form (subexpressions + outputs)."""
        return _count_ops(self.replacements, self.reduced)

    @property
    def arguments(self) -> tuple:
        """Flat argument order: coordinates, rates, parameters, inputs."""
        s = self.system
        return tuple(s.coordinates) + tuple(s.rates) + tuple(s.parameters) + tuple(s.inputs)

    @property
    def singularity(self) -> tuple[str, int]:
        """``("cos"|"sin", sign)`` with ``det E = sign * trig(q2)``."""
        return singular_function(self.system.sequence)

    def lagrangian(self):
        """``L = T - V`` (rigid-body form) as a sympy expression."""
        return _rigid_lagrangian(self.system)

    # ------------------------------------------------------------------ numeric

    def numeric(self):
        """A NumPy function ``f(q, qd, *, inertia, mass=None, com=None, gravity=None,
        torque_body=None, force_world=None, on_singular="raise") -> qdd``.

        ``q``, ``qd``: (..., n) coordinates [m, rad] and rates [m/s, rad/s] in the order of
        ``system.coordinates``.  ``inertia``: (3, 3) about the center of mass in body axes
        [kg m^2] (negated products), or (3,) principal moments for ``inertia="diagonal"``.
        ``mass`` [kg] and ``com`` (3,) [m, body axes] are needed with gravity or translation;
        ``gravity`` (3,) [m/s^2, world axes]; ``torque_body`` (..., 3) [N m];
        ``force_world`` (..., 3) [N, at the center of mass].  ``on_singular``: "raise",
        "warn" or "ignore" (see the module docstring for the thresholds).
        """
        sp = require_sympy()
        if self._numeric is None:
            fn = sp.lambdify(self.arguments, list(self.accelerations), modules="numpy", cse=True)
            self._numeric = _NumericAccelerations(self, fn)
        return self._numeric

    # ------------------------------------------------------------------ code

    def _function_name(self) -> str:
        s = self.system
        name = f"inertia_eom_{s.sequence.lower()}"
        if s.translation:
            name += "_6dof"
        if s.gravity:
            name += "_gravity"
        return name

    def _header_lines(self, comment: str, first: str = "route: E^T form, CSE") -> list[str]:
        s = self.system
        d = s.describe()
        trig, sign = self.singularity
        lines = [
            f"Equations of motion in Euler angles, generated by inertia ({first}).",
            d["rotation"],
            "coordinates: " + ", ".join(d["coordinates"]),
            "parameters: " + ", ".join(d["parameters"]),
            "inputs: " + ", ".join(d["inputs"]),
            d["units"],
            f"singular (gimbal lock) where det E = {'-' if sign < 0 else ''}{trig}({s.angles[1]}) = 0",
            f"count_ops (CSE form): {self.count_ops}",
        ]
        return [f"{comment} {line}".lstrip() for line in lines]

    def python_code(self) -> str:
        """A standalone Python function (``math`` only) returning the list of accelerations."""
        require_sympy()
        from sympy.printing.pycode import PythonCodePrinter

        printer = PythonCodePrinter({"standard": "python3"})
        s = self.system
        trig, _ = self.singularity
        args = ", ".join(a.name for a in self.arguments)
        out = self._header_lines("#")
        out += ["import math", "", "", f"def {self._function_name()}({args}):",
                f'    """Accelerations [{", ".join(a.name for a in s.accelerations)}]; '
                f'raises ZeroDivisionError at gimbal lock."""',
                f"    if abs(math.{trig}({s.angles[1].name})) < {GIMBAL_LOCK_TOL!r}:",
                f"        raise ZeroDivisionError('gimbal lock: {trig}({s.angles[1].name}) = 0')"]
        for sym, expr in self.replacements:
            out.append(f"    {sym} = {printer.doprint(expr)}")
        out.append("    return [" + ", ".join(printer.doprint(e) for e in self.reduced) + "]")
        return "\n".join(out) + "\n"

    def c_code(self) -> str:
        """A C99 function ``int NAME(const double *q, const double *qd, const double *params,
        const double *inputs, double *qdd)``; returns 0, or 1 at gimbal lock (qdd untouched)."""
        sp = require_sympy()
        s = self.system
        trig, _ = self.singularity
        used = set().union(*(e.free_symbols for _, e in self.replacements), *(e.free_symbols for e in self.reduced))
        used.add(s.angles[1])  # the gimbal-lock test reads it
        unpack = []
        for arr, syms in (("q", s.coordinates), ("qd", s.rates), ("params", s.parameters), ("inputs", s.inputs)):
            unpack += [f"    const double {v.name} = {arr}[{i}];" for i, v in enumerate(syms) if v in used]
        out = self._header_lines("//")
        out += ["#include <math.h>", "",
                f"int {self._function_name()}(const double *q, const double *qd, const double *params,",
                "    const double *inputs, double *qdd)", "{"]
        out += unpack
        out += [f"    if (fabs({trig}({s.angles[1].name})) < {GIMBAL_LOCK_TOL!r}) return 1;  /* gimbal lock */"]
        for sym, expr in self.replacements:
            out.append(f"    const double {sym} = {sp.ccode(expr, standard='C99')};")
        for i, e in enumerate(self.reduced):
            out.append(f"    qdd[{i}] = {sp.ccode(e, standard='C99')};")
        out += ["    return 0;", "}"]
        return "\n".join(out) + "\n"

    def readable(self):
        """The :class:`~.readable.ReadableForm`: ``M(q) q'' = f(q, q')``, the Lagrangian, compact entries."""
        if self._readable is None:
            from .readable import readable_form

            self._readable = readable_form(self.system)
        return self._readable

    def latex(self, form: str = "readable") -> str:
        """LaTeX: ``form="readable"`` the Lagrangian, the mass matrix and the force vector with
        textbook symbols (:mod:`.document`); ``form="cse"`` the common-subexpression form
        that the generated code evaluates."""
        if form == "cse":
            return self.cse_latex()
        if form != "readable":
            raise InputError(f"LaTeX form must be 'readable' or 'cse', got {form!r}")
        from .document import to_latex

        return to_latex(self.document(), self.readable_header())

    def markdown(self) -> str:
        """The readable form as Markdown with ``$$`` display math."""
        from .document import to_markdown

        return to_markdown(self.document(), self.readable_header(), self.title())

    def document(self) -> list:
        """The readable form as titled blocks of LaTeX rows (:mod:`.document`), for any writer."""
        from .document import blocks

        return blocks(self.readable())

    def readable_header(self) -> list[str]:
        """The model in words (rotation, symbols, units, singularity), one line each."""
        return self._header_lines("", "readable form")

    def title(self) -> str:
        s = self.system
        what = "free rigid body" if s.translation else ("heavy top" if s.gravity else "rotating rigid body")
        return f"Equations of motion of a {what} in {s.sequence} Euler angles"

    def cse_latex(self) -> str:
        """LaTeX (``align*``): the rotation, the Lagrangian's structure and the CSE'd accelerations."""
        sp = require_sympy()
        s = self.system
        ddot = [sp.Symbol(rf"\ddot{{{sp.latex(q)}}}") for q in s.coordinates]
        rows = [rf"R &= R_{{{s.sequence[0]}}}({sp.latex(s.angles[0])})\, R_{{{s.sequence[1]}}}({sp.latex(s.angles[1])})"
                rf"\, R_{{{s.sequence[2]}}}({sp.latex(s.angles[2])}), \quad \omega = E(q)\,\dot q",
                r"E^\top\!\left[J\,(E\ddot q + \dot E \dot q) + \omega \times J\omega\right] &= E^\top \tau"]
        rows += [rf"{sp.latex(sym)} &= {sp.latex(expr)}" for sym, expr in self.replacements]
        rows += [rf"{sp.latex(d)} &= {sp.latex(e)}" for d, e in zip(ddot, self.reduced)]
        return "\\begin{align*}\n" + " \\\\\n".join(rows) + "\n\\end{align*}\n"

    def to_dict(self) -> dict:
        """JSON-ready description: symbols, the CSE form as strings, counts and the singularity."""
        trig, sign = self.singularity
        d = self.system.describe()
        d.update({
            "inertia": self.system.inertia_form,
            "translation": self.system.translation,
            "gravity": self.system.gravity,
            "subexpressions": [[str(sym), str(expr)] for sym, expr in self.replacements],
            "outputs": [str(e) for e in self.reduced],
            "count_ops": self.count_ops,
            "singularity": {"det_E": f"{'-' if sign < 0 else ''}{trig}({self.system.angles[1]})",
                            "lock_tolerance": GIMBAL_LOCK_TOL, "warn_tolerance": GIMBAL_WARN_TOL},
        })
        return d

    def to_json(self) -> str:
        return json.dumps(self.to_dict(), indent=2)


class _NumericAccelerations:
    """The callable returned by :meth:`EquationsOfMotion.numeric`."""

    def __init__(self, eom: EquationsOfMotion, fn):
        self.eom = eom
        self._fn = fn
        trig, sign = eom.singularity
        self._det = (lambda x: sign * np.cos(x)) if trig == "cos" else (lambda x: sign * np.sin(x))

    def det_kinematic(self, q) -> np.ndarray:
        """``det E`` at the coordinates ``q`` (..., n)."""
        nt = len(self.eom.system.position)
        return self._det(np.asarray(q, float)[..., nt + 1])

    def __call__(self, q, qd, *, inertia, mass=None, com=None, gravity=None, torque_body=None,
                 force_world=None, on_singular: str = "raise") -> np.ndarray:
        s = self.eom.system
        n = s.n
        q = as_float_array(q, "q", (n,))
        qd = as_float_array(qd, "qd", (n,))
        params = list(_inertia_params(inertia, s.inertia_form))
        if s.has_com:
            if mass is None or com is None:
                raise InputError("this model has a center of mass (gravity or translation): give mass= [kg] "
                                 "and com= (3,) [m, body axes]")
            m = float(mass)
            if not (math.isfinite(m) and m > 0):
                raise InputError(f"mass must be finite and positive, got {mass!r}")
            params += [m] + list(as_float_array(com, "com", (3,), allow_batch=False))
        if s.gravity:
            if gravity is None:
                raise InputError("this model has gravity: give gravity= (3,) [m/s^2, world axes], "
                                 "e.g. (0, 0, -9.81)")
            params += list(as_float_array(gravity, "gravity", (3,), allow_batch=False))
        tau = as_float_array(torque_body if torque_body is not None else (0.0, 0.0, 0.0), "torque_body", (3,))
        inputs = [tau[..., i] for i in range(3)]
        if s.has_com:
            F = as_float_array(force_world if force_world is not None else (0.0, 0.0, 0.0), "force_world", (3,))
            inputs += [F[..., i] for i in range(3)]
        det = np.abs(self.det_kinematic(q))
        if on_singular not in ("raise", "warn", "ignore"):
            raise InputError(f"on_singular must be 'raise', 'warn' or 'ignore', got {on_singular!r}")
        worst = float(det.min(initial=np.inf))
        if worst < GIMBAL_LOCK_TOL and on_singular == "raise":
            k = np.unravel_index(int(np.argmin(det)), det.shape) if det.ndim else ()
            name = s.angles[1].name
            raise GimbalLockError(
                f"gimbal lock: |det E| = {worst:.3g} < {GIMBAL_LOCK_TOL:g} at state {tuple(int(i) for i in k)} "
                f"({name} = {float(q[k + (len(s.position) + 1,)]):.12g} rad): the {s.sequence} angle rates are "
                "undefined there. Use quaternions (inertia.dynamics) for attitudes that pass through it, "
                "or another Euler sequence whose singularity is elsewhere.")
        if worst < GIMBAL_WARN_TOL and on_singular != "ignore":
            warnings.warn(f"near gimbal lock: |det E| = {worst:.3g}; the mass matrix has condition number "
                          f"~{1 / max(worst, 1e-300) ** 2:.2g} and the accelerations lose accuracy",
                          GimbalLockWarning, stacklevel=2)
        args = [q[..., i] for i in range(n)] + [qd[..., i] for i in range(n)] + params + inputs
        with np.errstate(divide="ignore", invalid="ignore"):
            out = self._fn(*args)
        shape = np.broadcast_shapes(q.shape[:-1], qd.shape[:-1], tau.shape[:-1])
        return np.stack([np.broadcast_to(np.asarray(o, float), shape) for o in out], axis=-1)


def _inertia_params(inertia, form: str):
    if form == "diagonal":
        arr = np.asarray(inertia, float)
        if arr.shape == (3, 3):
            if np.abs(arr - np.diag(np.diag(arr))).max() > 0:
                raise InputError("inertia='diagonal' model given a non-diagonal inertia; derive with inertia='full'")
            arr = np.diag(arr)
        arr = as_float_array(arr, "inertia (principal moments)", (3,), allow_batch=False)
        return tuple(arr)
    J = as_symmetric_matrix3(inertia, "inertia", allow_batch=False)
    return (J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2])


def derive(sequence: str = "ZYX", *, translation: bool = False, gravity: bool = False,
           inertia: str = "full") -> EquationsOfMotion:
    """Equations of motion of a rigid body in Euler angles (see :class:`EulerAngleSystem`).

    The angular accelerations of a torque-free body at one configuration (angles [rad],
    rates [rad/s], inertia in body axes [kg m^2]):

    >>> import numpy as np
    >>> from inertia.symbolic import derive
    >>> f = derive("ZYX").numeric()
    >>> f([0.3, -0.2, 0.1], [0.1, 0.2, 0.3], inertia=np.diag([1.0, 2.0, 3.0]))
    array([ 0.0370925 , -0.00249772, -0.00395917])
    """
    return EquationsOfMotion(EulerAngleSystem(sequence, translation=translation, gravity=gravity,
                                              inertia=inertia))
