"""Fits to raw AFM curves (piezo displacement, cantilever deflection, spring constant) with
the contact point and the deflection baseline fitted: curves made from closed forms
independent of the fit's forward model (Ting's paraboloid, Lee-Radok for the cone and the
power law, see test_fit.py), turned into a raw curve with a known contact point z_c,
baseline b and spring constant k: deflection = F / k + b, z = z_c + indentation + F / k."""

import json
import math

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc._fit_model import parameters
from mdrvisc.analytic import ting_paraboloid_triangle
from mdrvisc.cli import main
from test_fit import T_PEAK, R, V, cone_ramp_hold, power_law_ramp_hold

# contact point (m), baseline (m), spring constant (N/m): the largest deflection change is
# 7 % of the largest indentation. The fit's model is the cantilever in series with the
# sample, so the deflection's noise stays in the data (a model prescribing the indentation
# (z - z_c) - (deflection - b) put it into the depths too, and at k = 0.05 N/m fitted the
# standard solid's moduli 2-3.5 % low, about 3 standard errors; test_soft_cantilever).
Z_C, BASELINE, K = 2.0e-6, 3.0e-8, 0.5
T_C = 0.5037  # time of contact (s): between samples
PARABOLOID = mv.Paraboloid(c=1 / (2 * R))


def raw_curve(indentation, force, seed=None, level=0.01, k=K):
    """Piezo and deflection of a curve of ``indentation`` (m, < 0 before contact) and
    ``force`` (N) with a cantilever of spring constant ``k`` (N/m); with ``seed``, Gaussian
    noise of ``level`` times the largest deflection change on the deflection (the piezo is
    exact)."""
    bend = force / k
    deflection = bend + BASELINE
    if seed is not None:
        rng = np.random.default_rng(seed)
        deflection = deflection + level * np.max(bend) * rng.standard_normal(bend.size)
    return Z_C + indentation + bend, deflection


def ting_raw(medium, samples=500, seed=None, k=K):
    """Approach from 0.5 um above the surface at V, contact at T_C, Ting's triangle of
    T_PEAK up and T_PEAK back (the indentation returns to zero), about ``samples`` samples
    with one at the turning point and one 1 ns after it (the forward model's drive is
    linear between samples; a dashpot's force, and with it this curve's piezo, jumps at
    the turn, which the second sample lets the model follow)."""
    dt = (T_C + 2 * T_PEAK) / samples
    t = T_C + T_PEAK + dt * np.arange(-round((T_C + T_PEAK) / dt), round(T_PEAK / dt) + 1)
    turn = int(np.argmin(np.abs(t - T_C - T_PEAK)))
    t = np.insert(t, turn + 1, t[turn] + 1e-9)
    s = t - T_C
    indentation = np.where(s <= T_PEAK, V * s, V * (2 * T_PEAK - s))
    assert np.min(np.abs(s - T_PEAK)) < 1e-12
    force = np.zeros_like(t)
    inside = s > 0
    force[inside], _, _ = ting_paraboloid_triangle(s[inside], medium, R, V, T_PEAK)
    z, deflection = raw_curve(indentation, force, seed, k=k)
    return t, z, deflection, indentation


def check_raw(result, true, percent=0.03, sigmas=3.0):
    depth_max = V * T_PEAK
    for name, value in true.items():
        fitted, err = result.parameters[name], result.stderr[name]
        assert abs(fitted - value) <= sigmas * err, f"{name}: {fitted} vs {value} +- {err}"
        assert abs(fitted / value - 1.0) <= percent, f"{name}: {fitted} vs {value}"
    err = result.stderr["contact_point"]
    assert abs(result.contact_point - Z_C) <= sigmas * err, (result.contact_point, err)
    assert abs(result.contact_point - Z_C) <= 0.01 * depth_max, result.contact_point
    assert abs(result.baseline - BASELINE) <= sigmas * result.stderr["baseline"]


# (a dashpot's force follows the contact's growth within each step and each element, a
# first-order error in the step and the element: 40 substeps, as in test_fit.py, and 2000
# elements; with 500 the parameters and the contact point are off by 1e-3)
TING_MEDIA = [
    (mv.Elastic(G=2e3), {}),
    (mv.Viscous(eta=500.0), {"substeps": 40, "n": 2000}),
    (mv.KelvinVoigt(G=1e3, eta=300.0), {"substeps": 40, "n": 2000}),
    (mv.Maxwell(G=2e3, eta=600.0), {}),
    (mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2), {}),
    (mv.Prony(G_inf=1e3, terms=((2e3, 0.03), (1.5e3, 0.5))), {"terms": 2}),
]


