"""The model a fit adjusts: a medium's parameters by name, the MDR forward model on the
indenter's half 1D profile (``_core.Curve``, prepared once) and the least-squares problem
Levenberg-Marquardt solves (:class:`Problem`).

The forward model returns the curve and its derivatives in the logarithms of the parameters
in one pass (forward-mode differentiation of the steps, exact for the discrete model);
Levenberg-Marquardt works in those logarithms (the parameters are positive), and in the
scaled contact point and baseline of a raw AFM curve (:mod:`mdrvisc._afm_raw`).
"""

import json

import numpy as np

from . import _core
from ._afm_raw import AfmCurve
from .errors import DataError, DomainError, InvalidInputError
from .geometry import Indenter
from .media import _Medium

#: The 1D profile reaches this factor times the largest contact radius of the data (depth
#: control) or of the measured depths (force control, and raw AFM curves at the first guess
#: of the contact point: the model's depths may exceed them while the fit searches).
#: A JKR contact loaded in equilibrium ("adhesive") outgrows the hard contact of its depth (by
#: 1.4 times at a depth of 2.5 times JKR's at zero load).
MARGIN = {"depth": 1.1, "force": 1.5, "adhesive": 2.5}

#: Samples the initial estimate uses at most (evenly spread over the data).
ESTIMATE_SAMPLES = 200


def parameters(medium: _Medium) -> dict[str, float]:
    """The medium's parameters by the names a fit uses (a Prony series: G_inf, G1, tau1, ...);
    the Poisson ratio, held, is not one of them."""
    return medium._parameters()


def medium_of(cls: type, values: dict[str, float], nu: float) -> _Medium:
    """The medium of class ``cls`` with the parameters ``values`` (names of :func:`parameters`)
    and the Poisson ratio ``nu``."""
    return cls._from_parameters(values, nu)


def moduli(values: dict[str, float]) -> list[str]:
    """The names among a medium's parameters that are moduli or viscosities (Pa, Pa s): its
    relaxation function is proportional to them together."""
    return [name for name in values if not (name.startswith("tau") or name in ("beta", "t0"))]


def with_derived(values: np.ndarray, jac: np.ndarray, free: list[str], asked: list[str]) -> np.ndarray:
    """The Jacobian in ``free``'s order from the columns of ``asked`` (and any further
    columns after them, kept last), the one free name not asked for being a modulus whose
    column is the force minus the other moduli's (Euler: the force is homogeneous of degree
    one in the moduli)."""
    if asked == free:
        return jac
    (derived,) = set(free) - set(asked)
    others = [asked.index(name) for name in moduli(dict.fromkeys(free)) if name != derived]
    column = values - jac[:, others].sum(axis=1)
    at = free.index(derived)
    return np.column_stack([jac[:, :at], column, jac[:, at:]])


#: Contact radius, in thicknesses, that MDR on a layer reaches (its punch table's).
LAYER_REACH = 8.0


def curves(indenter: Indenter, t: np.ndarray, depth: np.ndarray, prescribed: np.ndarray, control: str,
           margin: str, n: int, substeps: int, stiffness: float | None = None, layer=None, nu: float = 0.5):
    """The forward model of the fit (control as given; "spring" with ``stiffness``) and a
    depth-controlled one at the measured depths on at most :data:`ESTIMATE_SAMPLES` of the
    samples (for the initial estimate, with their indices), on the half 1D profile of n
    elements reaching ``MARGIN[margin]`` times the largest contact radius of the depths; on
    a ``layer`` (Poisson ratio ``nu``) twice that (a layer's contact is wider at a depth),
    up to 8 thicknesses, as the half-space-equivalent profile."""
    deepest = float(np.max(depth))
    try:
        a = indenter.contact_radius_at_depth(deepest)
    except DomainError as exc:
        raise DataError(f"fit: the deepest sample ({deepest} m) is beyond the indenter: {exc}") from None
    half = MARGIN[margin] * a
    if indenter.mdr_half_length is not None:
        half = a if indenter.is_flat else min(half, indenter.mdr_half_length)
    dx = half / n
    core = _core.Indenter.from_json(json.dumps(indenter._model(half)))
    if layer is None:
        profile = core.profile_1d((np.arange(n) + 0.5) * dx)
    else:
        half = min(2.0 * half, LAYER_REACH * layer.thickness) if not indenter.is_flat else half
        profile, dx = core.layer_profile_1d(half, n, layer.thickness, layer.base, nu)
        if profile[-1] <= deepest:
            raise DataError(f"fit: the contact at the deepest sample ({deepest} m) is wider than "
                            f"{LAYER_REACH} thicknesses of the layer ({layer.thickness} m), "
                            "the reach of MDR on a layer")
    curve = _core.Curve(profile, dx, t, prescribed, control, substeps, stiffness)
    some = np.unique(np.linspace(0, t.size - 1, min(t.size, ESTIMATE_SAMPLES)).round().astype(int))
    return curve, (_core.Curve(profile, dx, t[some], depth[some], "depth", 1), some)


