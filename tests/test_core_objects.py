"""Indenters and media hold the compiled core's objects: the media's closed forms written
here against theirs, parameter names and rebuilding by name, a tabulated disc filled by
Lee-Radok, a profile function's errors, and pickling."""

import math
import pickle

import numpy as np
import pytest
from scipy.special import gamma

import mdrvisc as mv
from mdrvisc import _core

T = np.array([[0.0, 0.01, 0.3], [1.0, 2.5, 40.0]])

MEDIA = [mv.Elastic(2.0, nu=0.3), mv.Viscous(1.5), mv.KelvinVoigt(1.0, 0.5), mv.Maxwell(2.0, 0.6),
         mv.StandardSolid(1.0, 3.0, 0.5, nu=0.4), mv.Prony(0.5, ((1.0, 0.1), (2.0, 2.0))),
         mv.PowerLaw(2.0, 0.2, 0.7, nu=0.1)]


def closed_forms(medium, t):
    """(G(t), J(t)) written here, for the media with closed forms of both."""
    with np.errstate(divide="ignore"):
        if isinstance(medium, mv.Elastic):
            return np.full_like(t, medium.G), np.full_like(t, 1.0 / medium.G)
        if isinstance(medium, mv.Viscous):
            return np.zeros_like(t), t / medium.eta
        if isinstance(medium, mv.KelvinVoigt):
            return np.full_like(t, medium.G), (1.0 - np.exp(-medium.G * t / medium.eta)) / medium.G
        if isinstance(medium, mv.Maxwell):
            return medium.G * np.exp(-t * medium.G / medium.eta), 1.0 / medium.G + t / medium.eta
        if isinstance(medium, mv.StandardSolid):
            g0 = medium.G_inf + medium.G1
            return (medium.G_inf + medium.G1 * np.exp(-t / medium.tau1),
                    1.0 / medium.G_inf + (1.0 / g0 - 1.0 / medium.G_inf)
                    * np.exp(-medium.G_inf * t / (g0 * medium.tau1)))
        if isinstance(medium, mv.PowerLaw):
            scale = gamma(1.0 - medium.beta) * gamma(1.0 + medium.beta)
            return (medium.G0 * (t / medium.t0) ** -medium.beta,
                    (t / medium.t0) ** medium.beta / (medium.G0 * scale))
    return None


@pytest.mark.parametrize("medium", MEDIA, ids=lambda m: type(m).__name__)
def test_media_compute_the_closed_forms_and_keep_the_shape(medium):
    g, j = medium.relaxation_modulus(T), medium.creep_compliance(T)
    assert g.shape == j.shape == T.shape
    assert isinstance(medium.creep_compliance(0.3), float)
    forms = closed_forms(medium, T)
    if forms is None:  # Prony: G(t) here; J(t) against partial fractions in test_viscoelastic.py
        g_inf, terms, _ = medium.rheology()
        np.testing.assert_allclose(g, g_inf + sum(gk * np.exp(-T / tau) for gk, tau in terms), rtol=1e-15)
        return
    # measured: 2.2e-16 but the power law's Gamma functions (Lanczos, 1.1e-15)
    np.testing.assert_allclose(g, forms[0], rtol=2e-15)
    np.testing.assert_allclose(j, forms[1], rtol=5e-15)


@pytest.mark.parametrize("medium", MEDIA, ids=lambda m: type(m).__name__)
def test_media_rebuild_from_the_cores_parameter_names(medium):
    names = list(medium._parameters())
    terms = len(medium.terms) if isinstance(medium, mv.Prony) else 0
    assert names == type(medium)._parameter_names(terms)
    if not isinstance(medium, mv.Prony):  # the fields, in order, are the core's parameters
        assert names == [name for name in medium.__dataclass_fields__ if name != "nu"]
    values = dict(reversed(list(medium._parameters().items())))
    assert type(medium)._from_parameters(values, medium.nu) == medium
    assert pickle.loads(pickle.dumps(medium)) == medium


