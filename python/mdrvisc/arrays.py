"""Array-level BEM entry points for any height map: off-centre, tilted, asymmetric or
non-square indenters that the axisymmetric geometry classes do not describe.

Height maps are (ny, nx) arrays of the indenter's height above its tip at element centres
(m, >= 0), with square elements of side ``dx`` (m). Inputs of any real dtype and memory
layout are accepted (copied to contiguous float64); complex, object or non-finite entries
are errors.
"""

import json
from collections.abc import Callable

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import _array, _callback, _flag, _integer, _number, _positive
from .errors import DomainError, InvalidInputError
from .result import Result

__all__ = ["contact", "adhesive_curve", "adhesive_pull_off", "viscous", "SurfaceOperator"]


def _grid(name, a):
    """``a`` as a C-contiguous 2-D float64 array; InvalidInputError naming ``name`` else."""
    arr = np.asarray(a)
    if arr.dtype.kind not in "biuf":
        raise InvalidInputError(f"{name} must hold real numbers, got dtype {arr.dtype}")
    if arr.ndim != 2 or arr.size == 0:
        raise InvalidInputError(f"{name} must be a non-empty 2-D array, got shape {arr.shape}")
    arr = np.ascontiguousarray(arr, dtype=np.float64)
    bad = np.argwhere(~np.isfinite(arr))
    if bad.size:
        index = tuple(bad[0].tolist())
        raise InvalidInputError(f"{name} must be finite, got {arr[tuple(bad[0])]} at index {index}")
    return arr


class SurfaceOperator:
    """The surface operator of a half-space on a grid, built once, applied many times:
    element pressures (Pa) to element-centre deflections (m) of an incompressible
    half-space with G = 1 Pa (FFTs in Rust, GIL released). Divide by the shear modulus G for
    an elastic body, or by eta for the surface velocity of a viscous one. One operator may be
    shared between threads: its buffers are behind a lock, so calls from different threads
    run one after the other (build one operator per thread to apply in parallel).

    Non-periodic (default): Love's coefficients of uniformly loaded squares, by zero-padded
    FFT convolution. ``periodic=True``: the grid is one period of a periodic cell, and the
    kernel is the half-space's spectral response u_q = p_q / (2 G abs(q)) at the cell's
    discrete wavevectors (E* = 4 G), with the mean mode set to zero: deflections have zero
    mean over the cell (a uniform pressure gives none), which makes the rigid-body approach
    of a contact the approach from the deflected surface's mean plane.

    Parameters
    ----------
    shape : (int, int)
        Grid shape (ny, nx), >= 1 each.
    dx : float
        Element side (m), > 0.
    periodic : bool
        Whether the grid is a periodic cell.

    Attributes ``shape``, ``dx``, ``periodic`` and ``padded`` (the FFT sizes (y, x): the
    grid's own for a periodic cell).
    """

    def __init__(self, shape: tuple[int, int], dx: float, periodic: bool = False) -> None:
        try:
            ny, nx = shape
        except (TypeError, ValueError):
            raise InvalidInputError(f"SurfaceOperator: shape must be (ny, nx), got {shape!r:.200}") from None
        ny = _integer("SurfaceOperator", "shape[0]", ny, 1)
        nx = _integer("SurfaceOperator", "shape[1]", nx, 1)
        self._op = _core.SurfaceOperator(nx, ny, _positive("SurfaceOperator", "dx", dx),
                                         periodic=_flag("SurfaceOperator", "periodic", periodic))

    @property
    def shape(self) -> tuple[int, int]:
        """Grid shape (ny, nx)."""
        return self._op.shape

    @property
    def dx(self) -> float:
        """Element side (m)."""
        return self._op.dx

    @property
    def padded(self) -> tuple[int, int]:
        """FFT sizes (y, x): zero-padded, or the grid's own for a periodic cell."""
        return self._op.padded

    @property
    def periodic(self) -> bool:
        """Whether the grid is a periodic cell."""
        return self._op.periodic

    def apply(self, p: ArrayLike, out: np.ndarray | None = None) -> np.ndarray:
        """Deflection (m, shape (ny, nx)) under pressures ``p`` (Pa, shape (ny, nx), any real
        dtype; non-finite values are errors) at G = 1 Pa. With ``out`` (a C-contiguous,
        writable float64 array of that shape) the deflection is written there and ``out`` is
        returned, which spares a solver loop the allocation of a new array per call."""
        arr = np.asarray(p)
        if arr.dtype.kind not in "biuf":
            raise InvalidInputError(f"pressure must hold real numbers, got dtype {arr.dtype}")
        if arr.shape != self.shape:
            raise InvalidInputError(f"pressure must have the operator's shape {self.shape}, got {arr.shape}")
        if out is not None and (not isinstance(out, np.ndarray) or out.dtype != np.float64):
            raise InvalidInputError(f"out must be a float64 numpy array, got {out!r:.60}")
        return self._op.apply(np.ascontiguousarray(arr, dtype=np.float64), out)

    def __repr__(self) -> str:
        return f"SurfaceOperator(shape={self.shape}, dx={self.dx!r}, periodic={self.periodic})"


