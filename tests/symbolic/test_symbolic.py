"""Symbolic Lagrangian mechanics in Euler angles, against independent truth:
scipy's Euler-angle rotations, finite differences of R(q), the exact torque-free solution,
Euler's equations as implemented in inertia.dynamics, the particle route, conservation of energy, and Newton's law for the center of mass."""

from __future__ import annotations

import ctypes
import shutil
import subprocess
import warnings

import numpy as np
import pytest

sp = pytest.importorskip("sympy")

import inertia  # noqa: E402
from inertia._core.rotations import matrix_to_quat, quat_to_matrix  # noqa: E402
from inertia.dynamics import exact_solution  # noqa: E402
from inertia.dynamics.equations import angular_acceleration_body  # noqa: E402
from inertia.errors import InputError  # noqa: E402
from inertia.symbolic import (  # noqa: E402
    SEQUENCES,
    EulerAngleSystem,
    GimbalLockError,
    GimbalLockWarning,
    ParticleRoute,
    derive,
    det_kinematic,
    kinematic_matrix,
    rigid,  # noqa: E402
    rotation_matrix,
)

Rotation = pytest.importorskip("scipy.spatial.transform").Rotation
Q = sp.symbols("q1:4", real=True)
VARIANTS = [{}, {"gravity": True}, {"translation": True}, {"translation": True, "gravity": True}]


def _middle_angle(seq, rng, size=None):
    """Middle angles well away from gimbal lock for the sequence's type."""
    if seq[0] != seq[2]:
        return rng.uniform(-1.0, 1.0, size)
    return rng.uniform(0.6, np.pi - 0.6, size)


def _random_angles(seq, rng):
    return np.array([rng.uniform(-3, 3), _middle_angle(seq, rng), rng.uniform(-3, 3)])


def _random_body(rng, *, diagonal=False, com=True):
    """A physical body: random principal frame, moments obeying the triangle inequality."""
    moments = np.sort(rng.uniform(0.5, 2.0, 3))
    moments[2] = min(moments[2], moments[0] + moments[1] - 0.05)
    if diagonal:
        J = np.diag(rng.permutation(moments))
    else:
        R, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        J = R @ np.diag(moments) @ R.T
    c = rng.normal(size=3) * 0.3 if com else np.zeros(3)
    return inertia.MassProperties(rng.uniform(0.5, 3.0), c, J)


def _numeric_kwargs(system, props, rng):
    kw = {"inertia": props.inertia_com, "torque_body": rng.normal(size=3)}
    if system.has_com:
        kw.update(mass=props.mass, com=props.com, force_world=rng.normal(size=3))
    if system.gravity:
        kw["gravity"] = np.array([0.3, -0.2, -9.81])
    return kw


def _flat_args(system, props, kw):
    """Parameters and inputs in the generated functions' order."""
    J = props.inertia_com
    params = [J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2]]
    if system.has_com:
        params += [props.mass, *props.com]
    if system.gravity:
        params += list(kw["gravity"])
    inputs = list(kw["torque_body"]) + (list(kw["force_world"]) if system.has_com else [])
    return params, inputs


# ----------------------------------------------------------------------------- kinematics


@pytest.mark.parametrize("seq", SEQUENCES)
def test_rotation_matrix_is_scipys_intrinsic_sequence(seq):
    rng = np.random.default_rng(abs(hash(seq)) % 2**32)
    fn = sp.lambdify(Q, rotation_matrix(seq, Q), "numpy")
    for _ in range(5):
        q = rng.uniform(-3, 3, 3)
        np.testing.assert_allclose(np.array(fn(*q), float), Rotation.from_euler(seq, q).as_matrix(), atol=1e-14)


