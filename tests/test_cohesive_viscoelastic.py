"""MDR's stepped viscoelastic JKR, with and without a process zone, against BEM's
Maugis–Dugdale zone on a standard solid,
under a depth-controlled approach and retract at one speed (the case of
examples/viscoelastic_pull_off.py): a paraboloid R = 50 um, w = 50 mJ/m^2, G_inf = 2 MPa,
G1 = 6 MPa, tau = 10 ms (G_0 / G_inf = 4), the zone's stress chosen so that Maugis's
transition parameter lambda = 2 sigma0 (R / (pi w K^2))^(1/3), K = 4 E* / 3, is 3 at the
relaxed modulus and 3 / 4^(2/3) at the glassy one (Johnson & Greenwood 1997).

The references are the elastic limits: slow against tau, BEM's largest tension over MDR's is
Maugis's pull-off at lambda over JKR's (mv.analytic.maugis_pull_off); fast, BEM gives the
glassy body's Maugis pull-off while MDR's relaxed critical opening gives G_0 / G_inf times
JKR's, so their ratio is Maugis's at the glassy lambda over G_0 / G_inf JKR. The allowance,
3 % of the ratio, is the BEM discretisation the cohesive verification states for a zone a few
elements wide at the pull-off (1-2 %) plus the depth step's sampling of the least force and,
slow, the cohesive zone's own rate effect, which reaches slower cycles than MDR's (see the
adhesion page's comparison over the speed).

With the zone's stress (``mv.JKR(stress=sigma0)``, sigma0 the BEM law's) MDR's edge lets go
by the crack's speed through the zone's creep compliance, which BEM's zone follows at every
speed (the second test)."""

import functools
import math

import numpy as np
import pytest

import mdrvisc as mv

R, W = 50e-6, 0.05
G_INF, G1, TAU = 2e6, 6e6, 0.01
D_MAX, D_MIN = 0.8e-6, -1.5e-6
LAMBDA = 3.0
K_RELAXED = 4.0 * (4.0 * G_INF) / 3.0
LAW = mv.MaugisDugdale(work_of_adhesion=W, stress=LAMBDA / 2 * (math.pi * W * K_RELAXED**2 / R) ** (1 / 3))
SIDE, N = 20e-6, 80


@functools.cache
def largest_tension(speed, method, stress=None):
    """The largest tension (N) of the cycle at ``speed`` (m/s) by ``method``; MDR's JKR with
    the process zone's ``stress`` (Pa) or without."""
    t_in = D_MAX / speed
    t_end = t_in + (D_MAX - D_MIN) / speed
    if method == "mdr":
        indenter, contact = mv.Paraboloid(c=1 / (2 * R)), mv.JKR(work_of_adhesion=W, stress=stress)
        n, steps = 2001, (100, 2000)
    else:
        dx = SIDE / N
        x = (np.arange(N) - (N - 1) / 2) * dx
        indenter = mv.HeightMap(-(x[:, None] ** 2 + x[None, :] ** 2) / (2 * R), dx)
        contact, n, steps = LAW, N, (20, 80)
    times = np.concatenate([np.linspace(t_in / steps[0], t_in, steps[0]),
                            np.linspace(t_in, t_end, steps[1] + 1)[1:]])
    scene = mv.Scene(indenter=indenter, medium=mv.StandardSolid(G_inf=G_INF, G1=G1, tau1=TAU),
                     contact=contact, depth=([0.0, t_in, t_end], [0.0, D_MAX, D_MIN]),
                     duration=t_end, times=times)
    options = {"tol": 1e-6} if method == "bem" else {}
    return -mv.solve(scene, method, n, **options).force.min()


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")
def test_bem_and_mdr_agree_slow_and_differ_by_the_modulus_ratio_fast():
    ratio = (G_INF + G1) / G_INF
    slow, fast = 1e-8, 1.0  # cycles of 3e4 tau and 3e-4 tau
    relaxed = mv.analytic.maugis_pull_off(LAMBDA) / 1.5
    glassy = mv.analytic.maugis_pull_off(LAMBDA / ratio ** (2 / 3)) / 1.5 / ratio
    assert largest_tension(slow, "bem") / largest_tension(slow, "mdr") == pytest.approx(relaxed, rel=0.03)
    assert largest_tension(fast, "bem") / largest_tension(fast, "mdr") == pytest.approx(glassy, rel=0.03)


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")
def test_mdr_with_the_process_zone_follows_bem_at_every_speed():
    """MDR's edge with the BEM law's zone stress against BEM over four decades of speed.

    At the ends the references are the elastic limits as above, with one difference: the
    zone's criterion lets a glassy body go at the glassy body's JKR (3/2 pi w R again for a
    paraboloid), so fast the ratio is Maugis's pull-off at the glassy lambda over JKR's, no
    longer divided by G_0 / G_inf; slow, both methods carry the zone's rate effect alike.

    Between them (310 and 3.1 relaxation times per cycle, where the relaxed-modulus criterion
    is 0.6 and 3.2 times BEM's) no closed form exists: there the two methods model one crack
    differently, and the allowance, 12 %, is the sum of what separates them: BEM's grid and
    steps (3 %, as above), Maugis's finite zone against the K-field's small one at the
    effective lambda of an enhanced work of adhesion (lambda / (G_0 / G_inf)^(1/3) = 1.89 at
    most: 2.5 % above JKR), and what MDR's K-field zone leaves out: the zone, pi K^2 /
    (8 sigma0^2) long, reaches a quarter of the contact radius at the largest enhancement,
    where the semi-infinite crack's opening is only a first approximation (the remaining
    6 %, an estimate, not derived; BEM is above MDR there by 5-7 %)."""
    stress = LAW.stress
    ratio = (G_INF + G1) / G_INF
    relaxed = mv.analytic.maugis_pull_off(LAMBDA) / 1.5
    glassy = mv.analytic.maugis_pull_off(LAMBDA / ratio ** (2 / 3)) / 1.5
    slow, fast = 1e-8, 1.0

    def ratio_at(speed):
        return largest_tension(speed, "bem") / largest_tension(speed, "mdr", stress)

    assert ratio_at(slow) == pytest.approx(relaxed, rel=0.03)
    assert ratio_at(fast) == pytest.approx(glassy, rel=0.03)
    for speed in (1e-6, 1e-4):
        assert ratio_at(speed) == pytest.approx(1.0, rel=0.12)