@pytest.mark.parametrize("true, options", TING_MEDIA, ids=[type(m).__name__ for m, _ in TING_MEDIA])
def test_noise_free_raw_curve_recovers_contact_point_and_medium(true, options):
    """Every medium of Ting's paraboloid from the class alone, the contact point and the
    baseline estimated from the curve. Measured worst: parameters 1.3e-4 (Prony G1: this
    curve's piezo z_c + indentation + F / k is curved between samples where the model's
    drive is linear; 8e-5 Viscous eta, 3e-6 standard solid), contact point 3.3e-5 of the
    largest indentation (1e-6 without a dashpot), baseline 7.4e-6 of the largest
    deflection."""
    t, z, deflection, _ = ting_raw(true)
    result = mv.fit(PARABOLOID, type(true), t, piezo=z, deflection=deflection, spring_constant=K,
                    **{"substeps": 8, **options})
    assert result.success, result.message
    true_values = parameters(true)
    errors = {name: result.parameters[name] / value - 1 for name, value in true_values.items()}
    print(type(true).__name__, errors, (result.contact_point - Z_C) / (V * T_PEAK),
          (result.baseline - BASELINE) / np.ptp(deflection), result.nfev)
    assert max(abs(e) for e in errors.values()) < 3e-4, errors
    assert abs(result.contact_point - Z_C) < 3e-4 * V * T_PEAK
    assert abs(result.baseline - BASELINE) < 1e-4 * np.ptp(deflection)


def test_soft_cantilever():
    """k = 0.05 N/m (the deflection 0.7 times the indentation), 1 % deflection noise, 20
    seeds: no bias from the deflection's noise (each parameter's mean relative error within
    3 standard errors of the mean of zero; a model prescribing the indentation from the
    noisy deflection was 2-3.5 % low) and standard errors of the right size (the spread of
    (fitted - true) / stderr below 2; measured over 30 seeds 0.78-0.86 for the medium, 0.79
    for the contact point, 1.06 for the baseline; it was 1.05-1.52 while the fit's Jacobian
    took a modulus's column from the others by Euler's relation, which the cantilever
    breaks: test_fit_convergence.py holds the ratio to 0.8-1.25 over 150 draws). At
    k = 0.01 N/m (deflection 3.5 times the indentation) the fit from the class alone can
    stop in other minima of a flat valley; from the true medium it lands within 2.2
    standard errors."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    errors, scores = [], []
    for seed in range(20):
        t, z, deflection, _ = ting_raw(true, seed=seed, k=0.05)
        result = mv.fit(PARABOLOID, mv.StandardSolid, t, piezo=z, deflection=deflection, spring_constant=0.05)
        assert result.success, result.message
        errors.append([result.parameters[n] / v - 1.0 for n, v in parameters(true).items()])
        scores.append([(result.parameters[n] - v) / result.stderr[n]
                       for n, v in parameters(true).items()])
    errors, scores = np.array(errors), np.array(scores)
    mean, spread = errors.mean(axis=0), errors.std(axis=0, ddof=1)
    assert np.all(np.abs(mean) <= 3.0 * spread / math.sqrt(len(errors))), (mean, spread)
    assert np.all(scores.std(axis=0, ddof=1) < 2.0), scores.std(axis=0, ddof=1)


@pytest.mark.parametrize("offset", [0.0, -0.2, 0.2], ids=["estimated", "early", "late"])
def test_noisy_raw_curve_within_three_standard_errors(offset):
    """1 % deflection noise; the contact point estimated from the curve, or given 20 % of the
    largest indentation too early or too late."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, z, deflection, _ = ting_raw(true, 1000, seed=5)
    guess = None if offset == 0.0 else Z_C + offset * V * T_PEAK
    result = mv.fit(PARABOLOID, mv.StandardSolid, t, piezo=z, deflection=deflection, spring_constant=K,
                    contact_point=guess)
    print(result)
    assert result.success, result.message
    check_raw(result, parameters(true))
    # jac is in the parameters themselves, the contact point and baseline in m: it gives
    # their standard errors as the fit does, covariance 2 cost / dof (J^T J)^-1
    covariance = 2.0 * result.cost / (t.size - len(result.free)) * np.linalg.inv(result.jac.T @ result.jac)
    for name, variance in zip(result.free, np.diag(covariance)):
        assert math.sqrt(variance) == pytest.approx(result.stderr[name], rel=1e-6), name


def test_noisy_raw_cone_ramp_and_hold():
    """A cone (Lee-Radok ramp and hold) on a Maxwell medium, 1 % deflection noise."""
    true, slope = mv.Maxwell(G=2e3, eta=600.0), 0.5
    t = np.linspace(0.0, T_C + 2.0, 600)
    s = t - T_C
    indentation = V * np.minimum(s, 1.0)
    force = np.zeros_like(t)
    force[s > 0] = cone_ramp_hold(s[s > 0], true, slope, 1.0)
    z, deflection = raw_curve(indentation, force, seed=9)
    result = mv.fit(mv.Cone(slope=slope), mv.Maxwell, t, piezo=z, deflection=deflection, spring_constant=K)
    print(result)
    check_raw(result, parameters(true))


