"""Type stub of the compiled core (``rust/src/python``): typed scene, report and field objects,
and the array-level solvers. Units are SI (m, s, N, Pa, Pa s)."""

from collections.abc import Callable
from typing import final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "EQUIVALENT_CONE_FACTOR",
    "MAGNITUDE",
    "Curve",
    "FieldSet",
    "Indenter",
    "Report",
    "Scene",
    "SurfaceOperator",
    "bem_punch",
    "bem_viscous",
    "contact_solve",
    "load_scene_file",
    "mdr_deflection",
    "mdr_pressure",
    "num_threads",
    "parse_scene_file",
    "parse_scene_table",
    "run_scene",
    "self_affine",
    "set_num_threads",
    "surface_deflection",
]

MAGNITUDE: float
EQUIVALENT_CONE_FACTOR: float

_Progress = Callable[[str, int, int], object] | None
_F64 = NDArray[np.float64]

@final
class Scene:
    """A validated scene of the crate's scene model."""
    @staticmethod
    def from_json(text: str) -> Scene: ...
    def to_json(self) -> str: ...
    def to_toml(self, method: str | None = None, n: int | None = None, path: str | None = None) -> str: ...
    def output_times(self) -> _F64: ...
    def field_times(self) -> _F64: ...
    def bem_grid(self, n: int) -> tuple[_F64, float, _F64, NDArray[np.bool_]]: ...
    def mdr_grid(self, n: int) -> tuple[_F64, float, _F64]: ...
    def depth_bounds(self) -> _F64: ...
    def extent_needed(self) -> float: ...

@final
class Indenter:
    """A validated indenter of the scene model."""
    @staticmethod
    def from_json(text: str) -> Indenter: ...
    def height(self, r: _F64) -> _F64: ...
    def profile_1d(self, x: _F64) -> _F64: ...
    def radius_at_depth(self, d: float) -> float: ...

@final
class Curve:
    """An indentation curve prepared once for fits: the half MDR profile, the samples and
    the prescribed depth, force, or drive through a spring of ``stiffness``."""
    def __new__(cls, profile: _F64, dx: float, times: _F64, values: _F64, control: str,
                substeps: int = 1, stiffness: float | None = None) -> Curve: ...
    def time_range(self) -> tuple[float, float]: ...
    def evaluate(self, media: list[str], free: list[str], shift: float | None = None
                 ) -> list[tuple[_F64, _F64, NDArray[np.uint64], str]]: ...

@final
class FieldSet:
    """Fields at one time."""
    @property
    def t(self) -> float: ...
    @property
    def x(self) -> _F64 | None: ...
    @property
    def y(self) -> _F64 | None: ...
    @property
    def r(self) -> _F64 | None: ...
    @property
    def x_extended(self) -> _F64 | None: ...
    @property
    def pressure(self) -> _F64 | None: ...
    @property
    def surface_velocity(self) -> _F64 | None: ...
    @property
    def deflection(self) -> _F64 | None: ...
    @property
    def gap(self) -> _F64 | None: ...

@final
class Report:
    """What a run computed and how."""
    @property
    def method(self) -> str: ...
    @property
    def n(self) -> int: ...
    @property
    def dx(self) -> float: ...
    @property
    def grid_shape(self) -> tuple[int, int] | None: ...
    @property
    def integrator(self) -> str: ...
    @property
    def t(self) -> _F64: ...
    @property
    def depth(self) -> _F64: ...
    @property
    def contact_length(self) -> _F64: ...
    @property
    def area(self) -> _F64 | None: ...
    @property
    def force(self) -> _F64: ...
    @property
    def velocity(self) -> _F64 | None: ...
    @property
    def stiffness_length(self) -> _F64 | None: ...
    @property
    def central_pressure(self) -> _F64 | None: ...
    @property
    def contact_fraction(self) -> _F64 | None: ...
    @property
    def patches(self) -> NDArray[np.uint64] | None: ...
    @property
    def mean_gap(self) -> _F64 | None: ...
    @property
    def saturated(self) -> NDArray[np.bool_] | None: ...
    @property
    def at_edge(self) -> NDArray[np.bool_] | None: ...
    @property
    def fields(self) -> list[FieldSet]: ...
    @property
    def steps(self) -> int: ...
    @property
    def solves(self) -> int: ...
    @property
    def iterations(self) -> int: ...
    @property
    def residual(self) -> float: ...
    @property
    def solver(self) -> str | None: ...
    @property
    def window(self) -> tuple[int, int, int, int] | None: ...
    @property
    def wall_time(self) -> float: ...
    @property
    def warnings(self) -> list[str]: ...
    @staticmethod
    def units() -> list[tuple[str, str]]: ...
    def summary(self) -> str: ...
    def table(self, name: str) -> str: ...
    def document(self, name: str, scene: Scene) -> str: ...