class Problem:
    """The least-squares problem of a fit: weighted residuals of the forward model against the
    measurements, and their Jacobian, at coordinates ``x``: the logarithms of the ``free``
    parameters of the medium, then the scaled coordinates of the raw AFM curve's free
    ``free_raw`` (its contact point and baseline).

    ``curve`` is the forward model, ``cls``, ``values0`` and ``nu`` the medium's class, its
    initial parameters (held ones keep these values) and its Poisson ratio; ``measured`` the
    data (N under depth control, m under force control; a raw curve's force follows its
    baseline), weighted by ``root_w``; ``asked`` the tangents the forward model computes (one
    modulus fewer than ``free`` under depth control, see :func:`with_derived`); ``n`` the
    profile's elements (a contact that reaches the last one fails), None for a flat punch
    (its profile is its footprint, all in contact). Calling it counts the
    forward solves in ``solves``; it keeps the last solve's model curve, so that
    :meth:`solution` at the point last evaluated solves nothing.
    """

    def __init__(self, curve, cls: type, values0: dict[str, float], nu: float, free: list[str],
                 asked: list[str], raw: AfmCurve | None, free_raw: list[str], measured: np.ndarray,
                 root_w: np.ndarray, n: int | None) -> None:
        self.curve, self.cls, self.values0, self.nu = curve, cls, values0, nu
        self.free, self.asked, self.raw, self.free_raw = free, asked, raw, free_raw
        self.measured, self.root_w, self.n = measured, root_w, n
        self.solves = 0
        self._last: tuple | None = None

    def x0(self) -> np.ndarray:
        """The initial coordinates."""
        logs = np.log([self.values0[name] for name in self.free])
        return np.concatenate([logs, np.zeros(len(self.free_raw))])

    def medium_at(self, x: np.ndarray) -> _Medium:
        """The medium at coordinates ``x``."""
        values = dict(self.values0)
        values.update({name: float(v) for name, v in zip(self.free, np.exp(x[:len(self.free)]))})
        return medium_of(self.cls, values, self.nu)

    def raw_at(self, x: np.ndarray) -> tuple[float, float, float]:
        """The raw AFM curve's contact point z_c, baseline b (m) and baseline slope m (m/m, 0
        without a tilt) at coordinates ``x``."""
        assert self.raw is not None
        return self.raw.at(x[len(self.free):], self.free_raw)

    def contact_parameters(self, x: np.ndarray) -> dict[str, float]:
        """The contact law's fitted parameters at ``x``, by name (none: hard contact)."""
        return {}

    def contact_at(self, x: np.ndarray):
        """The contact law at ``x`` (None: hard contact)."""
        return None

    def _failed(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return np.full(self.measured.size, np.inf), np.zeros((self.measured.size, x.size))

    def __call__(self, x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Weighted residuals and their Jacobian at ``x``; infinite residuals where the model
        is out of its domain (a medium the parameters do not make, contact before the first
        sample, a contact that reaches the profile's end)."""
        try:
            medium = self.medium_at(x)
        except InvalidInputError:
            return self._failed(x)
        media = [json.dumps(medium._model())]
        raw = self.raw
        if raw is None:
            values, jac, contact, forward = self.curve.evaluate(media, self.asked)[0]
            r = values - self.measured
        else:
            z_c, b, m = self.raw_at(x)
            if raw.z[0] > z_c:
                return self._failed(x)  # in contact before the first sample
            values, jac, contact, forward = self.curve.evaluate(media, self.asked, raw.shift(z_c))[0]
            r = values - raw.force(z_c, b, m)
        self._last = (x.copy(), medium, values, contact, forward)
        jac = with_derived(values, jac, self.free, self.asked)
        if raw is not None:
            jac = raw.jacobian(jac, self.free_raw, z_c, m)
        self.solves += 1
        if (self.n is not None and np.any(contact == self.n)) or not np.all(np.isfinite(jac)):
            return self._failed(x)
        return self.root_w * r, self.root_w[:, None] * jac

    def solution(self, x: np.ndarray):
        """The forward model at ``x``, without derivatives: (medium, values, contact, forward
        model's name); the last solve's where it was at ``x``, else one forward solve more."""
        if self._last is not None and np.array_equal(self._last[0], x):
            return self._last[1:]
        self.solves += 1
        medium = self.medium_at(x)
        media = [json.dumps(medium._model())]
        if self.raw is None:
            values, _, contact, forward = self.curve.evaluate(media, [])[0]
        else:
            values, _, contact, forward = self.curve.evaluate(media, [], self.raw.shift(self.raw_at(x)[0]))[0]
        return medium, values, contact, forward
