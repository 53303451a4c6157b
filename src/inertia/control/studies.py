"""Holding a spin about the intermediate axis: the passive wheel, the active LQR, a Monte Carlo.

Two bodies, each a :class:`SpinSetup`: the demo's steel T-handle spinning at 10 rad/s about its
intermediate axis (the stem), and the 900/800/600 kg m^2 spacecraft of Basilisk's
``scenarioAttitudeFeedbackRW`` (750 kg, three Honeywell HR16 wheels along the body axes, 50 N m s
and 0.2 N m each) spinning at 0.1 rad/s about its 800 kg m^2 axis.

* :func:`passive_sweep`: one wheel along the spin axis holding a constant momentum ``h``; swept
  across the dual-spin threshold ``h_min`` (:mod:`.dual_spin`), the spin departs below it and holds
  above it.  The simulated threshold is where the largest tilt over the run crosses
  ``DEPARTURE_FACTOR`` times the initial one (found by refining grids of batched runs).
* :func:`active_run`: three wheels under the LQR of :func:`.lqr.design_spin_hold`, from an
  ``initial_tilt`` of the spin axis from the angular momentum, beside the same body with its wheels
  idle (the free flip).
* :func:`monte_carlo`: the same hold, each run's controller designed on a model wrong by up to
  ``moment_error`` in each principal moment and ``axis_error`` in the principal axes; a run succeeds
  when the tilt stays within ``max_tilt`` from ``settle`` to the end.

The tilt is the angle between the body's spin axis and the total angular momentum ``I omega + h``:
with no external torque that momentum is fixed in space, so a small tilt is a spin axis held still.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_count
from ..dynamics.body import RigidBody
from ..dynamics.gyrostat import Gyrostat, WheelFeedback, gyrostat_rollout, rollout_threads
from .dual_spin import dual_spin_exponent, dual_spin_threshold
from .lqr import SpinHold, design_spin_hold

__all__ = ["SpinSetup", "t_handle_setup", "basilisk_setup", "initial_state", "PassiveSweep", "passive_sweep",
           "ActiveRun", "active_run", "MonteCarlo", "monte_carlo", "perturbed_models", "DEPARTURE_FACTOR", "Showcase",
           "showcase"]

#: The passive spin "departs" when its largest tilt exceeds this many times its initial tilt.  Near
#: the threshold the departure grows like sqrt(1 - h/h_min) and the held wobble like
#: 1/sqrt(h/h_min - 1): with a wobble of 1e-3 the factor 100 separates them within 1 % of h_min.
DEPARTURE_FACTOR = 100.0
#: The plant step of the passive sweep turns the body at most this angle [rad].
PASSIVE_ANGLE_PER_STEP = 0.01


@dataclass(frozen=True)
class SpinSetup:
    """A body, its wheels and the task: hold ``spin_rate`` about ``spin_axis`` (body frame, a
    principal axis) within ``max_tilt`` from ``settle`` to ``duration`` s, starting ``initial_tilt``
    off, the torques computed every ``period`` s and held over ``substeps`` plant steps."""

    name: str
    gyrostat: Gyrostat
    spin_axis: np.ndarray
    spin_rate: float
    period: float
    substeps: int
    duration: float
    settle: float
    initial_tilt: float = np.radians(5.0)
    max_tilt: float = np.radians(1.0)

    @property
    def n_steps(self) -> int:
        """Control periods in a run."""
        return int(round(self.duration / self.period))

    @property
    def principal_index(self) -> int:
        """The index (0, 1, 2; moments ascending) of the principal axis the spin axis lies on."""
        cos = np.abs(self.gyrostat.body.R_body_principal.T @ self.spin_axis)
        k = int(np.argmax(cos))
        if cos[k] < 1 - 1e-9:
            raise InputError(f"the spin axis {self.spin_axis.tolist()} is not a principal axis of {self.name} "
                             f"(closest: axis {k + 1}, cos {cos[k]:.9f})")
        return k


def t_handle_setup() -> SpinSetup:
    """The demo's steel T-handle at 10 rad/s about its stem (the intermediate axis; free, a flip
    every 3.1 s), three wheels along its principal axes, 2 mN m and 0.2 mN m s each; 60 s at 100 Hz."""
    from ..massprops.bodies import t_handle

    body = RigidBody.from_mass_properties(t_handle().props)
    axes = body.R_body_principal.T                       # rows: the principal axes, body frame
    g = Gyrostat(body, axes, max_torque=[2e-3] * 3, max_momentum=[2e-4] * 3)
    return SpinSetup("steel T-handle", g, axes[1].copy(), 10.0, 0.01, 2, 60.0, 2.0)


def basilisk_setup() -> SpinSetup:
    """Basilisk's ``scenarioAttitudeFeedbackRW`` body (750 kg, diag(900, 800, 600) kg m^2) with three
    HR16 wheels along x, y, z (50 N m s, 0.2 N m), at 0.1 rad/s about y (the 800 axis); 600 s at 10 Hz."""
    body = RigidBody(750.0, np.diag([900.0, 800.0, 600.0]))
    g = Gyrostat(body, np.eye(3), max_torque=[0.2] * 3, max_momentum=[50.0] * 3)
    return SpinSetup("Basilisk 900/800/600 spacecraft", g, np.array([0.0, 1.0, 0.0]), 0.1, 0.1, 1, 600.0, 100.0)


def initial_state(setup: SpinSetup, direction=0.0, *, tilt=None, body=None) -> np.ndarray:
    """States (..., 13 + n): the body's total angular momentum tilted by ``tilt`` (default
    ``setup.initial_tilt``) from the spin axis toward ``direction`` (rad, about the axis, from its
    first transverse principal axis), its magnitude that of the steady spin; wheels at rest (h = 0),
    attitude identity (body axes = world axes at t = 0)."""
    b = setup.gyrostat.body if body is None else body
    s = setup.spin_axis
    k = setup.principal_index
    e1, e2 = setup.gyrostat.body.R_body_principal[:, (k + 1) % 3], setup.gyrostat.body.R_body_principal[:, (k + 2) % 3]
    tilt = setup.initial_tilt if tilt is None else tilt
    phi = np.asarray(direction, dtype=float)[..., None]
    I = b.inertia_com
    L = np.linalg.norm(np.einsum("...ij,j->...i", I, setup.spin_rate * s), axis=-1)[..., None]
    L0 = L * (np.sin(tilt) * (np.cos(phi) * e1 + np.sin(phi) * e2) + np.cos(tilt) * s)
    w0 = np.linalg.solve(I, L0[..., None])[..., 0]
    x = np.zeros(w0.shape[:-1] + (13 + setup.gyrostat.n_wheels,))
    x[..., 6] = 1.0
    x[..., 10:13] = w0
    return x


# ---------------------------------------------------------------------------- passive
@dataclass(frozen=True)
class PassiveSweep:
    """The passive study: ``ratios`` (k,) of h to the formula's ``h_min`` (N m s), the largest tilt
    (k,) rad over ``duration`` s, ``departs`` (k,) bool, and ``h_threshold``, the simulated threshold
    (N m s); ``initial_tilt`` rad; ``wobble`` the relative rate about the minor axis at t = 0."""

    ratios: np.ndarray
    max_tilt: np.ndarray
    departs: np.ndarray
    h_min: float
    h_threshold: float
    initial_tilt: float
    wobble: float
    duration: float

    @property
    def threshold_error(self) -> float:
        """(simulated - formula) / formula."""
        return self.h_threshold / self.h_min - 1.0


def _passive_tilts(setup: SpinSetup, ratios, wobble, h_min, duration):
    """Largest tilt over the run of one wheel along the spin axis at ``ratios * h_min``, and the initial tilt."""
    g = Gyrostat(setup.gyrostat.body, setup.spin_axis[None])
    k = setup.principal_index
    e_other = setup.gyrostat.body.R_body_principal[:, 0 if k else 1]    # the wobble: about the minor axis
    W = setup.spin_rate
    ratios = np.asarray(ratios, dtype=float)
    x0 = np.zeros(ratios.shape + (14,))
    x0[..., 6] = 1.0
    x0[..., 10:13] = W * setup.spin_axis + wobble * abs(W) * e_other
    x0[..., 13] = ratios * h_min
    h = min(setup.period / setup.substeps, PASSIVE_ANGLE_PER_STEP / abs(W))
    n = int(np.ceil(duration / h))
    run = gyrostat_rollout(x0, h, n, gyrostat=g, save_every=1 if n == 0 else n, monitor_axis=setup.spin_axis)
    return run.tilt.max(axis=0), run.tilt[0]


def passive_sweep(setup: SpinSetup, ratios=(0.0, 0.5, 0.9, 0.95, 0.98, 1.02, 1.05, 1.1, 1.5), *,
                  wobble: float = 1e-3, duration=None, refine: int = 3) -> PassiveSweep:
    """Sweep a constant wheel momentum along the spin axis across the dual-spin threshold.

    ``ratios`` of ``h_min``; the threshold is then bracketed by a grid of 21 ratios in [0.5, 1.5]
    and refined ``refine`` times (each a grid of 11 over the bracket; a batched run each).  The
    runs last ``duration`` s, by default the setup's or, if longer, the time a spin 2 % below the
    threshold takes to grow ``10 DEPARTURE_FACTOR`` times at the formula's rate.
    """
    k = setup.principal_index
    h_min = dual_spin_threshold(setup.gyrostat.body.moments, k, setup.spin_rate).h_min
    if h_min == 0:
        raise InputError(f"the spin of {setup.name} about axis {k + 1} is stable without a wheel: no threshold")
    if duration is None:
        # long enough for a spin 2 % below the threshold to grow 10 DEPARTURE_FACTOR times
        lam2 = float(dual_spin_exponent(setup.gyrostat.body.moments, k, setup.spin_rate, 0.98 * h_min))
        T = max(setup.duration, np.log(10 * DEPARTURE_FACTOR) / np.sqrt(lam2))
    else:
        T = float(duration)
    ratios = np.asarray(ratios, dtype=float)
    tilt, tilt0 = _passive_tilts(setup, ratios, wobble, h_min, T)
    lo, hi = 0.5, 1.5
    grid = np.linspace(lo, hi, 21)
    for _ in range(refine + 1):
        t, t0 = _passive_tilts(setup, grid, wobble, h_min, T)
        gone = t > DEPARTURE_FACTOR * t0
        if gone.all() or not gone.any():
            raise InputError(f"no threshold between {grid[0]:.6g} and {grid[-1]:.6g} h_min in {T:g} s")
        j = int(np.flatnonzero(gone)[-1])                # the last ratio that departs
        lo, hi = grid[j], grid[min(j + 1, grid.size - 1)]
        grid = np.linspace(lo, hi, 11)
    return PassiveSweep(ratios, tilt, tilt > DEPARTURE_FACTOR * tilt0, h_min, 0.5 * (lo + hi) * h_min,
                        float(tilt0[0]), wobble, T)


# ---------------------------------------------------------------------------- active
@dataclass(frozen=True)
class ActiveRun:
    """The held spin beside the free one, from the same initial state.

    t (S,) s; held / free: states (S, 13 + n); tilt_held / tilt_free (S,) rad (the largest over each
    period); torque (S - 1, n) N m, the wheel torques applied over each period; controller: SpinHold.
    """

    setup: SpinSetup
    controller: SpinHold
    t: np.ndarray
    held: np.ndarray
    free: np.ndarray
    tilt_held: np.ndarray
    tilt_free: np.ndarray
    torque: np.ndarray

    @property
    def max_tilt_after_settle(self) -> float:
        """The largest tilt from ``settle`` to the end [rad]."""
        return float(self.tilt_held[self.t > self.setup.settle].max())

    @property
    def capture_time(self) -> float:
        """The time after which the tilt stays within ``max_tilt`` [s] (inf if it never does)."""
        out = np.flatnonzero(self.tilt_held > self.setup.max_tilt)
        if out.size == 0:
            return 0.0
        return float(self.t[out[-1] + 1]) if out[-1] + 1 < self.t.size else float("inf")


def active_run(setup: SpinSetup, *, direction: float = 0.0) -> ActiveRun:
    """The LQR (designed on the true body) holding the spin, and the free body, saved every period."""
    c = design_spin_hold(setup.gyrostat, setup.spin_axis, setup.spin_rate, setup.period, substeps=setup.substeps,
                         max_tilt=setup.max_tilt)
    x0 = initial_state(setup, direction)
    h = setup.period / setup.substeps
    kw = dict(gyrostat=setup.gyrostat, substeps=setup.substeps, save_every=1, monitor_axis=setup.spin_axis)
    held = gyrostat_rollout(x0, h, setup.n_steps, feedback=c.feedback(), **kw)
    free = gyrostat_rollout(x0, h, setup.n_steps, **kw)
    torque = np.diff(held.states[:, 13:], axis=0) / setup.period
    return ActiveRun(setup, c, held.t, held.states, free.states, held.tilt, free.tilt, torque)


# ---------------------------------------------------------------------------- Monte Carlo
@dataclass(frozen=True)
class MonteCarlo:
    """The robust study: per run, the largest tilt after settling (N,) rad, ``success`` (N,) bool,
    the model's errors (``moment_scale`` (N, 3): model moment / true moment, ``axis_angle`` (N,) rad),
    the settled spin rate (N,) rad/s, and the wall times of the designs and of the rollout [s]."""

    setup: SpinSetup
    max_tilt: np.ndarray
    success: np.ndarray
    moment_scale: np.ndarray
    axis_angle: np.ndarray
    final_spin_rate: np.ndarray
    design_seconds: float
    rollout_seconds: float
    threads: int

    @property
    def success_rate(self) -> float:
        return float(self.success.mean())

    @property
    def steps(self) -> int:
        """Closed-loop control periods simulated (runs x periods)."""
        return int(self.max_tilt.size * self.setup.n_steps)


def perturbed_models(body: RigidBody, n: int, rng, *, moment_error: float, axis_error: float) -> tuple:
    """``(models, moment_scale (n, 3), axis_angle (n,))``: each model's principal moments scaled by
    ``1 + U(-moment_error, moment_error)`` and its principal axes turned by ``U(0, axis_error)`` rad
    about a uniformly random axis.  A model need not be physical (it is only the controller's
    belief), so none is rejected."""
    moments, R = body.moments, body.R_body_principal
    scale = 1.0 + rng.uniform(-moment_error, moment_error, (n, 3))
    axis = rng.normal(size=(n, 3))
    axis /= np.linalg.norm(axis, axis=1, keepdims=True)
    angle = rng.uniform(0.0, axis_error, n)
    # Rodrigues: R_err = I + sin a [k]x + (1 - cos a) [k]x^2
    K = np.zeros((n, 3, 3))
    K[:, 0, 1], K[:, 0, 2], K[:, 1, 2] = -axis[:, 2], axis[:, 1], -axis[:, 0]
    K -= np.swapaxes(K, 1, 2)
    R_err = np.eye(3) + np.sin(angle)[:, None, None] * K + (1 - np.cos(angle))[:, None, None] * (K @ K)
    R_model = R_err @ R
    I_model = R_model @ ((moments * scale)[:, :, None] * np.swapaxes(R_model, 1, 2))
    return RigidBody(np.broadcast_to(body.mass, (n,)), I_model, validate=False), scale, angle


def monte_carlo(setup: SpinSetup, n_runs: int = 1000, *, seed: int = 0, moment_error: float = 0.2,
                axis_error: float = np.radians(5.0), threads: int | None = None) -> MonteCarlo:
    """``n_runs`` closed-loop runs of the true body, each under an LQR designed on a wrong model,
    from the initial tilt in a random direction; the designs are one batch, the runs one compiled
    rollout over the batch (the controller inside the loop)."""
    n = as_count(n_runs, "n_runs", 1)
    rng = np.random.default_rng(seed)
    t0 = time.perf_counter()
    models, scale, angle = perturbed_models(setup.gyrostat.body, n, rng, moment_error=moment_error,
                                            axis_error=axis_error)
    c = design_spin_hold(setup.gyrostat.with_body(models), setup.spin_axis, setup.spin_rate, setup.period,
                         substeps=setup.substeps, max_tilt=setup.max_tilt)
    x0 = initial_state(setup, rng.uniform(0.0, 2 * np.pi, n))
    t1 = time.perf_counter()
    settle_steps = int(round(setup.settle / setup.period))
    every = max(1, settle_steps // 5)
    while setup.n_steps % every:
        every -= 1
    fb = WheelFeedback(c.gain, c.omega_ref, c.h_ref)
    run = gyrostat_rollout(x0, setup.period / setup.substeps, setup.n_steps, gyrostat=setup.gyrostat, feedback=fb,
                           substeps=setup.substeps, save_every=every, monitor_axis=setup.spin_axis, threads=threads)
    t2 = time.perf_counter()
    window = every * setup.period
    late = run.tilt[run.t - window >= setup.settle - 1e-9 * window].max(axis=0)   # windows wholly after settle
    final_rate = run.states[-1, :, 10:13] @ setup.spin_axis
    return MonteCarlo(setup, late, late <= setup.max_tilt, scale, angle, final_rate, t1 - t0, t2 - t1,
                      rollout_threads(threads, n * setup.n_steps * setup.substeps))


# ---------------------------------------------------------------------------- the showcase
#: The ratios h / h_min of the showcase's passive sweep (its table and plot).
SHOWCASE_RATIOS = (0.0, 0.25, 0.5, 0.75, 0.9, 0.95, 0.98, 0.99, 1.01, 1.02, 1.05, 1.1, 1.25, 1.5)


@dataclass(frozen=True)
class Showcase:
    """Everything ``inertia demo --control`` shows, per body (keys: the setups' names)."""

    setups: dict
    passive: dict
    active: dict
    monte_carlo: dict


def showcase(n_runs: int = 1000, *, seed: int = 0, threads: int | None = None) -> Showcase:
    """The passive sweep, the active hold and the Monte Carlo for the T-handle and Basilisk's body."""
    setups = {s.name: s for s in (t_handle_setup(), basilisk_setup())}
    return Showcase(setups, {k: passive_sweep(s, SHOWCASE_RATIOS) for k, s in setups.items()},
                    {k: active_run(s) for k, s in setups.items()},
                    {k: monte_carlo(s, n_runs, seed=seed, threads=threads) for k, s in setups.items()})
