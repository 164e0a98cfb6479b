"""Fits of media to indentation curves made by methods independent of the fit's forward
model (MDR stepping of `_core.Curve`): Ting's closed form for the paraboloid
(`analytic.ting_paraboloid_triangle`, Prony integrals in closed form and roots by bisection,
no stepping), Lee-Radok hereditary integrals written here for the cone and the power law,
and BEM for the sphere. Noise-free data: the parameters to 1e-4 where the data's own error
allows; 1 % Gaussian noise with fixed seeds: within 3 standard errors and 3 %."""

import math
import warnings

import numpy as np
import pytest
from scipy import integrate, special

import mdrvisc as mv
from mdrvisc._fit_model import parameters
from mdrvisc._least_squares import levenberg_marquardt
from mdrvisc.analytic import ting_paraboloid_triangle

R = 5e-6  # tip radius (m)
V = 1e-6  # indentation rate (m/s)
T_PEAK = 1.0  # s


def triangle(samples=200):
    """Sample times and depths of an approach and retract at rate V."""
    t = np.linspace(0.0, 2.0 * T_PEAK, samples + 1)[1:]
    return t, np.where(t <= T_PEAK, V * t, V * (2.0 * T_PEAK - t))


def relative_errors(result, true):
    return {name: result.parameters[name] / value - 1.0 for name, value in true.items()}


def noisy(values, seed, level=0.01):
    """``values`` plus Gaussian noise of ``level`` times their largest magnitude."""
    rng = np.random.default_rng(seed)
    return values + level * np.max(np.abs(values)) * rng.standard_normal(values.shape)


def check_noisy(result, true, percent=True):
    """Within 3 standard errors and (``percent``) within 3 % (each parameter)."""
    for name, value in true.items():
        fitted, err = result.parameters[name], result.stderr[name]
        assert abs(fitted - value) <= 3.0 * err, f"{name}: {fitted} vs {value} +- {err}"
        assert not percent or abs(fitted / value - 1.0) <= 0.03, f"{name}: {fitted} vs {value}"


# Ting's paraboloid: media whose G(t) is a Prony series with a dashpot
# A two-term Prony series is identified (noise-free: to 3e-6), but not to 3 % at 1 % noise
# from a 2 s triangle: the relative standard errors are 5-19 % (tau1 worst; 8-15 % from
# 2000-4000 samples over 4-6 s triangles); its noisy triangle fit is held to 3 standard
# errors only, and a relaxation identifies it to 3 % (test_prony_two_terms_from_a_relaxation).
# (a dashpot's force follows the contact's growth within each step, a first-order error in
# the step: 40 substeps for 1e-4, measured 3e-5)
TING_MEDIA = [
    (mv.Elastic(G=2e3), {}),
    (mv.Viscous(eta=500.0), {"substeps": 40}),
    (mv.KelvinVoigt(G=1e3, eta=300.0), {"substeps": 40}),
    (mv.Maxwell(G=2e3, eta=600.0), {}),
    (mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2), {}),
    (mv.Prony(G_inf=1e3, terms=((2e3, 0.03), (1.5e3, 0.5))), {"terms": 2, "percent": False}),
]


def _name(value):
    return "" if isinstance(value, dict) else type(value).__name__


@pytest.mark.parametrize("true, options", TING_MEDIA, ids=_name)
def test_noise_free_ting_paraboloid_is_recovered(true, options):
    """From the class alone (initial guess estimated from the data). Measured worst relative
    error with 4 substeps: 3e-6 (Prony, tau1); the bound is 1e-4."""
    t, depth = triangle()
    force, _, _ = ting_paraboloid_triangle(t, true, R, V, T_PEAK)
    options = {k: v for k, v in options.items() if k != "percent"}
    result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), type(true), t, depth=depth, force=force,
                    **{"substeps": 4, **options})
    errors = relative_errors(result, parameters(true))
    assert result.success, result.message
    assert max(abs(e) for e in errors.values()) < 1e-4, errors


