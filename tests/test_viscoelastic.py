"""General linear viscoelasticity: creep and constant indentation rate (Lee–Radok), held depth,
loading and unloading (Ting), BEM and MDR, stiff relaxation times."""

import warnings
from types import SimpleNamespace

import numpy as np
import pytest

import mdrvisc as mv

C, FORCE = 1.0, 1.0
R = 1.0 / (2 * C)
TIMES = np.geomspace(1e-4, 5.0, 12)


def prony_creep_compliance(g_inf, terms, t):
    """J(t) (1/Pa) of G(t) = g_inf + sum G_k exp(-t / tau_k), g_inf > 0, by partial fractions,
    independent of the package: J^(s) = 1 / (s^2 G^(s)) = D(s) / (s N(s)) with
    D = prod (s + 1/tau_k) and N = s G^(s) D = g_inf D + sum G_k s prod_{j != k} (s + 1/tau_j)."""
    from numpy.polynomial import polynomial as poly

    denominator = np.array([1.0])
    for _, tau in terms:
        denominator = poly.polymul(denominator, [1 / tau, 1.0])
    numerator = g_inf * denominator
    for k, (g, _) in enumerate(terms):
        part = np.array([0.0, g])
        for j, (_, tau) in enumerate(terms):
            if j != k:
                part = poly.polymul(part, [1 / tau, 1.0])
        numerator = poly.polyadd(numerator, part)
    slope = poly.polyder(numerator)
    t = np.asarray(t, dtype=float)
    residues = sum((poly.polyval(r, denominator) / (r * poly.polyval(r, slope)) * np.exp(r * t)).real
                   for r in poly.polyroots(numerator))
    return poly.polyval(0.0, denominator) / poly.polyval(0.0, numerator) + residues


def creep_compliance(medium, t):
    """The medium's J(t) (1/Pa) written here: Maxwell 1/G + t/eta, Kelvin-Voigt
    (1 - exp(-t G / eta)) / G, the others by partial fractions of their relaxation modulus."""
    if isinstance(medium, mv.Maxwell):
        return 1 / medium.G + t / medium.eta
    if isinstance(medium, mv.KelvinVoigt):
        return (1 - np.exp(-t * medium.G / medium.eta)) / medium.G
    if isinstance(medium, mv.StandardSolid):
        return prony_creep_compliance(medium.G_inf, [(medium.G1, medium.tau1)], t)
    return prony_creep_compliance(medium.G_inf, medium.terms, t)


def creep_depth(medium, t):
    """Lee–Radok creep of a paraboloid under a step force: d^(3/2) = 3 F J(t) / (16 sqrt R)."""
    return (3 * FORCE * creep_compliance(medium, t) / (16 * np.sqrt(R))) ** (2 / 3)


MEDIA = [mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5), mv.Maxwell(G=2.0, eta=1.0),
         mv.Prony(G_inf=0.5, terms=[(1.0, 0.1), (2.0, 2.0)])]


@pytest.mark.parametrize("medium", MEDIA, ids=lambda m: type(m).__name__)
# measured (largest of the three media): MDR 3.1e-5, BEM 3.6e-4; the step force is a jump at
# t = 0 taken with the instantaneous modulus, so the error is second order in dt
@pytest.mark.parametrize("method,n,tol", [("mdr", 8001, 1e-4), ("bem", 65, 1e-3)])
def test_creep_under_a_step_force_follows_lee_radok(medium, method, n, tol):
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=FORCE, duration=5.0, times=TIMES)
    r = mv.solve(scene, method, n, dt=0.02)
    assert np.max(np.abs(r.depth / creep_depth(medium, TIMES) - 1)) < tol


def test_kelvin_voigt_creep_converges_first_order_in_the_step():
    medium = mv.KelvinVoigt(G=1.0, eta=0.5)
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=FORCE, duration=5.0, times=TIMES)
    # the dashpot is stepped by backward Euler: error ~ dt / (G / eta)^-1, first order
    errs = [np.max(np.abs(mv.solve(scene, "mdr", 8001, dt=dt).depth / creep_depth(medium, TIMES) - 1))
            for dt in (0.04, 0.01)]
    assert 2.5 < errs[0] / errs[1] < 6
    assert errs[1] < 0.5 * 0.01 / (medium.eta / medium.G)


