"""Magnitudes beyond double precision's reach are refused by name, never read as physics."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import inertia
from inertia._core.tolerances import REPRESENTABLE_MAX, REPRESENTABLE_MIN
from inertia.errors import InvalidInertiaError
from inertia.massprops.validity import check_inertia


@pytest.mark.parametrize("inertia_com", [
    [[1, 1e308, 0], [1e308, 1, 0], [0, 0, 1]],          # overflowed in 0.5 (I + I^T): moments were NaN
    [[1e200, 0, 0], [0, 1e200, 0], [0, 0, 1e200]],       # eigensolver squares overflow
    [[1e-200, 0, 0], [0, 1e-200, 0], [0, 0, 1e-200]],    # squares underflow: a "body at rest" downstream
])
def test_unrepresentable_tensors_are_refused_with_the_limit(inertia_com):
    with warnings.catch_warnings():
        warnings.simplefilter("error")                   # no overflow warning on the way
        codes = [v.code for v in check_inertia(inertia_com, 1.0)]
        with pytest.raises(InvalidInertiaError, match=r"outside the range the library computes with \[1e-150, 1e\+150\]"):
            inertia.MassProperties(1.0, [0, 0, 0], inertia_com)
    assert codes == ["not_representable"]


@pytest.mark.parametrize("mass", [1e-200, 1e200])
def test_unrepresentable_mass_is_refused(mass):
    assert "not_representable" in [v.code for v in check_inertia(np.eye(3), mass)]


@pytest.mark.parametrize("scale", [REPRESENTABLE_MIN * 10, 1e-30, 1.0, 1e30, REPRESENTABLE_MAX / 10])
def test_checks_are_scale_invariant_inside_the_range(scale):
    # the same body at every scale inside the range: same verdicts, moments scale exactly
    valid = np.array([[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]])
    flat = np.diag([1.0, 1.0, 2.0])                     # a plate: on the triangle inequality, valid
    bad = np.diag([1.0, 1.0, 3.0])                      # fails the triangle inequality
    assert check_inertia(valid * scale, 1.0) == []
    assert check_inertia(flat * scale, 1.0) == []
    assert [v.code for v in check_inertia(bad * scale, 1.0)] == ["triangle_inequality"]
    ref = np.linalg.eigvalsh(valid)
    moments, _ = inertia.MassProperties(1.0, [0, 0, 0], valid * scale).principal()
    assert np.allclose(moments / scale, ref, rtol=1e-13)
