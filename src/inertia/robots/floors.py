"""What simulators refuse, and what is only an idiom: the checks that need the kinematic tree.

A simulator moves *bodies*: a link on a moving joint together with every link welded to it
by fixed joints (MuJoCo merges bodies without joints into their parent; Pinocchio and Gazebo
lump fixed joints the same way).  So:

* ``massless_moving_link`` (error): a link on a moving joint with no mass (no inertial, or
  mass 0 and tensor 0) whose welded group has no mass either.  MuJoCo refuses the file
  ("mass and inertia of moving bodies must be larger than mjMINVAL").
* ``below_simulator_floor`` (error): a moving group whose mass or a principal moment is
  positive but below :data:`~inertia._core.tolerances.SIMULATOR_MIN_VALUE` (1e-15 kg,
  kg m^2): the same refusal, for a tensor that is rounding noise (2.4e-35 kg m^2).
* massless frames (the idiom ``base_footprint``, ``tool0``: mass 0 and tensor 0, or no
  inertial, on a fixed joint, or on a moving joint whose welded links carry the mass): not
  errors; the report lists them in one line per file.
* ``implausible_inertia`` (warning): a link whose largest radius of gyration
  ``sqrt(I3 / m)`` is below :data:`GYRATION_RATIO` of its size (its shapes' bounding-box
  half-diagonal, or the distance to the joints it carries): a unit slip or a placeholder
  (``1e-6`` for a 2 kg link), not a body.
* SDF links without ``<inertial>`` are not massless: Gazebo simulates them with 1 kg and
  1 kg m^2 per axis (a note, ``sdf_default_inertial``).

Which links move: a URDF or SDF joint other than ``fixed``, an MJCF body with a joint (bodies
without one are welded to their parent); an SDF link no joint attaches is a free body unless
its model is ``<static>``; a URDF root link is fixed to the world.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.tolerances import SIMULATOR_MIN_VALUE

#: a link's largest radius of gyration below this fraction of its size is implausible
GYRATION_RATIO = 0.01


def _massless(link) -> bool:
    i = link.inertial
    return i is None or (i.mass == 0 and not np.any(i.inertia_com_inertial))


def _static_sdf(model) -> bool:
    root = model.document.root if model.document is not None else None
    if root is None:
        return False
    return any((el.text or "").strip() in ("true", "1") for el in root.iter("static"))


def moving_links(model) -> list:
    """``moving[i]``: link i has a degree of freedom of its own (see the module docstring)."""
    static = model.format == "sdf" and _static_sdf(model)
    out = []
    for lk in model.links:
        if any(j.kind != "fixed" for j in lk.joints):
            out.append(True)
        elif model.format == "sdf" and lk.parent is None and not lk.joints:
            out.append(not static)
        else:
            out.append(False)
    return out


def welded_groups(model, moving) -> dict:
    """Moving link index -> ``[(member index, R_group_member, p_group_member)]``: the link and
    every link welded to it through fixed joints, posed in the moving link's frame."""
    groups: dict = {}
    pose: dict = {}
    for i, lk in enumerate(model.links):       # parents come before children in every reader
        if moving[i]:
            pose[i] = (i, np.eye(3), np.zeros(3))
        elif lk.parent is not None and lk.parent in pose and pose[lk.parent][0] is not None:
            g, R, p = pose[lk.parent]
            pose[i] = (g, R @ lk.R_parent_link, R @ lk.p_parent_link + p)
        else:
            pose[i] = (None, None, None)       # welded to the world: never moves
        g, R, p = pose[i]
        if g is not None:
            groups.setdefault(g, []).append((i, R, p))
    return groups


def group_mass(model, members, props_of) -> tuple[float, np.ndarray]:
    """``(mass, principal moments about the group's COM)`` of a welded group."""
    parts = []
    for i, R, p in members:
        props = props_of(model.links[i])
        if props is not None and props.mass != 0:
            parts.append((props.mass, R @ props.com + p, R @ props.inertia_com @ R.T))
    M = sum(m for m, _, _ in parts)
    if not M > 0:
        return float(M), np.zeros(3)
    com = sum(m * c for m, c, _ in parts) / M
    I = np.zeros((3, 3))
    for m, c, Ic in parts:
        d = c - com
        I += Ic + m * (float(d @ d) * np.eye(3) - np.outer(d, d))
    with np.errstate(all="ignore"):
        return float(M), np.linalg.eigvalsh(0.5 * (I + I.T))


def link_size(model, index: int, bounds) -> float:
    """A length the link spans: its shapes' bounding-box half-diagonal, or the distance from
    its frame to the joints it carries (0 when neither is known)."""
    size = 0.0
    if bounds is not None:
        lo, hi = bounds
        with np.errstate(all="ignore"):
            size = 0.5 * float(np.linalg.norm(hi - lo))
    for lk in model.links:
        if lk.parent == index:
            size = max(size, float(np.linalg.norm(lk.p_parent_link)))
    return size if math.isfinite(size) else 0.0


def radius_of_gyration(inertial) -> float:
    """``sqrt(I3 / m)`` [m] of a declared inertial (NaN when it has no positive mass)."""
    if not inertial.mass > 0:
        return math.nan
    with np.errstate(all="ignore"):
        top = float(np.linalg.eigvalsh(0.5 * (inertial.inertia_com_inertial + inertial.inertia_com_inertial.T))[2])
    return math.sqrt(top / inertial.mass) if top > 0 else 0.0


def floor_message(name, mass: float, moments) -> str:
    return (f"link {name!r} moves, but with the links welded to it its mass is {mass:.3g} kg and its principal "
            f"moments {', '.join(f'{x:.3g}' for x in moments)} kg m^2: below {SIMULATOR_MIN_VALUE:g}, the least "
            "MuJoCo accepts for a moving body (\"mass and inertia of moving bodies must be larger than mjMINVAL\"); "
            "a tensor this small is rounding noise or a placeholder: declare the real one, or 'inertia fix "
            "--from-geometry'")
