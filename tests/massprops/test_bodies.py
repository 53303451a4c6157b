"""Ready-made bodies: the T-handle's exact mass properties and its display mesh."""

from __future__ import annotations

import numpy as np
import pytest

from inertia.massprops.bodies import STEEL_DENSITY, t_handle
from inertia.massprops.mesh import mesh_properties


def _t_handle_closed_form(r1, l1, r2, l2, rho):
    """Two cylinders on the y axis, by hand: masses, COM, and the parallel-axis theorem."""
    m1, m2 = rho * np.pi * r1**2 * l1, rho * np.pi * r2**2 * l2
    c2 = r1 + l2 / 2                       # stem centre on +y
    M = m1 + m2
    yc = m2 * c2 / M
    d1, d2 = yc, c2 - yc                   # distances of the part centres from the COM (along y)
    Ixx = m1 * r1**2 / 2 + m1 * d1**2 + m2 * (3 * r2**2 + l2**2) / 12 + m2 * d2**2
    Iyy = m1 * (3 * r1**2 + l1**2) / 12 + m2 * r2**2 / 2
    Izz = m1 * (3 * r1**2 + l1**2) / 12 + m1 * d1**2 + m2 * (3 * r2**2 + l2**2) / 12 + m2 * d2**2
    return M, np.array([0.0, yc, 0.0]), np.diag([Ixx, Iyy, Izz])


@pytest.mark.parametrize("dims", [(0.006, 0.08, 0.005, 0.05, STEEL_DENSITY), (0.01, 0.3, 0.002, 0.1, 2700.0)])
def test_t_handle_equals_the_closed_form(dims):
    r1, l1, r2, l2, rho = dims
    body = t_handle(bar_radius=r1, bar_length=l1, stem_radius=r2, stem_length=l2, density=rho)
    M, com, I = _t_handle_closed_form(*dims)
    assert body.props.mass == pytest.approx(M, rel=1e-14)
    np.testing.assert_allclose(body.props.com, com, rtol=1e-14, atol=1e-18)
    np.testing.assert_allclose(body.props.inertia_com, I, rtol=1e-13, atol=1e-13 * I.max())


def test_default_t_handle_flips_well_separated_moments():
    moments = t_handle().props.principal().moments
    assert moments[0] < 0.8 * moments[1] and moments[1] < 0.8 * moments[2]   # a clear intermediate axis


def test_display_mesh_converges_to_the_exact_properties_as_O_1_over_n2():
    body = t_handle()
    errors = []
    for sides in (16, 32, 64, 128):
        v, f = body.display_mesh(sides=sides)
        p = mesh_properties(v, f, density=STEEL_DENSITY)     # closed and outward, or this raises
        errors.append(abs(p.mass / body.props.mass - 1))
        np.testing.assert_allclose(p.com, body.props.com, atol=body.props.com[1] * 4 * errors[-1] + 1e-15)
        rel_I = np.abs(p.inertia_com - body.props.inertia_com).max() / body.props.inertia_com.max()
        assert rel_I < 3 * errors[-1]
    # polygon area n/2 r^2 sin(2 pi/n) vs pi r^2: the error falls 4x per doubling
    ratios = [errors[k] / errors[k + 1] for k in range(3)]
    assert all(3.9 < r < 4.1 for r in ratios), ratios
    assert errors[-1] < 5e-4
