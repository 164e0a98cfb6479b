"""Type stub of the compiled core (``rust/src/python``): typed scene, report and field objects,
and the array-level solvers. Units are SI (m, s, N, Pa, Pa s)."""

from collections.abc import Callable
from typing import Any, final

import numpy as np
from numpy.typing import NDArray

__all__ = [
    "DEFAULT_N",
    "EQUIVALENT_CONE_FACTOR",
    "MAGNITUDE",
    "MAX_FILE_BYTES",
    "MAX_N",
    "OUTPUTS",
    "QUANTITIES",
    "SOLVER_DEFAULTS",
    "Curve",
    "FieldSet",
    "Indenter",
    "Medium",
    "Report",
    "Scene",
    "SurfaceOperator",
    "bem_punch",
    "bem_viscous",
    "cohesive_curve",
    "cohesive_pull_off",
    "contact_solve",
    "load_scene_file",
    "mdr_deflection",
    "mdr_pressure",
    "num_threads",
    "parse_scene_file",
    "parse_scene_table",
    "read_scene_file",
    "run_memory",
    "run_scene",
    "run_loads",
    "self_affine",
    "set_num_threads",
    "surface_deflection",
]

MAGNITUDE: float
#: Largest input file (bytes) the command lines read.
MAX_FILE_BYTES: int
EQUIVALENT_CONE_FACTOR: float
#: (name, unit, kind ("series" or "field"), computed by default, height maps only) of each output.
OUTPUTS: tuple[tuple[str, str, str, bool, bool], ...]
#: (name, unit (empty for counts, flags, labels), kind) of each quantity of a report; kinds
#: "series", "scalar", "shape", "coordinate", "field".
QUANTITIES: tuple[tuple[str, str, str], ...]
#: Defaults of run_scene's solver options: tol, max_iter, integrator, step, area_change, dt,
#: precondition, dense_limit, active_limit.
SOLVER_DEFAULTS: dict[str, Any]
#: Resolution of a run that names none, by method ("bem", "mdr").
DEFAULT_N: dict[str, int]
#: Largest resolution by method ("bem": elements across the footprint, "mdr": elements).
MAX_N: dict[str, int]

_Progress = Callable[[str, int, int], object] | None
_F64 = NDArray[np.float64]

@final
class Scene:
    """A validated scene of the crate's scene model."""
    @staticmethod
    def from_json(text: str) -> Scene: ...
    @staticmethod
    def build(
        model: str,
        heights: _F64 | None = None,
        r: _F64 | None = None,
        h: _F64 | None = None,
        slope: _F64 | None = None,
        force: _F64 | None = None,
        depth: _F64 | None = None,
    ) -> Scene: ...
    def with_values(
        self,
        changes: str,
        heights: _F64 | None = None,
        r: _F64 | None = None,
        h: _F64 | None = None,
        slope: _F64 | None = None,
        force: _F64 | None = None,
        depth: _F64 | None = None,
    ) -> Scene: ...
    def model(self) -> str: ...
    def arrays(self) -> dict[str, _F64]: ...
    def controlled_by(self) -> str: ...
    def history(self) -> tuple[_F64, _F64]: ...
    def __eq__(self, value: object, /) -> bool: ...
    def __reduce__(self) -> tuple[Any, tuple[Any, ...]]: ...
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
    """A validated indenter of the scene model, or an axisymmetric profile given by Python
    functions, with the crate's geometry and MDR relations."""
    @staticmethod
    def from_json(text: str) -> Indenter: ...
    @staticmethod
    def rod(radius: float) -> Indenter: ...
    @staticmethod
    def paraboloid(c: float, edge: float | None = None) -> Indenter: ...
    @staticmethod
    def cone(slope: float, edge: float | None = None) -> Indenter: ...
    @staticmethod
    def sphere(radius: float) -> Indenter: ...
    @staticmethod
    def pyramid(half_angle: float, edge: float | None = None) -> Indenter: ...
    @staticmethod
    def profile(r: _F64, h: _F64, slope: _F64 | None = None, edge: float | None = None,
                radius: float | None = None) -> Indenter: ...
    @staticmethod
    def from_functions(height: Callable[[_F64], _F64], profile: Callable[[_F64], _F64],
                       edge: float | None = None, radius: float | None = None,
                       fills: bool = True) -> Indenter: ...
    def height(self, r: _F64) -> _F64: ...
    def profile_1d(self, x: _F64) -> _F64: ...
    def layer_profile_1d(
        self, half: float, n: int, thickness: float, base: str, nu: float
    ) -> tuple[_F64, float]: ...
    def height_map(self, x: _F64, y: _F64) -> tuple[_F64, NDArray[np.bool_]]: ...
    @property
    def half_width(self) -> float | None: ...
    @property
    def half_length_1d(self) -> float | None: ...
    @property
    def is_flat(self) -> bool: ...
    @property
    def equivalent_cone_slope(self) -> float | None: ...
    @property
    def rim_inside(self) -> bool | None: ...
    def radius_at_depth(self, d: float) -> float: ...
    def radius_at_load(self, s: float) -> float: ...
    def depth_under_load(self, s: _F64) -> _F64: ...

