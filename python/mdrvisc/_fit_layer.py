"""A layer's thickness fitted with the medium (``mv.fit(..., body=mv.Layer(h0),
fit_thickness=True)``).

The forward model on a layer is built once per thickness (the layer's flat-punch stiffness
stretches the profile), so the thickness is not one more Levenberg-Marquardt coordinate:
the fit minimises the profile cost C(h) = min over the medium of the fit's cost on
``Layer(h)``, over u = log h, by a bracket from h0 and golden-section search; each C(h) is
one ordinary fit (warm-started from the nearest one). The standard errors and correlations
come from the joint Jacobian at the solution: the inner fit's columns and the thickness's,
d(model)/dh by a central difference of the forward model in log h.

What the data identify: for a sphere of radius R on a thick layer (a/h small), F ≈ G
(d^{3/2} + c1 sqrt(R) d^2 / h) up to constants, so the modulus and the thickness separate
only through the d^2 term, whose weight grows with a/h. A curve whose largest contact
radius is below :data:`SMALL_CONTACT` thicknesses is reported with an
:class:`~mdrvisc.errors.IdentifiabilityWarning`, as is a thickness whose relative standard
error exceeds 0.5 or whose correlation with a modulus exceeds 0.999 (the fit's usual
criteria: the correlation is high by nature, 0.998 for ten samples to a/h = 0.76 at 1 %
noise with h known to 5 %, so it is no criterion alone); a curve of a half-space (a thickness far
beyond the contact) runs the search to :data:`THICKEST` contact radii, where the layer is
the half-space to 1e-6, and its thickness comes out undetermined.
"""

import dataclasses
import math
import warnings
from collections.abc import Callable

import numpy as np

from ._fit_checks import covariance, identifiability
from .body import Layer
from .errors import DataError, IdentifiabilityWarning
from .media import _young

#: The thickest layer searched, in half-space contact radii at the deepest sample: there the
#: layer's force is the half-space's to about 1e-6 (docs/layers.md, *Verification*).
THICKEST = 1000.0

#: The thinnest layer searched, in those radii: MDR on a layer reaches 8 thicknesses (a
#: layer's contact is wider than the half-space's, so thinner ones may already be refused).
THINNEST = 1.0 / 8.0

#: First bracketing step of the search, in log h (a factor 2); it doubles while the cost falls.
FIRST_STEP = math.log(2.0)

#: The golden-section search stops when the bracket is this narrow in log h (0.1 % of h),
#: well inside the thickness's standard error at any noise the data can tell it through.
TOLERANCE = 1e-3

#: Step of the central difference d(model)/d(log h) at the solution.
DIFFERENCE_STEP = 1e-2

#: Below this largest contact radius, in thicknesses, the curve barely feels the base.
SMALL_CONTACT = 0.3

_GOLDEN = (math.sqrt(5.0) - 1.0) / 2.0


