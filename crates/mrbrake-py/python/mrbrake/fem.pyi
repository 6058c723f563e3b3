"""Type stubs of mrbrake.fem."""

import os
from typing import Any, Dict, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

class FemSolution:
    @property
    def physics(self) -> str:
        """``"magnetostatic"`` or ``"heat"``."""
    def to_dict(self) -> Dict[str, Any]:
        """``mrbrake fem solve PROBLEM --json``."""
    def field(
        self,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        """Nodes (m), triangles, |B| per triangle (T) or temperature per node (degC)."""
    def flux_function(self) -> Optional[npt.NDArray[np.float64]]:
        """psi = r * A_phi per node (Wb/rad); None for heat."""

def solve(problem: Union[str, "os.PathLike[str]"], order: Optional[int] = None) -> FemSolution: ...
