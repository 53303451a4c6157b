"""Write rigid bodies' ``PhysicsMassAPI`` attributes into a stage as a minimal edit.

What is written (stage units, body frame): ``physics:mass``, ``physics:centerOfMass`` (divided
by the body's world scale, which usd-core multiplies it by), ``physics:diagonalInertia``
(ascending) and ``physics:principalAxes`` (a unit quaternion, ``w >= 0``, of the proper rotation
whose columns are the principal axes), and ``PhysicsMassAPI`` where the body lacks it.  An
attribute whose float32 value would not change is left alone.

Where: each attribute in the layer that holds its strongest authored value (a new one where the
prim's ``PhysicsMassAPI``, else its ``PhysicsRigidBodyAPI``, is applied), so a converter's
``Physics.usda`` is edited, not the root layer.  A ``.usda`` layer is edited as text: only the
changed attribute lines (and an ``apiSchemas`` list that gains ``PhysicsMassAPI``) differ, and
the edit is checked by reading it back with usd-core against the same edit made through Sdf;
should the two differ, usd-core writes the layer.  A binary layer is edited through Sdf.  With
``layer=OUT`` the values go into a new override layer that sublayers the input, which is left
untouched.
"""

from __future__ import annotations

import os
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from ..._core.errors import InputError
from .mass import UNSET_TOLERANCE, is_set
from .stage import pxr_modules, read_stage

#: attribute -> (usda type, Sdf value type name)
ATTRS = {"physics:mass": ("float", "Float"), "physics:centerOfMass": ("point3f", "Point3f"),
         "physics:diagonalInertia": ("float3", "Float3"), "physics:principalAxes": ("quatf", "Quatf")}
MASS_API = "PhysicsMassAPI"


@dataclass
class UsdFixReport:
    """What the fix wrote (the fields :func:`inertia.cli.fix.fix_summary` prints)."""

    output: str
    changed: dict = field(default_factory=dict)
    skipped: dict = field(default_factory=dict)
    remaining: dict = field(default_factory=dict)
    identical: bool = False
    layers: list = field(default_factory=list)     # files written
    notes: list = field(default_factory=list)


def mass_api_values(stage, body, props) -> dict:
    """The four attributes (stage units, float32-ready tuples) that make ``body`` have the world
    SI mass properties ``props`` (a :class:`~inertia.massprops.properties.MassProperties`)."""
    from ..._core.rotations import matrix_to_quat
    from ...massprops.principal import principal_axes

    m_unit, kg_unit = stage.meters_per_unit, stage.kilograms_per_unit
    R, p = body.R_world_body, body.p_world_body
    com_B = R.T @ (np.asarray(props.com) / m_unit - p) / body.scale_world
    I_B = R.T @ np.asarray(props.inertia_com) @ R / (kg_unit * m_unit ** 2)
    w, V = principal_axes(I_B)   # the canonical frame: ascending, det +1, the documented signs
    q = matrix_to_quat(V)
    return {"physics:mass": props.mass / kg_unit, "physics:centerOfMass": tuple(com_B),
            "physics:diagonalInertia": tuple(w), "physics:principalAxes": tuple(q)}


def _f32(v):
    return np.asarray(v, np.float32)


def _same(current, new) -> bool:
    return current is not None and np.array_equal(_f32(current), _f32(new))


def _current(attrs, name: str):
    return {"physics:mass": attrs.mass, "physics:centerOfMass": attrs.center_of_mass,
            "physics:diagonalInertia": attrs.diagonal_inertia, "physics:principalAxes": attrs.principal_axes}[name]


def nearest_values(stage, i: int, tol: float = UNSET_TOLERANCE) -> tuple[dict, str]:
    """``({attribute: value}, why)`` that repair a body's authored values: a non-unit
    ``principalAxes`` normalised, a ``diagonalInertia`` that is not physical replaced by the
    nearest physical one (same axes)."""
    from ...massprops.validity import check_inertia
    from ..fix import nearest_physical_inertia

    a = stage.bodies[i].mass
    out, why = {}, []
    q = a.principal_axes
    if a.applied and q is not None and is_set(q, tol) and abs(np.linalg.norm(q) - 1) > 1e-6:
        out["physics:principalAxes"] = tuple(q / np.linalg.norm(q))
        why.append(f"principalAxes normalised (norm {np.linalg.norm(q):.6g})")
    d = a.diagonal_inertia
    if a.applied and is_set(d, tol) and check_inertia(np.diag(d)):
        fixed = np.diag(nearest_physical_inertia(np.diag(d)))
        out["physics:diagonalInertia"] = tuple(fixed)
        why.append(f"diagonalInertia {np.array2string(d, precision=6)} -> {np.array2string(fixed, precision=6)} "
                   "(nearest physical)")
    return out, "; ".join(why)


