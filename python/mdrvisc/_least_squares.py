"""Levenberg-Marquardt for small nonlinear least-squares problems with analytic Jacobians.

Minimises 0.5 |r(x)|^2 for a residual function that returns r and its Jacobian J together
(the fits' forward model computes both in one pass). The problems have a few parameters and
expensive residuals, so the linear algebra is dense numpy and every evaluation counts.

Scale-free: every iteration divides the Jacobian's columns by their norms (Marquardt's
scaling, so no coordinate's unit matters: logarithms of moduli and a contact point in units
of the data's depth alike) and takes the singular value decomposition of the scaled
Jacobian, J D^-1 = U S V^T, from which each damped step follows in closed form,
D dx = -V S / (S^2 + lambda) U^T r, with Nielsen's update of the damping lambda
(H. B. Nielsen, IMM-REP-1999-05) and a cap on each step's largest component (in the
caller's coordinates: a cap of 2 on a logarithm is a factor e^2 at most per step).

Stopping, on criteria a heavily damped step cannot fake (neither the step's length nor the
cost's decrease is one: a damped step makes both small far from the minimum):

* stationarity, the relative offset of Bates and Watts (Technometrics 23, 179-183, 1981):
  rho = (|U^T r| / sqrt(p)) / (|r| / sqrt(m - p)) <= ``offset_tol`` (m residuals, p
  coordinates). |U^T r| is the length of the residual's projection on the Jacobian's range,
  i.e. of the undamped Gauss-Newton step measured through J, so the linearised minimum lies
  within rho sqrt(p) standard errors of the point (in the covariance's metric) and the cost
  exceeds its minimum by rho^2 p / (m - p) of itself. It uses neither the damping nor the
  coordinates' units.
* residuals at round-off: |r| <= ``residual_floor`` (noise-free data that the model
  reproduces exactly, where rho measures round-off).
* a minimum to round-off: the Gauss-Newton step would lower the cost by less than the
  cost's own round-off (rho^2 p / (m - p) <= :data:`ROUND_OFF`), so no step's gain could
  be told from round-off. With many residuals this comes before ``offset_tol``: at m =
  8,000 and p = 4, at rho <= 1.4e-5 (the point within 3e-5 standard errors of the
  linearised minimum); trying steps there would only be refused, one evaluation each.
* a minimum at a kink: no step lowers the cost, and the linearised minimum lies within
  ``kink_tol`` standard errors (rho sqrt(p) <= ``kink_tol``). The fits' discrete forward
  models are piecewise smooth (an element enters the contact, the root of Ting's retract
  crosses a step), so their cost has kinks, where the one-sided Jacobians disagree and the
  relative offset stays above round-off; at one, every direction raises the cost.

Otherwise it stops unconverged: after ``max_iter`` iterations, or when no step lowers the
cost at a point farther from the linearised minimum (a Jacobian that is not the residuals'
derivative, or a large kink).
"""

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

Residuals = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]


#: Why Levenberg-Marquardt stopped, numbered as scipy.optimize.least_squares numbers its
#: successes (> 0) and failures (<= 0): 1 the stationarity (relative offset) test, 2 a
#: minimum to round-off (residuals at round-off, or a cost that the Gauss-Newton step
#: would lower by less than its round-off), 3 a minimum at a kink; 0 the
#: iteration limit, -2 no step lowers the cost at a point that is not stationary (or the
#: start is outside the residuals' domain).
MAX_ITER, STATIONARY, ROUND_OFF_MINIMUM, KINK, STALLED = 0, 1, 2, 3, -2

#: Relative cost decrease below which a cost evaluated in double precision cannot tell a
#: point from the minimum (sums of many squares round at about 1e-16 times their number's
#: square root).
ROUND_OFF = 1e-13

#: Singular values of the column-scaled Jacobian below this fraction of the largest are
#: round-off (the directions they span are left alone by the steps).
SINGULAR_FLOOR = 1e-13


@dataclass
class Solution:
    """Where Levenberg-Marquardt stopped: ``status`` (:data:`STATIONARY`,
    :data:`ROUND_OFF_MINIMUM`, :data:`KINK`, :data:`MAX_ITER` or :data:`STALLED`) and
    ``message`` say why; ``offset`` is the relative offset rho there (see the module's notes)."""

    x: np.ndarray
    residuals: np.ndarray
    jacobian: np.ndarray
    evaluations: int
    iterations: int
    status: int
    message: str
    offset: float

    @property
    def converged(self) -> bool:
        """Whether it stopped at a minimum (``status`` > 0)."""
        return self.status > 0


def _decomposed(jac: np.ndarray):
    """(column norms, U, S, V) of the Jacobian with its columns scaled to unit norm (a zero
    column stays zero); singular values below :data:`SINGULAR_FLOOR` of the largest
    dropped."""
    norms = np.linalg.norm(jac, axis=0)
    safe = np.where(norms > 0, norms, 1.0)
    u, s, vt = np.linalg.svd(jac / safe, full_matrices=False)
    keep = s > SINGULAR_FLOOR * (s[0] if s.size else 0.0)
    return safe, u[:, keep], s[keep], vt[keep].T


