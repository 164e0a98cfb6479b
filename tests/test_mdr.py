"""MDR against closed forms: viscous paraboloids, the rod, saturation, inverse transforms."""

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import analytic

VISCOUS = mv.Viscous(eta=1.0)


@pytest.mark.parametrize("c", [0.2, 1.0, 5.0, 20.0])
def test_paraboloid_follows_lee_radok(c):
    scene = mv.Scene(indenter=mv.Paraboloid(c=c), medium=VISCOUS, force=1.0, duration=5.0)
    r = mv.solve(scene, "mdr", 66049)
    d = analytic.paraboloid_depth(r.t, 1.0, c, 1.0)
    l_exact = analytic.paraboloid_contact_length(r.t, 1.0, c, 1.0)
    # measured 5.0e-10 and 2.9e-5 for every c (66049 elements)
    assert np.max(np.abs(r.depth / d - 1)) < 2.5e-9
    assert np.max(np.abs(r.contact_length / l_exact - 1)) < 1.5e-4
    assert not r.saturated.any()


def test_errors_shrink_with_element_count():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=VISCOUS, force=1.0, duration=5.0)
    exact = analytic.paraboloid_depth(5.0, 1.0, 1.0, 1.0)
    errs = [abs(mv.solve(scene, "mdr", n).depth[-1] / exact - 1) for n in (257, 1025, 4097)]
    assert errs[0] > errs[1] > errs[2]


def test_rod_rate_and_inverse_pressure():
    scene = mv.Scene(indenter=mv.Rod(radius=1.0), medium=VISCOUS, force=1.0, duration=1.0,
                     outputs=("depth", "contact_length", "pressure", "surface_velocity"))
    r = mv.solve(scene, "mdr", 66049)
    # MDR is exact for the flat punch: measured 0, 0, 2.2e-16 and 9.3e-13 (66049 elements)
    assert r.velocity[0] == pytest.approx(analytic.rod_velocity(1.0, 1.0, 1.0), rel=1e-12)
    assert r.central_pressure[0] == pytest.approx(analytic.rod_central_pressure(1.0, 1.0), rel=1e-12)
    f = r.fields[1.0]
    inside = f.r <= 0.9
    exact = analytic.rod_pressure(f.r[inside], 1.0, 1.0)
    assert np.max(np.abs(f.pressure[inside] / exact - 1)) < 1e-12
    outside = f.r >= 1.0
    v_exact = analytic.rod_surface_velocity(f.r[outside], 1.0, 1.0, 1.0)
    assert np.max(np.abs(f.surface_velocity[outside] / v_exact - 1)) < 5e-12


def test_saturation_of_the_flat_paraboloid():
    edge = 2.56
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.05, edge=edge), medium=VISCOUS, force=1.0, duration=5.0,
                     times=np.linspace(0.25, 5.0, 20), outputs=("depth", "contact_length", "velocity"))
    r = mv.solve(scene, "mdr", 66049)
    length = 2 * edge / np.sqrt(np.pi)
    assert r.saturated[-1] and not r.saturated[0]
    assert r.contact_length[-1] == pytest.approx(length, rel=1e-12)
    sat = r.saturated
    # once the whole indenter touches, it sinks at the flat-punch rate F / (4 eta l)
    rate = np.diff(r.depth[sat]) / np.diff(r.t[sat])
    assert np.allclose(rate, 1.0 / (4.0 * length), rtol=1e-9)
    assert np.all(np.diff(r.depth) > 0)


def test_mdr_pressure_matches_bem_for_a_paraboloid():
    outputs = ("depth", "contact_length", "pressure")
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=2.0,
                     outputs=outputs, field_times=[2.0])
    mdr = mv.solve(scene, "mdr", 66049).fields[2.0]
    bem_r = mv.solve(scene, "bem", 257)
    bem = bem_r.fields[2.0]
    c = bem.x.size // 2
    x, p = bem.x[c:], bem.pressure[c, c:]
    a = 0.5 * bem_r.contact_length[-1]
    sel = x <= 0.8 * a
    p_mdr = np.interp(x[sel], mdr.r, mdr.pressure)
    assert np.max(np.abs(p[sel] / p_mdr - 1)) < 0.02
