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

#: The parameters a raw AFM curve adds to the medium's (the last with ``baseline="tilt"``
#: only): the contact point z_c (m), the deflection baseline at it b (m), and the baseline's
#: slope m along the piezo (m/m).
RAW_NAMES = ("contact_point", "baseline", "baseline_slope")

#: The baseline models: a constant deflection before contact, or a line in the piezo
#: position (tilt, drift and virtual deflection), continued through the contact.
BASELINES = ("offset", "tilt")

#: Piezo positions or deflections (m) beyond this look like another unit (um, nm, V).
LARGEST_LENGTH = 1e-2


def _length(name: str, value: object) -> float:
    """``value`` as a finite float (m), or InvalidInputError naming ``name``."""
    number = _float(value)
    if number is None or not math.isfinite(number):
        raise InvalidInputError(f"fit: {name} must be a finite number (m), got {value!r:.80}")
    return number


def raw_input(depth, force, piezo, deflection, spring_constant, control) -> tuple | None:
    """(piezo, deflection, k) of a raw AFM curve, None for depth and force, or an error
    naming what is missing or given twice, and data that look like another unit."""
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
    z, deflection = array("piezo", piezo), array("deflection", deflection)
    for name, a in (("piezo", z), ("deflection", deflection)):
        span = float(np.max(a) - np.min(a)) if a.size else 0.0
        if span > LARGEST_LENGTH:
            raise DataError(f"fit: the {name} spans {span:.4g}, more than {LARGEST_LENGTH:g} m: lengths are "
                            f"in m (it looks like um, nm or volts: convert it, a deflection in V with the "
                            f"sensitivity)")
    return z, deflection, k


