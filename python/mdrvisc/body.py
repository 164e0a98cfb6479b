"""The body a scene presses into: a half-space (the default) or a :class:`Layer` of the
scene's medium on a rigid base."""

from __future__ import annotations

import dataclasses

from ._validate import _finite_positive
from .errors import InvalidInputError

__all__ = ["Layer", "BASES"]

#: How a layer may be joined to its rigid base: ``"bonded"`` (the bottom does not move) or
#: ``"frictionless"`` (the bottom slides freely on the base).
BASES = ("bonded", "frictionless")


@dataclasses.dataclass(frozen=True)
class Layer:
    """A layer of the scene's medium, of uniform thickness, on a rigid flat base, in place of
    the half-space: ``mv.Scene(..., body=mv.Layer(thickness, base))``.

    The layer has the medium's shear modulus and Poisson ratio (any nu, 0.5 included), so
    its surface compliance scales with 1 / G(t) as the half-space's does and every medium
    steps on it. It is solved by BEM, on free grids (the layer's influence coefficients,
    elements at most 8 thicknesses wide) and periodic cells (a periodic
    :class:`~mdrvisc.HeightMap`: the layer's spectral compliance), and by MDR for
    axisymmetric indenters under hard contact (elastic and viscoelastic media, no fields:
    the layer's flat-punch stiffness and exact contact radius from the punch's integral
    equation, a contact radius up to 8 thicknesses).

    Parameters
    ----------
    thickness : float
        Thickness (m), > 0.
    base : {"bonded", "frictionless"}
        How the layer is joined to its base (default ``"bonded"``).

    Examples
    --------
    >>> import mdrvisc as mv
    >>> mv.Layer(5e-6)
    Layer(thickness=5e-06, base='bonded')
    """

    thickness: float
    base: str = "bonded"

    def __post_init__(self):
        object.__setattr__(self, "thickness", _finite_positive("Layer", "thickness", self.thickness))
        if self.base not in BASES:
            raise InvalidInputError(f"Layer: base must be one of {BASES}, got {self.base!r:.80}")

    def _model(self) -> dict:
        """The scene model's ``layer`` table."""
        return {"thickness": self.thickness, "base": self.base}

    @classmethod
    def _of_model(cls, model: dict) -> Layer:
        """The Layer of a scene model's ``layer`` table."""
        return cls(model["thickness"], model.get("base", "bonded"))
