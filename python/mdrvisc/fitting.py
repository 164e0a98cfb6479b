"""Fits of media to measured indentation curves, with MDR as the forward model.

:func:`fit` takes an indenter, a medium (instance: initial guess; class: guess estimated
from the data), the sample times and the measured depth and force (or a raw AFM curve), and
returns a :class:`FitResult`, whose names follow scipy's ``OptimizeResult`` where the
concept is the same (``success``, ``status``, ``message``, ``nfev``, ``nit``, ``cost``,
``jac``). The fitted values are ``result.parameters`` (by name) and ``result.medium`` (a
medium ready for a :class:`~mdrvisc.Scene`).

The parts of a fit, each in its module: the model it adjusts (parameters by name, the MDR
forward model, the least-squares problem: :mod:`mdrvisc._fit_model`), the initial guess of a
medium class (:mod:`mdrvisc._guesses`), raw AFM curves (contact point, baseline, spring:
:mod:`mdrvisc._afm_raw`), checks of the data and of what the data identify
(:mod:`mdrvisc._fit_checks`), and Levenberg-Marquardt (:mod:`mdrvisc._least_squares`, the
package's own: the problems have a handful of parameters, each evaluation is a full forward
solve with its Jacobian, and a small dense solver needs no run-time dependency beyond
numpy). Standard errors come from the Jacobian at the solution and the residual variance.
"""

import dataclasses
import time
import warnings

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._afm_raw import BASELINE_SAMPLES, BASELINES, RAW_NAMES, AfmCurve, raw_input
from ._fit_adhesion import WORK_OF_ADHESION, AdhesiveProblem, check_contact, reach_margin, tip_radius
from ._fit_checks import array, check_times, covariance, identifiability
from ._fit_layer import fit_thickness as _fit_thickness
from ._fit_model import Problem, curves, moduli, parameters
from ._guesses import estimate
from ._least_squares import Solution, levenberg_marquardt
from ._validate import _integer, _poisson_ratio
from .body import Layer
from .contact import ContactLaw
from .errors import DataError, DomainError, IdentifiabilityWarning, InvalidInputError
from .geometry import Indenter
from .media import PowerLaw, Prony, _Medium, _young

#: Residuals (weighted, in the data's unit) below this fraction of the weighted data's norm
#: are the forward model's round-off: a fit that reaches them is at its minimum.
ROUND_OFF_RESIDUALS = 1e-11

__all__ = ["fit", "FitResult"]


#: Most Prony terms a fit estimates its start for (relaxation times a decade apart).
DECADES = 30


