"""Fits with adhesion (``mv.fit(..., contact=mv.JKR(...))``): approach and retract curves whose
retract dips below the baseline, depth-controlled and raw AFM curves (a cantilever in series).

The data are made independently of the fit's model (MDR with a contact edge moving between the
elements): by JKR's closed form for a paraboloid of radius R (Johnson, Kendall & Roberts 1971;
Maugis 2000, ch. 5) on an elastic body of contact modulus E* — Hertz on the approach, the
contact held at its largest radius a_m on the retract (F = 2 E* (a_m d - a_m^3 / (3 R)), Hertz
plus a flat punch) until the edge's elongation reaches sqrt(2 pi a w / E*), then the JKR branch
d = a^2 / R - sqrt(2 pi w a / E*), F = 4 E* a^3 / (3 R) - sqrt(8 pi w E* a^3) to its unstable end
(depth control: where dd/da = 0; through a cantilever of stiffness k: where d(d + F / k)/da = 0),
then no force. Each curve is made by a ``MAKERS`` entry (name: a function of the depth or
drive); a curve made by another method (the boundary elements with a cohesive zone of small
range) enters as one more entry.

Units: a sphere-like tip of R = 5 um on a soft gel (G = 1 kPa, E* = 4 kPa), w = 1 mJ/m^2:
pi w R = 16 nN, a quarter of the Hertz force at 3 um.
"""

import contextlib
import functools
import io
import json
import math

import numpy as np
import pytest
from scipy.optimize import brentq

import mdrvisc as mv
from mdrvisc import cli, fitting
from mdrvisc._fit_adhesion import AdhesiveProblem
from mdrvisc.errors import InvalidInputError

R, G, W = 5e-6, 1e3, 1e-3
E_STAR = 4.0 * G  # nu = 0.5
NOISE = 0.01


def hertz(d):
    return 4.0 / 3.0 * E_STAR * math.sqrt(R) * np.maximum(d, 0.0) ** 1.5


def branch_depth(a, w=W, e=E_STAR):
    """JKR: the depth (m) of contact radius a (m)."""
    return a * a / R - np.sqrt(2.0 * math.pi * w * a / e)


def branch_force(a, w=W, e=E_STAR):
    """JKR: the force (N) of contact radius a (m)."""
    return 4.0 * e * a**3 / (3.0 * R) - np.sqrt(8.0 * math.pi * w * e * a**3)


def pinned_force(a_m, d):
    """The contact held at radius a_m (m) at depth d (m): Hertz plus a flat punch."""
    return 2.0 * E_STAR * (a_m * d - a_m**3 / (3.0 * R))


def unstable_end(du_da, a_m):
    """The largest radius below a_m where du_da changes sign (the branch's unstable end)."""
    grid = np.geomspace(1e-4 * a_m, a_m, 4000)[::-1]
    values = du_da(grid)
    k = int(np.flatnonzero(values <= 0)[0])
    return brentq(du_da, grid[k], grid[k - 1], xtol=1e-16 * a_m)


def jkr_depth_control(d):
    """The force (N) of JKR under the prescribed depths d (m): one approach and one retract."""
    top = int(np.argmax(d))
    a_m = math.sqrt(R * d[top])
    d1 = branch_depth(a_m)
    a_end = unstable_end(lambda a: 2.0 * a / R - 0.5 * np.sqrt(2.0 * math.pi * W / (E_STAR * a)), a_m)
    force = hertz(d)
    attached = True
    for i in range(top + 1, d.size):
        if d[i] >= d1:
            force[i] = pinned_force(a_m, d[i])
        elif attached and d[i] > branch_depth(a_end):
            a = brentq(lambda a, di=d[i]: branch_depth(a) - di, a_end, a_m, xtol=1e-16 * a_m)
            force[i] = branch_force(a)
        else:
            attached, force[i] = False, 0.0
    return force


