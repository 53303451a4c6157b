"""The public surface of inertia.control: every exported name resolves, and importing it loads no NumPy."""

import subprocess
import sys

import inertia
import inertia.control as control


def test_every_exported_name_resolves_to_its_module():
    for name in control.__all__:
        module = getattr(getattr(control, name), "__module__", None)
        assert module is None or module.startswith(("inertia.control.", "inertia.dynamics.gyrostat")), (name, module)
    assert inertia.control is control


def test_import_is_lazy():
    code = "import sys, inertia, inertia.control; print('numpy' in sys.modules)"
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"
