"""Closed forms against the paper's numbers and independent physics and mathematics."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.optimize import brentq
from scipy.special import gamma

from mdrvisc import analytic as A
from mdrvisc.errors import DomainError, InvalidInputError
from mdrvisc.geometry import Cone, Paraboloid, Rod, Sphere
from mdrvisc.media import Elastic, KelvinVoigt, Maxwell, Prony, StandardSolid, Viscous
from mdrvisc.profiles import Axisymmetric


def mdr_impulse(g, a, eta):
    """4 eta * integral_{-a}^{a} (g(a) - g(x)) dx by QUADPACK (N s): the MDR dashpot balance."""
    value, _ = quad(lambda x: g(a) - g(x), -a, a, points=[0.0], epsabs=0.0, epsrel=1e-13,
                    limit=200)
    return 4.0 * eta * value


# ------------------------------------------------------------------ rod
def test_paper_rod_numbers():
    # Sect. 5: a = 1 m, F = 1 N, eta = 1 Pa s -> p0 = 0.1592 Pa, ddot = 0.125 m/s
    assert round(A.rod_central_pressure(1.0, 1.0), 4) == 0.1592
    assert A.rod_velocity(1.0, 1.0, 1.0) == 0.125


def test_rod_pressure_carries_the_force():
    F, a = 3.0, 0.7
    p0 = A.rod_central_pressure(F, a)
    assert A.rod_pressure(0.0, F, a) == p0
    # with r = a sin(phi) the edge singularity goes away: 2 pi p0 a^2 int_0^{pi/2} sin = F
    total = 2 * math.pi * quad(lambda phi: A.rod_pressure(a * math.sin(phi), F, a)
                               * a * math.sin(phi) * a * math.cos(phi), 0, math.pi / 2,
                               epsabs=0.0, epsrel=1e-12)[0]
    assert total == pytest.approx(F, rel=1e-9)
    np.testing.assert_array_equal(A.rod_pressure([a, 1.5 * a, 10.0], F, a), 0.0)
    assert A.rod_pressure(np.array([0.0, 0.5, 0.9]), F, a).shape == (3,)


def test_rod_surface_velocity_matches_boussinesq_far_away():
    F, a, eta = 2.0, 0.5, 3.0
    ddot = A.rod_velocity(F, a, eta)
    np.testing.assert_array_equal(A.rod_surface_velocity([0.0, 0.3, a], F, a, eta), ddot)
    # continuous at the edge, decreasing outside
    outside = A.rod_surface_velocity(np.linspace(a, 10 * a, 50), F, a, eta)
    assert outside[0] == pytest.approx(ddot, rel=1e-15) and np.all(np.diff(outside) < 0)
    # far field: a point force on a viscous half-space, du/dt = F / (4 pi eta r)
    r = 1e4 * a
    assert A.rod_surface_velocity(r, F, a, eta) == pytest.approx(F / (4 * math.pi * eta * r),
                                                                  rel=1e-8)


# ------------------------------------------------------------------ paraboloid
@settings(deadline=None, max_examples=50)
@given(F=st.floats(1e-3, 1e3), t=st.floats(1e-3, 1e3), c=st.floats(1e-2, 1e2),
       eta=st.floats(1e-2, 1e2))
def test_paraboloid_is_hertz_with_impulse(F, t, c, eta):
    # Lee-Radok: the elastic (Hertz) solution with E* = 4 eta and force F t
    a, d, _ = A.hertz(F * t, 1.0 / (2.0 * c), 4.0 * eta)
    assert A.paraboloid_depth(t, F, c, eta) == pytest.approx(d, rel=1e-12)
    assert A.paraboloid_contact_radius(t, F, c, eta) == pytest.approx(a, rel=1e-12)
    assert A.paraboloid_contact_length(t, F, c, eta) == pytest.approx(2 * a, rel=1e-12)


def test_paraboloid_scaling_and_force_balance():
    t = np.array([0.0, 0.5, 1.0, 2.0, 5.0])
    d = A.paraboloid_depth(t, 1.0, 1.0, 1.0)
    assert d[0] == 0.0
    # d ~ (F t / eta)^(2/3)
    assert A.paraboloid_depth(2.0, 1.0, 1.0, 1.0) / d[2] == pytest.approx(2 ** (2 / 3), rel=1e-14)
    assert A.paraboloid_depth(1.0, 3.0, 1.0, 1.0) / d[2] == pytest.approx(3 ** (2 / 3), rel=1e-14)
    assert A.paraboloid_depth(1.0, 2.0, 1.0, 2.0) == pytest.approx(d[2], rel=1e-14)
    # MDR balance: 4 eta int (d - 2 c x^2) dx = F t with d = 2 c a^2
    c, eta, F = 0.2, 1.5, 0.8
    for ti in [0.1, 1.0, 5.0]:
        a = A.paraboloid_contact_radius(ti, F, c, eta)
        assert mdr_impulse(lambda x: 2 * c * x * x, a, eta) == pytest.approx(F * ti, rel=1e-10)


def test_paper_paraboloid_magnitudes():
    # Sect. 6: F = 1 N, eta = 1 Pa s, 5 s; contact lengths of a few metres for small c
    length = [A.paraboloid_contact_length(5.0, 1.0, c, 1.0) for c in [0.05, 0.2, 1.0, 5.0, 20.0]]
    assert np.all(np.diff(length) < 0)
    # c = 0.05: d = (15 sqrt(0.1) / 16)^(2/3) = 0.4446 m, l = 2 sqrt(d / 0.1) = 4.217 m
    assert length[0] == pytest.approx(4.217, rel=1e-4)


# ------------------------------------------------------------------ cone
def test_cone_against_mdr_force_balance():
    s, eta, F = 0.4, 2.0, 1.5
    for t in [0.01, 1.0, 7.0]:
        d = A.cone_depth(t, F, s, eta)
        a = A.cone_contact_radius(t, F, s, eta)
        g = lambda x: 0.5 * math.pi * s * abs(x)  # noqa: E731
        assert g(a) == pytest.approx(d, rel=1e-14)
        assert mdr_impulse(g, a, eta) == pytest.approx(F * t, rel=1e-10)


def test_cone_against_sneddon():
    # Sneddon's elastic cone (half-angle alpha, tan(alpha) = 1/s): F = (2/pi) E* d^2 tan(alpha)
    s, eta, F, t = 1.3, 0.5, 2.0, 3.0
    d = A.cone_depth(t, F, s, eta)
    assert (2 / math.pi) * (4 * eta) * d * d / s == pytest.approx(F * t, rel=1e-14)
    assert A.cone_depth(4 * t, F, s, eta) == pytest.approx(2 * d, rel=1e-14)  # d ~ sqrt(t)


# ------------------------------------------------------------------ MDR maps
@pytest.mark.parametrize("n", [0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 7.5])
def test_power_law_factor(n):
    assert A.power_law_mdr_factor(n) == pytest.approx(
        math.sqrt(math.pi) * gamma(n / 2 + 1) / gamma(n / 2 + 0.5), rel=1e-13)
    # the MDR map of r^n at x = 1: int_0^1 n r^(n-1) (1 - r)^(-1/2) (1 + r)^(-1/2) dr
    direct = quad(lambda r: n / math.sqrt(1 + r), 0, 1, weight="alg", wvar=(n - 1, -0.5),
                  epsabs=0.0, epsrel=1e-13)[0]
    assert A.power_law_mdr_factor(n) == pytest.approx(direct, rel=1e-10)


def test_power_law_factor_known_values():
    assert A.power_law_mdr_factor(1) == pytest.approx(math.pi / 2, rel=1e-15)
    assert A.power_law_mdr_factor(2) == pytest.approx(2.0, rel=1e-15)
    assert math.isfinite(A.power_law_mdr_factor(1000.0))


def test_sphere_profile():
    R = 2.0
    x = np.array([-1.9, -0.5, 0.0, 1e-3, 0.5, 1.0, 1.9])
    expected = 0.5 * np.abs(x) * np.log((R + np.abs(x)) / (R - np.abs(x)))
    np.testing.assert_allclose(A.sphere_mdr_profile(x, R), expected, rtol=1e-12)
    # against the MDR integral of h = R - sqrt(R^2 - r^2), f' = r / sqrt(R^2 - r^2)
    for xi in [0.3, 1.0, 1.8]:
        direct = xi * quad(lambda r, xi=xi: r / math.sqrt(R * R - r * r) / math.sqrt(xi + r), 0, xi,
                           weight="alg", wvar=(0.0, -0.5), epsabs=0.0, epsrel=1e-13)[0]
        assert A.sphere_mdr_profile(xi, R) == pytest.approx(direct, rel=1e-10)
    # shallow limit: the paraboloid of the same curvature, g = 2 c x^2 = x^2 / R
    assert A.sphere_mdr_profile(1e-4, R) == pytest.approx(1e-8 / R, rel=1e-8)
    assert isinstance(A.sphere_mdr_profile(0.5, R), float)
    with pytest.raises(InvalidInputError, match=r"\|x\| = 2.0"):
        A.sphere_mdr_profile([0.1, -2.0], R)


# ------------------------------------------------------------------ Hertz
def test_hertz_balances():
    F, R, E = 2.5, 0.8, 3.0
    a, d, p0 = A.hertz(F, R, E)
    assert d == pytest.approx(a * a / R, rel=1e-15)
    # total force 2 pi int_0^a p r dr, with r = a sin(phi) to remove the edge's square root
    total = 2 * math.pi * quad(lambda phi: A.hertz_pressure(a * math.sin(phi), a, p0)
                               * a * math.sin(phi) * a * math.cos(phi), 0, math.pi / 2,
                               epsabs=0.0, epsrel=1e-13)[0]
    assert total == pytest.approx(F, rel=1e-12)
    # MDR with springs 4G dx = E* dx on g = x^2 / R
    spring = E * quad(lambda x: d - x * x / R, -a, a, epsabs=0.0, epsrel=1e-13)[0]
    assert spring == pytest.approx(F, rel=1e-12)
    assert A.hertz_pressure(0.0, a, p0) == p0
    np.testing.assert_array_equal(A.hertz_pressure([a, 2 * a], a, p0), 0.0)


# ------------------------------------------------------------------ Lee-Radok
J = np.array([0.0, 1e-3, 0.3, 1.0, 5.0])


def test_lee_radok_closed_forms():
    np.testing.assert_allclose(A.lee_radok_depth_from_impulse(J, Paraboloid(0.7), 2.0),
                               A.paraboloid_depth(J, 1.0, 0.7, 2.0), rtol=1e-15)
    np.testing.assert_allclose(A.lee_radok_depth_from_impulse(J, Cone(0.7), 2.0),
                               A.cone_depth(J, 1.0, 0.7, 2.0), rtol=1e-15)
    # rod: 8 eta a d = J, i.e. ddot = F / (8 a eta)
    np.testing.assert_allclose(A.lee_radok_depth_from_impulse(J, Rod(0.5), 2.0),
                               J * A.rod_velocity(1.0, 0.5, 2.0), rtol=1e-15)
    assert isinstance(A.lee_radok_depth_from_impulse(1.0, Paraboloid(1.0), 1.0), float)


def test_lee_radok_numeric_matches_closed_forms():
    c, s, eta = 0.7, 0.4, 2.0
    numeric = A.lee_radok_depth_from_impulse(J, Axisymmetric(lambda r: c * r * r), eta)
    np.testing.assert_allclose(numeric, A.paraboloid_depth(J, 1.0, c, eta), rtol=1e-8)
    numeric = A.lee_radok_depth_from_impulse(J, Axisymmetric(lambda r: s * r), eta)
    np.testing.assert_allclose(numeric, A.cone_depth(J, 1.0, s, eta), rtol=1e-8)


def test_lee_radok_sphere():
    R, eta = 1.0, 1.0

    def g(x):
        return 0.5 * abs(x) * math.log((R + abs(x)) / (R - abs(x)))

    for impulse in [1e-3, 0.5, 3.0]:
        d = A.lee_radok_depth_from_impulse(impulse, Sphere(R), eta)
        a = Sphere(R).contact_radius_at_depth(d)
        assert mdr_impulse(g, a, eta) == pytest.approx(impulse, rel=1e-8)
    # shallow: the paraboloid of the same tip curvature, c = 1/(2R)
    assert A.lee_radok_depth_from_impulse(1e-6, Sphere(R), eta) == pytest.approx(
        A.paraboloid_depth(1e-6, 1.0, 0.5 / R, eta), rel=1e-3)
    # the same cap given as a numerical profile (g diverges at the rim)
    cap = Axisymmetric(lambda r: r * r / (R + np.sqrt(R * R - r * r)),
                       df=lambda r: r / np.sqrt(R * R - r * r), radius=R)
    assert A.lee_radok_depth_from_impulse(0.5, cap, eta) == pytest.approx(
        A.lee_radok_depth_from_impulse(0.5, Sphere(R), eta), rel=1e-8)


def test_lee_radok_disc_filled_moves_like_a_rod():
    c, a0, eta = 1.0, 0.5, 1.5
    indenter = Axisymmetric(lambda r: c * r * r, radius=a0)
    filled = 32 * eta * c * a0**3 / 3  # paraboloid impulse when the contact reaches a0
    assert A.lee_radok_depth_from_impulse(0.5 * filled, indenter, eta) == pytest.approx(
        A.paraboloid_depth(0.5 * filled, 1.0, c, eta), rel=1e-8)
    extra = 2.0
    assert A.lee_radok_depth_from_impulse(filled + extra, indenter, eta) == pytest.approx(
        2 * c * a0**2 + extra / (8 * eta * a0), rel=1e-10)
    flat = Axisymmetric(lambda r: 0.0 * r, radius=a0)
    assert A.lee_radok_depth_from_impulse(extra, flat, eta) == pytest.approx(
        A.lee_radok_depth_from_impulse(extra, Rod(a0), eta), rel=1e-12)


def test_lee_radok_square_edge():
    # the paper's c = 0.05 paraboloid on a 2.56 m square: the contact circle reaches the
    # edge (a = 1.28 m) before t = 5 s at F = 1 N, eta = 1 Pa s
    indenter = Paraboloid(0.05, edge=2.56)
    assert A.lee_radok_depth_from_impulse(1.0, indenter, 1.0) == pytest.approx(
        A.paraboloid_depth(1.0, 1.0, 0.05, 1.0), rel=1e-15)
    with pytest.raises(DomainError, match="impulse of 5.0 N s .* exceeds half the edge"):
        A.lee_radok_depth_from_impulse([1.0, 5.0], indenter, 1.0)
    A.lee_radok_depth_from_impulse(5.0, Paraboloid(1.0, edge=2.56), 1.0)
    numeric = Axisymmetric(lambda r: 0.05 * r * r, edge=2.56)
    assert A.lee_radok_depth_from_impulse(1.0, numeric, 1.0) == pytest.approx(
        A.paraboloid_depth(1.0, 1.0, 0.05, 1.0), rel=1e-8)
    with pytest.raises(DomainError, match="impulse of 5.0 N s .* exceeds half the edge"):
        A.lee_radok_depth_from_impulse([1.0, 5.0], numeric, 1.0)
    # without an edge, the closed form holds at any impulse
    assert A.lee_radok_depth_from_impulse(5.0, Paraboloid(0.05), 1.0) == pytest.approx(0.4446,
                                                                                      rel=1e-4)


# ------------------------------------------------------------------ Ting
def ting_by_quadrature(t, medium, R, v, t_peak):
    """Ting's (F, a) at one time t from QUADPACK and brentq on the hereditary integrals."""
    eta = medium.rheology()[2]
    G = medium.relaxation_modulus

    def balance(t1):  # int_{t1}^t G(t - s) ddot(s) ds / v for t > t_peak
        return (quad(lambda s: G(t - s), t1, t_peak, epsabs=0.0, epsrel=1e-13)[0]
                - quad(lambda s: G(t - s), t_peak, t, epsabs=0.0, epsrel=1e-13)[0] - eta)

    if t <= t_peak:
        t1, dashpot = t, eta * math.sqrt(t)
    elif balance(0.0) <= 0.0:
        return 0.0, 0.0
    else:
        t1, dashpot = brentq(balance, 0.0, t_peak, xtol=1e-15, rtol=1e-15), 0.0
    hereditary = quad(lambda s: G(t - s), 0.0, t1, weight="alg", wvar=(0.5, 0.0), epsabs=0.0,
                      epsrel=1e-13)[0]
    return 8 * math.sqrt(R) * v**1.5 * (hereditary + dashpot), math.sqrt(R * v * t1)


