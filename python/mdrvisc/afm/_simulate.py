"""Raw AFM curves simulated with the forward model that :func:`mdrvisc.fit` inverts: the piezo
drives the cantilever's base, the cantilever (a spring of stiffness k) pushes the tip into
the medium, and the force k (z - z_c - d) balances the medium's at every sample (MDR,
the crate's spring control: ``_core.Curve`` with control "spring").

:func:`piezo_ramp` writes the usual protocols (approach, dwell, retract at given speeds);
:func:`simulate` returns the curve as an instrument file would (an :class:`~mdrvisc.afm.Curve`,
noise optional) with the noise-free force, indentation and contact radius beside it.
"""

from __future__ import annotations

import dataclasses
import json
import math

import numpy as np
from numpy.typing import ArrayLike

from .. import _core
from .._validate import _integer
from ..errors import DataError, DomainError, InvalidInputError
from ..geometry import Indenter
from ..media import _Medium
from ._files import Curve

__all__ = ["simulate", "piezo_ramp", "Simulation", "SEGMENTS"]

#: The segments of a simulated curve, by number.
SEGMENTS = ("approach", "dwell", "retract")

#: The 1D profile reaches this factor times the contact radius at the largest drive past the
#: contact point (the indentation never exceeds the drive).
MARGIN = 1.1


def _positive(name: str, value, allow_zero: bool = False) -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        v = math.nan
    if not math.isfinite(v) or v < 0 or (v == 0 and not allow_zero):
        bound = ">= 0" if allow_zero else "> 0"
        raise InvalidInputError(f"{name} must be a finite number {bound}, got {value!r}")
    return v