def plan_from_source(stage, source, *, rename=None, tol: float = 1e-6, unset_tolerance: float = UNSET_TOLERANCE,
                     report: UsdFixReport):
    """``{body index: {attribute: value}}`` writing the source's mass properties (a robot file or a
    RobotMassProperties) into every matched body that differs from it by more than ``tol``."""
    from ..diff import body_errors, match_bodies, read_bodies
    from .mass import stage_mass_properties

    src = source if hasattr(source, "links") else read_bodies(source)
    mine = stage_mass_properties(stage, tol=unset_tolerance)
    # the values as authored (only exact zeros "not set"): a body whose authored values already
    # equal the source's differs only by usd-core's reading of them, which no write can change
    authored = stage_mass_properties(stage, tol=0.0) if unset_tolerance > 0 else mine
    rows = {r.name: r for r in src.links}
    pairs = match_bodies(list(rows), [r.name for r in mine.links], rename)
    by_name = {r.name: k for k, r in enumerate(mine.links)}
    plan = {}
    for name, target in pairs.items():
        k = by_name[target]
        row, body = rows[name], stage.bodies[k]
        if max(body_errors(row, mine.links[k]).values(), default=0.0) <= tol:
            continue
        if max(body_errors(row, authored.links[k]).values(), default=0.0) <= tol:
            continue
        if not row.mass > 0:
            report.skipped[target] = (f"the source gives it no mass ({name!r}, {row.source}); UsdPhysics cannot say "
                                      "\"massless\" (0 means not set)")
            continue
        plan[k] = values = mass_api_values(stage, body, row.props)
        small = unset_tolerance > 0 and not is_set(values["physics:diagonalInertia"], unset_tolerance)
        report.changed[target] = (f"from {name!r}: mass {row.mass:.6g} kg, COM {np.round(row.com, 6).tolist()} m "
                                  f"(world), moments "
                                  f"{np.array2string(row.props.principal().moments, precision=6)} kg m^2"
                                  + (f" (an inertia below usd-core's {unset_tolerance:g}: it reads it as not set)"
                                     if small else ""))
    unmatched = sorted(set(rows) - set(pairs))
    if unmatched:
        report.notes.append(f"{len(unmatched)} bodies of the source have no body of that name in the stage: "
                            + ", ".join(unmatched[:10]) + (" ..." if len(unmatched) > 10 else ""))
    return plan


# ------------------------------------------------------------------------------ where to write


def _target(usd_stage, path: str, attr: str):
    """``(layer, spec path of the attribute)`` that holds the attribute's strongest value, or where
    a new one belongs (the layer applying PhysicsMassAPI, else PhysicsRigidBodyAPI)."""
    Usd = pxr_modules()[0]
    prim = usd_stage.GetPrimAtPath(path)
    a = prim.GetAttribute(attr)
    if a:
        for spec in a.GetPropertyStack(Usd.TimeCode.Default()):
            if spec.HasDefaultValue():
                return spec.layer, spec.path
    stack = prim.GetPrimStack()
    for api in (MASS_API, "PhysicsRigidBodyAPI"):
        for spec in stack:
            op = spec.GetInfo("apiSchemas") if spec.HasInfo("apiSchemas") else None
            if op is not None and api in list(op.GetAddedOrExplicitItems()):
                return spec.layer, spec.path.AppendProperty(attr)
    return stack[0].layer, stack[0].path.AppendProperty(attr)


def _writable(layer, why: str) -> None:
    packaged = layer.GetFileFormat().IsPackage() or "[" in layer.identifier
    if layer.anonymous or packaged or not layer.realPath:
        raise InputError(f"the values belong in {layer.identifier}, which cannot be edited in place ({why}); "
                         "write an override layer instead: --layer OUT.usda")


