"""Fits that stop at their minimum, and say so honestly: the same minimum from several
starts, the cost of an independent refinement (scipy's trust-region least squares on the
same model) not below the fit's, noise-free raw curves of every protocol recovered,
standard errors that match the spread over noise draws, diagnostics of parameters the data
do not determine, and baselines that are tilted.

The raw curves come from Ting's solution for a paraboloid on a Prony medium, written here in
closed form (the hereditary integrals of a ramp with Dawson's function, the roots of the
retract by bisection), independent of the fit's forward model (MDR elements), for a depth
that rises at a constant rate, may be held, and may fall at the same rate; the cantilever
turns it into a raw curve: deflection = F / k + baseline, piezo = z_c + indentation + F / k.
"""

import math
import warnings

import numpy as np
import pytest
from scipy import special

import mdrvisc as mv
from mdrvisc._afm_raw import AfmCurve
from mdrvisc._fit_model import parameters
from mdrvisc._least_squares import levenberg_marquardt
from mdrvisc.analytic import ting_paraboloid_triangle
from mdrvisc.fitting import _problem

R, V = 5e-6, 1e-6  # tip radius (m), indentation rate (m/s)
Z_C, BASELINE = 2.0e-6, 3.0e-8  # contact point, baseline (m)
PRE = 0.5  # time before contact (s)
PARABOLOID = mv.Paraboloid(c=1 / (2 * R))
SOLID = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
PROTOCOLS = {"approach-retract": (1.0, 0.0, 1.0), "approach-dwell": (1.0, 1.0, 0.0),
             "approach-dwell-retract": (1.0, 1.0, 1.0)}


def ting_trapezoid(s, medium, t_ramp, t_hold):
    """Ting's force (N) at times ``s`` (s, from contact) on the paraboloid of radius R pressed
    at rate V for ``t_ramp``, held for ``t_hold``, then pulled back at V; a Prony medium.

    Rising and held, F = c int G(s - u) dX(u) with X = d^(3/2), c = 8 sqrt(R) / (3 (1 - nu));
    on the ramp int_0^s exp(-(s - u) / tau) d(u^(3/2)) = 1.5 tau^(3/2) (sqrt(y) - D(sqrt(y))),
    y = s / tau, D Dawson's function. Falling, the contact radius is that of the time t1 on
    the ramp where int_t1^s G(s - u) dd(u) = 0 and F = c int_0^t1 G(s - u) dX(u); none once
    that root leaves the ramp (no contact again, as Ting assumes)."""
    g_inf, terms, eta = medium.rheology()
    assert eta == 0.0
    s = np.asarray(s, dtype=float)
    c = 8.0 * math.sqrt(R) / (3.0 * (1.0 - medium.nu))

    def ramp(u):  # per term: int_0^u exp(-(u - v) / tau) dX(v) on the ramp
        return [gk * 1.5 * V**1.5 * tau**1.5 * (np.sqrt(u / tau) - special.dawsn(np.sqrt(u / tau)))
                for gk, tau in terms]

    t_fall = t_ramp + t_hold
    force = np.zeros_like(s)
    up = (s > 0) & (s <= t_ramp)
    force[up] = c * (g_inf * (V * s[up]) ** 1.5 + sum(ramp(s[up])))
    held = (s > t_ramp) & (s <= t_fall)
    top = ramp(t_ramp)
    force[held] = c * (g_inf * (V * t_ramp) ** 1.5
                       + sum(q * np.exp(-(s[held] - t_ramp) / tau) for q, (_, tau) in zip(top, terms)))
    down = s > t_fall
    sd = s[down]

    def phi(t1):  # int_t1^s G(s - u) dd(u) / V
        value = g_inf * (t_ramp - t1) - g_inf * (sd - t_fall)
        for gk, tau in terms:
            value = value + gk * tau * (np.exp(-(sd - t_ramp) / tau) - np.exp(-(sd - t1) / tau))
            value = value - gk * tau * (1.0 - np.exp(-(sd - t_fall) / tau))
        return value

    lo, hi = np.zeros_like(sd), np.full_like(sd, t_ramp)
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        inside = phi(mid) > 0
        lo, hi = np.where(inside, mid, lo), np.where(inside, hi, mid)
    t1 = 0.5 * (lo + hi)
    falling = c * (g_inf * (V * t1) ** 1.5 + sum(q * np.exp(-(sd - t1) / tau) for q, (_, tau) in
                                                  zip(ramp(t1), terms)))
    falling[np.cumsum(phi(np.zeros_like(sd)) <= 0) > 0] = 0.0
    force[down] = falling
    return force