@pytest.mark.parametrize("seq", SEQUENCES)
def test_kinematic_matrix_matches_finite_differences_of_R(seq):
    """omega_body = E q' must equal vee(R^T dR/dt), with dR/dt by central differences of scipy's R."""
    rng = np.random.default_rng(7)
    E_fn = sp.lambdify(Q, kinematic_matrix(seq, Q), "numpy")
    for _ in range(5):
        q, qd = _random_angles(seq, rng), rng.normal(size=3)
        h = 1e-6
        R = Rotation.from_euler(seq, q).as_matrix()
        dR = (Rotation.from_euler(seq, q + h * qd).as_matrix() - Rotation.from_euler(seq, q - h * qd).as_matrix()) / (2 * h)
        W = R.T @ dR
        omega_fd = np.array([W[2, 1], W[0, 2], W[1, 0]])
        np.testing.assert_allclose(np.array(E_fn(*q), float) @ qd, omega_fd, atol=1e-8)


@pytest.mark.parametrize("seq", SEQUENCES)
def test_closed_form_det_E_equals_the_expanded_determinant(seq):
    E = kinematic_matrix(seq, Q)
    diff = sp.expand(sp.expand_trig(E.det() - det_kinematic(seq, Q)))
    assert _reduce_trig(diff, Q) == 0
    # and the singular function is cos for Tait-Bryan, sin for proper Euler
    assert det_kinematic(seq, Q).has(sp.cos(Q[1]) if seq[0] != seq[2] else sp.sin(Q[1]))


def _reduce_trig(expr, angles):
    """Reduce a polynomial in sin/cos of ``angles`` modulo sin^2 + cos^2 = 1 (exact, no simplify)."""
    s = sp.symbols(f"s0:{len(angles)}")
    c = sp.symbols(f"c0:{len(angles)}")
    sub = {}
    for a, si, ci in zip(angles, s, c):
        sub[sp.sin(a)] = si
        sub[sp.cos(a)] = ci
    poly = sp.expand(expr.xreplace(sub))
    if poly == 0:
        return 0
    free = sorted(poly.free_symbols - set(s) - set(c), key=str)
    gens = list(s) + list(c) + free
    _, rem = sp.reduced(poly, [si**2 + ci**2 - 1 for si, ci in zip(s, c)], *gens, order="lex")
    return sp.expand(rem)


def test_det_M_is_det_J_cos2_theta_symbolically_for_ZYX():
    system = EulerAngleSystem("ZYX")
    M = rigid.mass_matrix(system)
    theta = system.angles[1]
    diff = sp.expand(M.det(method="berkowitz") - system.J.det() * sp.cos(theta) ** 2)
    assert _reduce_trig(diff, system.angles) == 0
    # and the mass matrix really is E^T J E
    assert (M - system.E.T * system.J * system.E).applyfunc(sp.expand) == sp.zeros(3, 3)


# ----------------------------------------------------------------------------- the two routes


def test_six_point_lagrangian_equals_rigid_lagrangian_symbolically():
    """The six-point construction: M/6 at +-d_i on each axis gives L = 1/2 w^T J w."""
    system = EulerAngleSystem("ZYX", inertia="diagonal")
    route = ParticleRoute(system, 6)
    M, d = sp.symbols("M d_x d_y d_z", positive=True)[0], sp.symbols("d_x d_y d_z", positive=True)
    sub = {}
    for k, (axis, sign) in enumerate([(i, s) for i in range(3) for s in (1, -1)]):
        sub[route.masses[k]] = M / 6
        for j in range(3):
            sub[route.positions[k][j]] = sign * d[axis] if j == axis else 0
    L_a = route.lagrangian.xreplace(sub)
    Jxx, Jyy, Jzz = system.inertia_symbols
    J_six = {Jxx: M / 3 * (d[1] ** 2 + d[2] ** 2), Jyy: M / 3 * (d[0] ** 2 + d[2] ** 2),
             Jzz: M / 3 * (d[0] ** 2 + d[1] ** 2)}
    L_b = rigid.lagrangian(system).xreplace(J_six)
    assert _reduce_trig(sp.expand(L_a - L_b), system.angles) == 0


