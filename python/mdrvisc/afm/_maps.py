"""Force maps fitted curve by curve: :func:`fit_map` runs :func:`mdrvisc.fit` on every curve
of a map in parallel (worker processes on this machine or a Dask cluster, in chunks, as
:func:`mdrvisc.solve_many` runs scenes), keeps each finished row in a store so that a rerun
fits only what is missing, and isolates the curves that fail with their reason;
:class:`MapFit` holds the table and draws the parameter maps."""

from __future__ import annotations

import dataclasses
import hashlib
import json
import math
import os
import sys
import tempfile
import time
import warnings
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from .. import many
from ..errors import InvalidInputError, MdrviscError
from ..geometry import Indenter
from ..media import _Medium
from ..progress import ProgressBar
from ._files import Curve

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["fit_map", "MapFit", "CurveFailure", "draw_maps"]

#: Options of :func:`mdrvisc.fit` that :func:`fit_map` passes on to every fit (the data and
#: the first guesses of one curve are not among them).
FIT_OPTIONS = ("fixed", "nu", "terms", "n", "substeps", "max_iter", "baseline_model")


@dataclasses.dataclass(frozen=True)
class CurveFailure:
    """A curve whose fit raised: its position ``index`` in the map's list of curves, its
    ``grid_index`` and the exception ``error``."""

    index: int
    grid_index: tuple[int, int] | None
    error: BaseException

    def __repr__(self) -> str:
        message = str(self.error)[:160]
        return f"CurveFailure(index={self.index}, error={type(self.error).__name__}({message!r}))"


def _key(curve: Curve, spec: dict) -> str:
    """A SHA-256 (hex) of what decides a curve's fit: its arrays' bytes and spring constant,
    the segments fitted, the indenter, the model and the fit's options."""
    digest = hashlib.sha256()
    for a in (curve.times(spec["model"]), curve.piezo, curve.deflection, curve.segment):
        digest.update(np.ascontiguousarray(a).tobytes())
    model = spec["model"]
    document = {"k": curve.spring_constant, "segments": spec["segments"],
                "indenter": spec["indenter"]._model(),
                "model": model.__name__ if isinstance(model, type) else model._model(),
                "options": spec["options"], "arrays": digest.hexdigest()}
    text = json.dumps(document, sort_keys=True, separators=(",", ":"), default=repr)
    return hashlib.sha256(text.encode()).hexdigest()


class _RowStore:
    """A folder of finished rows, ``<key>.json`` each, written atomically (a temporary file
    renamed onto its name)."""

    def __init__(self, path) -> None:
        self.path = Path(path)
        self.path.mkdir(parents=True, exist_ok=True)

    def file(self, key: str) -> Path:
        return self.path / f"{key}.json"

    def load(self, key: str) -> dict | None:
        """The row stored under ``key``, None when absent or unreadable (fitted again)."""
        try:
            row = json.loads(self.file(key).read_text())
        except (OSError, ValueError):
            return None
        return row if isinstance(row, dict) else None

    def save(self, key: str, row: dict) -> None:
        handle, temporary = tempfile.mkstemp(dir=self.path, prefix=f".{key}.", suffix=".tmp")
        try:
            with os.fdopen(handle, "w") as f:
                json.dump(row, f)
            os.replace(temporary, self.file(key))
        except BaseException:
            Path(temporary).unlink(missing_ok=True)
            raise


def _row(result) -> dict:
    """The numbers of a :class:`~mdrvisc.FitResult` as a table row."""
    row: dict[str, Any] = {}
    for name, value in result.parameters.items():
        row[name], row[f"{name}_stderr"] = float(value), float(result.stderr[name])
    for name, value in result.young_moduli.items():
        row[name], row[f"{name}_stderr"] = float(value), float(result.young_stderr[name])
    row["contact_point"], row["contact_point_stderr"] = result.contact_point, result.stderr["contact_point"]
    row["baseline"], row["baseline_stderr"] = result.baseline, result.stderr["baseline"]
    if result.baseline_slope is not None:
        row["baseline_slope"] = result.baseline_slope
        row["baseline_slope_stderr"] = result.stderr["baseline_slope"]
    row.update(rms=float(result.rms), success=bool(result.success), status=int(result.status),
               message=result.message, nfev=int(result.nfev), fit_time=float(result.wall_time),
               reason=None, warnings="; ".join(result.warnings) or None)
    return row


