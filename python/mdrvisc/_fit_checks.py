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



#: Singular values of the Jacobian (its columns scaled to unit norm) below this fraction of
#: the largest leave a direction of the parameters undetermined: its standard errors are
#: infinite (a relative standard error of 1 / this at unit residuals is far past any use).
RANK_TOLERANCE = 1e-10


def covariance(jac: np.ndarray, variance: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(standard errors, correlation matrix, undetermined mask) of parameters whose residuals
    have the Jacobian ``jac`` (one column per parameter, in the parameters' units) and the
    ``variance``, from the singular value decomposition of ``jac`` with unit-norm columns.

    A parameter with a component along a direction of singular value below
    :data:`RANK_TOLERANCE` (rank deficiency, or a column that is zero) is undetermined: its
    standard error is inf and its correlations NaN. The others' covariance is the
    pseudo-inverse's over the determined directions; the correlation matrix is symmetric
    with entries in [-1, 1] and ones on its diagonal, and does not depend on ``variance``
    (zero for noise-free data, where the standard errors are zero)."""
    norms = np.linalg.norm(jac, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    _, s, vt = np.linalg.svd(jac / safe, full_matrices=False)
    largest = float(s[0]) if s.size and np.isfinite(s[0]) else 0.0
    keep = s > RANK_TOLERANCE * largest if largest > 0 else np.zeros(s.size, bool)
    v = vt.T
    null = v[:, ~keep]
    undetermined = (norms == 0) | (np.linalg.norm(null, axis=1) > np.sqrt(RANK_TOLERANCE))
    scaled = (v[:, keep] / s[keep]) @ (v[:, keep] / s[keep]).T  # (J^T J)^+ of the scaled columns
    diagonal = np.sqrt(np.maximum(np.diag(scaled), 0.0))
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        correlation = np.clip(scaled / np.outer(diagonal, diagonal), -1.0, 1.0)
        stderr = np.sqrt(variance) * diagonal / safe
    correlation = 0.5 * (correlation + correlation.T)
    stderr[undetermined] = np.inf
    correlation[undetermined, :] = np.nan
    correlation[:, undetermined] = np.nan
    np.fill_diagonal(correlation, 1.0)
    return stderr, correlation, undetermined


def identifiability(free: list[str], relative_err: np.ndarray, correlation: np.ndarray,
                    undetermined: np.ndarray) -> list[str]:
    """Messages naming the parameters the data do not determine: ``undetermined`` ones (a
    rank-deficient Jacobian), those whose ``relative_err`` (standard error over the value,
    or over the scale of a raw curve's contact point and baseline) exceeds
    :data:`LARGEST_RELATIVE_ERROR`, and pairs correlated beyond :data:`LARGEST_CORRELATION`."""
    out = []
    lost = [name for name, u in zip(free, undetermined) if u]
    if lost:
        out.append(f"fit: {', '.join(lost)} {'is' if len(lost) == 1 else 'are'} not determined by the data: "
                   "the Jacobian is rank deficient (no change of "
                   f"{'it' if len(lost) == 1 else 'them together'} changes the model to first order); "
                   "standard errors inf, correlations NaN")
    for name, e, u in zip(free, relative_err, undetermined):
        if not u and not e <= LARGEST_RELATIVE_ERROR:
            out.append(f"fit: {name} is not identified by the data: its relative standard error is {e:.3g}")
    for i, j in zip(*np.triu_indices(len(free), 1)):
        if abs(correlation[i, j]) > LARGEST_CORRELATION:
            out.append(f"fit: {free[i]} and {free[j]} are not separately identified: correlation "
                       f"{correlation[i, j]:+.5f}")
    return out
