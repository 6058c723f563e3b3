import os
from typing import Dict, Optional, Union

import numpy as np
import numpy.typing as npt

def characterize(
    config: Union[str, "os.PathLike[str]", None] = ..., seed: Optional[int] = ...
) -> Dict[str, npt.NDArray[np.float64]]: ...