def test_ting_root_integral_matches_quadrature():
    x = np.array([1e-3, 0.5, 5.0, 39.0, 41.0, 300.0, 1000.0])
    direct = [quad(lambda s, xi=xi: math.exp(-(xi - s)) * math.sqrt(s), 0.0, xi, epsabs=0.0,
                   epsrel=1e-13, limit=200)[0] for xi in x]
    np.testing.assert_allclose(A._relaxing_root_integral(x), direct, rtol=1e-12)
    assert A._relaxing_root_integral(np.array(0.0)) == 0.0


@pytest.mark.parametrize("medium", [Prony(0.5, [(1.0, 0.1), (2.0, 2.0)]), Maxwell(2.0, 1.0)],
                         ids=lambda m: type(m).__name__)
def test_ting_matches_quadrature_of_the_hereditary_integrals(medium):
    R, v, t_peak = 0.7, 0.3, 1.2
    t = np.array([0.0, 0.3, 1.2, 1.25, 1.4, 1.5, 1.6, 1.9, 2.0, 2.4, 3.0])
    force, radius, t_sep = A.ting_paraboloid_triangle(t, medium, R, v, t_peak)
    expected = np.array([ting_by_quadrature(ti, medium, R, v, t_peak) for ti in t])
    np.testing.assert_allclose(force, expected[:, 0], rtol=1e-10, atol=1e-14)
    np.testing.assert_allclose(radius, expected[:, 1], rtol=1e-10, atol=1e-14)
    # separation: contact at t_sep from below, none from above
    assert t_peak < t_sep < 2 * t_peak
    before, after = A.ting_paraboloid_triangle([t_sep * (1 - 1e-9), t_sep * (1 + 1e-9)], medium, R,
                                               v, t_peak)[0]
    assert before > 0.0 and after == 0.0


