"""Indenters: MDR maps against closed forms and direct quadrature, height maps, validation."""

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.integrate import quad
from scipy.special import gamma

from mdrvisc.errors import DomainError, InvalidInputError
from mdrvisc.geometry import Cone, Indenter, Paraboloid, Pyramid, Rod, Sphere
from mdrvisc.profiles import Axisymmetric

X = np.concatenate([np.geomspace(1e-6, 1e-2, 20), np.linspace(0.01, 3.0, 200)])


def relative_error(actual, expected):
    return np.max(np.abs(np.asarray(actual) / np.asarray(expected) - 1.0))


def mdr_map_by_quad(df, x):
    """g(x) = x * int_0^x f'(r) (x - r)^(-1/2) (x + r)^(-1/2) dr with QUADPACK's algebraic
    weight for the endpoint singularity: independent of the library's substitution."""
    value, _ = quad(lambda r: df(r) / math.sqrt(x + r), 0.0, x, weight="alg", wvar=(0.0, -0.5),
                    epsabs=0.0, epsrel=1e-13)
    return x * value


# ------------------------------------------------------------------ numerical MDR map
@pytest.mark.parametrize("with_derivative", [True, False])
def test_paraboloid_map(with_derivative):
    c = 0.7
    df = (lambda r: 2 * c * r) if with_derivative else None
    g = Axisymmetric(lambda r: c * r**2, df=df).profile_1d(X)
    assert relative_error(g, 2 * c * X**2) <= 1e-8


@pytest.mark.parametrize("with_derivative", [True, False])
def test_cone_map(with_derivative):
    s = 0.3
    df = (lambda r: np.full_like(r, s)) if with_derivative else None
    g = Axisymmetric(lambda r: s * r, df=df).profile_1d(X)
    assert relative_error(g, 0.5 * math.pi * s * X) <= 1e-8


@pytest.mark.parametrize("n", [1.0, 1.5, 2.0, 3.0, 4.0])
@pytest.mark.parametrize("with_derivative", [True, False])
def test_power_law_map(n, with_derivative):
    kappa = math.sqrt(math.pi) * gamma(n / 2 + 1) / gamma(n / 2 + 0.5)
    df = (lambda r: n * r ** (n - 1)) if with_derivative else None
    g = Axisymmetric(lambda r: r**n, df=df).profile_1d(X)
    assert relative_error(g, kappa * X**n) <= 1e-8


@pytest.mark.parametrize("with_derivative", [True, False])
def test_sphere_map_matches_closed_form(with_derivative):
    R = 1.7
    x = np.linspace(1e-4, 0.95 * R, 300)
    exact = 0.5 * x * (np.log1p(x / R) - np.log1p(-x / R))
    df = (lambda r: r / np.sqrt(R * R - r * r)) if with_derivative else None
    # f written without cancellation: the central difference needs f accurate relative to f
    numeric = Axisymmetric(lambda r: r * r / (R + np.sqrt(R * R - r * r)), df=df, radius=R)
    assert relative_error(numeric.profile_1d(x), exact) <= 1e-8
    assert relative_error(Sphere(R).profile_1d(x), exact) <= 1e-13


def test_general_profile_matches_direct_quadrature():
    f = lambda r: 1.0 - np.exp(-r * r)  # noqa: E731  (a Gaussian bump, f(0) = 0)
    df = lambda r: 2.0 * r * np.exp(-r * r)  # noqa: E731
    x = np.linspace(0.05, 3.0, 25)
    expected = np.array([mdr_map_by_quad(df, xi) for xi in x])
    assert relative_error(Axisymmetric(f).profile_1d(x), expected) <= 1e-8


def test_profiles_are_even_and_zero_at_the_axis():
    for indenter in [Paraboloid(2.0), Cone(1.0), Sphere(1.0), Axisymmetric(lambda r: r**3)]:
        x = np.linspace(0.0, 0.9, 10)
        g = indenter.profile_1d(x)
        np.testing.assert_array_equal(g, indenter.profile_1d(-x))
        assert g[0] == 0.0
        assert np.all(np.diff(g) > 0)
    np.testing.assert_array_equal(Rod(1.0).profile_1d(np.linspace(-1, 1, 7)), 0.0)


