"""Fits of media to measured indentation curves, with MDR as the forward model.

:func:`fit` takes an indenter, a medium (instance: initial guess; class: guess estimated
from the data), the sample times and the measured depth and force, and returns a
:class:`FitResult`. The forward model is the MDR viscoelastic stepping of the solvers on
the half of the indenter's 1D profile, prepared once (``_core.Curve``); it returns the
curve and its derivatives in the logarithms of the parameters in one pass (forward-mode
differentiation of the steps, exact for the discrete model). Levenberg-Marquardt works in
those logarithms (the parameters are positive); standard errors come from the Jacobian at
the solution and the residual variance.

Levenberg-Marquardt is the package's own (:mod:`mdrvisc._least_squares`, tested): the
problems have a handful of parameters, each evaluation is a full forward solve with its
Jacobian, and a small dense solver needs no run-time dependency beyond numpy.
"""

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
#: control) or of the measured depths (force control: the model's depths may exceed them
#: while the fit searches).
_MARGIN = {"depth": 1.1, "force": 1.5}

#: Samples the initial estimate uses at most (evenly spread over the data).
_ESTIMATE_SAMPLES = 200

#: A parameter whose standard error exceeds this fraction of its value is not identified.
_LARGEST_RELATIVE_ERROR = 0.5

#: Parameters whose correlation exceeds this in magnitude are not separately identified.
_LARGEST_CORRELATION = 0.999


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
    values = {name: v * by if not (name.startswith("tau") or name in ("beta", "t0")) else v
              for name, v in _parameters(medium).items()}
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
    wall_time : float
        Seconds the fit took.
    converged : bool
        Whether Levenberg-Marquardt met a tolerance; ``message`` says which.
    warnings : list of str
        Parameters the data do not identify (also raised as :class:`IdentifiabilityWarning`).
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
                 f"control), rms {self.rms:.3e} {unit}, {self.solves} solves, {self.wall_time:.3f} s",
                 f"  {'parameter':<10}{'value':>14}{'stderr':>14}{'relative':>11}"]
        young = {"E" + name[1:]: name for name in self.parameters if name.startswith("G")}
        rows = [(name, value, self.stderr[name], name) for name, value in self.parameters.items()]
        rows += [(name, value, self.young_stderr[name], young[name])
                 for name, value in self.young_moduli.items()]
        for name, value, err, of in rows:
            rel = "held" if of not in self.free else f"{err / value:.2e}"
            lines.append(f"  {name:<10}{value:>14.6g}{err:>14.3g}{rel:>11}")
        lines.append(f"  {'nu':<10}{self.nu:>14.6g}{'':>14}{'held':>11}")
        if not self.converged:
            lines.append(f"  not converged: {self.message}")
        return "\n".join(lines)