def relative_offset(r: np.ndarray, u: np.ndarray, samples: int) -> float:
    """Bates and Watts' relative offset of residuals ``r`` whose Jacobian's range has the
    orthonormal basis ``u`` (columns), over ``samples`` residuals; inf without degrees of
    freedom, 0 at zero residuals."""
    p = u.shape[1]
    norm = float(np.linalg.norm(r))
    if norm == 0.0:
        return 0.0
    if samples <= p or p == 0:
        return 0.0 if p == 0 else np.inf
    return float(np.linalg.norm(u.T @ r)) / np.sqrt(p) / (norm / np.sqrt(samples - p))


def _gain(offset: float, p: int, samples: int) -> float:
    """The relative decrease of the cost that the Gauss-Newton step would bring, rho^2 p /
    (m - p), at relative offset ``offset`` with ``p`` coordinates and ``samples`` residuals."""
    return offset**2 * p / max(samples - p, 1)


def levenberg_marquardt(fun: Residuals, x0: np.ndarray, *, max_iter: int = 100, offset_tol: float = 1e-6,
                        kink_tol: float = 0.05, residual_floor: float = 0.0,
                        max_step: float = 2.0) -> Solution:
    """Minimise 0.5 |r(x)|^2 from ``x0``; ``fun(x)`` returns ``(r, J)`` (non-finite
    residuals: outside the domain, a step there is refused).

    Stops converged when the relative offset is at most ``offset_tol``, when
    |r| <= ``residual_floor``, when the Gauss-Newton step would lower the cost by less than
    its round-off, or when no step lowers a cost that is at a kink within ``kink_tol``
    standard errors of its linearised minimum;
    unconverged after ``max_iter`` iterations or when no step lowers the cost
    elsewhere (the module's notes). Rows of r and J that are zero together (samples of
    weight zero) do not count as residuals.
    """
    x = np.asarray(x0, dtype=float).copy()
    r, jac = fun(x)
    evaluations = 1

    def finish(iterations: int, status: int, message: str, offset: float) -> Solution:
        return Solution(x, r, jac, evaluations, iterations, status, message, offset)

    if not (np.all(np.isfinite(r)) and np.all(np.isfinite(jac))):
        return finish(0, STALLED, "the initial point is outside the model's domain", np.inf)
    samples = int(np.count_nonzero((r != 0) | np.any(jac != 0, axis=1)))
    cost = 0.5 * float(r @ r)
    damping, grow = None, 2.0
    for iteration in range(1, max_iter + 1):
        norms, u, s, v = _decomposed(jac)
        ur = u.T @ r
        offset = relative_offset(r, u, samples)
        if np.sqrt(2.0 * cost) <= residual_floor:
            return finish(iteration - 1, ROUND_OFF_MINIMUM, "residuals at round-off", offset)
        if offset <= offset_tol:
            return finish(iteration - 1, STATIONARY,
                          f"stationary: relative offset {offset:.1e} <= {offset_tol:.0e}", offset)
        if _gain(offset, s.size, samples) <= ROUND_OFF:
            return finish(iteration - 1, ROUND_OFF_MINIMUM,
                          f"a minimum to round-off: the Gauss-Newton step would lower the cost by less than "
                          f"its round-off (relative offset {offset:.1e})", offset)
        if damping is None:
            damping = 1e-3 * float(s[0]) ** 2
        while True:
            step = -(v @ (s / (s * s + damping) * ur)) / norms
            biggest = float(np.max(np.abs(step), initial=0.0))
            if biggest > max_step:
                step *= max_step / biggest
            # the linear model's decrease, 0.5 |r|^2 - 0.5 |r + J step|^2
            js = jac @ step
            predicted = -float(r @ js) - 0.5 * float(js @ js)
            r_new, jac_new = fun(x + step)
            evaluations += 1
            finite = np.all(np.isfinite(r_new)) and np.all(np.isfinite(jac_new))
            cost_new = 0.5 * float(r_new @ r_new) if finite else np.inf
            ratio = (cost - cost_new) / predicted if predicted > 0 else -1.0
            if ratio > 1e-4:
                x = x + step
                r, jac, cost = r_new, jac_new, cost_new
                damping *= max(1.0 / 3.0, 1.0 - (2.0 * ratio - 1.0) ** 3)
                grow = 2.0
                break
            damping *= grow
            grow *= 2.0
            if damping > 1e16 * float(s[0]) ** 2:
                p = s.size
                if offset * np.sqrt(p) <= kink_tol:
                    return finish(iteration, KINK,
                                  "a minimum at a kink of the model: no step lowers the cost, the linearised "
                                  f"minimum {offset * np.sqrt(p):.1e} standard errors away", offset)
                return finish(iteration, STALLED,
                              f"no step lowers the cost, but the point is not stationary (relative offset "
                              f"{offset:.1e} > {offset_tol:.0e})", offset)
    norms, u, s, v = _decomposed(jac)
    offset = relative_offset(r, u, samples)
    if offset <= offset_tol:
        return finish(max_iter, STATIONARY, f"stationary: relative offset {offset:.1e} <= {offset_tol:.0e}",
                      offset)
    if _gain(offset, s.size, samples) <= ROUND_OFF:
        return finish(max_iter, ROUND_OFF_MINIMUM, f"a minimum to round-off (relative offset {offset:.1e})",
                      offset)
    return finish(max_iter, MAX_ITER, f"stopped after {max_iter} iterations (relative offset {offset:.1e})",
                  offset)
