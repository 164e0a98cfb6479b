"""Checks of a fit's data (finite one-dimensional arrays, strictly increasing times) and of
its outcome (parameters the data do not identify)."""

import numpy as np
from numpy.typing import ArrayLike

from .errors import DataError

#: A parameter whose standard error exceeds this fraction of its value is not identified.
LARGEST_RELATIVE_ERROR = 0.5

#: Parameters whose correlation exceeds this in magnitude are not separately identified.
LARGEST_CORRELATION = 0.999


def array(name: str, values: ArrayLike) -> np.ndarray:
    """``values`` as a 1D float64 array, or DataError naming the first entry that is not finite."""
    try:
        a = np.ascontiguousarray(values, dtype=float)
    except (TypeError, ValueError, OverflowError) as exc:
        raise DataError(f"fit: {name} must be an array of real numbers: {exc}") from None
    if a.ndim != 1:
        raise DataError(f"fit: {name} must be one-dimensional, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise DataError(f"fit: {name} must be finite, got {a[bad[0]]} at index {bad[0]} "
                        f"({bad.size} such entries)")
    return a


def check_times(t: np.ndarray) -> None:
    """DataError unless the times ``t`` (s) are >= 0 and strictly increasing, naming the first
    pair that is not."""
    if t.size and t[0] < 0:
        raise DataError(f"fit: times must be >= 0, got t[0] = {t[0]}")
    steps = np.diff(t)
    for problem, bad in (("duplicate", steps == 0), ("unsorted", steps < 0)):
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise DataError(f"fit: times must increase strictly; {problem} times: t[{k}] = {t[k]!r}, "
                            f"t[{k + 1}] = {t[k + 1]!r}")



def identifiability(free: list[str], log_err: np.ndarray, correlation: np.ndarray) -> list[str]:
    """Messages naming the parameters the data do not determine."""
    out = []
    for name, e in zip(free, log_err):
        if not e <= LARGEST_RELATIVE_ERROR:
            out.append(f"fit: {name} is not identified by the data: its relative standard error is {e:.3g}")
    for i, j in zip(*np.triu_indices(len(free), 1)):
        if abs(correlation[i, j]) > LARGEST_CORRELATION:
            out.append(f"fit: {free[i]} and {free[j]} are not separately identified: correlation "
                       f"{correlation[i, j]:+.5f}")
    return out
