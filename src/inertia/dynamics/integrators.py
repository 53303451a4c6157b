"""Fixed-step integrators for the rotational motion of a rigid body in its principal frame.

Every method has the same signature, so callers can swap them::

    q_next, omega_next = step_<name>(q_world_body, omega_body, moments, h, torque_body=None)

* ``q_world_body`` (..., 4): unit quaternion, scalar first ``(w, x, y, z)``, body -> world.
* ``omega_body`` (..., 3) [rad/s]: angular velocity of the body, expressed in the body frame.
* ``moments`` (..., 3) [kg m^2]: principal moments of inertia about the center of mass.
  **The body frame must be the principal frame** (inertia ``diag(moments)`` in it); rotate
  a general inertia to its principal axes first (:func:`inertia.massprops.principal_axes`).
* ``h`` [s]: step size, finite and non-zero (negative steps integrate backwards; the
  symmetric methods then retrace their forward steps to rounding).
* ``torque_body`` (..., 3) [N m] or None: torque about the center of mass **expressed in the
  body frame and held constant in the body frame over the step** (a zero-order hold).

Leading batch dimensions broadcast.  The returned quaternion is normalised.
:data:`METHODS` maps the public names to the step functions; :func:`integrate` runs many
steps and records a :class:`Trajectory`.

Summary (free body; measured figures in ``docs/dynamics.md`` and the tests):

============== ===== =================== ======= ========= =================================
name           order energy              ``|L|`` spatial L  with torque
============== ===== =================== ======= ========= =================================
euler_explicit 1     grows every step    grows   drifts    explicit, order 1
euler_implicit 1     decays              decays  drifts    in the Newton step, order 1
rk4            4     slow drift          drift   drift     constant body torque, order 4
splitting      2     bounded error       exact   exact     kick-drift-kick, order 2
dmv            2     exact               exact   exact     kick-DMV-kick, order 2
dmv4           4     exact               exact   exact     kick-DMV4-kick, order 2
midpoint       2     exact               exact   drifts    inside the implicit step, order 2
============== ===== =================== ======= ========= =================================

"exact" means conserved to rounding (about 1e-15 per step, a random walk).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .._core.errors import InputError, IntegrationError  # noqa: F401 (re-exported)
from .._core.validation import as_count, as_float_array, as_time_step, as_unit_quat
from ..massprops.validity import as_principal_moments
from .segments import METHOD_NAMES, NEWTON_MAX_ITER, run_segments

__all__ = [
    "step_euler_explicit",
    "step_euler_implicit",
    "step_rk4",
    "step_splitting",
    "step_dmv",
    "step_dmv4",
    "step_midpoint",
    "METHODS",
    "DEFAULT_METHOD",
    "METHOD_ORDER",
    "integrate",
    "integrate_segments",
    "check_method",
    "Trajectory",
    "NEWTON_MAX_ITER",
    "IntegrationError",
]



#: The integrator every entry point uses unless told otherwise (``integrate``, ``step``,
#: ``jacobians``, ``rollout``, the gyrostat's ``gyrostat_step``, ``gyrostat_jacobians``,
#: ``gyrostat_rollout``, ``design_spin_hold``, ``inertia simulate``): the splitting method.  Explicit, second
#: order, time-symmetric; it keeps |L| and the world-frame L exactly and the energy error
#: bounded for all time (rk4's drifts), it takes torques and the 6-DOF inputs like every
#: method, and costs about as much per step as rk4.
DEFAULT_METHOD = "splitting"


# ============================================================================ public steps
def _prepare(q_world_body, omega_body, moments, h, torque_body, *, validate: bool):
    q = as_unit_quat(q_world_body)
    w = as_float_array(omega_body, "omega_body", (3,))
    I = as_principal_moments(moments, validate=validate)
    hf = as_time_step(h)
    tau = None if torque_body is None else as_float_array(torque_body, "torque_body", (3,))
    shapes = [q.shape[:-1], w.shape[:-1], I.shape[:-1]] + ([] if tau is None else [tau.shape[:-1]])
    try:
        batch = np.broadcast_shapes(*shapes)
    except ValueError:
        raise InputError(f"batch shapes do not broadcast: q_world_body {q.shape}, omega_body {w.shape}, "
                         f"moments {I.shape}" + ("" if tau is None else f", torque_body {tau.shape}")) from None
    q = np.broadcast_to(q, batch + (4,))
    w = np.broadcast_to(w, batch + (3,))
    I = np.broadcast_to(I, batch + (3,))
    if tau is not None:
        tau = np.broadcast_to(tau, batch + (3,))
    return q, w, I, hf, tau


def _run(method, q_world_body, omega_body, moments, h, torque_body):
    # one step of Euler's equations: positive moments suffice (a body is validated where it
    # is set up: integrate, RigidBody, exact_solution)
    q, w, I, hf, tau = _prepare(q_world_body, omega_body, moments, h, torque_body, validate=False)
    qs, ws = run_segments(method, q, w, I, tau, [1], [hf], stop_if_not_finite=False)
    return qs[1], ws[1]


_PARAMS_DOC = """
    Parameters
    ----------
    q_world_body : (..., 4) float
        Unit quaternion (w, x, y, z), body -> world (renormalised if within 1e-6 of unit).
    omega_body : (..., 3) float, rad/s
        Angular velocity of the body, expressed in the (principal) body frame.
    moments : (..., 3) float, kg m^2
        Principal moments of inertia about the center of mass; the body frame is the
        principal frame.  Positive (a single step does not ask for the triangle inequality;
        :func:`integrate` does, unless ``validate=False``).
    h : float, s
        Step size (finite, non-zero; negative integrates backwards).
    torque_body : (..., 3) float, N m, or None
        Torque about the center of mass, body frame, constant in the body frame over the step.

    Returns
    -------
    q_next : (..., 4) float, unit quaternion.
    omega_next : (..., 3) float, rad/s, body frame.