def _mask(mask, shape):
    if mask is None:
        return np.ones(shape, dtype=bool)
    m = np.asarray(mask)
    if m.dtype != bool or m.shape != shape:
        raise InvalidInputError(f"mask must be a boolean array of shape {shape}, got {m.dtype} {m.shape}")
    return np.ascontiguousarray(m)


def contact(height: ArrayLike, dx: float, G: float, force: float | None = None,
            depth: float | None = None, mask: ArrayLike | None = None, tol: float = 1e-10,
            max_iter: int = 5000, active_limit: int | None = None, precondition: bool = True,
            depth_bound: float | None = None, deflection: bool = True, periodic: bool = False,
            mean_separation: float | None = None) -> Result:
    """Static elastic contact of a rigid indenter on an incompressible half-space of shear
    modulus ``G`` (Pa) under ``force`` (N) or at ``depth`` (m).

    ``periodic=True`` makes the map one period of a periodic cell (the periodic operator of
    :class:`SurfaceOperator`), solved whole: ``force`` is the total force on the cell (mean
    pressure times the cell area), ``depth`` the rigid-body approach from the mean plane of
    the deflected surface, and ``mean_separation`` (m, > 0; periodic only) the mean gap
    mean(height) - depth to hold instead; give exactly one of the three. The result's depth
    is that approach (mean separation = mean(height) - depth); ``depth_bound`` does not
    apply and ``at_edge`` is False.

    The solver is Polonsky–Keer (FFT conjugate gradients, relative tolerance ``tol``) or,
    while the contact set stays small, a dense primal-dual active-set solve (faer Cholesky on
    the set, exact to round-off): ``active_limit=None`` picks the faster from the measured
    crossover for the grid, 0 forces Polonsky–Keer, a number caps the dense set (elements).
    ``precondition`` applies the truncated inverse-kernel stencil to Polonsky–Keer's search
    directions (2–3x fewer iterations on large contacts, the same solution); False gives the
    plain method.

    The solve runs on the window (sub-grid, 2 elements of margin) of the elements that can
    touch: those with height <= depth, or under force control with height <= ``depth_bound``
    (m), an upper bound on the depth such as MDR's (without one, the whole grid). The result
    is the whole grid's, exactly, since deflections are positive; a bound the depth exceeds
    is widened and the solve repeated (``solves``). ``deflection=False`` skips the
    whole-grid deflection, which costs an operator on the whole grid when the window is
    smaller.

    Returns a :class:`Result` with t = [0]: depth (m), force (N), area (m^2), the fields at
    t = 0 (``result.fields[0.0].pressure`` in Pa and ``.deflection`` in m, (ny, nx)),
    ``solver`` ("polonsky-keer" or "active-set"), ``solves``, ``iterations`` (over all
    solves), ``residual``, ``window`` ((y0, x0, rows, columns) of the last solve).
    """
    h = _grid("height", height)
    dx = _positive("contact", "dx", dx)
    G = _positive("contact", "G", G)
    periodic = _flag("contact", "periodic", periodic)
    if mean_separation is not None:
        if not periodic:
            raise InvalidInputError("contact: mean_separation needs periodic=True")
        if depth is not None:
            raise InvalidInputError("contact: give exactly one of force, depth and mean_separation")
        depth = float(np.mean(h)) - _positive("contact", "mean_separation", mean_separation)
    if (force is None) == (depth is None):
        which = "force, depth and mean_separation" if periodic else "force and depth"
        raise InvalidInputError(f"contact: give exactly one of {which}")
    if force is not None:
        force = _positive("contact", "force", force)
    if depth_bound is not None:
        if periodic:
            raise InvalidInputError("contact: depth_bound sizes windows, which a periodic cell does not have")
        depth_bound = _positive("contact", "depth_bound", depth_bound)
    r = _core.contact_solve(h, _mask(mask, h.shape), dx, 1.0 / G, force=force,
                            depth=None if depth is None else _number("contact", "depth", depth),
                            tol=_positive("contact", "tol", tol),
                            max_iter=_integer("contact", "max_iter", max_iter, 1),
                            active_limit=None if active_limit is None
                            else _integer("contact", "active_limit", active_limit, 0),
                            precondition=_flag("contact", "precondition", precondition),
                            depth_bound=depth_bound, deflection=_flag("contact", "deflection", deflection),
                            periodic=periodic)
    return Result._from_report(r)