def _name(value):
    return "" if isinstance(value, dict) else type(value).__name__


@pytest.mark.parametrize("true, options", TING_MEDIA, ids=_name)
def test_noisy_ting_paraboloid_within_three_standard_errors(true, options):
    t, depth = triangle(400)
    force, _, _ = ting_paraboloid_triangle(t, true, R, V, T_PEAK)
    with warnings.catch_warnings():
        warnings.simplefilter("error", mv.IdentifiabilityWarning)
        result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), type(true), t, depth=depth, force=noisy(force, 7),
                        **{k: v for k, v in options.items() if k not in ("substeps", "percent")})
    check_noisy(result, parameters(true), options.get("percent", True))


def test_standard_solid_fit_recovers_the_separation_time():
    """Ting's separation time of the fitted medium against the true one (1 % noise; measured
    0.24 % off), and the fitted MDR curve's force is zero from the first sample after it."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, depth = triangle(400)
    force, _, t_sep = ting_paraboloid_triangle(t, true, R, V, T_PEAK)
    result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=noisy(force, 3))
    _, _, fitted_sep = ting_paraboloid_triangle(t, result.medium, R, V, T_PEAK)
    assert T_PEAK < t_sep < 2 * T_PEAK
    assert abs(fitted_sep / t_sep - 1.0) < 0.01, (fitted_sep, t_sep)
    first_zero = t[np.flatnonzero((result.model <= 0) & (t > T_PEAK))[0]]
    assert 0.0 <= first_zero - fitted_sep <= t[1] - t[0]


def cone_ramp_hold(t, medium, slope, t_ramp):
    """Lee-Radok for a cone pressed at rate V to t_ramp and held: the contact never shrinks,
    so F(t) = int_0^min(t, t_ramp) G(t - s) dF_e/ds ds with F_e = 8 G d^2 / (pi slope):
    dF_e/ds = 16 V^2 s / (pi slope) per unit G; Prony terms integrated in closed form."""
    g_inf, terms, eta = medium.rheology()
    top = np.minimum(t, t_ramp)

    def integral(g, tau):
        # int_0^top exp(-(t - s)/tau) s ds
        return tau * (top * np.exp(-(t - top) / tau) - tau * (np.exp(-(t - top) / tau) - np.exp(-t / tau)))

    total = g_inf * 0.5 * top**2 + sum(g * integral(g, tau) for g, tau in terms)
    total = total + eta * np.where(t <= t_ramp, t, 0.0)
    return 16.0 * V**2 / (math.pi * slope) * total


@pytest.mark.parametrize("true", [mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2),
                                  mv.Maxwell(G=2e3, eta=600.0)], ids=_name)
def test_cone_ramp_and_hold(true):
    """Noise-free (measured worst 1e-5 with 4 substeps) and 1 % noise."""
    slope, t = 0.5, np.linspace(0.0, 2.0, 201)[1:]
    depth = V * np.minimum(t, 1.0)
    force = cone_ramp_hold(t, true, slope, 1.0)
    cone = mv.Cone(slope=slope)
    exact = mv.fit(cone, type(true), t, depth=depth, force=force, substeps=4)
    assert max(abs(e) for e in relative_errors(exact, parameters(true)).values()) < 1e-4
    result = mv.fit(cone, type(true), t, depth=depth, force=noisy(force, 11))
    check_noisy(result, parameters(true))


def prony_ramp_hold(t, medium, rate, t_ramp):
    """Lee-Radok for a paraboloid pressed at ``rate`` to t_ramp and held (the contact never
    shrinks): F = 8 sqrt(R) rate^1.5 int_0^min(t, t_ramp) G(t - s) s^(1/2) ds, each Prony
    term by quadrature with the algebraic weight s^(1/2), G_inf in closed form."""
    g_inf, terms, _ = medium.rheology()
    out = []
    for now in t:
        top = min(now, t_ramp)
        total = g_inf * 2.0 / 3.0 * top**1.5
        for g, tau in terms:
            value, _ = integrate.quad(lambda s, now=now, tau=tau: math.exp(-(now - s) / tau), 0.0, top,
                                      weight="alg", wvar=(0.5, 0.0), epsabs=0.0, epsrel=1e-12)
            total += g * value
        out.append(total)
    return 8.0 * math.sqrt(R) * rate**1.5 * np.array(out)


def test_prony_two_terms_from_a_relaxation():
    """Two Prony terms are identified by a relaxation (a quick ramp to 1 um in 12 ms, held
    to 3 s, 2000 samples) where a triangle cannot: noise-free within 1e-4 (measured 4.5e-6
    with 16 substeps; 5e-5 with 4, the ramp's 8 samples), and at 1 % noise within 3 standard
    errors and 3 % (measured: errors up to 1.4 %, relative standard errors 0.2-1.9 %)."""
    true = mv.Prony(G_inf=1e3, terms=((2e3, 0.03), (1.5e3, 0.5)))
    t_ramp, rate = 0.012, 1e-6 / 0.012
    t = np.linspace(0.0, 3.0, 2001)[1:]
    depth = rate * np.minimum(t, t_ramp)
    force = prony_ramp_hold(t, true, rate, t_ramp)
    tip = mv.Paraboloid(c=1 / (2 * R))
    exact = mv.fit(tip, mv.Prony, t, depth=depth, force=force, terms=2, substeps=16)
    errors = relative_errors(exact, parameters(true))
    assert max(abs(e) for e in errors.values()) < 1e-4, errors
    for seed in (7, 8):
        result = mv.fit(tip, mv.Prony, t, depth=depth, force=noisy(force, seed), terms=2)
        check_noisy(result, parameters(true))


def power_law_ramp_hold(t, medium, t_ramp):
    """Lee-Radok for a paraboloid pressed at rate V to t_ramp and held, G = G0 (t/t0)^-beta:
    F = 8 sqrt(R) V^1.5 G0 t0^beta int_0^min(t,t_ramp) (t - s)^-beta s^(1/2) ds; during the
    ramp t^(3/2-beta) B(1 - beta, 3/2), on the hold by quadrature with the algebraic weight."""
    g0, beta, t0 = medium.G0, medium.beta, medium.t0
    scale = 8.0 * math.sqrt(R) * V**1.5 * g0 * t0**beta
    out = []
    for now in t:
        if now <= t_ramp:
            out.append(now ** (1.5 - beta) * special.beta(1.0 - beta, 1.5))
        else:
            value, _ = integrate.quad(lambda s, now=now: (now - s) ** -beta, 0.0, t_ramp, weight="alg",
                                      wvar=(0.5, 0.0), epsabs=0.0, epsrel=1e-12)
            out.append(value)
    return scale * np.array(out)


def test_power_law_held_depth_is_the_closed_form():
    """A paraboloid jumped... pressed quickly and held: F = 16/3 sqrt(R) G(t) d^1.5 only for a
    step; for a ramp of length r the hereditary integral, which this checks the Scene's MDR
    and BEM against (Prony series of the power law over the run's range; measured 2e-4 MDR
    n = 8000 from its step error)."""
    true = mv.PowerLaw(G0=1e3, beta=0.2, t0=1.0)
    t_ramp = 0.1
    times = np.linspace(0.1, 2.0, 20)
    scene = mv.Scene(indenter=mv.Paraboloid(c=1 / (2 * R)), medium=true,
                     depth=([0.0, t_ramp, 2.0], [0.0, V * t_ramp, V * t_ramp]), duration=2.0, times=times,
                     dt=1e-3)
    exact = power_law_ramp_hold(times, true, t_ramp)
    mdr = mv.solve(scene, "mdr", 4000)
    assert np.max(np.abs(mdr.force / exact - 1.0)) < 1e-3


def test_power_law_step_is_exact_relaxation():
    """Depth held from t = 0 (a jump): F(t) = 16/3 sqrt(R) G(t) d^1.5 exactly; what is left
    is the series' error (bound 1e-5) and MDR's element count's."""
    true = mv.PowerLaw(G0=1e3, beta=0.3, t0=1.0)
    d = 1e-7
    times = np.geomspace(0.01, 1.0, 9)
    scene = mv.Scene(indenter=mv.Paraboloid(c=1 / (2 * R)), medium=true, depth=d, duration=1.0, times=times,
                     dt=1e-2)
    exact = 16.0 / 3.0 * math.sqrt(R) * true.relaxation_modulus(times) * d**1.5
    mdr = mv.solve(scene, "mdr", 20000)
    assert np.max(np.abs(mdr.force / exact - 1.0)) < 3e-4


def test_power_law_fit():
    """Noise-free (t0 held; measured 1e-5) and 1 % noise."""
    true = mv.PowerLaw(G0=1e3, beta=0.2, t0=1.0)
    t = np.linspace(0.0, 1.0, 101)[1:]
    force = power_law_ramp_hold(t, true, 0.5)
    depth = V * np.minimum(t, 0.5)
    tip = mv.Paraboloid(c=1 / (2 * R))
    exact = mv.fit(tip, mv.PowerLaw, t, depth=depth, force=force, substeps=4)
    assert "t0" not in exact.free
    for name in ("G0", "beta"):
        assert abs(exact.parameters[name] / getattr(true, name) - 1.0) < 1e-4
    result = mv.fit(tip, mv.PowerLaw, t, depth=depth, force=noisy(force, 5))
    check_noisy(result, {"G0": 1e3, "beta": 0.2})


@pytest.fixture(scope="module")
def bem_sphere():
    """A sphere pressed into a standard solid and pulled back, by BEM (n = 129) and by fine
    MDR (n = 20000): the BEM data and their discretisation error."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    radius, t = 5e-6, np.linspace(0.05, 1.0, 20)
    scene = mv.Scene(indenter=mv.Sphere(radius=radius), medium=true,
                     depth=([0.0, 0.5, 1.0], [0.0, 5e-7, 2e-7]), duration=1.0, times=t, dt=5e-3)
    bem = mv.solve(scene, "bem", 129)
    mdr = mv.solve(scene, "mdr", 20000)
    return true, scene, bem, mdr


def test_bem_sphere_is_recovered_to_its_discretisation_error(bem_sphere):
    """The BEM forces differ from MDR's by up to 6e-3 (measured 3.7e-3, largest at the first,
    shallowest samples); the fitted parameters inherit errors of that size (measured 2.8e-3)."""
    true, scene, bem, mdr = bem_sphere
    data_error = np.max(np.abs(bem.force / mdr.force - 1.0))
    assert data_error < 6e-3
    result = mv.fit(mv.Sphere(radius=5e-6), mv.StandardSolid, bem.t, depth=bem.depth, force=bem.force,
                    substeps=8)
    for name, e in relative_errors(result, parameters(true)).items():
        assert abs(e) < 2 * data_error, (name, e)


def test_bem_sphere_with_noise(bem_sphere):
    true, _, bem, _ = bem_sphere
    result = mv.fit(mv.Sphere(radius=5e-6), mv.StandardSolid, bem.t, depth=bem.depth,
                    force=noisy(bem.force, 13), substeps=8)
    check_noisy(result, parameters(true))


def test_creep_fit_under_force_control():
    """A paraboloid under a ramped force on a standard solid: depth from the closed-form
    creep compliance (Lee-Radok, contact growing: d^1.5 = 3/(16 sqrt R) int J(t-s) dF(s))."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t = np.linspace(0.0, 1.0, 201)[1:]
    rate = 1e-9  # N/s, F = rate * s
    s = np.linspace(0.0, 1.0, 20001)
    jt = true.creep_compliance(s)
    # int_0^t J(t - s) rate ds = rate int_0^t J(u) du
    cumulative = integrate.cumulative_trapezoid(jt, s, initial=0.0)
    depth = (3.0 / (16.0 * math.sqrt(R)) * rate * np.interp(t, s, cumulative)) ** (2.0 / 3.0)
    force = rate * t
    result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=force,
                    control="force", substeps=4)
    assert max(abs(e) for e in relative_errors(result, parameters(true)).values()) < 1e-4
    assert result.forward == "elements"  # force control: no closed form over the contact


