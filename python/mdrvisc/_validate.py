"""Argument validation shared by the modules of mdrvisc.

Each validator names the function or class it checks for (``owner``) and the argument
(``name``) in its InvalidInputError, and returns the value in the form the caller computes
with. This module imports nothing else from mdrvisc but its errors, so every module can use it.
"""

import math

import numpy as np
from numpy.typing import ArrayLike

from .errors import InvalidInputError


def _positive(owner: str, name: str, value: object) -> float:
    """``value`` as a float, or InvalidInputError unless it is a finite number > 0."""
    try:
        number = float(value)
    except (TypeError, ValueError):
        number = None
    if isinstance(value, bool) or number is None or not math.isfinite(number) or number <= 0.0:
        shown = repr(value) if number is None or isinstance(value, bool) else repr(number)
        raise InvalidInputError(f"{owner}: {name} must be a finite positive number, got {shown}")
    return number


def _optional_positive(owner: str, name: str, value: object) -> float | None:
    """``value`` as a float, None kept; InvalidInputError unless finite and > 0."""
    return None if value is None else _positive(owner, name, value)


def _array(owner: str, name: str, value: ArrayLike, minimum: float | None = None) -> np.ndarray:
    """``value`` as a float64 array, or InvalidInputError naming the first bad entry.

    Every entry must be finite and, when ``minimum`` is given, >= ``minimum``.
    """
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError):
        raise InvalidInputError(f"{owner}: {name} must be real numbers, got {value!r}") from None
    bad = ~np.isfinite(array)
    rule = "finite"
    if minimum is not None:
        bad |= array < minimum
        rule = f"finite and >= {minimum!r}"
    if bad.any():
        index = np.unravel_index(np.argmax(bad), array.shape) if array.ndim else ()
        where = f" at index {tuple(int(i) for i in index)}" if array.ndim else ""
        raise InvalidInputError(
            f"{owner}: {name} must be {rule}, got {float(array[index])!r}{where}"
        )
    return array


def _out(array: ArrayLike) -> float | np.ndarray:
    """A 0-d result as a Python float, anything else unchanged."""
    return float(array) if np.ndim(array) == 0 else array