def test_bem_steps_are_third_order_where_the_history_is_smooth():
    """Creep of a paraboloid under a step force on a standard solid (tau = 0.5 s), depths at
    0.5-5 s against the same method at dt = 0.005 s (errors of the time step alone): BEM's
    steps, quadratic in each element's strain, lose a factor 8 per halving of dt from 0.25 s
    (measured 8.4 and 8.2, errors 4.4e-4 to 6.4e-6); MDR's, linear over each step, a factor
    4 (measured 4.0 and 4.0, errors 1.1e-3 to 6.8e-5). The contact grows without bound
    here, and an element entering it kinks its history; on a rough surface, where elements
    enter at every step, BEM's order falls to two (benchmarks/README.md, "Rough creep")."""
    medium = mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5)
    times = np.linspace(0.5, 5.0, 10)
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=FORCE, duration=5.0, times=times)
    for method, n, low, high in (("bem", 65, 6.5, 10.0), ("mdr", 8001, 3.5, 4.5)):
        ref = mv.solve(scene, method, n, dt=0.005).depth
        errs = [np.max(np.abs(mv.solve(scene, method, n, dt=dt).depth / ref - 1))
                for dt in (0.25, 0.125, 0.0625)]
        for coarse, fine in zip(errs, errs[1:]):
            assert low < coarse / fine < high, (method, errs)


@pytest.mark.parametrize("medium", [mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5),
                                    mv.Prony(G_inf=0.5, terms=[(1.0, 0.1), (2.0, 2.0)])],
                         ids=lambda m: type(m).__name__)
def test_bem_steps_do_not_interpolate_across_a_load_reversal(medium):
    """Ting's triangle (a paraboloid pushed in at 0.2 m/s for 1 s, then pulled out) by BEM
    65 at dt = 0.05 and 0.0125 s against the same at dt = 0.002 s. The depth's rate reverses
    at t = 1 s, a sample of its history: the steps there stay linear, which are exact for a
    kink at a step, instead of interpolating every element's strain through it (which erred by
    1.3e-3 to 3e-3 of the peak force at dt = 0.05-0.1 s). Measured: 1.3e-4 / 2.1e-4 at 0.05 s
    and 2.8e-6 / 4.0e-6 at 0.0125 s (the linear steps throughout: 2.5e-4 and 1.7e-5)."""
    t = np.linspace(0.05, 2.0, 40)
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, depth=([0.0, 1.0, 2.0], [0.0, 0.2, 0.0]),
                     duration=2.0, times=t)
    with warnings.catch_warnings():
        # the contact spans about 9 elements near separation: the same in every run compared
        warnings.simplefilter("ignore", mv.ResolutionWarning)
        ref = mv.solve(scene, "bem", 65, dt=0.002).force
        for dt, bound in ((0.05, 3e-4), (0.0125, 1e-5)):
            force = mv.solve(scene, "bem", 65, dt=dt).force
            assert np.max(np.abs(force - ref)) / ref.max() < bound, dt


def test_creep_compliance_closed_forms_match_the_generic_stepping():
    t = np.array([0.0, 0.05, 0.7, 4.0])
    for medium in (mv.StandardSolid(1.0, 3.0, 0.5), mv.Maxwell(2.0, 0.6)):
        # the same relaxation modulus as a Prony series, whose compliance is stepped
        g_inf, terms, _ = medium.rheology()
        generic = mv.Prony(g_inf, terms).creep_compliance(t)
        assert np.allclose(generic, medium.creep_compliance(t), rtol=1e-6)
    prony = MEDIA[2]
    # the package's stepping against partial fractions: measured 1.3e-8
    assert np.allclose(prony.creep_compliance(t), creep_compliance(prony, t), rtol=5e-8, atol=0)
    sls = mv.StandardSolid(1.0, 3.0, 0.5)
    assert sls.relaxation_modulus(0.0) == pytest.approx(4.0)
    assert sls.creep_compliance(1e9) == pytest.approx(1.0)


