"""Initial guesses of a fit given a medium class: candidates of unit modulus scale with
relaxation times spread over the data's span, each scaled by the linear least-squares factor
that best matches the forces (forces scale with the moduli at given depths), the best one
kept.
"""

import json
import math

import numpy as np

from ._fit_model import medium_of, moduli, parameters
from .errors import DataError, InvalidInputError
from .media import Elastic, KelvinVoigt, Maxwell, PowerLaw, Prony, StandardSolid, Viscous, _Medium


def guesses(cls: type, span: float, step: float, terms: int, nu: float) -> list[_Medium]:
    """Candidate media of unit modulus scale and Poisson ratio ``nu`` for a fit of class ``cls``
    to data over ``span`` (s) sampled every ``step`` (s) or more: relaxation times log-spaced
    between the two."""
    taus = np.geomspace(max(3.0 * step, 1e-3 * span), 3.0 * span, 9)
    if cls is Elastic:
        return [Elastic(1.0, nu=nu)]
    if cls is Viscous:
        return [Viscous(tau, nu=nu) for tau in taus]
    if cls in (KelvinVoigt, Maxwell):
        return [cls(1.0, tau, nu=nu) for tau in taus]
    if cls is StandardSolid:
        return [StandardSolid(0.5, 0.5, tau, nu=nu) for tau in taus]
    if cls is Prony:
        return [Prony(0.5, tuple((0.5 / terms, tau * 10.0 ** -j) for j in range(terms)), nu=nu)
                for tau in taus]
    if cls is PowerLaw:
        return [PowerLaw(1.0, beta, 1.0, nu=nu) for beta in (0.05, 0.1, 0.2, 0.35, 0.5, 0.7)]
    raise InvalidInputError(f"fit: model must be an mdrvisc medium or medium class, got {cls!r}")


def scaled(medium: _Medium, by: float) -> _Medium:
    """The medium with every modulus and viscosity multiplied by ``by`` (times and nu kept)."""
    values = parameters(medium)
    values.update({name: values[name] * by for name in moduli(values)})
    return medium_of(type(medium), values, medium.nu)


def estimate(curve, cls: type, force: np.ndarray, w: np.ndarray, span: float, step: float, terms: int,
             nu: float) -> _Medium:
    """The initial guess of class ``cls`` and Poisson ratio ``nu`` from the depth-controlled
    forward model ``curve`` and the forces ``force`` (N) it should give, weighted by ``w``:
    among candidates of unit modulus scale with relaxation times over the data's span (s,
    sampled every ``step`` s or more), the one whose best modulus scale (a linear least-squares
    factor: forces scale with the moduli at given depths) matches the forces best, so scaled."""
    candidates = guesses(cls, span, step, terms, nu)
    evaluated = curve.evaluate([json.dumps(m._model()) for m in candidates], [])
    best, best_cost = None, math.inf
    for medium, (values, _, _, _) in zip(candidates, evaluated):
        norm = float(np.sum(w * values * values))
        if not norm > 0:
            continue
        factor = float(np.sum(w * values * force)) / norm
        cost = float(np.sum(w * (factor * values - force) ** 2))
        if factor > 0 and cost < best_cost:
            best, best_cost = scaled(medium, factor), cost
    if best is None:
        raise DataError("fit: no initial guess matches the data: the forces do not grow with the depths")
    return best