def piezo_ramp(travel: float, speed: float, rate: float, *, dwell: float = 0.0, retract: bool = True,
               retract_speed: float | None = None, start: float = 0.0
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A piezo history: approach by ``travel`` at ``speed``, hold for ``dwell``, retract back.

    Parameters
    ----------
    travel : float
        Piezo travel towards the sample (m).
    speed : float
        Approach speed (m/s); ``retract_speed`` that of the retract (default the same).
    rate : float
        Sampling rate (Hz).
    dwell : float
        Hold at the deepest position (s), 0 for none.
    retract : bool
        Whether the piezo goes back to its start.
    start : float
        The piezo position of the first sample (m).

    Returns
    -------
    (t, piezo, segment) : ndarray, ndarray, ndarray of int
        Times (s) from 0, piezo positions (m, rising towards the sample) and segment numbers
        (0 approach, 1 dwell, 2 retract: :data:`SEGMENTS`).

    Examples
    --------
    >>> t, z, segment = mv.afm.piezo_ramp(2e-6, speed=2e-6, rate=2000.0)
    >>> float(t[-1]), float(z.max()), len(t)
    (2.0, 2e-06, 4001)
    """
    travel, speed, rate = _positive("piezo_ramp: travel", travel), _positive("piezo_ramp: speed", speed), \
        _positive("piezo_ramp: rate", rate)
    dwell = _positive("piezo_ramp: dwell", dwell, allow_zero=True)
    back = speed if retract_speed is None else _positive("piezo_ramp: retract_speed", retract_speed)
    dt = 1.0 / rate
    up = max(2, int(round(travel / speed * rate)))
    parts_t = [np.arange(up + 1) * dt * (travel / speed) / (up * dt)]
    parts_z = [np.linspace(0.0, travel, up + 1)]
    parts_s = [np.zeros(up + 1, dtype=np.int64)]
    now = float(parts_t[0][-1])
    if dwell > 0:
        count = max(1, int(round(dwell * rate)))
        parts_t.append(now + np.arange(1, count + 1) * dwell / count)
        parts_z.append(np.full(count, travel))
        parts_s.append(np.full(count, 1, dtype=np.int64))
        now += dwell
    if retract:
        down = max(2, int(round(travel / back * rate)))
        parts_t.append(now + np.arange(1, down + 1) * (travel / back) / down)
        parts_z.append(travel - np.linspace(0.0, travel, down + 1)[1:])
        parts_s.append(np.full(down, 2, dtype=np.int64))
    return np.concatenate(parts_t), start + np.concatenate(parts_z), np.concatenate(parts_s)


def _segments(z: np.ndarray) -> np.ndarray:
    """Segment numbers (:data:`SEGMENTS`) of a piezo history: approach up to the first deepest
    sample, dwell while it stays there, retract after."""
    top = float(np.max(z))
    at_top = np.flatnonzero(z == top)
    first, last = int(at_top[0]), int(at_top[-1])
    segment = np.zeros(z.size, dtype=np.int64)
    segment[first + 1:last + 1] = 1
    segment[last + 1:] = 2
    return segment


@dataclasses.dataclass(eq=False)
class Simulation:
    """A simulated raw AFM curve.

    Attributes
    ----------
    curve : Curve
        As an instrument file gives it: times, piezo (m, rising towards the sample), the
        deflection (m, with the baseline and any noise), the spring constant, segments.
    force : ndarray
        The noise-free force on the tip (N), k times the deflection less the baseline.
    depth : ndarray
        The indentation (m): piezo - contact point - (force / k).
    contact_radius : ndarray
        The contact radius (m) at each sample (the MDR profile's elements in contact).
    forward : str
        The forward model that ran ("hereditary" or "elements", as in :class:`mdrvisc.FitResult`).
    """

    curve: Curve
    force: np.ndarray
    depth: np.ndarray
    contact_radius: np.ndarray
    forward: str


def simulate(indenter: Indenter, medium: _Medium, t: ArrayLike, piezo: ArrayLike, spring_constant: float, *,
             contact_point: float = 0.0, baseline: float = 0.0, noise: float = 0.0,
             seed: int | np.random.Generator | None = None, segment: ArrayLike | None = None, n: int = 500,
             substeps: int = 1) -> Simulation:
    """A raw AFM curve: the piezo history ``piezo`` drives a cantilever of stiffness
    ``spring_constant`` whose tip indents ``medium``, the forward model of a raw-curve fit.

    The body is at rest at the first sample. The tip touches the surface where the piezo
    passes ``contact_point``; from there the force F = k (z - z_c - d) on the cantilever
    equals the medium's at indentation d (MDR on ``n`` elements, ``substeps`` steps per
    sample interval), so a soft cantilever indents less than the piezo travels and a
    viscoelastic medium's indentation creeps while the piezo holds.

    Parameters
    ----------
    indenter : Indenter
        The tip (axisymmetric).
    medium : medium
        An instance (e.g. ``mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.1)``).
    t, piezo : array_like
        Sample times (s, strictly increasing) and piezo positions (m, rising towards the
        sample), e.g. from :func:`piezo_ramp`.
    spring_constant : float
        k (N/m).
    contact_point : float
        The piezo position where the tip meets the surface (m).
    baseline : float
        The deflection out of contact (m), added to the deflection.
    noise : float
        Standard deviation (m) of Gaussian noise added to the deflection.
    seed : int or numpy Generator, optional
        The noise's random numbers.
    segment : array_like of int, optional
        Segment numbers (0 approach, 1 dwell, 2 retract: :data:`SEGMENTS`); default: approach
        up to the deepest piezo position, dwell while it stays there, retract after.
    n : int
        Elements of the half 1D profile (which reaches 1.1 times the contact radius at the
        largest drive past the contact point); 8 to 2**26 (``mdrvisc._core.MAX_N["mdr"]``).
    substeps : int
        Time steps per sample interval where the elements are stepped.

    Returns
    -------
    Simulation
        ``simulation.curve`` is what :func:`mdrvisc.afm.load` would give for such a file;
        ``simulation.curve.fit(indenter, type(medium))`` fits it.

    Examples
    --------
    >>> t, z, _ = mv.afm.piezo_ramp(3e-6, speed=5e-6, rate=2000.0, start=-1e-6)
    >>> sim = mv.afm.simulate(mv.Sphere(radius=5e-6), mv.Elastic(G=1e3), t, z, 0.05)
    >>> round(float(sim.force.max()) * 1e9, 2)   # nN
    22.36
    """
    if not isinstance(indenter, Indenter):
        raise InvalidInputError(f"simulate: indenter must be an mdrvisc indenter, got {indenter!r}")
    if not isinstance(medium, _Medium):
        raise InvalidInputError(f"simulate: medium must be an mdrvisc medium instance, got {medium!r}")
    k = _positive("simulate: spring_constant", spring_constant)
    n = _integer("simulate", "n", n, 8, _core.MAX_N["mdr"])
    substeps = _integer("simulate", "substeps", substeps, 1)
    t = np.array(t, dtype=float).ravel()
    z = np.array(piezo, dtype=float).ravel()
    if t.size != z.size or t.size < 2:
        raise DataError(f"simulate: t and piezo need the same number of samples (>= 2), got {t.size} "
                        f"and {z.size}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(z))):
        raise DataError("simulate: t and piezo must be finite")
    if not np.all(np.diff(t) > 0):
        raise DataError("simulate: t must be strictly increasing")
    for name, value in (("contact_point", contact_point), ("baseline", baseline)):
        if not math.isfinite(float(value)):
            raise InvalidInputError(f"simulate: {name} must be finite, got {value!r}")
    noise = _positive("simulate: noise", noise, allow_zero=True)
    drive = z - float(contact_point)
    if not drive[0] < 0:
        raise DataError(f"simulate: the first piezo position ({z[0]:.6g} m) must lie before the contact "
                        f"point ({contact_point:.6g} m): the tip starts out of contact")
    deepest = float(np.max(drive))
    if not deepest > 0:
        raise DataError(f"simulate: the piezo never passes the contact point ({contact_point:.6g} m)")
    try:
        a = indenter.contact_radius_at_depth(deepest)
    except DomainError as exc:
        raise DomainError(f"simulate: the largest drive past the contact point ({deepest:.6g} m) is beyond "
                          f"the indenter: {exc}") from None
    half = MARGIN * a
    if indenter.mdr_half_length is not None:
        half = a if indenter.is_flat else min(half, indenter.mdr_half_length)
    dx = half / n
    core = _core.Indenter.from_json(json.dumps(indenter._model(half)))
    profile = core.profile_1d((np.arange(n) + 0.5) * dx)
    curve = _core.Curve(profile, dx, t - t[0], drive, "spring", substeps, k)
    force, _, contact, forward = curve.evaluate([json.dumps(medium._model())], [])[0]
    if np.any(contact >= n) and not indenter.is_flat:
        raise DomainError("simulate: the contact reached the end of the 1D profile")
    deflection = force / k + float(baseline)
    if noise > 0:
        rng = seed if isinstance(seed, np.random.Generator) else np.random.default_rng(seed)
        deflection = deflection + rng.normal(0.0, noise, deflection.size)
    segments = _segments(z) if segment is None else np.asarray(segment, dtype=np.int64).ravel()
    if segments.size != t.size or not np.all((segments >= 0) & (segments < len(SEGMENTS))):
        raise DataError(f"simulate: segment needs {t.size} numbers in 0..2 (approach, dwell, retract)")
    record = Curve(time=t, piezo=z, deflection=deflection, spring_constant=k, segment=segments,
                   segments=SEGMENTS,
                   metadata={"spring constant": k, "simulated": True, "medium": repr(medium),
                             "indenter": repr(indenter), "contact point": float(contact_point),
                             "baseline": float(baseline), "noise": noise}, height="simulated")
    return Simulation(curve=record, force=force, depth=drive - force / k,
                      contact_radius=np.asarray(contact, dtype=float) * dx, forward=forward)
