"""Fits of media to measured indentation curves, with MDR as the forward model.

:func:`fit` takes an indenter, a medium (instance: initial guess; class: guess estimated
from the data), the sample times and the measured depth and force, and returns a
:class:`FitResult`. The forward model is the MDR viscoelastic stepping of the solvers on
the half of the indenter's 1D profile, prepared once (``_core.Curve``); it returns the
curve and its derivatives in the logarithms of the parameters in one pass (forward-mode
differentiation of the steps, exact for the discrete model). Levenberg-Marquardt works in
those logarithms (the parameters are positive); standard errors come from the Jacobian at
the solution and the residual variance.

Raw AFM curves (piezo displacement, cantilever deflection, spring constant) are fitted
with the contact point and the deflection baseline as two more parameters: they move
every depth of the history by the same amount, and the forward model's derivative along
such a shift is one more forward-mode tangent (exact for the discrete model as well).

Levenberg-Marquardt is the package's own (:mod:`mdrvisc._least_squares`, tested): the
problems have a handful of parameters, each evaluation is a full forward solve with its
Jacobian, and a small dense solver needs no run-time dependency beyond numpy.
"""

import dataclasses
import json
import math
import time
import warnings

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._least_squares import levenberg_marquardt
from ._validate import _integer, _poisson_ratio
from .errors import DataError, DomainError, IdentifiabilityWarning, InvalidInputError
from .geometry import Indenter
from .media import Elastic, KelvinVoigt, Maxwell, PowerLaw, Prony, StandardSolid, Viscous, _Medium, _young

__all__ = ["fit", "FitResult"]

#: The 1D profile reaches this factor times the largest contact radius of the data (depth
#: control) or of the measured depths (force control, and raw AFM curves at the first guess
#: of the contact point: the model's depths may exceed them while the fit searches).
_MARGIN = {"depth": 1.1, "force": 1.5}

#: Samples the initial estimate uses at most (evenly spread over the data).
_ESTIMATE_SAMPLES = 200

#: A parameter whose standard error exceeds this fraction of its value is not identified.
_LARGEST_RELATIVE_ERROR = 0.5

#: Parameters whose correlation exceeds this in magnitude are not separately identified.
_LARGEST_CORRELATION = 0.999

#: Raw AFM curves: the first fraction of the approach (up to the highest piezo position)
#: that must lie before contact, and the fewest samples it may have.
_BASELINE_FRACTION, _BASELINE_SAMPLES = 0.1, 5

#: Raw AFM curves: the deflection leaves the baseline where it exceeds the baseline's
#: median by this many robust standard deviations of it (the contact point's first guess).
_CONTACT_SIGMAS = 3.0

#: The parameters a raw AFM curve adds to the medium's.
_RAW_NAMES = ("contact_point", "baseline")


def _parameters(medium: _Medium) -> dict[str, float]:
    """The medium's parameters by the names a fit uses (a Prony series: G_inf, G1, tau1, ...);
    the Poisson ratio, held, is not one of them."""
    return medium._parameters()


def _medium(cls: type, values: dict[str, float], nu: float) -> _Medium:
    """The medium of class ``cls`` with the parameters ``values`` (names of :func:`_parameters`)
    and the Poisson ratio ``nu``."""
    if cls is Prony:
        k = (len(values) - 1) // 2
        return Prony(values["G_inf"], tuple((values[f"G{j}"], values[f"tau{j}"]) for j in range(1, k + 1)),
                     nu=nu)
    return cls(**values, nu=nu)


def _guesses(cls: type, span: float, step: float, terms: int, nu: float) -> list[_Medium]:
    """Candidate media of unit modulus scale and Poisson ratio ``nu`` for a fit of class ``cls``
    to data over ``span`` (s) sampled every ``step`` (s) or more: relaxation times log-spaced
    between the two."""
    taus = np.geomspace(max(3.0 * step, 1e-3 * span), 3.0 * span, 9)
    if cls is Elastic:
        return [Elastic(1.0, nu=nu)]
    if cls is Viscous:
        return [Viscous(tau, nu=nu) for tau in taus]
    if cls in (KelvinVoigt, Maxwell):
        return [cls(1.0, tau, nu=nu) for tau in taus]
    if cls is StandardSolid:
        return [StandardSolid(0.5, 0.5, tau, nu=nu) for tau in taus]
    if cls is Prony:
        return [Prony(0.5, tuple((0.5 / terms, tau * 10.0 ** -j) for j in range(terms)), nu=nu)
                for tau in taus]
    if cls is PowerLaw:
        return [PowerLaw(1.0, beta, 1.0, nu=nu) for beta in (0.05, 0.1, 0.2, 0.35, 0.5, 0.7)]
    raise InvalidInputError(f"fit: model must be an mdrvisc medium or medium class, got {cls!r}")


