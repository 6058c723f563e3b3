"""Type stubs of mrbrake.store."""

import os
from typing import Any, Dict, List, Union

def records(path: Union[str, "os.PathLike[str]"]) -> List[Dict[str, Any]]:
    """``mrbrake export STORE --json``."""

def load(path: Union[str, "os.PathLike[str]"]) -> Any:
    """A pandas DataFrame if pandas is installed, else a list of row dicts."""
