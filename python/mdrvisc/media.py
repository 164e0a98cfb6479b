"""Half-space media.

Each medium has a shear relaxation modulus G(t), a shear creep compliance J(t) and a
constant Poisson ratio ``nu`` (default 0.5, incompressible; -1 < nu <= 0.5). Its contact
modulus is E*(t) = 2 G(t) / (1 - nu) (4 G when incompressible) and its Young's modulus
E(t) = 2 (1 + nu) G(t) (``young_modulus(t)``; ``young_moduli`` for its parameters). The
viscoelastic media are written as G(t) = G_inf + sum_k G_k exp(-t / tau_k) + eta delta(t)
(:meth:`rheology`). The solvers work with E* = 4 G: they step the incompressible medium with
the same contact modulus, whose moduli and viscosities are the medium's times
1 / (2 (1 - nu)) (relaxation times kept). The power law has no finite series: the solvers
step one fitted to it over each run's time range (see :class:`PowerLaw`).

A constant Poisson ratio is what makes the elastic-viscoelastic correspondence with
E*(t) = 2 G(t) / (1 - nu) exact; a medium whose nu changes with time (a bulk modulus that
relaxes differently from the shear modulus) is not modelled.
"""

import dataclasses
import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from ._core import MAGNITUDE
from ._validate import _array, _number, _poisson_ratio, _positive
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


def _young(values: dict[str, float], nu: float) -> dict[str, float]:
    """Of parameters by name (G_inf, G1, tau1, ...), the shear moduli (and their errors) as
    Young's moduli E = 2 (1 + nu) G, named with G written E (E_inf, E1, ...)."""
    return {"E" + name[1:]: 2.0 * (1.0 + nu) * value for name, value in values.items()
            if name.startswith("G")}


class _Medium:
    """Shared interface: shear relaxation modulus G(t) (Pa), shear creep compliance J(t)
    (1/Pa), Poisson ratio ``nu`` and Young's modulus E(t) = 2 (1 + nu) G(t) (Pa)."""

    nu: float

    def _check_nu(self) -> None:
        """Validates the Poisson ratio (-1 < nu <= 0.5) and stores it as a float."""
        object.__setattr__(self, "nu", _poisson_ratio(type(self).__name__, self.nu))

    def rheology(self) -> Rheology:
        """(G_inf, [(G_k, tau_k), ...], eta): the shear relaxation modulus as a Prony series
        with a dashpot (Pa, s, Pa s)."""
        raise NotImplementedError

    def _parameters(self) -> dict[str, float]:
        """The parameters of G(t) by name (a Prony series: G_inf, G1, tau1, G2, ...); the
        Poisson ratio is not one of them."""
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "nu"}

    @property
    def young_moduli(self) -> dict[str, float]:
        """Young's moduli E = 2 (1 + nu) G of the medium's shear moduli (Pa), by their names
        with G written E: ``E`` (Elastic, KelvinVoigt, Maxwell), ``E_inf`` and ``E1``
        (StandardSolid), ``E_inf``, ``E1``, ``E2``, ... (Prony), ``E0`` (PowerLaw); none for
        a viscous medium."""
        return _young(self._parameters(), self.nu)

    def _model(self) -> dict:
        """The medium in the scene model's form (a scene file's ``[medium]`` table); ``nu`` only
        when it is not 0.5, so that scenes of incompressible media keep their text."""
        values = {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}
        if "terms" in values:
            values["terms"] = [list(term) for term in values["terms"]]
        if values["nu"] == 0.5:
            del values["nu"]
        return {"type": type(self).__name__.lower(), **values}

    def relaxation_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """Shear relaxation modulus G(t) (Pa) for t > 0 (the dashpot's delta at t = 0 left
        out)."""
        g_inf, terms, _ = self.rheology()
        t = _times(t)
        return g_inf + sum(g * np.exp(-t / tau) for g, tau in terms)

    def young_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """Young's relaxation modulus E(t) = 2 (1 + nu) G(t) (Pa) for t > 0 (constant nu)."""
        return 2.0 * (1.0 + self.nu) * self.relaxation_modulus(t)

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) (1/Pa): shear strain under a unit step of shear
        stress, by exact-exponential stepping of the hereditary law on a fine geometric time
        grid (closed forms in the subclasses)."""
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
    """Newtonian viscous half-space of shear viscosity ``eta`` (Pa s) and Poisson ratio ``nu``.

    Radok's correspondence: every elastic result for a fixed contact holds for deflection
    *rates* with G replaced by eta.
    """

    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "eta", _positive("Viscous", "eta", self.eta))
        self._check_nu()

    def rheology(self) -> Rheology:
        return 0.0, [], self.eta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = t / eta (1/Pa)."""
        return _times(t) / self.eta


@dataclass(frozen=True)
class Elastic(_Medium):
    """Linear elastic half-space of shear modulus ``G`` (Pa) and Poisson ratio ``nu``
    (Young's modulus E = 2 (1 + nu) G: ``young_moduli["E"]``); a scene with it and no
    duration is one static contact solve."""

    G: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Elastic", "G", self.G))
        self._check_nu()

    def rheology(self) -> Rheology:
        return self.G, [], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = 1 / G (1/Pa)."""
        return np.full(np.shape(_times(t)), 1.0 / self.G)


@dataclass(frozen=True)
class KelvinVoigt(_Medium):
    """Spring ``G`` (Pa) parallel to a dashpot ``eta`` (Pa s); Poisson ratio ``nu``."""

    G: float
    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("KelvinVoigt", "G", self.G))
        object.__setattr__(self, "eta", _positive("KelvinVoigt", "eta", self.eta))
        self._check_nu()

    def rheology(self) -> Rheology:
        return self.G, [], self.eta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = (1 - exp(-G t / eta)) / G (1/Pa)."""
        return -np.expm1(-self.G * _times(t) / self.eta) / self.G