def test_noisy_raw_power_law():
    """A paraboloid on a power-law medium (Lee-Radok ramp and hold), 1 % deflection noise."""
    true = mv.PowerLaw(G0=1e3, beta=0.2, t0=1.0)
    t = np.linspace(0.0, T_C + 1.0, 300)
    s = t - T_C
    indentation = V * np.minimum(s, 0.5)
    force = np.zeros_like(t)
    force[s > 0] = power_law_ramp_hold(s[s > 0], true, 0.5)
    z, deflection = raw_curve(indentation, force, seed=4)
    result = mv.fit(PARABOLOID, mv.PowerLaw, t, piezo=z, deflection=deflection, spring_constant=K)
    print(result)
    check_raw(result, {"G0": 1e3, "beta": 0.2})


def test_raw_curve_without_contact_is_refused():
    t = np.linspace(0.0, 1.0, 200)
    z = Z_C - 1e-6 + V * t
    deflection = BASELINE + 1e-10 * np.random.default_rng(0).standard_normal(t.size)
    with pytest.raises(mv.DataError, match="never reaches contact"):
        mv.fit(PARABOLOID, mv.Elastic, t, piezo=z, deflection=deflection, spring_constant=K)


def test_raw_curve_without_baseline_is_refused():
    t, z, deflection, indentation = ting_raw(mv.Elastic(G=2e3), 500, seed=1)
    inside = indentation > 0.05 * V
    with pytest.raises(mv.DataError, match="contact-free start"):
        mv.fit(PARABOLOID, mv.Elastic, t[inside], piezo=z[inside], deflection=deflection[inside],
               spring_constant=K)
    with pytest.raises(mv.DataError, match="contact-free start"):
        mv.fit(PARABOLOID, mv.Elastic, t[:6], piezo=z[:6], deflection=deflection[:6], spring_constant=K)


def test_raw_input_is_one_kind_or_the_other():
    t, z, deflection, indentation = ting_raw(mv.Elastic(G=2e3), 100)
    with pytest.raises(mv.InvalidInputError, match="spring_constant"):
        mv.fit(PARABOLOID, mv.Elastic, t, piezo=z, deflection=deflection)
    with pytest.raises(mv.InvalidInputError, match="raw AFM"):
        mv.fit(PARABOLOID, mv.Elastic, t, depth=indentation, force=deflection, piezo=z)
    with pytest.raises(mv.InvalidInputError, match="spring_constant must be > 0"):
        mv.fit(PARABOLOID, mv.Elastic, t, piezo=z, deflection=deflection, spring_constant=-1.0)
    with pytest.raises(mv.InvalidInputError, match="depth-controlled"):
        mv.fit(PARABOLOID, mv.Elastic, t, piezo=z, deflection=deflection, spring_constant=K, control="force")


def test_held_contact_point_and_table():
    """Held at the true value: only the medium and the baseline are fitted; the table names
    both."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, z, deflection, _ = ting_raw(true, 500)
    result = mv.fit(PARABOLOID, mv.StandardSolid, t, piezo=z, deflection=deflection, spring_constant=K,
                    contact_point=Z_C, fixed=("contact_point",), substeps=8)
    assert result.free == ["G_inf", "G1", "tau1", "baseline"]
    assert result.contact_point == Z_C and result.stderr["contact_point"] == 0.0
    text = repr(result)
    assert "contact_point" in text and "baseline" in text and "held" in text
    assert np.allclose(result.depth, z - Z_C - (deflection - result.baseline))


def test_command_line_fits_a_raw_curve(tmp_path, capsys):
    """``mdrvisc fit`` on a CSV of t, piezo, deflection with --spring-constant: the medium and
    the contact point of Ting's curve (noise-free; the same accuracy as the Python call, see
    the first test), in the table and the JSON; without the spring constant the missing
    columns are named with the hint."""
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)
    t, z, deflection, _ = ting_raw(true)
    path = tmp_path / "raw.csv"
    np.savetxt(path, np.column_stack([t, z, deflection]), delimiter=",", header="t,piezo,deflection",
               comments="")
    args = [str(path), "--indenter", f"paraboloid:c={1 / (2 * R)}", "--model", "standardsolid",
            "--spring-constant", str(K), "--substeps", "8"]
    assert main(["fit", *args]) == 0
    assert "contact_point" in capsys.readouterr().out
    assert main(["fit", *args, "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for name, value in parameters(true).items():
        assert abs(out["parameters"][name] / value - 1) < 3e-4, (name, out["parameters"][name])
    assert abs(out["contact_point"] - Z_C) < 3e-4 * V * T_PEAK
    assert main(["fit", *args[:-4]]) == 2
    assert "needs --spring-constant" in capsys.readouterr().err