@final
class SurfaceOperator:
    """The surface operator (DC-FFT, or a periodic cell's) of an nx x ny grid of elements of side dx (m)."""
    def __new__(cls, nx: int, ny: int, dx: float, periodic: bool = False) -> SurfaceOperator: ...
    def apply(self, p: _F64, out: _F64 | None = None) -> _F64: ...
    @property
    def shape(self) -> tuple[int, int]: ...
    @property
    def dx(self) -> float: ...
    @property
    def padded(self) -> tuple[int, int]: ...
    @property
    def periodic(self) -> bool: ...

def set_num_threads(n: int | None = None) -> None: ...
def num_threads() -> int: ...
def load_scene_file(path: str) -> tuple[Scene, str, int]: ...
def parse_scene_file(text: str, source: str) -> tuple[Scene, str, int]: ...
def parse_scene_table(text: str, source: str) -> tuple[Scene, str, int]: ...
def run_scene(
    scene: Scene,
    method: str,
    n: int,
    tol: float = 1e-10,
    max_iter: int = 5000,
    integrator: str = "implicit",
    step: float = 0.01,
    area_change: float = 0.01,
    dt: float | None = None,
    progress: _Progress = None,
    precondition: bool = True,
    dense_limit: int = ...,
    active_limit: int | None = None,
) -> Report: ...
def contact_solve(
    height: _F64,
    allowed: NDArray[np.bool_],
    dx: float,
    compliance: float,
    force: float | None = None,
    depth: float | None = None,
    tol: float = 1e-10,
    max_iter: int = 5000,
    progress: _Progress = None,
    dense_limit: int = ...,
    active_limit: int | None = None,
    precondition: bool = True,
    depth_bound: float | None = None,
    deflection: bool = True,
    periodic: bool = False,
) -> Report: ...
def bem_viscous(
    height: _F64,
    allowed: NDArray[np.bool_],
    dx: float,
    eta: float,
    times: _F64,
    force_times: _F64,
    force_values: _F64,
    rates: bool = False,
    fields_at: list[int] = ...,
    tol: float = 1e-10,
    max_iter: int = 5000,
    progress: _Progress = None,
    explicit: tuple[float, float, float] | None = None,
    dense_limit: int = ...,
    depth_bounds: list[float] | None = None,
    active_limit: int | None = None,
    precondition: bool = True,
) -> Report: ...
def bem_punch(
    allowed: NDArray[np.bool_],
    dx: float,
    eta: float,
    force: float,
    margin: int | None = None,
    tol: float = 1e-10,
    max_iter: int = 5000,
    progress: _Progress = None,
    dense_limit: int = ...,
    precondition: bool = True,
) -> Report: ...
def mdr_pressure(q: _F64, dx: float, r: _F64) -> _F64: ...
def mdr_deflection(w: _F64, dx: float, r: _F64) -> _F64: ...
def surface_deflection(p: _F64, dx: float, dense: bool = False) -> _F64: ...
def self_affine(
    nx: int,
    ny: int,
    dx: float,
    hurst: float,
    rms_height: float | None = None,
    rms_slope: float | None = None,
    rolloff: float | None = None,
    short_cutoff: float | None = None,
    seed: int = 0,
) -> _F64: ...