# The particle route is re-derived per case (seconds each): Z-Y-X in every variant, the
# other sequence types (Tait-Bryan and proper Euler) and the four-point model once or twice.
# Every one of the 12 sequences is checked against inertia.dynamics' Euler equations below.
_T, _G = {"translation": True}, {"gravity": True}
ROUTE_CASES = [(6, "ZYX", {}), (6, "ZYX", _G), (6, "ZYX", _T), (6, "ZYX", {**_T, **_G}),
               (4, "ZYX", {**_T, **_G}), (6, "ZXZ", _G), (4, "XYZ", _T), (4, "YXZ", _G),
               (6, "XYX", {**_T, **_G})]


@pytest.mark.parametrize("n_points, seq, variant", ROUTE_CASES,
                         ids=[f"{n}-{s}-{'+'.join(v) or 'rotation'}" for n, s, v in ROUTE_CASES])
def test_particle_route_and_rigid_route_agree_at_random_states(variant, seq, n_points):
    rng = np.random.default_rng(11)
    eom = derive(seq, **variant)
    system = eom.system
    f = eom.numeric()
    route = ParticleRoute(system, n_points)
    model_fn = inertia.six_point_model if n_points == 6 else inertia.four_point_model
    for _ in range(8):
        props = _random_body(rng, com=system.has_com)
        model = model_fn(props)
        q = np.concatenate([rng.normal(size=len(system.position)), _random_angles(seq, rng)])
        qd = rng.normal(size=system.n)
        kw = _numeric_kwargs(system, props, rng)
        a = f(q, qd, **kw)
        b = route.numeric(q, qd, model.masses, model.positions_body, gravity=kw.get("gravity"),
                          torque_body=kw["torque_body"], force_world=kw.get("force_world"))
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.abs(b).max())


@pytest.mark.parametrize("seq", SEQUENCES)
def test_accelerations_satisfy_eulers_equation_from_inertia_dynamics(seq):
    """omega' = E q'' + E' q' must equal J^-1 (tau - w x J w) computed by inertia.dynamics."""
    rng = np.random.default_rng(3)
    eom = derive(seq)
    s = eom.system
    f = eom.numeric()
    E_fn = sp.lambdify(s.angles, s.E, "numpy")
    Edot_qd = sp.lambdify(s.angles + s.rates, s.rate_of(s.E) * sp.Matrix(s.rates), "numpy")
    for _ in range(5):
        props = _random_body(rng, com=False)
        q, qd, tau = _random_angles(seq, rng), rng.normal(size=3), rng.normal(size=3)
        qdd = f(q, qd, inertia=props.inertia_com, torque_body=tau)
        omega = np.array(E_fn(*q), float) @ qd
        omega_dot = np.array(E_fn(*q), float) @ qdd + np.array(Edot_qd(*q, *qd), float).ravel()
        expected = angular_acceleration_body(omega, props.inertia_com, tau)
        np.testing.assert_allclose(omega_dot, expected, rtol=0, atol=1e-12 * np.abs(expected).max())


def test_euler_residual_vanishes_on_the_derived_accelerations():
    rng = np.random.default_rng(5)
    for variant in VARIANTS:
        eom = derive("ZYX", **variant)
        s = eom.system
        res = sp.lambdify(eom.arguments + s.accelerations, rigid.euler_residual(s), "numpy")
        props = _random_body(rng, com=s.has_com)
        q = np.concatenate([rng.normal(size=len(s.position)), _random_angles("ZYX", rng)])
        qd = rng.normal(size=s.n)
        kw = _numeric_kwargs(s, props, rng)
        qdd = eom.numeric()(q, qd, **kw)
        params, inputs = _flat_args(s, props, kw)
        r = np.array(res(*q, *qd, *params, *inputs, *qdd), float)
        assert np.abs(r).max() < 1e-12 * max(1.0, np.abs(qdd).max())


# ----------------------------------------------------------------------------- trajectories