def fit(indenter: Indenter, model: _Medium | type, t: ArrayLike, *, depth: ArrayLike, force: ArrayLike,
        control: str = "depth", weights: ArrayLike | None = None, fixed: tuple[str, ...] = (),
        nu: float | None = None, terms: int = 2, n: int = 500, substeps: int = 1,
        max_iter: int = 100) -> FitResult:
    """Fit a medium to an indentation curve: depth and force sampled at times ``t``.

    Parameters
    ----------
    indenter : Indenter
        The tip (any axisymmetric indenter of :mod:`mdrvisc.geometry` or :mod:`mdrvisc.profiles`).
    model : medium or medium class
        An instance (its values are the initial guess) or a class (the guess is estimated from
        the data: the elastic modulus that best matches the curve, then the best of a few
        relaxation times spread over the data's span).
    t : array_like
        Sample times (s), >= 0, strictly increasing. The body is at rest, unloaded, at t = 0.
    depth, force : array_like
        Indentation depth (m) and force (N) at ``t``.
    control : {"depth", "force"}
        What was prescribed: "depth" (relaxation, AFM force curves: the forces are the
        measurements) or "force" (creep: the depths are). Between samples the prescribed
        quantity varies linearly.
    weights : array_like, optional
        Weights of the squared residuals (>= 0), e.g. 1 / variance.
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
        time with a few samples and low noise.
    n : int
        Elements of the half 1D profile, which reaches 1.1 (depth control) or 1.5 (force
        control) times the largest contact radius of the data.
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
        contact at all, fewer usable samples than free parameters.
    """
    start = time.perf_counter()
    if control not in ("depth", "force"):
        raise InvalidInputError(f'fit: control must be "depth" or "force", got {control!r}')
    if not isinstance(indenter, Indenter):
        raise InvalidInputError(f"fit: indenter must be an mdrvisc indenter, got {indenter!r}")
    n = _integer("fit", "n", n, 8)
    substeps = _integer("fit", "substeps", substeps, 1)
    max_iter = _integer("fit", "max_iter", max_iter, 1)
    t, d, f = _array("t", t), _array("depth", depth), _array("force", force)
    for name, a in (("depth", d), ("force", f)):
        if a.size != t.size:
            raise DataError(f"fit: {name} has {a.size} samples, t has {t.size}")
    _check_times(t)
    w = np.ones_like(t) if weights is None else _array("weights", weights)
    if w.size != t.size:
        raise DataError(f"fit: weights has {w.size} samples, t has {t.size}")
    if np.any(w < 0) or not np.any(w > 0):
        raise DataError("fit: weights must be >= 0 and not all zero")
    prescribed, measured = (d, f) if control == "depth" else (f, d)
    if not np.any(d > 0) or not np.any(f > 0):
        which = "depth" if not np.any(d > 0) else "force"
        raise DataError(f"fit: no contact at all: {which} is <= 0 at every sample")

    # the model: its class, initial guess, free and held parameters
    if isinstance(model, type):
        if fixed:
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
    curve, estimate = _curves(indenter, t, d, prescribed, control, n, substeps)
    span = float(t[-1])
    step = float(np.min(np.diff(np.concatenate([[0.0], t[t > 0]])), initial=span))
    if guess is None:
        guess = _estimate(estimate[0], cls, f[estimate[1]], w[estimate[1]], span, step, terms, nu)
    names = list(_parameters(guess))
    held = set(fixed) | ({"t0"} if cls is PowerLaw else set())
    unknown = sorted(set(fixed) - set(names))
    if unknown:
        raise InvalidInputError(f"fit: fixed names {unknown} are not parameters of {cls.__name__} {names}")
    free = [name for name in names if name not in held]
    values0 = _parameters(guess)
    bad = [name for name in free if not values0[name] > 0]
    if bad:
        raise InvalidInputError(f"fit: parameters {bad} must be > 0 to be fitted in log space (or hold them)")
    usable = int(np.count_nonzero(w > 0))
    if usable < len(free) + 1:
        raise DataError(f"fit: {usable} samples with positive weight for {len(free)} free parameters "
                        f"({free}); a fit needs more samples than parameters")

    scale = float(np.max(np.abs(measured)))
    root_w = np.sqrt(w) / scale
    solves = 0

    def medium_at(x: np.ndarray) -> _Medium:
        values = dict(values0)
        values.update({name: float(v) for name, v in zip(free, np.exp(x))})
        return _medium(cls, values, nu)

    def residuals(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        nonlocal solves
        try:
            medium = medium_at(x)
        except InvalidInputError:
            return np.full(t.size, np.inf), np.zeros((t.size, len(free)))
        values, jac, contact = curve.evaluate([json.dumps(medium._model())], free)[0]
        solves += 1
        if np.any(contact == n):
            return np.full(t.size, np.inf), np.zeros((t.size, len(free)))
        return root_w * (values - measured), root_w[:, None] * jac

    x0 = np.log([values0[name] for name in free])
    solution = levenberg_marquardt(residuals, x0, max_iter=max_iter)
    medium = medium_at(solution.x)
    values, _, contact = curve.evaluate([json.dumps(medium._model())], [])[0]
    if np.any(contact == n):
        raise DomainError("fit: the fitted contact reaches the end of the 1D profile; the data's depths "
                          "are beyond the indenter's footprint")
    r, jac = solution.residuals, solution.jacobian
    dof = usable - len(free)
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
        rename = {f"{p}{old + 1}": f"{p}{new + 1}" for new, old in enumerate(order) for p in ("G", "tau")}
        medium = Prony(medium.G_inf, tuple(medium.terms[k] for k in order), nu=nu)
        parameters = _parameters(medium)
        free = [rename.get(name, name) for name in free]
        stderr = {rename.get(name, name): e for name, e in stderr.items()}
        stderr = {name: stderr[name] for name in parameters}
    young_moduli = medium.young_moduli
    young_stderr = _young(stderr, nu)
    messages = _identifiability(free, log_err, correlation)
    for message in messages:
        warnings.warn(message, IdentifiabilityWarning, stacklevel=2)
    residual = values - measured
    return FitResult(
        medium=medium, parameters=parameters, stderr=stderr, free=free, correlation=correlation,
        nu=nu, young_moduli=young_moduli, young_stderr=young_stderr,
        t=t, data=measured, model=values, residuals=residual,
        rms=float(np.sqrt(np.sum(w * residual**2) / np.sum(w))), control=control, solves=solves + 1,
        iterations=solution.iterations, wall_time=time.perf_counter() - start,
        converged=solution.converged, message=solution.message, warnings=messages)


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


def _curves(indenter, t, depth, prescribed, control, n, substeps):
    """The forward model of the fit (control as given) and a depth-controlled one at the
    measured depths on at most ``_ESTIMATE_SAMPLES`` of the samples (for the initial
    estimate, with their indices), on the half 1D profile of n elements."""
    deepest = float(np.max(depth))
    try:
        a = indenter.contact_radius_at_depth(deepest)
    except DomainError as exc:
        raise DataError(f"fit: the deepest sample ({deepest} m) is beyond the indenter: {exc}") from None
    half = _MARGIN[control] * a
    if indenter.mdr_half_length is not None:
        half = a if indenter.is_flat else min(half, indenter.mdr_half_length)
    dx = half / n
    core = _core.Indenter.from_json(json.dumps(indenter._model(half)))
    profile = core.profile_1d((np.arange(n) + 0.5) * dx)
    curve = _core.Curve(profile, dx, t, prescribed, control, substeps)
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
    for medium, (values, _, _) in zip(candidates, evaluated):
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