def _scaled(medium: _Medium, by: float) -> _Medium:
    """The medium with every modulus and viscosity multiplied by ``by`` (times and nu kept)."""
    values = _parameters(medium)
    values.update({name: values[name] * by for name in _moduli(values)})
    return _medium(type(medium), values, medium.nu)


def _array(name: str, values: ArrayLike) -> np.ndarray:
    """``values`` as a 1D float64 array, or DataError naming the first entry that is not finite."""
    try:
        a = np.ascontiguousarray(values, dtype=float)
    except (TypeError, ValueError) as exc:
        raise DataError(f"fit: {name} must be an array of real numbers: {exc}") from None
    if a.ndim != 1:
        raise DataError(f"fit: {name} must be one-dimensional, got shape {a.shape}")
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise DataError(f"fit: {name} must be finite, got {a[bad[0]]} at index {bad[0]} "
                        f"({bad.size} such entries)")
    return a


def _check_times(t: np.ndarray) -> None:
    if t.size and t[0] < 0:
        raise DataError(f"fit: times must be >= 0, got t[0] = {t[0]}")
    steps = np.diff(t)
    for problem, bad in (("duplicate", steps == 0), ("unsorted", steps < 0)):
        if np.any(bad):
            k = int(np.flatnonzero(bad)[0])
            raise DataError(f"fit: times must increase strictly; {problem} times: t[{k}] = {t[k]!r}, "
                            f"t[{k + 1}] = {t[k + 1]!r}")


class FitResult:
    """A medium fitted to an indentation curve.

    Attributes
    ----------
    medium : medium
        The fitted medium, an instance of the model's class (usable in a :class:`~mdrvisc.Scene`).
    parameters : dict
        Its parameters by name (Pa, s, Pa s; also attributes of the result: ``result.G1``):
        shear moduli, viscosities and times.
    stderr : dict
        Standard errors of the parameters (same names and units; 0 for held ones), from the
        Jacobian at the solution and the residual variance (first order in the logarithms).
    nu : float
        The Poisson ratio the fit held (the model's).
    young_moduli, young_stderr : dict
        Young's moduli E = 2 (1 + nu) G of the fitted shear moduli and their standard errors
        (Pa; names with G written E: ``E``, ``E_inf``, ``E1``, ``E0``; also attributes of the
        result: ``result.E1``).
    free : list of str
        The fitted parameters, in the order of ``correlation``'s rows.
    correlation : ndarray
        Correlation matrix of the fitted parameters.
    t, data, model, residuals : ndarray
        Sample times (s), the measured values, the fitted model's values and model - data
        (N under depth control, m under force control).
    rms : float
        Root mean square of the (weighted) residuals, in the data's unit.
    solves : int
        Forward solves (each with its derivatives).
    iterations : int
        Levenberg-Marquardt iterations.
    forward : str
        The forward model that ran: "hereditary" (Ting's solution: depth control, a depth
        that rises and then falls, a tip whose MDR profile rises away from its axis) or
        "elements" (the MDR elements stepped one by one; see :func:`fit`'s notes).
    wall_time : float
        Seconds the fit took.
    converged : bool
        Whether Levenberg-Marquardt met a tolerance; ``message`` says which.
    warnings : list of str
        Parameters the data do not identify (also raised as :class:`IdentifiabilityWarning`).
    contact_point, baseline : float
        Raw AFM curves only: the fitted contact point z_c (piezo position, m) and deflection
        baseline b (m); their standard errors are ``stderr["contact_point"]`` and
        ``stderr["baseline"]`` (0 when held), their correlations with the medium's parameters
        in ``correlation``.
    depth : ndarray
        Raw AFM curves only: the indentation (z - z_c) - (deflection - b) at the fitted z_c
        and b (m); ``data`` is then the force k (deflection - b) (N).
    spring_constant : float
        Raw AFM curves only: k (N/m), as given.
    """

    def __init__(self, **values) -> None:
        self.__dict__.update(values)

    def __getattr__(self, name: str) -> float:
        for table in ("parameters", "young_moduli"):
            values = self.__dict__.get(table, {})
            if name in values:
                return values[name]
        raise AttributeError(f"FitResult has no attribute {name!r}")

    def __repr__(self) -> str:
        unit = "N" if self.control == "depth" else "m"
        lines = [f"FitResult: {type(self.medium).__name__} to {self.data.size} samples ({self.control} "
                 f"control), rms {self.rms:.3e} {unit}, {self.solves} solves ({self.forward}), "
                 f"{self.wall_time:.3f} s",
                 f"  {'parameter':<14}{'value':>14}{'stderr':>14}{'relative':>11}"]
        young = {"E" + name[1:]: name for name in self.parameters if name.startswith("G")}
        rows = [(name, value, self.stderr[name], name) for name, value in self.parameters.items()]
        rows += [(name, value, self.young_stderr[name], young[name])
                 for name, value in self.young_moduli.items()]
        for name, value, err, of in rows:
            rel = "held" if of not in self.free else f"{err / value:.2e}"
            lines.append(f"  {name:<14}{value:>14.6g}{err:>14.3g}{rel:>11}")
        lines.append(f"  {'nu':<14}{self.nu:>14.6g}{'':>14}{'held':>11}")
        for name in _RAW_NAMES:
            if name in self.__dict__:
                err = self.stderr[name]
                rel = "held" if name not in self.free else "m"
                lines.append(f"  {name:<14}{self.__dict__[name]:>14.6g}{err:>14.3g}{rel:>11}")
        if not self.converged:
            lines.append(f"  not converged: {self.message}")
        return "\n".join(lines)


