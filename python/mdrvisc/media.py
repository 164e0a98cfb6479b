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

Each medium is computed by the compiled core's medium of the same parameters (built on
demand, so that media stay plain picklable data): its relaxation modulus, creep compliance,
series and parameter names are the solvers' own.
"""

import dataclasses
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._core import MAGNITUDE
from ._validate import _array, _number, _out, _poisson_ratio, _positive
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


def _message(error: InvalidInputError) -> str:
    """The compiled core's message of ``error`` without its "invalid input: " prefix."""
    return str(error).removeprefix("invalid input: ")


def _young(values: dict[str, float], nu: float) -> dict[str, float]:
    """Of parameters by name (G_inf, G1, tau1, ...), the shear moduli (and their errors) as
    Young's moduli E = 2 (1 + nu) G, named with G written E (E_inf, E1, ...)."""
    return {"E" + name[1:]: 2.0 * (1.0 + nu) * value for name, value in values.items()
            if name.startswith("G")}


class _Medium:
    """Shared interface: shear relaxation modulus G(t) (Pa), shear creep compliance J(t)
    (1/Pa), Poisson ratio ``nu`` and Young's modulus E(t) = 2 (1 + nu) G(t) (Pa), computed
    by the compiled core's medium."""

    nu: float

    def _check(self) -> None:
        """Validates the Poisson ratio (-1 < nu <= 0.5), stores it as a float, and has the
        compiled core check the whole medium (its errors named after this class)."""
        object.__setattr__(self, "nu", _poisson_ratio(type(self).__name__, self.nu))
        try:
            self._compiled()
        except InvalidInputError as exc:
            raise InvalidInputError(f"{type(self).__name__}: {_message(exc)}") from None

    def _values(self) -> list[float]:
        """The parameter values in the compiled core's order (the fields but nu)."""
        return [getattr(self, f.name) for f in dataclasses.fields(self) if f.name != "nu"]

    def _compiled(self) -> _core.Medium:
        """The compiled core's medium of these parameters."""
        return _core.Medium.from_values(type(self).__name__.lower(), self._values(), self.nu)

    @classmethod
    def _from_values(cls, values: list[float], nu: float):
        """The medium from its parameter values in the compiled core's order."""
        return cls(*values, nu=nu)

    @classmethod
    def _from_parameters(cls, values: dict[str, float], nu: float):
        """The medium of this class with the parameters ``values`` by the names of
        :meth:`_parameters` (a Prony series: G_inf, G1, tau1, ...) and Poisson ratio ``nu``;
        InvalidInputError, listing the names, for a missing or unknown one."""
        try:
            core = _core.Medium(cls.__name__.lower(), list(values.items()), nu)
        except InvalidInputError as exc:
            raise InvalidInputError(f"{cls.__name__}: {_message(exc)}") from None
        return cls._from_values([value for _, value in core.parameters()], nu)

    @classmethod
    def _parameter_names(cls, terms: int = 0) -> list[str]:
        """The names of the medium's parameters, in the compiled core's order (a Prony series
        of ``terms`` terms: G_inf, G1, tau1, G2, tau2, ...); the Poisson ratio is not one."""
        return _core.Medium.parameter_names(cls.__name__.lower(), terms)

    def rheology(self) -> Rheology:
        """(G_inf, [(G_k, tau_k), ...], eta): the shear relaxation modulus as a Prony series
        with a dashpot (Pa, s, Pa s)."""
        return self._compiled().rheology()

    def _parameters(self) -> dict[str, float]:
        """The parameters of G(t) by name (a Prony series: G_inf, G1, tau1, G2, ...); the
        Poisson ratio is not one of them."""
        return dict(self._compiled().parameters())

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
        return _out(self._compiled().relaxation_modulus(_times(t)))

    def young_modulus(self, t: ArrayLike) -> float | np.ndarray:
        """Young's relaxation modulus E(t) = 2 (1 + nu) G(t) (Pa) for t > 0 (constant nu)."""
        return 2.0 * (1.0 + self.nu) * self.relaxation_modulus(t)

    def creep_compliance(self, t: ArrayLike) -> float | np.ndarray:
        """Shear creep compliance J(t) (1/Pa): shear strain under a unit step of shear
        stress. Closed forms (given in each medium's docstring); for a Prony series,
        exact-exponential stepping of the hereditary law on a fine geometric time grid."""
        return _out(self._compiled().creep_compliance(_times(t)))