@settings(deadline=None, max_examples=30)
@given(c=st.floats(1e-3, 1e3), x=st.floats(1e-4, 1e2))
def test_closed_form_paraboloid_and_cone_profiles(c, x):
    assert Paraboloid(c).profile_1d(x) == pytest.approx(2 * c * x * x, rel=1e-15)
    assert Cone(c).profile_1d(-x) == pytest.approx(0.5 * math.pi * c * x, rel=1e-15)


def test_profile_keeps_shape():
    x = np.linspace(-1, 1, 12).reshape(3, 4)
    for indenter in [Rod(1.0), Paraboloid(1.0), Cone(1.0), Axisymmetric(lambda r: r**2)]:
        g = indenter.profile_1d(x)
        assert g.shape == (3, 4) and g.dtype == np.float64


def test_profile_1d_runs_on_66049_points():
    x = np.linspace(-2.56 / math.sqrt(math.pi), 2.56 / math.sqrt(math.pi), 66049)
    g = Axisymmetric(lambda r: r**1.5).profile_1d(x)
    assert g.shape == x.shape and np.all(np.isfinite(g))


# ------------------------------------------------------------------ height maps
def centres(n, lo=-1.0, hi=1.0):
    return lo + (np.arange(n) + 0.5) * (hi - lo) / n


def test_rod_mask_on_paper_grid():
    # Paper (Sect. 5): the rod's face of radius 1 m held 31417 square elements: the Gauss
    # circle count N(100) of grid points (i, j) * 0.01 m, |i|, |j| <= 100, within the circle.
    x = 0.01 * np.arange(-100, 101)
    h, mask = Rod(1.0).height_map(x, x)
    assert mask.sum() == 31417
    assert mask.sum() == sum(1 for i in range(-100, 101) for j in range(-100, 101)
                             if i * i + j * j <= 10000)
    np.testing.assert_array_equal(h, 0.0)


def test_rod_mask_on_half_offset_grid():
    # 200 x 200 centres (i + 1/2) * 0.01 - 1: odd lattice points (2i+1, 2j+1) in a circle of
    # radius 200 (none lies on it, since odd^2 + odd^2 = 2 mod 4).
    h, mask = Rod(1.0).height_map(centres(200), centres(200))
    expected = sum(1 for i in range(-100, 100) for j in range(-100, 100)
                   if (2 * i + 1) ** 2 + (2 * j + 1) ** 2 <= 40000)
    assert mask.sum() == expected == 31428
    assert h.shape == mask.shape == (200, 200)
    assert h.dtype == np.float64 and mask.dtype == bool
    assert h.flags.c_contiguous and mask.flags.c_contiguous


def test_rows_follow_y():
    h, mask = Rod(1.0).height_map([0.0, 0.5, 2.0], [0.0, 3.0])
    assert h.shape == (2, 3)
    np.testing.assert_array_equal(mask, [[True, True, False], [False, False, False]])


def test_paraboloid_edge_masks_the_square():
    x = centres(200)
    h, mask = Paraboloid(1.0, edge=1.0).height_map(x, x)
    inside = np.abs(x) <= 0.5
    np.testing.assert_array_equal(mask, np.outer(inside, inside))
    assert mask.sum() == 100 * 100
    r2 = x[None, :] ** 2 + x[:, None] ** 2
    np.testing.assert_allclose(h[mask], r2[mask], rtol=1e-15)
    np.testing.assert_array_equal(h[~mask], 0.0)
    assert Paraboloid(1.0).height_map(x, x)[1].all()


def test_paper_paraboloid_grid_is_all_inside():
    x = centres(257, -1.28, 1.28)
    h, mask = Paraboloid(20.0, edge=2.56).height_map(x, x)
    assert mask.all() and h.shape == (257, 257)


