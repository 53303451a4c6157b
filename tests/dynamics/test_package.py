"""The public surface of inertia.dynamics: every exported name resolves, and importing the
package stays free of NumPy until a name is used (the CLI start-up depends on it)."""

import subprocess
import sys

import inertia
import inertia.dynamics as dynamics


def test_every_exported_name_resolves_to_its_module():
    for name in dynamics.__all__:
        obj = getattr(dynamics, name)
        module = getattr(obj, "__module__", None)
        if module is not None:  # constants such as METHODS have none
            assert module.startswith(("inertia.dynamics.", "inertia.errors")), (name, module)


def test_subpackage_reachable_from_top_level():
    assert inertia.dynamics is dynamics
    assert inertia.dynamics.exact.exact_solution is dynamics.exact_solution


def test_import_is_lazy():
    code = "import sys, inertia, inertia.dynamics; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_unknown_name_is_an_attribute_error():
    import pytest

    with pytest.raises(AttributeError, match="no attribute 'nope'"):
        dynamics.nope