@dataclass(frozen=True)
class Viscous(_Medium):
    """Newtonian viscous half-space of shear viscosity ``eta`` (Pa s) and Poisson ratio ``nu``.

    Radok's correspondence: every elastic result for a fixed contact holds for deflection
    *rates* with G replaced by eta. Shear creep compliance J(t) = t / eta (1/Pa).

    Parameters
    ----------
    eta : float
        Shear viscosity (Pa s), > 0.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.

    Examples
    --------
    >>> mv.Viscous(eta=1.0).creep_compliance(2.0)     # 1/Pa  # doctest: +SKIP
    2.0
    """

    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "eta", _positive("Viscous", "eta", self.eta))
        self._check()


@dataclass(frozen=True)
class Elastic(_Medium):
    """Linear elastic half-space of shear modulus ``G`` (Pa) and Poisson ratio ``nu``
    (Young's modulus E = 2 (1 + nu) G: ``young_moduli["E"]``); a scene with it and no
    duration is one static contact solve. Shear creep compliance J(t) = 1 / G (1/Pa).

    Parameters
    ----------
    G : float
        Shear modulus (Pa), > 0; E = 3 G for an incompressible body.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.

    Examples
    --------
    >>> mv.Elastic(G=1e6, nu=0.3).young_moduli        # doctest: +SKIP
    {'E': 2600000.0}
    """

    G: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Elastic", "G", self.G))
        self._check()


@dataclass(frozen=True)
class KelvinVoigt(_Medium):
    """Kelvin–Voigt body: a spring ``G`` (Pa) parallel to a dashpot ``eta`` (Pa s); Poisson
    ratio ``nu``. Shear creep compliance J(t) = (1 - exp(-G t / eta)) / G (1/Pa).

    Parameters
    ----------
    G : float
        Shear modulus of the spring (Pa), > 0.
    eta : float
        Shear viscosity of the dashpot (Pa s), > 0; the retardation time is eta / G (s).
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.
    """

    G: float
    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("KelvinVoigt", "G", self.G))
        object.__setattr__(self, "eta", _positive("KelvinVoigt", "eta", self.eta))
        self._check()


@dataclass(frozen=True)
class Maxwell(_Medium):
    """Maxwell body: a spring ``G`` (Pa) in series with a dashpot ``eta`` (Pa s), relaxation
    time tau = eta / G; Poisson ratio ``nu``. Shear creep compliance J(t) = 1 / G + t / eta
    (1/Pa).

    Parameters
    ----------
    G : float
        Shear modulus of the spring (Pa), > 0: the instantaneous modulus.
    eta : float
        Shear viscosity of the dashpot (Pa s), > 0.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.
    """

    G: float
    eta: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G", _positive("Maxwell", "G", self.G))
        object.__setattr__(self, "eta", _positive("Maxwell", "eta", self.eta))
        self._check()


@dataclass(frozen=True)
class StandardSolid(_Medium):
    """Standard linear solid: G(t) = G_inf + G1 exp(-t / tau1) (Pa, s); Poisson ratio ``nu``
    (Young's moduli ``young_moduli["E_inf"]`` and ``["E1"]``). Shear creep compliance
    J(t) = 1/G_inf + (1/G0 - 1/G_inf) exp(-G_inf t / (G0 tau1)) (1/Pa), G0 = G_inf + G1.

    Parameters
    ----------
    G_inf : float
        Relaxed (long-time, rubbery) shear modulus (Pa), > 0.
    G1 : float
        Shear modulus of the relaxing Maxwell arm (Pa), > 0; the instantaneous (glassy)
        modulus is G_inf + G1.
    tau1 : float
        Relaxation time of that arm (s), > 0; the creep time is tau1 (G_inf + G1) / G_inf.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.

    Examples
    --------
    >>> medium = mv.StandardSolid(G_inf=1e3, G1=3e3, tau1=0.5)
    >>> medium.relaxation_modulus([0.0, 0.5, 100.0])      # Pa  # doctest: +SKIP
    array([4000.        , 2103.63832351, 1000.        ])
    """

    G_inf: float
    G1: float
    tau1: float
    nu: float = 0.5

    def __post_init__(self) -> None:
        for name in ("G_inf", "G1", "tau1"):
            object.__setattr__(self, name, _positive("StandardSolid", name, getattr(self, name)))
        self._check()


