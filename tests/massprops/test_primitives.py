"""Tests of inertia.massprops.primitives against independent truth.

Truth comes from
1. quadrature over the actual geometry: tensor-product Gauss-Legendre over a
   parametrisation of each solid/surface, with the Jacobian (volume element, or
   surface element |X_u x X_v|) computed generically by complex-step
   differentiation of the parametrisation -- only the *shape* is typed here, never
   a moment formula -- plus scipy adaptive quadrature (tplquad/dblquad) spot checks;
2. fine triangle meshes (trimesh.creation) through inertia.mesh_properties, with
   second-order convergence toward the closed forms;
3. limits and exact relations (subtraction of solids, classical limiting bodies).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import scipy.special
from scipy import integrate

import inertia
from inertia import (
    InputError,
    box,
    capsule,
    cone,
    cylinder,
    ellipsoid,
    mesh_properties,
    sphere,
    spherical_shell,
    torus,
    tube,
)

trimesh = pytest.importorskip("trimesh")

PI = math.pi

KIND = {False: "solid", True: "shell"}


# ============================================================================ generic quadrature
def _gl(n, lo, hi):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (hi + lo) + 0.5 * (hi - lo) * x, 0.5 * (hi - lo) * w


def _partial(X, args, k, h=1e-30):
    """Exact (to rounding) partial derivative of X w.r.t. args[k] by the complex step."""
    shifted = list(args)
    shifted[k] = shifted[k] + 1j * h
    return np.imag(np.asarray(X(*shifted))) / h


def _moments(points, weights):
    """Zeroth, first and second moments of a weighted point set: M, int x, int x x^T."""
    M = weights.sum()
    first = weights @ points
    second = np.einsum("n,ni,nj->ij", weights, points, points)
    return np.array([M, *first, *second.ravel()])


def solid_region(X, ranges, n=24):
    """Moments of the region X([lo0,hi0] x [lo1,hi1] x [lo2,hi2]), X: (u, v, w) -> (3, ...)."""
    rules = [_gl(n, lo, hi) for lo, hi in ranges]
    U = np.meshgrid(*[r[0] for r in rules], indexing="ij")
    W = np.einsum("i,j,k->ijk", *[r[1] for r in rules])
    U = [u.ravel() for u in U]
    J = np.stack([_partial(X, U, k) for k in range(3)], axis=-1)  # (3, N, 3): rows x, cols d/du_k
    det = np.abs(np.linalg.det(np.moveaxis(J, 0, 1)))
    P = np.real(np.asarray(X(*U))).T
    return _moments(P, det * W.ravel())


def surface_patch(X, ranges, n=24):
    """Moments of the surface patch X([lo0,hi0] x [lo1,hi1]), X: (u, v) -> (3, ...)."""
    (u, wu), (v, wv) = (_gl(n, lo, hi) for lo, hi in ranges)
    U, V = (g.ravel() for g in np.meshgrid(u, v, indexing="ij"))
    Xu, Xv = _partial(X, (U, V), 0), _partial(X, (U, V), 1)
    dA = np.linalg.norm(np.cross(Xu.T, Xv.T), axis=1)
    P = np.real(np.asarray(X(U, V))).T
    return _moments(P, dA * np.outer(wu, wv).ravel())


def props_from_moments(mom, density):
    """(mass, com, inertia about the COM) from region moments, by the definition I = tr(C) 1 - C."""
    M, first, second = mom[0], mom[1:4], mom[4:].reshape(3, 3)
    com = first / M
    C = second - M * np.outer(com, com)
    return density * M, com, density * (np.trace(C) * np.eye(3) - C)


def assert_matches(p, mass, com, inertia_com, rtol):
    scale_I = np.abs(inertia_com).max()
    scale_c = max(np.abs(com).max(), math.sqrt(scale_I / mass))
    assert p.mass == pytest.approx(mass, rel=rtol)
    np.testing.assert_allclose(p.com, com, rtol=0, atol=rtol * scale_c)
    np.testing.assert_allclose(p.inertia_com, inertia_com, rtol=0, atol=rtol * scale_I)


# ---------------------------------------------------------------- parametrisations (shape only)
def _cyl(rho, phi, z):
    return np.array([rho * np.cos(phi), rho * np.sin(phi), z + 0 * rho])


def _sph(rho, theta, phi, a=1.0, b=1.0, c=1.0, z0=0.0):
    return np.array([a * rho * np.sin(theta) * np.cos(phi), b * rho * np.sin(theta) * np.sin(phi),
                     z0 + c * rho * np.cos(theta)])


def _disc(z):
    return lambda rho, phi: _cyl(rho, phi, z + 0 * rho)


def box_regions(a, b, c, shell):
    if not shell:
        return [solid_region(lambda x, y, z: np.array([x, y, z]), [(-a / 2, a / 2), (-b / 2, b / 2), (-c / 2, c / 2)], 4)]
    out = []
    for s in (-1, 1):
        out.append(surface_patch(lambda y, z: np.array([s * a / 2 + 0 * y, y, z]), [(-b / 2, b / 2), (-c / 2, c / 2)], 4))
        out.append(surface_patch(lambda x, z: np.array([x, s * b / 2 + 0 * x, z]), [(-a / 2, a / 2), (-c / 2, c / 2)], 4))
        out.append(surface_patch(lambda x, y: np.array([x, y, s * c / 2 + 0 * x]), [(-a / 2, a / 2), (-b / 2, b / 2)], 4))
    return out


def ellipsoid_regions(a, b, c, shell, n=32):
    if not shell:
        return [solid_region(lambda r, t, f: _sph(r, t, f, a, b, c), [(0, 1), (0, PI), (0, 2 * PI)], 32)]
    return [surface_patch(lambda t, f: _sph(1.0, t, f, a, b, c), [(0, PI), (0, 2 * PI)], n)]


def cylinder_regions(r, h, shell, r_in=0.0):
    if not shell:
        return [solid_region(_cyl, [(r_in, r), (0, 2 * PI), (-h / 2, h / 2)])]
    out = [surface_patch(lambda f, z: _cyl(r + 0 * f, f, z), [(0, 2 * PI), (-h / 2, h / 2)])]
    if r_in > 0:
        out.append(surface_patch(lambda f, z: _cyl(r_in + 0 * f, f, z), [(0, 2 * PI), (-h / 2, h / 2)]))
    out += [surface_patch(_disc(z), [(r_in, r), (0, 2 * PI)]) for z in (-h / 2, h / 2)]
    return out


def cone_regions(r, h, shell):
    # base disc at z = 0, apex at z = h; radius at height z is r (1 - z / h)
    if not shell:
        return [solid_region(lambda s, f, z: _cyl(s * r * (1 - z / h), f, z), [(0, 1), (0, 2 * PI), (0, h)])]
    return [surface_patch(lambda f, z: _cyl(r * (1 - z / h) + 0 * f, f, z), [(0, 2 * PI), (0, h)]),
            surface_patch(_disc(0.0), [(0, r), (0, 2 * PI)])]


def capsule_regions(r, L, shell):
    out = []
    if L > 0:
        out += cylinder_regions(r, L, shell)[:1]  # solid, or the lateral surface only
    for s in (-1, 1):  # hemispheres centered at z = s L / 2, bulging outward
        th = (0, PI / 2) if s > 0 else (PI / 2, PI)
        if shell:
            out.append(surface_patch(lambda t, f: _sph(r, t, f, z0=s * L / 2), [th, (0, 2 * PI)], 32))
        else:
            out.append(solid_region(lambda q, t, f: _sph(q, t, f, z0=s * L / 2), [(0, r), th, (0, 2 * PI)], 32))
    return out


def torus_regions(R, a, shell):
    def solid(q, v, u):
        rho = R + q * np.cos(v)
        return np.array([rho * np.cos(u), rho * np.sin(u), q * np.sin(v)])
    if not shell:
        return [solid_region(solid, [(0, a), (0, 2 * PI), (0, 2 * PI)], 32)]
    return [surface_patch(lambda v, u: solid(a + 0 * v, v, u), [(0, 2 * PI), (0, 2 * PI)], 32)]


def tube_regions(r2, r1, h, shell):
    return cylinder_regions(r2, h, shell, r_in=r1)


def thick_sphere_regions(r2, r1):
    return [solid_region(_sph, [(r1, r2), (0, PI), (0, 2 * PI)], 32)]


CASES = [
    # id, primitive call (given density), regions
    ("box", lambda **k: box((0.3, 1.1, 2.0), **k), lambda sh: box_regions(0.3, 1.1, 2.0, sh)),
    ("sphere", lambda **k: sphere(0.7, **k), lambda sh: ellipsoid_regions(0.7, 0.7, 0.7, sh)),
    ("ellipsoid", lambda **k: ellipsoid((1.0, 0.7, 0.45), **k), lambda sh: ellipsoid_regions(1.0, 0.7, 0.45, sh, 96)),
    ("cylinder", lambda **k: cylinder(0.4, 1.3, **k), lambda sh: cylinder_regions(0.4, 1.3, sh)),
    ("cone", lambda **k: cone(0.5, 1.7, **k), lambda sh: cone_regions(0.5, 1.7, sh)),
    ("capsule", lambda **k: capsule(0.35, 0.9, **k), lambda sh: capsule_regions(0.35, 0.9, sh)),
    ("torus", lambda **k: torus(1.2, 0.3, **k), lambda sh: torus_regions(1.2, 0.3, sh)),
    ("tube", lambda **k: tube(0.5, 0.35, 0.8, **k), lambda sh: tube_regions(0.5, 0.35, 0.8, sh)),
]


# ============================================================================ 1. quadrature truth
@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
@pytest.mark.parametrize("name,make,regions", CASES, ids=[c[0] for c in CASES])
def test_matches_quadrature_over_geometry(name, make, regions, shell):
    rho = 2.7
    p = make(density=rho, kind=KIND[shell])
    mass, com, I = props_from_moments(sum(regions(shell)), rho)
    assert_matches(p, mass, com, I, rtol=1e-11)
    if shell:
        assert math.isnan(p.volume)
    else:
        assert p.volume == pytest.approx(mass / rho, rel=1e-12)


def test_thick_spherical_shell_matches_quadrature():
    rho = 1.3
    p = spherical_shell(0.9, 0.6, density=rho)
    mass, com, I = props_from_moments(sum(thick_sphere_regions(0.9, 0.6)), rho)
    assert_matches(p, mass, com, I, rtol=1e-12)
    assert p.volume == pytest.approx(mass / rho, rel=1e-13)


def test_solid_cone_com_and_frame():
    # base disc in z = 0, apex at z = +h, solid COM at h / 4 (stated frame)
    p = cone(0.5, 2.0, mass=1.0)
    np.testing.assert_allclose(p.com, [0, 0, 0.5], atol=1e-15)


def test_torus_solid_scipy_tplquad():
    """Adaptive scipy quadrature in cylindrical coordinates (rho, z, phi-integrated) of a solid torus."""
    R, a = 1.0, 0.4
    lo = lambda rho: -math.sqrt(max(a * a - (rho - R) ** 2, 0.0))  # noqa: E731
    hi = lambda rho: math.sqrt(max(a * a - (rho - R) ** 2, 0.0))  # noqa: E731
    opts = dict(epsabs=0, epsrel=1e-11)
    # volume and I_zz do not depend on phi (factor 2 pi); I_xx is a full triple integral
    vol = integrate.dblquad(lambda z, rho: 2 * PI * rho, R - a, R + a, lo, hi, **opts)[0]
    i_zz = integrate.dblquad(lambda z, rho: 2 * PI * rho * rho ** 2, R - a, R + a, lo, hi, **opts)[0]
    i_xx = integrate.tplquad(lambda phi, z, rho: rho * ((rho * math.sin(phi)) ** 2 + z * z),
                             R - a, R + a, lo, hi, 0, 2 * PI, **opts)[0]
    p = torus(R, a, density=1.0)
    assert p.mass == pytest.approx(vol, rel=1e-9)
    assert p.inertia_com[2, 2] == pytest.approx(i_zz, rel=1e-9)
    assert p.inertia_com[0, 0] == pytest.approx(i_xx, rel=1e-9)


@pytest.mark.parametrize("semi_axes", [(1.0, 0.1, 0.02), (0.05, 1.0, 0.3), (2.0, 2.0, 0.001), (0.01, 0.01, 1.0)])
def test_ellipsoid_shell_against_carlson_and_scipy(semi_axes):
    """Shell ellipsoid (numerical quadrature inside) vs Carlson R_G area and scipy dblquad moments.

    The reference uses a *different* parametrisation (polar axis z, whatever its length)
    and adaptive quadrature, so it shares no code path with the graded Gauss-Legendre rule.
    """
    a, b, c = semi_axes
    area_exact = 4 * PI * scipy.special.elliprg(b * b * c * c, a * a * c * c, a * a * b * b)

    def dA(t, f):
        st = math.sin(t)
        return st * math.sqrt((b * c * st * math.cos(f)) ** 2 + (a * c * st * math.sin(f)) ** 2
                              + (a * b * math.cos(t)) ** 2)

    def octant(g):
        return 8 * integrate.dblquad(lambda t, f: g(t, f) * dA(t, f), 0, PI / 2, 0, PI / 2,
                                     epsabs=0, epsrel=1e-12)[0]

    Sxx = octant(lambda t, f: (a * math.sin(t) * math.cos(f)) ** 2)
    Syy = octant(lambda t, f: (b * math.sin(t) * math.sin(f)) ** 2)
    Szz = octant(lambda t, f: (c * math.cos(t)) ** 2)
    p = ellipsoid(semi_axes, density=1.0, kind="shell")
    assert p.mass == pytest.approx(area_exact, rel=1e-13)
    expected = np.diag([Syy + Szz, Sxx + Szz, Sxx + Syy])
    np.testing.assert_allclose(p.inertia_com, expected, rtol=1e-10, atol=0)


# ============================================================================ 2. tessellations
def _mesh_props(mesh, shell, density=1.0):
    return mesh_properties(mesh.vertices, mesh.faces, density=density, kind=KIND[shell])


def _rel_error(p_mesh, p_exact):
    scale = np.abs(p_exact.inertia_com).max()
    length = math.sqrt(scale / p_exact.mass)
    return max(abs(p_mesh.mass / p_exact.mass - 1),
               np.abs(p_mesh.com - p_exact.com).max() / length,
               np.abs(p_mesh.inertia_com - p_exact.inertia_com).max() / scale)


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_box_mesh_is_exact(shell):
    size = (0.3, 1.1, 2.0)
    m = trimesh.creation.box(extents=size)
    exact = box(size, density=7.0, kind=KIND[shell])
    got = _mesh_props(m, shell, density=7.0)
    assert _rel_error(got, exact) < 1e-14


# Each family refines the tessellation 2x in edge length per step (sections doubled, or one
# icosphere subdivision); vertices lie on the exact surface, so errors are O(h^2).
def _icosphere(k, semi_axes):
    m = trimesh.creation.icosphere(subdivisions=k, radius=1.0)
    return trimesh.Trimesh(m.vertices * np.asarray(semi_axes), m.faces, process=False)


MESH_FAMILIES = [
    ("sphere", lambda sh: sphere(0.7, density=1.0, kind=KIND[sh]), lambda k: _icosphere(k, (0.7, 0.7, 0.7)), (3, 4, 5)),
    ("ellipsoid", lambda sh: ellipsoid((1.0, 0.7, 0.45), density=1.0, kind=KIND[sh]),
     lambda k: _icosphere(k, (1.0, 0.7, 0.45)), (3, 4, 5)),
    ("cylinder", lambda sh: cylinder(0.4, 1.3, density=1.0, kind=KIND[sh]),
     lambda n: trimesh.creation.cylinder(0.4, 1.3, sections=n), (64, 128, 256)),
    ("cone", lambda sh: cone(0.5, 1.7, density=1.0, kind=KIND[sh]),
     lambda n: trimesh.creation.cone(0.5, 1.7, sections=n), (64, 128, 256)),
    ("capsule", lambda sh: capsule(0.35, 0.9, density=1.0, kind=KIND[sh]),
     lambda n: trimesh.creation.capsule(height=0.9, radius=0.35, count=[n, n]), (32, 64, 128)),
    ("torus", lambda sh: torus(1.2, 0.3, density=1.0, kind=KIND[sh]),
     lambda n: trimesh.creation.torus(1.2, 0.3, major_sections=n, minor_sections=n), (32, 64, 128)),
    ("tube", lambda sh: tube(0.5, 0.35, 0.8, density=1.0, kind=KIND[sh]),
     lambda n: trimesh.creation.annulus(0.35, 0.5, 0.8, sections=n), (64, 128, 256)),
]


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
@pytest.mark.parametrize("name,exact,mesh,levels", MESH_FAMILIES, ids=[f[0] for f in MESH_FAMILIES])
def test_mesh_converges_second_order(name, exact, mesh, levels, shell):
    p_exact = exact(shell)
    meshes = [_mesh_props(mesh(k), shell) for k in levels]
    errors = [_rel_error(p, p_exact) for p in meshes]
    ratios = [errors[i] / errors[i + 1] for i in range(len(errors) - 1)]
    # second order: halving the edge length divides the error by ~4
    for r in ratios:
        assert 3.8 < r < 4.2, (errors, ratios)
    assert errors[-1] < 2e-3
    # Richardson extrapolation (4 fine - coarse) / 3 removes the h^2 term: the closed form
    # (or, for the ellipsoid shell, the numerical quadrature) must agree far better still.
    fine, coarse = meshes[-1], meshes[-2]
    scale = np.abs(p_exact.inertia_com).max()
    assert abs((4 * fine.mass - coarse.mass) / 3 / p_exact.mass - 1) < errors[-1] / 50
    extrap_I = (4 * fine.inertia_com - coarse.inertia_com) / 3
    assert np.abs(extrap_I - p_exact.inertia_com).max() / scale < errors[-1] / 50


# ============================================================================ 3. limits and relations
@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_sphere_is_round_ellipsoid(shell):
    assert ellipsoid((0.8, 0.8, 0.8), mass=3.0, kind=KIND[shell]).isclose(sphere(0.8, mass=3.0, kind=KIND[shell]), rtol=1e-14)
    assert ellipsoid((0.8, 0.8, 0.8), density=3.0, kind=KIND[shell]).isclose(sphere(0.8, density=3.0, kind=KIND[shell]),
                                                                        rtol=1e-13)


def test_ellipsoid_shell_axis_order_irrelevant():
    p = ellipsoid((0.2, 1.5, 0.7), mass=1.0, kind="shell")
    q = ellipsoid((1.5, 0.7, 0.2), mass=1.0, kind="shell")
    np.testing.assert_allclose(np.diag(p.inertia_com), np.diag(q.inertia_com)[[2, 0, 1]], rtol=1e-14)


def test_ellipsoid_shell_flat_limit_is_two_sided_elliptic_disc():
    # c -> 0: two elliptic discs, area 2 pi a b, I_xx = m b^2 / 4, I_yy = m a^2 / 4
    a, b = 1.3, 0.6
    p = ellipsoid((a, b, 1e-7), density=1.0, kind="shell")
    assert p.mass == pytest.approx(2 * PI * a * b, rel=1e-6)
    np.testing.assert_allclose(np.diag(p.inertia_com) / p.mass, [b * b / 4, a * a / 4, (a * a + b * b) / 4], rtol=1e-6)


def test_ellipsoid_shell_extreme_aspect_ratios_stay_accurate():
    # far beyond where the grading stops (aspect 1e-20): still a two-sided disc, to rounding
    p = ellipsoid((1.0, 0.5, 1e-20), density=1.0, kind="shell")
    assert p.mass == pytest.approx(2 * PI * 0.5, rel=1e-13)
    np.testing.assert_allclose(np.diag(p.inertia_com) / p.mass, [0.0625, 0.25, 0.3125], rtol=1e-13)
    # size-independent: a huge and a tiny ellipsoid give the same properties per unit mass
    big = ellipsoid((3e100, 2e100, 1e100), mass=1.0, kind="shell")
    small = ellipsoid((3e-100, 2e-100, 1e-100), mass=1.0, kind="shell")
    np.testing.assert_allclose(big.inertia_com * 1e-200, small.inertia_com * 1e200, rtol=1e-14)


def test_ellipsoid_shell_needle_limit():
    # a = b -> 0: mass per unit length ~ sqrt(1 - z^2/c^2) (semicircle law), so <z^2> = c^2 / 4
    c = 2.0
    p = ellipsoid((1e-5, 1e-5, c), mass=1.0, kind="shell")
    assert p.inertia_com[0, 0] == pytest.approx(c * c / 4, rel=1e-6)


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_tube_with_tiny_bore_tends_to_cylinder(shell):
    cyl = cylinder(0.5, 1.2, density=1.0, kind=KIND[shell])
    errs = [_rel_error(tube(0.5, eps, 1.2, density=1.0, kind=KIND[shell]), cyl) for eps in (1e-2, 1e-3, 1e-4)]
    assert errs[-1] < (1e-3 if shell else 1e-7)
    assert errs[0] > errs[1] > errs[2]


def test_tube_is_cylinder_minus_core():
    rho = 3.0
    outer, core = cylinder(0.5, 1.2, density=rho), cylinder(0.2, 1.2, density=rho)
    t = tube(0.5, 0.2, 1.2, density=rho)
    assert t.mass == pytest.approx(outer.mass - core.mass, rel=1e-14)
    np.testing.assert_allclose(t.inertia_com, outer.inertia_com - core.inertia_com, rtol=1e-14, atol=1e-15)


def test_thick_spherical_shell_is_ball_minus_cavity():
    rho = 3.0
    outer, core = sphere(0.9, density=rho), sphere(0.6, density=rho)
    s = spherical_shell(0.9, 0.6, density=rho)
    assert s.mass == pytest.approx(outer.mass - core.mass, rel=1e-14)
    np.testing.assert_allclose(s.inertia_com, outer.inertia_com - core.inertia_com, rtol=1e-13, atol=1e-15)


def test_thick_spherical_shell_tends_to_thin_shell_per_unit_mass():
    thin = spherical_shell(1.0, mass=1.0)
    assert thin.isclose(sphere(1.0, mass=1.0, kind="shell"), rtol=0)
    errs = [abs(spherical_shell(1.0, 1.0 - eps, mass=1.0).inertia_com[0, 0] - thin.inertia_com[0, 0])
            for eps in (1e-2, 1e-4, 1e-6, 1e-10)]
    # I/m = 2/3 r^2 (1 - eps + O(eps^2)): error linear in the thickness, no cancellation at tiny eps
    np.testing.assert_allclose(errs, 2 / 3 * np.array([1e-2, 1e-4, 1e-6, 1e-10]), rtol=2e-2)
    assert spherical_shell(1.0, 1.0 - 1e-12, density=1.0).mass == pytest.approx(4 * PI * 1e-12, rel=1e-3)


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_capsule_of_zero_length_is_sphere(shell):
    assert capsule(0.6, 0, mass=2.0, kind=KIND[shell]).isclose(sphere(0.6, mass=2.0, kind=KIND[shell]), rtol=1e-14)
    assert capsule(0.6, 0.0, density=2.0, kind=KIND[shell]).isclose(sphere(0.6, density=2.0, kind=KIND[shell]), rtol=1e-14)


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_long_capsule_tends_to_cylinder_per_unit_mass(shell):
    # I_xx / (m L^2) -> 1/12 as L / r -> infinity (both ends are negligible)
    r = 0.01
    p = capsule(r, 100.0, mass=1.0, kind=KIND[shell])
    assert p.inertia_com[0, 0] / 100.0 ** 2 == pytest.approx(1 / 12, rel=1e-3)


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_thin_torus_is_a_hoop(shell):
    # minor -> 0: hoop of radius R, I_zz = m R^2, I_xx = I_yy = m R^2 / 2
    p = torus(1.5, 1e-5, mass=2.0, kind=KIND[shell])
    np.testing.assert_allclose(np.diag(p.inertia_com), 2.0 * 1.5 ** 2 * np.array([0.5, 0.5, 1.0]), rtol=1e-9)


@pytest.mark.parametrize("shell,z2", [(False, 0.25), (True, 0.5)], ids=["solid", "shell"])
def test_torus_perpendicular_axis_relation(shell, z2):
    # For any body I_xx + I_yy - I_zz = 2 int z^2 dm.  The torus is a surface/solid of revolution
    # of a disc/circle of radius a, so int z^2 dm / m is the cross-section's <z^2>: a^2/4 (disc), a^2/2 (circle).
    R, a = 1.0, 0.7
    p = torus(R, a, mass=1.0, kind=KIND[shell])
    I = np.diag(p.inertia_com)
    assert I[0] + I[1] - I[2] == pytest.approx(2 * z2 * a * a, rel=1e-14)


def test_horn_torus_is_allowed():
    assert torus(1.0, 1.0, mass=1.0).check() == []


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
def test_flat_cylinder_is_disc_and_thin_cylinder_is_rod(shell):
    disc = cylinder(0.5, 1e-9, mass=1.0, kind=KIND[shell])
    np.testing.assert_allclose(np.diag(disc.inertia_com), [0.25 * 0.25, 0.25 * 0.25, 0.5 * 0.25], rtol=1e-8)
    rod = cylinder(1e-4, 2.0, mass=1.0, kind=KIND[shell])
    # the end caps of the shell shift <z^2> by a relative O(r / h) = 5e-5
    assert rod.inertia_com[0, 0] == pytest.approx(4.0 / 12.0, rel=2e-4 if shell else 1e-6)


def test_flat_box_shell_is_two_sided_plate():
    p = box((1.0, 2.0, 1e-9), mass=1.0, kind="shell")
    np.testing.assert_allclose(np.diag(p.inertia_com), [4 / 12, 1 / 12, 5 / 12], rtol=1e-8)


def test_needle_cone_shell_limit():
    # r -> 0: lateral mass per unit length grows linearly from the apex: <(z - zc)^2> = h^2 / 18
    p = cone(1e-5, 3.0, mass=1.0, kind="shell")
    assert p.inertia_com[0, 0] == pytest.approx(9.0 / 18.0, rel=2e-5)
    assert p.com[2] == pytest.approx(1.0, rel=2e-5)  # a third of the height above the base


ALL_CALLS = [
    ("box", lambda **k: box([0.3, 1, 2], **k)),
    ("sphere", lambda **k: sphere(1, **k)),
    ("ellipsoid", lambda **k: ellipsoid([1, 2, 3], **k)),
    ("cylinder", lambda **k: cylinder(1, 2, **k)),
    ("cone", lambda **k: cone(1, 2, **k)),
    ("capsule", lambda **k: capsule(1, 2, **k)),
    ("torus", lambda **k: torus(2, 1, **k)),
    ("tube", lambda **k: tube(2, 1, 3, **k)),
]


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
@pytest.mark.parametrize("name,make", ALL_CALLS, ids=[c[0] for c in ALL_CALLS])
def test_mass_and_density_agree_and_scale(name, make, shell):
    by_density = make(density=2.5, kind=KIND[shell])
    by_mass = make(mass=by_density.mass, kind=KIND[shell])
    assert by_mass.isclose(by_density, rtol=1e-14)
    assert by_density.frame == "body" and make(mass=1, kind=KIND[shell], frame="B").frame == "B"
    # at fixed mass, the inertia is linear in mass
    np.testing.assert_allclose(make(mass=4.0, kind=KIND[shell]).inertia_com, 4 * make(mass=1.0, kind=KIND[shell]).inertia_com,
                               rtol=1e-14, atol=0)


def test_spherical_shell_mass_and_density_agree():
    d = spherical_shell(1.0, 0.5, density=2.0)
    assert spherical_shell(1.0, 0.5, mass=d.mass).isclose(d, rtol=1e-14)


def test_integer_and_float_inputs_agree():
    assert box((1, 2, 3), mass=6).isclose(box(np.array([1.0, 2.0, 3.0]), mass=6.0), rtol=0)
    assert cylinder(np.float32(0.5), 2, mass=1).isclose(cylinder(0.5, 2.0, mass=1.0), rtol=0)


def test_scaling_law():
    # lengths x lam at fixed mass: inertia x lam^2 (every primitive, incl. the numerical ellipsoid shell)
    lam = 3.0
    p = ellipsoid((1.0, 0.5, 0.2), mass=1.0, kind="shell")
    q = ellipsoid((lam, lam * 0.5, lam * 0.2), mass=1.0, kind="shell")
    np.testing.assert_allclose(q.inertia_com, lam ** 2 * p.inertia_com, rtol=1e-13, atol=0)


# ============================================================================ 4. bad input
BAD = [
    (lambda: box((1, 0, 1), mass=1), r"box: size\[1\] must be finite and positive, got 0\.0"),
    (lambda: box((1, -2, 1), mass=1), r"box: size\[1\] must be finite and positive, got -2\.0"),
    (lambda: box((1, math.nan, 1), mass=1), r"box: size holds a non-finite value \(nan\)"),
    (lambda: box((1, 2), mass=1), r"box: size must have shape \(3,?\), got \(2,\)"),
    (lambda: box(1.0, mass=1), r"box: size must have shape \(3,?\), got \(\)"),
    (lambda: sphere(0, mass=1), r"sphere: radius must be finite and positive, got 0\.0"),
    (lambda: sphere(-1, mass=1), r"sphere: radius must be finite and positive, got -1\.0"),
    (lambda: sphere(math.nan, mass=1), r"sphere: radius must be finite and positive, got nan"),
    (lambda: sphere(math.inf, mass=1), r"sphere: radius must be finite and positive, got inf"),
    (lambda: sphere("big", mass=1), r"sphere: radius must be a number, got 'big'"),
    (lambda: ellipsoid((1, 1, -1), mass=1, kind="shell"), r"ellipsoid: semi_axes\[2\] must be finite and positive, got -1\.0"),
    (lambda: cylinder(1, 0, mass=1), r"cylinder: height must be finite and positive, got 0\.0"),
    (lambda: cylinder(-1, 1, mass=1), r"cylinder: radius must be finite and positive, got -1\.0"),
    (lambda: cone(1, math.nan, mass=1), r"cone: height must be finite and positive, got nan"),
    (lambda: capsule(0, 1, mass=1), r"capsule: radius must be finite and positive, got 0\.0"),
    (lambda: capsule(1, -1, mass=1), r"capsule: length must be finite and non-negative, got -1\.0"),
    (lambda: torus(1, 0, mass=1), r"torus: minor_radius must be finite and positive, got 0\.0"),
    (lambda: torus(-1, 0.5, mass=1), r"torus: major_radius must be finite and positive, got -1\.0"),
    (lambda: torus(1, 1.5, mass=1),
     r"torus: minor_radius must not exceed major_radius .*got minor_radius = 1\.5 m > major_radius = 1\.0 m"),
    (lambda: tube(1, 1, 1, mass=1),
     r"tube: inner_radius must be smaller than outer_radius, got inner_radius = 1\.0 m >= outer_radius = 1\.0 m"),
    (lambda: tube(1, 2, 1, mass=1), r"tube: inner_radius must be smaller than outer_radius, got inner_radius = 2\.0"),
    (lambda: tube(1, 0, 1, mass=1), r"tube: inner_radius must be finite and positive, got 0\.0"),
    (lambda: tube(1, 0.5, -1, mass=1), r"tube: height must be finite and positive, got -1\.0"),
    (lambda: spherical_shell(1, 1, mass=1),
     r"spherical_shell: inner_radius must be smaller than outer_radius, got inner_radius = 1\.0 m >= "
     r"outer_radius = 1\.0 m \(for a thin shell leave inner_radius=None\)"),
    (lambda: spherical_shell(1, 2, mass=1), r"spherical_shell: inner_radius must be smaller than outer_radius"),
    (lambda: spherical_shell(0, mass=1), r"spherical_shell: outer_radius must be finite and positive, got 0\.0"),
    (lambda: spherical_shell(1, -0.5, mass=1), r"spherical_shell: inner_radius must be finite and positive, got -0\.5"),
    (lambda: sphere(1), r"sphere: give exactly one of density= or mass=, got neither"),
    (lambda: sphere(1, mass=1, density=1), r"sphere: give exactly one of density= or mass=, got both"),
    (lambda: cylinder(1, 1, kind="shell"), r"cylinder shell: give exactly one of density= or mass=, got neither"),
    (lambda: sphere(1, mass=-1), r"mass must be finite and positive, got -1\.0"),
    (lambda: sphere(1, mass=0), r"mass must be finite and positive, got 0\.0"),
    (lambda: sphere(1, density=math.nan), r"density must be finite and positive, got nan"),
    (lambda: sphere(1, mass=1, kind="hollow"), r"sphere: kind must be 'solid' or 'shell', got 'hollow'"),
    (lambda: sphere(1, mass=1, kind=True), r"sphere: kind must be 'solid' or 'shell', got True"),
    (lambda: sphere(1e200, density=1), r"sphere: volume must be positive and finite, got inf"),
    (lambda: sphere(1e-120, mass=1), r"sphere: volume must be positive and finite, got 0\.0"),
    (lambda: ellipsoid((1e150, 1e150, 1e149), density=1, kind="shell"),
     r"ellipsoid shell: the inertia is out of float64 range"),
]


@pytest.mark.parametrize("call,message", BAD, ids=[f"bad{i}" for i in range(len(BAD))])
def test_bad_input_names_the_parameter(call, message):
    with pytest.raises(InputError, match=message):
        call()


def test_errors_are_inertia_errors():
    with pytest.raises(inertia.InertiaError):
        box((1, 1, 0), mass=1)
    with pytest.raises(ValueError):
        torus(1, 2, mass=1)


def test_positional_mass_is_refused():
    with pytest.raises(TypeError):
        sphere(1.0, 2.0)


# ============================================================================ 5. physical
PHYSICAL = ALL_CALLS + [
    ("flat_box", lambda **k: box((1, 1, 1e-6), **k)),
    ("needle_ellipsoid", lambda **k: ellipsoid((1e-3, 1e-3, 1), **k)),
    ("pancake_ellipsoid", lambda **k: ellipsoid((1, 1, 1e-4), **k)),
    ("flat_cone", lambda **k: cone(1, 1e-4, **k)),
    ("thin_tube", lambda **k: tube(1, 0.999, 10, **k)),
    ("horn_torus", lambda **k: torus(1, 1, **k)),
    ("zero_capsule", lambda **k: capsule(1, 0, **k)),
]


@pytest.mark.parametrize("shell", [False, True], ids=["solid", "shell"])
@pytest.mark.parametrize("name,make", PHYSICAL, ids=[c[0] for c in PHYSICAL])
def test_every_primitive_is_physical(name, make, shell):
    p = make(mass=1.7, kind=KIND[shell])
    assert p.check() == []
    moments = p.principal().moments
    assert np.all(moments > 0)
    assert moments[0] + moments[1] >= moments[2] * (1 - 1e-12)
    assert np.all(np.isfinite(p.com)) and p.inertia_com.shape == (3, 3)
    np.testing.assert_array_equal(p.inertia_com, p.inertia_com.T)


@pytest.mark.parametrize("inner", [None, 0.2, 0.99])
def test_spherical_shell_is_physical(inner):
    p = spherical_shell(1.0, inner, mass=1.0)
    assert p.check() == []
    assert math.isnan(p.volume) == (inner is None)


def test_exported_from_package():
    for name in ("box", "sphere", "ellipsoid", "cylinder", "cone", "capsule", "torus", "tube", "spherical_shell"):
        assert callable(getattr(inertia, name))
