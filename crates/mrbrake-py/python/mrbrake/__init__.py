"""mrbrake: design, simulate and characterise MR-fluid brakes for haptic devices.

The Python face of the mrbrake Rust crates (a thin PyO3 binding; the numerics are the library's,
the same as the ``mrbrake`` command-line program's). SI units throughout: metres, amperes,
newton-metres, tesla, seconds; quantities may also be given as strings with a unit ("60rpm").

Main entry points:

- :func:`analyze`: field, torque-current curve, gaps, coil and mechanics of a brake design.
- :mod:`mrbrake.materials`: the built-in material library (curves as NumPy arrays, provenance).
- :mod:`mrbrake.formula`: the thesis's closed-form torque and coil models.
- :mod:`mrbrake.haptic`: the 1-DOF haptic wall simulation (metrics, time histories as arrays).
- :mod:`mrbrake.rig`: the virtual test rig's characterisation log as arrays.
- :mod:`mrbrake.fem`: general problem files (magnetostatics, heat), as ``mrbrake fem solve``.
- :func:`sweep`, :func:`optimize`: design studies into a results store (``mrbrake sweep``,
  ``mrbrake optimize``).
- :func:`response`: the predicted dynamics (step responses, frequency response; ``mrbrake
  response``).
- :func:`thermal`: temperatures, warm-up, continuous rating and hot behaviour (``mrbrake
  thermal``).
- :func:`report`: the self-contained HTML report of a design, a store or a rig log (``mrbrake
  report``).
- :func:`calibrate`: spec fields fitted to a rig log's loop (``mrbrake calibrate``).
- :mod:`mrbrake.store`: the results store of design studies (``load``: a table).
- :mod:`mrbrake.sysid`: hysteresis characterisation, frequency response, transfer-function fits.

Errors: ``ValueError`` for bad input (the CLI's message), ``FileNotFoundError`` for a missing
input file, ``OSError`` for other I/O failures,
:class:`SolverError` for numerical failures, ``RuntimeError`` for internal ones.
Long computations release the GIL, so threads run analyses in parallel.
"""

from . import _native
from ._native import Analysis, SolverError, __version__

__all__ = ["Analysis", "SolverError", "analyze", "calibrate", "fem", "formula", "haptic", "materials", "optimize",
           "report", "response", "rig", "store", "sweep", "sysid", "thermal",
           "__version__"]


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


def _pairs(values, what):
    """``NAME=VALUES`` strings from a dict (values: a string with units, a number in SI or a
    list of them) or a list of strings."""
    if values is None:
        return []
    if isinstance(values, str):
        values = [values]
    if isinstance(values, dict):
        out = []
        for name, v in values.items():
            if isinstance(v, (list, tuple)):
                v = ",".join(x if isinstance(x, str) else repr(float(x)) for x in v)
            elif not isinstance(v, str):
                v = repr(v)
            out.append(f"{name}={v}")
        return out
    out = [str(v) for v in values]
    for v in out:
        if "=" not in v:
            raise ValueError(f"{what} '{v}': expected NAME=VALUE")
    return out