def test_zyx_equations_reproduce_the_exact_attitude():
    """I = (1,2,3), w0 = (0.4,0.8,0.6), (roll, pitch, yaw) = (0.1,-0.2,0.3): DOP853 on the generated
    equations vs the elliptic-function solution of Euler's equations with a quaternion."""
    from scipy.integrate import solve_ivp

    eom = derive("ZYX")
    f = eom.numeric()
    E_fn = sp.lambdify(eom.system.angles, eom.system.E, "numpy")
    J = np.diag([1.0, 2.0, 3.0])
    omega0 = np.array([0.4, 0.8, 0.6])
    roll, pitch, yaw = 0.1, -0.2, 0.3
    q0 = np.array([yaw, pitch, roll])
    qd0 = np.linalg.solve(np.array(E_fn(*q0), float), omega0)
    sol = solve_ivp(lambda t, y: np.concatenate([y[3:], f(y[:3], y[3:], inertia=J)]), (0.0, 3.0),
                    np.concatenate([q0, qd0]), method="DOP853", rtol=1e-13, atol=1e-13, dense_output=True)
    t = np.linspace(0.0, 3.0, 31)
    angles = sol.sol(t)[:3].T
    q_exact, omega_exact = exact_solution([1.0, 2.0, 3.0], omega0, t, matrix_to_quat(Rotation.from_euler("ZYX", q0).as_matrix()))
    R_generated = Rotation.from_euler("ZYX", angles).as_matrix()
    assert np.abs(R_generated - quat_to_matrix(q_exact)).max() < 1e-10
    assert np.abs(angles[:, 1]).max() < 1.0  # stayed well away from gimbal lock


def test_heavy_top_conserves_energy():
    """Pivoted body under gravity (no inputs): T + V from the Lagrangian is constant along DOP853."""
    from scipy.integrate import solve_ivp

    rng = np.random.default_rng(2)
    eom = derive("ZYX", gravity=True)
    s = eom.system
    f = eom.numeric()
    props = _random_body(rng, com=True)
    g = np.array([0.0, 0.0, -9.81])
    J = props.inertia_com
    params = [J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2], props.mass, *props.com, *g]
    L = eom.lagrangian()
    T = sp.hessian(L, s.rates)  # L = 1/2 qd^T M qd - V  =>  E = 2 T - L with T = 1/2 qd^T M qd
    kinetic = (sp.Matrix(s.rates).T * T * sp.Matrix(s.rates))[0, 0] / 2
    energy = sp.lambdify(s.coordinates + s.rates + s.parameters, 2 * kinetic - L, "numpy")
    y0 = np.concatenate([[0.2, 0.3, -0.1], rng.normal(size=3)])
    sol = solve_ivp(lambda t, y: np.concatenate([y[3:], f(y[:3], y[3:], inertia=J, mass=props.mass, com=props.com,
                                                          gravity=g)]),
                    (0.0, 2.0), y0, method="DOP853", rtol=1e-12, atol=1e-12)
    assert np.abs(sol.y[1]).max() < 1.3  # pitch stayed away from +-pi/2, so the check is meaningful
    e = np.array([energy(*y, *params) for y in sol.y.T])
    assert np.ptp(e) < 1e-9 * max(1.0, np.abs(e).max())
    assert np.ptp(sol.y[1]) > 0.05 and np.ptp(sol.y[2]) > 0.05  # it did swing


def test_translation_gives_newton_for_the_center_of_mass():
    """r_com = p + R c must accelerate at F/m + g whatever the rotation does."""
    rng = np.random.default_rng(4)
    eom = derive("ZYX", translation=True, gravity=True)
    s = eom.system
    f = eom.numeric()
    r_com = s.com_world()
    r_dd = sp.lambdify(s.coordinates + s.rates + s.accelerations + tuple(s.com),
                       s.time_derivative(s.time_derivative(r_com)), "numpy")
    for _ in range(5):
        props = _random_body(rng)
        q = np.concatenate([rng.normal(size=3), _random_angles("ZYX", rng)])
        qd = rng.normal(size=6)
        kw = _numeric_kwargs(s, props, rng)
        qdd = f(q, qd, **kw)
        a = np.array(r_dd(*q, *qd, *qdd, *props.com), float).ravel()
        np.testing.assert_allclose(a, kw["force_world"] / props.mass + kw["gravity"], atol=1e-12)


