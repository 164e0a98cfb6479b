"""Argument validation shared by the modules of mdrvisc.

Each validator names the function or class it checks for (``owner``) and the argument
(``name``) in its InvalidInputError, and returns the value in the form the caller computes
with. This module imports nothing else from mdrvisc but its errors and the compiled core's
range of physical inputs, so every module can use it.
"""

import math
import operator

import numpy as np
from numpy.typing import ArrayLike

from ._core import MAGNITUDE, MAX_FILE_BYTES
from .errors import InvalidInputError


def _read_text(path, what: str) -> str:
    """The text of the file at ``path`` (a ``what``, e.g. "sweep file"), read as the scene
    files are: at most :data:`mdrvisc._core.MAX_FILE_BYTES` bytes, UTF-8 with or without a
    byte-order mark; InvalidInputError naming the file otherwise (also when it cannot be
    read)."""
    try:
        with open(path, "rb") as handle:
            data = handle.read(MAX_FILE_BYTES + 1)
    except OSError as exc:
        raise InvalidInputError(f"cannot read {what} {str(path)!r}: {exc.strerror or exc}") from None
    if len(data) > MAX_FILE_BYTES:
        raise InvalidInputError(f"{path}: a {what} is at most {MAX_FILE_BYTES} bytes")
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise InvalidInputError(f"{path}: not UTF-8 text (byte {exc.start} is "
                                f"{data[exc.start:exc.start + 1]!r})") from None


def _float(value: object) -> float | None:
    """``value`` as a float, None when it is no real number (bools, strings, ints too large
for a float)."""
    if isinstance(value, (bool, np.bool_, str, bytes)):
        return None
    try:
        return float(value)  # type: ignore[arg-type]
    except (TypeError, ValueError, OverflowError):
        return None


def _magnitude(owner: str, name: str, number: float) -> float:
    """``number``, or InvalidInputError unless it is 0 or its magnitude lies within the
    crate's range of physical inputs ([1 / MAGNITUDE, MAGNITUDE])."""
    m = abs(number)
    if number != 0.0 and not (1.0 / MAGNITUDE <= m <= MAGNITUDE):
        raise InvalidInputError(
            f"{owner}: {name} = {number!r} is out of range: physical inputs must lie within "
            f"1e-100..1e100 in magnitude (rescale the units)")
    return number


def _positive(owner: str, name: str, value: object) -> float:
    """``value`` as a float, or InvalidInputError unless it is a finite number > 0 within
    the range of physical inputs."""
    return _magnitude(owner, name, _finite_positive(owner, name, value))


def _finite_positive(owner: str, name: str, value: object) -> float:
    """``value`` as a float, or InvalidInputError unless it is a finite number > 0 (for step
    lengths, whose smallness the crate bounds by the step count instead)."""
    number = _float(value)
    if number is None or not math.isfinite(number) or number <= 0.0:
        shown = f"{value!r:.80}" if number is None else repr(number)
        raise InvalidInputError(f"{owner}: {name} must be a finite positive number, got {shown}")
    return number


def _number(owner: str, name: str, value: object) -> float:
    """``value`` as a float, or InvalidInputError unless it is a finite real number within
    the range of physical inputs."""
    number = _float(value)
    if number is None or not math.isfinite(number):
        raise InvalidInputError(f"{owner}: {name} must be a finite real number, got {value!r:.80}")
    return _magnitude(owner, name, number)


def _poisson_ratio(owner: str, value: object) -> float:
    """``value`` as a float, or InvalidInputError naming ``nu`` unless it is a real number
    with -1 < nu <= 0.5 (the Poisson ratio of a stable isotropic solid; 0.5 is
    incompressible)."""
    number = _float(value)
    if number is None or not -1.0 < number <= 0.5:
        raise InvalidInputError(
            f"{owner}: nu (Poisson ratio) must be a real number with -1 < nu <= 0.5, got {value!r:.80}")
    return number


def _integer(owner: str, name: str, value: object, minimum: int, maximum: int | None = None) -> int:
    """``value`` as an int, or InvalidInputError unless it is an integer in [``minimum``,
    ``maximum``] (default: the largest the compiled core can take; bools and floats are
    refused, not truncated)."""
    try:
        number = None if isinstance(value, (bool, np.bool_)) else operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        number = None
    top = _LARGEST_INTEGER if maximum is None else maximum
    if number is None or number < minimum or number > top:
        shown = "2**63 - 1" if maximum is None else str(maximum)
        raise InvalidInputError(
            f"{owner}: {name} must be an integer in [{minimum}, {shown}], got {value!r:.80}")
    return number


#: The largest integer the compiled core takes (its sizes and counts are 64-bit).
_LARGEST_INTEGER = 2**63 - 1


def _flag(owner: str, name: str, value: object) -> bool:
    """``value`` as a bool, or InvalidInputError unless it is True or False."""
    if not isinstance(value, (bool, np.bool_)):
        raise InvalidInputError(f"{owner}: {name} must be True or False, got {value!r}")
    return bool(value)


def _callback(owner: str, name: str, value: object) -> object:
    """``value``, or InvalidInputError unless it is None or callable."""
    if value is not None and not callable(value):
        raise InvalidInputError(f"{owner}: {name} must be a callable or None, got {value!r}")
    return value


def _optional_positive(owner: str, name: str, value: object) -> float | None:
    """``value`` as a float, None kept; InvalidInputError unless finite and > 0."""
    return None if value is None else _positive(owner, name, value)


def _array(owner: str, name: str, value: ArrayLike, minimum: float | None = None) -> np.ndarray:
    """``value`` as a float64 array, or InvalidInputError naming the first bad entry.

    Every entry must be finite and, when ``minimum`` is given, >= ``minimum``.
    """
    try:
        array = np.asarray(value, dtype=np.float64)
    except (TypeError, ValueError, OverflowError):
        raise InvalidInputError(f"{owner}: {name} must be real numbers, got {value!r:.200}") from None
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
