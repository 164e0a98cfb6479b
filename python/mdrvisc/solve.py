"""``solve(scene, method, n)``: run a scene by BEM or MDR and return a :class:`Result`.

Grid sizing, the choice of engine (static contact, the exact viscous impulse step, the
paper's explicit loop, viscoelastic stepping) and the report are the compiled scene model's;
this module passes the options through, with the GIL released while it runs.
"""

from __future__ import annotations

import logging
import operator
from collections.abc import Callable

from . import _core
from .errors import InvalidInputError
from .progress import ProgressBar
from .result import Result
from .scene import Scene

__all__ = ["solve", "DEFAULT_N"]

#: Resolutions used when ``n`` is not given: the paper's.
DEFAULT_N = {"bem": 257, "mdr": 66049}


_log = logging.getLogger("mdrvisc")


def solve(scene: Scene, method: str = "bem", n: int | None = None, tol: float = 1e-10,
          max_iter: int = 5000, progress: Callable[[str, int, int], object] | bool | None = None,
          integrator: str = "implicit", step: float = 0.01, area_change: float = 0.01,
          dt: float | None = None) -> Result:
    """Solves ``scene`` by ``method`` ("bem" or "mdr") at resolution ``n``.

    Parameters
    ----------
    scene : Scene
    method : {"bem", "mdr"}
    n : int, optional
        BEM: elements across the footprint (n x n grid, at most 4096); MDR: elements of the
        1D indenter. Default 257 (BEM) or 66049 (MDR), the paper's resolutions.
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
    """
    if not isinstance(scene, Scene):
        raise InvalidInputError(f"solve: scene must be a Scene, got {scene!r}")
    if method not in DEFAULT_N:
        raise InvalidInputError(f"solve: method must be 'bem' or 'mdr', got {method!r}")
    n = DEFAULT_N[method] if n is None else n
    if isinstance(n, bool):
        raise InvalidInputError(f"solve: n must be a positive integer, got {n!r}")
    try:
        n = operator.index(n)
    except TypeError:
        raise InvalidInputError(f"solve: n must be a positive integer, got {n!r}") from None
    if n < 1:
        raise InvalidInputError(f"solve: n must be a positive integer, got {n!r}")
    callback = ProgressBar() if progress is True else progress
    _log.info("solve: %s n=%d, %r", method.upper(), n, scene)
    try:
        report = _core.run_scene(scene._model, method, n, tol=float(tol), max_iter=int(max_iter),
                                 integrator=integrator, step=float(step),
                                 area_change=float(area_change),
                                 dt=None if dt is None else float(dt), progress=callback)
    finally:
        if isinstance(callback, ProgressBar):
            callback.close()
    result = Result._from_report(report)
    _log.info("solved: %s%s", result.summary(),
              "".join(f"; warning: {w}" for w in result.warnings))
    return result
