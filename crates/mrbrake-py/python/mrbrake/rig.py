"""The virtual test rig: the thesis's characterisation experiment (section 5.3.1) simulated on a
brake model with sensor noise and quantisation, as ``mrbrake rig characterize`` logs it."""

from . import _native

__all__ = ["characterize"]


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