def jkr_spring(u, k):
    """The force (N) of JKR through a spring of stiffness k (N/m) driven by u (m, past the
    contact point): k (u - d) = F at each sample, one approach and one retract."""
    top = int(np.argmax(u))
    force = np.zeros_like(u)
    depth = u.copy()
    for i in range(top + 1):
        if u[i] > 0:
            depth[i] = brentq(lambda d, ui=u[i]: k * (ui - d) - hertz(d), 0.0, u[i], xtol=1e-18)
            force[i] = k * (u[i] - depth[i])
    a_m = math.sqrt(R * depth[top])
    d1 = branch_depth(a_m)
    drive = lambda a: branch_depth(a) + branch_force(a) / k  # noqa: E731
    da = lambda a: (2.0 * a / R - 0.5 * np.sqrt(2.0 * math.pi * W / (E_STAR * a))  # noqa: E731
                    + (4.0 * E_STAR * a**2 / R - 1.5 * np.sqrt(8.0 * math.pi * W * E_STAR * a)) / k)
    a_end = unstable_end(da, a_m)
    attached = True
    for i in range(top + 1, u.size):
        pinned = (k * u[i] + 2.0 * E_STAR * a_m**3 / (3.0 * R)) / (k + 2.0 * E_STAR * a_m)
        if pinned >= d1:
            force[i] = k * (u[i] - pinned)
        elif attached and u[i] > drive(a_end):
            a = brentq(lambda a, ui=u[i]: drive(a) - ui, a_end, a_m, xtol=1e-16 * a_m)
            force[i] = branch_force(a)
        else:
            attached, force[i] = False, 0.0
    return force


#: Makers of adhesive curves: (depth control, spring control) functions of the depths (m) and
#: of the drive (m) and stiffness (N/m).
MAKERS = {"jkr_closed_form": (jkr_depth_control, jkr_spring)}


def depth_curve(samples=300):
    """Approach to 3 um over 1 s, retract to -1.5 um over 1 s (the contact recedes from 0.53 um,
    passes JKR's least force at a = 2.8 um and lets go at -1.09 um)."""
    t = np.linspace(0.0, 2.0, 2 * samples + 1)
    d = np.where(t <= 1.0, 3e-6 * t, 3e-6 - 4.5e-6 * (t - 1.0))
    return t, d


def noisy(values, scale, seed):
    return values + NOISE * scale * np.random.default_rng(seed).standard_normal(values.size)


@pytest.mark.parametrize("maker", sorted(MAKERS))
def test_a_depth_controlled_retract_gives_the_medium_and_the_work_of_adhesion(maker):
    t, d = depth_curve()
    force = MAKERS[maker][0](d)
    assert force.min() < -1.4 * math.pi * W * R  # the dip passes JKR's -3/2 pi w R
    data = noisy(force, np.ptp(force), 1)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic, t, depth=d, force=data,
                 contact=mv.JKR(work_of_adhesion=0.3 * W))
    assert fit.success, fit.message
    assert fit.forward == "jkr"
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)
    assert fit.parameters["work_of_adhesion"] == pytest.approx(W, rel=0.03)
    assert fit.contact == mv.JKR(work_of_adhesion=fit.parameters["work_of_adhesion"])
    # the fit's scatter is the noise's, and its standard errors cover the truth
    assert fit.rms == pytest.approx(NOISE * np.ptp(force), rel=0.15)
    for name, truth in (("G", G), ("work_of_adhesion", W)):
        assert abs(fit.parameters[name] - truth) < 4.0 * fit.stderr[name]