def test_result_table_and_held_parameters():
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, depth = triangle()
    force, _, _ = ting_paraboloid_triangle(t, true, R, V, T_PEAK)
    result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid(1.5e3, 1e3, 0.2), t, depth=depth,
                    force=force, fixed=("tau1",))
    assert result.parameters["tau1"] == 0.2 and result.stderr["tau1"] == 0.0
    assert result.free == ["G_inf", "G1"]
    assert isinstance(result.medium, mv.StandardSolid)
    text = repr(result)
    assert "held" in text and "G_inf" in text and "StandardSolid" in text
    assert result.forward == "hereditary" and "(hereditary)" in text


def test_result_names_follow_scipy():
    """``cost`` is half the weighted sum of squared residuals; ``jac``, the weighted residuals'
    Jacobian in the parameters themselves, gives the standard errors (covariance 2 cost / dof
    (J^T J)^-1) and, the force being homogeneous of degree one in the moduli under depth
    control, sum_j G_j dr/dG_j = sqrt(w) model (Euler); ``status`` and ``success`` say why it
    stopped; the fitted values are ``parameters`` and ``medium``, not attributes."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, depth = triangle()
    force = noisy(ting_paraboloid_triangle(t, true, R, V, T_PEAK)[0], seed=5)
    w = np.linspace(1.0, 2.0, t.size)
    result = mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=force, weights=w)
    assert result.success and result.status in (1, 2, 3) and result.nfev > result.nit >= 1
    assert result.cost == pytest.approx(0.5 * np.sum(w * result.residuals**2), rel=1e-12)
    assert result.jac.shape == (t.size, 3) and result.free == ["G_inf", "G1", "tau1"]
    dof = t.size - 3
    covariance = 2.0 * result.cost / dof * np.linalg.inv(result.jac.T @ result.jac)
    for name, variance in zip(result.free, np.diag(covariance)):
        assert math.sqrt(variance) == pytest.approx(result.stderr[name], rel=1e-6), name
    euler = result.parameters["G_inf"] * result.jac[:, 0] + result.parameters["G1"] * result.jac[:, 1]
    assert np.allclose(euler, np.sqrt(w) * result.model, rtol=1e-9, atol=1e-12 * np.max(result.model))
    assert result.medium.G1 == result.parameters["G1"]
    with pytest.raises(AttributeError):
        result.G1  # noqa: B018
    stopped = mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=force, max_iter=1)
    assert not stopped.success and stopped.status == 0 and stopped.nit == 1
    assert "not converged" in repr(stopped) and "1 iterations" in stopped.message
    mv.Scene(indenter=mv.Paraboloid(c=1 / (2 * R)), medium=result.medium, force=1e-9, duration=1.0)


def test_unidentified_parameters_warn_by_name():
    """A standard solid fitted to an elastic curve: the relaxing part is not determined."""
    t, depth = triangle()
    force, _, _ = ting_paraboloid_triangle(t, mv.Elastic(G=2e3), R, V, T_PEAK)
    with pytest.warns(mv.IdentifiabilityWarning, match="tau1|G1"):
        mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=noisy(force, 1))


@pytest.mark.parametrize("change, match", [
    (lambda t, d, f: (t, d, np.where(np.arange(t.size) == 5, np.nan, f)), "force must be finite.*index 5"),
    (lambda t, d, f: (t[::-1].copy(), d, f), "unsorted"),
    (lambda t, d, f: (np.concatenate([t[:3], t[2:-1]]), d, f), "duplicate"),
    (lambda t, d, f: (t, -d, f), "no contact"),
    (lambda t, d, f: (t, d[:-1], f), "depth has"),
    (lambda t, d, f: (t[:3], d[:3], f[:3]), "3 samples with positive weight for 3 free"),
])
def test_bad_data_is_refused_by_name(change, match):
    t, depth = triangle(50)
    force, _, _ = ting_paraboloid_triangle(t, mv.Elastic(G=2e3), R, V, T_PEAK)
    t, depth, force = change(t, depth, force)
    with pytest.raises(mv.DataError, match=match):
        mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=force)


def test_unknown_fixed_names_are_refused():
    t, depth = triangle(50)
    force, _, _ = ting_paraboloid_triangle(t, mv.Elastic(G=2e3), R, V, T_PEAK)
    with pytest.raises(mv.InvalidInputError, match="tau9"):
        mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid(1.0, 1.0, 1.0), t, depth=depth, force=force,
               fixed=("tau9",))


@pytest.mark.parametrize("n", [7, 2**26 + 1, 4_571_058_572])
def test_resolutions_out_of_range_are_refused_before_allocating(n):
    """n above the core's MDR limit (2**26 elements) is refused by name rather than building
    a profile of n elements (4.6e9 of them: 34 GiB)."""
    t, depth = triangle(50)
    force, _, _ = ting_paraboloid_triangle(t, mv.Elastic(G=2e3), R, V, T_PEAK)
    assert mv._core.MAX_N["mdr"] == 2**26
    with pytest.raises(mv.InvalidInputError, match=r"fit: n must be an integer in \[8, 67108864\]"):
        mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.Elastic, t, depth=depth, force=force, n=n)


def test_levenberg_marquardt_matches_scipy():
    """An exponential decay with offset, from a poor start: the same minimum as scipy's
    trust-region least squares (to 1e-8)."""
    from scipy.optimize import least_squares

    x = np.linspace(0.0, 4.0, 50)
    y = 2.0 + 3.0 * np.exp(-x / 0.7) + 0.01 * np.random.default_rng(0).standard_normal(x.size)

    def residuals(p):
        a, b, tau = np.exp(p)
        e = np.exp(-x / tau)
        r = a + b * e - y
        return r, np.column_stack([a * np.ones_like(x), b * e, b * e * x / tau])

    ours = levenberg_marquardt(residuals, np.log([0.5, 0.5, 5.0]))
    theirs = least_squares(lambda p: residuals(p)[0], np.log([0.5, 0.5, 5.0]), jac=lambda p: residuals(p)[1],
                           xtol=1e-14, ftol=1e-14, gtol=1e-14)
    assert ours.converged and ours.status > 0
    assert np.allclose(ours.x, theirs.x, rtol=0, atol=1e-8)


def test_command_line_fit(tmp_path, capsys):
    """``mdrvisc fit`` on a CSV curve: the table, and JSON with the same parameters."""
    import json

    from mdrvisc.cli import main

    t, depth = triangle(100)
    force, _, _ = ting_paraboloid_triangle(t, mv.StandardSolid(1e3, 2e3, 0.2), R, V, T_PEAK)
    path = tmp_path / "curve.csv"
    np.savetxt(path, np.column_stack([t, depth, force]), delimiter=",", header="t,depth,force", comments="")
    args = [str(path), "--indenter", f"paraboloid:c={1 / (2 * R)}", "--model", "standardsolid"]
    assert main(["fit", *args]) == 0
    assert "StandardSolid" in capsys.readouterr().out
    assert main(["fit", *args, "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert abs(document["parameters"]["tau1"] / 0.2 - 1) < 1e-3
    assert document["success"] is True and document["status"] > 0 and document["nit"] < document["nfev"]
    assert document["cost"] >= 0 and "solves" not in document and "converged" not in document
    assert main(["fit", *args[:2], "blob:r=1", *args[3:]]) == 2


def test_weights_select_the_samples_that_count():
    """Ting's standard solid with the retract corrupted (forces 10 % high): zero weight on it
    recovers the medium from the approach alone (measured 8e-6), the corrupted values no
    longer matter at all, uniform weights do not recover it (measured 4-40 % off), and scaling
    all weights changes nothing."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, depth = triangle(400)
    force, _, _ = ting_paraboloid_triangle(t, true, R, V, T_PEAK)
    retract = t > T_PEAK
    corrupted = np.where(retract, 1.1 * force, force)
    tip = mv.Paraboloid(c=1 / (2 * R))
    approach_only = np.where(retract, 0.0, 1.0)
    picked = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=corrupted, weights=approach_only, substeps=4)
    errors = relative_errors(picked, parameters(true))
    print("approach only", errors)
    assert max(abs(e) for e in errors.values()) < 1e-4, errors
    other = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=np.where(retract, 3.0 * force, force),
                   weights=approach_only, substeps=4)
    for name, value in picked.parameters.items():
        assert abs(other.parameters[name] / value - 1.0) < 1e-9
    uniform = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=corrupted, substeps=4)
    errors = relative_errors(uniform, parameters(true))
    print("uniform", errors)
    assert max(abs(e) for e in errors.values()) > 0.02, errors
    scaled = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=corrupted, weights=7.0 * approach_only,
                    substeps=4)
    for name, value in picked.parameters.items():
        assert abs(scaled.parameters[name] / value - 1.0) < 1e-9
        assert abs(scaled.stderr[name] - picked.stderr[name]) <= 1e-6 * picked.stderr[name]