def test_ting_elastic_limit_is_hertz():
    G, R, v, t_peak = 2.0, 0.5, 0.2, 1.0
    t = np.linspace(0.0, 2.5, 26)
    force, radius, t_sep = A.ting_paraboloid_triangle(t, Prony(G, []), R, v, t_peak)
    depth = np.maximum(v * np.minimum(t, 2 * t_peak - t), 0.0)
    np.testing.assert_allclose(force, 16 / 3 * G * math.sqrt(R) * depth**1.5, rtol=1e-13,
                               atol=1e-16)
    np.testing.assert_allclose(radius, np.sqrt(R * depth), rtol=1e-13, atol=1e-16)
    np.testing.assert_allclose(radius[:11], radius[20:9:-1], rtol=1e-13, atol=1e-16)
    assert t_sep == pytest.approx(2 * t_peak, rel=1e-15)
    assert A.ting_paraboloid_triangle(2.5, Elastic(G), R, v, t_peak)[:2] == (0.0, 0.0)


def test_ting_kelvin_voigt_closed_form():
    # the edge element balances G (d(t) - d(t1)) = eta v: d(t1) = d(t) - eta v / G
    G, eta, R, v, t_peak = 1.5, 0.4, 0.5, 0.2, 1.0
    t = np.array([0.1, 0.5, 1.0, 1.0 + 1e-12, 1.2, 1.5, 1.7, 1.75, 2.0])
    force, radius, t_sep = A.ting_paraboloid_triangle(t, KelvinVoigt(G, eta), R, v, t_peak)
    depth = np.where(t <= t_peak, v * t, np.maximum(v * (2 * t_peak - t) - eta * v / G, 0.0))
    dashpot = np.where(t <= t_peak, 8 * math.sqrt(R) * eta * np.sqrt(v * t) * v, 0.0)
    np.testing.assert_allclose(force, 16 / 3 * G * math.sqrt(R) * depth**1.5 + dashpot, rtol=1e-12,
                               atol=1e-16)
    np.testing.assert_allclose(radius, np.sqrt(R * depth), rtol=1e-12, atol=1e-16)
    assert t_sep == pytest.approx(2 * t_peak - eta / G, rel=1e-14)
    # the dashpot alone outweighs the spring (v t_peak < eta v / G), and a viscous body: the
    # contact is lost as soon as the indenter turns
    assert A.ting_paraboloid_triangle(1.1, KelvinVoigt(G, 2.0), R, v, t_peak) == (0.0, 0.0, t_peak)
    assert A.ting_paraboloid_triangle(1.1, Viscous(eta), R, v, t_peak) == (0.0, 0.0, t_peak)