def _sdf_edit(layer, edits: list, api_prims: list) -> None:
    """Apply ``edits`` ``[(attribute spec path, name, value)]`` and add PhysicsMassAPI to
    ``api_prims`` (spec paths) in an Sdf layer."""
    _, _, _, _, Sdf, Gf = pxr_modules()
    for prim_path in api_prims:
        spec = layer.GetPrimAtPath(prim_path) or Sdf.CreatePrimInLayer(layer, prim_path)
        op = spec.GetInfo("apiSchemas") if spec.HasInfo("apiSchemas") else Sdf.TokenListOp()
        if op.isExplicit:
            op.explicitItems = list(op.explicitItems) + [MASS_API]
        else:
            op.prependedItems = list(op.prependedItems) + [MASS_API]
        spec.SetInfo("apiSchemas", op)
    for attr_path, name, value in edits:
        prim_path = attr_path.GetPrimPath()
        spec = layer.GetPrimAtPath(prim_path) or Sdf.CreatePrimInLayer(layer, prim_path)
        a = spec.attributes[name] if name in spec.attributes else Sdf.AttributeSpec(
            spec, name, getattr(Sdf.ValueTypeNames, ATTRS[name][1]))
        a.default = _gf_value(name, value, Gf)


def _gf_value(name, value, Gf):
    v = [float(x) for x in np.atleast_1d(_f32(value))]
    if name == "physics:mass":
        return v[0]
    if name == "physics:principalAxes":
        return Gf.Quatf(v[0], v[1], v[2], v[3])
    return Gf.Vec3f(*v)


def _number(x) -> str:
    """A float32 as its shortest text (usd-core reads it back as the same float32)."""
    text = str(np.float32(x))
    return text[:-2] if text.endswith(".0") else text


def _text_value(name, value) -> str:
    v = [_number(x) for x in np.atleast_1d(_f32(value))]
    return v[0] if name == "physics:mass" else "(" + ", ".join(v) + ")"


def _text_edit(text: str, edits: list, api_prims: list) -> str:
    """The usda text with ``edits`` and ``api_prims`` applied at their places (see :func:`_sdf_edit`)."""
    from .usda_text import indent_at, scan

    prims = scan(text)
    changes = []     # (position, old length, new text)
    for attr_path, name, value in edits:
        prim = prims[str(attr_path.GetPrimPath())]
        prop = prim.props.get(name)
        if prop is not None and prop.value is not None:
            changes.append((prop.value[0], prop.value[1] - prop.value[0], _text_value(name, value)))
            continue
        body_indent = (indent_at(text, next(iter(prim.props.values())).start) if prim.props else
                       indent_at(text, prim.child_start) if prim.child_start is not None else
                       indent_at(text, prim.header) + "    ")
        line = f"{body_indent}{ATTRS[name][0]} {name} = {_text_value(name, value)}\n"
        anchor = prim.last_prop_end if prim.last_prop_end is not None else prim.body[0]
        at = text.index("\n", anchor) + 1
        changes.append((at, 0, line))
    for prim_path in api_prims:
        prim = prims[str(prim_path)]
        changes.append(_api_change(text, prim))
    merged: dict = {}      # inserts at one place keep the order of ``edits``
    for pos, n, new in changes:
        old_n, old_new = merged.get(pos, (0, ""))
        merged[pos] = (max(n, old_n), old_new + new)
    out = text
    for pos in sorted(merged, reverse=True):
        n, new = merged[pos]
        out = out[:pos] + new + out[pos + n:]
    return out


def _api_change(text: str, prim):
    """The change that adds PhysicsMassAPI to a prim's ``apiSchemas`` (as Sdf adds it)."""
    import re

    from .usda_text import indent_at

    indent = indent_at(text, prim.header)
    if prim.meta is None:
        return (prim.name_end, 0, f' (\n{indent}    prepend apiSchemas = ["{MASS_API}"]\n{indent})')
    meta = text[prim.meta[0]:prim.meta[1]]
    m = re.search(r"(^|\n)[ \t]*(prepend\s+|)apiSchemas\s*=\s*\[", meta)
    if m is None:
        at = text.index("\n", prim.meta[0]) + 1 if "\n" in meta else prim.meta[0] + 1
        return (at, 0, f'{indent}    prepend apiSchemas = ["{MASS_API}"]\n')
    close = prim.meta[0] + meta.index("]", m.end())
    empty = not text[prim.meta[0] + m.end():close].strip()
    return (close, 0, f'"{MASS_API}"' if empty else f', "{MASS_API}"')