"""


def step_euler_explicit(q_world_body, omega_body, moments, h, torque_body=None):
    """Semi-implicit Euler with an explicit gyroscopic term (game-engine / MuJoCo ``Euler``).

    ``w+ = w + h I^-1 (tau - w x I w)``, then ``q+ = q (x) exp(h w+ / 2)`` (the new
    velocity moves the attitude, as MuJoCo's ``Euler`` and Drake's discrete mode do).

    Order 1 in omega and attitude.  Invariants: none.  For the free body the kinetic energy
    **grows at every step by exactly** ``dT = 1/2 h^2 a . I a`` with ``a = I^-1 (I w x w)``
    (the cross term vanishes because ``a . I w = (I w x w) . w = 0``), and
    ``|m+|^2 = |m|^2 + h^2 |m x w|^2``.  The growth compounds (``dT/dt ~ h T^2``), so long
    runs blow up; the drift pushes the body toward its minor axis.  Torque: explicit,
    evaluated with the start-of-step state.
    """
    return _run("euler_explicit", q_world_body, omega_body, moments, h, torque_body)


def step_euler_implicit(q_world_body, omega_body, moments, h, torque_body=None):
    """Linearised backward Euler on omega (MuJoCo ``implicit`` for free bodies), exp-map attitude.

    One Newton step of ``I (w+ - w) = h f(w+)``, ``f(w) = I w x w + tau``:
    ``(I - h D) dw = h f(w)`` with ``D = df/dw = [I w]x - [w]x I``; then
    ``q+ = q (x) exp(h w+ / 2)``.

    Order 1.  Invariants: none.  For the free body the kinetic energy and ``|L|`` **decay**
    (numerical damping of order ``h |w|^2`` per unit time), so a tumbling body drifts
    toward its major axis.  Unconditionally stable in omega.  Torque: inside ``f``,
    constant over the step.
    """
    return _run("euler_implicit", q_world_body, omega_body, moments, h, torque_body)


def step_rk4(q_world_body, omega_body, moments, h, torque_body=None):
    """Classical RK4 on the quaternion components and omega, then renormalise q.

    Order 4 in omega **and** in attitude (RK4 treats ``dq/dt = 1/2 q (x) (0, w)`` as an
    ordinary linear ODE in R^4; renormalising only removes an O(h^5) radial error).

    The cheaper-looking attitude update ``q+ = q (x) exp(h sum_i b_i w_i / 2)`` (the RK4
    weights applied to the stage velocities, then one exponential; MuJoCo <= 3.17 and MJX)
    is only **order 2** for a tumbling body: the exact increment is the time-ordered
    exponential of w(t), whose logarithm (Magnus series) is
    ``int w dt - (h^3/12) w x dw/dt + O(h^4)`` (sign depending on the convention); the
    commutator term is dropped, which is an O(h^3) local error whenever w changes direction.
    RKMK4 (Munthe-Kaas) restores order 4 with the dexp^-1 correction; RK4 on the components
    is the simplest 4th-order fix.

    Invariants: none exactly; energy, ``|L|`` and spatial L drift like O(h^4 t).
    Torque: held constant in the body frame over the step; still order 4.
    """
    return _run("rk4", q_world_body, omega_body, moments, h, torque_body)


def step_splitting(q_world_body, omega_body, moments, h, torque_body=None):
    """Lie-Poisson Strang splitting of the free body (McLachlan 1993; Reich 1994; Touma & Wisdom 1994).

    Split ``H = sum_j m_j^2 / (2 I_j)`` into the three planar rotors ``H_j``; each flows
    exactly as a rotation about body axis j at rate ``m_j / I_j``, applied to both ``m = I w``
    and ``q``.  Composition ``R1(h/2) R2(h/2) R3(h) R2(h/2) R1(h/2)`` (axes in the order given
    by ``moments``): five planar rotations, explicit, symmetric.

    Order 2.  Invariants: ``|L|`` and the spatial momentum ``L_W = R I w`` exact (every
    sub-step is an orthogonal map of m paired with the inverse map of the attitude);
    Poisson / symplectic; the energy error is bounded (no drift; backward error analysis)
    and O(h^2).  With torque: kick-drift-kick, ``m += h/2 tau`` before and after the free
    step (Strang splitting again, still order 2, reversible).
    """
    return _run("splitting", q_world_body, omega_body, moments, h, torque_body)


def step_dmv(q_world_body, omega_body, moments, h, torque_body=None):
    """Discrete Moser-Veselov algorithm in quaternion form (= LGVI / RATTLE on SO(3)).

    Solve for the body increment ``F = Rot((1, c) / sqrt(1 + |c|^2))``::

        c_j = (1 + |c|^2) h m_j / (2 I_j) + (I_k - I_l) / I_j * c_k c_l      (j, k, l cyclic)

    (Newton, 3 unknowns), then ``q+ = q (x) (1, c)/|.|`` and ``m+ = F^T m``.  Moser & Veselov
    (1991); quaternion form as in Hairer & Vilmart (2006); the Lee-Leok-McClamroch LGVI
    gives the same map for the free body.

    Order 2.  Invariants: energy, ``|L|`` and spatial L exact; symplectic.  It is the exact
    flow of a time-reparametrised rigid body, so its **phase** error is large (global error
    ~15x the splitting's on the test body).  With torque: kick-DMV-kick (order 2).

    Step-size limit: the equation for c has no real solution once ``h |w_j|`` exceeds about
    1 (test body: h = 0.7 works, h = 0.8 raises :class:`~inertia.errors.InputError`).
    """
    return _run("dmv", q_world_body, omega_body, moments, h, torque_body)


def step_dmv4(q_world_body, omega_body, moments, h, torque_body=None):
    """Preprocessed DMV of order 4 (Hairer & Vilmart, J. Phys. A 39:13225, 2006).

    The DMV step of :func:`step_dmv` applied with modified moments
    ``1/I~_j = css / I_j + cdd``, where ``css = 1 + h^2 (S1 G^2/2 + S2 T)``,
    ``cdd = h^2 (D1 G^2/2 + D2 T)``, ``S1 = sum I / (6 prod I)``, ``S2 = -sum(1/I)/3``,
    ``D1 = -1/(3 prod I)``, ``D2 = S1``, with T and G of the current step (both conserved).

    Order 4 (free body).  Invariants: energy, ``|L|``, spatial L exact.  With torque:
    kick-DMV4-kick, which is only **order 2** (the modified inertia corrects the free flow,
    not the splitting error).
    """
    return _run("dmv4", q_world_body, omega_body, moments, h, torque_body)


def step_midpoint(q_world_body, omega_body, moments, h, torque_body=None):
    """Implicit midpoint rule on the body momentum (Austin, Krishnaprasad & Wang 1993).

    ``m+ = m + h (y x I^-1 y + tau)`` with ``y = (m + m+)/2`` (Newton on 3 unknowns); the
    attitude turns with the midpoint velocity, ``q+ = q (x) exp(h I^-1 y / 2)``.

    Order 2.  Invariants: the quadratic ones of the momentum equation exactly: energy and
    ``|L|``.  Spatial L drifts (max 1.2e-3 relative on the test body at h = 0.1 over 1e4
    steps).  Symmetric (reversible).  Taking the midpoint rule on the quaternion as well
    (a Cayley update, which keeps ``|q|`` without projection) is also order 2 but its
    attitude error is 3.7x larger on the test body, so the exponential is used.
    With torque: inside the implicit equation (order 2).
    """
    return _run("midpoint", q_world_body, omega_body, moments, h, torque_body)


for _f in (step_euler_explicit, step_euler_implicit, step_rk4, step_splitting, step_dmv, step_dmv4,
           step_midpoint):
    _f.__doc__ = _f.__doc__.rstrip() + "\n" + _PARAMS_DOC
del _f

#: Public method names (CLI-visible) -> step functions with the uniform signature.
METHODS: dict[str, Callable] = {
    "euler_explicit": step_euler_explicit,
    "euler_implicit": step_euler_implicit,
    "rk4": step_rk4,
    "splitting": step_splitting,
    "dmv": step_dmv,
    "dmv4": step_dmv4,
    "midpoint": step_midpoint,
}

#: Order of accuracy of each method for the free body (omega and attitude), as measured in
#: ``tests/dynamics/test_integrators.py``.
METHOD_ORDER: dict[str, int] = {
    "euler_explicit": 1,
    "euler_implicit": 1,
    "rk4": 4,
    "splitting": 2,
    "dmv": 2,
    "dmv4": 4,
    "midpoint": 2,
}


# ============================================================================ trajectories
@dataclass(frozen=True)
class Trajectory:
    """Recorded states of :func:`integrate`.

    Attributes
    ----------
    t : (N,) float, s
        Times of the records, from 0 (the initial state).
    q_world_body : (N, ..., 4) float
        Unit quaternions, body -> world.
    omega_body : (N, ..., 3) float, rad/s
        Angular velocity in the body frame.
    """

    t: np.ndarray
    q_world_body: np.ndarray
    omega_body: np.ndarray

    def __len__(self) -> int:
        return len(self.t)


def integrate(q0, omega0_body, moments, h, n_steps, *, method: str = DEFAULT_METHOD, torque_body=None,
              record_every: int = 1, validate: bool = True,
              progress: Callable[[int], None] | None = None) -> Trajectory:
    """Integrate the rotational motion over ``n_steps`` fixed steps of size ``h``.

    Parameters
    ----------
    q0 : (..., 4) float
        Initial unit quaternion, body -> world.
    omega0_body : (..., 3) float, rad/s
        Initial angular velocity in the principal body frame.
    moments : (..., 3) float, kg m^2
        Principal moments about the center of mass (any order is not allowed here: the body
        frame is the principal frame, so they are taken as given).
    h : float, s
        Step size (non-zero; negative integrates backwards).
    n_steps : int >= 0
    method : str
        A key of :data:`METHODS`; default :data:`DEFAULT_METHOD`.
    torque_body : (..., 3) float, N m, or None
        Constant torque in the body frame (see each step function for how it enters).
    record_every : int >= 1
        Record the state every this many steps.  The initial state and the final state are
        always recorded.
    validate : bool, keyword-only
        Refuse moments that are not those of a physical body (a moment not positive, or the
        triangle inequality violated) with :class:`~inertia.errors.InvalidInertiaError`, the
        rule of :func:`inertia.massprops.validity.as_principal_moments` that ``exact_solution``
        and ``RigidBody`` apply too.  ``validate=False`` accepts any positive moments (textbook
        test bodies such as ``(2/3, 1, 2)``).
    progress : callable or None, keyword-only
        Called with the number of steps (per body) done since its previous call, a few
        times per second of work (``inertia simulate`` draws its progress bar with it).

    Returns
    -------
    Trajectory
        ``t`` (N,), ``q_world_body`` (N, ..., 4), ``omega_body`` (N, ..., 3) where the batch
        shape is the broadcast of the inputs' batch shapes.

    Raises
    ------
    InputError
        Bad arguments (shape, value, unknown method).
    InvalidInertiaError
        Moments of no physical body (see ``validate``).
    IntegrationError
        A step failed: the state became non-finite (e.g. ``euler_explicit`` blows up on the
        test body at h = 0.1 after about 1150 steps), or an implicit method's Newton iteration
        did not converge because ``h`` is too large.

    Examples
    --------
    >>> traj = integrate([1, 0, 0, 0], [1.0, 0.1, 0.2], [1, 2, 2.5], 0.1, 100, record_every=10)
    >>> traj.t.shape, traj.q_world_body.shape, traj.omega_body.shape
    ((11,), (11, 4), (11, 3))
    >>> integrate([1, 0, 0, 0], np.ones((5, 3)), [1, 2, 2.5], 0.1, 20, method="rk4").omega_body.shape
    (21, 5, 3)
    """
    check_method(method)
    n = as_count(n_steps, "n_steps", 0)
    every = as_count(record_every, "record_every", 1)
    recorded = np.r_[np.arange(0, n + 1, every), [n] if n % every else []].astype(np.int64)
    hf = as_time_step(h)
    qs, ws = _run_segments(q0, omega0_body, moments, np.diff(recorded), np.full(len(recorded) - 1, hf), method,
                           torque_body, validate, progress)
    return Trajectory(t=recorded * hf, q_world_body=qs, omega_body=ws)


def integrate_segments(q0, omega0_body, moments, steps, h, *, method: str = DEFAULT_METHOD, torque_body=None,
                       validate: bool = True, progress: Callable[[int], None] | None = None) -> Trajectory:
    """:func:`integrate` over consecutive segments with their own step counts and sizes.

    Segment k takes ``steps[k]`` steps of size ``h[k]``; the state is recorded at the start
    and at the end of every segment.  This is how samples at arbitrary times are taken
    with steps of at most a given size (``inertia simulate --times``).

    Parameters
    ----------
    steps : (S,) int >= 0
        Steps per segment.
    h : float or (S,) float, s
        Step size of each segment (finite, non-zero; a scalar applies to all).

    The other parameters are those of :func:`integrate`.

    Returns
    -------
    Trajectory
        S + 1 records: ``t[0] = 0`` and ``t[k + 1] = t[k] + steps[k] h[k]``.

    Examples
    --------
    >>> traj = integrate_segments([1, 0, 0, 0], [1.0, 0.1, 0.2], [1, 2, 2.5], [10, 4], [0.1, 0.05])
    >>> traj.t
    array([0. , 1. , 1.2])
    """
    check_method(method)
    counts = np.asarray(steps)
    if counts.ndim != 1 or not np.issubdtype(counts.dtype, np.integer) or (counts < 0).any():
        raise InputError(f"steps must be a 1-D sequence of integers >= 0, got {steps!r}")
    hs = np.asarray(h, dtype=float) if np.ndim(h) else np.full(counts.shape, as_time_step(h))
    if hs.shape != counts.shape or not np.isfinite(hs).all() or (hs == 0).any():
        raise InputError(f"h must be a finite non-zero step in s, or one per segment ({len(counts)}), got {h!r}")
    qs, ws = _run_segments(q0, omega0_body, moments, counts, hs, method, torque_body, validate, progress)
    return Trajectory(t=np.concatenate([[0.0], np.cumsum(counts * hs)]), q_world_body=qs, omega_body=ws)


def _run_segments(q0, omega0_body, moments, counts, hs, method, torque_body, validate, progress):
    q, w, I, _, tau = _prepare(q0, omega0_body, moments, 1.0, torque_body, validate=validate)
    return run_segments(method, q, w, I, tau, counts, hs, progress=progress)


def check_method(method) -> str:
    """``method`` if it names an integrator of :data:`METHODS`, else InputError."""
    if not isinstance(method, str) or method not in METHOD_NAMES:
        raise InputError(f"method must be one of {sorted(METHOD_NAMES)}, got {method!r}")
    return method