def test_ting_standard_solid_force_is_continuous_at_the_peak():
    medium, R, v, t_peak = StandardSolid(1.0, 3.0, 0.5), 0.5, 0.2, 1.0
    eps = 1e-7
    force, radius, _ = A.ting_paraboloid_triangle([t_peak - eps, t_peak, t_peak + eps], medium, R,
                                                  v, t_peak)
    # the force turns with a finite slope (a kink, no jump); so does the contact radius
    assert abs(force[2] - force[1]) < 1e-5 * force[1]
    assert abs(force[1] - force[0]) < 1e-5 * force[1]
    assert force[2] < force[1] and radius[2] < radius[1]
    assert abs(radius[2] - radius[1]) < 1e-5 * radius[1]


# ------------------------------------------------------------------ validation
@pytest.mark.parametrize("call", [
    lambda v: A.rod_velocity(v, 1.0, 1.0), lambda v: A.rod_velocity(1.0, v, 1.0),
    lambda v: A.rod_velocity(1.0, 1.0, v), lambda v: A.rod_central_pressure(v, 1.0),
    lambda v: A.rod_pressure(0.0, 1.0, v), lambda v: A.rod_surface_velocity(0.0, 1.0, 1.0, v),
    lambda v: A.paraboloid_depth(1.0, v, 1.0, 1.0), lambda v: A.paraboloid_depth(1.0, 1.0, v, 1.0),
    lambda v: A.paraboloid_contact_radius(1.0, 1.0, 1.0, v),
    lambda v: A.paraboloid_contact_length(1.0, 1.0, v, 1.0),
    lambda v: A.cone_depth(1.0, 1.0, v, 1.0), lambda v: A.cone_contact_radius(1.0, v, 1.0, 1.0),
    lambda v: A.power_law_mdr_factor(v), lambda v: A.sphere_mdr_profile(0.0, v),
    lambda v: A.hertz(v, 1.0, 1.0), lambda v: A.hertz(1.0, 1.0, v),
    lambda v: A.hertz_pressure(0.0, v, 1.0),
    lambda v: A.lee_radok_depth_from_impulse(1.0, Paraboloid(1.0), v),
    lambda v: A.ting_paraboloid_triangle(1.0, Elastic(1.0), v, 1.0, 1.0),
    lambda v: A.ting_paraboloid_triangle(1.0, Elastic(1.0), 1.0, v, 1.0),
    lambda v: A.ting_paraboloid_triangle(1.0, Elastic(1.0), 1.0, 1.0, v),
])
@pytest.mark.parametrize("value, shown", [(0.0, "0.0"), (-2.0, "-2.0"), (float("nan"), "nan"),
                                          (float("-inf"), "-inf")])