def test_numeric_function_is_batched():
    rng = np.random.default_rng(8)
    f = derive("ZYX").numeric()
    J = _random_body(rng, com=False).inertia_com
    q = np.stack([_random_angles("ZYX", rng) for _ in range(7)])
    qd = rng.normal(size=(7, 3))
    batch = f(q, qd, inertia=J)
    assert batch.shape == (7, 3)
    for k in range(7):
        np.testing.assert_allclose(batch[k], f(q[k], qd[k], inertia=J), rtol=1e-15, atol=1e-15)


# ----------------------------------------------------------------------------- gimbal lock


def test_gimbal_lock_raises_with_advice_and_warns_near_it():
    f = derive("ZYX").numeric()
    J = np.diag([1.0, 2.0, 3.0])
    with pytest.raises(GimbalLockError, match=r"gimbal lock.*theta = 1\.57079632679.*quaternions"):
        f([0.1, np.pi / 2, 0.2], [0.1, 0.2, 0.3], inertia=J)
    with pytest.warns(GimbalLockWarning, match="condition number"):
        f([0.1, np.pi / 2 - 1e-4, 0.2], [0.1, 0.2, 0.3], inertia=J)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        f([0.1, 0.3, 0.2], [0.1, 0.2, 0.3], inertia=J)  # far from it: silent
    # proper Euler sequences lock at sin(theta) = 0 instead
    with pytest.raises(GimbalLockError):
        derive("ZXZ").numeric()([0.1, 0.0, 0.2], [0.1, 0.2, 0.3], inertia=J)
    # a batch names the offending state
    with pytest.raises(GimbalLockError, match=r"at state \(1,\)"):
        f([[0.1, 0.2, 0.3], [0.0, -np.pi / 2, 0.0]], [[0.1, 0.2, 0.3]] * 2, inertia=J)


def test_bad_input_is_refused_clearly():
    with pytest.raises(InputError, match="unknown Euler sequence 'ZZX'"):
        derive("ZZX")
    f = derive("ZYX", gravity=True).numeric()
    with pytest.raises(InputError, match="give mass="):
        f([0, 0, 0], [0, 0, 0], inertia=np.eye(3), gravity=[0, 0, -9.81])
    with pytest.raises(InputError, match="gravity="):
        f([0, 0, 0], [0, 0, 0], inertia=np.eye(3), mass=1.0, com=[0, 0, 0.1])
    g = derive("ZYX").numeric()
    with pytest.raises(InputError, match=r"q must have shape \(\.\.\., 3\)"):
        g([0, 0], [0, 0, 0], inertia=np.eye(3))
    with pytest.raises(InputError, match="symmetric"):
        g([0, 0, 0], [0, 0, 0], inertia=[[1, 0.5, 0], [0, 1, 0], [0, 0, 1]])


# ----------------------------------------------------------------------------- compactness and code


def test_zyx_result_is_compact():
    """The issue's bar: no larger than LagrangesMethod + simplify (2,008 operations)."""
    assert derive("ZYX").count_ops <= 2008
    assert derive("ZYX", translation=True, gravity=True).count_ops <= 2008


@pytest.mark.parametrize("variant", VARIANTS, ids=lambda v: "+".join(v) or "rotation")
def test_generated_python_code_runs_and_agrees(variant):
    rng = np.random.default_rng(9)
    eom = derive("ZYX", **variant)
    s = eom.system
    namespace: dict = {}
    exec(compile(eom.python_code(), "<generated>", "exec"), namespace)  # noqa: S102 - our own generated code
    fn = namespace[eom._function_name()]
    props = _random_body(rng, com=s.has_com)
    q = np.concatenate([rng.normal(size=len(s.position)), _random_angles("ZYX", rng)])
    qd = rng.normal(size=s.n)
    kw = _numeric_kwargs(s, props, rng)
    expected = eom.numeric()(q, qd, **kw)
    params, inputs = _flat_args(s, props, kw)
    got = np.array(fn(*q, *qd, *params, *inputs))
    np.testing.assert_allclose(got, expected, rtol=1e-13, atol=1e-13)


