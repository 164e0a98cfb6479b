"""Results: what a solve computed, and how. One type serves :func:`mdrvisc.solve`,
:func:`mdrvisc.arrays.contact` and :func:`mdrvisc.arrays.viscous`; it saves to and loads
from ``.npz`` without pickle, gives a pandas table or a CSV file of its time series, and an
xarray Dataset of its series and fields (netCDF through xarray). The names of its
quantities, their kinds and units are the compiled core's (``mdrvisc._core.QUANTITIES``)."""

from __future__ import annotations

import csv
import dataclasses
import warnings
import zipfile
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from . import _core
from .errors import DataError, ResolutionWarning

if TYPE_CHECKING:
    import pandas as pd
    import xarray as xr

__all__ = ["Result", "Fields", "UNITS"]

#: Units of the quantities of a result (SI) that have one.
UNITS = {name: unit for name, unit, _ in _core.QUANTITIES if unit}


def _of_kind(kind: str) -> tuple[str, ...]:
    """The names of the report's quantities of ``kind``, in the core's order."""
    return tuple(name for name, _, k in _core.QUANTITIES if k == kind)


#: Series: one entry per output time (None where not computed).
SERIES = _of_kind("series")
#: The run's own numbers and labels.
SCALARS = _of_kind("scalar")
#: Tuples of integers.
SHAPES = _of_kind("shape")
#: Times of a run's events, any number of them (None where not tracked).
EVENTS = _of_kind("events")
#: Entries of a result file under this prefix are a store's (:mod:`mdrvisc.store`), not the
#: result's: :meth:`Result.load` skips them.
STORE_PREFIX = "store/"


@dataclasses.dataclass(frozen=True)
class Fields:
    """Fields at one time ``t`` (s). BEM: maps of shape (ny, nx) over element centres ``x``,
    ``y`` (m); a flat punch's surface velocity and deflection over ``x_extended`` on both
    axes. MDR: radial profiles over radii ``r`` (m), from the inverse transforms. Pressure in
    Pa, surface velocity in m/s, deflection in m; the gap of a height map (m: height below
    its highest point plus deflection minus depth, zero in contact); None where not asked
    for."""

    t: float
    x: np.ndarray | None = None
    y: np.ndarray | None = None
    r: np.ndarray | None = None
    x_extended: np.ndarray | None = None
    pressure: np.ndarray | None = None
    surface_velocity: np.ndarray | None = None
    deflection: np.ndarray | None = None
    gap: np.ndarray | None = None

    def __repr__(self) -> str:
        held = [f.name for f in dataclasses.fields(self)[1:] if getattr(self, f.name) is not None]
        return f"Fields(t={self.t!r}, {', '.join(held)})"


_FIELD_NAMES = tuple(f.name for f in dataclasses.fields(Fields))
#: The coordinates of the fields, and the maps and profiles over them.
_FIELD_COORDINATES = ("x", "y", "r", "x_extended")
_FIELD_VALUES = tuple(n for n in _FIELD_NAMES if n != "t" and n not in _FIELD_COORDINATES)
#: Units of the fields' values and coordinates.
_FIELD_UNITS = {"x": "m", "y": "m", "r": "m", "x_extended": "m", "pressure": "Pa",
                "surface_velocity": "m/s", "deflection": "m", "gap": "m"}