def fit(indenter: Indenter, model: _Medium | type, t: ArrayLike, *, depth: ArrayLike | None = None,
        force: ArrayLike | None = None, piezo: ArrayLike | None = None, deflection: ArrayLike | None = None,
        spring_constant: float | None = None, contact_point: float | None = None,
        baseline: float | None = None, control: str = "depth", weights: ArrayLike | None = None,
        fixed: tuple[str, ...] = (), nu: float | None = None, terms: int = 2, n: int = 500,
        substeps: int = 1, max_iter: int = 100) -> FitResult:
    """Fit a medium to an indentation curve: depth and force, or a raw AFM curve, at times ``t``.

    Parameters
    ----------
    indenter : Indenter
        The tip (any axisymmetric indenter of :mod:`mdrvisc.geometry` or :mod:`mdrvisc.profiles`).
    model : medium or medium class
        An instance (its values are the initial guess) or a class (the guess is estimated from
        the data: the elastic modulus that best matches the curve, then the best of a few
        relaxation times spread over the data's span).
    t : array_like
        Sample times (s), strictly increasing; >= 0 with ``depth`` and ``force`` (the body is
        at rest, unloaded, at t = 0); any origin with a raw AFM curve (the body is at rest
        at the first sample, which is before contact).
    depth, force : array_like
        Indentation depth (m) and force (N) at ``t``.
    piezo, deflection, spring_constant : array_like, array_like, float
        A raw AFM curve instead of ``depth`` and ``force``: the piezo displacement z (m),
        increasing towards the sample; the cantilever deflection (m), positive when the
        sample pushes the tip back (repulsion); the cantilever's spring constant k (N/m).
        The model is the cantilever in series with the sample: the piezo's travel past the
        contact point, z - z_c, drives the tip through the spring k, and the model's force
        k (z - z_c - indentation) is fitted to the measured one, k (deflection - b), so the
        deflection's noise stays in the data and does not enter the indentation. The
        contact point z_c and the deflection baseline b are fitted together with the medium
        (before contact the model's force is zero, so the baseline is fitted to the
        pre-contact deflection; it is a constant: remove a tilt or virtual deflection
        first). Depth control only; no adhesion is modelled (give adhesive parts of a
        retract zero weight). The first tenth of the approach (the samples up to the
        highest z, at least 5) must be before contact.
    contact_point, baseline : float, optional
        Raw AFM curves: initial guesses of z_c and b (m). Without them, b is the median of
        the deflection over the first tenth of the approach and z_c the piezo position
        where the deflection last rises above b by 3 robust standard deviations of that
        part (the median absolute deviation times 1.4826) before the deepest point.
        ``fixed=("contact_point",)`` or ``("baseline",)`` holds them.
    control : {"depth", "force"}
        What was prescribed: "depth" (relaxation, AFM force curves: the forces are the
        measurements) or "force" (creep: the depths are). Between samples the prescribed
        quantity varies linearly.
    weights : array_like, optional
        Weights of the squared residuals (>= 0, not all zero), e.g. 1 / variance; samples of
        weight zero are left out of the fit and of the count of usable samples.
    fixed : tuple of str
        Names of parameters held at the model's values (needs an instance). A
        :class:`PowerLaw`'s reference time ``t0`` is always held: only G0 t0^beta enters G(t).
    nu : float, optional
        Poisson ratio of a class ``model`` (default 0.5), -1 < nu <= 0.5; an instance brings its
        own (give it there). Always held, never fitted: the curve fixes the contact modulus
        2 G(t) / (1 - nu) only, so the fitted shear moduli scale with 1 - nu.
    terms : int
        Prony terms when ``model`` is the :class:`Prony` class. Terms whose relaxation times
        lie within a factor of a few of each other, or outside the data's span, are not
        identified (:class:`IdentifiabilityWarning`): k >= 2 needs data that cover every
        time with a few samples and low noise; a quick ramp and a long hold (relaxation)
        separates the times far better than an approach and retract at one speed.
    n : int
        Elements of the half 1D profile, which reaches 1.1 (depth control) or 1.5 (force
        control, raw AFM curves) times the largest contact radius of the data.
    substeps : int
        Time steps per sample interval (the stepping's error falls as substeps^-2 while the
        contact grows).
    max_iter : int
        Most Levenberg-Marquardt iterations.

    Returns
    -------
    FitResult

    Raises
    ------
    DataError
        Data not finite, times not strictly increasing, arrays of different lengths, no
        contact at all, fewer usable samples than free parameters; a raw AFM curve whose
        deflection never leaves its baseline or that has no contact-free start.

    Notes
    -----
    The forward model is MDR. Under depth control, with a depth that rises and then falls
    (approach, hold, retract: a single maximum) and a tip whose MDR profile rises away from
    its axis, it is Ting's solution: the elements' forces integrated over the contact in
    closed form, so the cost does not grow with ``n`` (which then samples the profile's
    area function, error ~(dx / a)^2) and a 2,000-sample curve takes about a millisecond.
    Otherwise (force control, raw AFM curves, several load cycles, a depth that wiggles)
    the n elements are stepped one by one, each with its own history (contact-edge error
    ~dx / a). Ting's solution assumes, as his paper does,
    that a contact that has let go on retraction does not touch again while the depth
    falls.
    """
    start = time.perf_counter()
    if control not in ("depth", "force"):
        raise InvalidInputError(f'fit: control must be "depth" or "force", got {control!r}')
    if not isinstance(indenter, Indenter):
        raise InvalidInputError(f"fit: indenter must be an mdrvisc indenter, got {indenter!r}")
    n = _integer("fit", "n", n, 8)
    substeps = _integer("fit", "substeps", substeps, 1)
    max_iter = _integer("fit", "max_iter", max_iter, 1)
    raw = _raw_input(depth, force, piezo, deflection, spring_constant, control)
    t = _array("t", t)
    if raw is None:
        d, f = _array("depth", depth), _array("force", force)
        for name, a in (("depth", d), ("force", f)):
            if a.size != t.size:
                raise DataError(f"fit: {name} has {a.size} samples, t has {t.size}")
        _check_times(t)
        if not np.any(d > 0) or not np.any(f > 0):
            which = "depth" if not np.any(d > 0) else "force"
            raise DataError(f"fit: no contact at all: {which} is <= 0 at every sample")
    else:
        for name, a in zip(("piezo", "deflection"), raw[:2]):
            if a.size != t.size:
                raise DataError(f"fit: {name} has {a.size} samples, t has {t.size}")
        if t.size:
            t = t - t[0]
        _check_times(t)
        raw = _AfmCurve.estimate(*raw, contact_point, baseline)
        d, f = raw.depth(raw.contact_point, raw.baseline), raw.force(raw.baseline)
    w = np.ones_like(t) if weights is None else _array("weights", weights)
    if w.size != t.size:
        raise DataError(f"fit: weights has {w.size} samples, t has {t.size}")
    if np.any(w < 0) or not np.any(w > 0):
        raise DataError("fit: weights must be >= 0 and not all zero")
    prescribed, measured = (d, f) if control == "depth" else (f, d)
    if raw is not None:
        prescribed = raw.z - raw.contact_point  # the drive past the contact point's guess

    # the model: its class, initial guess, free and held parameters
    if isinstance(model, type):
        if set(fixed) - set(_RAW_NAMES):
            raise InvalidInputError("fit: fixed parameters need a medium instance (their values)")
        cls, guess = model, None
        nu = 0.5 if nu is None else _poisson_ratio("fit", nu)
    elif isinstance(model, _Medium):
        if nu is not None:
            raise InvalidInputError(f"fit: nu is given with a medium instance, which has its own "
                                    f"(nu={model.nu!r}): give it to the medium")
        cls, guess, nu = type(model), model, model.nu
    else:
        raise InvalidInputError(f"fit: model must be an mdrvisc medium or medium class, got {model!r}")
    if cls is Prony and guess is None:
        terms = _integer("fit", "terms", terms, 1)

    # the forward model on the half profile, prepared once
    margin = "force" if raw is not None else control
    curve, estimate = _curves(indenter, t, d, prescribed, "spring" if raw is not None else control, margin, n,
                              substeps, raw.k if raw is not None else None)
    span = float(t[-1])
    step = float(np.min(np.diff(np.concatenate([[0.0], t[t > 0]])), initial=span))
    if guess is None:
        guess = _estimate(estimate[0], cls, f[estimate[1]], w[estimate[1]], span, step, terms, nu)
    names = list(_parameters(guess))
    held = set(fixed) | ({"t0"} if cls is PowerLaw else set())
    unknown = sorted(set(fixed) - set(names) - (set(_RAW_NAMES) if raw is not None else set()))
    if unknown:
        raise InvalidInputError(f"fit: fixed names {unknown} are not parameters of {cls.__name__} {names}")
    free = [name for name in names if name not in held]
    values0 = _parameters(guess)
    bad = [name for name in free if not values0[name] > 0]
    if bad:
        raise InvalidInputError(f"fit: parameters {bad} must be > 0 to be fitted in log space (or hold them)")
    free_raw = [name for name in _RAW_NAMES if raw is not None and name not in held]
    usable = int(np.count_nonzero(w > 0))
    if usable < len(free) + len(free_raw) + 1:
        raise DataError(f"fit: {usable} samples with positive weight for {len(free) + len(free_raw)} free "
                        f"parameters ({free + free_raw}); a fit needs more samples than parameters")

    scale = float(np.max(np.abs(measured)))
    root_w = np.sqrt(w) / scale
    solves = 0
    p = len(free)

    def medium_at(x: np.ndarray) -> _Medium:
        values = dict(values0)
        values.update({name: float(v) for name, v in zip(free, np.exp(x[:p]))})
        return _medium(cls, values, nu)

    def failed() -> tuple[np.ndarray, np.ndarray]:
        return np.full(t.size, np.inf), np.zeros((t.size, x0.size))

    def residuals(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal solves
        try:
            medium = medium_at(x)
        except InvalidInputError:
            return failed()
        media = [json.dumps(medium._model())]
        if raw is None:
            values, jac, contact, _ = curve.evaluate(media, asked)[0]
            r = values - measured
        else:
            z_c, b = raw.at(x[p:], free_raw)
            if raw.z[0] > z_c:
                return failed()  # in contact before the first sample
            values, jac, contact, _ = curve.evaluate(media, asked, raw.shift(z_c))[0]
            r = values - raw.force(b)
        jac = _with_derived(values, jac, free, asked)
        if raw is not None:
            jac = raw.jacobian(jac, free_raw)
        solves += 1
        if np.any(contact == n):
            return failed()
        return root_w * r, root_w[:, None] * jac

    # under depth control the force is proportional to the moduli together (Pa, Pa s; the
    # contact set depends on their ratios only): the derivatives in their logarithms add up
    # to the force, so one of them follows from the others and the forward model is asked
    # for one tangent fewer
    asked = free
    if control == "depth" and set(_moduli(values0)) <= set(free):
        asked = [name for name in free if name != _moduli(values0)[0]]
    x0 = np.concatenate([np.log([values0[name] for name in free]), np.zeros(len(free_raw))])
    solution = levenberg_marquardt(residuals, x0, max_iter=max_iter)
    medium = medium_at(solution.x)
    media = [json.dumps(medium._model())]
    if raw is None:
        values, _, contact, forward = curve.evaluate(media, [])[0]
    else:
        z_c, b = raw.at(solution.x[p:], free_raw)
        values, _, contact, forward = curve.evaluate(media, [], raw.shift(z_c))[0]
        d, measured = raw.depth(z_c, b), raw.force(b)
        before = int(np.count_nonzero(d[:int(np.argmax(raw.z)) + 1] <= 0))
        if before < _BASELINE_SAMPLES:
            raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): at the "
                            f"fitted contact point ({z_c:.6g} m) {before} samples of the approach are before "
                            f"contact, fewer than {_BASELINE_SAMPLES}")
    if np.any(contact == n):
        raise DomainError("fit: the fitted contact reaches the end of the 1D profile; the data's depths "
                          "are beyond the indenter's footprint")
    r, jac = solution.residuals, solution.jacobian
    dof = usable - len(free) - len(free_raw)
    variance = float(r @ r) / dof
    covariance = variance * np.linalg.pinv(jac.T @ jac)
    log_err = np.sqrt(np.maximum(np.diag(covariance), 0.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        correlation = covariance / np.outer(log_err, log_err)
    parameters = _parameters(medium)
    stderr = {name: 0.0 for name in parameters}
    for name, e in zip(free, log_err):
        stderr[name] = parameters[name] * float(e)
    if cls is Prony:
        # terms in increasing relaxation time: a fit finds them in any order
        order = sorted(range(len(medium.terms)), key=lambda k: medium.terms[k][1])
        rename = {f"{prefix}{old + 1}": f"{prefix}{new + 1}" for new, old in enumerate(order)
                  for prefix in ("G", "tau")}
        medium = Prony(medium.G_inf, tuple(medium.terms[k] for k in order), nu=nu)
        parameters = _parameters(medium)
        free = [rename.get(name, name) for name in free]
        stderr = {rename.get(name, name): e for name, e in stderr.items()}
        stderr = {name: stderr[name] for name in parameters}
    young_moduli = medium.young_moduli
    young_stderr = _young(stderr, nu)
    afm = {}
    if raw is not None:
        afm = {"contact_point": z_c, "baseline": b, "spring_constant": raw.k, "depth": d}
        for name, e in zip(_RAW_NAMES, raw.scales()):
            stderr[name] = float(log_err[p + free_raw.index(name)]) * e if name in free_raw else 0.0
    # the raw curve's parameters are judged in their scales (the largest depth, the
    # deflection's range), the medium's relative to their values
    messages = _identifiability(free + free_raw, log_err, correlation)
    for message in messages:
        warnings.warn(message, IdentifiabilityWarning, stacklevel=2)
    residual = values - measured
    return FitResult(
        medium=medium, parameters=parameters, stderr=stderr, free=free + free_raw, correlation=correlation,
        nu=nu, young_moduli=young_moduli, young_stderr=young_stderr,
        t=t, data=measured, model=values, residuals=residual,
        rms=float(np.sqrt(np.sum(w * residual**2) / np.sum(w))), control=control, solves=solves + 1,
        iterations=solution.iterations, forward=forward, wall_time=time.perf_counter() - start,
        converged=solution.converged, message=solution.message, warnings=messages, **afm)


def _moduli(values: dict[str, float]) -> list[str]:
    """The names among a medium's parameters that are moduli or viscosities (Pa, Pa s): its
    relaxation function is proportional to them together."""
    return [name for name in values if not (name.startswith("tau") or name in ("beta", "t0"))]


def _with_derived(values: np.ndarray, jac: np.ndarray, free: list[str], asked: list[str]) -> np.ndarray:
    """The Jacobian in ``free``'s order from the columns of ``asked`` (and any further
    columns after them, kept last), the one free name not asked for being a modulus whose
    column is the force minus the other moduli's (Euler: the force is homogeneous of degree
    one in the moduli)."""
    if asked == free:
        return jac
    (derived,) = set(free) - set(asked)
    others = [asked.index(name) for name in _moduli(dict.fromkeys(free)) if name != derived]
    column = values - jac[:, others].sum(axis=1)
    at = free.index(derived)
    return np.column_stack([jac[:, :at], column, jac[:, at:]])


def _raw_input(depth, force, piezo, deflection, spring_constant, control):
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
    k = float(spring_constant)
    if not (math.isfinite(k) and k > 0):
        raise InvalidInputError(f"fit: spring_constant must be > 0 (N/m), got {spring_constant!r}")
    return _array("piezo", piezo), _array("deflection", deflection), k


@dataclasses.dataclass
class _AfmCurve:
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
        count = max(_BASELINE_SAMPLES, int(round(_BASELINE_FRACTION * (top + 1))))
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
        b = median if baseline is None else float(baseline)
        above = deflection[:top + 1] - b > _CONTACT_SIGMAS * sigma
        if not np.any(above[count:]):
            raise DataError(f"fit: a raw AFM curve never reaches contact: the deflection never exceeds the "
                            f"baseline ({b:.6g} m) by {_CONTACT_SIGMAS:g} times its scatter ({sigma:.3g} m)")
        deepest = int(np.argmax(deflection[:top + 1]))
        below = np.flatnonzero(~above[:deepest + 1])
        first = int(below[-1]) if below.size else 0
        z_c = float(z[first]) if contact_point is None else float(contact_point)
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
            values[name] += float(u) * dict(zip(_RAW_NAMES, self.scales()))[name]
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


def _identifiability(free: list[str], log_err: np.ndarray, correlation: np.ndarray) -> list[str]:
    """Messages naming the parameters the data do not determine."""
    out = []
    for name, e in zip(free, log_err):
        if not e <= _LARGEST_RELATIVE_ERROR:
            out.append(f"fit: {name} is not identified by the data: its relative standard error is {e:.3g}")
    for i, j in zip(*np.triu_indices(len(free), 1)):
        if abs(correlation[i, j]) > _LARGEST_CORRELATION:
            out.append(f"fit: {free[i]} and {free[j]} are not separately identified: correlation "
                       f"{correlation[i, j]:+.5f}")
    return out


def _curves(indenter, t, depth, prescribed, control, margin, n, substeps, stiffness=None):
    """The forward model of the fit (control as given; "spring" with ``stiffness``) and a
    depth-controlled one at the measured depths on at most ``_ESTIMATE_SAMPLES`` of the
    samples (for the initial estimate, with their indices), on the half 1D profile of n
    elements reaching ``_MARGIN[margin]`` times the largest contact radius of the depths."""
    deepest = float(np.max(depth))
    try:
        a = indenter.contact_radius_at_depth(deepest)
    except DomainError as exc:
        raise DataError(f"fit: the deepest sample ({deepest} m) is beyond the indenter: {exc}") from None
    half = _MARGIN[margin] * a
    if indenter.mdr_half_length is not None:
        half = a if indenter.is_flat else min(half, indenter.mdr_half_length)
    dx = half / n
    core = _core.Indenter.from_json(json.dumps(indenter._model(half)))
    profile = core.profile_1d((np.arange(n) + 0.5) * dx)
    curve = _core.Curve(profile, dx, t, prescribed, control, substeps, stiffness)
    some = np.unique(np.linspace(0, t.size - 1, min(t.size, _ESTIMATE_SAMPLES)).round().astype(int))
    return curve, (_core.Curve(profile, dx, t[some], depth[some], "depth", 1), some)


def _estimate(curve, cls, force, w, span, step, terms, nu):
    """The initial guess of class ``cls`` and Poisson ratio ``nu``: among candidates of unit
    modulus scale with
    relaxation times over the data's span, the one whose best modulus scale (a linear
    least-squares factor: forces scale with the moduli at given depths) matches the forces
    best, so scaled."""
    candidates = _guesses(cls, span, step, terms, nu)
    evaluated = curve.evaluate([json.dumps(m._model()) for m in candidates], [])
    best, best_cost = None, math.inf
    for medium, (values, _, _, _) in zip(candidates, evaluated):
        norm = float(np.sum(w * values * values))
        if not norm > 0:
            continue
        factor = float(np.sum(w * values * force)) / norm
        cost = float(np.sum(w * (factor * values - force) ** 2))
        if factor > 0 and cost < best_cost:
            best, best_cost = _scaled(medium, factor), cost
    if best is None:
        raise DataError("fit: no initial guess matches the data: the forces do not grow with the depths")
    return best