@pytest.mark.parametrize("maker", sorted(MAKERS))
def test_a_raw_afm_retract_gives_the_medium_the_work_of_adhesion_and_the_contact_point(maker):
    k, z_c, b = 0.05, 3e-6, 2e-8
    t = np.linspace(0.0, 2.0, 801)
    u = np.where(t <= 1.0, -1.5e-6 + 5.74e-6 * t, 4.24e-6 - 6.74e-6 * (t - 1.0))
    force = MAKERS[maker][1](u, k)
    assert force.min() < -1.4 * math.pi * W * R and force[-1] == 0.0
    deflection = noisy(force / k + b, np.ptp(force / k), 2)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic, t, piezo=u + z_c, deflection=deflection,
                 spring_constant=k, contact=mv.JKR(work_of_adhesion=0.3 * W))
    assert fit.success, fit.message
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)
    assert fit.parameters["work_of_adhesion"] == pytest.approx(W, rel=0.03)
    assert fit.contact_point == pytest.approx(z_c, abs=0.03 * 1e-6)
    assert fit.baseline == pytest.approx(b, abs=3 * NOISE * np.ptp(force / k))


#: A curve by the boundary elements with a Maugis–Dugdale zone (``mv.arrays.adhesive_curve``):
#: a sphere-like paraboloid R = 1 m on G = 1 Pa (E* = 4 Pa) with w = 0.01 J/m^2 (pi w R =
#: 0.0314 N) at the transition parameter lambda = 2 sigma0 (R / (pi w K^2))^(1/3) = 3,
#: K = 4 E* / 3: sigma0 = 1.445 Pa, range h0 = w / sigma0 = 6.9 mm; Maugis's pull-off is
#: then 1.1 % above JKR's (``mv.analytic.maugis_pull_off``). The grid of 64 x 64 elements of
#: 14 mm over 0.9 m holds the contact (radius 0.39 m at the deepest) and its zone, the element
#: below the law's resolution limit E* h0 / (1.12 sigma0) = 17 mm; refined to 96 x 96 its
#: forces move by 1.9 % of their range at the last sample before the jump out
#: (``benchmarks/bench_adhesion.py``) and by at most 0.7 % elsewhere.
BEM_R, BEM_G, BEM_W, BEM_LAMBDA = 1.0, 1.0, 0.01, 3.0


@functools.cache
def bem_curve():
    """Depths (m) and forces (N) of a depth-controlled approach from -0.02 m to 0.08 m and a
    retract to -0.04 m by the boundary elements (the cohesive zone jumps in before the touch
    and out past JKR's unstable end, at finite range)."""
    k = 4.0 * (4.0 * BEM_G) / 3.0
    stress = BEM_LAMBDA / 2.0 * (math.pi * BEM_W * k * k) ** (1.0 / 3.0)
    n, side = 64, 0.9
    dx = side / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    height = (x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * BEM_R)
    d = np.concatenate([np.linspace(-0.02, 0.08, 21), np.linspace(0.08, -0.04, 49)[1:]])
    law = mv.MaugisDugdale(work_of_adhesion=BEM_W, stress=stress)
    curve = mv.arrays.adhesive_curve(height, dx, BEM_G, law, d, tol=1e-8)
    return d, curve["force"]


def test_a_boundary_element_retract_with_a_cohesive_zone_gives_the_medium_and_the_work_of_adhesion():
    """The boundary elements' curve (a cohesive zone of finite range, not the fit's model)
    loads and unloads on the JKR branch (at zero depth JKR's -4/3 pi w R, through its least
    force -3/2 pi w R); fitted by JKR with the equilibrium approach at 1 % noise it gives G and
    w within 3 %. JKR's touch rule (Hertz on the approach) does not describe it."""
    d, force = bem_curve()
    unit = math.pi * BEM_W * BEM_R
    top = int(np.argmax(d))
    at_zero = force[top + 1:][np.argmin(np.abs(d[top + 1:]))]
    assert at_zero / unit == pytest.approx(-4.0 / 3.0, rel=0.02)
    assert force.min() / unit == pytest.approx(-mv.analytic.maugis_pull_off(BEM_LAMBDA), rel=0.02)
    t = np.linspace(0.0, 2.0, d.size)
    data = noisy(force, np.ptp(force), 7)
    fit = mv.fit(mv.Paraboloid(c=0.5 / BEM_R), mv.Elastic, t, depth=d, force=data,
                 contact=mv.JKR(work_of_adhesion=0.3 * BEM_W, approach="equilibrium"))
    assert fit.success, fit.message
    assert fit.parameters["G"] == pytest.approx(BEM_G, rel=0.03)
    assert fit.parameters["work_of_adhesion"] == pytest.approx(BEM_W, rel=0.03)
    assert fit.contact == mv.JKR(work_of_adhesion=fit.parameters["work_of_adhesion"], approach="equilibrium")
    touch = mv.fit(mv.Paraboloid(c=0.5 / BEM_R), mv.Elastic, t, depth=d, force=data,
                   contact=mv.JKR(work_of_adhesion=0.3 * BEM_W))
    assert touch.rms > 1.5 * fit.rms