def test_sphere_mask_is_open_and_cap_is_on_the_sphere():
    x = np.arange(-2.0, 3.0)
    _, mask = Sphere(2.0).height_map(x, x)
    assert mask.sum() == 9  # integer points with i^2 + j^2 < 4 (the rim points are out)
    assert Rod(2.0).height_map(x, x)[1].sum() == 13  # the rod's rim is in
    R = 1.3
    xs = centres(101, -1.4, 1.4)
    h, mask = Sphere(R).height_map(xs, xs)
    r2 = xs[None, :] ** 2 + xs[:, None] ** 2
    np.testing.assert_array_equal(mask, r2 < R * R)
    # a point of the cap lies at distance R from the centre (0, 0, R)
    np.testing.assert_allclose(((R - h) ** 2 + r2)[mask], R * R, rtol=1e-14)


@pytest.mark.parametrize("indenter", [
    Rod(0.8), Paraboloid(5.0), Paraboloid(0.05, edge=1.5), Cone(0.4), Cone(2.0, edge=1.0),
    Sphere(0.9), Sphere(5.0), Pyramid(0.6), Pyramid(1.2, edge=1.0), Axisymmetric(lambda r: r**1.5),
    Axisymmetric(lambda r: r**2, edge=1.2), Axisymmetric(lambda r: 1 - np.cos(r), radius=0.7),
])
def test_heights_are_finite_and_nonnegative(indenter):
    x = centres(64, -1.1, 1.1)
    h, mask = indenter.height_map(x, x[:50])
    assert h.shape == mask.shape == (50, 64)
    assert np.all(np.isfinite(h)) and np.all(h >= 0)
    np.testing.assert_array_equal(h[~mask], 0.0)
    assert h[mask].size == 0 or h[mask].min() >= 0


def test_cone_and_axisymmetric_heights():
    x = np.linspace(-1, 1, 21)
    r = np.hypot(x[None, :], x[:, None])
    np.testing.assert_allclose(Cone(0.25).height_map(x, x)[0], 0.25 * r, rtol=1e-15)
    np.testing.assert_allclose(Axisymmetric(lambda q: q**3).height_map(x, x)[0], r**3, rtol=1e-15)


# ------------------------------------------------------------------ sizes and contact radius
def test_sizes_and_flags():
    assert Rod(1.5).footprint_half_width == 1.5 == Rod(1.5).mdr_half_length
    assert Sphere(2.0).footprint_half_width == 2.0 == Sphere(2.0).mdr_half_length
    p = Paraboloid(1.0, edge=2.56)
    assert p.footprint_half_width == 1.28
    assert p.mdr_half_length == pytest.approx(2.56 / math.sqrt(math.pi))
    assert math.pi * p.mdr_half_length**2 == pytest.approx(2.56**2)  # equal area
    assert Cone(1.0, edge=1.0).footprint_half_width == 0.5
    for unbounded in [Paraboloid(1.0), Cone(1.0), Axisymmetric(lambda r: r**2)]:
        assert unbounded.footprint_half_width is None and unbounded.mdr_half_length is None
    assert Axisymmetric(lambda r: r**2, radius=0.5).mdr_half_length == 0.5
    assert Axisymmetric(lambda r: r**2, edge=2.0).footprint_half_width == 1.0
    assert Rod(1.0).is_flat
    assert not any(i.is_flat for i in [Paraboloid(1.0), Cone(1.0), Sphere(1.0),
                                       Axisymmetric(lambda r: 0 * r, radius=1.0)])
    assert all(isinstance(i, Indenter) for i in [Rod(1.0), Sphere(1.0), Cone(1.0)])


def test_repr_shows_parameters():
    assert repr(Rod(2.0)) == "Rod(radius=2.0)"
    assert repr(Paraboloid(0.05, edge=2.56)) == "Paraboloid(c=0.05, edge=2.56)"
    assert repr(Cone(0.5)) == "Cone(slope=0.5, edge=None)"
    assert repr(Sphere(1.0)) == "Sphere(radius=1.0)"

    def bowl(r):
        return r**2

    assert repr(Axisymmetric(bowl, radius=1.0)) == (
        "Axisymmetric(f=test_repr_shows_parameters.<locals>.bowl, df=None, edge=None, radius=1.0)"
    )


