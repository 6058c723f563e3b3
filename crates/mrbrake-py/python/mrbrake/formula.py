"""The thesis's closed-form models: brake torque of a disc, multi-disc, drum and multi-drum brake
from a yield stress, and the coil of a winding window (``mrbrake formula ...``).

Every function returns the dict of the matching ``mrbrake formula ... --json`` command. Lengths
in m, stresses in Pa, flux densities in T, speeds in rad/s, viscosities in Pa*s, currents in A,
temperatures in degC; each quantity may also be a string with a unit (``"22.5mm"``, ``"60rpm"``).

The yield stress is ``tau_y`` (given) or read from the fluid's tau_y(B) curve at ``b``; with a
``speed`` the viscous torque is added (viscosity ``eta``, default the fluid's off-state one; disc
and drum brakes also need the fluid ``gap``). Bad input raises ``ValueError``.
"""

from . import _native

__all__ = ["coil", "drum", "multi_disc", "multi_drum", "single_disc"]


def single_disc(r1, r2, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None, gap=None):
    """Single-disc brake torque, thesis (3.6)/(3.7): T = 4*pi*tau_y*(R2^3 - R1^3)/3 (N*m)
    [+ viscous term]. ``r1``, ``r2``: inner and outer radius of the fluid annulus (m)."""
    return _native.formula_disc(1, r1, r2, tau_y=tau_y, b=b, fluid=fluid, speed=speed, eta=eta,
                                gap=gap)


def multi_disc(discs, r1, r2, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None,
               gap=None):
    """Multi-disc brake torque, thesis (3.8): ``discs`` times the single disc (N*m); each disc is
    sheared on both faces."""
    return _native.formula_disc(discs, r1, r2, tau_y=tau_y, b=b, fluid=fluid, speed=speed, eta=eta,
                                gap=gap)


def drum(r, h, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None, eta=None, gap=None):
    """Drum brake torque, thesis (3.9): T = 4*pi*tau_y*R^2*h (N*m) [+ viscous term]. ``r``: drum
    radius (m), ``h``: drum height (m)."""
    return _native.formula_drum(r, h, tau_y=tau_y, b=b, fluid=fluid, speed=speed, eta=eta, gap=gap)


def multi_drum(r0, h, d, g, surfaces, *, tau_y=None, b=None, fluid="mrf-122eg", speed=None,
               eta=None):
    """Multi-drum brake torque, thesis (4.4)/(4.5): T = 2*pi*h*tau_y*sum(R_k^2) (N*m) with
    R_k = R_(k-1) + d + g. ``r0``: innermost fluid radius (m), ``h``: cylinder height (m), ``d``:
    wall thickness (m), ``g``: fluid gap (m), ``surfaces``: number of fluid surfaces."""
    return _native.formula_multi_drum(r0, h, d, g, surfaces, tau_y=tau_y, b=b, fluid=fluid,
                                      speed=speed, eta=eta)


def coil(window_width, window_height, *, awg=None, wire_diameter=None, inner_radius="5mm",
         turns=None, current="2A", temperature="20C"):
    """A coil in a winding window, thesis (4.1)-(4.3): turns that fit (default number of turns),
    wire length (m), resistance (ohm), current density (A/mm^2), power (W), voltage (V).

    ``window_width``, ``window_height``: the window (m); ``awg`` (18-32) or ``wire_diameter`` (m,
    bare); ``inner_radius``: inner radius of the winding (m, default 5 mm); ``current`` (A);
    ``temperature``: copper temperature (degC). The CLI's warnings (turns that do not fit, current
    above the wire's rating) are not raised; compare ``turns`` with ``turns_fit`` and ``current_A``
    with ``wire_current_rating_A``."""
    return _native.formula_coil(window_width, window_height, awg=awg, wire_diameter=wire_diameter,
                                inner_radius=inner_radius, turns=turns, current=current,
                                temperature=temperature)
