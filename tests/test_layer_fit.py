"""A layer's thickness fitted with the medium (``mv.fit(..., body=mv.Layer(h0),
fit_thickness=True)``) on curves made by BEM (``mv.solve(..., "bem")``), independent of the
fit's MDR forward model.

The bound: with noise the fitted thickness and modulus lie within 3 of their reported
standard errors of the truth, plus 0.5 % for BEM's discretisation at n = 65 (MDR on a
layer against BEM: 0.02 % in force, docs/layers.md, and BEM at n = 65 against n = 129
0.01 %: 0.5 % leaves the thickness's weaker leverage on the force room), and the standard
errors themselves are a claim (below 10 %); without noise within 0.5 %. A half-space's
curve must not yield a precise thickness."""

import functools

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.errors import IdentifiabilityWarning, InvalidInputError

TIP = mv.Paraboloid(c=0.5)  # R = 1
H = 0.5  # contact up to 0.76 thicknesses at the largest force
FORCES = np.linspace(0.1, 1.0, 10)
NOISE = 0.01
BEM_ERROR = 5e-3
STANDARD_SOLID = dict(G_inf=1.0, G1=2.0, tau1=0.2)


@functools.cache
def elastic_curve(layered: bool, thickness: float = H) -> tuple[np.ndarray, np.ndarray]:
    """Depths of an incompressible elastic layer (G = 1) of ``thickness``, or the half-space,
    under FORCES by static BEM solves, and the forces with 1 % noise (of the largest)."""
    body = mv.Layer(thickness) if layered else None
    depth = np.array([mv.solve(mv.Scene(indenter=TIP, medium=mv.Elastic(G=1.0, nu=0.5), force=f, body=body),
                               "bem", 65).depth[-1] for f in FORCES])
    noise = NOISE * FORCES.max() * np.random.default_rng(7).standard_normal(FORCES.size)
    return depth, FORCES + noise


def within(fit, name, value, truth):
    """The fitted ``value`` of ``name`` within 3 standard errors and BEM's error of ``truth``."""
    err = fit.stderr[name]
    assert err < 0.1 * truth, (name, value, err)
    assert abs(value - truth) < 3 * err + BEM_ERROR * truth, (name, value, err, truth)


def test_an_elastic_layers_thickness_is_fitted():
    depth, force = elastic_curve(True)
    t = np.arange(1.0, FORCES.size + 1)
    fit = mv.fit(TIP, mv.Elastic, t, depth=depth, force=force, body=mv.Layer(2 * H), fit_thickness=True,
                 n=200)
    assert fit.success, fit.message
    assert fit.free == ["G", "thickness"]
    within(fit, "thickness", fit.body.thickness, H)
    within(fit, "G", fit.parameters["G"], 1.0)
    # the modulus and the thickness trade off (a thinner layer looks stiffer): correlated
    assert fit.correlation[0, 1] == fit.correlation[1, 0] > 0.9
    assert fit.jac.shape == (FORCES.size, 2)
    # the joint standard error of G exceeds the one at a known thickness
    known = mv.fit(TIP, mv.Elastic, t, depth=depth, force=force, body=mv.Layer(fit.body.thickness), n=200)
    assert fit.stderr["G"] > 2 * known.stderr["G"]
    assert "thickness" in repr(fit)


