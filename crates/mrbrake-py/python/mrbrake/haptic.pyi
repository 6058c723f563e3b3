import os
from typing import Any, Dict, Optional, Union

import numpy as np
import numpy.typing as npt

class WallRun:
    metrics: Dict[str, Any]
    trace: Dict[str, npt.NDArray[np.float64]]
    def __init__(self, metrics: Dict[str, Any], trace: Dict[str, npt.NDArray[np.float64]]) -> None: ...
    def to_dict(self) -> Dict[str, Any]: ...

def wall(
    device: str,
    *,
    scenario: str = ...,
    stiffness: float = ...,
    damping: float = ...,
    duration: Union[float, str, None] = ...,
    model: Union[str, "os.PathLike[str]", None] = ...,
) -> WallRun: ...