@dataclasses.dataclass
class AfmCurve:
    """A raw AFM curve: piezo z (m, increasing towards the sample), deflection (m), spring
    constant k (N/m), the baseline model (``tilt``: a line in z), and the first guesses of
    the contact point z_c, the baseline at it b (m) and its slope m, with their scales: the
    largest indentation, the deflection's range and that range over the piezo's."""

    z: np.ndarray
    deflection: np.ndarray
    k: float
    contact_point: float
    baseline: float
    depth_scale: float
    deflection_scale: float
    tilt: bool = False
    slope: float = 0.0
    slope_scale: float = 1.0

    @property
    def names(self) -> tuple[str, ...]:
        """The parameters this curve adds to the medium's."""
        return RAW_NAMES if self.tilt else RAW_NAMES[:2]

    @classmethod
    def estimate(cls, z, deflection, k, contact_point, baseline, model="offset"):
        """The first guesses (given ones kept), or DataError when the curve does not start
        out of contact (``model`` "offset": a constant baseline), never leaves its baseline,
        or looks flipped."""
        if baseline is not None:
            baseline = _length("baseline", baseline)
        top = int(np.argmax(z))
        count = max(BASELINE_SAMPLES, int(round(BASELINE_FRACTION * (top + 1))))
        if top + 1 < 2 * count:
            flipped = (" The piezo is highest near the start and falls afterwards: it looks flipped (the "
                       "piezo must increase towards the sample; an instrument's height that falls towards "
                       "it enters as -height)." if float(z[0] - np.min(z)) > 0.5 * float(np.ptp(z)) else "")
            raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): the approach "
                            f"(up to the highest piezo position, sample {top}) has {top + 1} samples, fewer "
                            f"than {2 * count}.{flipped}")
        tilt = model == "tilt"
        if tilt:
            line = _line(z[:count], deflection[:count])
        else:
            _check_flat(deflection[:count], deflection, count)
            line = (0.0, float(np.median(deflection[:count])))
        first, sigma = _departure(z, deflection, top, count, line, baseline)
        if tilt and first > count:
            # the line again over the part before the first guess of contact: drift seen
            # over a longer span
            line = _line(z[:max(count, (3 * first) // 4)], deflection[:max(count, (3 * first) // 4)])
            first, sigma = _departure(z, deflection, top, count, line, baseline)
        z_c = float(z[first]) if contact_point is None else _length("contact_point", contact_point)
        if not z_c > z[0]:
            raise DataError(f"fit: the contact point ({z_c:.6g} m) must lie after the first sample "
                            f"(piezo {z[0]:.6g} m)")
        if tilt:
            slope = line[0]
            b = line[0] * z_c + line[1] if baseline is None else float(baseline)
        else:
            slope = 0.0
            b = float(np.median(deflection[:count])) if baseline is None else float(baseline)
        deflection_scale = float(np.max(deflection) - np.min(deflection))
        depth_scale = float(np.max(z - z_c - (deflection - b - slope * (z - z_c))))
        if not depth_scale > 0:
            raise DataError("fit: a raw AFM curve never reaches contact: the indentation at the contact "
                            f"point's guess ({z_c:.6g} m) is <= 0 at every sample")
        slope_scale = deflection_scale / max(float(np.ptp(z)), 1e-300)
        return cls(z, deflection, k, z_c, b, depth_scale, deflection_scale, tilt, slope, slope_scale)

    def scales(self) -> tuple[float, ...]:
        """The scales of the fit's coordinates of z_c, b (m) and, with a tilt, m (m/m)."""
        return (self.depth_scale, self.deflection_scale, self.slope_scale)[:len(self.names)]

    def at(self, x: np.ndarray, free: list[str]) -> tuple[float, float, float]:
        """z_c, b (m) and m (m/m) at the fit's coordinates ``x`` of the ``free`` ones among them."""
        values = {"contact_point": self.contact_point, "baseline": self.baseline,
                  "baseline_slope": self.slope}
        scales = dict(zip(self.names, self.scales()))
        for name, u in zip(free, x):
            values[name] += float(u) * scales[name]
        return values["contact_point"], values["baseline"], values["baseline_slope"]

    def line(self, z_c: float, b: float, m: float) -> np.ndarray:
        """The baseline b + m (z - z_c) at every sample (m)."""
        return b + m * (self.z - z_c)

    def depth(self, z_c: float, b: float, m: float = 0.0) -> np.ndarray:
        """Indentation (m): (z - z_c) - (deflection - baseline)."""
        return (self.z - z_c) - (self.deflection - self.line(z_c, b, m))

    def force(self, z_c: float, b: float, m: float = 0.0) -> np.ndarray:
        """Force (N): k (deflection - baseline)."""
        return self.k * (self.deflection - self.line(z_c, b, m))

    def shift(self, z_c: float) -> float:
        """What z_c adds to every drive z - z_c of the guess's (m)."""
        return self.contact_point - z_c

    def jacobian(self, jac: np.ndarray, free: list[str], z_c: float, m: float) -> np.ndarray:
        """The Jacobian of model - data in the fit's coordinates from the curve's: the
        medium's columns and the shift's last column dF/dshift (N/m); d/dz_c = -dF/dshift
        - k m (the baseline turns about the contact point z_c), d/db = k (the data's force
        falls as b rises; the model's does not move), d/dm = k (z - z_c), times the scales."""
        d_shift = jac[:, -1]
        columns = {"contact_point": (-d_shift - self.k * m) * self.depth_scale,
                   "baseline": np.full_like(d_shift, self.k * self.deflection_scale)}
        if "baseline_slope" in free:
            columns["baseline_slope"] = self.k * (self.z - z_c) * self.slope_scale
        return np.column_stack([jac[:, :-1]] + [columns[name] for name in free])


def _line(z: np.ndarray, deflection: np.ndarray) -> tuple[float, float]:
    """(slope, intercept) of the least-squares line of the deflection in z."""
    if float(np.ptp(z)) == 0.0:
        return 0.0, float(np.median(deflection))
    slope, intercept = np.polyfit(z, deflection, 1)
    return float(slope), float(intercept)


def _check_flat(start: np.ndarray, deflection: np.ndarray, count: int) -> None:
    """DataError when the start of the approach is not flat (a constant baseline)."""
    steps = np.arange(count, dtype=float)
    slope, intercept = np.polyfit(steps, start, 1)
    scatter = 1.4826 * float(np.median(np.abs(start - slope * steps - intercept)))
    if abs(slope) * (count - 1) > 5.0 * max(scatter, 1e-12 * float(np.max(np.abs(deflection)))):
        raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): the "
                        f"deflection changes by {slope * (count - 1):.3g} m over the first {count} "
                        f"samples, more than 5 times its scatter about a line ({scatter:.3g} m); a tilted "
                        f"or drifting baseline is fitted with baseline_model=\"tilt\"")


def _departure(z, deflection, top, count, line, baseline) -> tuple[int, float]:
    """(the last sample of the approach before the deflection rises above the baseline
    ``line`` (slope, intercept; shifted to ``baseline`` when given) by
    :data:`CONTACT_SIGMAS` robust standard deviations of its first ``count`` samples,
    the deviation), or DataError when it never does."""
    base = line[0] * z + line[1]
    if baseline is not None:
        base = base - float(np.median(base[:count])) + float(baseline)
    excess = deflection[:top + 1] - base[:top + 1]
    # (a floor far below any noise: a noise-free line's scatter is round-off)
    sigma = max(1.4826 * float(np.median(np.abs(excess[:count] - np.median(excess[:count])))),
                1e-9 * float(np.ptp(excess)))
    above = excess > CONTACT_SIGMAS * sigma
    low, high = -float(np.min(excess[count:])), float(np.max(excess[count:]))
    if low > max(2.0 * high, 10.0 * CONTACT_SIGMAS * sigma):
        raise DataError(f"fit: the deflection of the approach falls {low:.3g} m below its baseline and "
                        f"rises {high:.3g} m above it, as if its sign were flipped (the deflection is "
                        "positive when the sample pushes the tip back)")
    if not np.any(above[count:]):
        raise DataError(f"fit: a raw AFM curve never reaches contact: the deflection never exceeds the "
                        f"baseline ({float(base[0]):.6g} m at the start) by {CONTACT_SIGMAS:g} times its "
                        f"scatter ({sigma:.3g} m)")
    deepest = int(np.argmax(excess))
    below = np.flatnonzero(~above[:deepest + 1])
    return (int(below[-1]) if below.size else 0), sigma