def raw_curve(medium, protocol, samples, k, seed=None, level=0.01, slope=0.0):
    """(t, piezo, deflection) of ``protocol`` (ramp, hold and retract times) with contact at
    PRE: the deflection F / k + BASELINE + ``slope`` (z - Z_C) (a tilt), with ``seed``
    Gaussian noise of ``level`` times the largest F / k."""
    t_ramp, t_hold, t_back = protocol
    t = np.linspace(0.0, PRE + t_ramp + t_hold + t_back, samples)
    s = t - PRE
    indentation = V * np.clip(s, None, t_ramp) - V * np.clip(s - t_ramp - t_hold, 0.0, None)
    bend = ting_trapezoid(np.maximum(s, 0.0), medium, t_ramp, t_hold) / k
    z = Z_C + indentation + bend
    deflection = bend + BASELINE + slope * (z - Z_C)
    if seed is not None:
        deflection = deflection + level * np.max(bend) * np.random.default_rng(seed).standard_normal(t.size)
    return t, z, deflection


def test_closed_form_is_tings_triangle():
    """The trapezoid's closed form without a hold is analytic.ting_paraboloid_triangle's."""
    s = np.linspace(0.0, 2.0, 401)[1:]
    for medium in (SOLID, mv.Prony(G_inf=1e3, terms=((2e3, 0.03), (1.5e3, 0.5)))):
        ours = ting_trapezoid(s, medium, 1.0, 0.0)
        theirs, _, _ = ting_paraboloid_triangle(s, medium, R, V, 1.0)
        assert np.max(np.abs(ours - theirs)) <= 1e-12 * np.max(theirs)


def fit_raw(t, z, deflection, k, model=mv.StandardSolid, **options):
    return mv.fit(PARABOLOID, model, t, piezo=z, deflection=deflection, spring_constant=k, **options)


def test_same_minimum_from_several_starts():
    """An approach and dwell, 1 % noise: from the class alone, from media a factor 2-3 off
    and from contact points 20 % of the depth early or late, the same minimum, every
    parameter within 5 % of its standard error. (The discrete model's cost is piecewise
    smooth, an element entering the contact at each kink; its local minima lie about 1 % of
    a standard error apart.)"""
    t, z, deflection = raw_curve(SOLID, PROTOCOLS["approach-dwell"], 1500, 0.5, seed=3)
    starts = [{}, {"model": mv.StandardSolid(G_inf=3e3, G1=7e2, tau1=0.6)},
              {"model": mv.StandardSolid(G_inf=4e2, G1=5e3, tau1=0.07), "contact_point": Z_C - 0.2e-6},
              {"contact_point": Z_C + 0.2e-6}]
    results = [fit_raw(t, z, deflection, 0.5, **start) for start in starts]
    first = results[0]
    for result in results:
        assert result.success, result.message
        for name in first.free:
            value = first.parameters.get(name, getattr(first, name, None))
            other = result.parameters.get(name, getattr(result, name, None))
            assert abs(other - value) <= 0.05 * first.stderr[name], (name, other, value, first.stderr[name])


def refined_cost(result, t, z, deflection, k):
    """The cost at ``result`` of the model its fit (from the class StandardSolid) minimised,
    and the cost that scipy's trust-region least squares reaches from there on the same
    model (the fit's residuals and Jacobian: its 1D profile depends on the first guess of
    the contact point, so the problem is set up as the fit's)."""
    from scipy.optimize import least_squares

    problem, _, scale = _problem(PARABOLOID, mv.StandardSolid, t, None, None, z, deflection, k, None, None,
                                 "depth", None, (), None, 2, 500, 1)
    raw = problem.raw
    x0 = np.concatenate([np.log([result.parameters[name] for name in problem.free]),
                         [(result.contact_point - raw.contact_point) / raw.depth_scale,
                          (result.baseline - raw.baseline) / raw.deflection_scale]])
    refined = least_squares(lambda x: problem(x)[0], x0, jac=lambda x: problem(x)[1], method="trf",
                            x_scale="jac", xtol=1e-15, ftol=1e-15, gtol=1e-15, max_nfev=200)
    start = problem(x0)[0]
    return 0.5 * float(start @ start) * scale**2, 0.5 * float(refined.fun @ refined.fun) * scale**2