# ------------------------------------------------------------------------------ the fix


def fix_stage(path, output=None, *, source=None, rename=None, in_place: bool = False, layer=None,
              tol: float = 1e-6, unset_tolerance: float = UNSET_TOLERANCE) -> UsdFixReport:
    """Repair a stage's MassAPI attributes, or write a source's values into it (``source``).

    ``output``: a corrected copy of the root layer (every edit must fall in it); ``in_place``:
    edit the layers that hold the values; ``layer``: a new override layer (the input untouched).
    Exactly one of the three.
    """
    Usd, _, _, _, Sdf, _ = pxr_modules()
    path = Path(path)
    modes = [output is not None, bool(in_place), layer is not None]
    if sum(modes) != 1:
        raise InputError("give exactly one of -o OUT (a corrected copy), --in-place, or --layer OUT.usda "
                         "(an override layer)")
    target_out = Path(output or layer or path)
    if (output or layer) and target_out.resolve() == path.resolve():
        raise InputError(f"{target_out} is the input: pass --in-place to edit it")
    stage = read_stage(path)
    report = UsdFixReport(str(target_out))
    if source is not None:
        plan = plan_from_source(stage, source, rename=rename, tol=tol, unset_tolerance=unset_tolerance,
                                report=report)
    else:
        plan = {}
        for i, b in enumerate(stage.bodies):
            values, why = nearest_values(stage, i, unset_tolerance)
            if values:
                plan[i] = values
                report.changed[b.label] = why
    edits = {i: {k: v for k, v in values.items() if not _same(_current(stage.bodies[i].mass, k), v)}
             for i, values in plan.items()}
    usd = stage.usd_stage
    by_layer: dict = {}
    for i, values in edits.items():
        body = stage.bodies[i]
        prim = usd.GetPrimAtPath(body.path)
        if prim.IsInstanceProxy():
            report.skipped[body.label] = "it is inside an instance: edit the prototype's source instead"
            report.changed.pop(body.label, None)
            continue
        needs_api = bool(values) and not body.mass.applied
        for name, value in values.items():
            lay, attr_path = ((None, Sdf.Path(body.path).AppendProperty(name)) if layer
                              else _target(usd, body.path, name))
            by_layer.setdefault(lay, ([], []))[0].append((attr_path, name, value))
        if needs_api:
            lay, attr_path = (None, Sdf.Path(body.path)) if layer else _target(usd, body.path, "physics:mass")
            by_layer.setdefault(lay, ([], []))[1].append(attr_path.GetPrimPath())
    if layer is not None:
        _write_override(stage, Path(layer), *by_layer.get(None, ([], [])))
        report.layers.append(str(layer))
    else:
        root = usd.GetRootLayer()
        for lay, (attr_edits, api_prims) in by_layer.items():
            if output is not None and lay != root:
                raise InputError(f"the values of {path} live in {lay.realPath or lay.identifier}, not in the file "
                                 "itself: use --in-place (edits that layer) or --layer OUT.usda (an override layer)")
            _writable(lay, "a layer inside a package or in memory")
            dest = Path(output) if output is not None else Path(lay.realPath)
            report.notes += _write_layer(lay, dest, attr_edits, api_prims)
            report.layers.append(str(dest))
        if output is not None and root not in by_layer:
            _copy_unchanged(root, Path(output))
            report.layers.append(str(output))
    report.identical = not any(edits.values())
    return report