def fit_thickness(inner: Callable, values: Callable, layer: Layer, radius: float, root_w: np.ndarray, first):
    """The fit of :func:`mdrvisc.fit` with the thickness of ``layer`` (its initial guess)
    fitted: ``inner(layer, start)`` is the ordinary fit on a layer (``start`` the medium to
    start from, None for the caller's model), ``values(layer, medium)`` the forward model's
    values of a medium on a layer, ``radius`` the half-space contact radius (m) at the
    deepest sample, ``root_w`` the square roots of the samples' weights, ``first`` the
    fit at the initial thickness. Returns the inner fit at the fitted thickness with the
    joint standard errors, correlations, Jacobian and warnings, and ``body`` the fitted layer."""
    base = layer.base
    usable = int(np.count_nonzero(root_w > 0))
    dof = usable - len(first.free) - 1
    if dof < 1:
        raise DataError(f"fit: {usable} samples with positive weight for {len(first.free) + 1} free "
                        f"parameters ({first.free + ['thickness']}); a fit needs more samples than "
                        "parameters")
    u0 = math.log(layer.thickness)
    fits: dict[float, object] = {u0: first}

    def cost(u: float) -> float:
        if u not in fits:
            start = fits[min(fits, key=lambda v: abs(v - u))].medium
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", IdentifiabilityWarning)
                    fits[u] = inner(Layer(math.exp(u), base), start)
            except DataError:
                return math.inf  # a layer so thin that the contact goes beyond MDR's reach
        return fits[u].cost if fits[u].success else math.inf

    lo, hi = math.log(THINNEST * radius), max(math.log(THICKEST * radius), u0)
    lo = min(lo, u0)
    a, b, c = _bracket(cost, u0, lo, hi)
    u = _golden(cost, a, b, c)
    best = fits[u]
    h = math.exp(u)
    up, down = (values(Layer(h * math.exp(s * DIFFERENCE_STEP), base), best.medium) for s in (1, -1))
    column = root_w * (up - down) / (2.0 * DIFFERENCE_STEP * h)
    jac = np.column_stack([best.jac.reshape(column.size, -1), column])
    free = best.free + ["thickness"]  # a Prony's terms renamed in the order of their times
    variance = float(np.sum((root_w * best.residuals) ** 2)) / dof
    err, correlation, undetermined = covariance(jac, variance)
    stderr = dict(best.stderr)
    stderr.update({name: float(e) for name, e in zip(free, err)})
    scales = [best.parameters.get(name, np.nan) for name in best.free]
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = err / np.abs(np.asarray(scales + [h]))
    messages = identifiability(free, relative, correlation, undetermined)
    messages += _thickness_messages(radius / h, u >= hi - TOLERANCE)
    return dataclasses.replace(
        best, stderr=stderr, young_stderr=_young(stderr, best.nu), free=free, correlation=correlation,
        jac=jac, nfev=sum(f.nfev for f in fits.values()) + 2, nit=sum(f.nit for f in fits.values()),
        warnings=messages, body=Layer(h, base))


def _bracket(cost: Callable, u0: float, lo: float, hi: float) -> tuple[float, float, float]:
    """(a, b, c) with a <= b <= c within [lo, hi] and cost(b) <= cost(a), cost(c): a bracket
    of the profile cost's minimum from u0, by steps that double while the cost falls; a = b or
    b = c where the minimum is at a bound."""
    f0 = cost(u0)
    step = FIRST_STEP
    up = min(u0 + step, hi)
    if up > u0 and cost(up) < f0:
        direction, (a, b) = 1.0, (u0, up)
    else:
        down = max(u0 - step, lo)
        if down < u0 and cost(down) < f0:
            direction, (a, b) = -1.0, (u0, down)
        else:
            return down, u0, up
    bound = hi if direction > 0 else lo
    while True:
        step *= 2.0
        c = b + direction * step
        c = min(c, hi) if direction > 0 else max(c, lo)
        if cost(c) >= cost(b):
            return (a, b, c) if direction > 0 else (c, b, a)
        a, b = b, c
        if b == bound:
            return (a, b, b) if direction > 0 else (b, b, a)


def _golden(cost: Callable, a: float, b: float, c: float) -> float:
    """The point of least cost found by golden-section search in the bracket (a, b, c) until
    it is :data:`TOLERANCE` wide (b, the bracket's middle, is one of the evaluated points)."""
    if b == c or b == a:  # the minimum at a bound of the search
        return b
    while c - a > TOLERANCE:
        # probe the wider side of b
        x = b + (1.0 - _GOLDEN) * (c - b) if c - b > b - a else b - (1.0 - _GOLDEN) * (b - a)
        if cost(x) < cost(b):
            a, c = (b, c) if x > b else (a, b)
            b = x
        else:
            a, c = (a, x) if x > b else (x, c)
    return b


def _thickness_messages(reach: float, at_thickest: bool) -> list[str]:
    """Warnings of what the curve tells of the thickness: a contact that stays below
    :data:`SMALL_CONTACT` thicknesses (``reach``: the largest half-space contact radius over
    the fitted thickness), a search that ran to :data:`THICKEST` radii."""
    if at_thickest:
        return [f"fit: thickness is not determined by the data: the curve is a half-space's to within its "
                f"residuals (the search ran to {THICKEST:g} contact radii)"]
    if reach < SMALL_CONTACT:
        return [f"fit: thickness is weakly determined: the largest contact radius is {reach:.3g} thicknesses "
                f"(below {SMALL_CONTACT}), where the modulus and the thickness separate only through the "
                "force's d^2 term"]
    return []