@pytest.mark.parametrize("k", [0.03, 0.01])
def test_flat_valley_cost_is_the_minimum(k):
    """A soft cantilever (the deflection 1.2 and 3.5 times the indentation: the moduli and
    the contact point trade off along a flat valley), 1 % noise: an independent refinement
    started at the fit's answer finds no cost lower by more than 1e-9 of it."""
    t, z, deflection = raw_curve(SOLID, PROTOCOLS["approach-retract"], 1000, k, seed=7)
    result = fit_raw(t, z, deflection, k)
    assert result.success, result.message
    at_ours, theirs = refined_cost(result, t, z, deflection, k)
    assert at_ours == pytest.approx(result.cost, rel=1e-12)
    assert theirs >= result.cost * (1.0 - 1e-9), (theirs, result.cost)


@pytest.mark.parametrize("protocol", PROTOCOLS, ids=list(PROTOCOLS))
def test_noise_free_protocols_are_recovered(protocol):
    """Noise-free raw curves, 2,000 samples, from the class alone: the medium to 1e-4, the
    contact point to 1e-4 of the largest indentation."""
    t, z, deflection = raw_curve(SOLID, PROTOCOLS[protocol], 2000, 0.5)
    result = fit_raw(t, z, deflection, 0.5, substeps=4)
    assert result.success, result.message
    for name, value in parameters(SOLID).items():
        assert abs(result.parameters[name] / value - 1.0) <= 1e-4, (name, result.parameters[name])
    assert abs(result.contact_point - Z_C) <= 1e-4 * V
    assert abs(result.baseline - BASELINE) <= 1e-4 * np.ptp(deflection)


def test_standard_errors_match_the_spread_over_noise():
    """Over 400 noise draws of one curve (depth control, Ting's forward model: milliseconds
    a fit), the spread of each fitted parameter is its standard error (the ratio within
    0.8-1.25; the spread's own sampling error is 3.5 %)."""
    t = np.linspace(0.0, 2.0, 301)[1:]
    depth = np.where(t <= 1.0, V * t, V * (2.0 - t))
    clean, _, _ = ting_paraboloid_triangle(t, SOLID, R, V, 1.0)
    rng = np.random.default_rng(11)
    fitted, errors = [], []
    for _ in range(400):
        force = clean + 0.01 * np.max(clean) * rng.standard_normal(t.size)
        result = mv.fit(PARABOLOID, SOLID, t, depth=depth, force=force)
        assert result.success, result.message
        fitted.append([result.parameters[name] for name in result.free])
        errors.append([result.stderr[name] for name in result.free])
    ratio = np.std(fitted, axis=0, ddof=1) / np.mean(errors, axis=0)
    assert np.all((ratio >= 0.8) & (ratio <= 1.25)), ratio


def test_raw_standard_errors_match_the_spread_over_noise():
    """The same for raw curves through a soft cantilever (k = 0.05 N/m, the deflection 0.7
    times the indentation), 150 draws of 300 samples: the medium's, the contact point's and
    the baseline's spreads are their standard errors (0.8-1.25; sampling error 6 %)."""
    fitted, errors = [], []
    for seed in range(150):
        t, z, deflection = raw_curve(SOLID, PROTOCOLS["approach-retract"], 300, 0.05, seed=100 + seed)
        result = fit_raw(t, z, deflection, 0.05, model=SOLID, contact_point=Z_C, baseline=BASELINE)
        assert result.success, result.message
        values = {**result.parameters, "contact_point": result.contact_point, "baseline": result.baseline}
        fitted.append([values[name] for name in result.free])
        errors.append([result.stderr[name] for name in result.free])
    ratio = np.std(fitted, axis=0, ddof=1) / np.mean(errors, axis=0)
    assert np.all((ratio >= 0.8) & (ratio <= 1.25)), ratio


