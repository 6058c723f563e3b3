"""Type stubs of mrbrake.materials."""

from typing import Any, Dict, Optional, Tuple

import numpy as np
import numpy.typing as npt

class Material:
    @property
    def name(self) -> str: ...
    @property
    def kind(self) -> str: ...
    @property
    def description(self) -> str: ...
    @property
    def provenance(self) -> Dict[str, str]:
        """``source``, ``method``, ``trust``."""
    @property
    def bh_curve(self) -> Optional[Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64]]]:
        """``(H in A/m, B in T)`` of a tabulated curve; ``None`` for a linear material."""
    @property
    def yield_stress_curve(
        self,
    ) -> Optional[Tuple[npt.NDArray[np.float64], npt.NDArray[np.float64], str]]:
        """An MR fluid's ``(x, tau_y in Pa, variable)``; x in T or A/m."""
    def b_of_h(self, h: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """B (T) at field strengths h (A/m)."""
    def tau_y_of_b(self, b: npt.NDArray[np.float64]) -> npt.NDArray[np.float64]:
        """Yield stress (Pa) of an MR fluid at flux densities b (T)."""
    def to_dict(
        self,
        b: Optional[npt.NDArray[np.float64]] = None,
        h: Optional[npt.NDArray[np.float64]] = None,
    ) -> Dict[str, Any]:
        """``mrbrake materials show NAME --json``."""

def list() -> Dict[str, Any]:  # noqa: A001
    """``mrbrake materials list --json``."""

def get(name: str) -> Material: ...