@pytest.mark.parametrize("start", [0.03, 10.0])
def test_a_poor_first_guess_still_finds_the_work_of_adhesion(start):
    """From a work of adhesion 30 times too small or 10 times too large (which would hold the
    contact through the whole retract, where the force does not depend on it) and a modulus
    5 times too small."""
    t, d = depth_curve(150)
    force = jkr_depth_control(d)
    data = noisy(force, np.ptp(force), 5)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic(G=G / 5), t, depth=d, force=data,
                 contact=mv.JKR(work_of_adhesion=start * W))
    assert fit.success, fit.message
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)
    assert fit.parameters["work_of_adhesion"] == pytest.approx(W, rel=0.03)


def test_a_held_work_of_adhesion_stays():
    t, d = depth_curve(100)
    data = noisy(jkr_depth_control(d), np.ptp(jkr_depth_control(d)), 3)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic(G=500.0), t, depth=d, force=data,
                 contact=mv.JKR(work_of_adhesion=W), fixed=("work_of_adhesion",))
    assert fit.free == ["G"]
    assert fit.parameters["work_of_adhesion"] == W and fit.stderr["work_of_adhesion"] == 0.0
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)


def branch_errors(n):
    """The forward model's force and its finite-difference Jacobian on a half profile of n
    elements against the closed form: the largest errors (in the force's range) of the force,
    of the Jacobian on the approach and the held contact, and on the JKR branch (the number of
    its samples last)."""
    t, d = depth_curve(400)
    force = jkr_depth_control(d)
    base, _, _ = fitting._problem(mv.Paraboloid(c=0.5 / R), mv.Elastic(G=G), t, d, force, None, None, None,
                                  None, None, "depth", None, (), None, 2, n, 1)
    problem = AdhesiveProblem(base, mv.JKR(work_of_adhesion=W), held=False)
    values, _ = problem._forward(np.log([G, W]), 0.0)
    jac = problem.jacobian(np.log([G, W]), values)
    scale = np.ptp(force)
    top = int(np.argmax(d))
    a_m = math.sqrt(R * d[top])
    held = np.arange(d.size) <= top
    held |= (np.arange(d.size) > top) & (d > branch_depth(a_m))
    # d F / d log E* = F and d F / d log w = 0 where the radius does not move
    held_error = max(np.max(np.abs(jac[held, 0] - values[held])), np.max(np.abs(jac[held, 1])))
    on_branch = np.flatnonzero(~held & (force != 0.0))
    a_end = unstable_end(lambda a: 2.0 * a / R - 0.5 * np.sqrt(2.0 * math.pi * W / (E_STAR * a)), a_m)
    branch_error = 0.0
    for i in on_branch:
        a = brentq(lambda a, di=d[i]: branch_depth(a) - di, a_end, a_m, xtol=1e-16 * a_m)
        root = math.sqrt(2.0 * math.pi * W * a / E_STAR)
        phi_a = 2.0 * a / R - 0.5 * root / a
        f_a = 4.0 * E_STAR * a**2 / R - 1.5 * math.sqrt(8.0 * math.pi * W * E_STAR * a)
        half = 0.5 * math.sqrt(8.0 * math.pi * W * E_STAR * a**3)
        # at the sample's depth, phi = a^2 / R - root(a, w, E*) - d = 0 moves a
        d_log_e = (branch_force(a) + half) + f_a * (-0.5 * root / phi_a)
        d_log_w = -half + f_a * (0.5 * root / phi_a)
        branch_error = max(branch_error, abs(jac[i, 0] - d_log_e), abs(jac[i, 1] - d_log_w))
    return (np.max(np.abs(values - force)) / scale, held_error / scale, branch_error / scale,
            on_branch.size)