@dataclasses.dataclass(eq=False)
class FitResult:
    """A medium fitted to an indentation curve.

    The fitted values: ``result.parameters["G1"]`` (by name) or ``result.medium.G1`` (the
    medium); Young's moduli ``result.young_moduli["E1"]``. How the fit ended, by scipy's
    ``OptimizeResult`` names: ``success``, ``status``, ``message``, ``nfev``, ``nit``,
    ``cost``, ``jac``.

    Attributes
    ----------
    medium : medium
        The fitted medium, an instance of the model's class (usable in a :class:`~mdrvisc.Scene`).
    parameters : dict
        Its parameters by name (Pa, s, Pa s): shear moduli, viscosities and times.
    stderr : dict
        Standard errors of the parameters (same names and units; 0 for held ones), from the
        Jacobian at the solution (in the parameters themselves, its singular value
        decomposition with unit-norm columns) and the residual variance; inf for parameters
        the data do not determine (a rank-deficient Jacobian, with an
        :class:`IdentifiabilityWarning`); a raw AFM curve's also of ``contact_point``,
        ``baseline`` (m) and ``baseline_slope``.
    nu : float
        The Poisson ratio the fit held (the model's).
    young_moduli, young_stderr : dict
        Young's moduli E = 2 (1 + nu) G of the fitted shear moduli and their standard errors
        (Pa; names with G written E: ``E``, ``E_inf``, ``E1``, ``E0``).
    free : list of str
        The fitted parameters, in the order of ``correlation``'s rows and ``jac``'s columns.
    correlation : ndarray
        Correlation matrix of the fitted parameters: symmetric, entries in [-1, 1], ones on
        the diagonal, NaN in the rows and columns of undetermined parameters.
    t, data, model, residuals : ndarray
        Sample times (s), the measured values, the fitted model's values and model - data
        (N under depth control, m under force control).
    rms : float
        Root mean square of the (weighted) residuals, in the data's unit.
    cost : float
        Half the weighted sum of squared residuals at the solution, 0.5 sum(w (model -
        data)^2) (N^2 or m^2), the value the fit minimised.
    jac : ndarray
        Jacobian of the weighted residuals sqrt(w) (model - data) at the solution with respect
        to the ``free`` parameters (one row per sample, one column per parameter: N or m per
        Pa, s, Pa s, or m).
    success : bool
        Whether the fit stopped at a minimum (``status`` > 0; see :func:`fit`'s notes).
    status : int
        Why it stopped, successes > 0 and failures <= 0 as in
        :func:`scipy.optimize.least_squares`: 1 stationary (the relative offset test), 2 a
        minimum to round-off, 3 a minimum at a kink of the discrete model; 0 the iteration
        limit (``max_iter``), -2 no step lowers the cost at a point that is not stationary.
    message : str
        The same in words.
    nfev : int
        Forward solves (each with its derivatives, so also the Jacobian's evaluations).
    nit : int
        Levenberg-Marquardt iterations.
    control : str
        "depth" or "force": what was prescribed.
    forward : str
        The forward model that ran: "hereditary" (Ting's solution: a depth that rises and
        then falls, under depth control or through a raw curve's cantilever, and a tip whose
        MDR profile rises away from its axis) or
        "elements" (the MDR elements stepped one by one; see :func:`fit`'s notes); "jkr" or
        "dmt" for an adhesive fit (``contact``).
    wall_time : float
        Seconds the fit took.
    warnings : list of str
        Parameters the data do not identify (also raised as :class:`IdentifiabilityWarning`).
    contact_point, baseline : float or None
        Raw AFM curves only: the fitted contact point z_c (piezo position, m) and deflection
        baseline b (m; with a tilt, the baseline's value at z_c); their standard errors are
        ``stderr["contact_point"]`` and ``stderr["baseline"]`` (0 when held), their
        correlations with the medium's parameters in ``correlation``.
    depth : ndarray or None
        Raw AFM curves only: the indentation (z - z_c) - (deflection - baseline) at the
        fitted z_c and baseline (m); ``data`` is then the force k (deflection - baseline) (N).
    spring_constant : float or None
        Raw AFM curves only: k (N/m), as given.
    baseline_slope : float or None
        Raw AFM curves with ``baseline_model="tilt"`` only: the baseline's slope m along the
        piezo (m/m): the baseline is b + m (z - z_c).
    contact : ContactLaw or None
        Adhesive fits only (``contact=mv.JKR(...)``): the fitted law; its work of adhesion
        (J/m^2) is also ``parameters["work_of_adhesion"]``, with its standard error in
        ``stderr``.
    body : Layer or None
        Fits on a layer (``body=``) only: the layer, with the fitted thickness (m) under
        ``fit_thickness=True``; its standard error is ``stderr["thickness"]`` (0 when held),
        its correlations with the medium's parameters in ``correlation`` (row "thickness" of
        ``free``).
    """

    medium: _Medium
    parameters: dict[str, float]
    stderr: dict[str, float]
    nu: float
    young_moduli: dict[str, float]
    young_stderr: dict[str, float]
    free: list[str]
    correlation: np.ndarray
    t: np.ndarray
    data: np.ndarray
    model: np.ndarray
    residuals: np.ndarray
    rms: float
    cost: float
    jac: np.ndarray
    success: bool
    status: int
    message: str
    nfev: int
    nit: int
    control: str
    forward: str
    wall_time: float
    warnings: list[str]
    contact_point: float | None = None
    baseline: float | None = None
    depth: np.ndarray | None = None
    spring_constant: float | None = None
    baseline_slope: float | None = None
    contact: ContactLaw | None = None
    body: Layer | None = None

    def __repr__(self) -> str:
        unit = "N" if self.control == "depth" else "m"
        lines = [f"FitResult: {type(self.medium).__name__} to {self.data.size} samples ({self.control} "
                 f"control), rms {self.rms:.3e} {unit}, {self.nfev} solves ({self.forward}), "
                 f"{self.wall_time:.3f} s",
                 f"  {'parameter':<14}{'value':>14}{'stderr':>14}{'relative':>11}"]
        young = {"E" + name[1:]: name for name in self.parameters if name.startswith("G")}
        rows = [(name, value, self.stderr[name], name) for name, value in self.parameters.items()]
        rows += [(name, value, self.young_stderr[name], young[name])
                 for name, value in self.young_moduli.items()]
        for name, value, err, of in rows:
            if of not in self.free:
                rel = "held"
            elif value != 0 and err > 0 and np.isfinite(err):
                rel = f"{err / value:.2e}"
            else:  # ran to 0, or no spread: no standard error to speak of
                err, rel = np.nan, "undetermined"
            lines.append(f"  {name:<14}{value:>14.6g}{err:>14.3g}{rel:>13}")
        lines.append(f"  {'nu':<14}{self.nu:>14.6g}{'':>14}{'held':>11}")
        for name, value in (("contact_point", self.contact_point), ("baseline", self.baseline),
                            ("baseline_slope", self.baseline_slope)):
            if value is not None:
                err = self.stderr[name]
                rel = "held" if name not in self.free else ("m/m" if name == "baseline_slope" else "m")
                lines.append(f"  {name:<14}{value:>14.6g}{err:>14.3g}{rel:>11}")
        if self.body is not None:
            h, err = self.body.thickness, self.stderr.get("thickness", 0.0)
            rel = f"{err / h:.2e}" if "thickness" in self.free else "held"
            lines.append(f"  {'thickness':<14}{h:>14.6g}{err:>14.3g}{rel:>13}")
        if not self.success:
            lines.append(f"  not converged: {self.message}")
        return "\n".join(lines)


