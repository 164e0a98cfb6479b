"""AFM curves in mdrvisc's units and signs (:class:`Curve`) and instrument files read through
afmformats (:func:`load`).

afmformats gives a curve as columns: "force" (N, the cantilever's spring constant times its
deflection), "height (piezo)" and "height (measured)" (m, falling as the piezo moves towards
the sample), "segment" (0 approach, then any dwell, the last the retract) and "time" (s).
mdrvisc's piezo position rises towards the sample, and the deflection is the force over the
spring constant: ``piezo = -height``, ``deflection = force / k``.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import pathlib
from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import DataError, InvalidInputError
from ..fitting import fit
from ..media import Elastic

if TYPE_CHECKING:
    from ..fitting import FitResult
    from ..geometry import Indenter

__all__ = ["Curve", "load", "AFM_EXTRA"]

#: What installs the optional dependency that reads instrument files.
AFM_EXTRA = "pip install 'mdrvisc[afm]'"


def _afmformats():
    """The afmformats module, or an ImportError saying how to install it."""
    try:
        import afmformats
    except ImportError as exc:
        raise ImportError(f"mdrvisc.afm.load reads instrument files through afmformats, which is not "
                          f"installed: {AFM_EXTRA}") from exc
    return afmformats


def segment_names(count: int) -> tuple[str, ...]:
    """The names of ``count`` segments in their order: "approach", then "dwell" (one segment)
    or "dwell1", "dwell2", ... (several), then "retract"; a single segment is "approach"."""
    if count <= 1:
        return ("approach",)
    middle = count - 2
    dwell = ("dwell",) if middle == 1 else tuple(f"dwell{i + 1}" for i in range(middle))
    return ("approach", *dwell, "retract")


@dataclasses.dataclass(eq=False)
class Curve:
    """One AFM force curve in SI units and mdrvisc's signs.

    Attributes
    ----------
    time : ndarray or None
        Sample times (s), increasing through every segment (a file's retract times that
        restart at 0 are continued); None when the file has neither times nor sampling rates.
    piezo : ndarray
        Piezo position (m), rising towards the sample (afmformats' height, negated).
    deflection : ndarray
        Cantilever deflection (m), positive when the sample pushes the tip back: the file's
        force divided by ``spring_constant``. Its baseline (the deflection out of contact) is
        not removed: :func:`mdrvisc.fit` fits it.
    spring_constant : float
        The cantilever's spring constant k (N/m).
    segment : ndarray of int
        The segment of each sample, 0, 1, ...; its name is ``segments[segment]``.
    segments : tuple of str
        Segment names: "approach", "dwell" (or "dwell1", "dwell2", ...), "retract".
    index : int
        The curve's position in its file (0, 1, ...).
    grid_index : tuple of int or None
        (column x, row y) of the curve in a force map or QI map; None for single curves.
    position : tuple of float or None
        (x, y) of the curve on the sample (m), where the file says.
    metadata : dict
        Everything the file says of the curve, with afmformats' keys and SI values
        (e.g. "spring constant", "sensitivity", "speed approach", "grid shape x").
    path : pathlib.Path or None
        The file read.
    height : str
        Which height column gave ``piezo``: "height (piezo)" or "height (measured)".

    Examples
    --------
    >>> curves = mv.afm.load("cell.jpk-force-map")            # doctest: +SKIP
    >>> approach = curves[0].select("approach")                # doctest: +SKIP
    >>> result = approach.fit(mv.Sphere(radius=5e-6), mv.Elastic)   # doctest: +SKIP
    """

    time: np.ndarray | None
    piezo: np.ndarray
    deflection: np.ndarray
    spring_constant: float
    segment: np.ndarray
    segments: tuple[str, ...]
    index: int = 0
    grid_index: tuple[int, int] | None = None
    position: tuple[float, float] | None = None
    metadata: dict[str, Any] = dataclasses.field(default_factory=dict)
    path: pathlib.Path | None = None
    height: str = "height (piezo)"

    def __post_init__(self) -> None:
        k = float(self.spring_constant)
        if not (math.isfinite(k) and k > 0):
            raise DataError(f"AFM curve {self.index}: the spring constant must be > 0 (N/m), got "
                            f"{self.spring_constant!r}")
        self.spring_constant = k
        self.piezo = np.ascontiguousarray(self.piezo, dtype=float)
        self.deflection = np.ascontiguousarray(self.deflection, dtype=float)
        self.segment = np.ascontiguousarray(self.segment, dtype=np.int64)
        sizes = {"piezo": self.piezo.size, "deflection": self.deflection.size, "segment": self.segment.size}
        if self.time is not None:
            self.time = np.ascontiguousarray(self.time, dtype=float)
            sizes["time"] = self.time.size
        if len(set(sizes.values())) != 1:
            raise DataError(f"AFM curve {self.index}: arrays of different lengths {sizes}")
        if self.segment.size and not (0 <= self.segment.min() and self.segment.max() < len(self.segments)):
            raise DataError(f"AFM curve {self.index}: segment numbers outside 0..{len(self.segments) - 1}")

    def __len__(self) -> int:
        return self.piezo.size

    def __repr__(self) -> str:
        where = "" if self.grid_index is None else f" at grid {self.grid_index}"
        counts = ", ".join(f"{name} {int(np.count_nonzero(self.segment == i))}"
                           for i, name in enumerate(self.segments))
        return (f"<afm.Curve {self.index}{where}: {len(self)} samples ({counts}), k = "
                f"{self.spring_constant:.4g} N/m>")

    @property
    def force(self) -> np.ndarray:
        """The cantilever's force k deflection (N), baseline included."""
        return self.spring_constant * self.deflection

    def mask(self, *names: str) -> np.ndarray:
        """Where the samples of the segments ``names`` are (a boolean array)."""
        unknown = [name for name in names if name not in self.segments]
        if unknown or not names:
            raise InvalidInputError(f"AFM curve {self.index}: segments must be some of "
                                    f"{list(self.segments)}, got {list(names)}")
        return np.isin(self.segment, [self.segments.index(name) for name in names])

    def select(self, *names: str) -> Curve:
        """The curve of the segments ``names`` only (e.g. ``select("approach")``), in the
        file's order; the time keeps its origin."""
        keep = self.mask(*names)
        return dataclasses.replace(self, time=None if self.time is None else self.time[keep],
                                   piezo=self.piezo[keep], deflection=self.deflection[keep],
                                   segment=self.segment[keep])

    def times(self, model: Any) -> np.ndarray:
        """The sample times (s) a fit of ``model`` uses: ``time``, or, for an elastic medium
        (which has no time scale) of a curve without times, the sample numbers."""
        if self.time is not None:
            return self.time
        if model is Elastic or isinstance(model, Elastic):
            return np.arange(len(self), dtype=float)
        raise DataError(f"AFM curve {self.index}: the file gives no times (no time column, no sampling "
                        f"rate), which a viscoelastic fit needs")

    def fit(self, indenter: Indenter, model: Any, segments: Sequence[str] | None = None,
            **options: Any) -> FitResult:
        """:func:`mdrvisc.fit` of the raw curve (piezo, deflection, spring constant).

        ``segments``: the names of the segments fitted (default: all); ``options``: those of
        :func:`mdrvisc.fit` (``contact_point``, ``baseline``, ``fixed``, ``weights``, ``nu``,
        ``n``, ...).
        """
        curve = self if segments is None else self.select(*segments)
        return fit(indenter, model, curve.times(model), piezo=curve.piezo, deflection=curve.deflection,
                   spring_constant=curve.spring_constant, **options)


def _continuous(time: np.ndarray, segment: np.ndarray) -> np.ndarray:
    """``time`` with each segment that starts at or before the end of the one before moved on
    to continue it, one sampling step later."""
    time = time.astype(float).copy()
    starts = np.flatnonzero(np.diff(segment) != 0) + 1
    for start in starts:
        if time[start] <= time[start - 1]:
            before = time[max(0, start - 2):start]
            step = float(before[-1] - before[0]) if before.size == 2 else 0.0
            after = time[start:start + 2]
            step = step if step > 0 else (float(after[-1] - after[0]) if after.size == 2 else 1.0)
            time[start:] += time[start - 1] + step - time[start]
    return time


def _from_rates(metadata: dict, segment: np.ndarray) -> np.ndarray | None:
    """Times (s) from the approach and retract sampling rates (Hz), or None."""
    rates = metadata.get("rate approach"), metadata.get("rate retract")
    if any(r is None or not r > 0 for r in rates):
        return None
    last = segment.max() if segment.size else 0
    dt = np.where(segment == last, 1.0 / rates[1], 1.0 / rates[0]) if last > 0 else np.full(
        segment.size, 1.0 / rates[0])
    return np.concatenate([[0.0], np.cumsum(dt[:-1])])


def _curve(data, index: int, path: pathlib.Path, height: str | None) -> Curve:
    """The :class:`Curve` of one afmformats ``AFMData``."""
    metadata = dict(data.metadata)
    columns = list(data.columns)
    if height is None:
        height = next((c for c in ("height (piezo)", "height (measured)") if c in columns), None)
    if height is None or height not in columns or "force" not in columns:
        raise DataError(f"{path}: curve {index} has columns {columns}; a force curve needs 'force' and "
                        f"'height (piezo)' or 'height (measured)'")
    k = metadata.get("spring constant")
    if k is None:
        raise DataError(f"{path}: the file gives no spring constant; load(..., spring_constant=K) gives it")
    h = np.asarray(data[height], dtype=float)
    force = np.asarray(data["force"], dtype=float)
    segment = (np.asarray(data["segment"], dtype=np.int64) if "segment" in columns
               else np.zeros(h.size, np.int64))
    count = int(metadata.get("segment count") or segment.max() + 1)
    if segment.max(initial=0) == 0 and count >= 2 and h.size > 2:
        # approach and retract joined in one segment (Igor files): split at the deepest piezo
        segment = (np.arange(h.size) > int(np.argmin(h))).astype(np.int64)
        count = 2
    count = max(count, int(segment.max(initial=0)) + 1)
    time = np.asarray(data["time"], dtype=float) if "time" in columns else _from_rates(metadata, segment)
    if time is not None:
        time = _continuous(time, segment)
    grid = None
    if metadata.get("grid index x") is not None and metadata.get("grid index y") is not None:
        grid = (int(metadata["grid index x"]), int(metadata["grid index y"]))
    position = None
    if metadata.get("position x") is not None and metadata.get("position y") is not None:
        position = (float(metadata["position x"]), float(metadata["position y"]))
    metadata.pop("path", None)
    return Curve(time=time, piezo=-h, deflection=force / float(k), spring_constant=float(k), segment=segment,
                 segments=segment_names(count), index=index, grid_index=grid, position=position,
                 metadata=metadata, path=path, height=height)


def load(path, *, spring_constant: float | None = None, sensitivity: float | None = None,
         height: str | None = None, modality: str | None = None) -> list[Curve]:
    """The force curves of an AFM file, read by afmformats (``pip install 'mdrvisc[afm]'``).

    Reads what afmformats reads: JPK (``.jpk-force``, ``.jpk-force-map``, ``.jpk-qi-data``,
    ``.jpk-qi-series``), Asylum Igor (``.ibw``), afmformats' HDF5 (``.h5``) and
    tab-separated (``.tab``) exports, AFM workshop (``.csv``, zipped maps), NT-MDT text.
    Single curves give one :class:`Curve`, force maps and QI data one per pixel, with its
    ``grid_index`` and ``position``.

    Parameters
    ----------
    path : str or Path
        The file.
    spring_constant : float, optional
        The cantilever's spring constant (N/m), replacing the file's (needed where the file
        has none).
    sensitivity : float, optional
        The deflection sensitivity (m/V), for files that store volts without it.
    height : str, optional
        The column taken as the piezo position: "height (piezo)" (default, where present) or
        "height (measured)" (the height sensor's).
    modality : str, optional
        afmformats' modality ("force-distance", "creep-compliance", "stress-relaxation") of
        files that hold several.

    Returns
    -------
    list of Curve
        Piezo rising towards the sample (``-height``), deflection = force / k (m), times
        continuous through the segments (s), segments named "approach", "dwell", "retract".

    Raises
    ------
    ImportError
        afmformats is not installed.
    DataError
        The file is not a force curve file afmformats reads, or gives no spring constant.

    Examples
    --------
    >>> curves = mv.afm.load("map.jpk-force-map")    # doctest: +SKIP
    >>> curves[0].grid_index, curves[0].spring_constant   # doctest: +SKIP
    ((0, 0), 0.0155)
    """
    afmformats = _afmformats()
    path = pathlib.Path(path)
    if not path.exists():
        raise DataError(f"{path}: no such file")
    override: dict[str, float] = {}
    for key, value in (("spring constant", spring_constant), ("sensitivity", sensitivity)):
        if value is not None:
            if not (isinstance(value, (int, float)) and math.isfinite(value) and value > 0):
                raise InvalidInputError(f"load: {key.replace(' ', '_')} must be a number > 0, got {value!r}")
            override[key] = float(value)
    if height not in (None, "height (piezo)", "height (measured)"):
        raise InvalidInputError(f"load: height must be 'height (piezo)' or 'height (measured)', got "
                                f"{height!r}")
    # afmformats logs a loader's failure with its traceback before raising it; the DataError
    # below says what failed, so its logger is quiet while it reads
    quiet = logging.getLogger("afmformats")
    level = quiet.level
    quiet.setLevel(logging.CRITICAL)
    try:
        datasets = afmformats.load_data(path, meta_override=override or None, modality=modality)
    except afmformats.errors.FileFormatNotSupportedError as exc:
        raise DataError(f"{path}: not a file afmformats reads ({exc})") from None
    except afmformats.errors.AFMFileFormatError as exc:
        raise DataError(f"{path}: afmformats cannot read it: {type(exc).__name__}: {exc}") from None
    except afmformats.errors.MissingMetaDataError as exc:
        raise DataError(f"{path}: {exc} (give load(..., spring_constant=, sensitivity=))") from None
    except (NotImplementedError, ValueError, KeyError) as exc:
        raise DataError(f"{path}: afmformats cannot read it: {type(exc).__name__}: {exc}") from None
    finally:
        quiet.setLevel(level)
    return [_curve(data, i, path, height) for i, data in enumerate(datasets)]