def test_contact_radius_closed_forms():
    # Hertz geometry a^2 = R d with R = 1/(2c); Sneddon's cone a = 2 d / (pi tan(beta)).
    assert Paraboloid(2.0).contact_radius_at_depth(0.01) == pytest.approx(math.sqrt(0.25 * 0.01))
    assert Cone(0.5).contact_radius_at_depth(0.3) == pytest.approx(2 * 0.3 / (math.pi * 0.5))
    assert Rod(0.7).contact_radius_at_depth(0.0) == 0.7
    assert Paraboloid(1.0).contact_radius_at_depth(0.0) == 0.0


def test_contact_radius_numeric():
    R = 1.0
    def g(a):
        return 0.5 * a * (math.log1p(a / R) - math.log1p(-a / R))

    for d in [1e-8, 1e-3, 0.1, 1.0, 10.0]:
        a = Sphere(R).contact_radius_at_depth(d)
        assert g(a * (1 - 1e-14)) <= d <= g(a * (1 + 1e-14))  # a is the root to 1e-14
    # shallow sphere: Hertz a = sqrt(R d)
    assert Sphere(R).contact_radius_at_depth(1e-8) == pytest.approx(1e-4, rel=1e-7)
    n, c = 1.5, 0.8
    kappa = math.sqrt(math.pi) * gamma(n / 2 + 1) / gamma(n / 2 + 0.5)
    for d in [1e-6, 0.2, 50.0]:
        a = Axisymmetric(lambda r: c * r**n).contact_radius_at_depth(d)
        assert a == pytest.approx((d / (kappa * c)) ** (1 / n), rel=1e-10)
    R = 1.0
    cap = Axisymmetric(lambda r: r * r / (R + np.sqrt(R * R - r * r)),
                       df=lambda r: r / np.sqrt(R * R - r * r), radius=R)
    assert cap.contact_radius_at_depth(0.3) == pytest.approx(
        Sphere(R).contact_radius_at_depth(0.3), rel=1e-10)
    capped = Axisymmetric(lambda r: r**2, radius=0.5)
    assert capped.contact_radius_at_depth(0.4) == pytest.approx(math.sqrt(0.2), rel=1e-10)
    assert capped.contact_radius_at_depth(0.6) == 0.5  # g(0.5) = 0.5: the face is covered


def test_unreachable_depth_is_a_domain_error():
    # f = 1 - 1/(1 + r^2) levels off: g(x) < 1 for all x
    bounded = Axisymmetric(lambda r: 1.0 - 1.0 / (1.0 + r * r),
                           df=lambda r: 2.0 * r / (1.0 + r * r) ** 2)
    with pytest.raises(DomainError, match="reaches depth 5.0"):
        bounded.contact_radius_at_depth(5.0)


# ------------------------------------------------------------------ validation
@pytest.mark.parametrize("make, name", [
    (Rod, "radius"), (Sphere, "radius"), (Paraboloid, "c"), (Cone, "slope"),
    (lambda v: Paraboloid(1.0, edge=v), "edge"), (lambda v: Cone(1.0, edge=v), "edge"),
    (lambda v: Pyramid(0.5, edge=v), "edge"),
    (lambda v: Axisymmetric(lambda r: r, radius=v), "radius"),
    (lambda v: Axisymmetric(lambda r: r, edge=v), "edge"),
])
@pytest.mark.parametrize("value, shown", [
    (0.0, "0.0"), (-1.0, "-1.0"), (-1, "-1.0"), (float("nan"), "nan"), (float("inf"), "inf"),
    ("abc", "'abc'"), (None, "None"), (True, "True"),
])
def test_bad_parameters(make, name, value, shown):
    if value is None and make not in (Rod, Sphere, Paraboloid, Cone):
        return  # an optional size: None means unbounded
    with pytest.raises(InvalidInputError, match=f"{name} must be a finite positive number, "
                                                f"got {shown}") as info:
        make(value)
    assert isinstance(info.value, ValueError)