def test_the_finite_difference_jacobian_matches_jkr_derivatives():
    """d F / d log E* and d F / d log w: exact on the approach (F and 0) and on the held
    contact (F and 0, its radius set by the approach); on the JKR branch those of the closed
    form at the sample's depth (implicit in the radius), converging with the profile's
    elements (the edge's slope is the piecewise-linear profile's: error ~dx / a)."""
    coarse, fine = branch_errors(2000), branch_errors(8000)
    assert fine[3] > 50
    assert fine[0] < 1e-6 and fine[1] < 1e-8
    assert fine[2] < 1e-3 and fine[2] < coarse[2] / 3


def test_dmt_fits_of_depth_controlled_curves():
    """DMT (``contact=mv.DMT(...)``): a depth-controlled curve (Hertz less 2 pi w R while
    d > 0) gives G and w; tips without a radius are refused."""
    t, d = depth_curve()
    force = np.where(d > 0.0, hertz(d) - 2.0 * math.pi * W * R, 0.0)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic, t, depth=d, force=noisy(force, np.ptp(force), 6),
                 contact=mv.DMT(work_of_adhesion=0.3 * W))
    assert fit.success and fit.forward == "dmt", fit.message
    assert fit.contact == mv.DMT(work_of_adhesion=fit.parameters["work_of_adhesion"])
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)
    assert fit.parameters["work_of_adhesion"] == pytest.approx(W, rel=0.03)
    with pytest.raises(InvalidInputError, match="rounded tip"):
        mv.fit(mv.Cone(slope=0.5), mv.Elastic, t, depth=d, force=force,
               contact=mv.DMT(work_of_adhesion=W))


def raw_drive():
    """Time (s) and drive u (m, past the contact point) of a raw approach and retract."""
    t = np.linspace(0.0, 2.0, 801)
    return t, np.where(t <= 1.0, -1.5e-6 + 5.74e-6 * t, 4.24e-6 - 6.74e-6 * (t - 1.0))


def jkr_spring_equilibrium(u, k):
    """The force (N) of JKR loaded in equilibrium through a spring of stiffness k (N/m)
    driven by u (m): out of contact until the touch (u = 0), then on the branch where the
    drive d + F / k of the radius equals u, beyond its least drive (the spring's unstable end),
    which the retract runs down to before the contact lets go."""
    drive = lambda a: branch_depth(a) + branch_force(a) / k  # noqa: E731
    da = lambda a: (2.0 * a / R - 0.5 * np.sqrt(2.0 * math.pi * W / (E_STAR * a))  # noqa: E731
                    + (4.0 * E_STAR * a**2 / R - 1.5 * np.sqrt(8.0 * math.pi * W * E_STAR * a)) / k)
    a_end = unstable_end(da, 10.0 * R)
    force = np.zeros_like(u)
    touched = False
    for i, ui in enumerate(u):
        touched = (touched or ui >= 0.0) and ui > drive(a_end)
        if touched:
            a = brentq(lambda a, ui=ui: drive(a) - ui, a_end, 10.0 * R, xtol=1e-16 * R)
            force[i] = branch_force(a)
    return force


def dmt_spring(u, k):
    """The force (N) of DMT through a spring of stiffness k (N/m) driven by u (m): the
    contact jumps in at the touch (u = 0) with the attraction P = 2 pi w R and holds while
    k (u - d) = Hertz(d) - P has a depth d >= 0, down to u = -P / k on the retract."""
    pull = 2.0 * math.pi * W * R
    top = int(np.argmax(u))
    force = np.zeros_like(u)
    touching = False
    for i, ui in enumerate(u):
        touching = ui > 0.0 if i <= top else touching and ui > -pull / k
        if touching:
            d = brentq(lambda d, ui=ui: k * (ui - d) - hertz(d) + pull, 0.0, ui + pull / k, xtol=1e-18)
            force[i] = k * (ui - d)
    return force


