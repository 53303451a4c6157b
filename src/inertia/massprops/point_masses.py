"""Mass properties of a system of point masses."""

from __future__ import annotations


def point_masses(masses, positions, *, frame: str = "body", validate: bool = True):
    """Mass properties of point masses (N,) kg at positions (N, 3) m.

    ``I_ij = sum_k m_k (|r_k|^2 delta_ij - r_ki r_kj)`` with r relative to the COM.
    Fewer than three non-collinear points give a zero principal moment, which fails
    validation unless ``validate=False``.  For the raw tensor about an arbitrary origin
    with batch dimensions use :func:`inertia.massprops.point_mass_inertia`.
    """
    from .properties import MassProperties

    return MassProperties.from_point_masses(masses, positions, frame=frame, validate=validate)
