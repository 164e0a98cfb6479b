"""Half-space media. All are incompressible (Poisson ratio 1/2, E* = 4 G).

Each medium has a shear relaxation modulus G(t) and creep compliance J(t); the
viscoelastic ones are written as G(t) = G_inf + sum_k G_k exp(-t / tau_k) + eta delta(t)
(:meth:`rheology`), which is what the solvers step. The power law has no finite series:
the solvers step one fitted to it over each run's time range (see :class:`PowerLaw`).
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._core import MAGNITUDE
from ._validate import _array, _number, _positive
from .errors import InvalidInputError

__all__ = ["Viscous", "Elastic", "KelvinVoigt", "Maxwell", "StandardSolid", "Prony", "PowerLaw"]

#: A medium as a Prony series with a dashpot, (G_inf, [(G_k, tau_k), ...], eta) (Pa, s, Pa s).
Rheology = tuple[float, list[tuple[float, float]], float]


def _times(t):
    """Times (s) as a float64 array, finite and >= 0; InvalidInputError otherwise."""
    if isinstance(t, (str, bytes)):
        raise InvalidInputError(f"times must be real numbers, got {t!r:.80}")
    t = _array("medium", "times", t, minimum=0.0)
    if np.any(t > MAGNITUDE):
        raise InvalidInputError(
            f"times must be <= {MAGNITUDE:g} s (the range of physical inputs), got {t.max()!r}")
    return t


class _Medium:
    """Shared interface: relaxation modulus G(t) (Pa) and creep compliance J(t) (1/Pa)."""

    def rheology(self) -> Rheology:
        """(G_inf, [(G_k, tau_k), ...], eta): the medium as a Prony series with a dashpot."""
        raise NotImplementedError

    def _model(self) -> dict:
        """The medium in the scene model's form (a scene file's ``[medium]`` table)."""
        values = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        if "terms" in values:
            values["terms"] = [list(term) for term in values["terms"]]
        return {"type": type(self).__name__.lower(), **values}

    def relaxation_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """G(t) (Pa) for t > 0 (the dashpot's delta at t = 0 left out)."""
        g_inf, terms, _ = self.rheology()
        t = _times(t)
        return g_inf + sum(g * np.exp(-t / tau) for g, tau in terms)

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) (1/Pa): strain under a unit step of stress, by exact-exponential stepping of
        the hereditary law on a fine geometric time grid (closed forms in the subclasses)."""
        g_inf, terms, eta = self.rheology()
        t = _times(t)
        end = max(float(np.max(t, initial=0.0)), 1e-300)
        taus = [tau for _, tau in terms] or [end]
        grid = np.unique(np.concatenate([[0.0], np.geomspace(min(taus) * 1e-6, end, 20000), t.ravel()]))
        x, q, out = 0.0, np.zeros(len(terms)), np.empty(grid.size)
        out[0] = 0.0 if eta > 0 else 1.0 / (g_inf + sum(g for g, _ in terms))
        x = out[0]
        q = np.array([g * x for g, _ in terms])
        for i in range(1, grid.size):
            dt = grid[i] - grid[i - 1]
            e = np.array([np.exp(-dt / tau) for _, tau in terms])
            # (tau/dt)(1 - exp(-dt/tau)), by its series where dt/tau underflows the quotient
            a = np.array([g * (1 - 0.5 * dt / tau if dt / tau < 1e-8 else (tau / dt) * -np.expm1(-dt / tau))
                          for g, tau in terms])
            g_eff = g_inf + a.sum() + eta / dt
            x_new = (1.0 - (e @ q - (a.sum() + eta / dt) * x)) / g_eff
            q = e * q + a * (x_new - x)
            x = out[i] = x_new
        return np.interp(t, grid, out)


@dataclass(frozen=True)
class Viscous(_Medium):
    """Newtonian viscous half-space of shear viscosity ``eta`` (Pa s).

    Radok's correspondence: every elastic result for a fixed contact holds for deflection
    *rates* with G replaced by eta.
    """

    eta: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "eta", _positive("Viscous", "eta", self.eta))

    def rheology(self) -> Rheology:
        return 0.0, [], self.eta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = t / eta (1/Pa)."""
        return _times(t) / self.eta


@dataclass(frozen=True)
class Elastic(_Medium):
    """Linear elastic half-space of shear modulus ``G`` (Pa); a scene with it and no duration
    is one static contact solve."""

    G: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Elastic", "G", self.G))

    def rheology(self) -> Rheology:
        return self.G, [], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = 1 / G (1/Pa)."""
        return np.full(np.shape(_times(t)), 1.0 / self.G)


@dataclass(frozen=True)
class KelvinVoigt(_Medium):
    """Spring ``G`` (Pa) parallel to a dashpot ``eta`` (Pa s)."""

    G: float
    eta: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("KelvinVoigt", "G", self.G))
        object.__setattr__(self, "eta", _positive("KelvinVoigt", "eta", self.eta))

    def rheology(self) -> Rheology:
        return self.G, [], self.eta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = (1 - exp(-G t / eta)) / G (1/Pa)."""
        return -np.expm1(-self.G * _times(t) / self.eta) / self.G


