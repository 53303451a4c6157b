"""Tests of the exact mesh integrals (inertia.geometry.integrals), each against independent truth:
closed forms, exact rational arithmetic on the very same float vertices (fractions.Fraction),
mpmath at 40 digits for the shell (whose areas are square roots), trimesh near the origin,
symmetries of the integrals; and their determinism (the same bits in every call and process).
"""

from __future__ import annotations

import functools
import subprocess
import sys
from fractions import Fraction
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import inertia
from inertia.errors import InputError
from inertia.geometry import integrals as mk

# unit cube [0, 1]^3, faces counter-clockwise seen from outside
CUBE_V = np.array([[x, y, z] for x in (0.0, 1.0) for y in (0.0, 1.0) for z in (0.0, 1.0)])
CUBE_F = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                   [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])
FAR = 1e7 * np.ones(3) / np.sqrt(3.0)


# ---------------------------------------------------------------------- helpers
def props(vertices, faces, *, shell=False, density=1.0):
    """(measure, com, inertia about the COM) through the public kernel functions."""
    integrals = (mk.shell_integrals if shell else mk.solid_integrals)(vertices, faces)
    com, inertia = mk.central_inertia(*integrals, density)
    return integrals[0], com, inertia


def rel_err(a, b):
    """Largest entry of |a - b| relative to the largest entry of |b|."""
    return float(np.abs(np.asarray(a) - b).max() / np.abs(b).max())


def box(lo, hi):
    lo, hi = np.asarray(lo, float), np.asarray(hi, float)
    return lo + CUBE_V * (hi - lo), CUBE_F.copy()


def union(*parts):
    """Several closed meshes as one (the integrals add)."""
    vs, fs, n = [], [], 0
    for v, f in parts:
        vs.append(v)
        fs.append(f + n)
        n += len(v)
    return np.vstack(vs), np.vstack(fs)


def exact_solid(vertices, faces):
    """Volume, COM and central inertia (unit density) computed in exact rational arithmetic
    from the float vertices as given (Tonon's tetrahedron formulas about the origin), then rounded."""
    V = [[Fraction(x) for x in row] for row in np.asarray(vertices, float).tolist()]
    vol, F = Fraction(0), [Fraction(0)] * 3
    S = [[Fraction(0)] * 3 for _ in range(3)]
    for i, j, k in np.asarray(faces).tolist():
        a, b, c = V[i], V[j], V[k]
        det = (a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2])
               + a[2] * (b[0] * c[1] - b[1] * c[0]))
        s = [a[m] + b[m] + c[m] for m in range(3)]
        vol += det
        for m in range(3):
            F[m] += det * s[m]
            for n in range(m, 3):
                S[m][n] += det * (a[m] * a[n] + b[m] * b[n] + c[m] * c[n] + s[m] * s[n])
    vol /= 6
    com = [x / 24 / vol for x in F]
    C = [[S[min(m, n)][max(m, n)] / 120 - vol * com[m] * com[n] for n in range(3)] for m in range(3)]
    tr = C[0][0] + C[1][1] + C[2][2]
    inertia = [[(tr if m == n else 0) - C[m][n] for n in range(3)] for m in range(3)]
    return float(vol), np.array([float(x) for x in com]), np.array([[float(x) for x in r] for r in inertia])


def random_hull(seed, n_points=40):
    """A random closed convex mesh (outward winding), anisotropic so its principal moments differ."""
    from scipy.spatial import ConvexHull

    rng = np.random.default_rng(seed)
    pts = rng.normal(size=(n_points, 3)) * np.array([2.0, 1.0, 0.5]) + rng.normal(size=3)
    hull = ConvexHull(pts)
    faces = hull.simplices.copy()                        # int32, winding not consistent
    a, b, c = (pts[faces[:, k]] for k in range(3))
    inward = np.einsum("ij,ij->i", np.cross(b - a, c - a), hull.equations[:, :3]) < 0
    faces[inward] = faces[inward][:, ::-1]
    return pts, faces


def rotation(q):
    w, x, y, z = np.asarray(q, float) / np.linalg.norm(q)
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
                     [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
                     [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]])