@dataclass(frozen=True)
class Maxwell(_Medium):
    """Spring ``G`` (Pa) in series with a dashpot ``eta`` (Pa s), tau = eta / G; Poisson ratio
    ``nu``."""

    G: float
    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Maxwell", "G", self.G))
        object.__setattr__(self, "eta", _positive("Maxwell", "eta", self.eta))
        self._check_nu()

    def rheology(self) -> Rheology:
        return 0.0, [(self.G, self.eta / self.G)], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = 1 / G + t / eta (1/Pa)."""
        return 1.0 / self.G + _times(t) / self.eta


@dataclass(frozen=True)
class StandardSolid(_Medium):
    """Standard linear solid: G(t) = G_inf + G1 exp(-t / tau1) (Pa, s); Poisson ratio ``nu``
    (Young's moduli ``young_moduli["E_inf"]`` and ``["E1"]``)."""

    G_inf: float
    G1: float
    tau1: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        for name in ("G_inf", "G1", "tau1"):
            object.__setattr__(self, name, _positive("StandardSolid", name, getattr(self, name)))
        self._check_nu()

    def rheology(self) -> Rheology:
        return self.G_inf, [(self.G1, self.tau1)], 0.0

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = 1/G_inf + (1/G0 - 1/G_inf) exp(-G_inf t / (G0 tau1))
        (1/Pa), G0 = G_inf + G1."""
        g0 = self.G_inf + self.G1
        decay = np.exp(-self.G_inf * _times(t) / (g0 * self.tau1))
        return 1.0 / self.G_inf + (1.0 / g0 - 1.0 / self.G_inf) * decay


@dataclass(frozen=True)
class Prony(_Medium):
    """Generalised Maxwell body: G(t) = G_inf + sum_k G_k exp(-t / tau_k) (Pa, s); Poisson
    ratio ``nu``."""

    G_inf: float
    terms: tuple
    nu: float = 0.5

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
        self._check_nu()

    def _parameters(self) -> dict[str, float]:
        out = {"G_inf": self.G_inf}
        for k, (g, tau) in enumerate(self.terms, 1):
            out[f"G{k}"], out[f"tau{k}"] = g, tau
        return out

    def rheology(self) -> Rheology:
        return self.G_inf, list(self.terms), 0.0


@dataclass(frozen=True)
class PowerLaw(_Medium):
    """Power-law rheology G(t) = G0 (t / t0)^-beta (Pa, s), 0 < beta < 1: the standard model
    of cell rheology (a continuous spectrum of relaxation times); Poisson ratio ``nu``.

    ``t0`` is a reference time (default 1 s): only G0 t0^beta enters G(t), so a fit holds it.
    Both methods step the power law as a Prony series with a long-time modulus and a
    dashpot, built once per run over its time range (from its shortest step to its last
    output time) by the trapezoid rule of G(t)'s Laplace integral, 3.5 terms per decade:
    its G(t) there is within 1e-5 of the power law's, relative (measured: 4e-6).
    """

    G0: float
    beta: float
    t0: float = 1.0
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G0", _positive("PowerLaw", "G0", self.G0))
        beta = _positive("PowerLaw", "beta", self.beta)
        if beta >= 1.0:
            raise InvalidInputError(f"PowerLaw: beta must lie in (0, 1), got {self.beta!r}")
        object.__setattr__(self, "beta", beta)
        object.__setattr__(self, "t0", _positive("PowerLaw", "t0", self.t0))
        self._check_nu()

    def rheology(self) -> Rheology:
        """Refused: the power law has no finite Prony series; the solvers fit one over each
        run's time range."""
        raise InvalidInputError(
            "PowerLaw has no finite Prony series: the solvers step one fitted over each run's time "
            "range; use relaxation_modulus and creep_compliance for its closed forms")

    def relaxation_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """Shear relaxation modulus G(t) = G0 (t / t0)^-beta (Pa) for t > 0."""
        return self.G0 * (_times(t) / self.t0) ** -self.beta

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) = (t / t0)^beta / (G0 Gamma(1 - beta) Gamma(1 + beta))
        (1/Pa)."""
        scale = math.gamma(1.0 - self.beta) * math.gamma(1.0 + self.beta)
        return (_times(t) / self.t0) ** self.beta / (self.G0 * scale)


#: Media solved by the general viscoelastic stepping (not the exact viscous impulse step).
VISCOELASTIC = (KelvinVoigt, Maxwell, StandardSolid, Prony, PowerLaw)


def medium_from_model(model: dict) -> _Medium:
    """The medium of a scene model's ``[medium]`` table."""
    classes = {cls.__name__.lower(): cls for cls in (Elastic, Viscous) + VISCOELASTIC}
    return classes[model["type"]](**{k: v for k, v in model.items() if k != "type"})
