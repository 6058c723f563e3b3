"""The virtual test rig: the thesis's characterisation (5.3.1) and frequency-response (5.3.2)
experiments simulated on a brake model with sensor noise and quantisation, as ``mrbrake rig
characterize`` and ``mrbrake rig freqresp`` log them (here as NumPy arrays)."""

from . import _native

__all__ = ["characterize", "freqresp"]


def characterize(config=None, seed=None):
    """The characterisation run: current ramps 0 -> I_max -> 0 with pauses, repeated.

    Parameters
    ----------
    config : str or os.PathLike, optional
        A rig configuration (TOML, ``mrbrake rig config`` prints the default); default the
        thesis rig.
    seed : int, optional
        Noise seed (overrides the configuration's).

    Returns
    -------
    dict of numpy.ndarray
        ``time_s`` (s), ``current_a`` (A), ``torque_nm`` (measured, N*m), ``speed_rad_s``
        (rad/s): the columns of the CLI's ``characterization.csv`` at full precision (float64,
        one value per logged sample). ``mrbrake.sysid.characterize(d["time_s"], d["current_a"],
        d["torque_nm"])`` fits them. Runs without the GIL.
    """
    return _native.rig_characterize(None if config is None else str(config), seed)


def freqresp(config=None, seed=None, model=None):
    """The frequency-response runs (section 5.3.2): sinusoidal torque demands through the inverse
    model, one run per test frequency.

    Parameters
    ----------
    config : str or os.PathLike, optional
        A rig configuration (TOML); default the thesis rig.
    seed : int, optional
        Noise seed (overrides the configuration's; run k uses seed + 1 + k, as the CLI).
    model : str or os.PathLike, optional
        The inverse model (JSON from ``mrbrake characterize --save-model``) that shapes the
        current; default the configured branches.

    Returns
    -------
    list of dict
        One per frequency, in increasing order: ``frequency_rad_s`` (float, rad/s) and float64
        arrays ``time_s`` (s), ``input_nm`` (demanded torque, N*m), ``output_nm`` (measured
        torque, N*m), ``current_a`` (A): the CLI's ``sine_NN.csv`` logs at full precision.
        ``mrbrake.sysid`` estimates the frequency response from them. Runs without the GIL.
    """
    return _native.rig_freqresp(None if config is None else str(config), seed,
                                None if model is None else str(model))