def _cohesive(owner, law):
    """The JSON table of a cohesive law for the core; InvalidInputError for other laws."""
    from .contact import Exponential, MaugisDugdale

    if not isinstance(law, (MaugisDugdale, Exponential)):
        raise InvalidInputError(f"{owner}: contact must be mv.MaugisDugdale or mv.Exponential, "
                                f"got {law!r}")
    return json.dumps(law._model())


def adhesive_curve(height: ArrayLike, dx: float, G: float, contact, depths: ArrayLike,
                   mask: ArrayLike | None = None, periodic: bool = False, tol: float = 1e-10,
                   max_iter: int = 5000) -> dict[str, np.ndarray]:
    """Static adhesive contact under a cohesive-zone law (``mv.MaugisDugdale`` or
    ``mv.Exponential``) of a rigid indenter on an incompressible half-space of shear modulus
    ``G`` (Pa; E* = 4 G), at each approach of ``depths`` (m) in turn, each solve started from
    the last (a depth-controlled approach and retract follows its history: the zone a
    retract keeps is the one it had). ``height`` is the separation before loading (m), on
    elements of side ``dx`` (m); ``periodic=True`` makes it one period of a periodic cell,
    the depth then the approach from the deflected surface's mean plane.

    Returns a dict of arrays per depth: ``depth`` (m), ``force`` (N, tensile: negative),
    ``contact`` and ``zone`` (elements at zero gap, and out of contact within the law's
    range), ``energy`` (J, elastic plus interaction), ``sweeps`` and ``iterations``.

    >>> import numpy as np, mdrvisc as mv
    >>> x = (np.arange(32) - 15.5) * 0.04
    >>> h = (x[:, None] ** 2 + x[None, :] ** 2) / 2          # a sphere of radius 1 m
    >>> law = mv.MaugisDugdale(work_of_adhesion=0.01, stress=0.2)
    >>> c = mv.arrays.adhesive_curve(h, 0.04, 1.0, law, [0.01, 0.0, -0.02])  # doctest: +SKIP
    """
    h = _grid("height", height)
    d = np.ascontiguousarray(np.atleast_1d(_array("adhesive_curve", "depths", depths)).ravel())
    r = _core.cohesive_curve(h, _mask(mask, h.shape), _positive("adhesive_curve", "dx", dx),
                             1.0 / _positive("adhesive_curve", "G", G),
                             _cohesive("adhesive_curve", contact), d,
                             tol=_positive("adhesive_curve", "tol", tol),
                             max_iter=_integer("adhesive_curve", "max_iter", max_iter, 1),
                             periodic=_flag("adhesive_curve", "periodic", periodic))
    return dict(r)