class Result:
    """What a solve computed, and how.

    Series (numpy arrays, one entry per output time ``t`` in s): ``depth`` (m),
    ``contact_length`` (m), ``force`` (N), and where computed ``area`` (m^2), ``zone_area``
    (m^2: the contact and the adhesive zone around it, BEM under a cohesive-zone law) and
    ``zone_length`` (m: its outer diameter 2 sqrt(zone_area / pi)), ``velocity``
    (penetration rate, m/s), ``stiffness_length`` (F / (4 eta dd/dt), m; F (1 - nu) / (2 eta dd/dt)
    for a Poisson ratio nu),
    ``central_pressure`` (Pa), ``saturated`` (the contact covers the whole indenter),
    ``at_edge`` (it reached the outermost ring of the BEM grid); for a height map
    ``contact_fraction`` (real contact area over the map's), ``patches`` (number of contact
    patches, edge-connected, integers) and ``mean_gap`` (m, over the map); None elsewhere.
    ``fields``: {t: :class:`Fields`} at the field times (t = 0 for a static solve).

    The run: ``method`` ("bem"/"mdr"), ``n``, ``dx`` (m), ``grid_shape`` (BEM), ``integrator``,
    ``steps``, ``solves``, ``iterations``, ``residual`` (largest final relative residual),
    ``solver``, ``window`` and ``level_iterations`` (static BEM solves: the iterations of each
    nested grid level, coarsest first, the solved grid last; they sum to ``iterations``),
    ``wall_time`` (s), ``warnings``.

    An adhesive contact (:class:`~mdrvisc.JKR`, :class:`~mdrvisc.DMT`): ``pull_off_force`` (N,
    negative: the tension the contact carried in its last state before it first let go),
    ``pull_off_depth`` (m) and ``pull_off_time`` (s) of that state (None without a pull-off),
    ``jump_in`` and ``jump_out`` (s: times of the steps at which a contact formed already in
    tension, or let go in tension; arrays, None under hard contact). Under force control
    the depth is NaN while a tensile force finds no contact.
    """

    units = UNITS

    def __init__(self, *, method: str, n: int, dx: float, t, depth, contact_length, force,
                 area=None, zone_area=None, zone_length=None, velocity=None,
                 stiffness_length=None, central_pressure=None,
                 contact_fraction=None, patches=None, mean_gap=None, saturated=None, at_edge=None,
                 fields=None, grid_shape=None, integrator: str = "implicit",
                 solver: str | None = None, window=None, level_iterations=None, steps: int = 0,
                 solves: int = 0, iterations: int = 0, residual: float = 0.0, wall_time: float = 0.0,
                 warnings=(), pull_off_force=None, pull_off_depth=None, pull_off_time=None,
                 jump_in=None, jump_out=None) -> None:
        self.method, self.n, self.dx = str(method), int(n), float(dx)
        for name, value in (("t", t), ("depth", depth), ("contact_length", contact_length),
                            ("force", force), ("area", area), ("zone_area", zone_area),
                            ("zone_length", zone_length), ("velocity", velocity),
                            ("stiffness_length", stiffness_length), ("central_pressure", central_pressure),
                            ("contact_fraction", contact_fraction), ("mean_gap", mean_gap)):
            setattr(self, name, None if value is None else np.asarray(value, dtype=np.float64))
        self.patches = None if patches is None else np.asarray(patches, dtype=np.int64)
        for name, value in (("saturated", saturated), ("at_edge", at_edge)):
            setattr(self, name, None if value is None else np.asarray(value, dtype=bool))
        self.fields = None if not fields else dict(fields)
        self.grid_shape = None if grid_shape is None else tuple(int(v) for v in grid_shape)
        self.window = None if window is None else tuple(int(v) for v in window)
        self.level_iterations = (None if level_iterations is None
                                 else tuple(int(v) for v in level_iterations))
        self.integrator, self.solver = str(integrator), None if solver is None else str(solver)
        self.steps, self.solves, self.iterations = int(steps), int(solves), int(iterations)
        self.residual, self.wall_time = float(residual), float(wall_time)
        self.warnings = [str(w) for w in warnings]
        for name, value in (("pull_off_force", pull_off_force), ("pull_off_depth", pull_off_depth),
                            ("pull_off_time", pull_off_time)):
            setattr(self, name, None if value is None else float(value))
        for name, value in (("jump_in", jump_in), ("jump_out", jump_out)):
            setattr(self, name, None if value is None else np.asarray(value, dtype=np.float64).ravel())

    @classmethod
    def _from_report(cls, report) -> Result:
        """Wraps a ``mdrvisc._core.Report``, issuing its warnings as :class:`ResolutionWarning`
        at the caller of the public function that solved it."""
        fields = {f.t: Fields(**{k: getattr(f, k) for k in _FIELD_NAMES}) for f in report.fields}
        values = {k: getattr(report, k) for k in SERIES + SCALARS + SHAPES + EVENTS}
        for message in report.warnings:
            warnings.warn(message, ResolutionWarning, stacklevel=3)
        return cls(fields=fields, warnings=report.warnings, **values)

    def summary(self) -> str:
        """One line: method, resolution, steps, solves, iterations, residual, wall time."""
        return (f"{self.method.upper()} n={self.n} dx={self.dx:.4e} m steps={self.steps} "
                f"solves={self.solves} iterations={self.iterations} residual={self.residual:.2e} "
                f"wall={self.wall_time:.3f} s")

    def __repr__(self) -> str:
        last = (f"t={self.t[-1]:.4g} s: depth={self.depth[-1]:.6g} m, "
                f"contact_length={self.contact_length[-1]:.6g} m")
        fields = "" if not self.fields else f", fields at {len(self.fields)} times"
        warn = "" if not self.warnings else f", {len(self.warnings)} warning(s)"
        return f"<Result {self.summary()}; {len(self.t)} outputs, last {last}{fields}{warn}>"

    def to_dict(self) -> dict:
        """Every quantity as plain data: arrays, numbers, strings, lists; fields as a list of
        dicts with their time under ``"t"``."""
        out = {k: getattr(self, k) for k in SERIES + SCALARS + SHAPES + EVENTS}
        out["warnings"] = list(self.warnings)
        out["fields"] = [dataclasses.asdict(f) for f in (self.fields or {}).values()]
        return out

    def save(self, path) -> Path:
        """Writes the result to ``path`` (``.npz``, numpy's format; no pickle), losslessly."""
        flat = {}
        for name, value in self.to_dict().items():
            if name == "fields":
                for i, entry in enumerate(value):
                    for key, array in entry.items():
                        if array is not None:
                            flat[f"fields/{i}/{key}"] = np.asarray(array)
            elif name == "warnings":
                flat[name] = np.asarray(value, dtype=str)
            elif value is not None:
                flat[name] = np.asarray(value)
        path = Path(path)
        with open(path, "wb") as handle:
            np.savez(handle, **flat)
        return path

    @classmethod
    def load(cls, path) -> Result:
        """Reads a result written by :meth:`save`.

        Raises
        ------
        FileNotFoundError
            No file at ``path``.
        DataError
            The file is not a result saved by :meth:`save` (damaged, truncated, empty,
            another program's ``.npz``, a pickle: pickles are never loaded); the message names
            the file and what is wrong.
        """
        try:
            return cls._read(path)
        except FileNotFoundError:
            raise
        except (OSError, ValueError, EOFError, KeyError, TypeError, AttributeError,
                zipfile.BadZipFile) as exc:
            what = ("a pickle, which is never loaded" if "pickle" in str(exc)
                    else f"{type(exc).__name__}: {exc}")
            raise DataError(f"Result.load: {str(path)!r} is not a result saved by Result.save "
                            f"({what})") from None

    @classmethod
    def _read(cls, path) -> Result:
        """The result in the ``.npz`` file at ``path``; numpy's and the dataclass's errors
        on anything else."""
        with np.load(path, allow_pickle=False) as data:
            items = {k: data[k] for k in data.files}
        fields: dict[int, dict] = {}
        values = {}
        for key, array in items.items():
            if key.startswith(STORE_PREFIX):  # what a store keeps beside the result
                continue
            if key.startswith("fields/"):
                _, index, name = key.split("/")
                fields.setdefault(int(index), {})[name] = float(array) if name == "t" else array
            elif key == "warnings":
                values[key] = [str(w) for w in array]
            elif key in SERIES or key in EVENTS:
                values[key] = array
            elif key in SHAPES:
                values[key] = tuple(int(v) for v in array)
            else:
                values[key] = array.item()
        parsed = {entry["t"]: Fields(**entry) for _, entry in sorted(fields.items())}
        return cls(fields=parsed, **values)

    def to_dataframe(self) -> pd.DataFrame:
        """The time series as a pandas DataFrame, one row per output time (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError("Result.to_dataframe needs pandas: pip install pandas") from exc
        return pd.DataFrame(self._series())

    def _series(self) -> dict[str, np.ndarray]:
        """The computed series by name, in the core's order (``t`` first)."""
        return {k: getattr(self, k) for k in SERIES if getattr(self, k) is not None}

    def to_csv(self, path, units: bool = False) -> Path:
        """Writes the time series to ``path`` as CSV: a header of their names, then one row
        per output time (booleans as 0 and 1, numbers at full precision).

        Parameters
        ----------
        path : str or path-like
            The file to write.
        units : bool
            Write each name with its unit, ``depth [m]``, in the header.

        Returns
        -------
        Path
            ``path``.

        Examples
        --------
        >>> result.to_csv("creep.csv")                           # doctest: +SKIP
        >>> np.loadtxt("creep.csv", delimiter=",", skiprows=1)   # doctest: +SKIP
        """
        series = self._series()
        names = [f"{k} [{UNITS[k]}]" if units and k in UNITS else k for k in series]
        columns = [v.astype(np.int64) if v.dtype == bool else v for v in series.values()]
        path = Path(path)
        with open(path, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(names)
            for row in zip(*columns):
                writer.writerow([repr(v.item()) for v in row])
        return path

    def to_xarray(self) -> xr.Dataset:
        """The result as an :class:`xarray.Dataset` (needs xarray: ``pip install
        'mdrvisc[xarray]'``), which writes netCDF with ``to_netcdf``.

        The series are variables over the output times ``t`` (s); the fields, where any,
        variables over their times ``field_t`` (s): BEM maps over the element centres ``y``,
        ``x`` (m; a flat punch's surface velocity and deflection over ``y_extended``,
        ``x_extended``), MDR radial profiles over ``radial``, with their radii ``r`` (m) a
        coordinate over (``field_t``, ``radial``) since they follow each time's contact
        radius. Each variable's ``units`` attribute is its unit; the run's numbers and labels
        (``method``, ``n``, ``dx``, ``steps``, ``wall_time``, ...) and its warnings are
        attributes of the Dataset. Booleans stay booleans (netCDF stores them as bytes).

        Returns
        -------
        xarray.Dataset

        Examples
        --------
        >>> data = result.to_xarray()                          # doctest: +SKIP
        >>> data.pressure.sel(field_t=100.0).plot()            # doctest: +SKIP
        >>> data.to_netcdf("creep.nc")                         # doctest: +SKIP
        >>> xr.open_dataset("creep.nc")                        # doctest: +SKIP
        """
        try:
            import xarray as xr
        except ImportError as exc:
            raise ImportError("Result.to_xarray needs xarray: pip install 'mdrvisc[xarray]'") from exc
        series = self._series()
        t = series.pop("t")
        variables = {k: ("t", v, {"units": UNITS[k]} if k in UNITS else {}) for k, v in series.items()}
        coords: dict = {"t": ("t", t, {"units": "s", "long_name": "output time"})}
        fields = list((self.fields or {}).values())
        if fields:
            coords["field_t"] = ("field_t", np.array([f.t for f in fields]),
                                 {"units": "s", "long_name": "time of the fields"})
            first = fields[0]
            dims_of = {}
            for name, dim in (("x", "x"), ("y", "y"), ("x_extended", "x_extended")):
                if getattr(first, name) is not None:
                    coords[dim] = (dim, getattr(first, name), {"units": "m"})
            if first.x_extended is not None:
                coords["y_extended"] = ("y_extended", first.x_extended, {"units": "m"})
            if first.r is not None:
                coords["r"] = (("field_t", "radial"), np.stack([f.r for f in fields]),
                               {"units": "m", "long_name": "radius"})
            for name in _FIELD_VALUES:
                values = [getattr(f, name) for f in fields]
                if any(v is None for v in values):
                    continue
                shape = values[0].shape
                if len(shape) == 1:
                    dims_of[name] = ("field_t", "radial")
                elif first.y is not None and shape == (first.y.size, first.x.size):
                    dims_of[name] = ("field_t", "y", "x")
                else:
                    dims_of[name] = ("field_t", "y_extended", "x_extended")
                variables[name] = (dims_of[name], np.stack(values), {"units": _FIELD_UNITS[name]})
        attrs = {}
        for k in SCALARS + SHAPES:
            value = getattr(self, k)
            if value is None:
                continue
            attrs[k] = (np.asarray(value, dtype=np.int64) if isinstance(value, tuple)
                        else int(value) if isinstance(value, bool) else value)
        attrs["warnings"] = "\n".join(self.warnings)
        attrs["source"] = "mdrvisc"
        return xr.Dataset(variables, coords=coords, attrs=attrs)