@functools.cache
def creep_curve() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Times, depths and forces of a standard solid (STANDARD_SOLID) layer of thickness H
    under a depth ramp to 0.15 R and hold, by BEM at 50 samples."""
    scene = mv.Scene(indenter=TIP, medium=mv.StandardSolid(**STANDARD_SOLID),
                     depth=([0.0, 0.3, 1.0], [0.0, 0.15, 0.15]), duration=1.0, body=mv.Layer(H),
                     times=np.linspace(0.02, 1.0, 50))
    bem = mv.solve(scene, "bem", 65)
    return bem.t, bem.depth, bem.force


def test_a_viscoelastic_layers_thickness_is_fitted():
    """Without noise the thickness and the relaxed modulus come back within BEM's
    discretisation error (0.5 %), the relaxing part within the 1 % the fit at a known
    thickness is held to on a BEM creep curve (tests/test_layer_mdr.py); thickness from a
    guess of 2 H."""
    t, depth, force = creep_curve()
    fit = mv.fit(TIP, mv.StandardSolid, t, depth=depth, force=force, body=mv.Layer(2 * H), fit_thickness=True,
                 n=200)
    assert fit.success, fit.message
    assert abs(fit.body.thickness / H - 1) < BEM_ERROR, fit
    assert abs(fit.parameters["G_inf"] / STANDARD_SOLID["G_inf"] - 1) < BEM_ERROR, fit
    for name in ("G1", "tau1"):
        assert abs(fit.parameters[name] / STANDARD_SOLID[name] - 1) < 1e-2, fit


def test_a_viscoelastic_layers_thickness_is_fitted_through_noise():
    """The same curve's force with 1 % noise (of the largest): thickness and relaxed
    modulus within 3 standard errors + 0.5 %."""
    t, depth, force = creep_curve()
    noisy = force + NOISE * force.max() * np.random.default_rng(8).standard_normal(t.size)
    fit = mv.fit(TIP, mv.StandardSolid, t, depth=depth, force=noisy, body=mv.Layer(2 * H), fit_thickness=True,
                 n=200)
    assert fit.success, fit.message
    assert fit.free == ["G_inf", "G1", "tau1", "thickness"]
    within(fit, "thickness", fit.body.thickness, H)
    within(fit, "G_inf", fit.parameters["G_inf"], STANDARD_SOLID["G_inf"])


def test_a_half_spaces_curve_claims_no_thickness():
    """On a half-space's curve the search runs thick and the thickness is reported as not
    determined (a warning, and no standard error below half the value), the modulus still
    the half-space's."""
    depth, force = elastic_curve(False)
    t = np.arange(1.0, FORCES.size + 1)
    with pytest.warns(IdentifiabilityWarning, match="thickness"):
        fit = mv.fit(TIP, mv.Elastic, t, depth=depth, force=force, body=mv.Layer(H), fit_thickness=True,
                     n=200)
    assert not fit.stderr["thickness"] < 0.5 * fit.body.thickness
    assert fit.body.thickness > 10 * H
    assert abs(fit.parameters["G"] - 1.0) < 3 * fit.stderr["G"] + BEM_ERROR


def test_a_contact_small_against_the_thickness_is_reported():
    """A layer 8 H thick, the contact below 0.2 thicknesses: the fit warns that the
    thickness is weakly determined (here from noise-free data, so it is still found, within
    BEM's error over the thickness's leverage on the force, ~ a/h)."""
    depth, _ = elastic_curve(True, 8 * H)
    t = np.arange(1.0, FORCES.size + 1)
    with pytest.warns(IdentifiabilityWarning, match="weakly determined"):
        fit = mv.fit(TIP, mv.Elastic, t, depth=depth, force=FORCES, body=mv.Layer(4 * H), fit_thickness=True,
                     n=200)
    reach = TIP.contact_radius_at_depth(depth.max()) / (8 * H)
    assert reach < 0.2
    assert abs(fit.body.thickness / (8 * H) - 1) < BEM_ERROR / reach, fit


def test_what_a_thickness_fit_does_not_take_is_refused():
    depth, force = elastic_curve(True)
    t = np.arange(1.0, FORCES.size + 1)
    with pytest.raises(InvalidInputError, match="fit_thickness needs body"):
        mv.fit(TIP, mv.Elastic, t, depth=depth, force=force, fit_thickness=True)
    with pytest.raises(InvalidInputError, match="raw AFM"):
        mv.fit(TIP, mv.Elastic, t, piezo=depth + 1e-3, deflection=force, spring_constant=1.0,
               body=mv.Layer(H), fit_thickness=True)
    with pytest.raises(InvalidInputError, match="layer"):
        mv.fit(TIP, mv.Elastic, t, depth=depth, force=force, body=mv.Layer(H), fit_thickness=True,
               contact=mv.JKR(work_of_adhesion=0.1))
    with pytest.raises(InvalidInputError, match="thickness"):
        mv.Layer(0.0)
