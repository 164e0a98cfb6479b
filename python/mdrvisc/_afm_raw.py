"""Raw AFM curves in a fit: the piezo displacement, the cantilever deflection and its spring
constant, with the contact point z_c and the deflection baseline b as two more parameters.

They move every depth of the history by the same amount, and the forward model's derivative
along such a shift is one more forward-mode tangent (exact for the discrete model).
:func:`raw_input` checks what was given; :class:`AfmCurve` holds the curve, its first guesses
of z_c and b (from the contact-free start of the approach) and the fit's coordinates of them.
Lengths in m, forces in N, spring constants in N/m.
"""

import dataclasses
import math

import numpy as np

from ._fit_checks import array
from ._validate import _float
from .errors import DataError, InvalidInputError

#: The first fraction of the approach (up to the highest piezo position) that must lie before
#: contact, and the fewest samples it may have.
BASELINE_FRACTION, BASELINE_SAMPLES = 0.1, 5

#: The deflection leaves the baseline where it exceeds the baseline's median by this many
#: robust standard deviations of it (the contact point's first guess).
CONTACT_SIGMAS = 3.0

#: The parameters a raw AFM curve adds to the medium's.
RAW_NAMES = ("contact_point", "baseline")


def _length(name: str, value: object) -> float:
    """``value`` as a finite float (m), or InvalidInputError naming ``name``."""
    number = _float(value)
    if number is None or not math.isfinite(number):
        raise InvalidInputError(f"fit: {name} must be a finite number (m), got {value!r:.80}")
    return number


def raw_input(depth, force, piezo, deflection, spring_constant, control) -> tuple | None:
    """(piezo, deflection, k) of a raw AFM curve, None for depth and force, or an error
    naming what is missing or given twice."""
    given = {name for name, v in (("depth", depth), ("force", force), ("piezo", piezo),
                                  ("deflection", deflection), ("spring_constant", spring_constant))
             if v is not None}
    if given == {"depth", "force"}:
        return None
    if given != {"piezo", "deflection", "spring_constant"}:
        raise InvalidInputError("fit: give depth= and force=, or a raw AFM curve as piezo=, deflection= and "
                                f"spring_constant=; got {sorted(given)}")
    if control != "depth":
        raise InvalidInputError(f"fit: a raw AFM curve is depth-controlled (the piezo moves); "
                                f"control={control!r}")
    k = _float(spring_constant)
    if k is None or not (math.isfinite(k) and k > 0):
        raise InvalidInputError(f"fit: spring_constant must be > 0 (N/m), got {spring_constant!r:.80}")
    return array("piezo", piezo), array("deflection", deflection), k


@dataclasses.dataclass
class AfmCurve:
    """A raw AFM curve: piezo z (m, increasing towards the sample), deflection (m), spring
    constant k (N/m), and the first guesses of the contact point z_c and the baseline b
    (m) with their scales: the largest indentation and the deflection's range."""

    z: np.ndarray
    deflection: np.ndarray
    k: float
    contact_point: float
    baseline: float
    depth_scale: float
    deflection_scale: float

    @classmethod
    def estimate(cls, z, deflection, k, contact_point, baseline):
        """The first guesses (given ones kept), or DataError when the curve does not start
        out of contact or never leaves its baseline."""
        top = int(np.argmax(z))
        count = max(BASELINE_SAMPLES, int(round(BASELINE_FRACTION * (top + 1))))
        if top + 1 < 2 * count:
            raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): the approach "
                            f"(up to the highest piezo position, sample {top}) has {top + 1} samples, fewer "
                            f"than {2 * count}")
        start = deflection[:count]
        median = float(np.median(start))
        sigma = 1.4826 * float(np.median(np.abs(start - median)))
        # a start in contact rises: a line through it changes by more than its scatter about it
        steps = np.arange(count, dtype=float)
        slope, intercept = np.polyfit(steps, start, 1)
        scatter = 1.4826 * float(np.median(np.abs(start - slope * steps - intercept)))
        if abs(slope) * (count - 1) > 5.0 * max(scatter, 1e-12 * float(np.max(np.abs(deflection)))):
            raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): the "
                            f"deflection changes by {slope * (count - 1):.3g} m over the first {count} "
                            f"samples, more than 5 times its scatter about a line ({scatter:.3g} m)")
        b = median if baseline is None else _length("baseline", baseline)
        above = deflection[:top + 1] - b > CONTACT_SIGMAS * sigma
        if not np.any(above[count:]):
            raise DataError(f"fit: a raw AFM curve never reaches contact: the deflection never exceeds the "
                            f"baseline ({b:.6g} m) by {CONTACT_SIGMAS:g} times its scatter ({sigma:.3g} m)")
        deepest = int(np.argmax(deflection[:top + 1]))
        below = np.flatnonzero(~above[:deepest + 1])
        first = int(below[-1]) if below.size else 0
        z_c = float(z[first]) if contact_point is None else _length("contact_point", contact_point)
        if not z_c > z[0]:
            raise DataError(f"fit: the contact point ({z_c:.6g} m) must lie after the first sample "
                            f"(piezo {z[0]:.6g} m)")
        deflection_scale = float(np.max(deflection) - np.min(deflection))
        depth_scale = float(np.max(z - z_c - (deflection - b)))
        if not depth_scale > 0:
            raise DataError("fit: a raw AFM curve never reaches contact: the indentation at the contact "
                            f"point's guess ({z_c:.6g} m) is <= 0 at every sample")
        return cls(z, deflection, k, z_c, b, depth_scale, deflection_scale)

    def scales(self) -> tuple[float, float]:
        """The scales (m) of the fit's coordinates of z_c and b."""
        return self.depth_scale, self.deflection_scale

    def at(self, x: np.ndarray, free: list[str]) -> tuple[float, float]:
        """z_c and b (m) at the fit's coordinates ``x`` of the ``free`` ones among them."""
        values = {"contact_point": self.contact_point, "baseline": self.baseline}
        for name, u in zip(free, x):
            values[name] += float(u) * dict(zip(RAW_NAMES, self.scales()))[name]
        return values["contact_point"], values["baseline"]

    def depth(self, z_c: float, b: float) -> np.ndarray:
        """Indentation (m): (z - z_c) - (deflection - b)."""
        return (self.z - z_c) - (self.deflection - b)

    def force(self, b: float) -> np.ndarray:
        """Force (N): k (deflection - b)."""
        return self.k * (self.deflection - b)

    def shift(self, z_c: float) -> float:
        """What z_c adds to every drive z - z_c of the guess's (m)."""
        return self.contact_point - z_c

    def jacobian(self, jac: np.ndarray, free: list[str]) -> np.ndarray:
        """The Jacobian of model - data in the fit's coordinates from the curve's: the
        medium's columns and the shift's last column dF/dshift (N/m); d/dz_c = -dF/dshift,
        d/db = k (the data's force falls as b rises; the model's does not move), times the
        scales."""
        d_shift = jac[:, -1]
        columns = {"contact_point": -d_shift * self.depth_scale,
                   "baseline": np.full_like(d_shift, self.k * self.deflection_scale)}
        return np.column_stack([jac[:, :-1]] + [columns[name] for name in free])