def test_prony_names_and_unknown_names():
    assert mv.Prony._parameter_names(2) == ["G_inf", "G1", "tau1", "G2", "tau2"]
    with pytest.raises(mv.InvalidInputError, match=r"Maxwell: .*\[\"G\", \"eta\"\]"):
        mv.Maxwell._from_parameters({"G": 1.0, "tau": 2.0}, 0.5)
    assert sorted(_core.Medium.kinds()) == sorted(
        cls.__name__.lower() for cls in (mv.Elastic, mv.Viscous) + mv.media.VISCOELASTIC)


def test_the_core_checks_what_the_dataclasses_leave_to_it():
    with pytest.raises(mv.InvalidInputError, match=r"^PowerLaw: .*beta must lie in \(0, 1\), got 1"):
        mv.PowerLaw(1.0, 1.0)
    with pytest.raises(mv.InvalidInputError, match="^Prony: .*no stiffness"):
        mv.Prony(0.0, ())
    with pytest.raises(mv.InvalidInputError, match="^Prony: G_inf must be finite and >= 0, got -1"):
        mv.Prony(-1.0, ((1.0, 1.0),))


def test_a_tabulated_disc_filled_moves_like_a_rod():
    """A paraboloid h = c r^2 tabulated to its disc of radius a0 (exact: cubic Hermite): the
    paraboloid's Lee-Radok depth until the contact fills the disc at J = 32 eta c a0^3 / 3,
    then 8 eta a0 d grows with the impulse."""
    c, a0, eta = 1.0, 0.5, 1.5
    r = np.linspace(0.0, a0, 11)
    profile = mv.Profile(r, c * r * r, slope=2.0 * c * r, radius=a0)
    filled = 32.0 * eta * c * a0**3 / 3.0
    # measured 1.1e-16 and 0: Simpson's rule is exact for the cubic load integrand
    assert profile.depth_from_impulse(0.5 * filled, eta) == pytest.approx(
        mv.analytic.paraboloid_depth(0.5 * filled, 1.0, c, eta), rel=1e-12)
    assert profile.depth_from_impulse(filled + 2.0, eta) == pytest.approx(
        2.0 * c * a0**2 + 2.0 / (8.0 * eta * a0), rel=1e-12)


def test_a_profile_functions_own_error_comes_back_as_itself():
    class Broken(Exception):
        pass

    def slope(r):
        if np.any(r > 5.0):
            raise Broken("beyond the measured part")
        return 2.0 * r

    bowl = mv.Axisymmetric(lambda r: r * r, df=slope)
    assert bowl.contact_radius_at_depth(0.5) == pytest.approx(0.5, rel=1e-12)  # g = 2 x^2
    with pytest.raises(Broken, match="beyond the measured part"):
        bowl.contact_radius_at_depth(100.0)


@pytest.mark.parametrize("indenter", [
    mv.Rod(0.5), mv.Paraboloid(0.7, edge=2.0), mv.Cone(0.4), mv.Sphere(1.0), mv.Pyramid(0.6, edge=1.0),
    mv.Profile(np.linspace(0.0, 1.0, 5), np.linspace(0.0, 1.0, 5) ** 2, radius=1.0),
], ids=repr)
def test_indenters_pickle_and_rebuild_their_core(indenter):
    copy = pickle.loads(pickle.dumps(indenter))
    assert repr(copy) == repr(indenter)
    x = np.linspace(-0.4, 0.4, 5)
    np.testing.assert_array_equal(copy.profile_1d(x), indenter.profile_1d(x))
    np.testing.assert_array_equal(copy.height_map(x, x)[0], indenter.height_map(x, x)[0])
    assert copy.depth_from_impulse(0.01, 1.0) == indenter.depth_from_impulse(0.01, 1.0)


def test_the_equivalent_cone_is_the_cores():
    alpha = math.radians(35.0)
    slope = mv.Pyramid(alpha).equivalent_cone.slope
    assert slope == pytest.approx(1.0 / (0.7453 * math.pi / 2 * math.tan(alpha)), rel=1e-15)
