"""The 1-DOF haptic simulation: a hand presses into a virtual wall rendered by a conventional MR
brake, the thesis's bidirectional brake pair, or an ideal motor (``mrbrake haptic wall``).

Units: stiffness in N*m/rad, damping in N*m*s/rad, times in s, angles in rad, torques in N*m,
currents in A.
"""

from . import _native

__all__ = ["WallRun", "wall"]


class WallRun:
    """One simulated wall interaction.

    Attributes
    ----------
    metrics : dict
        The sticky-wall measures, the document of ``mrbrake haptic wall --json`` (penetration,
        sticky torque, energies, passivity, peak current, ...; units in the key names).
    trace : dict of numpy.ndarray
        The time histories at 1 kHz, the columns of ``mrbrake haptic wall --csv`` at full
        precision: ``time_s``, ``angle_rad``, ``intended_rad``, ``wall_rad`` (N,) and
        ``current_a``, ``capacity_nm`` (N, 2: brake 1 and brake 2), ``actuator_torque_nm``,
        ``device_torque_nm``, ``hand_torque_nm``, ``ideal_wall_torque_nm`` (N,); float64.
    """

    __slots__ = ("metrics", "trace")

    def __init__(self, metrics, trace):
        self.metrics = metrics
        self.trace = trace

    def to_dict(self):
        """The metrics (``mrbrake haptic wall --json``)."""
        return self.metrics

    def __repr__(self):
        return (f"WallRun(device={self.metrics.get('device')!r}, "
                f"samples={len(self.trace['time_s'])})")


def wall(device, *, scenario="press-withdraw", stiffness=30.0, damping=0.02, duration=None,
         model=None):
    """Simulate a hand pressing into a virtual wall and withdrawing (``mrbrake haptic wall``).

    Parameters
    ----------
    device : {"conventional", "bidirectional", "motor"}
        The actuator: one MR brake fixed to the shaft, two brakes on opposite one-way bearings
        (the thesis's design), or an ideal DC motor (active reference).
    scenario : {"press-withdraw", "slide-hold", "moving-wall"}
    stiffness : float
        Virtual wall stiffness K (N*m/rad, >= 0).
    damping : float
        Virtual wall damping B (N*m*s/rad, >= 0).
    duration : float (s) or str, optional
        Run length; default the scenario's 4 s.
    model : str or os.PathLike, optional
        A characterisation JSON (``mrbrake characterize --model``) used for both brakes, in the
        plant and the controller; default built-in prototype-like branches.

    Returns
    -------
    WallRun
        ``.metrics`` (dict) and ``.trace`` (dict of NumPy arrays). Runs without the GIL.
    """
    metrics, trace = _native.haptic_wall(device, scenario=scenario, stiffness=stiffness,
                                         damping=damping, duration=duration,
                                         model=None if model is None else str(model))
    return WallRun(metrics, trace)