def data_mesh(meshes, name):
    """A test mesh file (the `meshes` fixture: made by tests/_make.py, or ../shared/data) as
    trimesh reads and welds it."""
    return _data_mesh(str(meshes.path(name)), name)


@functools.lru_cache(maxsize=None)
def _data_mesh(path, name):
    trimesh = pytest.importorskip("trimesh")
    m = trimesh.load(path, process=True, force="mesh")
    if name == "spot.obj":
        m.merge_vertices(merge_tex=True, merge_norm=True)
    assert m.is_watertight and m.is_winding_consistent
    return np.array(m.vertices), np.array(m.faces)


# ---------------------------------------------------------------------- closed forms
def test_unit_cube_solid_is_exact():
    volume, com, inertia = props(CUBE_V, CUBE_F)
    assert volume == pytest.approx(1.0, rel=1e-15, abs=0)
    np.testing.assert_allclose(com, [0.5, 0.5, 0.5], rtol=0, atol=1e-15)
    np.testing.assert_allclose(inertia, np.eye(3) / 6, rtol=0, atol=1e-15)


def test_unit_cube_shell_is_exact():
    # hollow cube, unit surface density: area 6, I = 5/18 m a^2 = 5/3
    area, com, inertia = props(CUBE_V, CUBE_F, shell=True)
    assert area == pytest.approx(6.0, rel=1e-15, abs=0)
    np.testing.assert_allclose(com, [0.5, 0.5, 0.5], rtol=0, atol=1e-15)
    np.testing.assert_allclose(inertia, np.eye(3) * 5 / 3, rtol=0, atol=5 / 3 * 1e-15)


# ---------------------------------------------------------------------- far from the origin
@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_cube_far_from_origin_keeps_its_central_tensor(shell):
    measure, com, inertia = props(CUBE_V + FAR, CUBE_F, shell=shell)
    expected = np.eye(3) * (5 / 3 if shell else 1 / 6)
    assert rel_err(inertia, expected) <= 1e-12
    assert measure == pytest.approx(6.0 if shell else 1.0, rel=1e-12)
    np.testing.assert_allclose(com, FAR + 0.5, rtol=1e-15)


def test_trimesh_loses_the_far_cube_contrast():
    """trimesh expands about the origin: the same cube comes out with garbage, negative moments."""
    trimesh = pytest.importorskip("trimesh")
    v = CUBE_V + FAR
    theirs = trimesh.triangles.mass_properties(v[CUBE_F]).inertia
    err_theirs = rel_err(theirs, np.eye(3) / 6)
    if err_theirs < 1e-6:
        pytest.skip(f"trimesh {trimesh.__version__} is now accurate here ({err_theirs:.1e}); no contrast left")
    assert err_theirs > 1e3 and np.linalg.eigvalsh(theirs).min() < 0
    assert rel_err(props(v, CUBE_F)[2], np.eye(3) / 6) <= 1e-12


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_rotated_cube_far_away_matches_exact_rationals(seed):
    rng = np.random.default_rng(seed)
    R = rotation(rng.normal(size=4))
    v = (CUBE_V - 0.5) @ R.T * rng.uniform(0.5, 2.0) + FAR * rng.uniform(0.3, 3.0, size=3)
    vol, com, inertia = exact_solid(v, CUBE_F)
    got = props(v, CUBE_F)
    assert got[0] == pytest.approx(vol, rel=1e-13)
    np.testing.assert_allclose(got[1], com, rtol=1e-15)
    assert rel_err(got[2], inertia) <= 1e-12


def test_lopsided_body_gets_a_second_pass_about_the_com(monkeypatch):
    # a unit cube with a needle 1e3 long and 1e-6 thick: the box center lies far out on
    # the needle (kappa ~ 1e6), so one pass about it loses ~8 digits
    v, f = union(box([0, 0, 0], [1, 1, 1]), box([1, 0.5 - 5e-7, 0.5 - 5e-7], [1001, 0.5 + 5e-7, 0.5 + 5e-7]))
    vol, com, inertia = exact_solid(v, f)
    two_pass = props(v, f)
    assert rel_err(two_pass[2], inertia) <= 1e-14
    np.testing.assert_allclose(two_pass[1], com, rtol=0, atol=1e-15)
    monkeypatch.setattr(mk, "REFINE_KAPPA", np.inf)
    one_pass = props(v, f)
    assert rel_err(one_pass[2], inertia) > 1e-12     # the second pass is what makes the difference