def _fit_chunk(chunk):
    """[(index, row or None, exception or None)] of a chunk [(index, curve, spec)]."""
    out = []
    for index, curve, spec in chunk:
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                result = curve.fit(spec["indenter"], spec["model"], spec["segments"], **spec["options"])
            out.append((index, _row(result), None))
        except Exception as exc:  # a curve that fails is reported, the map goes on
            error = exc if _picklable(exc) else MdrviscError(f"{type(exc).__name__}: {exc}")
            out.append((index, None, error))
    return out


def _picklable(exc: BaseException) -> bool:
    import pickle

    try:
        pickle.dumps(exc)
    except Exception:
        return False
    return True


def _grid_shape(curves: Sequence[Curve]) -> tuple[int, int] | None:
    """(rows y, columns x) of the map, from the file's grid shape or the largest grid index;
    None when a curve has no grid index."""
    if not curves or any(c.grid_index is None for c in curves):
        return None
    nx = max(c.grid_index[0] for c in curves) + 1  # type: ignore[index]
    ny = max(c.grid_index[1] for c in curves) + 1  # type: ignore[index]
    meta = curves[0].metadata
    nx = max(nx, int(meta.get("grid shape x") or 0))
    ny = max(ny, int(meta.get("grid shape y") or 0))
    return ny, nx


@dataclasses.dataclass
class MapFit:
    """The outcome of :func:`fit_map`.

    Attributes
    ----------
    table : pandas.DataFrame
        One row per curve, in the order of the curves: ``index``, ``grid_x``, ``grid_y``,
        ``x``, ``y`` (m), every fitted parameter and its ``<name>_stderr`` (Pa, s; Young's
        moduli ``E``, ``E_inf``, ``E0`` ... too), ``contact_point`` and ``baseline`` (m) with
        their standard errors, ``rms`` (N), ``success``, ``status``, ``message``, ``nfev``,
        ``fit_time`` (s), ``reason`` (why the fit raised; None where it ran) and ``warnings``
        (parameters the curve does not identify). Failed curves have NaN values.
    failures : list of CurveFailure
        The curves whose fit raised.
    shape : tuple of int or None
        (rows, columns) of the map's grid; None for curves without grid positions.
    computed, loaded : int
        Curves fitted now and rows read from the store.
    wall_time : float
        Seconds of the whole map.
    """

    table: pd.DataFrame
    failures: list[CurveFailure]
    shape: tuple[int, int] | None
    computed: int = 0
    loaded: int = 0
    wall_time: float = 0.0

    def __repr__(self) -> str:
        return f"<MapFit {self.summary()}>"

    def summary(self) -> str:
        """One line: curves fitted (now, from the store), failed, not converged, wall time."""
        total = len(self.table)
        unconverged = int((~self.table["success"].astype(bool)).sum()) - len(self.failures)
        return (f"{total - len(self.failures)}/{total} curves fitted ({self.computed} now, "
                f"{self.loaded} from the store), {len(self.failures)} failed, {unconverged} not converged, "
                f"wall {self.wall_time:.2f} s")

    def image(self, column: str) -> np.ndarray:
        """The map of ``column`` (rows y, columns x; NaN where no curve or no value)."""
        if self.shape is None:
            raise InvalidInputError("MapFit.image: the curves have no grid positions")
        if column not in self.table.columns:
            raise InvalidInputError(f"MapFit.image: no column {column!r}; columns: "
                                    f"{list(self.table.columns)}")
        out = np.full(self.shape, np.nan)
        values = self.table[column].to_numpy(dtype=float, na_value=np.nan)
        out[self.table["grid_y"].to_numpy(int), self.table["grid_x"].to_numpy(int)] = values
        return out

    def default_columns(self) -> list[str]:
        """The maps :meth:`draw` draws by default: the first Young's modulus, the contact
        point, beta or the first relaxation time (where the model has one), and rms."""
        columns = self.table.columns
        modulus = next((c for c in ("E", "E_inf", "E0", "E1") if c in columns), None)
        time_like = next((c for c in ("beta", "tau1", "tau") if c in columns), None)
        return [c for c in (modulus, "contact_point", time_like, "rms") if c is not None]

    def draw(self, columns: Sequence[str] | None = None, path=None, cmap: str = "viridis"):
        """Images of the parameter maps (matplotlib: ``pip install matplotlib``), one panel per
        column (default :meth:`default_columns`), each with its colour bar; saved to ``path``
        when given. Returns the figure."""
        return draw_maps(self, columns, path, cmap)


