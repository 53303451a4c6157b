"""Compare the mass properties of two robot descriptions body by body, across formats.

Each side (URDF, SDF, MJCF, ``.xacro``, OpenUSD) is read into its bodies' mass, center of mass
and inertia about the COM, in its root frame at the default configuration
(:func:`inertia.robots.whole.robot_mass_properties`; USD stages:
:func:`inertia.robots.usd.mass.stage_mass_properties`, world frame).  Bodies are matched by
name: as written, then as USD identifiers (``a-b`` -> ``a_b``, a leading digit prefixed with
``_``, which is how converters rename them), then through ``rename`` (``{name in A: name in B}``).

A matched pair differs when one of

* mass: ``|m_A - m_B| / max(m_A, m_B)``,
* inertia: ``max|I_A - I_B| / max(max|I_A|, max|I_B|)`` (root-frame tensors about each COM),
* COM: ``|c_A - c_B|`` in metres (root frame), compared when both have mass,

exceeds ``tol``.  A body without a counterpart is first merged into its nearest ancestor that
has one (converters merge links welded by fixed joints); one with none differs by 1 in mass if
it has mass, and is listed, not counted, if it has none.
"""

from __future__ import annotations

import re
from dataclasses import dataclass, field

import numpy as np

#: default tolerance: relative for mass and inertia, metres for the COM
DIFF_TOL = 1e-6


@dataclass
class BodyDiff:
    """One body's values on both sides (None where it is absent) and its errors."""

    name_a: str | None
    name_b: str | None
    a: object
    b: object
    errors: dict = field(default_factory=dict)

    @property
    def worst(self) -> float:
        return max(self.errors.values(), default=0.0)

    def to_dict(self) -> dict:
        def side(r):
            return None if r is None else {"mass": r.mass, "com": r.com.tolist(), "inertia_com": r.inertia_com.tolist(),
                                           "source": r.source}
        return {"name_a": self.name_a, "name_b": self.name_b, "errors": self.errors, "a": side(self.a),
                "b": side(self.b)}


@dataclass
class DiffReport:
    """``differ``: bodies beyond the tolerance, worst first; ``same``: how many agree."""

    a: str
    b: str
    tol: float
    differ: list
    same: int
    massless_unmatched: list = field(default_factory=list)
    notes: list = field(default_factory=list)
    totals: dict = field(default_factory=dict)

    def to_dict(self) -> dict:
        return {"a": self.a, "b": self.b, "tol": self.tol, "n_differ": len(self.differ), "n_same": self.same,
                "differ": [d.to_dict() for d in self.differ], "massless_unmatched": self.massless_unmatched,
                "totals": self.totals, "notes": self.notes}


def usd_identifier(name: str) -> str:
    """``name`` as a valid USD prim name (what converters write for it)."""
    out = re.sub(r"[^A-Za-z0-9_]", "_", name)
    return "_" + out if out[:1].isdigit() or not out else out


def read_bodies(path, *, physx: bool = False, unset_tolerance=None, search_paths=(), xacro_args=None,
                mesh_units: str = "m"):
    """The :class:`~inertia.robots.whole.RobotMassProperties` of any robot description."""
    from .usd.stage import is_usd_path

    if is_usd_path(path):
        from .usd.mass import UNSET_TOLERANCE, stage_mass_properties

        return stage_mass_properties(path, physx=physx,
                                     tol=UNSET_TOLERANCE if unset_tolerance is None else unset_tolerance)
    from .io import read_robot
    from .whole import robot_mass_properties

    model = read_robot(path, search_paths=search_paths, xacro_args=xacro_args)
    return robot_mass_properties(model, mesh_units=mesh_units)


def match_bodies(names_a, names_b, rename=None) -> dict:
    """``{name in A: name in B}``: ``rename`` first, then equal names, then equal USD identifiers."""
    rename = dict(rename or {})
    b_set = set(names_b)
    by_ident: dict = {}
    for n in names_b:
        by_ident.setdefault(usd_identifier(n), n)
    out, used = {}, set()
    for n in names_a:
        target = rename.get(n)
        if target is None:
            target = n if n in b_set else by_ident.get(usd_identifier(n))
        if target is not None and target in b_set and target not in used:
            out[n] = target
            used.add(target)
    return out