# ---------------------------------------------------------------------- exact arithmetic, trimesh
def exact_integrals(vertices, faces, r, shell):
    """(measure, first (3,), second (3, 3)) about the float point ``r``, in mpmath at 50 digits
    (the corners minus r exactly; the shell's areas are square roots), then rounded."""
    mpmath = pytest.importorskip("mpmath")
    with mpmath.workdps(50):
        R = [mpmath.mpf(float(x)) for x in r]
        V = [[mpmath.mpf(x) - R[k] for k, x in enumerate(row)] for row in np.asarray(vertices, float).tolist()]
        m, F, S = mpmath.mpf(0), [mpmath.mpf(0)] * 3, [[mpmath.mpf(0)] * 3 for _ in range(3)]
        for i, j, k in np.asarray(faces).tolist():
            a, b, c = V[i], V[j], V[k]
            u = [b[q] - a[q] for q in range(3)]
            w = [c[q] - a[q] for q in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            wt = mpmath.sqrt(sum(x * x for x in n)) if shell else sum(a[q] * n[q] for q in range(3))
            s = [a[q] + b[q] + c[q] for q in range(3)]
            m += wt
            for p in range(3):
                F[p] += wt * s[p]
                for q in range(3):
                    S[p][q] += wt * (a[p] * a[q] + b[p] * b[q] + c[p] * c[q] + s[p] * s[q])
        d0, d1, d2 = (2, 6, 24) if shell else (6, 24, 120)
        return (float(m / d0), np.array([float(x / d1) for x in F]),
                np.array([[float(x / d2) for x in row] for row in S]))


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_random_hulls_match_exact_arithmetic(seed, shell):
    v, f = random_hull(seed)
    v = v + np.random.default_rng(seed).uniform(-1e3, 1e3, size=3) * (seed % 2)
    fn = mk.shell_integrals if shell else mk.solid_integrals
    got = fn(v, f)
    np.testing.assert_array_equal(got[3], mk.reference_point(v))      # about the box center
    exact = exact_integrals(v, f, got[3], shell)
    size = np.ptp(v, axis=0).max()
    assert got[0] == pytest.approx(exact[0], rel=1e-13)
    np.testing.assert_allclose(got[1], exact[1], rtol=0, atol=1e-13 * exact[0] * size)   # first ~ measure * size
    assert rel_err(got[2], exact[2]) <= 1e-13


@pytest.mark.parametrize("name", ["icosphere1", "icosphere3", "icosphere4"])
def test_agrees_with_trimesh_near_the_origin(name):
    trimesh = pytest.importorskip("trimesh")
    m = trimesh.creation.icosphere(subdivisions=int(name[-1]))
    _agrees_with_trimesh(np.array(m.vertices), np.array(m.faces))


@pytest.mark.parametrize("name", ["wingnut.obj", "ballA.off", "featuretype.stl", "spot.obj"])
def test_agrees_with_trimesh_near_the_origin_on_mesh_files(name, meshes):
    _agrees_with_trimesh(*data_mesh(meshes, name))


def _agrees_with_trimesh(v, f):
    trimesh = pytest.importorskip("trimesh")
    theirs = trimesh.triangles.mass_properties(v[f])
    volume, com, inertia = props(v, f)
    size = np.ptp(v, axis=0).max()
    assert volume == pytest.approx(theirs.volume, rel=1e-10)
    np.testing.assert_allclose(com, theirs.center_mass, rtol=0, atol=1e-10 * size)
    assert rel_err(inertia, theirs.inertia) <= 1e-10


# ---------------------------------------------------------------------- symmetries
@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_invariant_under_face_order_and_vertex_rotation(shell, meshes):
    v, f = data_mesh(meshes, "wingnut.obj")
    rng = np.random.default_rng(7)
    base = props(v, f, shell=shell)
    shuffled = props(v, f[rng.permutation(len(f))], shell=shell)
    rolled = props(v, np.roll(f, rng.integers(1, 3), axis=1), shell=shell)   # (a,b,c) -> (c,a,b)
    for other in (shuffled, rolled):
        assert other[0] == pytest.approx(base[0], rel=1e-13)
        np.testing.assert_allclose(other[1], base[1], rtol=0, atol=1e-13 * np.ptp(v, axis=0).max())
        assert rel_err(other[2], base[2]) <= 1e-13


def test_inward_winding_negates_the_solid_integrals():
    v, f = random_hull(3)
    out = mk.solid_integrals(v, f)
    inv = mk.solid_integrals(v, f[:, ::-1])
    assert out[0] > 0 and inv[0] == pytest.approx(-out[0], rel=1e-14)
    assert rel_err(-inv[2], out[2]) <= 1e-14
    assert rel_err(mk.shell_integrals(v, f[:, ::-1])[2],
                   mk.shell_integrals(v, f)[2]) <= 1e-14


HULL_V, HULL_F = random_hull(11)
_HULL = props(HULL_V, HULL_F)
_HULL_SIZE = float(np.linalg.norm(np.ptp(HULL_V, axis=0)))


@settings(max_examples=40, deadline=None)
@given(q=st.lists(st.floats(-1, 1), min_size=4, max_size=4).filter(lambda q: np.linalg.norm(q) > 0.1),
       t=st.lists(st.floats(-1e3, 1e3), min_size=3, max_size=3),
       shell=st.booleans())
def test_rigid_motion_rotates_the_tensor_and_moves_the_com(q, t, shell):
    R, t = rotation(q), np.array(t)
    base = props(HULL_V, HULL_F, shell=shell) if shell else _HULL
    moved = props(HULL_V @ R.T + t, HULL_F, shell=shell)
    # the moved vertices are rounded at u |t|: that, not the kernel, sets the tolerance
    tol = 5e-14 * (1 + np.abs(t).max() / _HULL_SIZE)
    assert moved[0] == pytest.approx(base[0], rel=tol)
    np.testing.assert_allclose(moved[1], R @ base[1] + t, rtol=0, atol=tol * _HULL_SIZE)
    assert rel_err(moved[2], R @ base[2] @ R.T) <= tol


# ---------------------------------------------------------------------- reference point
def test_integrals_move_exactly_to_a_given_reference():
    v, f = random_hull(5)
    vol, first, second, p = mk.solid_integrals(v, f)
    r = np.array([0.3, -2.0, 1.5])
    vol_r, first_r, second_r, r_out = mk.solid_integrals(v, f, reference=r)
    np.testing.assert_array_equal(r_out, r)
    ex_vol, ex_com, ex_inertia = exact_solid(v, f)
    assert vol_r == vol
    np.testing.assert_allclose(first_r / vol_r + r, ex_com, rtol=0, atol=1e-14)
    com, inertia = mk.central_inertia(vol_r, first_r, second_r, r_out, 1.0)
    assert rel_err(inertia, ex_inertia) <= 1e-13


def test_reference_point_is_the_box_center():
    v = np.array([[0.0, -1.0, 2.0], [4.0, 3.0, 2.5], [1.0, 0.0, 3.0]])
    np.testing.assert_array_equal(mk.reference_point(v), [2.0, 1.0, 2.5])
    assert mk.solid_integrals(v, np.zeros((0, 3), int))[3].tolist() == [2.0, 1.0, 2.5]


# ---------------------------------------------------------------------- bad input, determinism
@pytest.mark.parametrize("bad", [8, -1])
def test_vertex_index_out_of_range_is_refused(bad):
    f = CUBE_F.copy()
    f[5, 1] = bad
    with pytest.raises(InputError, match=rf"^faces\[5, 1\] = {bad} names no vertex \(there are 8\)$"):
        mk.solid_integrals(CUBE_V, f)
    with pytest.raises(InputError, match=r"^faces\[5, 1\] = "):
        mk.shell_integrals(CUBE_V, f)


def test_non_finite_vertex_is_refused():
    v = CUBE_V.copy()
    v[6, 2] = np.nan
    with pytest.raises(InputError, match=r"^mesh integrals are not finite: vertex 6 = \[1.0, 1.0, nan\] is not finite$"):
        mk.solid_integrals(v, CUBE_F)


def test_bad_shapes_and_names_are_refused():
    with pytest.raises(InputError, match=r"^vertices must have shape \(V, 3\), got \(8, 2\)$"):
        mk.solid_integrals(CUBE_V[:, :2], CUBE_F)
    with pytest.raises(InputError, match=r"^faces must have shape \(F, 3\), got \(12, 4\)$"):
        mk.solid_integrals(CUBE_V, np.hstack([CUBE_F, CUBE_F[:, :1]]))
    with pytest.raises(InputError, match=r"^faces must hold integer vertex indices, got dtype float64$"):
        mk.solid_integrals(CUBE_V, CUBE_F.astype(float))
    with pytest.raises(InputError, match=r"^vertices is empty"):
        mk.solid_integrals(np.zeros((0, 3)), np.zeros((0, 3), int))
    with pytest.raises(InputError, match=r"^reference must be a finite \(3,\) point, got "):
        mk.solid_integrals(CUBE_V, CUBE_F, reference=[0.0, 1.0])
    with pytest.raises(InputError, match=r"^cannot locate the center of mass: the measure \(volume or area\) is 0.0$"):
        mk.central_inertia(0.0, np.zeros(3), np.zeros((3, 3)), np.zeros(3), 1.0)


def test_other_integer_dtypes_and_empty_faces():
    ref = mk.solid_integrals(CUBE_V, CUBE_F)
    for dtype in (np.int32, np.uint16, np.int64):
        got = mk.solid_integrals(CUBE_V, CUBE_F.astype(dtype))
        assert got[0] == ref[0] and np.array_equal(got[2], ref[2])
    empty = mk.solid_integrals(CUBE_V, np.zeros((0, 3), np.int64))
    assert empty[0] == 0.0 and not empty[1].any() and not empty[2].any()


_BITS = "import sys; sys.path.insert(0, {root!r}); from tests.geometry.test_mesh_kernel import bits_of_a_run; " \
        "print(bits_of_a_run())"


def bits_of_a_run() -> str:
    """A digest of the integrals (solid, shell), of mesh_properties (the clean-solid pass) and of
    its principal frame (the compiled eigensolver) of a sphere of 20,480 faces (two chunks of the
    summation) far from the origin, stretched."""
    import hashlib

    trimesh = pytest.importorskip("trimesh")
    m = trimesh.creation.icosphere(subdivisions=5)
    v = np.asarray(m.vertices) * [1.0, 2.0, 0.5] + [1e3, -2e2, 7.0]
    f = np.asarray(m.faces)
    out = [*mk.solid_integrals(v, f), *mk.shell_integrals(v, f)]
    p = inertia.mesh_properties(v, f, density=1.0)
    pf = p.principal()
    out += [p.mass, p.com, p.inertia_com, pf.moments, pf.R_body_principal]
    return hashlib.sha256(b"".join(np.asarray(x, dtype=np.float64).tobytes() for x in out)).hexdigest()


def test_integrals_give_the_same_bits_in_every_call_and_in_a_fresh_process():
    first = bits_of_a_run()
    assert bits_of_a_run() == first
    root = str(Path(__file__).resolve().parents[2])
    out = subprocess.run([sys.executable, "-c", _BITS.format(root=root)], capture_output=True, text=True,
                         timeout=300, cwd=root)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == first


def test_integrals_give_the_same_bits_on_threads():
    """The kernels release the GIL and share nothing: calls on 4 threads at once give the bits of
    a call alone."""
    from concurrent.futures import ThreadPoolExecutor

    first = bits_of_a_run()
    with ThreadPoolExecutor(4) as pool:
        assert list(pool.map(lambda _: bits_of_a_run(), range(8))) == [first] * 8