def draw_maps(fitted: MapFit, columns: Sequence[str] | None = None, path=None, cmap: str = "viridis"):
    """The figure of :meth:`MapFit.draw`."""
    try:
        import matplotlib

        if path is not None and "matplotlib.pyplot" not in sys.modules:
            matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError as exc:
        raise ImportError("MapFit.draw needs matplotlib: pip install matplotlib") from exc
    columns = list(columns) if columns is not None else fitted.default_columns()
    units = {"contact_point": "m", "baseline": "m", "baseline_slope": "m/m", "rms": "N", "beta": "",
             "tau1": "s", "tau": "s"}
    figure, axes = plt.subplots(1, len(columns), figsize=(3.2 * len(columns), 3.0), squeeze=False,
                                layout="constrained")
    table = fitted.table
    extent = None
    if table[["x", "y"]].notna().all().all() and len(table) > 1:
        x, y = table["x"].to_numpy(float) * 1e6, table["y"].to_numpy(float) * 1e6
        ny, nx = fitted.shape or (1, 1)
        dx = (x.max() - x.min()) / max(nx - 1, 1)
        dy = (y.max() - y.min()) / max(ny - 1, 1)
        extent = (x.min() - dx / 2, x.max() + dx / 2, y.min() - dy / 2, y.max() + dy / 2)
    for ax, column in zip(axes[0], columns):
        image = ax.imshow(fitted.image(column), origin="lower", cmap=cmap, extent=extent)
        unit = units.get(column, "Pa" if column.startswith(("E", "G")) else "")
        figure.colorbar(image, ax=ax, label=f"{column} ({unit})" if unit else column)
        ax.set_title(column)
        ax.set_xlabel("x (µm)" if extent else "column")
        ax.set_ylabel("y (µm)" if extent else "row")
    if path is not None:
        figure.savefig(path, dpi=120)
    return figure


