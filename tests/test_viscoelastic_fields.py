"""Viscoelastic penetration rate and fields (pressure, deflection, surface velocity), BEM and
MDR, against Lee–Radok for a paraboloid on a Maxwell body under a force ramp F = k t.

While the contact grows, Lee–Radok gives d^(3/2) = 3/(16 sqrt R) integral J(t - s) dF(s), the
surface outside the contact is Hertz's elastic shape for the current contact radius
a(t) = sqrt(R d(t)) (independent of the medium), and the pressure is the hereditary integral
p(r, t) = integral G(t - s) dP(r, s) of Hertz's pressure at unit modulus,
P(r, s) = 8 / (pi R) sqrt(a(s)^2 - r^2). The references below are written from these formulas
and integrated with scipy, sharing nothing with the stepping.
"""

import numpy as np
import pytest
from scipy.integrate import quad

import mdrvisc as mv

C = 1.0
R = 1.0 / (2 * C)
K = 1.0  # force rate (N/s)
MAXWELL = mv.Maxwell(G=2.0, eta=1.0)
TAU = MAXWELL.eta / MAXWELL.G
T_END = 2.0
FIELD_OUTPUTS = ("depth", "velocity", "pressure", "deflection", "surface_velocity")


def ramp_scene(times=(1.0, 2.0), outputs=FIELD_OUTPUTS):
    fields = {"field_times": [T_END]} if "pressure" in outputs else {}
    return mv.Scene(indenter=mv.Paraboloid(c=C), medium=MAXWELL, force=([0.0, T_END], [0.0, K * T_END]),
                    duration=T_END, times=list(times), outputs=outputs, **fields)


def creep_integral(t):
    """integral_0^t J(u) du for the Maxwell body, J(u) = 1/G + u/eta."""
    return t / MAXWELL.G + t**2 / (2 * MAXWELL.eta)


def depth_and_rate(t):
    """Lee–Radok depth and penetration rate under F = K t."""
    t = np.asarray(t, float)
    d = (3 * K * creep_integral(t) / (16 * np.sqrt(R))) ** (2 / 3)
    rate = 2 / 3 * d / creep_integral(t) * (1 / MAXWELL.G + t / MAXWELL.eta)
    return d, rate


def contact_radius(t):
    return np.sqrt(R * depth_and_rate(t)[0]) if t > 0 else 0.0


def hertz_deflection(r, a):
    """Hertz's surface deflection outside a contact of radius a: it depends on a and R only."""
    return ((2 * a * a - r * r) * np.arcsin(a / r) + a * np.sqrt(r * r - a * a)) / (np.pi * R)


def hertz_deflection_rate(r, t):
    """d/dt of `hertz_deflection` at fixed r: (4 a asin(a / r) / (pi R)) da/dt."""
    d, rate = depth_and_rate(t)
    a = np.sqrt(R * d)
    return 4 * a * np.arcsin(a / r) / (np.pi * R) * 0.5 * np.sqrt(R / d) * rate


def lee_radok_pressure(r, t):
    """p(r, t) = G(0) P(r, t) + integral_0^t G'(t - s) P(r, s) ds (by parts), G = G0 exp(-t/tau)."""
    def unit(s):
        a = contact_radius(s)
        return 8 / (np.pi * R) * np.sqrt(max(a * a - r * r, 0.0))

    tail = quad(lambda s: -MAXWELL.G / TAU * np.exp(-(t - s) / TAU) * unit(s), 0.0, t, limit=200)[0]
    return MAXWELL.G * unit(t) + tail


@pytest.fixture(scope="module")
def mdr_run():
    return mv.solve(ramp_scene(), "mdr", 8001, dt=0.01)


def test_mdr_penetration_rate_is_second_order_in_the_step():
    times = np.array([0.5, 1.0, 2.0])
    errors = []
    for dt in (0.04, 0.02):
        r = mv.solve(ramp_scene(times, ("depth", "velocity")), "mdr", 8001, dt=dt)
        errors.append(np.max(np.abs(r.velocity / depth_and_rate(times)[1] - 1)))
    # measured 1.6e-4 and 3.3e-5: ratio 4.9
    assert errors[1] < 1e-4
    assert errors[0] / errors[1] > 3.5


def test_mdr_fields_follow_lee_radok(mdr_run):
    f = mdr_run.fields[T_END]
    a = 0.5 * mdr_run.contact_length[-1]
    d, rate = depth_and_rate(T_END)
    outside = f.r > max(a, np.sqrt(R * d))
    # measured 1.5e-5 (the MDR's contact radius is a multiple of dx/2)
    assert np.max(np.abs(f.deflection[outside] / hertz_deflection(f.r[outside], np.sqrt(R * d)) - 1)) < 5e-5
    inside = f.r < a
    assert np.allclose(f.deflection[inside], mdr_run.depth[-1] - C * f.r[inside] ** 2, rtol=0, atol=1e-12)
    # away from the rim, where the rate of an element that just entered contact is resolved
    # by no step: measured 7e-6 beyond 1.1 a
    away = f.r > 1.1 * a
    assert np.max(np.abs(f.surface_velocity[away] / hertz_deflection_rate(f.r[away], T_END) - 1)) < 3e-5
    assert np.all(f.surface_velocity[inside] == mdr_run.velocity[-1])
    assert abs(mdr_run.velocity[-1] / rate - 1) < 1e-5  # measured 2.8e-6
    # pressure: p >= 0, the force by the trapezoid rule (measured 1.7e-5), Lee–Radok inside
    assert np.all(f.pressure >= 0)
    assert np.trapezoid(2 * np.pi * f.r * f.pressure, f.r) == pytest.approx(K * T_END, rel=6e-5)
    core = f.r < 0.9 * a
    exact = np.array([lee_radok_pressure(x, T_END) for x in f.r[core][::10]])
    assert np.max(np.abs(f.pressure[core][::10] - exact)) < 1.5e-3 * exact.max()  # measured 4.9e-4