def test_inseparable_parameters_are_undetermined():
    """Two Prony terms of one relaxation time (held): only G1 + G2 enters the curve. Their
    standard errors are inf, their correlations NaN, an IdentifiabilityWarning names them;
    G_inf keeps a finite error; the correlation matrix is symmetric. Refitted to the fit's
    own noise-free model (residuals zero: no variance) the same, with G_inf's error 0."""
    t = np.linspace(0.0, 2.0, 201)[1:]
    depth = np.where(t <= 1.0, V * t, V * (2.0 - t))
    force, _, _ = ting_paraboloid_triangle(t, SOLID, R, V, 1.0)
    guess = mv.Prony(G_inf=8e2, terms=((1.5e3, 0.2), (1e3, 0.2)))
    force = force * (1.0 + 0.01 * np.random.default_rng(2).standard_normal(t.size))
    for data in ("noisy", "exact"):
        with pytest.warns(mv.IdentifiabilityWarning, match="G1, G2 are not determined"):
            result = mv.fit(PARABOLOID, guess, t, depth=depth, force=force, fixed=("tau1", "tau2"))
        assert math.isinf(result.stderr["G1"]) and math.isinf(result.stderr["G2"])
        assert math.isfinite(result.stderr["G_inf"])
        c = result.correlation
        assert np.array_equal(np.isnan(c), np.isnan(c.T))
        assert np.allclose(np.nan_to_num(c), np.nan_to_num(c.T))
        assert np.isnan(c[0, 1]) and np.isnan(c[1, 2]) and np.all(np.diag(c) == 1.0)
        assert result.parameters["G1"] + result.parameters["G2"] == pytest.approx(2e3, rel=0.05)
        if data == "exact":
            assert result.stderr["G_inf"] < 1e-6 * result.parameters["G_inf"]
        force = result.model


def test_modulus_that_runs_to_zero():
    """A standard solid fitted to a Maxwell fluid's curve: G_inf runs towards 0. Its standard
    error is the size the data allow (not 1e-30), it is reported as not identified, and the
    correlation matrix is symmetric with entries in [-1, 1]."""
    t = np.linspace(0.0, 2.0, 401)[1:]
    depth = np.where(t <= 1.0, V * t, V * (2.0 - t))
    force, _, _ = ting_paraboloid_triangle(t, mv.Maxwell(G=2e3, eta=400.0), R, V, 1.0)
    force = force + 0.01 * np.max(force) * np.random.default_rng(4).standard_normal(t.size)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        result = mv.fit(PARABOLOID, mv.StandardSolid, t, depth=depth, force=force)
    c = result.correlation
    assert np.allclose(c, c.T) and np.all(np.abs(c) <= 1.0) and np.all(np.diag(c) == 1.0)
    g_inf, err = result.parameters["G_inf"], result.stderr["G_inf"]
    # in the moduli themselves the Jacobian is well conditioned: the error is the covariance's
    covariance = 2.0 * result.cost / (t.size - 3) * np.linalg.inv(result.jac.T @ result.jac)
    assert err == pytest.approx(math.sqrt(covariance[0, 0]), rel=1e-6)
    assert g_inf < 1e-3 * result.parameters["G1"] and err > 1e6 * g_inf
    assert any(issubclass(w.category, mv.IdentifiabilityWarning) and "G_inf" in str(w.message)
               for w in caught)
    assert not any(issubclass(w.category, RuntimeWarning) for w in caught)


# baselines


def tilted(slope, seed=None, samples=1500):
    return raw_curve(SOLID, PROTOCOLS["approach-retract"], samples, 0.5, seed=seed, slope=slope)


def test_tilted_baseline_is_fitted():
    """A baseline tilted by 2 % along the piezo (its change over the approach 2.5 times the
    largest deflection), noise-free: with baseline_model="tilt" the medium, contact point,
    baseline (at the contact point) and slope are recovered (1e-4); the offset baseline
    refuses the curve and names the tilt model."""
    t, z, deflection = tilted(0.02)
    result = fit_raw(t, z, deflection, 0.5, baseline_model="tilt", substeps=4)
    assert result.success, result.message
    for name, value in parameters(SOLID).items():
        assert abs(result.parameters[name] / value - 1.0) <= 1e-4, (name, result.parameters[name])
    assert abs(result.contact_point - Z_C) <= 1e-4 * V
    assert abs(result.baseline - BASELINE) <= 1e-4 * np.ptp(deflection)
    assert abs(result.baseline_slope - 0.02) <= 1e-4 * 0.02
    assert "baseline_slope" in result.free and "baseline_slope" in repr(result)
    with pytest.raises(mv.DataError, match='baseline_model="tilt"'):
        fit_raw(t, z, deflection, 0.5)