def test_message_format():
    with pytest.raises(ValueError) as info:
        Paraboloid(-1.0)
    assert str(info.value) == "Paraboloid: c must be a finite positive number, got -1.0"


def test_bad_axisymmetric_profiles():
    with pytest.raises(InvalidInputError, match=r"f\(0\) must be 0"):
        Axisymmetric(lambda r: r**2 + 1.0)
    with pytest.raises(InvalidInputError, match="not both"):
        Axisymmetric(lambda r: r**2, edge=1.0, radius=1.0)
    with pytest.raises(InvalidInputError, match="callable"):
        Axisymmetric(2.0)
    with pytest.raises(InvalidInputError, match="callable"):
        Axisymmetric(lambda r: r, df=1.0)
    with pytest.raises(InvalidInputError, match="not finite at r = 0.5"):
        Axisymmetric(lambda r: np.where(r == 0.5, np.nan, r))
    with pytest.raises(InvalidInputError, match="same shape"):
        Axisymmetric(lambda r: np.ones(3))
    with pytest.raises(InvalidInputError, match=">= 0"):
        Axisymmetric(lambda r: -r).height_map([0.5], [0.5])


def test_bad_coordinates_and_depths():
    with pytest.raises(InvalidInputError, match="x = 1.0"):
        Sphere(1.0).profile_1d([0.5, 1.0])
    with pytest.raises(InvalidInputError, match="x = -1.5"):
        Rod(1.0).profile_1d([-1.5])
    with pytest.raises(InvalidInputError, match="x = 2.0"):
        Axisymmetric(lambda r: r**2, radius=1.0).profile_1d(2.0)
    with pytest.raises(InvalidInputError, match="nan"):
        Paraboloid(1.0).profile_1d([0.0, float("nan")])
    with pytest.raises(InvalidInputError, match="1-D"):
        Rod(1.0).height_map(np.zeros((2, 2)), [0.0])
    with pytest.raises(InvalidInputError, match="1-D"):
        Rod(1.0).height_map([], [0.0])
    with pytest.raises(InvalidInputError, match="inf"):
        Rod(1.0).height_map([0.0, float("inf")], [0.0])
    with pytest.raises(InvalidInputError, match="-1.0"):
        Paraboloid(1.0).contact_radius_at_depth(-1.0)
    with pytest.raises(InvalidInputError, match="single depth"):
        Cone(1.0).contact_radius_at_depth([0.1, 0.2])


# ------------------------------------------------------------------ Lee-Radok depth
@pytest.mark.parametrize("indenter", [Rod(0.5), Paraboloid(0.7), Cone(0.4), Sphere(1.0),
                                      Paraboloid(0.05, edge=2.56),
                                      Axisymmetric(lambda r: 0.7 * r * r, radius=0.5)],
                         ids=repr)
def test_depth_from_impulse_is_the_lee_radok_depth(indenter):
    from mdrvisc.analytic import lee_radok_depth_from_impulse

    impulse = np.array([0.0, 1e-3, 0.3, 1.0])
    np.testing.assert_array_equal(indenter.depth_from_impulse(impulse, 2.0),
                                  lee_radok_depth_from_impulse(impulse, indenter, 2.0))
    assert isinstance(indenter.depth_from_impulse(0.3, 2.0), float)


def test_depth_from_impulse_validates():
    with pytest.raises(InvalidInputError, match=r"^Cone.depth_from_impulse: impulse must be "
                                                r"finite and >= 0.0, got -1.0 at index \(1,\)"):
        Cone(1.0).depth_from_impulse([1.0, -1.0], 1.0)
    with pytest.raises(InvalidInputError, match="^Rod.depth_from_impulse: eta must be a finite"):
        Rod(1.0).depth_from_impulse(1.0, 0.0)
    with pytest.raises(DomainError, match="^Paraboloid.depth_from_impulse: at an impulse of 5.0"):
        Paraboloid(0.05, edge=2.56).depth_from_impulse([1.0, 5.0], 1.0)
