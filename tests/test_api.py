"""The public surface: a small top level, subpackages that resolve, nothing heavy on import."""

from __future__ import annotations

import importlib
import subprocess
import sys

import pytest

import inertia

SUBPACKAGES = ("errors", "geometry", "massprops", "particles", "dynamics", "symbolic", "robots", "control", "viz",
               "batch")


def test_top_level_is_small_and_every_name_resolves():
    names = [n for n in inertia.__all__ if n != "__version__"]
    assert 20 <= len(names) <= 30, len(names)
    for n in names:
        assert getattr(inertia, n) is not None, n
    assert set(dir(inertia)) >= set(names) | set(SUBPACKAGES)


@pytest.mark.parametrize("package", [p for p in SUBPACKAGES if p not in ("viz",)])
def test_every_subpackage_name_resolves(package):
    if package in ("symbolic",):
        pytest.importorskip("sympy")
    if package == "batch":
        pytest.importorskip("pandas")
    mod = importlib.import_module(f"inertia.{package}")
    for n in getattr(mod, "__all__", ()):
        assert getattr(mod, n) is not None, (package, n)


def test_one_home_per_top_level_name():
    # a top-level name is the very object its subpackage exports (no copies, no wrappers)
    for n in ("MassProperties", "box", "mesh_properties", "load_mesh", "six_point_model", "InputError"):
        obj = getattr(inertia, n)
        owner = importlib.import_module(obj.__module__ if not isinstance(obj, type) or n != "InputError"
                                        else "inertia.errors")
        assert getattr(owner, n) is obj


def test_import_and_help_load_no_numpy():
    probe = ("import sys, contextlib, io\n"
             "import inertia, inertia.massprops, inertia.geometry, inertia.dynamics, inertia.particles\n"
             "from inertia.cli.main import main\n"
             "with contextlib.redirect_stdout(io.StringIO()):\n"
             "    try:\n"
             "        main(['--help'])\n"
             "    except SystemExit:\n"
             "        pass\n"
             "print(sorted(m for m in ('numpy', 'scipy') if m in sys.modules))\n")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=60, check=True)
    assert out.stdout.strip() == "[]"
