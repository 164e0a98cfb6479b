"""Scenes (what to compute) and results (what was computed, and how)."""

from dataclasses import dataclass, field

import numpy as np

from ._validate import _positive
from .errors import InvalidInputError
from .geometry import Indenter
from .media import VISCOELASTIC, Elastic, Viscous

__all__ = ["Scene", "Result", "OUTPUTS"]

#: Outputs a scene may ask for. ``depth`` and ``contact_length`` (from the contact area) are
#: always computed; ``velocity`` (penetration rate dd/dt, m/s) and ``stiffness_length``
#: (F / (4 eta dd/dt), m, the paper's contact length) need an extra flat-punch solve per
#: output time in BEM; ``pressure`` (Pa), ``surface_velocity`` (m/s) and ``deflection`` (m)
#: are fields at ``field_times``.
OUTPUTS = ("depth", "contact_length", "velocity", "stiffness_length", "pressure",
           "surface_velocity", "deflection")
FIELD_OUTPUTS = ("pressure", "surface_velocity", "deflection")
#: Samples taken of a loading history given as a callable.
CALLABLE_SAMPLES = 4001


def _history(force, name="force"):
    """(times, values) float arrays of a force (N, >= 0) or depth (m) history given as a
    number or (t, value) samples."""
    if isinstance(force, (int, float, np.floating, np.integer)) and not isinstance(force, bool):
        f = _positive("Scene", name, force)
        return np.array([0.0]), np.array([f])
    try:
        t, f = (np.ascontiguousarray(a, dtype=np.float64) for a in force)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(
            f"Scene: {name} must be a positive number or a pair (times, values), got {force!r}"
        ) from exc
    if t.ndim != 1 or t.shape != f.shape or t.size == 0:
        raise InvalidInputError(f"Scene: {name} history needs two 1-D arrays of equal, non-zero length")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(f))):
        raise InvalidInputError(f"Scene: {name} history must be finite")
    if t[0] != 0.0 or np.any(np.diff(t) <= 0):
        raise InvalidInputError(f"Scene: {name} history times must start at 0 and increase, got {t}")
    if name == "force" and np.any(f < 0):
        raise InvalidInputError(f"Scene: forces must be >= 0 (no adhesion), got {f}")
    return t, f


