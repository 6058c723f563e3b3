"""Type stubs of mrbrake (units: SI; see the docstrings)."""

import os
from typing import Any, Dict, List, Optional, Tuple, Union

import numpy as np
import numpy.typing as npt

from . import fem as fem
from . import formula as formula
from . import haptic as haptic
from . import materials as materials
from . import rig as rig
from . import store as store
from . import sysid as sysid

__version__: str

Quantity = Union[float, str]
Spec = Union[None, str, "os.PathLike[str]", Dict[str, Any]]

class SolverError(RuntimeError):
    """A numerical failure (Newton without convergence, a failed fit)."""

class Analysis:
    """The result of :func:`analyze` (unit 1 energised for the curve and the field)."""

    @property
    def name(self) -> str: ...
    @property
    def configuration(self) -> str: ...
    @property
    def max_current_a(self) -> float:
        """Maximum coil current (A)."""
    @property
    def current_a(self) -> npt.NDArray[np.float64]:
        """Currents of the sweep (A), shape (points,)."""
    @property
    def torque_nm(self) -> npt.NDArray[np.float64]:
        """Total torque (N*m) at each current: yield + viscous + seal friction."""
    @property
    def yield_torque_nm(self) -> npt.NDArray[np.float64]:
        """Field-dependent yield torque (N*m) at each current."""
    @property
    def thesis_formula_nm(self) -> npt.NDArray[np.float64]:
        """The thesis method's torque (N*m) at each current."""
    @property
    def mean_b_t(self) -> npt.NDArray[np.float64]:
        """Mean gap |B| (T) at each current."""
    @property
    def flux_linkage_wb(self) -> npt.NDArray[np.float64]:
        """Coil flux linkage (Wb) at each current."""
    @property
    def torque(self) -> Dict[str, Any]:
        """Torque summary (N*m; the CLI's ``torque``)."""
    @property
    def gaps(self) -> List[Dict[str, Any]]:
        """Per-gap results at the maximum current (the CLI's ``gaps``)."""
    @property
    def coil(self) -> Dict[str, Any]:
        """Coil figures (turns, ohm, W, H, s; the CLI's ``coil``)."""
    @property
    def mechanics(self) -> Dict[str, Any]:
        """Mass (kg), size (m), inertia, torque density (the CLI's ``mechanics``)."""
    @property
    def mesh(self) -> Dict[str, int]: ...
    @property
    def timings_s(self) -> Dict[str, float]:
        """Wall-clock seconds per stage: mesh, setup, solve, post, total."""
    @property
    def warnings(self) -> List[str]: ...
    def to_dict(self) -> Dict[str, Any]:
        """The keys of ``mrbrake analyze --json``."""
    def field(
        self,
    ) -> Tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.float64]]:
        """``(nodes (N, 2) [r, z] in m, triangles (M, 3), |B| (M,) in T per triangle)``."""
    def flux_function(self) -> npt.NDArray[np.float64]:
        """psi = r * A_phi at the nodes (Wb/rad); its level lines are flux lines."""
    def regions(self) -> Tuple[npt.NDArray[np.int64], Dict[int, Tuple[str, str]]]:
        """Region tag per triangle and ``{tag: (part name, material)}``."""

def analyze(
    spec: Spec = None,
    mesh: str = "default",
    order: int = 1,
    currents: Optional[int] = None,
    *,
    speed: Optional[Quantity] = None,
    seal_friction: Optional[Quantity] = None,
    temperature: Optional[Quantity] = None,
) -> Analysis:
    """Analyse a brake design (``mrbrake analyze``); see the docstring for units."""

PathLike = Union[str, "os.PathLike[str]"]

def sweep(
    spec: Spec = ...,
    vary: Union[Dict[str, Union[Quantity, List[Quantity]]], List[str], str, None] = ...,
    *,
    store: PathLike,
    set: Union[Dict[str, Any], List[str], None] = ...,
    sample: Optional[str] = ...,
    seed: int = ...,
    resume: bool = ...,
    jobs: int = ...,
    shard: Optional[str] = ...,
    mesh: str = ...,
    order: int = ...,
    speed: Optional[Quantity] = ...,
) -> Dict[str, Any]:
    """A parameter sweep into a results store (``mrbrake sweep --json``); SI units."""

def optimize(
    problem: PathLike,
    store: Optional[PathLike] = ...,
    *,
    resume: bool = ...,
    jobs: int = ...,
    out: Optional[PathLike] = ...,
    max_evaluations: Optional[int] = ...,
    generations: Optional[int] = ...,
    seed: Optional[int] = ...,
    set: Union[Dict[str, Any], List[str], None] = ...,
) -> Dict[str, Any]:
    """An optimisation study from a problem file (``mrbrake optimize --json``)."""

def calibrate(
    spec: Spec = ...,
    *,
    log: PathLike,
    parameters: Union[List[str], str],
    set: Union[Dict[str, Any], List[str], None] = ...,
    frd: Optional[PathLike] = ...,
    points: int = ...,
    max_evaluations: int = ...,
    jobs: int = ...,
    mesh: str = ...,
    order: int = ...,
    speed: Optional[Quantity] = ...,
    record: Optional[List[str]] = ...,
) -> Dict[str, Any]:
    """Spec fields fitted to a rig log's loop (``mrbrake calibrate --json`` + ``calibrated_spec``)."""

def response(
    spec: Spec = ...,
    mesh: str = ...,
    *,
    drive: str = ...,
    duration: Optional[Quantity] = ...,
    step: Optional[str] = ...,
    bias: Optional[Quantity] = ...,
    fluid_lag: Optional[Quantity] = ...,
    conductivity: Optional[Quantity] = ...,
) -> Dict[str, Any]:
    """The predicted dynamics (``mrbrake response --json``); SI units."""

def thermal(
    spec: Spec = ...,
    mesh: str = ...,
    *,
    current: Optional[Quantity] = ...,
    duty: float = ...,
    period: Optional[Quantity] = ...,
    ambient: Optional[Quantity] = ...,
    h: Optional[Quantity] = ...,
    emissivity: float = ...,
    insulation_class: str = ...,
    time: Optional[Quantity] = ...,
    dt: Optional[Quantity] = ...,
    speed: Optional[Quantity] = ...,
    behaviour: bool = ...,
) -> Dict[str, Any]:
    """Temperatures, warm-up, ratings and hot behaviour (``mrbrake thermal --json``); SI, degC."""

def report(
    spec: Spec = ...,
    output: Optional[PathLike] = ...,
    *,
    store: Optional[PathLike] = ...,
    problem: Optional[PathLike] = ...,
    log: Optional[PathLike] = ...,
    frd: Optional[PathLike] = ...,
    poles: Optional[int] = ...,
    zeros: Optional[int] = ...,
    fit_order: Optional[int] = ...,
    mesh: str = ...,
    order: int = ...,
    points: int = ...,
    speed: Optional[Quantity] = ...,
    temperature: Optional[Quantity] = ...,
    response: bool = ...,
    thermal: bool = ...,
    uncertainty: Optional[PathLike] = ...,
) -> str:
    """The HTML report ``mrbrake report`` writes (a design, a store or a rig log)."""
