"""Fits with an adhesive contact law: the least-squares problem of a fit whose forward model is
JKR contact by MDR (``_core.Curve.evaluate_jkr``: an elastic body, or a viscoelastic one under
depth control, the contact's edge moving continuously between the elements) or DMT's
(``evaluate_dmt``: the hard contact plus the attraction 2 pi w R of a rounded tip), so that
the retract's dip below the baseline is data.

The coordinates are those of :class:`~mdrvisc._fit_model.Problem` with the logarithm of the
work of adhesion after the medium's (unless it is held). The Jacobian is by finite
differences: the forward model settles the contact at the samples in microseconds, and its
force is smooth in the parameters except where a sample crosses the pull-off (a jump) or the
edge starts to recede (a kink), where the one-sided difference of the smaller magnitude is
taken.
"""

import json

import numpy as np

from ._fit_model import Problem, medium_of
from .contact import DMT, JKR, Hard
from .errors import InvalidInputError
from .geometry import Indenter, Paraboloid, Sphere
from .media import Elastic, Prony, StandardSolid, _Medium

#: Viscoelastic media a JKR fit of a depth-controlled curve takes (a relaxed modulus, no
#: dashpot in parallel): the contact's edge follows the relaxed modulus, each element its own
#: hereditary integral.
VISCOELASTIC = (StandardSolid, Prony)

#: Name of the work of adhesion among a fit's parameters (J/m^2).
WORK_OF_ADHESION = "work_of_adhesion"

#: Step of the finite differences in the fit's coordinates (logarithms, scaled contact point):
#: truncation ~STEP^2, round-off ~1e-16 / STEP of the force.
STEP = 1e-6

#: Fractions of the given work of adhesion the fit starts from, the best kept: too large a
#: work of adhesion holds the contact through the whole retract, where the force does not
#: depend on it (a plateau of the cost), while from below the fit finds it.
START_FRACTIONS = np.geomspace(1e-3, 1.0, 7)

#: Factors of the medium's first guess a raw fit whose contact jumps in starts from at each of
#: its contact points (the guess was made at the first).
MODULUS_FACTORS = np.geomspace(0.25, 4.0, 9)

#: Robust standard deviations of the baseline's scatter the deflection falls below it where a
#: contact jumps in (a start of the contact point).
JUMP_SIGMAS = 5.0

#: One-sided differences that disagree by more than this fraction of their magnitudes
#: straddle a jump or a kink.
DISAGREE = 1e-3


def check_contact(contact: object, model: object, control: str, indenter: Indenter,
                  raw: bool) -> JKR | DMT | None:
    """The adhesive law of :func:`~mdrvisc.fit`'s ``contact`` (None: hard contact), or
    InvalidInputError for a law, medium, control, tip or curve (``raw``: an AFM curve) the
    adhesive fit does not cover."""
    if contact is None or isinstance(contact, Hard):
        return None
    if not isinstance(contact, (JKR, DMT)):
        raise InvalidInputError(f"fit: contact must be mv.Hard(), mv.JKR(work_of_adhesion=...) or "
                                f"mv.DMT(work_of_adhesion=...), got {contact!r}")
    if isinstance(contact, DMT) and tip_radius(indenter) is None:
        raise InvalidInputError(f"fit: DMT's attraction 2 pi w R needs a rounded tip (mv.Sphere, "
                                f"mv.Paraboloid), got {indenter!r}")
    cls = model if isinstance(model, type) else type(model)
    if cls is not Elastic and not (isinstance(contact, JKR) and contact.approach == "touch"
                                   and cls in VISCOELASTIC and not raw):
        raise InvalidInputError(f"fit: an adhesive fit takes an elastic medium (mv.Elastic), or with "
                                f"mv.JKR(approach='touch') on a depth-controlled curve one of "
                                f"{', '.join(c.__name__ for c in VISCOELASTIC)}; got {cls.__name__}")
    if isinstance(contact, JKR) and contact.stress is not None and cls is not Elastic:
        raise InvalidInputError("fit: a viscoelastic JKR fit lets the edge go by Heß's rule with the "
                                "relaxed modulus; the process zone's stress (mv.JKR(stress=...)) is "
                                "for scenes (mv.solve)")
    if control != "depth":
        raise InvalidInputError(f"fit: an adhesive fit is depth-controlled (or a raw AFM curve); "
                                f"control={control!r}")
    return contact


