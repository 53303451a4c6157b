"""One finding type and one registry of codes: every code the package writes is registered, and
the same fact keeps its code from the validity check to a robot check, a mesh and a batch row."""

from __future__ import annotations

import ast
import inspect
from pathlib import Path

import numpy as np
import pytest

import inertia
from inertia.errors import CODES, Finding, InertiaError

SRC = Path(__file__).resolve().parents[1] / "src" / "inertia"
#: calls whose first argument is a code
CODE_FIRST = {"Finding", "mesh_finding", "reader_finding", "add"}


def _literal_codes():
    """``(file:line, code)`` of every code written as a literal in the package: ``code=`` keywords,
    first arguments of the finding constructors, ``code = ...`` class attributes, the codes of
    the readers' ``(code, message)`` notes and of ``_refuse``."""
    for path in sorted(SRC.rglob("*.py")):
        tree = ast.parse(path.read_text())
        where = path.relative_to(SRC)
        for node in ast.walk(tree):
            if isinstance(node, ast.Call):
                name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
                for kw in node.keywords:
                    if kw.arg == "code" and isinstance(kw.value, ast.Constant):
                        yield f"{where}:{node.lineno}", kw.value.value
                if name in CODE_FIRST and node.args and isinstance(node.args[0], ast.Constant) \
                        and isinstance(node.args[0].value, str) and name != "add" or (
                        name == "add" and isinstance(node.func, ast.Attribute) and node.args
                        and isinstance(node.args[0], ast.Constant) and isinstance(node.args[0].value, str)
                        and len(node.args) >= 2):
                    yield f"{where}:{node.lineno}", node.args[0].value
                if name == "_refuse" and len(node.args) == 4 and isinstance(node.args[3], ast.Constant):
                    yield f"{where}:{node.lineno}", node.args[3].value
                if name == "append" and node.args and isinstance(node.args[0], ast.Tuple) \
                        and isinstance(node.func.value, ast.Attribute) and node.func.value.attr == "notes" \
                        and isinstance(node.args[0].elts[0], ast.Constant):
                    yield f"{where}:{node.lineno}", node.args[0].elts[0].value
            elif isinstance(node, ast.ClassDef):
                for stmt in node.body:
                    if isinstance(stmt, ast.Assign) and [getattr(t, "id", None) for t in stmt.targets] == ["code"] \
                            and isinstance(stmt.value, ast.Constant):
                        yield f"{where}:{stmt.lineno}", stmt.value.value


def test_every_code_written_in_the_package_is_registered_once():
    found = list(_literal_codes())
    assert len(found) > 80                                       # the walker sees the package
    unknown = sorted({f"{where}: {code}" for where, code in found if code not in CODES})
    assert not unknown, "codes missing from inertia.errors.CODES:\n" + "\n".join(unknown)
    assert all(sev in ("error", "warning", "note") and text for sev, text in CODES.values())


def test_every_error_class_has_a_registered_code():
    classes = [c for c in vars(inertia.errors).values() if inspect.isclass(c) and issubclass(c, InertiaError)]
    assert len(classes) >= 9
    assert all(c.code in CODES for c in classes)


def test_a_finding_refuses_an_unknown_code_and_takes_the_registered_severity():
    with pytest.raises(KeyError, match="'no_such_code' is not in"):
        Finding("no_such_code", "text")
    with pytest.raises(ValueError, match="severity must be one of"):
        Finding("open_edges", "text", severity="fatal")
    f = Finding("open_edges", "3 open edges", where="part.stl", values={"count": np.int64(3), "edge": (1, 2)})
    assert f.severity == "error" and str(f) == "part.stl: 3 open edges"
    assert f.to_dict() == {"code": "open_edges", "severity": "error", "message": "3 open edges", "where": "part.stl",
                           "values": {"count": 3, "edge": [1, 2]}}
    assert list(f.to_dict()) == ["code", "severity", "message", "where", "values"]
    assert f.replace(severity="warning").severity == "warning" and f.severity == "error"


def test_the_same_fact_keeps_its_code_from_the_validity_check_to_a_robot_check(tmp_path):
    from inertia.robots.check import check_link, check_model
    from inertia.robots.io import read_robot
    from inertia.robots.model import Inertial, Link

    # truth: a negative mass and a NaN entry, one code each, wherever they are met
    assert [f.code for f in inertia.check_inertia(np.eye(3), mass=-1.0)] == ["non_positive_mass"]
    assert [f.code for f in inertia.check_inertia(np.diag([np.nan, 1.0, 1.0]))] == ["non_finite"]
    urdf = tmp_path / "r.urdf"
    urdf.write_text('<robot name="r"><link name="a"><inertial><mass value="-1"/>'
                    '<inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link></robot>')
    (a,) = check_model(read_robot(urdf)).links
    assert [(f.code, f.severity) for f in a.errors] == [("non_positive_mass", "error")]
    assert a.errors[0].where.startswith(f"{urdf}:1") and "link 'a'" in a.errors[0].where
    # the readers refuse NaN; a model built in Python reaches the check with it
    nan = Link("b", 3, Inertial(1.0, np.zeros(3), np.eye(3), np.diag([np.nan, 1.0, 1.0])))
    b = check_link(nan, "made.urdf:3")
    assert [(f.code, f.severity) for f in b.errors] == [("non_finite", "error")]


def test_an_error_carries_its_findings():
    with pytest.raises(inertia.InvalidInertiaError) as ei:
        inertia.MassProperties(1.0, np.zeros(3), np.diag([1.0, 1.0, 3.0]))
    (f,) = ei.value.findings
    assert ei.value.code == "invalid_inertia" and f.code == "triangle_inequality" and f.values["margin"] == -1.0
    v = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
    with pytest.raises(inertia.MeshError) as ei:
        inertia.mesh_properties(v, [[0, 2, 1], [0, 1, 3], [0, 3, 2]], density=1.0)
    assert ei.value.code == "open_edges" == ei.value.findings[0].code
    assert ei.value.findings == ei.value.report.errors