def test_mdr_surface_velocity_converges_at_the_rim():
    errors = []
    for dt in (0.01, 0.0025):
        r = mv.solve(ramp_scene((T_END,)), "mdr", 8001, dt=dt)
        f = r.fields[T_END]
        a = max(0.5 * r.contact_length[-1], contact_radius(T_END))
        near = (f.r > a) & (f.r < 1.01 * a)
        errors.append(np.max(np.abs(f.surface_velocity[near] / hertz_deflection_rate(f.r[near], T_END) - 1)))
    # measured 1.5e-2 and 6.3e-3: the kink of an element's displacement as it enters contact
    assert errors[1] < 0.6 * errors[0]


@pytest.mark.parametrize("n,deflection_tol,velocity_tol,pressure_tol",
                         [(65, 4.5e-4, 2.5e-2, 2.5e-3), (129, 1.5e-4, 5e-3, 3e-4)])
def test_bem_fields_follow_lee_radok_and_converge(n, deflection_tol, velocity_tol, pressure_tol):
    # measured at n = 65: 1.5e-4, 8.4e-3, 8.6e-4; at n = 129: 4.8e-5, 1.6e-3, 9.2e-5
    r = mv.solve(ramp_scene(), "bem", n, dt=0.01)
    f = r.fields[T_END]
    x, y = np.meshgrid(f.x, f.y)
    radius = np.hypot(x, y)
    a = contact_radius(T_END)
    out = radius > 1.2 * a
    assert np.max(np.abs(f.deflection[out] / hertz_deflection(radius[out], a) - 1)) < deflection_tol
    velocity = hertz_deflection_rate(radius[out], T_END)
    assert np.max(np.abs(f.surface_velocity[out] / velocity - 1)) < velocity_tol
    assert np.all(f.pressure >= 0)
    core = radius < 0.8 * a
    # the reference on 321 radii, interpolated (its own error is 3e-6 of the peak there)
    radii = np.linspace(0.0, 0.8 * a, 321)
    exact = np.interp(radius[core], radii, [lee_radok_pressure(v, T_END) for v in radii])
    assert np.max(np.abs(f.pressure[core] - exact)) < pressure_tol * exact.max()
    assert np.max(np.abs(r.velocity / depth_and_rate(r.t)[1] - 1)) < 1e-2  # measured 3.1e-3


def test_kelvin_voigt_rate_follows_its_creep():
    medium = mv.KelvinVoigt(G=1.0, eta=0.5)
    times = np.array([0.2, 0.5, 1.0, 2.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, force=1.0, duration=2.0, times=times,
                     outputs=("depth", "velocity"))
    r = mv.solve(scene, "mdr", 8001, dt=0.002)
    retard = medium.eta / medium.G
    j = (1 - np.exp(-times / retard)) / medium.G
    d = (3 * j / (16 * np.sqrt(R))) ** (2 / 3)
    rate = 2 / 3 * d / j * np.exp(-times / retard) / (medium.G * retard)
    # first order: the dashpot's backward-Euler step (measured 6.7e-4 of the largest rate)
    assert np.max(np.abs(r.velocity - rate)) < 2e-3 * rate.max()


def test_stiffness_length_is_refused_with_the_reason():
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=MAXWELL, force=1.0, duration=1.0,
                     outputs=("depth", "stiffness_length"))
    with pytest.raises(mv.InvalidInputError, match="stiffness_length.*purely viscous"):
        mv.solve(scene, "mdr", 401)


@pytest.fixture(scope="module")
def unloading_pair():
    """A standard solid pushed in and pulled out (depth 0 -> 0.2 -> 0 m at 0.1 m/s): the
    contact shrinks after t = 1 s, where Lee–Radok no longer holds (Ting's regime)."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=C), medium=mv.StandardSolid(1.0, 3.0, 0.5),
                     depth=([0.0, 1.0, 2.0], [0.0, 0.2, 0.0]), duration=2.0, times=[0.5, 1.0, 1.2, 1.4],
                     outputs=FIELD_OUTPUTS, field_times=[1.0, 1.2, 1.4])
    return mv.solve(scene, "mdr", 8001, dt=0.005), mv.solve(scene, "bem", 129, dt=0.005)


@pytest.mark.parametrize("t", [1.0, 1.2, 1.4])
def test_bem_and_mdr_fields_agree_while_the_contact_shrinks(unloading_pair, t):
    mdr, bem = unloading_pair
    fm, fb = mdr.fields[t], bem.fields[t]
    a = 0.5 * mdr.contact_length[list(mdr.t).index(t)]
    x, y = np.meshgrid(fb.x, fb.y)
    radius = np.hypot(x, y)
    core, outside = radius < 0.8 * a, (radius > 1.2 * a) & (radius < fm.r[-1])
    away = core | outside
    on_grid = {name: np.interp(radius, fm.r, getattr(fm, name))
               for name in ("pressure", "deflection", "surface_velocity")}
    # measured (largest over the three times): 2.8e-4, 4.4e-5, 2.1e-3 of each field's peak
    assert np.max(np.abs(fb.pressure - on_grid["pressure"])[core]) < 1e-3 * fm.pressure.max()
    assert np.max(np.abs(fb.deflection - on_grid["deflection"])[away]) < 1.5e-4 * np.abs(fm.deflection).max()
    velocity_peak = np.abs(fm.surface_velocity).max()
    assert np.max(np.abs(fb.surface_velocity - on_grid["surface_velocity"])[away]) < 6e-3 * velocity_peak
    assert np.all(fb.pressure >= 0) and np.all(fm.pressure >= 0)