def reach_margin(law: JKR | DMT | None) -> str | None:
    """The key of :data:`~mdrvisc._fit_model.MARGIN` sizing the profile of a fit with ``law``
    (None: the control's) whose contact jumps in: a JKR contact loaded in equilibrium outgrows
    the hard one, and a raw curve's contact point may lie well before its first guess (which
    the deflection's rise gives, after the jump in)."""
    return "adhesive" if jumps_in(law) else None


def jumps_in(law: JKR | DMT | None) -> bool:
    """Whether the contact of ``law`` jumps in at the touch (DMT, JKR in equilibrium)."""
    return isinstance(law, DMT) or (isinstance(law, JKR) and law.approach == "equilibrium")


def tip_radius(indenter: Indenter) -> float | None:
    """Radius of curvature (m) of a rounded tip (paraboloid 1 / (2 c), sphere), else None."""
    if isinstance(indenter, Paraboloid):
        return 0.5 / indenter.c
    if isinstance(indenter, Sphere):
        return indenter.radius
    return None


class AdhesiveProblem(Problem):
    """The least-squares problem of ``base`` (its data, weights, medium and raw AFM curve) with
    the contact ``law`` (JKR, or DMT with the tip radius ``radius``, m) of initial work of
    adhesion ``law.work_of_adhesion``, fitted unless ``held``."""

    def __init__(self, base: Problem, law: JKR | DMT, held: bool, radius: float | None = None) -> None:
        super().__init__(base.curve, base.cls, base.values0, base.nu, base.free, base.free, base.raw,
                         base.free_raw, base.measured, base.root_w, base.n)
        self.medium_free = list(base.free)
        self.free = self.medium_free + ([] if held else [WORK_OF_ADHESION])
        self.w0, self.law, self.radius, self.given = law.work_of_adhesion, type(law), radius, law
        self.approach = law.approach if isinstance(law, JKR) else None
        self.stress = law.stress if isinstance(law, JKR) else None

    def x0(self) -> np.ndarray:
        """The initial coordinates: the medium's initial values, and the work of adhesion of
        :data:`START_FRACTIONS` of the given one and the contact point of
        :meth:`contact_point_starts` whose residuals are least."""
        values = dict(self.values0, work_of_adhesion=self.w0)
        logs = np.log([values[name] for name in self.free])
        x = np.concatenate([logs, np.zeros(len(self.free_raw))])
        starts = [x]
        if WORK_OF_ADHESION in self.free:
            at = self.free.index(WORK_OF_ADHESION)
            starts = [np.concatenate([x[:at], [np.log(self.w0 * f)], x[at + 1:]]) for f in START_FRACTIONS]
        points = self.contact_point_starts() if "contact_point" in self.free_raw else [0.0]
        if len(points) > 1:
            # the medium's first guess was made at the first contact point: scale it too
            at = len(self.free) + self.free_raw.index("contact_point")
            scaled = len(self.medium_free)
            starts = [np.concatenate([s[:scaled] + np.log(f), s[scaled:at], [c], s[at + 1:]])
                      for s in starts for c in points for f in MODULUS_FACTORS]
        return min(starts, key=self._cost)

    def contact_point_starts(self) -> list[float]:
        """Coordinates of the raw curve's contact point to start from: its first guess (where
        the deflection last leaves its baseline before it rises); for a law whose contact jumps
        in, also the sample before the deflection first falls :data:`JUMP_SIGMAS` robust
        standard deviations of the baseline's scatter below it on the approach (the jump in
        precedes the rise)."""
        starts = [0.0]
        raw = self.raw
        if raw is None or not jumps_in(self.given):
            return starts
        top = int(np.argmax(raw.z))
        excess = raw.deflection[:top + 1] - raw.line(raw.contact_point, raw.baseline, raw.slope)[:top + 1]
        count = max(2, (top + 1) // 10)
        sigma = 1.4826 * float(np.median(np.abs(excess[:count] - np.median(excess[:count]))))
        low = np.flatnonzero(excess[count:] < -JUMP_SIGMAS * sigma)
        if low.size and sigma > 0:
            at = count + int(low[0]) - 1
            starts.append((float(raw.z[at]) - raw.contact_point) / raw.depth_scale)
        return starts

    def _cost(self, x: np.ndarray) -> float:
        """Sum of the squared weighted residuals at ``x`` (no Jacobian; infinite out of the
        model's domain)."""
        try:
            self.medium_at(x)
        except InvalidInputError:
            return np.inf
        if self.raw is not None and self.raw.z[0] > self.raw_at(x)[0]:
            return np.inf  # in contact before the first sample
        values, contact = self._forward(x, self._shift(x))
        measured = self.measured if self.raw is None else self.raw.force(*self.raw_at(x))
        if self.n is not None and np.any(contact == self.n):
            return np.inf
        return float(np.sum((self.root_w * (values - measured)) ** 2))

    def medium_at(self, x: np.ndarray) -> _Medium:
        """The medium at coordinates ``x``."""
        values = dict(self.values0)
        values.update({name: float(np.exp(v)) for name, v in zip(self.medium_free, x)})
        return medium_of(self.cls, values, self.nu)

    def contact_parameters(self, x: np.ndarray) -> dict[str, float]:
        """The work of adhesion (J/m^2) at ``x``, by name."""
        if WORK_OF_ADHESION not in self.free:
            return {WORK_OF_ADHESION: self.w0}
        return {WORK_OF_ADHESION: float(np.exp(x[self.free.index(WORK_OF_ADHESION)]))}

    def contact_at(self, x: np.ndarray) -> JKR | DMT:
        """The contact law at ``x``."""
        w = self.contact_parameters(x)[WORK_OF_ADHESION]
        if self.law is DMT:
            return DMT(work_of_adhesion=w)
        return JKR(work_of_adhesion=w, approach=self.approach, stress=self.stress)

    def raw_at(self, x: np.ndarray) -> tuple[float, float, float]:
        """The raw AFM curve's contact point, baseline and slope at ``x``."""
        assert self.raw is not None
        return self.raw.at(x[len(self.free):], self.free_raw)

    def _forward(self, x: np.ndarray, shift: float) -> tuple[np.ndarray, np.ndarray]:
        """Force (N) and elements of the half profile in contact at the samples, at ``x`` with
        the drive moved by ``shift`` (m)."""
        medium = json.dumps(self.medium_at(x)._model())
        w = self.contact_parameters(x)[WORK_OF_ADHESION]
        if self.law is DMT:
            values, _, _, contact = self.curve.evaluate_dmt(medium, 2.0 * np.pi * w * self.radius, shift)
        else:
            values, _, _, contact = self.curve.evaluate_jkr(medium, w, shift, self.approach)
        return values, contact

    def _shift(self, x: np.ndarray) -> float:
        return 0.0 if self.raw is None else self.raw.shift(self.raw_at(x)[0])

    def jacobian(self, x: np.ndarray, values: np.ndarray) -> np.ndarray:
        """d force / d coordinate along the medium's and the work of adhesion's coordinates,
        then (raw AFM curves) along the shift of the drive (N/m), by finite differences;
        ``values`` the force at ``x``."""
        p, shift = len(self.free), self._shift(x)
        columns = []
        for j in range(p + (self.raw is not None)):
            if j < p:
                step = np.zeros_like(x)
                step[j] = STEP
                up, _ = self._forward(x + step, shift)
                down, _ = self._forward(x - step, shift)
                h = STEP
            else:
                h = STEP * self.raw.depth_scale
                up, _ = self._forward(x, shift + h)
                down, _ = self._forward(x, shift - h)
            ahead, behind = (up - values) / h, (values - down) / h
            apart = np.abs(ahead - behind) > DISAGREE * (np.abs(ahead) + np.abs(behind))
            smaller = np.where(np.abs(ahead) < np.abs(behind), ahead, behind)
            columns.append(np.where(apart, smaller, 0.5 * (ahead + behind)))
        return np.column_stack(columns)

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Weighted residuals and their Jacobian at ``x`` (infinite residuals out of the model's
        domain, as :class:`Problem`'s)."""
        try:
            self.medium_at(x)
        except InvalidInputError:
            return self._failed(x)
        raw = self.raw
        if raw is not None:
            z_c, b, m = self.raw_at(x)
            if raw.z[0] > z_c:
                return self._failed(x)  # in contact before the first sample
        values, contact = self._forward(x, self._shift(x))
        jac = self.jacobian(x, values)
        if raw is None:
            r = values - self.measured
        else:
            r = values - raw.force(z_c, b, m)
            jac = raw.jacobian(jac, self.free_raw, z_c, m)
        self.solves += 1
        if (self.n is not None and np.any(contact == self.n)) or not np.all(np.isfinite(jac)):
            return self._failed(x)
        return self.root_w * r, self.root_w[:, None] * jac

    def solution(self, x: np.ndarray):
        """The forward model at ``x``: (medium, force, elements in contact, "jkr" or "dmt");
        one forward solve more."""
        self.solves += 1
        values, contact = self._forward(x, self._shift(x))
        return self.medium_at(x), values, contact, self.law.__name__.lower()
