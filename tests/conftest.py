"""Shared test fixtures: paths to ../shared data and random physical bodies."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

REPO = Path(__file__).resolve().parents[1]
SHARED_DATA = (REPO / ".." / "shared" / "data").resolve()


@pytest.fixture(scope="session")
def shared_data() -> Path:
    if not SHARED_DATA.is_dir():
        pytest.skip(f"shared data not found at {SHARED_DATA}")
    return SHARED_DATA


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """Uniform random proper rotation (QR of a Gaussian matrix with sign fix)."""
    Q, R = np.linalg.qr(rng.normal(size=(3, 3)))
    Q = Q * np.sign(np.diag(R))
    if np.linalg.det(Q) < 0:
        Q[:, 0] = -Q[:, 0]
    return Q


def random_point_cloud(rng: np.random.Generator, n: int = 7):
    """Random positive masses and positions: always a physical body (n >= 4 non-coplanar a.s.)."""
    return rng.uniform(0.1, 2.0, size=n), rng.normal(size=(n, 3)) * rng.uniform(0.1, 3.0, size=3)