def sweep(spec=None, vary=None, *, store, set=None, sample=None, seed=1, resume=False, jobs=0,
          shard=None, mesh="default", order=1, speed=None):
    """A parameter sweep over brake-spec fields into a results store (``mrbrake sweep``): every
    design is a full analysis, stored the moment it completes; stored designs are not recomputed.

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        The base spec, as for :func:`analyze` (``None``: the embedded thesis brake).
    vary : dict or list of str
        The variables and their values: ``{"g": "0.5mm,0.75mm", "h": [0.007, 0.009]}`` (numbers
        in SI: m, A) or the CLI's ``--vary`` strings ``["g=0.5mm,0.75mm", "h=5mm..10mm:6",
        "R0=20mm..30mm"]`` (bounds need ``sample``). Names: spec fields (``drum.gap``) or thesis
        symbols (g, h, d, R0, R1, R2, n, N, I, AWG).
    store : str or os.PathLike
        The SQLite results store; created if missing, an existing one needs ``resume=True``.
    set : dict or list of str, optional
        Fixed changes to the base spec (``{"coil.turns": "fill"}``), the CLI's ``--set``.
    sample : str, optional
        ``"lhs:N"`` (Latin hypercube, seeded by ``seed``) or ``"sobol:N"`` instead of the full
        factorial grid.
    resume : bool
        Continue an existing store.
    jobs : int
        Analyses run at the same time (0: one per core).
    shard : str, optional
        ``"K/N"``: evaluate only shard K of N of the plan.
    mesh, order : str, int
        Mesh density and element order of every analysis.
    speed : float (rad/s) or str, optional
        Relative speed for the off-state torque; default ``"1rad/s"``.

    Returns
    -------
    dict
        The document of ``mrbrake sweep --json``: the designs (key, status, variables, metrics in
        SI) and the run's summary. :func:`mrbrake.store.load` reads the store back as a table.

    Raises ``ValueError`` for bad input (the CLI's message), ``OSError`` for an unreadable spec
    or an unwritable store. Runs without the GIL.
    """
    overrides = [tuple(p.split("=", 1)) for p in _pairs(set, "set")]
    overrides = [(k.strip(), v.strip()) for k, v in overrides]
    return _native.sweep(spec, _pairs(vary, "vary"), str(store), overrides, sample=sample,
                         seed=seed, resume=resume, jobs=jobs, shard=shard, mesh=mesh, order=order,
                         speed=speed)


def optimize(problem, store=None, *, resume=False, jobs=0, out=None, max_evaluations=None,
             generations=None, seed=None, set=None):
    """A constrained single- or multi-objective optimisation of a brake design (``mrbrake
    optimize``): NSGA-II or pattern search as the problem file says, every evaluation a full
    analysis through the results store.

    Parameters
    ----------
    problem : str or os.PathLike
        The problem file (TOML: base spec, variables with bounds, constraints, objectives,
        algorithm; see ``mrbrake optimize --help``).
    store : str or os.PathLike, optional
        The SQLite results store; default ``<problem stem>.sqlite`` in the current folder. An
        existing store needs ``resume=True``.
    jobs : int
        Analyses run at the same time (0: one per core).
    out : str or os.PathLike, optional
        Also write the CLI's ``--out`` folder (evaluations.csv, pareto.csv, plots, front designs).
    max_evaluations : int, optional
        The most designs to evaluate, overriding the problem's budget (the CLI's
        ``--max-evaluations``; for NSGA-II the generations that fit in it).
    generations : int, optional
        NSGA-II generations after the initial population (``--generations``).
    seed : int, optional
        The seed instead of the problem's ``algorithm.seed`` (``--seed``).
    set : dict or list of str, optional
        Fixed changes to the base spec after the problem's ``[set]`` (``{"materials.bobbin":
        "pom"}`` or ``["coil.turns=fill"]``), the CLI's ``--set``; a variable on the same field
        is then fixed at that value.

    Returns
    -------
    dict
        The document of ``mrbrake optimize --json`` (the front, the reference design, counts).

    Raises ``ValueError`` for a bad problem file or keyword (the CLI's message),
    ``FileNotFoundError`` for a missing problem file. Runs without the GIL.
    """
    return _native.optimize_problem(str(problem), None if store is None else str(store),
                                    resume=resume, jobs=jobs,
                                    out=None if out is None else str(out),
                                    generations=generations, max_evaluations=max_evaluations,
                                    seed=seed, set=_pairs(set, "set"))


from . import fem, formula, haptic, materials, rig, store, sysid  # noqa: E402  (submodules use the names above)