def test_heavier_weight_pulls_the_fit_towards_a_segment():
    """Data of two media: the approach from one standard solid, the retract from another
    (G_inf 20 % higher). The retract's residual shrinks as its weight grows."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    other = mv.StandardSolid(G_inf=1.2e3, G1=2e3, tau1=0.2)
    t, depth = triangle(400)
    retract = t > T_PEAK
    force = np.where(retract, ting_paraboloid_triangle(t, other, R, V, T_PEAK)[0],
                     ting_paraboloid_triangle(t, true, R, V, T_PEAK)[0])
    tip = mv.Paraboloid(c=1 / (2 * R))
    misfits = []
    for heavy in (0.1, 1.0, 10.0):
        result = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=force,
                        weights=np.where(retract, heavy, 1.0))
        misfits.append((np.sqrt(np.mean(result.residuals[retract] ** 2)),
                        np.sqrt(np.mean(result.residuals[~retract] ** 2))))
    print(misfits)
    retract_rms, approach_rms = zip(*misfits)
    assert retract_rms[0] > retract_rms[1] > retract_rms[2]
    assert approach_rms[0] < approach_rms[1] < approach_rms[2]


@pytest.mark.parametrize("weights, match", [
    (np.zeros(50), "not all zero"),
    (np.where(np.arange(50) == 3, -1.0, 1.0), ">= 0"),
    (np.ones(49), "weights has 49"),
    (np.where(np.arange(50) < 3, 1.0, 0.0), "3 samples with positive weight"),
])
def test_bad_weights_are_refused(weights, match):
    t, depth = triangle(50)
    force, _, _ = ting_paraboloid_triangle(t, mv.Elastic(G=2e3), R, V, T_PEAK)
    with pytest.raises(mv.DataError, match=match):
        mv.fit(mv.Paraboloid(c=1 / (2 * R)), mv.StandardSolid, t, depth=depth, force=force, weights=weights)


def creep_ramp_hold(true, t, t_ramp=0.05, f_max=1e-9):
    """A paraboloid under a force ramped to f_max (N) over t_ramp (s) and held, on a
    standard solid: depth from the creep compliance (Lee-Radok, the contact grows:
    d^1.5 = 3/(16 sqrt R) int J(t - s) dF(s)), the integral of J by the trapezoidal rule on
    200001 points (relative error ~1e-9)."""
    s = np.linspace(0.0, float(t[-1]), 200001)
    cumulative = integrate.cumulative_trapezoid(true.creep_compliance(s), s, initial=0.0)
    top = np.minimum(t, t_ramp)
    impulse = f_max / t_ramp * (np.interp(t, s, cumulative) - np.interp(t - top, s, cumulative))
    depth = (3.0 / (16.0 * math.sqrt(R)) * impulse) ** (2.0 / 3.0)
    return depth, f_max * np.minimum(t / t_ramp, 1.0)


@pytest.mark.parametrize("seed", [2, 8])
def test_noisy_creep_fit_under_force_control(seed):
    """1 % Gaussian noise on the measured depths of a creep curve (ramp 0.05 s, hold to 2 s,
    ten relaxation times): relative standard errors 0.2-1.6 %; measured within 0.6 standard
    errors and 0.9 % (seeds 2, 8, 3). Noise-free: measured 1.5e-6."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t = np.linspace(0.0, 2.0, 401)[1:]
    depth, force = creep_ramp_hold(true, t)
    tip = mv.Paraboloid(c=1 / (2 * R))
    exact = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=force, control="force", substeps=4)
    assert max(abs(e) for e in relative_errors(exact, parameters(true)).values()) < 1e-4
    result = mv.fit(tip, mv.StandardSolid, t, depth=noisy(depth, seed), force=force, control="force")
    check_noisy(result, parameters(true))


