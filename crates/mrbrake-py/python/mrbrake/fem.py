"""General axisymmetric problems from problem files (``mrbrake fem solve``): non-linear
magnetostatics (and its transient / harmonic variants) or ``physics = "heat"``. Lengths in the
units of the file's ``length_unit``, results in SI."""

import os

from . import _native
from ._native import FemSolution

__all__ = ["FemSolution", "solve"]


def solve(problem, order=None):
    """Solve the problem file at ``problem`` (a path; meshes and curves it names are read relative
    to it). ``order`` (1 or 2) replaces the file's element order.

    Returns a :class:`FemSolution`: ``to_dict()`` is ``mrbrake fem solve PROBLEM --json`` (probes,
    region results, energy, timings), ``field()`` gives ``(nodes (N, 2) in m, triangles (M, 3),
    values)`` with |B| per triangle in T (magnetostatics) or the temperature per node in degC
    (heat), ``flux_function()`` the flux lines' function (Wb/rad).

    Raises ``ValueError`` for a bad file (the CLI's message), :class:`mrbrake.SolverError` when
    the solve fails numerically.
    """
    return _native.fem_solve(os.fspath(problem), order)