def fit_map(curves: Sequence[Curve], indenter: Indenter, model: _Medium | type, *,
            segments: Sequence[str] | None = ("approach",), client=None, store=None,
            workers: int | None = None, progress: bool = True, **fit_options: Any) -> MapFit:
    """Fits ``model`` to every curve of a force map, in parallel.

    Parameters
    ----------
    curves : sequence of Curve
        E.g. ``mv.afm.load("map.jpk-force-map")`` or simulated curves.
    indenter, model :
        As in :func:`mdrvisc.fit` (a class: the first guess is estimated from each curve; an
        instance: every curve starts from its values).
    segments : sequence of str or None
        The segments fitted (default the approach; None: the whole curve).
    client : dask.distributed.Client, optional
        Fit on that cluster (``pip install 'mdrvisc[dask]'``); default this machine.
    store : str or Path, optional
        A folder of finished rows (one JSON file per curve, named by a hash of its data, the
        model and the options): rows there are read, not fitted again, so an interrupted map
        resumes.
    workers : int, optional
        Worker processes on this machine (default: the cores available); ignored with a client.
    progress : bool
        A progress bar and a closing summary on stderr.
    **fit_options :
        ``fixed``, ``nu``, ``terms``, ``n``, ``substeps``, ``max_iter`` and
        ``baseline_model`` of :func:`mdrvisc.fit` (``"tilt"``: each curve's baseline a line
        in the piezo position, its slope in the table's ``baseline_slope`` column, m/m).

    Returns
    -------
    MapFit
        ``table`` (pandas, one row per curve), ``failures``, ``image(column)``, ``draw()``.
        A curve whose fit raises is a row with its ``reason`` (and a :class:`CurveFailure`);
        the other curves go on.

    Examples
    --------
    >>> curves = mv.afm.load("cells.jpk-force-map")                       # doctest: +SKIP
    >>> fitted = mv.afm.fit_map(curves, mv.Sphere(radius=5e-6), mv.Elastic)  # doctest: +SKIP
    >>> fitted.draw(path="modulus.png")                                   # doctest: +SKIP
    """
    try:
        import pandas as pd
    except ImportError as exc:
        raise ImportError("fit_map returns a pandas table: pip install 'mdrvisc[afm]'") from exc
    start = time.perf_counter()
    curves = list(curves)
    for i, curve in enumerate(curves):
        if not isinstance(curve, Curve):
            raise InvalidInputError(f"fit_map: curves[{i}] must be an mdrvisc.afm.Curve, got {curve!r}")
    if not isinstance(indenter, Indenter):
        raise InvalidInputError(f"fit_map: indenter must be an mdrvisc indenter, got {indenter!r}")
    if not (isinstance(model, _Medium) or (isinstance(model, type) and issubclass(model, _Medium))):
        raise InvalidInputError(f"fit_map: model must be an mdrvisc medium or medium class, got {model!r}")
    unknown = set(fit_options) - set(FIT_OPTIONS)
    if unknown:
        raise InvalidInputError(f"fit_map: unknown fit option(s) {sorted(unknown)}; known: "
                                f"{list(FIT_OPTIONS)}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InvalidInputError(f"fit_map: workers must be a positive integer, got {workers!r}")
    spec = {"indenter": indenter, "model": model, "segments": None if segments is None else list(segments),
            "options": dict(fit_options)}
    shelf = None if store is None else _RowStore(store)
    rows: list[dict | None] = [None] * len(curves)
    failures: list[CurveFailure] = []
    counts = {"computed": 0, "loaded": 0}
    keys: list[str | None] = [None] * len(curves)
    tasks = []
    for index, curve in enumerate(curves):
        if shelf is not None:
            try:
                keys[index] = _key(curve, spec)
            except MdrviscError:
                keys[index] = None  # no times for this model: the fit says so
            row = shelf.load(keys[index]) if keys[index] is not None else None
            if row is not None:
                rows[index] = row
                counts["loaded"] += 1
                continue
        tasks.append((index, curve, spec))

    def collect(index: int, row: dict | None, error: BaseException | None) -> None:
        if error is not None:
            failures.append(CurveFailure(index, curves[index].grid_index, error))
            return
        assert row is not None
        key = keys[index]
        if shelf is not None and key is not None:
            shelf.save(key, row)
        rows[index] = row
        counts["computed"] += 1

    bar = ProgressBar() if progress and curves else None
    done = [counts["loaded"]]

    def advance(count: int) -> None:
        done[0] += count
        if bar is not None:
            bar("curves", done[0], len(curves))

    advance(0)
    try:
        if client is not None:
            many._run_dask(tasks, client, advance, collect, work=_fit_chunk)
        else:
            many._run_local(tasks, min(workers or many._cores(), max(1, len(tasks))), advance, collect,
                            work=_fit_chunk)
    finally:
        if bar is not None:
            bar.close()
    failures.sort(key=lambda f: f.index)
    reasons = {f.index: f"{type(f.error).__name__}: {f.error}" for f in failures}
    records = []
    for index, (curve, row) in enumerate(zip(curves, rows)):
        grid = curve.grid_index or (None, None)
        position = curve.position or (math.nan, math.nan)
        record = {"index": index, "grid_x": grid[0], "grid_y": grid[1], "x": position[0], "y": position[1]}
        if row is None:
            record.update(success=False, reason=reasons.get(index, "not fitted (interrupted)"))
        else:
            record.update(row)
        records.append(record)
    table = pd.DataFrame.from_records(records)
    fitted = MapFit(table, failures, _grid_shape(curves), counts["computed"], counts["loaded"],
                    time.perf_counter() - start)
    if progress:
        print(f"fit_map: {fitted.summary()}", file=sys.stderr, flush=True)
    return fitted
