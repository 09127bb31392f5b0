# Type stubs of the compiled module (signorini._signorini). The public API
# is the Python half (signorini, signorini.exact, signorini.fem,
# signorini.studies, signorini.sweep), which wraps these.
from os import PathLike
from typing import Any, Optional, Sequence

import numpy as np
import numpy.typing as npt

F64 = npt.NDArray[np.float64]

__version__: str

class SceneError(ValueError): ...
class BlowUp(Exception): ...
class InternalError(RuntimeError): ...

class Exact:
    @property
    def name(self) -> str: ...
    @property
    def length(self) -> float: ...
    def u(self, x: F64, t: F64) -> F64: ...
    def u_x(self, x: F64, t: F64) -> F64: ...
    def u_t(self, x: F64, t: F64) -> F64: ...
    def lam(self, t: F64) -> F64: ...
    def energy(self) -> float: ...
    def energy_at(self, t: F64) -> F64: ...

def exact_solution(name: str, g: float | None = ..., u0: float | None = ..., length: float | None = ..., t_max: float | None = ..., energy: float | None = ..., wave_speed: float | None = ..., gap: float | None = ..., family: float | None = ...) -> Exact: ...

class ExactBackbone:
    @property
    def family(self) -> int: ...
    @property
    def threshold(self) -> float: ...
    @property
    def linear_period(self) -> float: ...
    @property
    def limit_period(self) -> float: ...
    def at(self, energy: F64) -> dict[str, npt.NDArray[Any]]: ...

def exact_backbone(length: float | None = ..., wave_speed: float | None = ..., gap: float | None = ..., far_end: str | None = ..., family: int | None = ...) -> ExactBackbone: ...

class RunArrays:
    t: F64
    tip: F64
    lam_t: F64
    lam: F64
    energy_t: F64
    energy: F64
    contact_dofs: list[int]
    contact_lo: F64
    contact_hi: F64
    contact_u: F64
    forces: F64
    active: npt.NDArray[np.bool_]
    fields_t: F64
    fields: F64
    norms: Optional[dict[str, float]]
    steps: int
    contact_steps: int
    dt: float
    status: str
    energy_max_ratio: float
    energy_exceeded: Optional[dict[str, Any]]
    energy_warning: Optional[str]
    events: Optional[dict]

def run_scene(scene: Any, energy: Optional[bool] = ..., fields_every: int = ..., energy_warn: Optional[float] = ...) -> RunArrays: ...
def check_scene(scene: Any) -> str: ...
def check_scene_numbers(scene: Any) -> dict[str, Any]: ...
def scene_text(scene: dict[str, Any]) -> str: ...

class Matrices:
    kind: str
    h: float
    x: list[float]
    @property
    def mass_band(self) -> F64: ...
    @property
    def stiffness_band(self) -> F64: ...
    @property
    def half_bandwidth(self) -> int: ...
    @property
    def n(self) -> int: ...
    @property
    def massless(self) -> list[int]: ...
    def kappa_h(self) -> float: ...

def bar_matrices(elements: int, mass: str = ..., length: float = ..., wave_speed: float = ..., right_end: str = ..., contacts: Optional[Sequence[int]] = ..., degree: int = ...) -> Matrices: ...
def beam_matrices(elements: int, length: float = ..., k2: float = ...) -> Matrices: ...
def study(name: str, kwargs: dict[str, Any], out: str | PathLike[str]) -> dict[str, Any]: ...
def study_check(name: str, kwargs: dict[str, Any]) -> None: ...
def study_fields(name: str) -> list[tuple[str, str, str, str | None]]: ...
def run_sweep(
    scene_text: str,
    scene_name: str,
    base: Optional[str],
    out: str,
    param: str,
    start: float,
    stop: float,
    count: int,
    log: bool,
    second: Optional[tuple[str, float, float, int, bool]],
    transient: float,
    record: float,
    phase: float,
    period_tol: float,
    impacts: bool,
    follow: bool,
    shard: Optional[tuple[int, int]],
    resume: bool,
    threads: Optional[int],
) -> dict[str, Any]: ...
def _panic_for_tests() -> None: ...
