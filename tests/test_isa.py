"""The variants of the hot kernels (the rollout loops; the clean-solid pass and the mesh sums),
compiled for x86-64, x86-64-v3 and x86-64-v4 in a portable build and chosen by cpuid at the first
call (src/ext/dispatch.cpp), give the same bits: every one this CPU runs is forced in turn through
the private hooks of ``inertia._ext`` and the results compared bit for bit.  A native build holds
one variant, "native", and only that is checked.  And the module holds no fused multiply-add, so
a native build gives a portable build's bits too."""

from __future__ import annotations

import platform
import re
import shutil
import subprocess

import numpy as np
import pytest

import inertia
from inertia import _ext
from inertia.dynamics import RigidBody
from inertia.dynamics.integrators import METHODS
from inertia.dynamics.rollouts import rollout
from tests.dynamics.test_rollout import G, _batch

VARIANTS = _ext._isas()                 # name -> whether this CPU runs it, lowest first
RUNS = [name for name, ok in VARIANTS.items() if ok]


@pytest.fixture
def restore_isa():
    before = _ext._isa()
    yield
    _ext._force_isa(before)


def test_the_hooks_name_the_variant_in_use_and_refuse_what_the_cpu_or_build_lacks(restore_isa):
    if "native" in VARIANTS:                              # a build tuned for its machine: no dispatch
        assert _ext._isa() == "native" and VARIANTS == {"native": True}
        return
    assert _ext._isa() == RUNS[-1]                        # the highest this CPU runs
    assert RUNS[0] == next(iter(VARIANTS))                # the build's own level always runs
    for name, ok in VARIANTS.items():
        if ok:
            _ext._force_isa(name)
            assert _ext._isa() == name
        else:
            with pytest.raises(RuntimeError, match=f"^this CPU lacks the instructions of the {name} kernels"):
                _ext._force_isa(name)
    with pytest.raises(ValueError, match=r"^no kernels named 'x86-64-v9' in this build; it holds: "):
        _ext._force_isa("x86-64-v9")


# ------------------------------------------------------------------------------ inputs
def uv_sphere(n_lat=30, n_lon=40, r=1.3):
    """A closed UV sphere: its poles have n_lon faces around (more than 24: the sorted matching)."""
    theta = np.linspace(0.0, np.pi, n_lat + 1)[1:-1]
    phi = np.linspace(0.0, 2 * np.pi, n_lon, endpoint=False)
    t, p = np.meshgrid(theta, phi, indexing="ij")
    ring = np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], -1).reshape(-1, 3)
    v = r * np.vstack([[0.0, 0.0, 1.0], ring, [0.0, 0.0, -1.0]]) + [0.3, -0.2, 0.1]
    south = len(v) - 1
    idx = lambda i, j: 1 + i * n_lon + j % n_lon  # noqa: E731
    f = [[0, idx(0, j), idx(0, j + 1)] for j in range(n_lon)]
    for i in range(n_lat - 2):
        for j in range(n_lon):
            f += [[idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)], [idx(i, j), idx(i + 1, j + 1), idx(i, j + 1)]]
    f += [[south, idx(n_lat - 2, j + 1), idx(n_lat - 2, j)] for j in range(n_lon)]
    return v, np.array(f, dtype=np.int64)


def torus(n_major, n_minor, R=1.0, r=0.3):
    """A closed torus (not star-shaped: the union-find path of the clean-solid pass)."""
    u, w = np.meshgrid(np.linspace(0, 2 * np.pi, n_major, endpoint=False),
                       np.linspace(0, 2 * np.pi, n_minor, endpoint=False), indexing="ij")
    v = np.stack([(R + r * np.cos(w)) * np.cos(u), (R + r * np.cos(w)) * np.sin(u), r * np.sin(w)], -1).reshape(-1, 3)
    i, j = np.meshgrid(np.arange(n_major), np.arange(n_minor), indexing="ij")
    a, b = i * n_minor + j, ((i + 1) % n_major) * n_minor + j
    c, d = ((i + 1) % n_major) * n_minor + (j + 1) % n_minor, i * n_minor + (j + 1) % n_minor
    f = np.concatenate([np.stack([a, b, c], -1).reshape(-1, 3), np.stack([a, c, d], -1).reshape(-1, 3)])
    return v * [1.0, 0.8, 1.1] + [0.1, 0.2, -0.3], f.astype(np.int64)


MESHES = {"uv sphere": uv_sphere(), "torus": torus(40, 24),
          # 76,800 vertices, 153,600 faces: the prefetching path and many summation chunks
          "large torus": torus(320, 240)}


def results() -> list[bytes]:
    """Every output of the hot kernels, through the public calls and the kernels themselves."""
    out = []
    x0, bodies, u = _batch(150)                            # chunks of 64 and a padded tail of 22
    for method in METHODS:
        for frame in ("world", "body"):
            out.append(rollout(x0, u, 1e-3, 40, body=bodies, method=method, force_frame=frame, gravity=G,
                               save_every=10, threads=2).tobytes())
    one = RigidBody(bodies.mass[7], bodies.inertia_com[7])
    out.append(rollout(x0[7], u[7], 1e-3, 40, body=one, method="splitting").tobytes())
    for v, f in MESHES.values():
        p = inertia.mesh_properties(v, f, density=1.2)
        out += [np.float64(p.mass).tobytes(), p.com.tobytes(), p.inertia_com.tobytes()]
        adj = np.full(f.shape, -1, dtype=np.int64)
        out += [_ext.integrals.clean_solid(v, f, 1e-12, adj=adj).tobytes(), adj.tobytes()]
        out += [_ext.integrals.solid_sums(v, f, np.array([0.1, 0.0, -0.2])).tobytes(),
                _ext.integrals.shell_sums(v, f, np.array([0.1, 0.0, -0.2])).tobytes()]
    return out


def test_every_variant_the_cpu_runs_gives_the_same_bits(restore_isa):
    runs = {}
    for name in RUNS:
        _ext._force_isa(name)
        assert _ext._isa() == name
        runs[name] = results()
    first = RUNS[0]
    for name in RUNS[1:]:
        assert len(runs[name]) == len(runs[first])
        for k, (a, b) in enumerate(zip(runs[first], runs[name])):
            assert a == b, f"output {k}: {name} differs from {first}"


@pytest.mark.skipif(platform.machine().lower() not in ("x86_64", "amd64") or not shutil.which("objdump"),
                    reason="x86-64 and objdump only")
def test_the_compiled_core_holds_no_fused_multiply_add():
    """No FMA instruction in the module, so a native build gives the bits of a portable one too (GCC 12
    formed vfmaddsub out of a quaternion product despite -ffp-contract=off, until its unit was compiled
    without basic-block SLP)."""
    listing = subprocess.run(["objdump", "-d", "--no-show-raw-insn", _ext.__file__], capture_output=True, text=True,
                             check=True).stdout
    fused = sorted(set(re.findall(r"\bv?f(?:n?m(?:add|sub)(?:sub|add)?)\w*", listing)))
    assert not fused, fused
