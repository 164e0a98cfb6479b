"""Height maps: a rigid surface given by its heights on a grid of square elements, a rough
surface measured or generated, or any shape sampled. A :class:`HeightMap` is an indenter of
:class:`mdrvisc.Scene`, solved by BEM on the map's own grid.

Units: lengths in m. Heights are the rigid surface's, of any sign: the highest point touches
first, and depths are measured from there. Element centres lie symmetric about the origin,
x_i = (i - (nx - 1) / 2) dx, and likewise y.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike

from ._validate import _array, _flag, _positive
from .errors import InvalidInputError

__all__ = ["HeightMap"]


def _topography(surface) -> tuple[np.ndarray, float | None, bool | None]:
    """(heights (ny, nx), pixel size (m) or None, periodicity or None) of a SurfaceTopography
    topography, read through its interface (``heights()``, ``pixel_size`` or
    ``physical_sizes`` and ``nb_grid_pts``, ``is_periodic``); its arrays are indexed (x, y)."""
    if getattr(surface, "dim", 2) != 2:
        raise InvalidInputError(f"HeightMap: a topography must be a 2-D map, got dim = {surface.dim!r}")
    if getattr(surface, "has_undefined_data", False):
        raise InvalidInputError("HeightMap: the topography has undefined (masked) data; fill or crop it")
    heights = np.asarray(surface.heights())
    if heights.ndim != 2:
        raise InvalidInputError(f"HeightMap: a topography must be a 2-D map, got shape {heights.shape}")
    size = getattr(surface, "pixel_size", None)
    if size is None and hasattr(surface, "physical_sizes"):
        size = np.asarray(surface.physical_sizes, dtype=np.float64) / np.asarray(heights.shape)
    dx = None
    if size is not None:
        sx, sy = (float(v) for v in np.broadcast_to(np.asarray(size, dtype=np.float64), (2,)))
        if not math.isclose(sx, sy, rel_tol=1e-9):
            raise InvalidInputError(
                f"HeightMap: the topography's pixels are not square ({sx!r} x {sy!r} m); resample it")
        dx = sx
    periodic = getattr(surface, "is_periodic", None)
    return heights.T, dx, None if periodic is None else bool(periodic)


class HeightMap:
    """A rigid surface given by its heights on a grid of square elements.

    Parameters
    ----------
    heights : array_like or topography
        Heights of the rigid surface (m), a 2-D array of real numbers of shape (ny, nx) (row
        index = y), of any sign: the highest point touches first. A topography of the
        optional SurfaceTopography package is accepted too: its heights (indexed (x, y)
        there) are transposed to (ny, nx), its pixel size gives ``dx`` and its periodicity
        ``periodic``.
    dx : float, optional
        Element side (m); required for an array, and for a topography equal to its pixel
        size when given.
    periodic : bool, optional
        Whether the map is one cell of a periodic surface (default False, or the
        topography's), solved with the periodic half-space. On a periodic cell ``force`` is
        the total force on the cell, the mean pressure times the cell's area; deflections
        have zero mean over the cell, and the depth is the approach of the highest point
        from the deflected surface's mean plane, so that the mean gap (the mean separation)
        is the mean height below the highest point minus the depth: to hold a mean
        separation g, prescribe the depth ``heights.max() - heights.mean() - g``. Contact
        patches join across opposite edges.

    Notes
    -----
    The map fixes the BEM grid, so ``solve(scene, "bem")`` needs no ``n`` (given, it must be
    the longer side, :attr:`n`); MDR cannot solve a height map. Besides the depth and the
    contact area a solve reports the contact fraction, the number of contact patches and the
    mean gap at every output time, and ``"gap"`` fields when asked for.
    """

    def __init__(self, heights: ArrayLike, dx: float | None = None, periodic: bool | None = None) -> None:
        given_dx, given_periodic = None, None
        if callable(getattr(heights, "heights", None)) and (
                hasattr(heights, "pixel_size") or hasattr(heights, "physical_sizes")):
            heights, given_dx, given_periodic = _topography(heights)
        array = np.asarray(heights)
        if array.dtype.kind not in "iuf":
            raise InvalidInputError(
                f"HeightMap: heights must be real numbers (integer or float), got dtype {array.dtype}")
        if array.ndim != 2:
            raise InvalidInputError(f"HeightMap: heights must be a 2-D array (ny, nx), got {array.shape}")
        if array.size == 0:
            raise InvalidInputError(f"HeightMap: heights are empty (shape {array.shape})")
        array = np.array(_array("HeightMap", "heights", array), dtype=np.float64, order="C")
        array.flags.writeable = False
        if dx is None:
            if given_dx is None:
                raise InvalidInputError("HeightMap: dx (the element side, m) is required for an array")
            dx = given_dx
        dx = _positive("HeightMap", "dx", dx)
        if given_dx is not None and not math.isclose(dx, given_dx, rel_tol=1e-9):
            raise InvalidInputError(
                f"HeightMap: dx = {dx!r} differs from the topography's pixel size {given_dx!r}")
        if periodic is None:
            periodic = bool(given_periodic)
        self._heights = array
        self._dx = dx
        self._periodic = _flag("HeightMap", "periodic", periodic)

    @property
    def heights(self) -> np.ndarray:
        """Heights (m), read-only, shape (ny, nx)."""
        return self._heights

    @property
    def dx(self) -> float:
        """Element side (m)."""
        return self._dx

    @property
    def periodic(self) -> bool:
        """Whether the map is one cell of a periodic surface."""
        return self._periodic

    @property
    def shape(self) -> tuple[int, int]:
        """(ny, nx)."""
        ny, nx = self._heights.shape
        return int(ny), int(nx)

    @property
    def n(self) -> int:
        """The resolution of a solve on the map: its longer side, in elements."""
        return max(self.shape)

    @property
    def x(self) -> np.ndarray:
        """Element-centre x (m), (nx,)."""
        nx = self.shape[1]
        return (np.arange(nx) - 0.5 * (nx - 1)) * self._dx

    @property
    def y(self) -> np.ndarray:
        """Element-centre y (m), (ny,)."""
        ny = self.shape[0]
        return (np.arange(ny) - 0.5 * (ny - 1)) * self._dx

    def _model(self, extent: float | None = None) -> dict:
        """The map in the scene model's form (a scene file's ``[indenter]`` table), its
        heights as the read-only array, which the core copies once."""
        return {"type": "heightmap", "heights": self._heights, "dx": self._dx, "periodic": self._periodic}

    @classmethod
    def _of_core(cls, heights: np.ndarray, dx: float, periodic: bool = False) -> HeightMap:
        """The map of a core scene's heights (a float64 array of its own, validated there),
        held without a copy."""
        heights.flags.writeable = False
        out = cls.__new__(cls)
        out._heights, out._dx, out._periodic = heights, float(dx), bool(periodic)
        return out

    def __repr__(self) -> str:
        """``HeightMap(shape=(ny, nx), dx=..., periodic=...)``."""
        return f"HeightMap(shape={self.shape}, dx={self._dx!r}, periodic={self._periodic!r})"
