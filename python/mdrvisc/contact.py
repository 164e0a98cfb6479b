"""Contact laws: how the indenter and the body interact across the gap. A :class:`~mdrvisc.Scene`
takes one as ``contact`` (default :class:`Hard`); the compiled core decides what each law
means for the solvers (``ContactLaw`` in the crate).

>>> import mdrvisc as mv
>>> scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25),
...                  contact=mv.JKR(work_of_adhesion=0.05),
...                  force=([0.0, 1.0, 2.0], [0.0, 1.0, -1.0]), duration=2.0)
>>> r = mv.solve(scene, "mdr", 2001)       # doctest: +SKIP
>>> r.pull_off_force                       # doctest: +SKIP  (-3/2 pi w R = -0.2356 N)

Adhesive laws are solved by MDR; an adhesive scene on an elastic medium follows its loading
history (its pull-off depends on it), so it takes a duration like a time-dependent one.
"""

from __future__ import annotations

import abc
from dataclasses import dataclass

from ._validate import _positive

__all__ = ["ContactLaw", "Hard", "JKR", "DMT", "contact_from_model"]


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
    retract rate up to G_0 / G_inf times the relaxed one."""

    work_of_adhesion: float

    def __post_init__(self) -> None:
        object.__setattr__(self, "work_of_adhesion",
                           _positive("JKR", "work_of_adhesion", self.work_of_adhesion))

    def _model(self):
        return {"type": "jkr", "work_of_adhesion": self.work_of_adhesion}


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


def contact_from_model(model) -> ContactLaw:
    """The law of a scene model's ``contact`` entry (absent: hard)."""
    if model is None or model == "hard":
        return Hard()
    classes = {"jkr": JKR, "dmt": DMT}
    return classes[model["type"]](**{k: v for k, v in model.items() if k != "type"})
