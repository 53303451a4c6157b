"""What MuJoCo's compiler computes for a geom's mass and inertia, mode by mode.

A body whose inertia MuJoCo infers from its geoms (``inertiafromgeom``) is simulated with
the compiler's numbers, not the exact solid's.  For meshes these depend on
``<mesh inertia="...">`` (MuJoCo's XML reference, *asset/mesh/inertia*; its source,
``user_mesh.cc``: ``ComputeFaceCentroid``, ``ComputeVolume``, ``ComputeInertia``):

* ``legacy`` (MuJoCo's default): each face spans a pyramid with an apex; the pyramids'
  volumes are taken as **absolute values**.  Exact for convex meshes; a non-convex mesh
  counts the volume outside its concave parts (so_arm100's ``Base``: +72 % mass), and an
  open mesh still gets a number.  The center of mass comes from pyramids with their apex at
  the area-weighted centroid of the faces; volume and inertia from pyramids with their apex
  at that center of mass (the two passes differ for non-convex meshes, as in MuJoCo).
* ``convex``: the exact solid of the mesh's convex hull.
* ``exact``: signed pyramids (the exact solid of a closed, consistently wound mesh; MuJoCo
  refuses inconsistent winding, and an open mesh gets an apex-dependent number).
* ``shell``: the surface carries the mass (density per unit area).

Vertices are rounded to float32 as MuJoCo stores them, then scaled in double; faces whose
cross product is shorter than ``mjMINVAL`` (1e-15) count as zero area.  Primitive geoms with
``shellinertia="true"`` use MuJoCo's shell formulas (exact for sphere, box, cylinder and
capsule; for the ellipsoid MuJoCo's surface area is Thomsen's approximation and its inertia
that of a 1e-6 m thick homoeoid layer, reproduced here so that the check sees what the
simulator simulates).  A primitive given a mesh and no usable size (``<geom type="box"
mesh="m">``) is fitted as MuJoCo fits it (``FitGeom``): to the equivalent inertia box of the
mesh, or its axis-aligned box in the principal frame with ``<compiler fitaabb="true">``,
times ``fitscale``, placed at the mesh's center of mass and principal axes.
"""

from __future__ import annotations

import math

import numpy as np

from .._core.errors import InertiaError

#: MuJoCo's smallest denominator (``mjMINVAL``): faces with a shorter cross product have no area
MJ_MINVAL = 1e-15

#: ``<mesh inertia=...>`` values, MuJoCo's default first
MESH_INERTIA_MODES = ("legacy", "convex", "exact", "shell")

#: the code of the InertiaError raised where MuJoCo's compiler refuses a mesh (the model does not load)
MUJOCO_REFUSES_MESH = "mujoco_refuses_mesh"


def check_orientation(vertices: np.ndarray, faces: np.ndarray) -> None:
    """MuJoCo's refusal of a mesh in ``exact`` mode whose faces are not consistently wound: a
    directed edge shared by two faces (``Process`` in user_mesh.cc: faces of area up to
    sqrt(mjMINVAL) in the file's units are not counted; vertices as in the file, before scale)."""
    v, f = np.asarray(vertices, float), np.asarray(faces, np.int64)
    D, E, F = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(E - D, F - D)
    f = f[0.5 * np.sqrt(np.einsum("ij,ij->i", cross, cross)) > math.sqrt(MJ_MINVAL)]
    key = np.sort((f * len(v) + np.roll(f, -1, axis=1)).ravel())  # directed edge a -> b as a * V + b
    twice = key[1:][key[1:] == key[:-1]]
    if len(twice):
        a, b = divmod(int(twice[0]), len(v))
        raise InertiaError(f"faces of the mesh have inconsistent orientation: two faces run from vertex {a + 1} to "
                           f"vertex {b + 1} (MuJoCo refuses it in inertia=\"exact\")", code=MUJOCO_REFUSES_MESH)


