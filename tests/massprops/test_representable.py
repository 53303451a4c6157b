"""Tensors at the edges of double precision are judged right, never read as physics by overflow."""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import inertia
from inertia.errors import InvalidInertiaError
from inertia.massprops.validity import check_inertia


def test_huge_products_are_judged_not_overflowed():
    # 0.5 (I + I^T) overflowed to inf and the moments came back NaN: accepted.  Now the
    # moments are +-1e308 (exact: eigenvalues 1 +- 1e308, 1): not positive definite.
    I = [[1, 1e308, 0], [1e308, 1, 0], [0, 0, 1]]
    with warnings.catch_warnings():
        warnings.simplefilter("error")                   # no overflow warning on the way
        found = check_inertia(I, 1.0)
        with pytest.raises(InvalidInertiaError, match=r"not positive definite: principal moments \(-1e\+308, 1, 1e\+308\)"):
            inertia.MassProperties(1.0, [0, 0, 0], I)
    assert "not_positive_definite" in [v.code for v in found]


@pytest.mark.parametrize("scale", [1e-300, 1e-200, 1e-30, 1.0, 1e30, 1e200, 1e300])
def test_checks_are_scale_invariant(scale):
    # the same bodies at every scale: same verdicts, moments scale exactly
    valid = np.array([[2.0, -0.3, 0.1], [-0.3, 3.0, 0.2], [0.1, 0.2, 4.0]])
    flat = np.diag([1.0, 1.0, 2.0])                     # a plate: on the triangle inequality, valid
    bad = np.diag([1.0, 1.0, 3.0])                      # fails the triangle inequality
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert check_inertia(valid * scale, 1.0) == []
        assert check_inertia(flat * scale, 1.0) == []
        assert [v.code for v in check_inertia(bad * scale, 1.0)] == ["triangle_inequality"]