def test_bad_parameters(call, value, shown):
    with pytest.raises(InvalidInputError, match=f"must be a finite positive number, got {shown}"):
        call(value)


@pytest.mark.parametrize("call, name", [
    (lambda v: A.paraboloid_depth(v, 1.0, 1.0, 1.0), "t"),
    (lambda v: A.cone_depth(v, 1.0, 1.0, 1.0), "t"),
    (lambda v: A.rod_pressure(v, 1.0, 1.0), "r"),
    (lambda v: A.hertz_pressure(v, 1.0, 1.0), "r"),
    (lambda v: A.lee_radok_depth_from_impulse(v, Sphere(1.0), 1.0), "impulse"),
    (lambda v: A.ting_paraboloid_triangle(v, Elastic(1.0), 1.0, 1.0, 1.0), "t"),
])
def test_bad_arrays(call, name):
    with pytest.raises(InvalidInputError, match=f"{name} must be finite and >= 0.0, got -1.0 "
                                                r"at index \(1,\)") as info:
        call([1.0, -1.0])
    assert isinstance(info.value, ValueError)
    with pytest.raises(InvalidInputError, match="got nan"):
        call(float("nan"))


def test_lee_radok_needs_an_indenter():
    with pytest.raises(InvalidInputError, match="Indenter"):
        A.lee_radok_depth_from_impulse(1.0, "paraboloid", 1.0)


def test_ting_needs_a_medium():
    with pytest.raises(InvalidInputError, match="medium"):
        A.ting_paraboloid_triangle(1.0, 2.0, 1.0, 1.0, 1.0)


def test_indenter_and_medium_are_duck_typed():
    # analytic imports no indenter or medium classes: anything with their methods will do
    class Flat:
        def depth_from_impulse(self, impulse, eta):
            return impulse / (8.0 * eta)

    assert A.lee_radok_depth_from_impulse(2.0, Flat(), 0.5) == 0.5

    class Spring:
        def rheology(self):
            return 2.0, [], 0.0

    t = np.linspace(0.0, 2.0, 9)
    np.testing.assert_array_equal(A.ting_paraboloid_triangle(t, Spring(), 0.5, 0.2, 1.0)[0],
                                  A.ting_paraboloid_triangle(t, Elastic(2.0), 0.5, 0.2, 1.0)[0])
    with pytest.raises(InvalidInputError, match="Indenter"):
        A.lee_radok_depth_from_impulse(1.0, Paraboloid, 1.0)  # the class, not an indenter