def _faces_geometry(v: np.ndarray, f: np.ndarray):
    """Per-face area, unit normal and centroid, with MuJoCo's small-face rule."""
    D, E, F = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    cross = np.cross(E - D, F - D)
    length = np.sqrt(np.einsum("ij,ij->i", cross, cross))
    keep = length >= MJ_MINVAL
    area = np.where(keep, length / 2, 0.0)
    normal = np.zeros_like(cross)
    normal[keep] = cross[keep] / length[keep, None]
    return area, normal, (D + E + F) / 3, (D, E, F)


def hull_faces(v: np.ndarray) -> np.ndarray:
    """Outward-wound triangles of the convex hull of ``v`` (qhull, as MuJoCo)."""
    from scipy.spatial import ConvexHull, QhullError

    try:
        hull = ConvexHull(v)
    except (QhullError, ValueError) as exc:
        raise InertiaError(f"the convex hull of the mesh cannot be built (a flat or degenerate mesh): "
                           f"{str(exc).splitlines()[0]}") from None
    f = hull.simplices.copy()
    D, E, F = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    inward = np.einsum("ij,ij->i", np.cross(E - D, F - D), hull.equations[:, :3]) < 0
    f[inward] = f[inward][:, ::-1]
    return f


def mesh_inertia(vertices, faces, mode: str = "legacy"):
    """MuJoCo's ``(measure, com, inertia_per_density)`` of a mesh in ``mode``.

    Parameters
    ----------
    vertices : (N, 3) float
        Vertex coordinates [m] in the mesh file's axes, already scaled (MuJoCo's ``scale``).
    faces : (F, 3) int
        Triangles as in the file.
    mode : {"legacy", "convex", "exact", "shell"}

    Returns
    -------
    measure : float
        Volume [m^3] (area [m^2] for ``shell``): the geom's mass is ``density * measure``.
    com : (3,) float
        Center of mass [m], mesh axes.
    inertia : (3, 3) float
        Inertia about ``com`` per unit density [m^5, or m^4 for shell], negated products.

    Raises
    ------
    InertiaError
        Where MuJoCo's compiler refuses the mesh, with its reason.
    """
    if mode not in MESH_INERTIA_MODES:
        raise InertiaError(f"mesh inertia {mode!r} is none of {', '.join(MESH_INERTIA_MODES)}")
    v = np.asarray(vertices, float)
    f = np.asarray(faces, np.int64)
    area, normal, center, _ = _faces_geometry(v, f)
    total_area = float(area.sum())
    if not total_area >= MJ_MINVAL:
        raise InertiaError("mesh surface area is too small (MuJoCo refuses it)", code=MUJOCO_REFUSES_MESH)
    facecen = (area[:, None] * center).sum(axis=0) / total_area
    if mode == "convex":
        f = hull_faces(v)
        area, normal, center, _ = _faces_geometry(v, f)
    if mode == "shell":
        weight = area
    else:
        weight = np.einsum("ij,ij->i", center - facecen, normal) * area / 3
        if mode == "legacy":
            weight = np.abs(weight)
    total = float(weight.sum())
    if mode != "shell" and not total >= MJ_MINVAL:
        if total < 0:
            raise InertiaError("mesh volume is negative (misoriented triangles; MuJoCo refuses it)",
                               code=MUJOCO_REFUSES_MESH)
        raise InertiaError("mesh volume is too small (MuJoCo refuses it; it suggests inertia=\"shell\")",
                           code=MUJOCO_REFUSES_MESH)
    com = (weight[:, None] * (center * 0.75 + facecen * 0.25)).sum(axis=0) / total
    measure, inertia = _second_moments(v - com, f, mode)
    return measure, com, inertia