@pytest.mark.parametrize("contact", ["jkr_equilibrium", "dmt"])
def test_a_raw_curve_whose_contact_jumps_in_gives_the_medium_and_the_contact_point(contact):
    """Raw AFM curves of contacts that jump in at the touch (JKR loaded in equilibrium, DMT):
    the deflection falls below its baseline at the contact point before it rises, so the fit
    starts its contact point there too (and its modulus scaled about the first guess): G and
    the contact point come back, and w within 3 % (JKR) or three standard errors (DMT, whose
    w the jump alone tells: its standard error is 1.8 % here)."""
    k, z_c, b = 0.05, 3e-6, 2e-8
    t, u = raw_drive()
    if contact == "dmt":
        force, law = dmt_spring(u, k), mv.DMT(work_of_adhesion=0.3 * W)
        assert force.min() == pytest.approx(-2.0 * math.pi * W * R, rel=1e-3)
    else:
        force, law = jkr_spring_equilibrium(u, k), mv.JKR(work_of_adhesion=0.3 * W, approach="equilibrium")
        assert force.min() == pytest.approx(-1.5 * math.pi * W * R, rel=1e-3)
    touch = int(np.flatnonzero(force)[0])
    assert u[touch] >= 0.0 > u[touch - 1] and force[touch] < 0.0  # the jump in
    deflection = noisy(force / k + b, np.ptp(force / k), 2)
    fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.Elastic, t, piezo=u + z_c, deflection=deflection,
                 spring_constant=k, contact=law)
    assert fit.success, fit.message
    assert fit.parameters["G"] == pytest.approx(G, rel=0.03)
    if contact == "dmt":
        assert abs(fit.parameters["work_of_adhesion"] - W) < 3.0 * fit.stderr["work_of_adhesion"]
    else:
        assert fit.parameters["work_of_adhesion"] == pytest.approx(W, rel=0.03)
    assert fit.contact_point == pytest.approx(z_c, abs=0.03 * 1e-6)


@pytest.mark.parametrize("kw, words", [
    (dict(model=mv.Maxwell), "elastic"),
    (dict(model=mv.StandardSolid, contact=mv.JKR(work_of_adhesion=W, approach="equilibrium")), "elastic"),
    (dict(model=mv.StandardSolid, contact=mv.DMT(work_of_adhesion=W)), "elastic"),
    (dict(model=mv.StandardSolid, contact=mv.JKR(work_of_adhesion=W, stress=1.0)), "for scenes"),
    (dict(control="force"), "depth-controlled"),
    (dict(contact=mv.Hard), "mv.JKR"),
    (dict(body=mv.Layer(thickness=50 * R)), "on a layer"),
])
def test_what_an_adhesive_fit_refuses(kw, words):
    t, d = depth_curve(50)
    args = dict(model=mv.Elastic, contact=mv.JKR(work_of_adhesion=W), control="depth")
    args.update(kw)
    with pytest.raises(InvalidInputError, match=words):
        mv.fit(mv.Paraboloid(c=0.5 / R), args.pop("model"), t, depth=d, force=jkr_depth_control(d) + 1e-9,
               **args)


