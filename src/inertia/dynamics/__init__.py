"""Rotational dynamics: Euler's equations, integrators, the exact solution, the flip, 6-DOF transitions."""