@pytest.mark.parametrize("slope", [-0.05, 0.01, 0.05])
def test_noisy_tilted_baseline_within_three_standard_errors(slope):
    t, z, deflection = tilted(slope, seed=12)
    result = fit_raw(t, z, deflection, 0.5, baseline_model="tilt")
    assert result.success, result.message
    for name, value in parameters(SOLID).items():
        assert abs(result.parameters[name] - value) <= 3.0 * result.stderr[name], name
    for name, value in (("contact_point", Z_C), ("baseline", BASELINE), ("baseline_slope", slope)):
        assert abs(getattr(result, name) - value) <= 3.0 * result.stderr[name], name


def test_untilted_curve_has_the_same_fit_either_way():
    """A flat baseline: the tilt model finds a slope within 3 of its standard errors of
    zero, and the medium within 3 standard deviations of the difference of the two nested
    estimates (sqrt(stderr_tilt^2 - stderr_offset^2)) of the offset model's."""
    t, z, deflection = tilted(0.0, seed=5)
    offset = fit_raw(t, z, deflection, 0.5)
    tilt = fit_raw(t, z, deflection, 0.5, baseline_model="tilt")
    assert offset.baseline_slope is None and abs(tilt.baseline_slope) <= 3.0 * tilt.stderr["baseline_slope"]
    for name in parameters(SOLID):
        spread = math.sqrt(tilt.stderr[name] ** 2 - offset.stderr[name] ** 2)
        assert abs(tilt.parameters[name] - offset.parameters[name]) <= 3.0 * spread, name


def test_contact_point_guess_is_robust_to_drift():
    """A drift of 5 % (over the approach: 6 times the largest deflection) moves the first
    guess of the contact point by less than 2 % of the largest indentation from that of the
    same curve without it (same noise), and the guess of the slope is within 5 % of it."""
    flat = AfmCurve.estimate(*tilted(0.0, seed=1)[1:], 0.5, None, None, "tilt")
    curve = AfmCurve.estimate(*tilted(0.05, seed=1)[1:], 0.5, None, None, "tilt")
    assert abs(curve.contact_point - flat.contact_point) <= 0.02 * V
    assert curve.slope == pytest.approx(0.05, rel=0.05)


# messages on data that look like a wrong unit or a flipped axis


def test_wrong_units_and_flipped_axes_are_named():
    t, z, deflection = raw_curve(SOLID, PROTOCOLS["approach-retract"], 600, 0.5, seed=2)
    with pytest.raises(mv.DataError, match="piezo spans .* lengths are in m"):
        fit_raw(t, z * 1e6, deflection, 0.5)
    with pytest.raises(mv.DataError, match="deflection spans .* lengths are in m"):
        fit_raw(t, z, deflection * 1e9, 0.5)
    with pytest.raises(mv.DataError, match="piezo .* looks flipped"):
        fit_raw(t, -z, deflection, 0.5)
    with pytest.raises(mv.DataError, match="sign were flipped"):
        fit_raw(t, z, -deflection, 0.5)
    with pytest.raises(mv.InvalidInputError, match="baseline_model"):
        fit_raw(t, z, deflection, 0.5, baseline_model="linear")


def test_no_numpy_warning_outside_the_domain():
    """Residuals that are not finite outside a domain (the forward model's contact past the
    profile's end, a medium the parameters do not make), with a NaN Jacobian there: steps
    into it are refused without numpy's RuntimeWarnings, and a start there stops at once."""
    x = np.linspace(0.0, 1.0, 40)
    y = 2.0 * x + 0.5

    def residuals(p):
        if p[0] > 0.6:  # the domain ends before the minimum at log 2: the search runs into it
            return np.full(x.size, np.inf), np.full((x.size, 2), np.nan)
        return np.exp(p[0]) * x + p[1] - y, np.column_stack([np.exp(p[0]) * x, np.ones_like(x)])

    with warnings.catch_warnings():
        warnings.simplefilter("error")
        inside = levenberg_marquardt(residuals, np.array([0.0, 0.0]))
        outside = levenberg_marquardt(residuals, np.array([1.0, 0.0]))
    assert inside.x[0] <= 0.6 and inside.evaluations > 2
    assert not outside.converged and outside.evaluations == 1 and "domain" in outside.message
