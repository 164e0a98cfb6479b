"""``solve(scene, method, n)``: run a scene by BEM or MDR and return a :class:`Result`.

Grid sizing, the choice of engine (static contact, the exact viscous impulse step, the
paper's explicit loop, viscoelastic stepping) and the report are the compiled scene model's;
this module passes the options through, with the GIL released while it runs.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from . import _core
from ._validate import _callback, _finite_positive, _integer, _number, _positive
from .errors import InvalidInputError
from .heightmap import HeightMap
from .progress import ProgressBar
from .result import Result
from .scene import Scene

__all__ = ["solve", "DEFAULT_N", "SOLVER_DEFAULTS"]

#: Resolutions used when ``n`` is not given: the paper's (the compiled core's, by method).
DEFAULT_N = dict(_core.DEFAULT_N)
#: Defaults of the solver options: the compiled core's (its ``SolverOptions`` and
#: ``ExplicitControl``), which the signature of :func:`solve` repeats.
SOLVER_DEFAULTS = dict(_core.SOLVER_DEFAULTS)


_log = logging.getLogger("mdrvisc")


def resolution(scene: Scene, method: str, n: int | None) -> int:
    """The ``n`` a solve of ``scene`` by ``method`` runs at: ``n`` when given, else a height
    map's own (its longer side) or the method's default (``DEFAULT_N``)."""
    if n is not None:
        return n
    return scene.indenter.n if isinstance(scene.indenter, HeightMap) else DEFAULT_N[method]


def solve(scene: Scene, method: str = "bem", n: int | None = None, tol: float = SOLVER_DEFAULTS["tol"],
          max_iter: int = SOLVER_DEFAULTS["max_iter"],
          progress: Callable[[str, int, int], object] | bool | None = None,
          integrator: str = SOLVER_DEFAULTS["integrator"], step: float = SOLVER_DEFAULTS["step"],
          area_change: float = SOLVER_DEFAULTS["area_change"],
          dt: float | None = SOLVER_DEFAULTS["dt"]) -> Result:
    """Solves ``scene`` by ``method`` ("bem" or "mdr") at resolution ``n``.

    Parameters
    ----------
    scene : Scene
    method : {"bem", "mdr"}
    n : int, optional
        BEM: elements across the grid (n x n, at most 8192), which covers the footprint, or
        1.2 times the largest contact radius for an unbounded indenter and for a sphere whose
        contact stays inside its footprint; MDR: elements of the
        1D indenter. Default 257 (BEM) or 66049 (MDR), the paper's resolutions. A
        :class:`~mdrvisc.HeightMap` fixes the grid: its ``n`` (the longer side) by default,
        and any other is refused.
    tol : float
        Relative tolerance of the BEM contact solver (sum ``|dp|`` / sum p); MDR is exact.
    max_iter : int
        Iteration limit of the BEM solver; reaching it raises ConvergenceError.
    progress : callable(stage, done, total) or True, optional
        Called from the calling thread between chunks of work; an exception it raises stops
        the run and propagates. True: a :class:`~mdrvisc.progress.ProgressBar` (a bar with
        the time left; tqdm's, in terminals and notebooks, when tqdm is installed).
    integrator : {"implicit", "explicit"}
        Viscous medium under a force: "implicit" (default) takes one exact impulse step per
        output time (no time-discretisation error while the contact grows); "explicit" is
        the paper's loop (Fig. 1b): surface velocity of the current contact, explicit Euler
        steps dt = step * t, the contact re-solved when its area grew by more than
        ``area_change`` (paper: 1 %). A flat punch needs one solve whatever is named.
    step, area_change : float
        Controls of the explicit integrator.
    dt : float, optional
        Longest time step (s) of the viscoelastic stepping; default ``scene.dt``, else
        duration / 500.

    Returns
    -------
    Result
        The series at the output times and the fields at the field times, with what the run
        did (steps, solves, iterations, wall time) and its warnings.

    Raises
    ------
    InvalidInputError
        A bad method, resolution or option (the message names it).
    ConvergenceError
        The BEM contact solver reached ``max_iter``.
    DomainError
        The contact left what the method represents (an unbounded grid's edge, a sphere's
        equator).

    See Also
    --------
    mdrvisc.load_curve : a static scene under several loads, warm-started.
    mdrvisc.solve_many : many scenes in parallel, locally or on a Dask cluster.
    mdrvisc.Result.to_xarray : the result as a labelled Dataset (netCDF).

    Examples
    --------
    The paper's paraboloid on a viscous half-space by both methods, against Lee and Radok:

    >>> import mdrvisc as mv
    >>> scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0),
    ...                  force=1.0, duration=5.0)
    >>> bem = mv.solve(scene, method="bem", n=129)                   # doctest: +SKIP
    >>> mdr = mv.solve(scene, method="mdr", n=4097)                  # doctest: +SKIP
    >>> exact = mv.analytic.paraboloid_depth(bem.t, 1.0, 1.0, 1.0)   # doctest: +SKIP
    >>> bem.depth / exact - 1                                        # doctest: +SKIP
    """
    if not isinstance(scene, Scene):
        raise InvalidInputError(f"solve: scene must be a Scene, got {scene!r}")
    if method not in DEFAULT_N:
        raise InvalidInputError(f"solve: method must be 'bem' or 'mdr', got {method!r}")
    n = _integer("solve", "n", resolution(scene, method, n), 1)
    if integrator not in ("implicit", "explicit"):
        raise InvalidInputError(f"solve: integrator must be 'implicit' or 'explicit', got {integrator!r}")
    # every option is checked, whether or not this scene and method use it
    options = {"tol": _positive("solve", "tol", tol), "max_iter": _integer("solve", "max_iter", max_iter, 1),
               "step": _finite_positive("solve", "step", step),
               "area_change": _number("solve", "area_change", area_change),
               "dt": None if dt is None else _finite_positive("solve", "dt", dt)}
    if options["area_change"] < 0:
        raise InvalidInputError(f"solve: area_change must be >= 0, got {area_change!r}")
    if progress is not True and progress is not False:
        _callback("solve", "progress", progress)
    callback = ProgressBar() if progress is True else (progress or None)
    _log.info("solve: %s n=%d, %r", method.upper(), n, scene)
    try:
        report = _core.run_scene(scene._model, method, n, integrator=integrator, progress=callback, **options)
    finally:
        if isinstance(callback, ProgressBar):
            callback.close()
    result = Result._from_report(report)
    _log.info("solved: %s%s", result.summary(),
              "".join(f"; warning: {w}" for w in result.warnings))
    return result