def calibrate(spec=None, *, log, parameters, set=None, frd=None, points=11, max_evaluations=120,
              jobs=0, mesh="default", order=1, speed=None, record=None):
    """Fit spec fields so the design's predicted torque-current curve (the FEA at every trial
    point) matches a rig log's loop (``mrbrake calibrate``), with standard errors, correlations
    and the parameter groups the data cannot separate.

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        The spec to calibrate, as for :func:`analyze` (``None``: the embedded thesis brake).
    log : str or os.PathLike
        A repeated-ramp characterisation log (``time_s, current_A, torque_Nm``), as
        ``mrbrake rig characterize`` writes it; its currents must reach the maximum current.
    parameters : list of str
        The fields to fit: ``"PATH"`` (bounds 0.5x to 1.5x its value) or ``"PATH=LOW..HIGH"``
        with units (``"drum.gap=0.4mm..0.8mm"``, ``"fluid.yield_stress_scale=0.5..1.2"``).
    set : dict or list of str, optional
        Fixed changes before fitting (``{"drag.seals_per_rotor": 2}``), the CLI's ``--set``.
    frd : str or os.PathLike, optional
        Frequency-response data of the same brake (``mrbrake freqresp``), fitted as well.
    points : int
        Currents compared, evenly from 0 to the maximum current.
    max_evaluations : int
        Most residual evaluations (each an FEA of the curve).
    jobs : int
        Analyses run at the same time (0: one per core).
    mesh, order, speed
        As for :func:`sweep`.
    record : list of str, optional
        Study metrics (e.g. ``"bandwidth_rad_s"``) predicted before and after.

    Returns
    -------
    dict
        The document of ``mrbrake calibrate --json`` (``parameters`` with ``estimate`` and
        ``standard_error`` in SI, ``correlation``, ``unidentifiable``, residuals, ``curve``), plus
        ``calibrated_spec``: the spec's text with the estimates (what ``-o`` writes).

    Raises ``ValueError`` for bad input (the CLI's message), ``OSError`` for an unreadable log,
    :class:`SolverError` when an analysis fails. Runs without the GIL.
    """
    overrides = [tuple(p.split("=", 1)) for p in _pairs(set, "set")]
    overrides = [(k.strip(), v.strip()) for k, v in overrides]
    if isinstance(parameters, str):
        parameters = [parameters]
    return _native.calibrate(spec, str(log), list(parameters), overrides,
                             frd=None if frd is None else str(frd), points=points,
                             max_evaluations=max_evaluations, jobs=jobs, mesh=mesh, order=order,
                             speed=speed, record=list(record or []))


def response(spec=None, mesh="default", *, drive="current", duration=None, step=None, bias=None,
             fluid_lag=None, conductivity=None):
    """The predicted dynamics of a brake design (``mrbrake response``): the torque's step response
    per direction (eddy currents in the flux path, the coil circuit, the fluid's lag) and the
    small-signal frequency response with its -3 dB bandwidth.

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        As for :func:`analyze` (``None``: the embedded thesis brake).
    mesh : str
        Mesh density.
    drive : str
        ``"current"`` (an ideal current source) or ``"voltage"`` (a voltage step on the coil).
    duration : float (s) or str, optional
        Length of the step responses; default ``"100ms"``.
    step : str, optional
        The current step ``"FROM..TO"`` (``"0A..2A"``); default 0 A to the maximum current.
    bias : float (A) or str, optional
        DC bias of the frequency response; default half the maximum current.
    fluid_lag : float (s) or str, optional
        First-order lag of the fluid's yield stress; default the library's.
    conductivity : float (S/m) or str, optional
        The flux-path steel's conductivity instead of the spec's or the library's.

    Returns
    -------
    dict
        The document of ``mrbrake response --json`` (``step`` per direction with ``t63_s``,
        ``t90_s`` and the time histories, ``frequency_response`` points, ``bandwidth_rad_s``), SI.

    Raises ``ValueError`` for bad input (the CLI's message), ``OSError`` for an unreadable spec,
    :class:`SolverError` when a solve fails. Runs without the GIL.
    """
    return _native.response(spec, mesh, drive=drive, duration=duration, step=step, bias=bias,
                            fluid_lag=fluid_lag, conductivity=conductivity)