@pytest.mark.parametrize("method,n,tol", [("mdr", 8001, 1e-8), ("bem", 65, 2e-4)])
@pytest.mark.parametrize("dt", [0.01, 0.001])
def test_a_depth_held_from_the_start_relaxes_as_the_closed_form(method, n, tol, dt):
    """A depth d there from t = 0 on a Maxwell body: F(t) = 16/3 sqrt(R) G(t) d^(3/2) with
    G(t) = G exp(-t / tau) (E* = 4 G), exactly at any step: the jump is taken at t = 0 with
    the instantaneous modulus, not spread over the first step. Measured: MDR 2.8e-9, BEM
    (65 x 65) 7.2e-5, the same at both steps."""
    medium, depth = mv.Maxwell(G=2.0, eta=1.0), 0.1
    times = np.array([0.1, 0.5, 1.0, 2.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, depth=depth, duration=2.0, times=times)
    r = mv.solve(scene, method, n, dt=dt)
    exact = 16 / 3 * np.sqrt(R) * medium.G * np.exp(-times * medium.G / medium.eta) * depth**1.5
    assert np.max(np.abs(r.force / exact - 1)) < tol


# Ting (1966): the paraboloid pushed in at V until T_PEAK, then pulled out at V. Separation
# at 1.51 s (standard solid) and 2 T_PEAK - eta / G = 1.73 s (Kelvin-Voigt), between outputs.
V, T_PEAK = 0.2, 1.0
TING_MEDIA = [mv.StandardSolid(1.0, 3.0, 0.5), mv.KelvinVoigt(G=1.5, eta=0.4)]


def against_ting(medium, method, n, dt, spacing=0.01):
    """Errors of a triangle depth history's solution against Ting's: the largest force errors
    while loading and while unloading (relative to the peak force) and contact-radius error (in
    elements dx); ``separates``: the force is positive exactly at the outputs before Ting's
    separation time, and ``compressive``: it never turns tensile."""
    times = np.arange(1, round(2 * T_PEAK / spacing) + 1) * spacing
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, duration=2 * T_PEAK, times=times,
                     depth=([0.0, T_PEAK, 2 * T_PEAK], [0.0, V * T_PEAK, 0.0]))
    r = mv.solve(scene, method, n, dt=dt)
    force, radius, t_sep = mv.analytic.ting_paraboloid_triangle(r.t, medium, R, V, T_PEAK)
    error = np.abs(r.force - force) / force.max()
    return SimpleNamespace(loading=error[r.t <= T_PEAK].max(), unloading=error[r.t > T_PEAK].max(),
                           radius=np.max(np.abs(r.contact_length / 2 - radius)) / r.dx,
                           separates=np.array_equal(r.force > 0, r.t < t_sep),
                           compressive=np.all(r.force >= 0))


@pytest.mark.parametrize("medium,loading", [(TING_MEDIA[0], 3e-6), (TING_MEDIA[1], 5e-3)],
                         ids=["StandardSolid", "KelvinVoigt"])
def test_loading_then_unloading_mdr_follows_ting(medium, loading):
    coarse, fine = (against_ting(medium, "mdr", n, dt) for n, dt in ((8001, 0.005), (16001, 0.0025)))
    # force error from the time step: second order for the standard solid; first order for
    # Kelvin-Voigt's dashpot, whose elements entering the contact within a step are pressed at
    # less than V (~dt / 4t of the dashpot force, while loading only)
    assert coarse.loading < loading and fine.loading < coarse.loading / 1.8
    assert coarse.unloading < 2e-6 and fine.unloading < coarse.unloading / 1.8
    # the contact edge is exact to the element: half the contact length is a to within dx / 2
    for run in (coarse, fine):
        assert run.radius < 0.5 + 1e-6 and run.separates and run.compressive


@pytest.mark.parametrize("medium,loading", [(TING_MEDIA[0], 1.5e-4), (TING_MEDIA[1], 1.2e-2)],
                         ids=["StandardSolid", "KelvinVoigt"])
def test_loading_then_unloading_bem_follows_ting(medium, loading):
    run = against_ting(medium, "bem", 65, 0.01)
    # while loading, Kelvin-Voigt's first-order time-step error (see the MDR test) dominates;
    # the rest falls with the element size squared (unloading, measured: 1.0e-4, 3.0e-5, 1.6e-5
    # at n = 65, 100, 130); the radius from the contact area is within a fraction of an element
    assert run.loading < loading and run.unloading < 1.5e-4
    assert run.radius < 0.45 and run.separates and run.compressive


@pytest.mark.parametrize("tau", [1e-6, 1e6])
def test_relaxation_times_far_from_the_step_are_stable(tau):
    # tau << dt: the Prony term has relaxed (modulus G_inf); tau >> dt: it is glassy
    medium = mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=tau)
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=FORCE, duration=5.0, times=[1.0, 5.0])
    r = mv.solve(scene, "mdr", 8001, dt=0.1)
    modulus = 1.0 if tau < 1 else 4.0
    elastic = (3 * FORCE / (16 * np.sqrt(R) * modulus)) ** (2 / 3)
    assert np.allclose(r.depth, elastic, rtol=2e-3)
    assert np.all(np.isfinite(r.depth))


def test_loading_keys_are_checked():
    """An elastic scene held at a depth is static (no duration) and needs a depth > 0; one
    key of force and depth; Prony times > 0."""
    static = mv.Scene(indenter=mv.Paraboloid(c=C), medium=mv.Elastic(G=1.0), depth=0.1)
    assert static.controlled_by == "depth" and static.duration is None
    with pytest.raises(mv.InvalidInputError, match="static: give no duration"):
        mv.Scene(indenter=mv.Paraboloid(c=C), medium=mv.Elastic(G=1.0), depth=0.1, duration=1.0)
    for depth in (0.0, -1e-7):
        with pytest.raises(mv.InvalidInputError, match="final depth > 0"):
            mv.Scene(indenter=mv.Sphere(radius=1.0), medium=mv.Elastic(G=1.0), depth=depth)
    with pytest.raises(mv.InvalidInputError, match="only one of the keys 'force' and 'depth'"):
        mv.Scene(indenter=mv.Paraboloid(c=C), medium=mv.Maxwell(1.0, 1.0), force=1.0, depth=0.1, duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="tau_k"):
        mv.Prony(G_inf=1.0, terms=[(1.0, -2.0)])