def _second_moments(vc: np.ndarray, f: np.ndarray, mode: str):
    """``(measure, inertia)`` about the origin of ``vc`` (ComputeInertia's pass)."""
    area, normal, center, (D, E, F) = _faces_geometry(vc, f)
    if mode == "shell":
        weight, C = area, 12.0
    else:
        weight, C = np.einsum("ij,ij->i", center, normal) * area / 3, 20.0
        if mode == "legacy":
            weight = np.abs(weight)
    S = D + E + F
    # sum over the triangle of x_i x_j, doubled on the vertices, plus the cross terms
    P = (np.einsum("ni,nj->ij", weight[:, None] * D, D) + np.einsum("ni,nj->ij", weight[:, None] * E, E)
         + np.einsum("ni,nj->ij", weight[:, None] * F, F) + np.einsum("ni,nj->ij", weight[:, None] * S, S)) / C
    inertia = np.trace(P) * np.eye(3) - P
    return float(weight.sum()), inertia


def _quat_mul(a, b):
    w1, x1, y1, z1 = a
    w2, x2, y2, z2 = b
    return np.array([w1 * w2 - x1 * x2 - y1 * y2 - z1 * z2, w1 * x2 + x1 * w2 + y1 * z2 - z1 * y2,
                     w1 * y2 - x1 * z2 + y1 * w2 + z1 * x2, w1 * z2 + x1 * y2 - y1 * x2 + z1 * w2])


def _quat_matrix(q):
    from .._core.rotations import quat_to_matrix

    return quat_to_matrix(q / np.linalg.norm(q))


#: MuJoCo's Jacobi tolerance (``kEigEPS``): it stops rotating below about 1.4e-6 rad
_EIG_EPS = 1e-12


def principal_descending(inertia: np.ndarray):
    """Principal moments in decreasing order and the axes as MuJoCo's compiler finds them.

    MuJoCo's ``mjuu_eig3`` runs Jacobi rotations accumulated in a quaternion and stops when a
    rotation's cosine exceeds ``1 - 1e-12``, so its axes are good to about 1e-6 rad; a fitted
    primitive is placed in those axes, so this follows the same iteration to give the same
    frame (eigenvalues within 1e-12 are not reordered).  Returns ``(moments, R)`` with the
    axes as the columns of the proper rotation ``R``.
    """
    A = np.asarray(inertia, float)
    q = np.array([1.0, 0.0, 0.0, 0.0])
    for _ in range(500):
        V = _quat_matrix(q)
        D = V.T @ A @ V
        ev = np.diag(D).copy()
        if abs(D[0, 1]) > abs(D[0, 2]) and abs(D[0, 1]) > abs(D[1, 2]):
            r, c, k = 0, 1, 2
        elif abs(D[0, 2]) > abs(D[1, 2]):
            r, c, k = 0, 2, 1
        else:
            r, c, k = 1, 2, 0
        if abs(D[r, c]) < _EIG_EPS:
            break
        tau = (D[c, c] - D[r, r]) / (2 * D[r, c])
        t = 1.0 / (tau + math.sqrt(1 + tau * tau)) if tau >= 0 else -1.0 / (-tau + math.sqrt(1 + tau * tau))
        cos = 1.0 / math.sqrt(1 + t * t)
        if cos > 1.0 - _EIG_EPS:
            break
        step = np.zeros(4)
        step[k + 1] = -math.sqrt(0.5 - 0.5 * cos) if tau >= 0 else math.sqrt(0.5 - 0.5 * cos)
        if k == 1:
            step[k + 1] = -step[k + 1]
        step[0] = math.sqrt(1.0 - step[k + 1] ** 2)
        q = _quat_mul(q, step / np.linalg.norm(step))
        q /= np.linalg.norm(q)
    for j in range(3):  # decreasing order: swap neighbours (0, 1, 0) with a quarter turn
        a = j % 2
        if ev[a] + _EIG_EPS < ev[a + 1]:
            ev[a], ev[a + 1] = ev[a + 1], ev[a]
            turn = np.zeros(4)
            turn[0] = turn[(a + 2) % 3 + 1] = math.sqrt(0.5)
            q = _quat_mul(q, turn)
            q /= np.linalg.norm(q)
    return ev, _quat_matrix(q)


