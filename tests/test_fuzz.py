"""Fuzzing the readers: mutated mesh and robot files give a result or one of our errors.

Seeds are small valid files written by ``tests.fuzzing``; hypothesis draws the mutations
(edge-value numbers, deleted/duplicated/swapped lines, dropped attributes, byte flips,
truncation).  Only :class:`inertia.errors.InertiaError` may escape, and a returned result
holds finite numbers.  ``bench/fuzz.py`` runs the same mutators over 1e5 inputs in worker
processes (so a crash is counted, not fatal), with special paths (tests/test_input_paths.py)
and failing outputs (tests/cli/test_output_faults.py).
"""

from __future__ import annotations

import random
import warnings

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from inertia.errors import InertiaError  # noqa: E402
from tests.fuzzing import MESH_SEEDS, ROBOT_SEEDS, mutate_any, seed_ply_binary, seed_stl_binary  # noqa: E402

_MESH = [(ext, f()) for ext, f in MESH_SEEDS.items()] + [(".stl", seed_stl_binary()), (".ply", seed_ply_binary())]
_ROBOT = list(ROBOT_SEEDS.items())
_SETTINGS = settings(max_examples=150, deadline=None, derandomize=True,
                     suppress_health_check=[HealthCheck.function_scoped_fixture, HealthCheck.too_slow])


def _mutated(seed_list, pick, seed):
    ext, data = seed_list[pick % len(seed_list)]
    return ext, mutate_any(data, random.Random(seed))


@_SETTINGS
@given(pick=st.integers(0, 10_000), seed=st.integers(0, 2**32 - 1))
def test_mutated_mesh_files_give_numbers_or_our_errors(tmp_path_factory, pick, seed):
    import inertia

    ext, data = _mutated(_MESH, pick, seed)
    path = tmp_path_factory.mktemp("mesh") / f"fuzz{ext}"
    path.write_bytes(data)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)     # a leaked NumPy warning is a bug too
        try:
            p = inertia.mesh_file_properties(path, density=1.0)
        except InertiaError:
            return
    assert np.isfinite(p.mass) and p.mass > 0
    assert np.all(np.isfinite(p.com)) and np.all(np.isfinite(p.inertia_com))


@_SETTINGS
@given(pick=st.integers(0, 10_000), seed=st.integers(0, 2**32 - 1))
def test_mutated_robot_files_give_a_report_or_our_errors(tmp_path_factory, pick, seed):
    from inertia.robots import check_model, read_robot

    ext, data = _mutated(_ROBOT, pick, seed)
    path = tmp_path_factory.mktemp("robot") / f"fuzz{ext}"
    path.write_bytes(data)
    with warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        try:
            check_model(read_robot(path))
        except InertiaError:
            return