def test_a_viscoelastic_jkr_fit_recovers_the_standard_solid_and_the_work_of_adhesion():
    """JKR on a standard solid (G_0 / G_inf = 4, tau1 = 0.5 s, over a 2 s approach and
    retract): data by MDR's stepped viscoelastic JKR (``mv.solve``, 8001 elements; an
    independent path: elements stepped one by one, each letting go by Heß's rule with the
    relaxed modulus), fitted by the continuous-edge model (the edge on the relaxed elastic
    curve, each element's hereditary integral since it attached). Noise-free, the four
    parameters come back to the stepped model's discretisation (0.5 %); at 1 % noise within
    three standard errors (which are 1-3 %: G_inf, tau1 and w trade off over one relaxation
    time)."""
    medium = mv.StandardSolid(G_inf=G, G1=3.0 * G, tau1=0.5)
    t, d = depth_curve()
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5 / R), medium=medium, contact=mv.JKR(work_of_adhesion=W),
                     depth=(t, d), duration=2.0, times=t[1:])
    stepped = mv.solve(scene, "mdr", 8001)
    force = np.concatenate([[0.0], stepped.force])
    assert force.min() < -1.4 * math.pi * W * R
    truth = dict(G_inf=G, G1=3.0 * G, tau1=0.5, work_of_adhesion=W)
    for noise, seed in ((0.0, 0), (NOISE, 1)):
        data = force + noise * np.ptp(force) * np.random.default_rng(seed).standard_normal(force.size)
        fit = mv.fit(mv.Paraboloid(c=0.5 / R), mv.StandardSolid, t, depth=d, force=data,
                     contact=mv.JKR(work_of_adhesion=0.3 * W))
        assert fit.success, fit.message
        for name, value in truth.items():
            if noise == 0.0:
                assert fit.parameters[name] == pytest.approx(value, rel=0.005), name
            else:
                assert abs(fit.parameters[name] - value) < 3.0 * fit.stderr[name], name
    with pytest.raises(InvalidInputError, match="elastic"):
        mv.fit(mv.Paraboloid(c=0.5 / R), mv.StandardSolid, t, piezo=d + 3e-6, deflection=force / 0.05,
               spring_constant=0.05, contact=mv.JKR(work_of_adhesion=W))


def test_the_equilibrium_approach_is_for_fits():
    """``mv.JKR(approach=...)`` takes "touch" or "equilibrium"; a scene, whose MDR stepping
    grows the contact by the touch rule, refuses the equilibrium approach by name."""
    with pytest.raises(InvalidInputError, match="approach"):
        mv.JKR(work_of_adhesion=W, approach="jump")
    with pytest.raises(InvalidInputError, match="equilibrium"):
        mv.Scene(indenter=mv.Paraboloid(c=0.5 / R), medium=mv.Elastic(G=G),
                 contact=mv.JKR(work_of_adhesion=W, approach="equilibrium"),
                 depth=([0.0, 1.0], [0.0, 1e-6]), duration=1.0)


def test_the_command_line_fits_the_work_of_adhesion(tmp_path):
    """``mdrvisc fit ... --contact jkr:W``: the work of adhesion among the fitted parameters."""
    t, d = depth_curve(150)
    force = jkr_depth_control(d)
    path = tmp_path / "retract.csv"
    np.savetxt(path, np.c_[t, d, noisy(force, np.ptp(force), 4)], delimiter=",", header="t,depth,force",
               comments="")
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(["fit", str(path), "--indenter", f"paraboloid:c={0.5 / R}", "--model", "elastic",
                           "--contact", f"jkr:{0.3 * W}", "--json"])
    assert status == 0, err.getvalue()
    document = json.loads(out.getvalue())
    assert document["forward"] == "jkr" and "work_of_adhesion" in document["free"]
    assert document["parameters"]["work_of_adhesion"] == pytest.approx(W, rel=0.03)
    assert document["parameters"]["G"] == pytest.approx(G, rel=0.03)
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err := io.StringIO()):
        status = cli.main(["fit", str(path), "--indenter", f"paraboloid:c={0.5 / R}", "--model", "elastic",
                           "--contact", "sticky"])
    assert status == 2 and "--contact" in err.getvalue()
    assert cli._contact("jkr:0.01:equilibrium") == mv.JKR(work_of_adhesion=0.01, approach="equilibrium")
    assert cli._contact("dmt:0.01") == mv.DMT(work_of_adhesion=0.01)
    with pytest.raises(InvalidInputError, match="--contact"):
        cli._contact("dmt:0.01:equilibrium")
