"""Route (a): the body as constrained point masses.

Each particle k has a mass ``m_k`` and a fixed position ``r_k`` in body axes; its world
position is ``p + R(q) r_k`` (``R(q) r_k`` without translation).  The Lagrangian is the
literal sum ``L = sum_k 1/2 m_k |d/dt (p + R r_k)|^2 + sum_k m_k g . (p + R r_k)`` with
``d/dt R = sum_j dR/dq_j q_j'``, and the Euler-Lagrange equations are formed term by term::

    M(q) q'' = Q - (d^2 L / dq' dq) q' + dL/dq,       M = d^2 L / dq'^2

Generalized forces come from virtual work: a body torque (a couple) contributes
``E^T tau`` to the angles; a world force at the center of mass contributes
``(d r_com / dq)^T F``.  Nothing is simplified or solved symbolically: :func:`numeric`
evaluates ``M`` and the right-hand side and solves the small system with LU.

With the six-point (or four-point) model of :mod:`inertia.particles` the particles
reproduce the body's mass, center of mass and inertia, so route (a) must give the same
accelerations as route (b); the tests check that at random states.
"""

from __future__ import annotations

import numpy as np

from .._core.errors import InputError
from ._sympy import require_sympy
from .system import EulerAngleSystem


class ParticleRoute:
    """Symbolic Euler-Lagrange equations of ``n_particles`` point masses rigidly attached to the body.

    Symbols ``mu_k`` (masses) and ``r_k = (rx_k, ry_k, rz_k)`` (body-frame positions) are
    the route's own parameters; the system's inertia, mass and center-of-mass symbols are
    not used (they are implied by the particles).
    """

    def __init__(self, system: EulerAngleSystem, n_particles: int = 6):
        sp = require_sympy()
        self.system = system
        self.n_particles = int(n_particles)
        self.masses = sp.symbols(f"mu_0:{self.n_particles}", positive=True)
        self.positions = [sp.Matrix(sp.symbols(f"rx_{k} ry_{k} rz_{k}", real=True))
                          for k in range(self.n_particles)]
        s = system
        p = sp.Matrix(s.position) if s.translation else sp.zeros(3, 1)
        p_dot = sp.Matrix(s.rates[:3]) if s.translation else sp.zeros(3, 1)
        R_dot = s.rate_of(s.R)
        T, V = sp.S.Zero, sp.S.Zero
        for m_k, r_k in zip(self.masses, self.positions):
            v = p_dot + R_dot * r_k
            T += m_k * (v.T * v)[0, 0] / 2
            if s.gravity:
                V -= m_k * (s.g.T * (p + s.R * r_k))[0, 0]
        self.lagrangian = T - V
        q, qd = s.coordinates, s.rates
        dL_dqd = [sp.diff(self.lagrangian, v) for v in qd]
        self.mass_matrix = sp.Matrix(s.n, s.n, lambda i, j: sp.diff(dL_dqd[i], qd[j]))
        # d/dt (dL/dq') without the q'' part, minus dL/dq
        bias = [sum((sp.diff(dL_dqd[i], q[j]) * qd[j] for j in range(s.n)), start=sp.S.Zero)
                - sp.diff(self.lagrangian, q[i]) for i in range(s.n)]
        # generalized forces: E^T tau on the angles, (d r_com / dq)^T F on everything
        total = sum(self.masses, start=sp.S.Zero)
        com = sum((m * r for m, r in zip(self.masses, self.positions)), start=sp.zeros(3, 1)) / total
        Q = sp.zeros(s.n, 1)
        nt = len(s.position)
        Q[nt:, 0] = s.E.T * s.torque_body
        if s.has_com:
            r_com = p + s.R * com
            Q += r_com.jacobian(q).T * s.force_world
        self.rhs = Q - sp.Matrix(bias)
        self._fn = None

    @property
    def symbols(self) -> tuple:
        """Argument order of the numeric functions."""
        s = self.system
        flat = tuple(x for r in self.positions for x in r)
        g = tuple(s.g) if s.gravity else ()
        return tuple(s.coordinates) + tuple(s.rates) + tuple(self.masses) + flat + g + s.inputs

    def numeric(self, q, qd, masses, positions_body, *, gravity=None, torque_body=None, force_world=None):
        """Accelerations ``q''`` at one state by LU on ``M q'' = rhs`` (NumPy floats)."""
        sp = require_sympy()
        s = self.system
        if self._fn is None:
            self._fn = sp.lambdify(self.symbols, [self.mass_matrix, self.rhs], modules="numpy", cse=True)
        masses = np.asarray(masses, float).reshape(-1)
        positions_body = np.asarray(positions_body, float).reshape(-1, 3)
        if masses.shape[0] != self.n_particles or positions_body.shape[0] != self.n_particles:
            raise InputError(f"this route was derived for {self.n_particles} particles, got "
                             f"{masses.shape[0]} masses and {positions_body.shape[0]} positions")
        args = list(np.asarray(q, float)) + list(np.asarray(qd, float)) + list(masses) + list(positions_body.ravel())
        if s.gravity:
            args += list(np.asarray(gravity if gravity is not None else (0, 0, 0), float))
        args += list(np.asarray(torque_body if torque_body is not None else (0, 0, 0), float))
        if s.has_com:
            args += list(np.asarray(force_world if force_world is not None else (0, 0, 0), float))
        M, rhs = self._fn(*args)
        return np.linalg.solve(np.asarray(M, float), np.asarray(rhs, float).reshape(-1))
