"""Equivalent particle models: a few point masses with a rigid body's mass, COM and inertia tensor.

A rigid body enters the Newton-Euler (or Lagrange) equations only through its mass, its
centre of mass and its central inertia tensor.  So any set of point masses that reproduces
these three quantities, held rigidly together, moves exactly like the body.  Two constructions
are provided, both in the principal frame P (origin at the COM, principal axes, moments
ascending ``I1 <= I2 <= I3``) and then placed in the body's frame F.

Both use the principal central second moments (see :mod:`inertia.massprops.equivalent`)

    s_i = (I_j + I_k - I_i) / 2 = sum m x_i^2 >= 0    [kg m^2],

which are non-negative for every real body (the triangle inequality of the principal
moments).  A point set reproduces the tensor exactly when its mass is M, its COM is at the
origin of P and ``sum m r r^T = diag(s_i)``, because ``I = tr(S) 1 - S``.

* :func:`six_point_model`: mass M/6 at ``+-d_i`` on each principal axis, with
  ``d_i^2 = 3 s_i / M = 3/(2M) (I_j + I_k - I_i)``.
* :func:`four_point_model`: the minimal model, four masses M/4 at the vertices of a regular
  tetrahedron scaled along the principal axes.

Positions are given in the principal frame (``positions_principal``) and in the body frame F
of the input (``positions_body = p_body_com + R_body_principal @ p_principal``).
:meth:`ParticleModel.positions_world` moves them with a pose.

This layer imports from :mod:`inertia.massprops`; the reverse never happens.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from .._core.errors import InputError
from .._core.tolerances import PHYSICAL_RTOL
from .._core.validation import as_float_array, as_rotation_matrix, as_vector3, frozen_array
from ..massprops.equivalent import flat_findings, principal_second_moments
from ..massprops.properties import MassProperties

__all__ = ["ParticleModel", "six_point_model", "four_point_model"]

#: Vertices of the cube ``[-1, 1]^3`` with an even number of minus signs: a regular
#: tetrahedron centred at the origin.  The unit directions are ``t_k = TETRAHEDRON_SIGNS[k] / sqrt(3)``,
#: with ``sum_k t_k = 0`` and ``sum_k t_k t_k^T = 4/3 * 1``.  The first vertex lies on the
#: (+,+,+) diagonal of the principal frame, which fixes the orientation deterministically.
TETRAHEDRON_SIGNS = np.array([[1.0, 1.0, 1.0],
                              [1.0, -1.0, -1.0],
                              [-1.0, 1.0, -1.0],
                              [-1.0, -1.0, 1.0]])
TETRAHEDRON_SIGNS.setflags(write=False)


@dataclass(frozen=True, eq=False)
class ParticleModel:
    """Point masses, held rigidly together, with the mass, COM and inertia tensor of a body.

    Immutable.  Build one with :func:`six_point_model` or :func:`four_point_model`.  The
    constructor only checks shapes and signs.  ``positions_body`` is computed from the
    principal-frame positions and the pose of the principal frame, so the two always agree.

    Attributes
    ----------
    kind : str
        ``"six_point"``, ``"four_point"`` or a caller's label.
    masses : (n,) float, kg
        Point masses, each > 0.
    positions_principal : (n, 3) float, m
        Point positions in the principal frame P (origin at the COM, principal axes in the
        order of the ascending moments).
    R_body_principal : (3, 3) float
        Proper rotation mapping P coordinates to F coordinates (the principal axes are its
        columns, expressed in F).
    p_body_com : (3,) float, m
        The COM (origin of P) in F.
    frame : str
        Name of the body frame F (from the input MassProperties).
    findings : tuple of Finding
        ``flat_body`` for a flat body (its points coincide or are coplanar).
    positions_body : (n, 3) float, m
        Point positions in the body frame F:
        ``positions_body[k] = p_body_com + R_body_principal @ positions_principal[k]``.
        Computed, not passed.

    Notes
    -----
    Sign convention of the reproduced inertia: negated products, ``I = sum m (|r|^2 1 - r r^T)``,
    so that ``L = I @ omega``.
    """

    kind: str
    masses: np.ndarray
    positions_principal: np.ndarray
    R_body_principal: np.ndarray
    p_body_com: np.ndarray
    frame: str = "body"
    findings: tuple = ()
    positions_body: np.ndarray = field(init=False, repr=False)

    def __post_init__(self):
        m = as_float_array(self.masses, "masses", ())
        p_P = as_float_array(self.positions_principal, "positions_principal", (3,))
        if m.ndim != 1 or m.size == 0 or p_P.shape != (m.shape[0], 3):
            raise InputError(f"expected masses (n,) with n >= 1 and positions_principal (n, 3), "
                             f"got {m.shape} and {p_P.shape}")
        if np.any(m <= 0):
            k = int(np.argmax(m <= 0))
            raise InputError(f"point mass {k} must be positive, got {m[k]:.6g} kg")
        R_body_principal = as_rotation_matrix(self.R_body_principal, "R_body_principal", allow_batch=False)
        p_FBcm = as_vector3(self.p_body_com, "p_body_com")
        if not isinstance(self.frame, str):
            raise InputError(f"frame must be a string name, got {self.frame!r}")
        # r_F = p_FBcm + R_body_principal r_P, for every row
        p_F = p_FBcm + p_P @ R_body_principal.T
        object.__setattr__(self, "masses", frozen_array(m))
        object.__setattr__(self, "positions_principal", frozen_array(p_P))
        object.__setattr__(self, "R_body_principal", frozen_array(R_body_principal))
        object.__setattr__(self, "p_body_com", frozen_array(p_FBcm))
        object.__setattr__(self, "positions_body", frozen_array(p_F))
        object.__setattr__(self, "findings", tuple(self.findings))

    # ------------------------------------------------------------------ queries
    @property
    def n_points(self) -> int:
        """Number of point masses."""
        return int(self.masses.shape[0])

    def __len__(self) -> int:
        return self.n_points

    @property
    def mass(self) -> float:
        """Total mass [kg]."""
        return float(self.masses.sum())

    def positions_world(self, R_world_body, p_world_body=(0.0, 0.0, 0.0)) -> np.ndarray:
        """Point positions in the world frame W for a pose (or a batch of poses) of the body frame F.

        Parameters
        ----------
        R_world_body : (..., 3, 3) float
            Proper rotation(s) mapping F coordinates to W coordinates (``v_W = R_WF @ v_F``).
        p_world_body : (..., 3) float, m
            Origin of F in W (default: the W origin).  Leading dimensions broadcast with
            those of ``R_world_body``.

        Returns
        -------
        (..., n, 3) float, m
            ``r_W[..., k, :] = p_world_body + R_world_body @ positions_body[k]``.

        Examples
        --------
        >>> import numpy as np
        >>> from ..massprops.properties import MassProperties
        >>> from .models import six_point_model
        >>> model = six_point_model(MassProperties(1.0, [0, 0, 0], np.diag([1.0, 2.0, 2.5])))
        >>> model.positions_world(np.eye(3), [0.0, 0.0, 1.0]).shape
        (6, 3)
        >>> model.positions_world(np.broadcast_to(np.eye(3), (10, 3, 3)), np.zeros((10, 3))).shape
        (10, 6, 3)
        """
        R_WF = as_rotation_matrix(R_world_body, "R_world_body", allow_batch=True)
        p_WFo = as_float_array(p_world_body, "p_world_body", (3,), allow_batch=True)
        # r_W = p_WFo + R_WF r_F, for each of the n points, broadcasting the pose batch
        r_W = np.einsum("...ij,nj->...ni", R_WF, self.positions_body)
        return r_W + p_WFo[..., None, :]

    def mass_properties(self) -> MassProperties:
        """Mass properties recomputed from the point masses, in the body frame F.

        Returns
        -------
        MassProperties
            Mass [kg], COM [m] and central inertia [kg m^2] of the points in F.  It equals the
            input of the model to rounding.  Built with ``validate=False``: a set of positive
            point masses is physical by construction, and a flat body lies exactly on the
            triangle inequality, where rounding could tip the check.
        """
        return MassProperties.from_point_masses(self.masses, self.positions_body, frame=self.frame, validate=False)

    def to_dict(self) -> dict:
        """Plain-Python dict (JSON-ready): masses [kg], positions [m] in F and in P, pose of P, frame.

        Keys: ``kind``, ``frame``, ``masses`` (n), ``positions_body`` (n x 3, in F),
        ``positions_principal`` (n x 3, in P), ``R_body_principal`` (3 x 3), ``p_body_com``
        (3), ``findings``.
        """
        return {
            "kind": self.kind,
            "frame": self.frame,
            "masses": self.masses.tolist(),
            "positions_body": self.positions_body.tolist(),
            "positions_principal": self.positions_principal.tolist(),
            "R_body_principal": self.R_body_principal.tolist(),
            "p_body_com": self.p_body_com.tolist(),
            "findings": [f.to_dict() for f in self.findings],
        }

    def __repr__(self) -> str:
        return (f"ParticleModel(kind={self.kind!r}, n_points={self.n_points}, mass={self.mass:.6g}, "
                f"frame={self.frame!r})")


def six_point_model(props: MassProperties, *, rtol: float = PHYSICAL_RTOL) -> ParticleModel:
    """Six equal point masses on the principal axes that reproduce mass, COM and inertia tensor.

    Parameters
    ----------
    props : MassProperties
        The body: mass M [kg], COM [m] and central inertia [kg m^2] in its frame F.
    rtol : float
        The physical-validity tolerance, as for :func:`inertia.massprops.equivalent_box`.

    Returns
    -------
    ParticleModel
        ``kind="six_point"``; masses ``M/6`` each.  Rows ``2i`` and ``2i + 1`` sit at ``+d_i e_i``
        and ``-d_i e_i`` in the principal frame (axis i = 0, 1, 2 in the order of the ascending
        moments).  ``positions_body`` holds the same points in F.

    Raises
    ------
    inertia.errors.NoEquivalentModelError
        The tensor is not physical: a margin ``I_j + I_k - I_i`` is negative beyond the tolerance
        (then ``d_i`` would be imaginary), the tensor is not positive definite, the mass is not
        positive, or the tensor is not symmetric.  The message names each violated inequality
        with its numbers, e.g. ``"no six-point model: I1 + I2 - I3 = -1 < 0 (needs d3^2 = ..."``.

    Notes
    -----
    Pairs of mass ``m = M/6`` at ``+-d_i`` on each
    principal axis have their COM at the origin and no products of inertia.  Their moments are
    ``I_i = 2m (d_j^2 + d_k^2) = M/3 (d_j^2 + d_k^2)``.  Inverting the linear system gives

        d_i^2 = 3/(2M) (I_j + I_k - I_i) = 3 s_i / M.

    The triangle inequality ``I_j + I_k - I_i = 2 sum m x_i^2 >= 0`` holds for every real mass
    distribution, so a physical body always has real ``d_i``.

    Flat body (lamina, ``I1 + I2 = I3``): ``d3 = 0``, so the two points of axis 3 coincide at
    the COM.  The model is still exact, and a warning says so.  A margin that is negative only
    within the tolerance (rounding) is clipped to ``d_i = 0``.

    Examples
    --------
    >>> import numpy as np
    >>> from ..massprops.properties import MassProperties
    >>> from .models import six_point_model
    >>> props = MassProperties(6.0, [0.0, 0.0, 1.0], np.diag([2.0, 2.0, 2.0]))
    >>> model = six_point_model(props)
    >>> model.masses.shape, model.positions_body.shape
    ((6,), (6, 3))
    >>> model.positions_principal[0].tolist()   # d_i^2 = 3/(2*6) * 2 = 0.5
    [0.7071067811865476, 0.0, 0.0]
    >>> model.mass_properties().isclose(props)
    True
    """
    sm = principal_second_moments(props, model="six-point model", symbol="d", factor=3.0, rtol=rtol)
    M = props.mass
    d = np.sqrt(3.0 * sm.second_moments / M)  # d_i^2 = 3 s_i / M, metres
    p_P = np.zeros((6, 3))
    for i in range(3):
        p_P[2 * i, i] = d[i]
        p_P[2 * i + 1, i] = 0.0 - d[i]  # 0.0 - 0.0 is +0.0: no "-0.0" for a flat axis
    notes = flat_findings(sm, lambda i: f"d{i + 1} = {d[i]:.3g} m, so points {2 * i} and {2 * i + 1} "
                                      f"(+-d{i + 1} on principal axis {i + 1}) coincide at the COM")
    pf = sm.principal
    return ParticleModel("six_point", np.full(6, M / 6.0), p_P, pf.R_body_principal, pf.p_body_com,
                         frame=props.frame, findings=notes)


def four_point_model(props: MassProperties, *, rtol: float = PHYSICAL_RTOL) -> ParticleModel:
    """The minimal particle model: four equal masses that reproduce mass, COM and inertia tensor.

    ``props`` and ``rtol`` as for :func:`six_point_model`.

    Returns
    -------
    ParticleModel
        ``kind="four_point"``; masses ``M/4`` each.  In the principal frame, row k sits at
        ``(sigma_k1 c1, sigma_k2 c2, sigma_k3 c3)`` with ``c_i = sqrt(s_i / M)`` and the signs
        ``sigma_k`` the rows of :data:`TETRAHEDRON_SIGNS`: (+,+,+), (+,-,-), (-,+,-), (-,-,+).

    Raises
    ------
    inertia.errors.NoEquivalentModelError
        As :func:`six_point_model`: the tensor is not physical.

    Notes
    -----
    Construction.  In the principal frame P the central second-moment matrix of the body is
    ``S = sum m r r^T = diag(s_i)`` with ``s_i = (I_j + I_k - I_i)/2``.  Take the unit directions of a
    regular tetrahedron, ``t_k = sigma_k / sqrt(3)``, for which ``sum_k t_k = 0`` and
    ``sum_k t_k t_k^T = 4/3 * 1``.  Scale them per axis:

        r_k = sqrt(3) diag(sqrt(s_i / M)) t_k = diag(c_i) sigma_k,    m_k = M/4.

    Then ``sum m_k r_k = 0`` (COM at the origin).  Also ``sum m_k r_k r_k^T = (M/4) 3 D (4/3) D = M D^2
    = diag(s_i)`` with ``D = diag(c_i)``, so mass, COM and the full tensor
    ``I = tr(S) 1 - S`` are reproduced.  In floating point the off-diagonal sums and the COM
    cancel exactly, because each is a sum of ``+-c_i c_j`` with two signs of each kind.

    Minimality.  Any three points are coplanar, and their COM lies in their plane.  With the
    plane normal ``n``, ``n^T S n = sum m (n . r)^2 = 0``.  So ``n`` is a principal axis with
    ``s_n = 0``, which forces the flat-plate equality ``I_n = I_a + I_b`` (``I1 + I2 = I3``).  A
    tensor with a strict triangle inequality therefore needs at least four points, and four
    suffice.  (Two points are collinear and give a zero moment.)

    Orientation.  The tetrahedron is fixed in P (first vertex on the (+,+,+) diagonal).  P itself
    follows the deterministic canonical rule of :mod:`inertia.massprops.principal`, including
    its rule for repeated moments, so the model is a deterministic function of ``props``.

    Flat body (``I1 + I2 = I3``): ``c3 = 0``, and the four points form a rectangle in the
    plane normal to principal axis 3.  The model is still exact, and a warning says so.

    Examples
    --------
    >>> import numpy as np
    >>> from ..massprops.properties import MassProperties
    >>> from .models import four_point_model
    >>> sphere = MassProperties(4.0, [0.0, 0.0, 0.0], 0.4 * 4.0 * 0.5**2 * np.eye(3))
    >>> model = four_point_model(sphere)
    >>> model.positions_body.shape
    (4, 3)
    >>> model.mass_properties().isclose(sphere)
    True
    """
    sm = principal_second_moments(props, model="four-point model", symbol="c", factor=1.0, rtol=rtol)
    M = props.mass
    c = np.sqrt(sm.second_moments / M)  # c_i^2 = s_i / M, metres
    p_P = TETRAHEDRON_SIGNS * c + 0.0  # r_k = diag(c) sigma_k; "+ 0.0" turns -0.0 (flat axis) into +0.0
    notes = flat_findings(sm, lambda i: f"c{i + 1} = {c[i]:.3g} m, so the four points lie in the plane normal to "
                                      f"principal axis {i + 1}")
    pf = sm.principal
    return ParticleModel("four_point", np.full(4, M / 4.0), p_P, pf.R_body_principal, pf.p_body_com,
                         frame=props.frame, findings=notes)
