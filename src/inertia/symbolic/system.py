"""The symbols of a rigid body described by Euler angles (and optionally a position).

:class:`EulerAngleSystem` holds every sympy symbol the two derivation routes share: the
generalized coordinates, their rates and accelerations, the body parameters and the inputs.
Time derivatives are formed by the chain rule on plain symbols (``d/dt f(q, q') =
df/dq q' + df/dq' q''``) instead of sympy ``Function('q')(t)`` objects, which keeps every
expression small and the derivation fast.

Model
-----
* Rotation only (default): the body turns about its origin, which is fixed in the world.
  Without gravity the origin is the center of mass, so the parameters are the inertia
  ``J`` about the center of mass (body axes, negated products: ``L = J omega``).  With
  gravity the center of mass sits at ``c`` (body frame) from the pivot and the mass ``m``
  enters.
* ``translation=True`` adds the world position ``p = (x, y, z)`` of the body origin as three
  more coordinates (placed first): a free 6-DOF body whose center of mass is at
  ``p + R c``.
* Inputs: a torque ``tau`` in body axes (a couple) and, when the center of mass is modelled,
  a force ``F`` in world axes applied at the center of mass.  Gravity is a uniform field
  ``g`` (world axes, m/s^2), potential ``V = -m g . r_com``.
"""

from __future__ import annotations

from .._core.errors import InputError
from ._sympy import require_sympy
from .rotations import angle_names, kinematic_matrix, parse_sequence, rotation_matrix

INERTIA_FORMS = ("full", "diagonal")


class EulerAngleSystem:
    """Symbols and basic kinematics of a rigid body parametrised by an Euler sequence.

    Parameters
    ----------
    sequence : str
        One of the twelve intrinsic sequences (default ``"ZYX"``: yaw, pitch, roll).
    translation : bool
        Add the world position of the body origin as coordinates (6-DOF).
    gravity : bool
        Add a uniform gravity field ``g`` (world axes) acting at the center of mass.
    inertia : ``"full"`` or ``"diagonal"``
        A general symmetric inertia (six symbols) or principal axes along the body axes.
    """

    def __init__(self, sequence: str = "ZYX", *, translation: bool = False, gravity: bool = False,
                 inertia: str = "full"):
        sp = require_sympy()
        if inertia not in INERTIA_FORMS:
            raise InputError(f"inertia must be one of {INERTIA_FORMS}, got {inertia!r}")
        self.sequence = parse_sequence(sequence)
        self.translation = bool(translation)
        self.gravity = bool(gravity)
        self.inertia_form = inertia
        #: the center of mass and the mass enter only with gravity or translation
        self.has_com = self.translation or self.gravity

        names = angle_names(self.sequence)
        self.angles = sp.symbols(names, real=True)
        self.position = sp.symbols("x y z", real=True) if self.translation else ()
        self.coordinates = tuple(self.position) + tuple(self.angles)
        self.rates = tuple(sp.Symbol(f"{s.name}_d", real=True) for s in self.coordinates)
        self.accelerations = tuple(sp.Symbol(f"{s.name}_dd", real=True) for s in self.coordinates)

        if inertia == "full":
            Jxx, Jyy, Jzz, Jxy, Jxz, Jyz = sp.symbols("J_xx J_yy J_zz J_xy J_xz J_yz", real=True)
            self.inertia_symbols = (Jxx, Jyy, Jzz, Jxy, Jxz, Jyz)
            self.J = sp.Matrix([[Jxx, Jxy, Jxz], [Jxy, Jyy, Jyz], [Jxz, Jyz, Jzz]])
        else:
            Jxx, Jyy, Jzz = sp.symbols("J_xx J_yy J_zz", positive=True)
            self.inertia_symbols = (Jxx, Jyy, Jzz)
            self.J = sp.diag(Jxx, Jyy, Jzz)
        if self.has_com:
            self.mass = sp.Symbol("m", positive=True)
            self.com = sp.Matrix(sp.symbols("c_x c_y c_z", real=True))
        else:
            self.mass, self.com = None, sp.zeros(3, 1)
        self.g = sp.Matrix(sp.symbols("g_x g_y g_z", real=True)) if self.gravity else sp.zeros(3, 1)
        self.torque_body = sp.Matrix(sp.symbols("tau_x tau_y tau_z", real=True))
        self.force_world = sp.Matrix(sp.symbols("F_x F_y F_z", real=True)) if self.has_com else sp.zeros(3, 1)

        self.R = rotation_matrix(self.sequence, self.angles)
        self.E = kinematic_matrix(self.sequence, self.angles)
        angle_rates = self.rates[len(self.position):]
        self.omega_body = self.E * sp.Matrix(angle_rates)

    # ------------------------------------------------------------------ bookkeeping

    @property
    def n(self) -> int:
        """Number of generalized coordinates (3 or 6)."""
        return len(self.coordinates)

    @property
    def parameters(self) -> tuple:
        """Body parameters in calling order: inertia entries, then m, c, then g."""
        out = tuple(self.inertia_symbols)
        if self.has_com:
            out += (self.mass,) + tuple(self.com)
        if self.gravity:
            out += tuple(self.g)
        return out

    @property
    def inputs(self) -> tuple:
        """Inputs in calling order: body torque, then (with a center of mass) world force."""
        out = tuple(self.torque_body)
        if self.has_com:
            out += tuple(self.force_world)
        return out

    def time_derivative(self, expr):
        """``d/dt`` of an expression in the coordinates and rates (chain rule)."""
        sp = require_sympy()
        if isinstance(expr, sp.MatrixBase):
            return expr.applyfunc(self.time_derivative)
        out = sp.S.Zero
        for q, qd, qdd in zip(self.coordinates, self.rates, self.accelerations):
            out += sp.diff(expr, q) * qd + sp.diff(expr, qd) * qdd
        return out

    def rate_of(self, matrix):
        """Elementwise time derivative of a matrix that depends on the coordinates only."""
        return matrix.applyfunc(lambda e: sum((e.diff(q) * qd for q, qd in zip(self.coordinates, self.rates)),
                                              start=0))

    def com_world(self):
        """World position of the center of mass, ``p + R c`` (``R c`` without translation)."""
        sp = require_sympy()
        p = sp.Matrix(self.position) if self.translation else sp.zeros(3, 1)
        return p + self.R * self.com

    def describe(self) -> dict:
        """Names and meanings of every symbol, for the JSON export and the docs."""
        return {
            "sequence": self.sequence,
            "rotation": f"R_world_body = R_{self.sequence[0]}({self.angles[0]}) R_{self.sequence[1]}({self.angles[1]}) "
                        f"R_{self.sequence[2]}({self.angles[2]}) (intrinsic)",
            "coordinates": [s.name for s in self.coordinates],
            "rates": [s.name for s in self.rates],
            "accelerations": [s.name for s in self.accelerations],
            "parameters": [s.name for s in self.parameters],
            "inputs": [s.name for s in self.inputs],
            "units": "SI: angles rad, positions m, J kg m^2 about the center of mass in body axes "
                     "(negated products, L = J omega), m kg, c m (body axes), g m/s^2 and F N (world axes), "
                     "tau N m (body axes)",
        }