@pytest.mark.skipif(shutil.which("gcc") is None, reason="gcc not installed")
def test_generated_c_code_compiles_and_agrees(tmp_path):
    rng = np.random.default_rng(10)
    eom = derive("ZYX", translation=True, gravity=True)
    s = eom.system
    src = tmp_path / "eom.c"
    src.write_text(eom.c_code())
    lib = tmp_path / "libeom.so"
    subprocess.run(["gcc", "-O2", "-std=c99", "-Wall", "-Werror", "-shared", "-fPIC", str(src), "-o", str(lib), "-lm"],
                   check=True, capture_output=True)
    c_fn = getattr(ctypes.CDLL(str(lib)), eom._function_name())
    dp = ctypes.POINTER(ctypes.c_double)
    c_fn.argtypes = [dp] * 5
    c_fn.restype = ctypes.c_int
    props = _random_body(rng)
    q = np.concatenate([rng.normal(size=3), _random_angles("ZYX", rng)])
    qd = rng.normal(size=6)
    kw = _numeric_kwargs(s, props, rng)
    J = props.inertia_com
    params = np.array([J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2], props.mass, *props.com, *kw["gravity"]])
    inputs = np.concatenate([kw["torque_body"], kw["force_world"]])
    out = np.zeros(6)

    def ptr(a):
        return np.ascontiguousarray(a, dtype=np.float64).ctypes.data_as(dp)

    assert c_fn(ptr(q), ptr(qd), ptr(params), ptr(inputs), out.ctypes.data_as(dp)) == 0
    np.testing.assert_allclose(out, eom.numeric()(q, qd, **kw), rtol=1e-12, atol=1e-12)
    q_lock = q.copy()
    q_lock[4] = np.pi / 2
    assert c_fn(ptr(q_lock), ptr(qd), ptr(params), ptr(inputs), out.ctypes.data_as(dp)) == 1


def test_json_export_round_trips_through_sympy():
    """The JSON's subexpressions and outputs, parsed back, give the numeric function's values."""
    rng = np.random.default_rng(12)
    eom = derive("ZYX", gravity=True)
    d = eom.to_dict()
    assert d["coordinates"] == ["psi", "theta", "phi"] and d["count_ops"] == eom.count_ops
    props = _random_body(rng)
    kw = _numeric_kwargs(eom.system, props, rng)
    q, qd = _random_angles("ZYX", rng), rng.normal(size=3)
    J = props.inertia_com
    values = dict(zip(d["coordinates"], q)) | dict(zip(d["rates"], qd))
    values |= dict(zip(d["parameters"], [J[0, 0], J[1, 1], J[2, 2], J[0, 1], J[0, 2], J[1, 2], props.mass,
                                          *props.com, *kw["gravity"]]))
    values |= dict(zip(d["inputs"], [*kw["torque_body"], *kw["force_world"]]))
    env = {k: sp.Float(v, 30) for k, v in values.items()}
    for name, text in d["subexpressions"]:
        env[name] = sp.sympify(text, locals={k: sp.Symbol(k) for k in env}).subs({sp.Symbol(k): v for k, v in env.items()})
    out = [float(sp.sympify(t, locals={k: sp.Symbol(k) for k in env}).subs({sp.Symbol(k): v for k, v in env.items()}))
           for t in d["outputs"]]
    np.testing.assert_allclose(out, eom.numeric()(q, qd, **kw), rtol=1e-12, atol=1e-12)


def test_latex_export_has_every_subexpression_and_output():
    eom = derive("ZYX")
    tex = eom.latex(form="cse")
    assert tex == eom.cse_latex() and tex.startswith("\\begin{align*}") and tex.rstrip().endswith("\\end{align*}")
    assert tex.count("&=") == len(eom.replacements) + 3 + 2
    for name in (r"\ddot{\psi}", r"\ddot{\theta}", r"\ddot{\phi}"):
        assert name in tex
