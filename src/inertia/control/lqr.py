"""Discrete LQR, and its design for holding a spin with reaction wheels.

:func:`design_spin_hold` linearises the gyrostat's control-period map
(:func:`inertia.dynamics.gyrostat.gyrostat_jacobians`, complex step) about the steady spin
``omega = Omega s`` with the wheels at ``h_ref``, and keeps the rows and columns of the body rate and
the wheel momenta: the attitude drops out (the dynamics are the same in every attitude), so the
controller needs a rate gyro and the wheel tachometers, no attitude sensor.  Two directions of that
reduced state are then set aside:

* the total angular momentum ``|I omega + h|``: the wheels cannot change it (its functional ``c``
  satisfies ``c A = c`` and ``c B = 0``); the design works in ``ker c`` and reads a momentum error as
  a spin-rate error (the projection along ``(s, 0)``), so a body whose true momentum differs from the
  model's settles at the spin rate its momentum allows, with the wheels back at ``h_ref``;
* the spin phase about ``s``, which nothing needs.

What remains is stabilisable; the weights follow Bryson's rule (Bryson & Ho, *Applied Optimal
Control*, 1975, section 5.4): the tilt of ``s`` from the angular momentum against ``max_tilt``, the
rate error against ``Omega max_tilt``, each wheel's momentum and torque against its limits.  The
Riccati equation is scipy's :func:`scipy.linalg.solve_discrete_are` for one design; a batch of
designs (one per model of a Monte Carlo study) goes through the structure-preserving doubling
algorithm in NumPy (Chu, Fan, Lin & Wang, Int. J. Control 77(8):767-788, 2004), each solution
checked by its residual and by the stability of its closed loop.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .._core.errors import InputError
from .._core.validation import as_count, as_float_array
from ..dynamics.gyrostat import Gyrostat, WheelFeedback, gyrostat_jacobians
from ..dynamics.integrators import DEFAULT_METHOD

__all__ = ["dlqr", "SpinHold", "design_spin_hold", "DARE_RTOL", "DOUBLING_MAX_ITER"]

#: A Riccati solution is accepted when its residual is below DARE_RTOL times the size of its terms.
DARE_RTOL = 1e-9
#: Iterations of the doubling algorithm (it converges quadratically: ~10 for a well-damped design).
DOUBLING_MAX_ITER = 64


def _t(a):
    return np.swapaxes(a, -1, -2)


def _dare_residual(A, B, Q, R, P):
    """Relative residual of ``A'PA - P - A'PB (R + B'PB)^-1 B'PA + Q`` (..,)."""
    BtPA = _t(B) @ P @ A
    res = _t(A) @ P @ A - P - _t(BtPA) @ np.linalg.solve(R + _t(B) @ P @ B, BtPA) + Q
    scale = np.abs(Q).max(axis=(-2, -1)) + np.abs(P).max(axis=(-2, -1))
    return np.abs(res).max(axis=(-2, -1)) / scale


def _dare_doubling(A, B, Q, R):
    """Stabilising DARE solutions of a batch by structure-preserving doubling:
    ``A+ = A (I + G H)^-1 A``, ``G+ = G + A (I + G H)^-1 G A'``, ``H+ = H + A' H (I + G H)^-1 A``
    from ``G = B R^-1 B'``, ``H = Q``; H converges to P.  Each system stops on its own (so its
    result does not depend on the others in the batch)."""
    eye = np.eye(A.shape[-1])
    Ak, Gk, Hk = A.copy(), B @ np.linalg.solve(R, _t(B)), np.array(Q)
    todo = np.ones(A.shape[:-2], dtype=bool)
    with np.errstate(over="ignore", invalid="ignore"):   # a system with no solution diverges: checked after
        for _ in range(DOUBLING_MAX_ITER):
            a, g, h = Ak[todo], Gk[todo], Hk[todo]
            W = eye + g @ h
            WA, WG = np.linalg.solve(W, a), np.linalg.solve(W, g)
            h_next = h + _t(a) @ h @ WA
            Gk[todo], Ak[todo] = g + a @ WG @ _t(a), a @ WA
            done = ~(np.abs(h_next - h).max(axis=(-2, -1)) > 1e-14 * np.abs(h_next).max(axis=(-2, -1)))
            Hk[todo] = 0.5 * (h_next + _t(h_next))
            todo[todo] = ~done
            if not todo.any():
                break
    return Hk


def dlqr(A, B, Q, R) -> tuple[np.ndarray, np.ndarray]:
    """Discrete-time LQR: the gain K of ``u = -K x`` minimising ``sum x'Qx + u'Ru`` for ``x+ = A x + B u``.

    Parameters
    ----------
    A : (..., n, n), B : (..., n, m), Q : (..., n, n) symmetric >= 0, R : (..., m, m) symmetric > 0.

    Returns
    -------
    K : (..., m, n) = ``(R + B'PB)^-1 B'PA``; P : (..., n, n), the stabilising solution of the DARE.

    Raises InputError when (A, B) is not stabilisable or (Q, A) not detectable (no stabilising P).

    >>> A, B = np.array([[1.0, 0.1], [0.0, 1.0]]), np.array([[0.005], [0.1]])   # a double integrator
    >>> K, P = dlqr(A, B, np.eye(2), [[1.0]])
    >>> K.shape, bool(np.abs(np.linalg.eigvals(A - B @ K)).max() < 1)
    ((1, 2), True)
    """
    from scipy.linalg import solve_discrete_are

    A, B, Q, R = (np.asarray(a, dtype=np.float64) for a in (A, B, Q, R))
    batch = np.broadcast_shapes(A.shape[:-2], B.shape[:-2], Q.shape[:-2], R.shape[:-2])
    A, B = np.broadcast_to(A, batch + A.shape[-2:]), np.broadcast_to(B, batch + B.shape[-2:])
    Q, R = np.broadcast_to(Q, batch + Q.shape[-2:]), np.broadcast_to(R, batch + R.shape[-2:])
    def scipy_dare(k=()):
        try:
            return solve_discrete_are(A[k], B[k], Q[k], R[k])
        except (ValueError, np.linalg.LinAlgError) as e:
            raise InputError(f"no stabilising LQR solution{' for system ' + str(k) if k else ''}: {e}") from None

    if batch:
        P = _dare_doubling(A, B, Q, R)
        with np.errstate(over="ignore", invalid="ignore"):
            redo = ~(_dare_residual(A, B, Q, R, P) <= DARE_RTOL)
        for k in zip(*np.nonzero(redo)):        # the few the doubling did not settle: scipy's QZ
            P[k] = scipy_dare(tuple(int(i) for i in k))
    else:
        P = scipy_dare()
    K = np.linalg.solve(R + _t(B) @ P @ B, _t(B) @ P @ A)
    radius = np.abs(np.linalg.eigvals(A - B @ K)).max(axis=-1)
    bad = ~(radius < 1.0) | ~(_dare_residual(A, B, Q, R, P) <= DARE_RTOL)
    if np.any(bad):
        k = tuple(int(i) for i in np.argwhere(np.atleast_1d(bad))[0]) if batch else ()
        raise InputError(f"no stabilising LQR solution{' for system ' + str(k) if batch else ''}: closed-loop "
                         f"spectral radius {np.atleast_1d(radius)[k if batch else 0]:.6g} (needs < 1); is (A, B) "
                         "stabilisable and (Q, A) detectable?")
    return K, P


@dataclass(frozen=True, eq=False)
class SpinHold:
    """A wheel controller holding the spin ``omega = Omega s`` (body frame), designed by LQR.

    gain : (..., n, 3 + n), N m per rad/s and per N m s, on ``[omega_body - omega_ref, h - h_ref]``;
    omega_ref : (3,) rad/s, body frame; h_ref : (..., n) N m s; period : float s (the torques are
    held over it); substeps : int, plant steps per period in the design; spin_axis : (3,) unit,
    body frame; closed_loop_radius / open_loop_radius : (...) spectral radius of the reduced
    control-period map with and without the controller (> 1: unstable).
    """

    gain: np.ndarray
    omega_ref: np.ndarray
    h_ref: np.ndarray
    period: float
    substeps: int
    method: str
    spin_axis: np.ndarray
    spin_rate: float
    closed_loop_radius: np.ndarray
    open_loop_radius: np.ndarray

    def feedback(self) -> WheelFeedback:
        """The law for :func:`inertia.dynamics.gyrostat.gyrostat_rollout` (evaluated in its compiled loop)."""
        return WheelFeedback(self.gain, self.omega_ref, self.h_ref)


def design_spin_hold(model: Gyrostat, spin_axis, spin_rate: float, period: float, *, h_bias: float = 0.0,
                     max_tilt: float = np.radians(1.0), substeps: int = 1, method: str = DEFAULT_METHOD) -> SpinHold:
    """Design the LQR that holds a spin of ``model`` about the body axis ``spin_axis`` with its wheels.

    Parameters
    ----------
    model : Gyrostat
        The controller's model of the body and wheels (a batch of models gives a batch of designs).
        ``spin_axis`` should be a principal axis of the true body (a steady spin); the model's may
        be off: its errors change the gains, not the set point.
    spin_axis : (3,) float, body frame (normalised).
    spin_rate : float, rad/s, non-zero.
    period : float, s, the control period (torques held over it).
    h_bias : float, N m s, the wheels' set-point momentum along ``spin_axis`` (0: none).
    max_tilt : float, rad, the tilt of the spin axis from the angular momentum the weights aim at.
    substeps, method : the plant steps of the design's model (as for the rollout that will run it).

    Returns
    -------
    SpinHold

    Examples
    --------
    >>> from inertia.dynamics import RigidBody
    >>> g = Gyrostat(RigidBody.from_principal_moments(750.0, [600.0, 800.0, 900.0]), np.eye(3),
    ...              max_torque=[0.2] * 3, max_momentum=[50.0] * 3)
    >>> c = design_spin_hold(g, [0, 1, 0], 0.1, 0.1)
    >>> c.gain.shape, bool(c.open_loop_radius > 1 > c.closed_loop_radius)
    ((3, 6), True)
    """
    if not isinstance(model, Gyrostat):
        raise InputError(f"model must be a Gyrostat, got {type(model).__name__}")
    n = model.n_wheels
    if n == 0:
        raise InputError("a spin hold needs at least one wheel")
    s = as_float_array(spin_axis, "spin_axis", (3,), allow_batch=False)
    if not np.linalg.norm(s) > 0:
        raise InputError("spin_axis must be a non-zero vector")
    s = s / np.linalg.norm(s)
    W = float(spin_rate)
    if not (np.isfinite(W) and W != 0):
        raise InputError(f"spin_rate must be finite and non-zero, got {spin_rate!r}")
    T = float(period)
    if not (np.isfinite(T) and T > 0):
        raise InputError(f"period must be positive, got {period!r}")
    sub = as_count(substeps, "substeps", 1)
    theta = float(max_tilt)
    if not (np.isfinite(theta) and theta > 0):
        raise InputError(f"max_tilt must be a positive angle in rad, got {max_tilt!r}")
    batch = model.batch_shape
    Gt = np.broadcast_to(_t(model.wheel_axes), batch + (3, n))          # the wheel axes as columns
    I = np.broadcast_to(model.body.inertia_com, batch + (3, 3))
    # set point: the wheels' momentum h_bias along s (least squares over the wheels)
    h_ref = np.einsum("...ij,j->...i", np.linalg.pinv(Gt), h_bias * s)
    if np.abs(np.einsum("...ij,...j->...i", Gt, h_ref) - h_bias * s).max() > 1e-9 * max(abs(h_bias), 1e-300):
        raise InputError(f"the wheels cannot hold a momentum of {h_bias:g} N m s along the spin axis {s.tolist()}")
    x_nom = np.concatenate([np.zeros(h_ref.shape[:-1] + (6,)), np.broadcast_to([1.0, 0, 0, 0], h_ref.shape[:-1] + (4,)),
                            np.broadcast_to(W * s, h_ref.shape[:-1] + (3,)), h_ref], axis=-1)
    A, B = gyrostat_jacobians(x_nom, None, T / sub, gyrostat=model, method=method, substeps=sub)
    Ar, Br = A[..., 9:, 9:], B[..., 9:, 6:]                  # rate and wheel rows: the attitude drops out
    # the momentum functional c (c A = c, c B = 0) and the basis V of ker c
    L = np.einsum("...ij,...j->...i", I, W * s) + np.einsum("...ij,...j->...i", Gt, h_ref)
    L_norm = np.linalg.norm(L, axis=-1)
    if np.any(~(L_norm > 0)):
        raise InputError("the set point has no angular momentum: nothing for the wheels to hold")
    L_hat = L / L_norm[..., None]
    c = np.concatenate([np.einsum("...ij,...j->...i", I, L_hat), np.einsum("...ji,...j->...i", Gt, L_hat)], axis=-1)
    # Bryson's scales (Bryson & Ho, section 5.4): the rate error against Omega max_tilt, each wheel's
    # momentum and torque against its limit; the design runs in these units (well conditioned)
    h_scale = np.where(np.isfinite(model.max_momentum), model.max_momentum, L_norm[..., None])
    u_scale = np.where(np.isfinite(model.max_torque), model.max_torque, L_norm[..., None] / T)
    d = np.concatenate([np.broadcast_to(np.full(3, abs(W) * theta), batch + (3,)),
                        np.broadcast_to(h_scale, batch + (n,))], axis=-1)          # z = d * z~
    Ar, Br, c = Ar * d[..., None, :] / d[..., :, None], Br * u_scale[..., None, :] / d[..., :, None], c * d
    r = np.concatenate([s, np.zeros(n)]) / d
    Pi = np.eye(3 + n) - r[..., :, None] * c[..., None, :] / np.einsum("...i,...i->...", c, r)[..., None, None]
    V = np.linalg.qr(np.broadcast_to(c[..., :, None], batch + (3 + n, 1)), mode="complete")[0][..., :, 1:]
    Ay, By = _t(V) @ Ar @ V, _t(V) @ Br
    # weights: the tilt (the transverse angular momentum over |L|) against max_tilt, and the scaled state
    P_perp = np.eye(3) - np.outer(s, s)
    C_tilt = P_perp @ np.concatenate([I, Gt], axis=-1) * d[..., None, :] / (L_norm[..., None, None] * theta)
    Qz = _t(C_tilt) @ C_tilt + np.eye(3 + n)
    Ky, _ = dlqr(Ay, By, _t(V) @ Qz @ V, np.broadcast_to(np.eye(n), batch + (n, n)))
    gain = u_scale[..., :, None] * (Ky @ _t(V) @ Pi) / d[..., None, :]
    radius = lambda M: np.abs(np.linalg.eigvals(M)).max(axis=-1)  # noqa: E731
    return SpinHold(gain, W * s, h_ref, T, sub, method, s, W, radius(Ay - By @ Ky), radius(Ay))
