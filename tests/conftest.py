"""Shared test fixtures: the two tiers of mesh and robot inputs, and random physical bodies.

Inputs come in two tiers.  The "made" tier is written by the tests themselves
(``tests/_make.py``): a plain clone with nothing beside it runs it in full.  The "real" tier
(tests marked ``realdata``) reads the curated public files of ``../shared/data`` beside the
checkout (override the location with ``INERTIA_SHARED_DATA``: the ``shared`` folder or its
``data`` folder).  Without them the real tier skips with one line; with
``INERTIA_REQUIRE_REALDATA=1`` it fails instead.
"""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest

from tests import _make

REPO = Path(__file__).resolve().parents[1]

REALDATA_SKIP = "../shared/data not found: real-data tier skipped"


def _shared_data_dir() -> Path:
    env = os.environ.get("INERTIA_SHARED_DATA")
    base = Path(env).expanduser() if env else REPO.parent / "shared"
    return (base / "data" if (base / "data").is_dir() else base).resolve()


SHARED_DATA = _shared_data_dir()


def _shared_data_present() -> bool:
    return (SHARED_DATA / "meshes").is_dir() and (SHARED_DATA / "robots").is_dir()


def _require_shared_data() -> Path:
    if not _shared_data_present():
        if os.environ.get("INERTIA_REQUIRE_REALDATA") == "1":
            pytest.fail(f"INERTIA_REQUIRE_REALDATA=1 but the real-data tier has no data: {SHARED_DATA} "
                        "(../shared/data, or INERTIA_SHARED_DATA) is missing", pytrace=False)
        pytest.skip(REALDATA_SKIP)  # one location, so `-rs` reports the whole tier as one line
    return SHARED_DATA


def pytest_collection_modifyitems(config, items):
    for item in items:
        if "shared_data" in getattr(item, "fixturenames", ()):
            item.add_marker(pytest.mark.realdata)


def pytest_runtest_setup(item):
    if item.get_closest_marker("realdata") is not None:
        _require_shared_data()


@pytest.fixture(scope="session")
def shared_data() -> Path:
    """``../shared/data`` (real-data tier only: the test is marked ``realdata``)."""
    return _require_shared_data()


TIERS = ["made", pytest.param("real", marks=pytest.mark.realdata)]


@pytest.fixture(scope="session", params=TIERS)
def meshes(request, tmp_path_factory) -> _make.MeshSet:
    """The test meshes: written here ("made") or ``../shared/data/meshes`` ("real")."""
    if request.param == "real":
        meshes = _make.real_mesh_set(_require_shared_data() / "meshes")
        # the real set's OFF, PLY and glTF files are read through trimesh (extra inertia[mesh])
        pytest.importorskip("trimesh", reason="the real meshes are read with trimesh (extra inertia[mesh])")
        return meshes
    pytest.importorskip("trimesh", reason="the made meshes are written with trimesh (extra inertia[mesh])")
    return _make.make_mesh_set(tmp_path_factory.mktemp("meshes"))


@pytest.fixture(scope="session", params=TIERS)
def robots(request, tmp_path_factory) -> _make.RobotSet:
    """The test robot files: written here ("made") or ``../shared/data/robots`` ("real")."""
    if request.param == "real":
        return _make.real_robot_set(_require_shared_data() / "robots")
    pytest.importorskip("trimesh", reason="the made robot meshes are written with trimesh (extra inertia[mesh])")
    return _make.make_robot_set(tmp_path_factory.mktemp("robots"))


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