@dataclass(frozen=True)
class Prony(_Medium):
    """Generalised Maxwell body (Prony series): G(t) = G_inf + sum_k G_k exp(-t / tau_k)
    (Pa, s), G_inf >= 0; Poisson ratio ``nu``.

    Parameters
    ----------
    G_inf : float
        Relaxed (long-time) shear modulus (Pa), >= 0 (0: a fluid-like body).
    terms : sequence of (float, float)
        The Maxwell arms as pairs (G_k, tau_k): shear modulus (Pa, > 0) and relaxation time
        (s, > 0) of each.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.

    Examples
    --------
    >>> mv.Prony(G_inf=1e3, terms=[(2e3, 0.1), (1e3, 10.0)])      # doctest: +SKIP
    """

    G_inf: float
    terms: tuple
    nu: float = 0.5

    def __post_init__(self) -> None:
        g_inf = _number("Prony", "G_inf", self.G_inf)
        try:
            terms = tuple((_positive("Prony", "G_k", g), _positive("Prony", "tau_k", tau))
                          for g, tau in self.terms)
        except (TypeError, ValueError) as exc:
            if isinstance(exc, InvalidInputError):
                raise
            raise InvalidInputError(f"Prony: terms must be pairs (G_k, tau_k), got {self.terms!r}") from exc
        object.__setattr__(self, "G_inf", g_inf)
        object.__setattr__(self, "terms", terms)
        self._check()

    def _values(self) -> list[float]:
        return [self.G_inf, *(value for term in self.terms for value in term)]

    @classmethod
    def _from_values(cls, values: list[float], nu: float):
        return cls(values[0], tuple(zip(values[1::2], values[2::2])), nu=nu)


@dataclass(frozen=True)
class PowerLaw(_Medium):
    """Power-law rheology G(t) = G0 (t / t0)^-beta (Pa, s), 0 < beta < 1: the standard model
    of cell rheology (a continuous spectrum of relaxation times); Poisson ratio ``nu``.
    Shear creep compliance J(t) = (t / t0)^beta / (G0 Gamma(1 - beta) Gamma(1 + beta)) (1/Pa).

    ``t0`` is a reference time (default 1 s): only G0 t0^beta enters G(t), so a fit holds it.
    Both methods step the power law as a Prony series with a long-time modulus and a
    dashpot, built once per run over its time range (from its shortest step to its last
    output time) by the trapezoid rule of G(t)'s Laplace integral, 3.5 terms per decade:
    its G(t) there is within 1e-5 of the power law's, relative (measured: 4e-6).

    Parameters
    ----------
    G0 : float
        Shear modulus at the reference time t0 (Pa), > 0.
    beta : float
        Power-law exponent, 0 < beta < 1: 0 is an elastic solid, 1 a Newtonian fluid.
    t0 : float, optional
        Reference time (s), > 0, default 1 s.
    nu : float, optional
        Poisson ratio, -1 < nu <= 0.5 (default 0.5, incompressible); constant in time.
    """

    G0: float
    beta: float
    t0: float = 1.0
    nu: float = 0.5

    def __post_init__(self) -> None:
        object.__setattr__(self, "G0", _positive("PowerLaw", "G0", self.G0))
        object.__setattr__(self, "beta", _positive("PowerLaw", "beta", self.beta))
        object.__setattr__(self, "t0", _positive("PowerLaw", "t0", self.t0))
        self._check()

    def rheology(self) -> Rheology:
        """Refused: the power law has no finite Prony series; the solvers fit one over each
        run's time range."""
        raise InvalidInputError(
            "PowerLaw has no finite Prony series: the solvers step one fitted over each run's time "
            "range; use relaxation_modulus and creep_compliance for its closed forms")


#: Media solved by the general viscoelastic stepping (not the exact viscous impulse step).
VISCOELASTIC = (KelvinVoigt, Maxwell, StandardSolid, Prony, PowerLaw)


def medium_from_model(model: dict) -> _Medium:
    """The medium of a scene model's ``[medium]`` table."""
    classes = {cls.__name__.lower(): cls for cls in (Elastic, Viscous) + VISCOELASTIC}
    return classes[model["type"]](**{k: v for k, v in model.items() if k != "type"})