@dataclass(frozen=True)
class Maxwell(_Medium):
    """Spring ``G`` (Pa) in series with a dashpot ``eta`` (Pa s); tau = eta / G."""

    G: float
    eta: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Maxwell", "G", self.G))
        object.__setattr__(self, "eta", _positive("Maxwell", "eta", self.eta))

    def rheology(self) -> Rheology:
        return 0.0, [(self.G, self.eta / self.G)], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = 1 / G + t / eta (1/Pa)."""
        return 1.0 / self.G + _times(t) / self.eta


@dataclass(frozen=True)
class StandardSolid(_Medium):
    """Standard linear solid: G(t) = G_inf + G1 exp(-t / tau1) (Pa, s)."""

    G_inf: float
    G1: float
    tau1: float

    def __post_init__(self) -> None:
        for name in ("G_inf", "G1", "tau1"):
            object.__setattr__(self, name, _positive("StandardSolid", name, getattr(self, name)))

    def rheology(self) -> Rheology:
        return self.G_inf, [(self.G1, self.tau1)], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = 1/G_inf + (1/G0 - 1/G_inf) exp(-G_inf t / (G0 tau1)), G0 = G_inf + G1."""
        g0 = self.G_inf + self.G1
        decay = np.exp(-self.G_inf * _times(t) / (g0 * self.tau1))
        return 1.0 / self.G_inf + (1.0 / g0 - 1.0 / self.G_inf) * decay


@dataclass(frozen=True)
class Prony(_Medium):
    """Generalised Maxwell body: G(t) = G_inf + sum_k G_k exp(-t / tau_k) (Pa, s)."""

    G_inf: float
    terms: tuple

    def __post_init__(self) -> None:
        g_inf = _number("Prony", "G_inf", self.G_inf)
        if g_inf < 0:
            raise InvalidInputError(f"Prony: G_inf must be finite and >= 0, got {self.G_inf!r}")
        try:
            terms = tuple((_positive("Prony", "G_k", g), _positive("Prony", "tau_k", tau))
                          for g, tau in self.terms)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, InvalidInputError):
                raise
            raise InvalidInputError(f"Prony: terms must be pairs (G_k, tau_k), got {self.terms!r}") from exc
        if g_inf == 0 and not terms:
            raise InvalidInputError("Prony: the medium has no stiffness (G_inf = 0 and no terms)")
        object.__setattr__(self, "G_inf", g_inf)
        object.__setattr__(self, "terms", terms)

    def rheology(self) -> Rheology:
        return self.G_inf, list(self.terms), 0.0


@dataclass(frozen=True)
class PowerLaw(_Medium):
    """Power-law rheology G(t) = G0 (t / t0)^-beta (Pa, s), 0 < beta < 1: the standard model
    of cell rheology (a continuous spectrum of relaxation times).

    ``t0`` is a reference time (default 1 s): only G0 t0^beta enters G(t), so a fit holds it.
    Both methods step the power law as a Prony series with a long-time modulus and a
    dashpot, built once per run over its time range (from its shortest step to its last
    output time) by the trapezoid rule of G(t)'s Laplace integral, 3.5 terms per decade:
    its G(t) there is within 1e-5 of the power law's, relative (measured: 4e-6).
    """

    G0: float
    beta: float
    t0: float = 1.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "G0", _positive("PowerLaw", "G0", self.G0))
        beta = _positive("PowerLaw", "beta", self.beta)
        if beta >= 1.0:
            raise InvalidInputError(f"PowerLaw: beta must lie in (0, 1), got {self.beta!r}")
        object.__setattr__(self, "beta", beta)
        object.__setattr__(self, "t0", _positive("PowerLaw", "t0", self.t0))

    def rheology(self) -> Rheology:
        """Refused: the power law has no finite Prony series; the solvers fit one over each
        run's time range."""
        raise InvalidInputError(
            "PowerLaw has no finite Prony series: the solvers step one fitted over each run's time "
            "range; use relaxation_modulus and creep_compliance for its closed forms")

    def relaxation_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """G(t) = G0 (t / t0)^-beta (Pa) for t > 0."""
        return self.G0 * (_times(t) / self.t0) ** -self.beta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """J(t) = (t / t0)^beta / (G0 Gamma(1 - beta) Gamma(1 + beta)) (1/Pa)."""
        scale = math.gamma(1.0 - self.beta) * math.gamma(1.0 + self.beta)
        return (_times(t) / self.t0) ** self.beta / (self.G0 * scale)


#: Media solved by the general viscoelastic stepping (not the exact viscous impulse step).
VISCOELASTIC = (KelvinVoigt, Maxwell, StandardSolid, Prony, PowerLaw)


def medium_from_model(model: dict) -> _Medium:
    """The medium of a scene model's ``[medium]`` table."""
    classes = {cls.__name__.lower(): cls for cls in (Elastic, Viscous) + VISCOELASTIC}
    return classes[model["type"]](**{k: v for k, v in model.items() if k != "type"})