@dataclasses.dataclass
class _Data:
    """A fit's curve, checked: times ``t`` (s), depths (m) and forces (N) (a raw AFM curve's at
    the first guesses of its contact point and baseline), ``weights``, what the forward model
    is driven by (``prescribed``) and what it is fitted to (``measured``), and the raw AFM
    curve (None for depth and force)."""

    t: np.ndarray
    depth: np.ndarray
    force: np.ndarray
    weights: np.ndarray
    prescribed: np.ndarray
    measured: np.ndarray
    raw: AfmCurve | None


def fit(indenter: Indenter, model: _Medium | type, t: ArrayLike, *, depth: ArrayLike | None = None,
        force: ArrayLike | None = None, piezo: ArrayLike | None = None, deflection: ArrayLike | None = None,
        spring_constant: float | None = None, contact_point: float | None = None,
        baseline: float | None = None, control: str = "depth", weights: ArrayLike | None = None,
        fixed: tuple[str, ...] = (), nu: float | None = None, terms: int = 2, n: int = 500,
        substeps: int = 1, max_iter: int = 100, baseline_model: str = "offset",
        contact: ContactLaw | None = None, body: Layer | None = None,
        fit_thickness: bool = False) -> FitResult:
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
        pre-contact deflection; see ``baseline_model`` for a tilted one). Depth control
        only; without ``contact`` no adhesion is modelled (give adhesive parts of a retract
        zero weight, or fit them with ``contact=mv.JKR(...)``). The
        first tenth of the approach (the samples up to the highest z, at least 5) must be
        before contact. Lengths in m: a piezo or deflection spanning more than 1 cm (um,
        nm or volts), a piezo that falls towards the sample, or a deflection that falls
        below its baseline as the tip presses are refused with a message saying so.
    contact_point, baseline : float, optional
        Raw AFM curves: initial guesses of z_c and b (m). Without them, b is the median of
        the deflection over the first tenth of the approach (with a tilt: the line fitted
        to the deflection there, in z, at z_c) and z_c the piezo position where the
        deflection last rises above that baseline by 3 robust standard deviations of that
        part (the median absolute deviation times 1.4826) before the deepest point (with a
        tilt, the line is then fitted again to the first three quarters of the samples
        before that guess, and the guess repeated: a drift over the whole approach does not
        move it). ``fixed=("contact_point",)``, ``("baseline",)`` or ``("baseline_slope",)``
        holds them.
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
        control, raw AFM curves) times the largest contact radius of the data; 8 to 2**26
        (``mdrvisc._core.MAX_N["mdr"]``).
    substeps : int
        Time steps per sample interval (the stepping's error falls as substeps^-2 while the
        contact grows).
    max_iter : int
        Most Levenberg-Marquardt iterations.
    baseline_model : {"offset", "tilt"}
        Raw AFM curves: the deflection's baseline, a constant b ("offset") or a line
        b + m (z - z_c) in the piezo position ("tilt": tilt, drift or virtual deflection,
        continued through the contact), its slope m (m/m) fitted with the rest
        (``result.baseline_slope``).
    contact : ContactLaw, optional
        ``mv.JKR(work_of_adhesion=w)``: fit the work of adhesion w (J/m^2, initial guess w)
        with the medium, so the retract's dip below the baseline is data
        (``fixed=("work_of_adhesion",)`` holds it). JKR by MDR with the contact's edge
        moving continuously between the elements: it grows as a hard contact on the approach
        (the touch rule), stays at its largest radius on the retract until the edge's
        elongation reaches sqrt(2 pi a w / E*), then recedes in JKR equilibrium to the
        pull-off (depth control: JKR's unstable end; a raw curve: where the cantilever
        snaps off); ``mv.JKR(..., approach="equilibrium")`` loads and unloads on the JKR
        branch instead, jumping in at the touch. ``mv.DMT(work_of_adhesion=w)``: the hard
        contact plus the attraction 2 pi w R of a rounded tip (:class:`Sphere`,
        :class:`Paraboloid`) while the surfaces touch. An elastic medium (:class:`Elastic`),
        depth control or a raw AFM curve (whose contact point also starts where the deflection
        first falls below its baseline when the contact jumps in); JKR with the touch rule on a
        depth-controlled curve also takes :class:`StandardSolid` and :class:`Prony` (the edge
        lets go by the relaxed modulus, each element carries its hereditary integral); the
        result's ``forward`` is "jkr" or "dmt". Default: hard contact (no adhesion).
    body : Layer, optional
        A :class:`~mdrvisc.Layer` of known thickness in place of the half-space (default
        None): the forward model is MDR on the layer (its flat-punch stiffness and exact
        contact radius; ``docs/layers.md``) as a half-space's foundation in a stretched
        coordinate, so Ting's solution and its millisecond path carry over. The contact
        may reach 8 thicknesses.
    fit_thickness : bool
        With ``body=mv.Layer(h0)``: fit the layer's thickness too, h0 its initial guess
        (default False: the thickness is known and held). The thickness minimises the
        profile cost (the fit's cost on a layer of that thickness, the medium fitted), by a
        bracket from h0 and golden-section search in log h to 0.1 %; each step is one
        ordinary fit. Its standard error (``stderr["thickness"]``) and correlations come
        from the joint Jacobian at the solution (d(model)/dh by a central difference).
        Depth and force data (not a raw AFM curve), hard contact. The data tell the
        thickness only where the contact reaches a sizeable fraction of it: a largest
        contact radius below 0.3 thicknesses, a relative standard error above 0.5 or a
        correlation with a modulus beyond 0.999, or a curve that is a half-space's within
        its residuals (the search runs to 1000 contact radii) raise an
        :class:`IdentifiabilityWarning` (``docs/layers.md``).

    Returns
    -------
    FitResult

    Examples
    --------
    A raw AFM curve on a drifting baseline, the contact point and the drift fitted with a
    standard solid (lengths in m, k in N/m)::

        fit = mv.fit(mv.Sphere(radius=5e-6), mv.StandardSolid, t, piezo=z, deflection=d,
                     spring_constant=0.5, baseline_model="tilt")
        fit.success, fit.message                   # stopped at a minimum, and why
        fit.young_moduli["E_inf"], fit.young_stderr["E_inf"]   # Pa
        fit.contact_point, fit.baseline_slope      # m, m/m

    A cell of unknown height on a dish, its thickness fitted from a guess of 5 um::

        fit = mv.fit(mv.Sphere(radius=5e-6), mv.StandardSolid, t, depth=d, force=f,
                     body=mv.Layer(5e-6), fit_thickness=True)
        fit.body.thickness, fit.stderr["thickness"]            # m
        fit.correlation[fit.free.index("G_inf"), fit.free.index("thickness")]

    Raises
    ------
    DataError
        Data not finite, times not strictly increasing, arrays of different lengths, no
        contact at all, fewer usable samples than free parameters; a raw AFM curve whose
        deflection never leaves its baseline or that has no contact-free start.

    Notes
    -----
    Levenberg-Marquardt works in coordinates without units: the logarithms of the medium's
    parameters, and a raw curve's contact point, baseline and slope in units of the data's
    largest indentation, deflection range and that range over the piezo's; each iteration
    scales the Jacobian's columns to unit norm. It stops, with ``success``, only at a
    minimum:

    * stationary: the relative offset of Bates and Watts, rho = (``|P r|`` / sqrt(p)) /
      (``|r|`` / sqrt(m - p)) with P r the residuals' projection on the Jacobian's range (m
      residuals, p parameters), is at most 1e-6: the undamped Gauss-Newton step to the
      linearised minimum is shorter than 1e-6 sqrt(p) standard errors, and the cost exceeds
      the minimum's by about rho^2 p / (m - p) of itself;
    * a minimum to round-off: residuals below 1e-11 of the data, or a cost that the
      Gauss-Newton step would lower by less than 1e-13 of itself (rho^2 p / (m - p) <=
      1e-13: with many samples this comes before rho <= 1e-6, e.g. at rho <= 1.4e-5 for
      8,000 samples and 4 parameters, the point within 3e-5 standard errors of the
      linearised minimum);
    * a minimum at a kink: no step lowers the cost, and the linearised minimum lies within
      0.05 standard errors. The discrete forward model is piecewise smooth (an element
      enters the contact, the root of Ting's retract crosses a step), so its cost has
      kinks; its local minima lie about 1e-2 standard errors apart.

    Neither a step's length nor the cost's decrease is a criterion: a heavily damped step
    makes both small far from the minimum. After ``max_iter`` iterations, or when no step
    lowers the cost farther from the linearised minimum, ``success`` is false and
    ``message`` gives rho.

    The forward model is MDR. Under depth control, with a depth that rises and then falls
    (approach, hold, retract: a single maximum) and a tip whose MDR profile rises away from
    its axis, it is Ting's solution: the elements' forces integrated over the contact in
    closed form, so the cost does not grow with ``n`` (which then samples the profile's
    area function, error ~(dx / a)^2) and a 2,000-sample curve takes about a millisecond.
    A raw AFM curve goes the same way with the cantilever in series: at each sample the
    indentation d solves k (z - z_c - d) = F[d](t), Ting's force of the history so far, a
    scalar equation (its derivatives by the implicit-function theorem), as long as the
    indentation rises while in contact (any path before it) and then falls until the
    contact lets go. Otherwise (force control, several load cycles, a depth that wiggles
    in contact) the n elements are stepped one by one, each with its own history
    (contact-edge error ~dx / a). Ting's solution assumes, as his paper does,
    that a contact that has let go on retraction does not touch again while the depth
    falls.
    """
    start = time.perf_counter()
    max_iter = _integer("fit", "max_iter", max_iter, 1)
    law = check_contact(contact, model, control, indenter, piezo is not None or deflection is not None)
    held_law = law is not None and WORK_OF_ADHESION in fixed
    if law is not None and body is not None:
        raise InvalidInputError("fit: an adhesive fit (contact=) on a layer (body=) is not available: "
                                "the adhesive forward model is JKR/DMT on a half-space")
    if fit_thickness:
        return _fitted_thickness(indenter, model, t, depth, force, piezo, deflection, control, weights, fixed,
                                 nu, terms, n, substeps, max_iter, body, start)
    if law is not None:
        fixed = tuple(name for name in fixed if name != WORK_OF_ADHESION)
    problem, data, scale = _problem(indenter, model, t, depth, force, piezo, deflection, spring_constant,
                                    contact_point, baseline, control, weights, fixed, nu, terms, n, substeps,
                                    baseline_model, body, reach_margin(law))
    if law is not None:
        problem = AdhesiveProblem(problem, law, held_law, tip_radius(indenter))
    # residuals below this are round-off of the forward model's sums (noise-free data that
    # the model reproduces)
    floor = ROUND_OFF_RESIDUALS * float(np.linalg.norm(problem.root_w * data.measured))
    solution = levenberg_marquardt(problem, problem.x0(), max_iter=max_iter, residual_floor=floor)
    result = _result(problem, solution, data, control, scale, start)
    result.body = body
    for message in result.warnings:
        warnings.warn(message, IdentifiabilityWarning, stacklevel=2)
    return result


def _fitted_thickness(indenter, model, t, depth, force, piezo, deflection, control, weights, fixed, nu, terms,
                      n, substeps, max_iter, body, start) -> FitResult:
    """:func:`fit` with ``fit_thickness=True`` (its arguments checked here, the search in
    :mod:`mdrvisc._fit_layer`)."""
    if not isinstance(body, Layer):
        raise InvalidInputError(f"fit: fit_thickness needs body=mv.Layer(h0), h0 the initial guess of the "
                                f"thickness (m), got body={body!r:.200}")
    if piezo is not None or deflection is not None:
        raise InvalidInputError("fit: fit_thickness takes depth and force; a raw AFM curve's layer "
                                "thickness is not fitted (fit its depth and force, or give the thickness)")

    def inner(layer: Layer, medium: _Medium | None) -> FitResult:
        return fit(indenter, model if medium is None else medium, t, depth=depth, force=force,
                   control=control, weights=weights, fixed=fixed, nu=nu if medium is None else None,
                   terms=terms, n=n, substeps=substeps, max_iter=max_iter, body=layer)

    def values(layer: Layer, medium: _Medium) -> np.ndarray:
        problem, _, _ = _problem(indenter, medium, t, depth, force, None, None, None, None, None, control,
                                 weights, fixed, None, terms, n, substeps, body=layer)
        return problem.solution(problem.x0())[1]

    with warnings.catch_warnings():  # the search's own fits: what the data identify is judged at its end
        warnings.simplefilter("ignore", IdentifiabilityWarning)
        first = inner(body, None)  # checks the data; its fit at h0 starts the search
    deepest = float(np.max(np.asarray(depth, dtype=float)))
    root_w = np.sqrt(np.ones(first.t.size) if weights is None else np.asarray(weights, dtype=float))
    result = _fit_thickness(inner, values, body, indenter.contact_radius_at_depth(deepest), root_w, first)
    result.wall_time = time.perf_counter() - start
    for message in result.warnings:
        warnings.warn(message, IdentifiabilityWarning, stacklevel=3)
    return result


def _problem(indenter, model, t, depth, force, piezo, deflection, spring_constant, contact_point, baseline,
             control, weights, fixed, nu, terms, n, substeps,
             baseline_model="offset", body=None, margin=None) -> tuple[Problem, _Data, float]:
    """The least-squares problem of :func:`fit`'s arguments (checked), its data and the
    scale its residuals were divided by (the largest measurement); ``margin`` a key of
    :data:`~mdrvisc._fit_model.MARGIN` in place of the control's."""
    if control not in ("depth", "force"):
        raise InvalidInputError(f'fit: control must be "depth" or "force", got {control!r}')
    if not isinstance(indenter, Indenter):
        raise InvalidInputError(f"fit: indenter must be an mdrvisc indenter, got {indenter!r}")
    if baseline_model not in BASELINES:
        raise InvalidInputError(f"fit: baseline_model must be one of {BASELINES}, got {baseline_model!r}")
    if body is not None and not isinstance(body, Layer):
        raise InvalidInputError(f"fit: body must be an mdrvisc.Layer or None, got {body!r:.200}")
    n = _integer("fit", "n", n, 8, _core.MAX_N["mdr"])
    substeps = _integer("fit", "substeps", substeps, 1)
    data = _read_data(t, depth, force, piezo, deflection, spring_constant, contact_point, baseline, control,
                      weights, baseline_model)
    cls, guess, nu = _model_class(model, fixed, nu)
    if cls is Prony and guess is None:
        terms = _integer("fit", "terms", terms, 1)
        # the guesses space the relaxation times a decade apart, from about the span down
        most = min((data.t.size - 1) // 2, DECADES)
        if terms > most:
            raise InvalidInputError(
                f"fit: terms = {terms} is more Prony terms than {data.t.size} samples can tell apart "
                f"(2 parameters each, their relaxation times a decade apart): at most {max(most, 0)}")

    # the forward model on the half profile, prepared once, and the initial guess
    raw, t, w = data.raw, data.t, data.weights
    curve, (estimate_curve, some) = curves(
        indenter, t, data.depth, data.prescribed, "spring" if raw is not None else control,
        margin or ("force" if raw is not None else control), n, substeps, raw.k if raw is not None else None,
        layer=body, nu=nu)
    if guess is None:
        span = float(t[-1])
        step = float(np.min(np.diff(np.concatenate([[0.0], t[t > 0]])), initial=span))
        guess = estimate(estimate_curve, cls, data.force[some], w[some], span, step, terms, nu)
    free, free_raw, values0 = _free_parameters(cls, guess, fixed, raw, w)

    # under depth control the force is proportional to the moduli together (Pa, Pa s; the
    # contact set depends on their ratios only): the derivatives in their logarithms add up
    # to the force, so one of them follows from the others and the forward model is asked
    # for one tangent fewer. Not through a cantilever: there the depth, and with it the
    # force, depends on the moduli otherwise
    asked = free
    if control == "depth" and raw is None and set(moduli(values0)) <= set(free):
        asked = [name for name in free if name != moduli(values0)[0]]
    scale = float(np.max(np.abs(data.measured)))
    # a flat punch's profile spans its footprint, all of it in contact: no end to reach
    problem = Problem(curve, cls, values0, nu, free, asked, raw, free_raw, data.measured,
                      np.sqrt(w) / scale, None if indenter.is_flat else n)
    return problem, data, scale


def _read_data(t, depth, force, piezo, deflection, spring_constant, contact_point, baseline, control,
               weights, baseline_model="offset") -> _Data:
    """The fit's curve checked (DataError naming what is wrong), a raw AFM curve with the first
    guesses of its contact point and baseline."""
    raw = raw_input(depth, force, piezo, deflection, spring_constant, control)
    t = array("t", t)
    if raw is None:
        d, f = array("depth", depth), array("force", force)
        for name, a in (("depth", d), ("force", f)):
            if a.size != t.size:
                raise DataError(f"fit: {name} has {a.size} samples, t has {t.size}")
        check_times(t)
        if not np.any(d > 0) or not np.any(f > 0):
            which = "depth" if not np.any(d > 0) else "force"
            raise DataError(f"fit: no contact at all: {which} is <= 0 at every sample")
        curve = None
    else:
        for name, a in zip(("piezo", "deflection"), raw[:2]):
            if a.size != t.size:
                raise DataError(f"fit: {name} has {a.size} samples, t has {t.size}")
        if t.size:
            t = t - t[0]
        check_times(t)
        curve = AfmCurve.estimate(*raw, contact_point, baseline, baseline_model)
        guess = (curve.contact_point, curve.baseline, curve.slope)
        d, f = curve.depth(*guess), curve.force(*guess)
    w = np.ones_like(t) if weights is None else array("weights", weights)
    if w.size != t.size:
        raise DataError(f"fit: weights has {w.size} samples, t has {t.size}")
    if np.any(w < 0) or not np.any(w > 0):
        raise DataError("fit: weights must be >= 0 and not all zero")
    prescribed, measured = (d, f) if control == "depth" else (f, d)
    if curve is not None:
        prescribed = curve.z - curve.contact_point  # the drive past the contact point's guess
    return _Data(t, d, f, w, prescribed, measured, curve)


def _model_class(model, fixed: tuple[str, ...], nu: float | None) -> tuple[type, _Medium | None, float]:
    """(class, initial guess or None, Poisson ratio) of the ``model`` argument."""
    if isinstance(model, type):
        if set(fixed) - set(RAW_NAMES):
            raise InvalidInputError("fit: fixed parameters need a medium instance (their values)")
        return model, None, 0.5 if nu is None else _poisson_ratio("fit", nu)
    if isinstance(model, _Medium):
        if nu is not None:
            raise InvalidInputError(f"fit: nu is given with a medium instance, which has its own "
                                    f"(nu={model.nu!r}): give it to the medium")
        return type(model), model, model.nu
    raise InvalidInputError(f"fit: model must be an mdrvisc medium or medium class, got {model!r}")


def _free_parameters(cls: type, guess: _Medium, fixed: tuple[str, ...], raw: AfmCurve | None,
                     w: np.ndarray) -> tuple[list[str], list[str], dict[str, float]]:
    """(the medium's free parameters, the raw AFM curve's, the guess's values by name), or an
    error naming unknown or non-positive ones, or too few samples of positive weight ``w``."""
    names = list(parameters(guess))
    held = set(fixed) | ({"t0"} if cls is PowerLaw else set())
    unknown = sorted(set(fixed) - set(names) - (set(raw.names) if raw is not None else set()))
    if unknown:
        raise InvalidInputError(f"fit: fixed names {unknown} are not parameters of {cls.__name__} {names}")
    free = [name for name in names if name not in held]
    values0 = parameters(guess)
    bad = [name for name in free if not values0[name] > 0]
    if bad:
        raise InvalidInputError(f"fit: parameters {bad} must be > 0 to be fitted in log space (or hold them)")
    free_raw = [name for name in (raw.names if raw is not None else ()) if name not in held]
    usable = int(np.count_nonzero(w > 0))
    if usable < len(free) + len(free_raw) + 1:
        raise DataError(f"fit: {usable} samples with positive weight for {len(free) + len(free_raw)} free "
                        f"parameters ({free + free_raw}); a fit needs more samples than parameters")
    return free, free_raw, values0


def _result(problem: Problem, solution: Solution, data: _Data, control: str, scale: float,
            start: float) -> FitResult:
    """The :class:`FitResult` of Levenberg-Marquardt's ``solution``: the forward model there,
    standard errors and correlations from its Jacobian and the residual variance (the data's
    residuals were divided by ``scale``), the parameters' identifiability."""
    medium, values, contact, forward = problem.solution(solution.x)
    measured, raw, free, free_raw = data.measured, data.raw, problem.free, problem.free_raw
    afm = {}
    if raw is not None:
        z_c, b, m = problem.raw_at(solution.x)
        d, measured = raw.depth(z_c, b, m), raw.force(z_c, b, m)
        before = int(np.count_nonzero(d[:int(np.argmax(raw.z)) + 1] <= 0))
        if before < BASELINE_SAMPLES:
            raise DataError(f"fit: a raw AFM curve needs a contact-free start (the baseline): at the "
                            f"fitted contact point ({z_c:.6g} m) {before} samples of the approach are before "
                            f"contact, fewer than {BASELINE_SAMPLES}")
        afm = {"contact_point": z_c, "baseline": b, "spring_constant": raw.k, "depth": d,
               "baseline_slope": m if raw.tilt else None}
    if problem.n is not None and np.any(contact == problem.n):
        raise DomainError("fit: the fitted contact reaches the end of the 1D profile; the data's depths "
                          "are beyond the indenter's footprint")
    r, jac = solution.residuals, solution.jacobian
    w = data.weights
    dof = int(np.count_nonzero(w > 0)) - len(free) - len(free_raw)
    # the Jacobian in the parameters themselves: the coordinates are their logarithms (the
    # medium's) or scaled (the raw curve's), and the residuals were divided by scale
    values_by_name = parameters(medium) | problem.contact_parameters(solution.x)
    units = [values_by_name[name] for name in free]
    if raw is not None:
        units += [dict(zip(raw.names, raw.scales()))[name] for name in free_raw]
    jac_parameters = jac * (scale / np.asarray(units))
    err, correlation, undetermined = covariance(jac_parameters, float(r @ r) * scale**2 / dof)
    stderr = {name: 0.0 for name in values_by_name}
    stderr.update({name: float(e) for name, e in zip(free, err)})
    # judged relative to their values (the medium's) or to their scales (the largest depth,
    # the deflection's range: the raw curve's)
    with np.errstate(divide="ignore", invalid="ignore"):
        relative = err / np.abs(np.asarray(units))
    if problem.cls is Prony:
        # terms in increasing relaxation time: a fit finds them in any order
        order = sorted(range(len(medium.terms)), key=lambda k: medium.terms[k][1])
        rename = {f"{prefix}{old + 1}": f"{prefix}{new + 1}" for new, old in enumerate(order)
                  for prefix in ("G", "tau")}
        medium = Prony(medium.G_inf, tuple(medium.terms[k] for k in order), nu=problem.nu)
        values_by_name = parameters(medium)
        free = [rename.get(name, name) for name in free]
        stderr = {rename.get(name, name): e for name, e in stderr.items()}
        stderr = {name: stderr[name] for name in values_by_name}
    young_stderr = _young(stderr, problem.nu)
    if raw is not None:
        for name in raw.names:
            stderr[name] = float(err[len(free) + free_raw.index(name)]) if name in free_raw else 0.0
    messages = identifiability(free + free_raw, relative, correlation, undetermined)
    residual = values - measured
    return FitResult(
        medium=medium, parameters=values_by_name, stderr=stderr, nu=problem.nu,
        young_moduli=medium.young_moduli, young_stderr=young_stderr, free=free + free_raw,
        correlation=correlation, t=data.t, data=measured, model=values, residuals=residual,
        rms=float(np.sqrt(np.sum(w * residual**2) / np.sum(w))), cost=0.5 * float(np.sum(w * residual**2)),
        jac=jac_parameters, success=solution.converged, status=solution.status, message=solution.message,
        nfev=problem.solves, nit=solution.iterations, control=control, forward=forward,
        wall_time=time.perf_counter() - start, warnings=messages, contact=problem.contact_at(solution.x),
        **afm)
