"""mrbrake: design, simulate and characterise MR-fluid brakes for haptic devices.

The Python face of the mrbrake Rust crates (a thin PyO3 binding; the numerics are the library's,
the same as the ``mrbrake`` command-line program's). SI units throughout: metres, amperes,
newton-metres, tesla, seconds; quantities may also be given as strings with a unit ("60rpm").

Main entry points:

- :func:`analyze`: field, torque-current curve, gaps, coil and mechanics of a brake design.
- :mod:`mrbrake.materials`: the built-in material library (curves as NumPy arrays, provenance).
- :mod:`mrbrake.fem`: general problem files (magnetostatics, heat), as ``mrbrake fem solve``.
- :mod:`mrbrake.store`: the results store of design studies (``load``: a table).
- :mod:`mrbrake.sysid`: hysteresis characterisation, frequency response, transfer-function fits.

Errors: ``ValueError`` for bad input (the CLI's message), ``OSError`` for I/O failures,
:class:`SolverError` for numerical failures, ``RuntimeError`` for internal ones.
Long computations release the GIL, so threads run analyses in parallel.
"""

from . import _native
from ._native import Analysis, SolverError, __version__

__all__ = ["Analysis", "SolverError", "analyze", "fem", "materials", "store", "sysid", "__version__"]


def analyze(spec=None, mesh="default", order=1, currents=None, *, speed=None,
            seal_friction=None, temperature=None):
    """Analyse a brake design: the non-linear axisymmetric field at each current of a sweep, the
    torque-current curve, per-gap results, coil and mechanics (``mrbrake analyze``).

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        ``None``: the embedded thesis bidirectional brake. A path to a TOML spec, TOML text (a
        string containing ``=`` or a newline), or a dict with the TOML file's keys and tables.
    mesh : {"coarse", "default", "fine"}
        Mesh density.
    order : {1, 2}
        Element order of the field solution (2: quadratic triangles, about 4x the unknowns).
    currents : int, optional
        Number of currents of the sweep, evenly spaced from 0 to the maximum current (>= 2;
        default 21, the CLI's ``--points``).
    speed : float (rad/s) or str, optional
        Relative speed for the viscous torque; default ``"1rad/s"``.
    seal_friction : float (N*m) or str, optional
        Seal and bearing friction added to every torque; default ``"0Nm"``.
    temperature : float (degC) or str, optional
        Copper temperature for the coil resistance; default ``"20C"``.

    Returns
    -------
    Analysis
        Attributes (``torque_nm``, ``current_a``, ``coil``, ``gaps``, ...), ``to_dict()`` with the
        keys of ``mrbrake analyze --json``, ``field()`` for matplotlib's ``tripcolor``.

    Raises
    ------
    ValueError
        Invalid spec or argument (message as the CLI's).
    SolverError
        The field solution failed numerically.
    """
    return _native.analyze(spec, mesh, order, currents, speed=speed,
                           seal_friction=seal_friction, temperature=temperature)


from . import fem, materials, store, sysid  # noqa: E402  (submodules use the names above)