@final
class Medium:
    """A validated medium of the scene model: its shear relaxation modulus, creep compliance,
    series and parameters."""
    def __new__(cls, kind: str, parameters: list[tuple[str, float]], nu: float) -> Medium: ...
    @staticmethod
    def from_values(kind: str, values: list[float], nu: float) -> Medium: ...
    @staticmethod
    def kinds() -> list[str]: ...
    @staticmethod
    def parameter_names(kind: str, terms: int = 0) -> list[str]: ...
    @property
    def kind(self) -> str: ...
    @property
    def nu(self) -> float: ...
    def parameters(self) -> list[tuple[str, float]]: ...
    def rheology(self) -> tuple[float, list[tuple[float, float]], float]: ...
    def relaxation_modulus(self, t: _F64) -> _F64: ...
    def creep_compliance(self, t: _F64) -> _F64: ...

@final
class Curve:
    """An indentation curve prepared once for fits: the half MDR profile, the samples and
    the prescribed depth, force, or drive through a spring of ``stiffness``."""
    def __new__(cls, profile: _F64, dx: float, times: _F64, values: _F64, control: str,
                substeps: int = 1, stiffness: float | None = None) -> Curve: ...
    def elements_only(self) -> Curve: ...
    def time_range(self) -> tuple[float, float]: ...
    def evaluate(self, media: list[str], free: list[str], shift: float | None = None
                 ) -> list[tuple[_F64, _F64, NDArray[np.uint64], str]]: ...
    def evaluate_jkr(self, medium: str, work_of_adhesion: float, shift: float = 0.0,
                     approach: str = "touch") -> tuple[_F64, _F64, _F64, NDArray[np.uint64]]: ...
    def evaluate_dmt(self, medium: str, attraction: float, shift: float = 0.0
                     ) -> tuple[_F64, _F64, _F64, NDArray[np.uint64]]: ...

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
    def zone_area(self) -> _F64 | None: ...
    @property
    def zone_length(self) -> _F64 | None: ...
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
    def level_iterations(self) -> list[int] | None: ...
    @property
    def pull_off_force(self) -> float | None: ...
    @property
    def pull_off_depth(self) -> float | None: ...
    @property
    def pull_off_time(self) -> float | None: ...
    @property
    def jump_in(self) -> NDArray[np.float64] | None: ...
    @property
    def jump_out(self) -> NDArray[np.float64] | None: ...
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
def read_scene_file(path: str) -> Scene: ...
def run_memory(
    scene: Scene,
    method: str,
    n: int,
    integrator: str = ...,
    dt: float | None = None,
    precondition: bool = ...,
) -> float:
    """The memory (bytes) ``run_scene`` with these arguments reaches at its peak, as checked
    before it allocates."""
def run_scene(
    scene: Scene,
    method: str,
    n: int,
    tol: float = ...,
    max_iter: int = ...,
    integrator: str = ...,
    step: float = ...,
    area_change: float = ...,
    dt: float | None = None,
    progress: _Progress = None,
    precondition: bool = ...,
    dense_limit: int = ...,
    active_limit: int | None = ...,
) -> Report:
    """Solves ``scene``; the defaults (``...``) are ``SOLVER_DEFAULTS``'s."""
def run_loads(
    scene: Scene,
    method: str,
    n: int,
    forces: list[float],
    tol: float = ...,
    max_iter: int = ...,
    progress: _Progress = None,
    precondition: bool = ...,
    dense_limit: int = ...,
    active_limit: int | None = ...,
) -> list[Report]:
    """Solves the static ``scene`` under each force in turn, each solve warm-started."""
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
def cohesive_curve(
    height: _F64,
    allowed: NDArray[np.bool_],
    dx: float,
    compliance: float,
    contact: str,
    depths: _F64,
    tol: float = 1e-10,
    max_iter: int = 5000,
    progress: _Progress = None,
    periodic: bool = False,
) -> dict[str, _F64]:
    """Depth-controlled static adhesive contact under a cohesive law (JSON table)."""
def cohesive_pull_off(
    height: _F64,
    allowed: NDArray[np.bool_],
    dx: float,
    compliance: float,
    contact: str,
    d_max: float,
    d_min: float,
    steps: int = 30,
    tol: float = 1e-10,
    max_iter: int = 5000,
    progress: _Progress = None,
    periodic: bool = False,
) -> dict[str, float]:
    """The pull-off of a depth-controlled approach and retract under a cohesive law."""
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