def _write_layer(layer, dest: Path, attr_edits: list, api_prims: list) -> list:
    """Write ``layer`` with the edits to ``dest`` (text edit for usda, Sdf otherwise)."""
    from ..._core.atomic import write_bytes_atomic
    from .usda_text import layer_signature

    Sdf = pxr_modules()[4]
    expected = Sdf.Layer.CreateAnonymous(".usda")
    expected.TransferContent(layer)
    _sdf_edit(expected, attr_edits, api_prims)
    is_text = Path(layer.realPath).read_bytes()[:5] == b"#usda"
    if is_text and dest.suffix.lower() in (".usda", ".usd"):
        text = Path(layer.realPath).read_text(encoding="utf-8")
        try:
            new = _text_edit(text, attr_edits, api_prims)
            check = Sdf.Layer.CreateAnonymous(".usda")
            ok = check.ImportFromString(new) and layer_signature(check) == layer_signature(expected)
        except (ValueError, KeyError):
            ok = False
        write_bytes_atomic(dest, (new if ok else expected.ExportToString()).encode("utf-8"))
        _reload(dest)
        return [] if ok else [f"{dest}: the text edit could not be verified, so usd-core wrote the whole layer "
                              "(same opinions, its own formatting)"]
    if dest == Path(layer.realPath):
        _sdf_edit(layer, attr_edits, api_prims)
        layer.Save()
    else:
        expected.Export(str(dest))
        _reload(dest)
    return []


def _reload(path: Path) -> None:
    """Make usd-core's layer registry (which outlives a stage in this process) read ``path`` again."""
    Sdf = pxr_modules()[4]
    layer = Sdf.Layer.Find(str(path))
    if layer is not None:
        layer.Reload(True)


def _copy_unchanged(root, dest: Path) -> None:
    import shutil

    shutil.copyfile(root.realPath, dest)


def _write_override(stage, dest: Path, attr_edits: list, api_prims: list) -> None:
    """A new layer at ``dest`` that sublayers the stage's root layer and holds the edits as ``over``s;
    the root layer's stage metadata (units, up axis, default prim) is copied, since a stage takes
    them from its root layer."""
    from ..._core.atomic import write_bytes_atomic

    Sdf = pxr_modules()[4]
    root = stage.usd_stage.GetRootLayer()
    out = Sdf.Layer.CreateAnonymous(dest.suffix or ".usda")
    rel = os.path.relpath(root.realPath, dest.resolve().parent)
    out.subLayerPaths.append(rel)
    for key in ("metersPerUnit", "kilogramsPerUnit", "upAxis", "defaultPrim"):
        if root.pseudoRoot.HasInfo(key):
            out.pseudoRoot.SetInfo(key, root.pseudoRoot.GetInfo(key))
    _sdf_edit(out, attr_edits, api_prims)
    if dest.suffix.lower() == ".usdc":
        out.Export(str(dest))
    else:
        write_bytes_atomic(dest, out.ExportToString().encode("utf-8"))
    _reload(dest)


def check_written(report: UsdFixReport, source=None, *, rename=None, tol: float = 1e-6,
                  unset_tolerance: float = UNSET_TOLERANCE) -> None:
    """Fill ``report.remaining``: bodies of the written stage still invalid, or still apart from the source."""
    from .check import check_stage

    target = report.output
    if source is not None:
        from ..diff import diff_robots

        d = diff_robots(source, target, tol=tol, rename=rename, unset_tolerance=unset_tolerance)
        for row in d.differ:
            name = row.name_b or row.name_a
            if name in report.skipped:
                continue
            why = ", ".join(f"{k} {v:.2e}" for k, v in row.errors.items() if v > tol)
            report.remaining[name] = f"still differs from the source ({why})" + _tolerance_hint(target, name,
                                                                                               unset_tolerance)
        return
    rep = check_stage(target, tol=unset_tolerance)
    for lk in rep.links:
        if lk.errors:
            report.remaining[lk.name] = "; ".join(str(e) for e in lk.errors)


def _tolerance_hint(path, name: str, unset_tolerance: float) -> str:
    """Why a written body may still differ: an inertia below usd-core's tolerance."""
    stage = read_stage(path)
    b = stage.body(name)
    d = b.mass.diagonal_inertia
    if unset_tolerance > 0 and d is not None and np.any(d) and not is_set(d, unset_tolerance):
        return (f": its inertia (norm {np.linalg.norm(d):.3g} in stage units) is below usd-core's {unset_tolerance:g}, "
                "so usd-core reads it as not set; no value that small can be authored")
    return ""


__all__ = ["fix_stage", "mass_api_values", "plan_from_source", "nearest_values", "check_written", "UsdFixReport"]
