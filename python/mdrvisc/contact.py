"""Contact laws: how the indenter and the body interact across the gap. A :class:`~mdrvisc.Scene`
takes one as ``contact`` (default :class:`Hard`); the compiled core decides what each law
means for the solvers (``ContactLaw`` in the crate).

>>> import mdrvisc as mv
>>> scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25),
...                  contact=mv.JKR(work_of_adhesion=0.05),
...                  force=([0.0, 1.0, 2.0], [0.0, 1.0, -1.0]), duration=2.0)
>>> r = mv.solve(scene, "mdr", 2001)       # doctest: +SKIP
>>> r.pull_off_force                       # doctest: +SKIP  (-3/2 pi w R = -0.2356 N)

JKR and DMT are solved by MDR, the cohesive-zone laws :class:`MaugisDugdale` and
:class:`Exponential` by BEM under depth control; an adhesive scene on an elastic medium follows
its loading history (its pull-off depends on it), so it takes a duration like a
time-dependent one.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

from ._validate import _positive
from .errors import InvalidInputError

__all__ = ["ContactLaw", "Hard", "JKR", "DMT", "MaugisDugdale", "Exponential",
           "contact_from_model"]


class ContactLaw(abc.ABC):
    """Base of the contact laws."""

    @abc.abstractmethod
    def _model(self):
        """The law in the scene model's form: ``"hard"`` or a table with its ``type``."""


@dataclass(frozen=True)
class Hard(ContactLaw):
    """Frictionless, non-adhesive contact (Signorini): no tension, the default."""

    def _model(self):
        return "hard"


@dataclass(frozen=True)
class JKR(ContactLaw):
    """Adhesion of zero range (Johnson, Kendall & Roberts 1971) with work of adhesion
    ``work_of_adhesion`` w (J/m^2), for every axisymmetric indenter by MDR (Heß's rule): an
    element attaches when the indenter touches it and lets go when its elongation reaches
    sqrt(2 pi a w / E*) at contact radius a, E* the body's relaxed contact modulus. A
    paraboloid of radius R lets go at -3/2 pi w R under force control and -5/6 pi w R under
    depth control; a flat punch of radius a at -sqrt(8 pi a^3 w E*) (Kendall 1971). A
    viscoelastic body needs a relaxed modulus (G_inf > 0); its pull-off grows with the
    retract rate up to G_0 / G_inf times the relaxed one.

    ``approach`` says how the contact grows on an approach: ``"touch"`` (the default) as a
    hard contact (Hertz on a paraboloid), the contact then held at its largest radius on the
    retract until its edge lets go; ``"equilibrium"`` on the JKR branch, jumping in at the
    touch (loading and unloading retrace each other: the zero-range limit of a cohesive zone,
    what boundary elements with a Maugis–Dugdale law of large transition parameter give).
    Fits (:func:`~mdrvisc.fit`) take both; scenes step the touch rule.

    ``stress`` (Pa, optional) is the cohesive stress sigma0 of the crack tip's process zone
    (a Dugdale zone of range w / sigma0, as :class:`MaugisDugdale`'s). A viscoelastic body
    needs it to let its edge go by the crack's speed: the zone, pi K^2 / (8 sigma0^2) long
    for the edge's stress intensity K, is crossed in a time dt at the edge's speed, and the
    edge lets go when K^2 C_eff(dt) / 2 reaches w, C_eff the creep compliance of the
    contact modulus averaged over the zone (Schapery; Greenwood & Johnson 1981): the relaxed
    body's JKR for slow cracks, the glassy body's for fast ones. Without it a viscoelastic
    body lets go by Heß's rule with the relaxed modulus, right only for cycles slow against
    its relaxation (see the adhesion page). An elastic body does not use it; fits refuse it
    on viscoelastic media.

    >>> import mdrvisc as mv
    >>> mv.JKR(work_of_adhesion=0.05, approach="equilibrium").approach
    'equilibrium'
    >>> mv.JKR(work_of_adhesion=0.05, stress=1e6).stress
    1000000.0
    """

    work_of_adhesion: float
    approach: str = "touch"
    stress: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "work_of_adhesion",
                           _positive("JKR", "work_of_adhesion", self.work_of_adhesion))
        if self.approach not in ("touch", "equilibrium"):
            raise InvalidInputError(f"JKR: approach must be 'touch' or 'equilibrium', got {self.approach!r}")
        if self.stress is not None:
            object.__setattr__(self, "stress", _positive("JKR", "stress", self.stress))

    def _model(self):
        if self.approach != "touch":
            raise InvalidInputError("JKR: scenes grow a JKR contact by the touch rule; "
                                    "approach='equilibrium' is for fits (mv.fit(..., contact=...))")
        model = {"type": "jkr", "work_of_adhesion": self.work_of_adhesion}
        if self.stress is not None:
            model["stress"] = self.stress
        return model