def body_errors(a, b) -> dict:
    """Mass, COM and inertia errors between two rows (see the module docstring)."""
    ma, mb = float(a.mass if a is not None else 0.0), float(b.mass if b is not None else 0.0)
    if a is None or b is None or max(ma, mb) == 0:
        return {"mass": 1.0 if max(ma, mb) > 0 else 0.0}
    out = {"mass": abs(ma - mb) / max(abs(ma), abs(mb))}
    Ia, Ib = np.asarray(a.inertia_com), np.asarray(b.inertia_com)
    scale = max(np.abs(Ia).max(), np.abs(Ib).max())
    out["inertia"] = float(np.abs(Ia - Ib).max() / scale) if scale > 0 else 0.0
    if ma > 0 and mb > 0:
        out["com"] = float(np.linalg.norm(np.asarray(a.com) - np.asarray(b.com)))
    return out


@dataclass
class Lumped:
    """A body with the bodies below it that the other side does not have (merged into it)."""

    name: str
    props: object
    source: str
    merged: list

    @property
    def mass(self):
        return self.props.mass

    @property
    def com(self):
        return self.props.com

    @property
    def inertia_com(self):
        return self.props.inertia_com


def lump_unmatched(rows: list, matched: set, notes: list, side: str) -> dict:
    """``{name: row}`` where each body without a counterpart is merged into its nearest ancestor
    that has one (converters merge links welded by fixed joints); bodies with no such ancestor
    stay as they are."""
    from ..massprops.properties import combine

    extra: dict = {}
    out = {}
    for r in rows:
        if r.name in matched:
            continue
        j = getattr(r, "parent", None)
        while j is not None and rows[j].name not in matched:
            j = getattr(rows[j], "parent", None)
        if j is None:
            out[r.name] = r
        else:
            extra.setdefault(rows[j].name, []).append(r)
    for r in rows:
        if r.name not in matched:
            continue
        more = extra.get(r.name)
        if not more:
            out[r.name] = r
            continue
        parts = [x.props for x in [r, *more] if x.mass > 0]
        props = combine(parts, frame=r.props.frame, validate=False) if parts else r.props
        out[r.name] = Lumped(r.name, props, r.source, [x.name for x in more])
        notes.append(f"{side}: {', '.join(x.name for x in more)} merged into {r.name} (no body of that name on the "
                     "other side; converters merge links welded by fixed joints)")
    return out


def diff_robots(a, b, *, tol: float = DIFF_TOL, rename=None, read=read_bodies, **read_options) -> DiffReport:
    """Compare two robot descriptions (paths, or RobotMassProperties) body by body."""
    ra = a if hasattr(a, "links") else read(a, **read_options)
    rb = b if hasattr(b, "links") else read(b, **read_options)
    pairs = match_bodies([r.name for r in ra.links], [r.name for r in rb.links], rename)
    notes: list = []
    rows_a = lump_unmatched(list(ra.links), set(pairs), notes, "A")
    rows_b = lump_unmatched(list(rb.links), set(pairs.values()), notes, "B")
    diffs, same = [], 0
    for name, row in rows_a.items():
        other = rows_b.get(pairs.get(name))
        d = BodyDiff(name, pairs.get(name), row, other, body_errors(row, other))
        if d.worst > tol:
            diffs.append(d)
        elif other is not None:
            same += 1
    matched_b = set(pairs.values())
    unmatched = [f"{ra.path}: {n}" for n, r in rows_a.items() if n not in pairs and r.mass == 0]
    for name, row in rows_b.items():
        if name in matched_b:
            continue
        if row.mass > 0:
            diffs.append(BodyDiff(None, name, None, row, body_errors(None, row)))
        else:
            unmatched.append(f"{rb.path}: {name}")
    diffs.sort(key=lambda d: -d.worst)
    report = DiffReport(str(ra.path), str(rb.path), tol, diffs, same, unmatched, notes)
    report.totals = {"mass_a": ra.total.mass, "mass_b": rb.total.mass, "frame_a": ra.frame, "frame_b": rb.frame}
    return report