def test_bem_cone_is_recovered_to_its_discretisation_error():
    """A cone pressed at rate V into a standard solid and held, by BEM (n = 65): its forces
    differ from Lee-Radok's closed form (``cone_ramp_hold``) by the BEM's discretisation
    error (measured 3.1e-3, with its time step); the fitted parameters are within twice that
    (measured 3.7e-4)."""
    true, slope = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2), 0.5
    t = np.linspace(0.1, 2.0, 20)
    scene = mv.Scene(indenter=mv.Cone(slope=slope), medium=true, depth=([0.0, 1.0, 2.0], [0.0, V, V]),
                     duration=2.0, times=t, dt=5e-3)
    bem = mv.solve(scene, "bem", 65)
    exact = cone_ramp_hold(t, true, slope, 1.0)
    data_error = np.max(np.abs(bem.force / exact - 1.0))
    print("data error", data_error)
    result = mv.fit(mv.Cone(slope=slope), mv.StandardSolid, t, depth=bem.depth, force=bem.force, substeps=8)
    errors = relative_errors(result, parameters(true))
    print("fit errors", errors)
    for name, e in errors.items():
        assert abs(e) < 2 * data_error, (name, e, data_error)


@pytest.mark.parametrize("medium", [mv.Elastic(G=2e3), mv.Viscous(eta=500.0),
                                    mv.KelvinVoigt(G=1e3, eta=300.0), mv.Maxwell(G=2e3, eta=600.0),
                                    mv.StandardSolid(1e3, 2e3, 0.2),
                                    mv.Prony(1e3, ((2e3, 0.03), (1.5e3, 0.5))), mv.PowerLaw(1e3, 0.2, 1.0)],
                         ids=_name)
def test_derived_modulus_column_is_the_forward_models_own(medium):
    """Under depth control one modulus's column of the Jacobian is the force minus the other
    moduli's (the force is proportional to the moduli together); against the column the
    forward model computes itself (measured agreement ~1e-13 of the largest entry)."""
    import json

    from mdrvisc._fit_model import curves, moduli, with_derived

    t, depth = triangle(100)
    tip = mv.Paraboloid(c=1 / (2 * R))
    curve, _ = curves(tip, t, depth, depth, "depth", "depth", 300, 2)
    free = [name for name in parameters(medium) if name != "t0"]
    derived = moduli(parameters(medium))[0]
    asked = [name for name in free if name != derived]
    model = [json.dumps(medium._model())]
    values, full, _, _ = curve.evaluate(model, free)[0]
    _, jac, _, _ = curve.evaluate(model, asked)[0]
    rebuilt = with_derived(values, jac, free, asked)
    assert np.max(np.abs(rebuilt - full)) <= 1e-10 * np.max(np.abs(full))