@dataclass(frozen=True)
class DMT(ContactLaw):
    """Adhesion of Derjaguin, Muller & Toporov (1975) with work of adhesion
    ``work_of_adhesion`` w (J/m^2): the non-adhesive contact plus the attraction 2 pi w R of a
    rounded tip of radius R (paraboloid R = 1 / (2 c), sphere) while the surfaces touch, so
    the pull-off force is 2 pi w R and the contact jumps in with that tension at the touch."""

    work_of_adhesion: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "work_of_adhesion",
                           _positive("DMT", "work_of_adhesion", self.work_of_adhesion))

    def _model(self):
        return {"type": "dmt", "work_of_adhesion": self.work_of_adhesion}


@dataclass(frozen=True, init=False)
class MaugisDugdale(ContactLaw):
    """Maugis–Dugdale cohesive zone (Maugis 1992), solved by BEM under depth control: a
    tensile traction ``stress`` sigma0 (Pa) acts wherever the gap is at most
    h0 = w / sigma0 (m), in the contact too, with work of adhesion ``work_of_adhesion`` w
    (J/m^2). Give the stress or the ``range`` h0. For a sphere of radius R on a body of
    contact modulus E*, the transition parameter lambda = 2 sigma0 (R / (pi w E*^2))^(1/3)
    takes the pull-off from DMT's 2 pi w R (lambda -> 0) to JKR's 3/2 pi w R (large lambda).

    >>> import mdrvisc as mv
    >>> mv.MaugisDugdale(work_of_adhesion=0.05, range=1e-9).stress
    50000000.0
    """

    work_of_adhesion: float
    stress: float

    def __init__(self, work_of_adhesion: float, stress: float | None = None,
                 range: float | None = None) -> None:
        w = _positive("MaugisDugdale", "work_of_adhesion", work_of_adhesion)
        if (stress is None) == (range is None):
            raise InvalidInputError("MaugisDugdale: give one of stress (Pa) or range (m)")
        if stress is None:
            stress = w / _positive("MaugisDugdale", "range", range)
        object.__setattr__(self, "work_of_adhesion", w)
        object.__setattr__(self, "stress", _positive("MaugisDugdale", "stress", stress))

    @property
    def range(self) -> float:
        """The range h0 = w / sigma0 (m)."""
        return self.work_of_adhesion / self.stress

    def _model(self):
        return {"type": "maugis_dugdale", "work_of_adhesion": self.work_of_adhesion,
                "stress": self.stress}


@dataclass(frozen=True)
class Exponential(ContactLaw):
    """Exponential cohesive law, solved by BEM under depth control: the interaction energy
    -w exp(-g / rho) per unit area (the Adhesion package's ``Exponential(gamma0, rho)``), so a
    tensile traction (w / rho) exp(-g / rho) at gap g >= 0, with work of adhesion
    ``work_of_adhesion`` w (J/m^2) and decay length ``range`` rho (m).

    >>> import mdrvisc as mv
    >>> mv.Exponential(work_of_adhesion=0.05, range=1e-9).range
    1e-09
    """

    work_of_adhesion: float
    range: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "work_of_adhesion",
                           _positive("Exponential", "work_of_adhesion", self.work_of_adhesion))
        object.__setattr__(self, "range", _positive("Exponential", "range", self.range))

    def _model(self):
        return {"type": "exponential", "work_of_adhesion": self.work_of_adhesion,
                "range": self.range}


def contact_from_model(model) -> ContactLaw:
    """The law of a scene model's ``contact`` entry (absent: hard)."""
    if model is None or model == "hard":
        return Hard()
    classes = {"jkr": JKR, "dmt": DMT, "maugis_dugdale": MaugisDugdale,
               "exponential": Exponential}
    return classes[model["type"]](**{k: v for k, v in model.items() if k != "type"})
