"""Half-space media. All are incompressible (Poisson ratio 1/2, E* = 4 G)."""

from dataclasses import dataclass

from .analytic import _positive

__all__ = ["Viscous", "Elastic"]


@dataclass(frozen=True)
class Viscous:
    """Newtonian viscous half-space of shear viscosity ``eta`` (Pa s).

    Radok's correspondence: every elastic result for a fixed contact holds for deflection
    *rates* with G replaced by eta.
    """

    eta: float

    def __post_init__(self):
        object.__setattr__(self, "eta", _positive("Viscous", "eta", self.eta))


@dataclass(frozen=True)
class Elastic:
    """Linear elastic half-space of shear modulus ``G`` (Pa); a scene with it and no duration
    is one static contact solve."""

    G: float

    def __post_init__(self):
        object.__setattr__(self, "G", _positive("Elastic", "G", self.G))