def thermal(spec=None, mesh="default", *, current=None, duty=1.0, period=None, ambient=None, h=None,
            emissivity=0.0, insulation_class="155C", time=None, dt=None, speed=None,
            behaviour=True):
    """The brake's temperatures and heat ratings (``mrbrake thermal``): steady hot spot at a
    current and duty cycle, warm-up, time to the insulation limit, continuous current, largest
    duty at the maximum current, and (``behaviour``) what heat does to the brake.

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        As for :func:`analyze` (``None``: the embedded thesis brake).
    mesh : str
        Mesh density.
    current : float (A) or str, optional
        Coil current when on; default the spec's maximum current.
    duty : float
        Duty cycle in (0, 1].
    period : float (s) or str, optional
        Period of the duty cycle, checked against the thermal time constant.
    ambient : float (degC) or str, optional
        Ambient temperature; default ``"25C"``.
    h : float (W/(m^2 K)), str or "natural", optional
        Heat-transfer coefficient of the housing, or natural convection; default 10.
    emissivity : float
        Emissivity of the housing for radiation, in [0, 1].
    insulation_class : str
        Insulation limit: a temperature (``"155C"``) or an IEC 60085 class letter.
    time, dt : float (s) or str, optional
        Warm-up duration and step; default ``"2h"`` and ``"10s"``.
    speed : float (rad/s) or str, optional
        Shaft speed for the viscous heat; default ``"0rad/s"``.
    behaviour : bool
        Also compute the hot behaviour (viscosity, resistance, voltage drive: a magnetic
        analysis); ``False`` is the CLI's ``--no-behaviour``.

    Returns
    -------
    dict
        The document of ``mrbrake thermal --json`` (``steady``, ``warmup``,
        ``continuous_current_A``, ``max_duty_at_max_current``, ``behaviour``, ...), SI with
        temperatures in degC.

    Raises ``ValueError`` for bad input (the CLI's message), ``FileNotFoundError`` for a missing
    spec, :class:`SolverError` when a solve fails. Runs without the GIL.
    """
    return _native.thermal(spec, mesh, current=current, duty=duty, period=period, ambient=ambient,
                           h=h, emissivity=emissivity, insulation_class=insulation_class,
                           time=time, dt=dt, speed=speed, behaviour=behaviour)


def report(spec=None, output=None, *, store=None, problem=None, log=None, frd=None, poles=None,
           zeros=None, fit_order=None, mesh="default", order=1, points=21, speed=None,
           temperature=None, response=False, thermal=False, uncertainty=None):
    """The self-contained HTML report (``mrbrake report``): of a design (``spec``, default the
    embedded thesis brake with its published values), of a results store (``store``) or of a
    rig characterisation (``log``). The page is the one the CLI writes, composed by the same
    library code.

    Parameters
    ----------
    spec : None, str, os.PathLike or dict
        The design, as for :func:`analyze`.
    output : str or os.PathLike, optional
        Also write the page there (atomically).
    store : str or os.PathLike, optional
        A study report of this results store.
    problem : str or os.PathLike, optional
        The problem whose objectives define the study's front (default: the one the store
        records).
    log : str or os.PathLike, optional
        A characterisation report of this repeated-ramp rig log (CSV).
    frd : str or os.PathLike, optional
        Frequency-response data (``mrbrake freqresp``) for the Bode diagram (with ``log``).
    poles, zeros, fit_order : int, optional
        The fitted transfer function and the branch polynomials (with ``log``); the CLI's
        defaults.
    mesh, order, points, speed, temperature
        The design report's static analysis, as for :func:`analyze`.
    response, thermal : bool
        Add the predicted dynamics / the heat section (their commands' defaults).
    uncertainty : str or os.PathLike, optional
        Add the uncertainty section of ``mrbrake uncertainty --json`` saved to this file.

    Returns
    -------
    str
        The HTML page. The analyses' warnings and the problem's notes are issued as
        ``UserWarning``.

    Raises ``ValueError`` for bad input (the CLI's message), ``FileNotFoundError`` for a missing
    spec, store, problem or log, :class:`SolverError` when an analysis fails. Runs without the
    GIL.
    """
    import warnings

    def path(p):
        return None if p is None else str(p)

    defaults = {}
    for name, value in (("poles", poles), ("zeros", zeros), ("fit_order", fit_order)):
        if value is not None:
            defaults[name] = value
    page = _native.report(spec, path(output), store=path(store), problem=path(problem),
                          log=path(log), frd=path(frd), mesh=mesh, order=order, points=points,
                          speed=speed, temperature=temperature, response=response,
                          thermal=thermal, uncertainty=path(uncertainty), **defaults)
    for w in page["warnings"]:
        warnings.warn(w, UserWarning, stacklevel=2)
    return page["html"]
