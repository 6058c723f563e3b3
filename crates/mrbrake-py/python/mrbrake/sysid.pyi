"""Type stubs of mrbrake.sysid."""

from typing import Any, Dict, Optional

import numpy as np
import numpy.typing as npt

ArrayLike = npt.ArrayLike

class TransferFunctionFit:
    @property
    def numerator(self) -> npt.NDArray[np.float64]:
        """Highest power of s first."""
    @property
    def denominator(self) -> npt.NDArray[np.float64]:
        """Highest power of s first, constant term 1."""
    @property
    def delay_s(self) -> float: ...
    @property
    def fit_percent(self) -> float: ...
    def response(self, omega: npt.NDArray[np.float64]) -> npt.NDArray[np.complex128]:
        """G(j omega) including the delay, omega in rad/s."""
    def to_dict(self) -> Dict[str, Any]:
        """``mrbrake tfest --json``."""

def characterize(
    time: ArrayLike, current: ArrayLike, torque: ArrayLike, order: int = 5, bins: int = 200
) -> Dict[str, Any]:
    """time in s, current in A, torque in N*m; ``mrbrake characterize --json``."""

def freqresp(
    time: ArrayLike,
    input: ArrayLike,
    output: ArrayLike,
    omega: float,
    discard_periods: float = 1.0,
    settle: float = 0.5,
) -> Dict[str, Any]:
    """One FRD point at omega (rad/s); settle in s."""

def tfest(
    omega: ArrayLike,
    response: ArrayLike,
    poles: int,
    zeros: int = 0,
    weighting: str = "uniform",
    delay: float = 0.0,
    weight: Optional[ArrayLike] = None,
) -> TransferFunctionFit:
    """omega in rad/s, response complex, delay in s."""
