import os
from typing import Any, Dict, List, Optional, Union

import numpy as np
import numpy.typing as npt

def characterize(
    config: Union[str, "os.PathLike[str]", None] = ..., seed: Optional[int] = ...
) -> Dict[str, npt.NDArray[np.float64]]: ...
def freqresp(
    config: Union[str, "os.PathLike[str]", None] = ...,
    seed: Optional[int] = ...,
    model: Union[str, "os.PathLike[str]", None] = ...,
) -> List[Dict[str, Any]]: ...
