"""Levenberg-Marquardt for small nonlinear least-squares problems with analytic Jacobians.

Minimises 0.5 |r(x)|^2 for a residual function that returns r and its Jacobian J together
(the fits' forward model computes both in one pass). Marquardt's scaling by diag(J^T J),
Nielsen's update of the damping (H. B. Nielsen, IMM-REP-1999-05) and a cap on each step's
largest component (the coordinates are logarithms of positive parameters: a cap of 2 is
a factor e^2 at most per step). The problems have a few parameters and expensive residuals,
so the linear algebra is dense numpy and every evaluation counts.
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Residuals = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


#: Why Levenberg-Marquardt stopped, as scipy.optimize.least_squares numbers it: 0 the
#: iteration limit, 1 the gradient test (gtol), 2 the cost test (ftol; also when no step
#: lowers the cost: a minimum to round-off), 3 the step test (xtol).
MAX_ITER, GTOL, FTOL, XTOL = 0, 1, 2, 3


@dataclass
class Solution:
    """Where Levenberg-Marquardt stopped: ``status`` (:data:`MAX_ITER`, :data:`GTOL`,
    :data:`FTOL` or :data:`XTOL`) and ``message`` say why; ``converged`` unless the
    iteration limit stopped it."""

    x: np.ndarray
    residuals: np.ndarray
    jacobian: np.ndarray
    evaluations: int
    iterations: int
    status: int
    message: str

    @property
    def converged(self) -> bool:
        """Whether a tolerance (not the iteration limit) stopped it."""
        return self.status != MAX_ITER


def levenberg_marquardt(fun: Residuals, x0: np.ndarray, *, max_iter: int = 100, xtol: float = 1e-10,
                        ftol: float = 1e-14, gtol: float = 1e-12, max_step: float = 2.0) -> Solution:
    """Minimise 0.5 |r(x)|^2 from ``x0``; ``fun(x)`` returns ``(r, J)``.

    Stops when a step changes no coordinate by more than ``xtol`` (absolute: the coordinates
    are logarithms), when an accepted step lowers the cost, or the linear model predicts it
    to lower the cost, by less than ``ftol`` of it, or when the scaled gradient is below
    ``gtol``; after ``max_iter`` iterations it stops with
    ``converged`` false (``status`` :data:`MAX_ITER`).
    """
    x = np.asarray(x0, dtype=float).copy()
    r, jac = fun(x)
    evaluations = 1
    cost = 0.5 * float(r @ r)
    damping, grow = None, 2.0
    for iteration in range(1, max_iter + 1):
        a = jac.T @ jac
        g = jac.T @ r
        scale = np.maximum(np.diag(a), 1e-30 * max(float(np.max(np.diag(a), initial=0.0)), 1e-300))
        if float(np.max(np.abs(g) / np.sqrt(scale), initial=0.0)) <= gtol * max(np.sqrt(2 * cost), 1e-300):
            return Solution(x, r, jac, evaluations, iteration - 1, GTOL, "gradient below tolerance")
        if damping is None:
            damping = 1e-3
        while True:
            try:
                step = np.linalg.solve(a + damping * np.diag(scale), -g)
            except np.linalg.LinAlgError:
                damping *= grow
                grow *= 2.0
                continue
            biggest = float(np.max(np.abs(step), initial=0.0))
            if biggest > max_step:
                step *= max_step / biggest
            if biggest <= xtol:
                return Solution(x, r, jac, evaluations, iteration, XTOL, "step below tolerance")
            predicted = -(g @ step) - 0.5 * step @ a @ step
            if predicted <= ftol * cost:
                return Solution(x, r, jac, evaluations, iteration, FTOL,
                                "predicted cost reduction below tolerance")
            r_new, jac_new = fun(x + step)
            evaluations += 1
            cost_new = 0.5 * float(r_new @ r_new) if np.all(np.isfinite(r_new)) else np.inf
            ratio = (cost - cost_new) / predicted if predicted > 0 else -1.0
            if ratio > 1e-4:
                x = x + step
                reduction = cost - cost_new
                r, jac, cost = r_new, jac_new, cost_new
                damping *= max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
                grow = 2.0
                if reduction <= ftol * cost_new:
                    return Solution(x, r, jac, evaluations, iteration, FTOL, "cost reduction below tolerance")
                break
            damping *= grow
            grow *= 2.0
            if damping > 1e16:
                return Solution(x, r, jac, evaluations, iteration, FTOL,
                                "no step lowers the cost (a minimum to round-off)")
    return Solution(x, r, jac, evaluations, max_iter, MAX_ITER, f"stopped after {max_iter} iterations")