def adhesive_pull_off(height: ArrayLike, dx: float, G: float, contact, d_max: float,
                      d_min: float, steps: int = 30, mask: ArrayLike | None = None,
                      periodic: bool = False, tol: float = 1e-10,
                      max_iter: int = 5000) -> dict[str, float]:
    """The pull-off of :func:`adhesive_curve`'s contact: approach to ``d_max`` and retract
    to ``d_min`` (m) in ``steps`` steps each, and the least force along the retract, its
    depth refined three times over the two steps around it (the force a force-controlled
    retract lets go at). Returns a dict: ``force`` (N, negative), ``depth`` (m), ``contact``
    and ``zone`` (elements there), ``solves``.

    >>> import numpy as np, mdrvisc as mv
    >>> x = (np.arange(32) - 15.5) * 0.04
    >>> h = (x[:, None] ** 2 + x[None, :] ** 2) / 2
    >>> law = mv.MaugisDugdale(work_of_adhesion=0.01, stress=0.2)
    >>> mv.arrays.adhesive_pull_off(h, 0.04, 1.0, law, 0.02, -0.1)["force"]  # doctest: +SKIP
    """
    h = _grid("height", height)
    r = _core.cohesive_pull_off(h, _mask(mask, h.shape), _positive("adhesive_pull_off", "dx", dx),
                                1.0 / _positive("adhesive_pull_off", "G", G),
                                _cohesive("adhesive_pull_off", contact),
                                _number("adhesive_pull_off", "d_max", d_max),
                                _number("adhesive_pull_off", "d_min", d_min),
                                steps=_integer("adhesive_pull_off", "steps", steps, 1),
                                tol=_positive("adhesive_pull_off", "tol", tol),
                                max_iter=_integer("adhesive_pull_off", "max_iter", max_iter, 1),
                                periodic=_flag("adhesive_pull_off", "periodic", periodic))
    return dict(r)


def viscous(height: ArrayLike, dx: float, eta: float,
            force: float | tuple[ArrayLike, ArrayLike], times: ArrayLike,
            mask: ArrayLike | None = None, rates: bool = False, tol: float = 1e-10,
            max_iter: int = 5000, unbounded: bool = False,
            progress: Callable[[str, int, int], object] | None = None,
            precondition: bool = True) -> Result:
    """Implicit viscous BEM run for any height map: a rigid indenter under ``force`` (N, a
    number or (times, forces) samples) on a half-space of viscosity ``eta`` (Pa s), with
    output at ``times`` (s).

    With ``unbounded=True`` the grid is a window onto a larger indenter, and a contact that
    reaches the grid's edge raises DomainError instead of being a finite indenter's edge.
    ``precondition=False`` turns off the inverse-kernel preconditioner of the contact solves
    (see :func:`contact`).
    Returns a :class:`Result` (contact_length from the contact area).
    """
    h = _grid("height", height)
    m = _mask(mask, h.shape)
    dx = _positive("viscous", "dx", dx)
    eta = _positive("viscous", "eta", eta)
    if np.isscalar(force) or (isinstance(force, np.ndarray) and force.ndim == 0):
        ft, fv = np.array([0.0]), np.array([_positive("viscous", "force", force)])
    else:
        try:
            ft, fv = force  # type: ignore[misc]
        except (TypeError, ValueError):
            raise InvalidInputError(
                f"viscous: force must be a number or (times, forces), got {force!r:.200}") from None
        ft = np.ascontiguousarray(_array("viscous", "force times", ft).ravel())
        fv = np.ascontiguousarray(_array("viscous", "forces", fv).ravel())
    t = np.ascontiguousarray(_array("viscous", "times", times).ravel())
    options = {"rates": _flag("viscous", "rates", rates), "tol": _positive("viscous", "tol", tol),
               "max_iter": _integer("viscous", "max_iter", max_iter, 1),
               "progress": _callback("viscous", "progress", progress),
               "precondition": _flag("viscous", "precondition", precondition)}
    r = _core.bem_viscous(h, m, dx, eta, t, ft, fv, **options)
    unbounded = _flag("viscous", "unbounded", unbounded)
    result = Result._from_report(r)
    if unbounded and np.any(result.at_edge):
        first = result.t[np.argmax(result.at_edge)]
        raise DomainError(f"BEM: the contact reached the edge of the grid at t = {first} s")
    return result