@dataclass(frozen=True)
class Scene:
    """A rigid indenter pressed into a half-space.

    Parameters
    ----------
    indenter : Indenter
        Rod, Paraboloid, Cone, Sphere or Axisymmetric (see :mod:`mdrvisc.geometry`).
    medium : Viscous or Elastic
    force : float, (array, array) or callable
        Constant force (N) from first touch at t = 0, or a piecewise-linear history
        (times in s from 0, forces in N, >= 0), held constant after its last sample, or a
        callable F(t) (sampled at 4001 points over the duration).
    depth : float or (array, array)
        Instead of ``force``: a prescribed depth history (m; piecewise linear, negative =
        above the surface), for the viscoelastic media. Give exactly one of the two.
    duration : float, optional
        Simulated time (s); required for a viscous medium, absent for a static elastic solve.
    times : array_like, optional
        Output times (s), > 0 and increasing, ending at or before ``duration``; default five
        equal steps up to ``duration``.
    outputs : iterable of str
        What to compute, from :data:`OUTPUTS`; fields only when named.
    field_times : array_like, optional
        Times (s) of field outputs; default the final time. They are added to ``times``.
    dt : float, optional
        Longest time step (s) of the viscoelastic stepping (default ``duration / 500``);
        ``solve(..., dt=...)`` overrides it. The viscous engine needs none.
    """

    indenter: Indenter
    medium: object
    force: object = None
    duration: float = None
    times: object = None
    outputs: tuple = ("depth", "contact_length")
    field_times: object = None
    depth: object = None
    dt: float = None
    history: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self):
        if not isinstance(self.indenter, Indenter):
            raise InvalidInputError(f"Scene: indenter must be an mdrvisc indenter, got {self.indenter!r}")
        if not isinstance(self.medium, (Viscous, Elastic) + VISCOELASTIC):
            raise InvalidInputError(f"Scene: medium must be an mdrvisc medium, got {self.medium!r}")
        if (self.force is None) == (self.depth is None):
            raise InvalidInputError("Scene: give exactly one of force and depth")
        if self.depth is not None and not isinstance(self.medium, VISCOELASTIC + (Viscous,)):
            raise InvalidInputError(f"Scene: depth control needs a time-dependent medium, got {self.medium!r}")
        load, name = (self.force, "force") if self.depth is None else (self.depth, "depth")
        if callable(load):
            # a callable history is sampled finely and then followed piecewise linearly
            if self.duration is None:
                raise InvalidInputError(f"Scene: a callable {name} history needs a duration")
            span = np.linspace(0.0, _positive("Scene", "duration", self.duration), CALLABLE_SAMPLES)
            values = np.asarray([load(float(t)) for t in span], dtype=np.float64)
            load = (span, values)
        object.__setattr__(self, "history", _history(load, name))
        outputs = (self.outputs,) if isinstance(self.outputs, str) else tuple(self.outputs)
        bad = [o for o in outputs if o not in OUTPUTS]
        if bad:
            raise InvalidInputError(f"Scene: unknown outputs {bad}; choose from {OUTPUTS}")
        object.__setattr__(self, "outputs", outputs)
        if self.dt is not None:
            object.__setattr__(self, "dt", _positive("Scene", "dt", self.dt))
        if isinstance(self.medium, Elastic):
            if self.duration is not None or self.times is not None:
                raise InvalidInputError("Scene: an elastic scene is static: give no duration or times")
            return
        if self.duration is None:
            raise InvalidInputError("Scene: a time-dependent scene needs a duration (s)")
        duration = _positive("Scene", "duration", self.duration)
        object.__setattr__(self, "duration", duration)
        times = (np.linspace(duration / 5.0, duration, 5) if self.times is None
                 else np.asarray(self.times, dtype=np.float64).ravel())
        fields = (np.array([duration]) if self.field_times is None
                  else np.asarray(self.field_times, dtype=np.float64).ravel())
        for name, arr in (("times", times), ("field_times", fields)):
            if arr.size == 0 or not np.all(np.isfinite(arr)) or np.any(arr <= 0) or np.any(arr > duration * (1 + 1e-12)):
                raise InvalidInputError(f"Scene: {name} must be finite, in (0, duration], got {arr}")
        if np.any(np.diff(times) <= 0):
            raise InvalidInputError(f"Scene: times must increase, got {times}")
        if any(o in FIELD_OUTPUTS for o in outputs):
            # a field time within round-off of an output time is served by that output time
            near = (np.abs(times[None, :] - fields[:, None]) <= 1e-12 * duration).any(axis=1)
            times = np.union1d(times, fields[~near])
        object.__setattr__(self, "times", np.ascontiguousarray(times))
        object.__setattr__(self, "field_times", fields)

    @property
    def controlled_by(self):
        """"force" or "depth"."""
        return "force" if self.depth is None else "depth"

    def wants(self, output):
        """Whether the scene asks for ``output``."""
        return output in self.outputs

    @property
    def wants_fields(self):
        """Whether any field output is asked for."""
        return any(o in FIELD_OUTPUTS for o in self.outputs)

    @property
    def final_load(self):
        """Impulse (N s) up to the last output time (viscous), or the force (N) (elastic)."""
        if isinstance(self.medium, Elastic):
            return float(self.history[1][-1])
        return self.impulse(float(self.times[-1]))

    def impulse(self, end):
        """Integral of the force history from 0 to ``end`` (N s)."""
        t, f = self.history
        grid = np.append(t[t < end], end)
        vals = np.interp(grid, t, f)
        return float(np.sum(0.5 * (vals[1:] + vals[:-1]) * np.diff(grid)))


@dataclass
class Result:
    """What a solve computed, and how.

    Units: t in s, depth and lengths in m, velocity in m/s, pressure in Pa, area in m^2.
    Fields not asked for are None. ``saturated``: the contact covers the whole indenter
    (BEM: every footprint element; MDR: every element); ``at_edge`` (BEM): the contact
    reached the outermost ring of the grid.
    """

    method: str
    n: int
    dx: float
    t: np.ndarray
    depth: np.ndarray
    contact_length: np.ndarray
    area: np.ndarray = None
    force: np.ndarray = None
    velocity: object = None
    stiffness_length: np.ndarray = None
    central_pressure: float = None
    fields: dict = None
    saturated: np.ndarray = None
    at_edge: np.ndarray = None
    steps: int = 0
    solves: int = 0
    iterations: int = 0
    residual: float = 0.0
    wall_time: float = 0.0
    grid_shape: tuple = None
    integrator: str = "implicit"
    warnings: list = field(default_factory=list)
    units: dict = field(default_factory=lambda: {
        "t": "s", "depth": "m", "contact_length": "m", "area": "m^2", "velocity": "m/s",
        "stiffness_length": "m", "central_pressure": "Pa", "dx": "m", "wall_time": "s", "force": "N"})

    def summary(self):
        """One line: method, resolution, steps, solves, iterations, residual, wall time."""
        return (f"{self.method.upper()} n={self.n} dx={self.dx:.4g} m steps={self.steps} "
                f"solves={self.solves} iterations={self.iterations} residual={self.residual:.2e} "
                f"wall={self.wall_time:.3f} s")
