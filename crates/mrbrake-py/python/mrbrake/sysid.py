"""System identification on NumPy arrays (thesis chapter 5).

- :func:`characterize`: the torque-current hysteresis loop of a repeated-ramp log, fitted by one
  polynomial per branch (the controller's inverse model).
- :func:`freqresp`: gain and phase of one sinusoidal test by sine fits (one FRD point).
- :func:`tfest`: a continuous-time transfer function fitted to frequency-response data
  (Sanathanan-Koerner iterations, then Levenberg-Marquardt).

Arrays are read in place when they are contiguous float64 (complex128 for ``response``); any
other array is converted once.
"""

import numpy as _np

from . import _native
from ._native import TransferFunctionFit

__all__ = ["TransferFunctionFit", "characterize", "freqresp", "tfest"]


def _f64(values):
    return _np.ascontiguousarray(values, dtype=_np.float64)


def characterize(time, current, torque, order=5, bins=200):
    """Characterise the static torque-current hysteresis loop (``mrbrake characterize``).

    Parameters
    ----------
    time : array_like (s), strictly increasing
    current : array_like (A)
    torque : array_like (N*m)
    order : int
        Polynomial order of each branch (1..12; the thesis uses 5).
    bins : int
        Current bins over which the repetitions are averaged.

    Returns
    -------
    dict
        The keys of ``mrbrake characterize --json``: ``rising`` / ``falling`` (``coefficients`` in
        ascending powers of I in A, N*m; fit percentages), ``current_min_A``, ``current_max_A``,
        ``off_state_torque_Nm``, ``max_torque_Nm``, ``max_hysteresis_Nm``, ``repetitions``,
        ``samples``, ``sample_rate_Hz``; ``log`` is ``"<arrays>"``.
    """
    return _native.sysid_characterize(_f64(time), _f64(current), _f64(torque), order, bins)


def freqresp(time, input, output, omega, discard_periods=1.0, settle=0.5):  # noqa: A002
    """One frequency-response point from a sinusoidal test at ``omega`` (rad/s).

    ``input`` is the desired torque, ``output`` the measured one (any units, the same for both);
    the first ``max(discard_periods periods, settle s)`` are discarded. Returns the dict of one
    point of ``mrbrake freqresp --json``: ``omega_rad_s``, ``magnitude_dB``, ``phase_deg``,
    ``re``, ``im``, fit qualities (%), ``tracking`` (RMSE), ``periods``.
    """
    return _native.sysid_freqresp(_f64(time), _f64(input), _f64(output), float(omega),
                                  float(discard_periods), float(settle))


def tfest(omega, response, poles, zeros=0, weighting="uniform", delay=0.0, weight=None):
    """Fit ``G(s) = N(s)/D(s)`` (``zeros``/``poles`` degrees) to frequency-response data.

    Parameters
    ----------
    omega : array_like (rad/s)
    response : array_like, complex
        G(j omega) at each frequency.
    poles, zeros : int
        Degrees of the denominator (>= 1) and numerator (<= poles).
    weighting : {"uniform", "relative"}
        Absolute complex error, or relative (weight 1/|G|).
    delay : float (s)
        Known input delay removed before fitting.
    weight : array_like, optional
        Extra per-point weights (multiplied with ``weighting``).

    Returns
    -------
    TransferFunctionFit
        ``numerator``, ``denominator`` (descending powers of s), ``fit_percent``,
        ``response(omega)``, ``to_dict()`` (``mrbrake tfest --json``).
    """
    response = _np.ascontiguousarray(response, dtype=_np.complex128)
    weight = None if weight is None else _f64(weight)
    return _native.sysid_tfest(_f64(omega), response, int(poles), int(zeros), weighting,
                               float(delay), weight)