@pytest.mark.parametrize("medium", [mv.Viscous(eta=0.5), mv.KelvinVoigt(G=1.0, eta=0.5),
                                    mv.Maxwell(G=2.0, eta=1.0), mv.StandardSolid(1.0, 3.0, 0.5)],
                         ids=lambda m: type(m).__name__)
def test_constant_indentation_rate_follows_lee_radok(medium):
    # d = v t: F(t) = (16/3) sqrt(R) integral_0^t G(t - s) d/ds (v s)^(3/2) ds
    from scipy.integrate import quad

    v, times = 0.1, np.array([0.25, 1.0, 2.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, depth=([0.0, 1.0], [0.0, v]), duration=2.0,
                     times=times)
    eta = medium.rheology()[2]  # of eta delta(t) in G(t), which relaxation_modulus leaves out
    # the depth history is held after t = 1 s: integrate the hereditary law piecewise
    def force(t):
        def rate(s):
            return 1.5 * v**1.5 * np.sqrt(s) if s <= 1.0 else 0.0

        val, _ = quad(lambda s: medium.relaxation_modulus(t - s) * rate(s), 0.0, min(t, 1.0), limit=200)
        # the dashpot adds eta d/dt (v t)^(3/2) at t; at the kink t = 1 s the solution there
        # is the end of the loading step, so the rate from the left
        return 16.0 / 3.0 * np.sqrt(R) * (val + eta * rate(t))

    exact = np.array([force(t) for t in times])
    # a dashpot's elements entering the contact within a step are pressed at less than v: a
    # first-order error of ~dt / 4t of its force (2e-3 at t = 0.25 s for dt = 2 ms)
    r = mv.solve(scene, "mdr", 8001, dt=0.001)
    assert np.allclose(r.force, exact, rtol=2e-3)


def test_elastic_limit_is_hertz_and_callables_are_histories():
    medium = mv.Prony(G_inf=2.0, terms=[])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=lambda t: min(t, 1.0), duration=2.0,
                     times=[0.5, 2.0])
    r = mv.solve(scene, "mdr", 8001)
    for f, d in zip((0.5, 1.0), r.depth):
        assert d == pytest.approx(mv.analytic.hertz(f, R, 4 * 2.0)[1], rel=1e-5)


@pytest.mark.parametrize("method,n,tol", [("mdr", 8001, 3e-4), ("bem", 100, 3e-3)])
def test_creep_of_rod_and_cone_follows_lee_radok(method, n, tol):
    medium = mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5)
    times = np.geomspace(1e-4, 5.0, 8)
    j = creep_compliance(medium, times)
    rod = mv.Scene(indenter=mv.Rod(radius=0.5), medium=medium, force=FORCE, duration=5.0, times=times)
    # flat punch: F = 8 G a d, so d(t) = F J(t) / (8 a)
    assert np.max(np.abs(mv.solve(rod, method, n, dt=0.02).depth / (FORCE * j / (8 * 0.5)) - 1)) < tol
    slope = 0.5
    cone = mv.Scene(indenter=mv.Cone(slope=slope), medium=medium, force=FORCE, duration=5.0, times=times)
    # cone: F = 8 G d^2 / (pi s), so d(t)^2 = pi s F J(t) / 8
    exact = np.sqrt(np.pi * slope * FORCE * j / 8)
    assert np.max(np.abs(mv.solve(cone, method, n, dt=0.02).depth / exact - 1)) < 5 * tol


def test_depth_controlled_viscous_medium_matches_the_viscous_engine():
    # the general stepping under the depth history that the exact viscous run produced
    viscous = mv.Viscous(eta=1.0)
    t = np.linspace(0.05, 5.0, 100)
    forward = mv.solve(mv.Scene(indenter=mv.Paraboloid(c=C), medium=viscous, force=FORCE, duration=5.0,
                                times=t), "mdr", 8001)
    back = mv.solve(mv.Scene(indenter=mv.Paraboloid(c=C), medium=viscous,
                             depth=(np.concatenate([[0.0], t]), np.concatenate([[0.0], forward.depth])),
                             duration=5.0, times=t[1:]), "mdr", 8001, dt=0.01)
    # the depth history is sampled every 0.05 s and d ~ t^(2/3) curves most early: the
    # sampled history's force error falls as the sampling gets finer relative to t
    err = np.abs(back.force / FORCE - 1)
    assert err[5] < 2.5e-2 and err[-1] < err[5] / 8
    assert np.all(np.diff(err[5:]) < 1e-4)
