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


@pytest.mark.parametrize("package", SUBPACKAGES)
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


#: the public names of each package: a change here is a change of the public surface (CHANGELOG.md)
PUBLIC = {
    "massprops": ["MassProperties", "Part", "PrincipalFrame", "assemble", "check_inertia", "elements_from_inertia",
                  "equivalent_box", "equivalent_ellipsoid", "inertia_about_point", "inertia_from_elements",
                  "mesh_file_properties", "mesh_properties", "point_masses", "principal_axes", "rotate_inertia"],
    "dynamics": ["DEFAULT_METHOD", "METHODS", "RigidBody", "angular_momentum_world", "axis_stability",
                 "exact_solution", "flip_interval", "integrate", "jacobians", "kinetic_energy", "pack_input",
                 "pack_state", "rollout", "step", "unpack_state"],
    "geometry": ["MeshReport", "SUPPORTED_EXTENSIONS", "UNITS", "box_edges", "central_inertia", "check_mesh",
                 "compact_vertices", "cylinder_mesh", "load_mesh", "merge_meshes", "orient_faces", "shell_integrals",
                 "solid_integrals", "validate_inputs", "weld_vertices"],
    "particles": ["ParticleModel", "four_point_model", "six_point_model"],
    "viz": ["DisplayMesh", "FlipScene", "active_plot", "body_plot", "build_report", "display_mesh", "invariants_plot",
            "monte_carlo_plot", "omega_plot", "page_data", "passive_plot", "polhode_plot", "render_flip",
            "render_hold", "video_format", "write_control", "write_page"],
    "batch": ["BatchSummary", "COLUMNS", "Job", "collect_jobs", "mass_properties_dask", "mass_properties_table",
              "process_file", "read_frame", "run_batch"],
    "control": ["ActiveRun", "DualSpinThreshold", "MonteCarlo", "PassiveSweep", "Showcase", "SpinHold", "SpinSetup",
                "active_run", "basilisk_setup", "design_spin_hold", "dlqr", "dual_spin_exponent",
                "dual_spin_threshold", "initial_state", "monte_carlo", "passive_sweep", "perturbed_models",
                "saturate_wheel_torque", "showcase", "t_handle_setup"],
    "robots": ["CheckReport", "Geometry", "Inertial", "Joint", "Link", "LinkMass", "RobotFileError",
               "RobotMassProperties", "RobotModel", "check_model", "detect_format", "expand_xacro", "fix_file",
               "inertial_block", "link_geometry_properties", "link_poses", "nearest_physical_inertia", "read_mjcf",
               "read_robot", "read_sdf", "read_urdf", "robot_mass_properties"],
    "symbolic": ["EquationsOfMotion", "EulerAngleSystem", "GIMBAL_LOCK_TOL", "GIMBAL_WARN_TOL", "GimbalLockError",
                 "GimbalLockWarning", "ParticleRoute", "SEQUENCES", "accelerations", "derive", "det_kinematic",
                 "euler_residual", "kinematic_matrix", "kinematic_matrix_inverse", "lagrangian", "mass_matrix",
                 "rotation_matrix"],
}


def test_every_public_package_has_all():
    assert set(PUBLIC) | {"errors"} == set(SUBPACKAGES)
    for package in SUBPACKAGES:
        assert isinstance(importlib.import_module(f"inertia.{package}").__all__, (list, tuple)), package


@pytest.mark.parametrize("package", sorted(PUBLIC))
def test_the_public_names_of_each_package_are_pinned(package):
    names = importlib.import_module(f"inertia.{package}").__all__
    assert sorted(names) == PUBLIC[package]
    assert not [n for n in names if n.startswith("_")]


def test_massprops_and_dynamics_stay_small():
    assert len(PUBLIC["massprops"]) <= 15 and len(PUBLIC["dynamics"]) <= 15


def test_no_test_skips_when_our_own_code_fails_to_import():
    # an ImportError of inertia itself is a failure; only optional third-party packages may skip
    import re
    from pathlib import Path

    pattern = re.compile(r"importorskip\(\s*[\"']inertia|except ImportError:\s*\n\s*return \[\]")
    tests = Path(__file__).parent
    bad = [str(p.relative_to(tests)) for p in tests.rglob("*.py")
           if p.name != "test_api.py" and pattern.search(p.read_text())]
    assert not bad, bad