def inertia_box(moments_desc: np.ndarray, measure: float) -> np.ndarray:
    """Half sizes of MuJoCo's equivalent inertia box (``boxsz``) of unit-density moments."""
    e0, e1, e2 = moments_desc
    with np.errstate(invalid="ignore"):
        return 0.5 * np.sqrt(6 * np.array([e1 + e2 - e0, e0 + e2 - e1, e0 + e1 - e2]) / measure)


def check_mesh_inertia(moments: np.ndarray) -> None:
    """MuJoCo's compile-time checks on a mesh's principal moments (``Process``), smallest first."""
    e = moments
    if not e[0] > 0:
        raise InertiaError("eigenvalue of mesh inertia must be positive (MuJoCo refuses it)", code=MUJOCO_REFUSES_MESH)
    tol = lambda c: c * (1.0 - 1e-6) - 1e-9  # noqa: E731  (MuJoCo's inequality tolerance)
    if e[0] + e[1] < tol(e[2]) or e[0] + e[2] < tol(e[1]) or e[1] + e[2] < tol(e[0]):
        raise InertiaError("eigenvalues of mesh inertia violate A + B >= C (MuJoCo refuses it)",
                           code=MUJOCO_REFUSES_MESH)


def fit_primitive(kind: str, vertices, faces, mode: str, *, fitaabb: bool = False, fitscale: float = 1.0):
    """MuJoCo's fit of a primitive to a mesh: ``(size, R_mesh_geom, p_mesh_geom)``.

    ``size`` is MuJoCo's geom size (half lengths; capsule and cylinder: radius, half
    height), ``R_mesh_geom``/``p_mesh_geom`` the fitted geom's frame in the mesh's axes:
    the principal frame at the center of mass (of ``mode``), shifted to the axis-aligned
    box's center with ``fitaabb``.
    """
    measure, com, inertia = mesh_inertia(vertices, faces, mode)
    moments, R = principal_descending(inertia)
    check_mesh_inertia(moments[::-1])
    center = np.zeros(3)
    if not fitaabb:
        b = inertia_box(moments, measure)
        if kind == "sphere":
            size = [b.sum() / 3]
        elif kind == "capsule":
            r = (b[0] + b[1]) / 2
            size = [r, max(0.0, b[2] - r / 2)]
        elif kind == "cylinder":
            size = [(b[0] + b[1]) / 2, b[2]]
        elif kind in ("box", "ellipsoid"):
            size = list(b)
        else:
            raise InertiaError(f"a {kind} cannot be fitted to a mesh")
    else:
        local = (np.asarray(vertices, float) - com) @ R
        lo, hi = local.min(axis=0), local.max(axis=0)
        center = (lo + hi) / 2
        half = hi - center
        if kind == "sphere":
            size = [float(half.max())]
        elif kind in ("capsule", "cylinder"):
            r = float(max(half[0], half[1]))
            size = [r, float(half[2]) - (r if kind == "capsule" else 0.0)]
        elif kind in ("box", "ellipsoid"):
            size = list(half)
        else:
            raise InertiaError(f"a {kind} cannot be fitted to a mesh")
    size = [float(s) * fitscale for s in size]
    return size, R, com + R @ center


def ellipsoid_shell(semi_axes, mass: float) -> tuple[float, np.ndarray]:
    """MuJoCo's ``(area, principal moments)`` of an ellipsoid shell of ``mass`` (see module)."""
    a, b, c = (float(s) for s in semi_axes)
    p = 1.6075
    area = 4 * math.pi * (((a * b) ** p + (b * c) ** p + (c * a) ** p) / 3) ** (1 / p)
    eps = 1e-6
    va = 4 * math.pi * a * b * c / 3
    ae, be, ce = a + eps, b + eps, c + eps
    vb = 4 * math.pi * ae * be * ce / 3
    rho = mass / (vb - va)
    ma, mb = va * rho, vb * rho
    inner = ma * np.array([b * b + c * c, a * a + c * c, a * a + b * b]) / 5
    outer = mb * np.array([be * be + ce * ce, ae * ae + ce * ce, ae * ae + be * be]) / 5
    return area, outer - inner
