"""A constant Poisson ratio nu: every medium's contact modulus is E*(t) = 2 G(t) / (1 - nu).

References are closed forms written here from E = 2 G (1 + nu) and E* = E / (1 - nu^2)
(Hertz; Lee-Radok creep of a paraboloid with the shear creep compliance J(t) of a standard
solid; Radok's viscous paraboloid and flat punch; the power law's hereditary integral by
the Beta function), none of them code of the solvers. Data of the fit: Ting's closed form
(``analytic.ting_paraboloid_triangle``, no stepping), itself checked here against the
hereditary integral by quadrature at nu = 0.3."""

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import integrate, special

import mdrvisc as mv
from mdrvisc.analytic import ting_paraboloid_triangle

NU = 0.3
C = 0.5  # paraboloid h = c r^2 (1/m): radius of curvature R = 1 m
R = 1.0 / (2.0 * C)

MEDIA = [
    lambda nu: mv.Elastic(G=2.0, nu=nu),
    lambda nu: mv.Viscous(eta=2.0, nu=nu),
    lambda nu: mv.KelvinVoigt(G=1.0, eta=2.0, nu=nu),
    lambda nu: mv.Maxwell(G=1.0, eta=2.0, nu=nu),
    lambda nu: mv.StandardSolid(G_inf=1.0, G1=2.0, tau1=0.5, nu=nu),
    lambda nu: mv.Prony(G_inf=1.0, terms=((2.0, 0.5),), nu=nu),
    lambda nu: mv.PowerLaw(G0=1.0, beta=0.3, nu=nu),
]


def hertz_depth(force, g, nu):
    """Hertz: F = (4/3) E / (1 - nu^2) sqrt(R) d^(3/2), E = 2 G (1 + nu)."""
    e = 2.0 * g * (1.0 + nu)
    return (3.0 * force * (1.0 - nu**2) / (4.0 * e * math.sqrt(R))) ** (2.0 / 3.0)


# Hertz at nu = 0.3. Measured relative depth errors: MDR n = 4001 2.3e-7, BEM n = 257 4.1e-5.
@pytest.mark.parametrize("method, n, tolerance", [("mdr", 4001, 1e-6), ("bem", 257, 2e-4)])
def test_hertz_with_a_poisson_ratio(method, n, tolerance):
    g, force = 2.0, 0.02
    scene = mv.Scene(indenter=mv.Paraboloid(c=C, edge=1.0), medium=mv.Elastic(G=g, nu=NU), force=force)
    depth = mv.solve(scene, method, n).depth[-1]
    exact = hertz_depth(force, g, NU)
    assert abs(depth / exact - 1.0) < tolerance, (depth, exact)
    # the same body incompressible is stiffer by (1 - 0.3) / (1 - 0.5) in E*
    assert abs(exact / hertz_depth(force, g, 0.5) - (0.7 / 0.5) ** (2.0 / 3.0)) < 1e-12


def standard_solid_creep(t, g_inf, g1, tau1):
    """Shear creep compliance of G(t) = G_inf + G1 exp(-t / tau1) (1/Pa)."""
    g0 = g_inf + g1
    return 1.0 / g_inf + (1.0 / g0 - 1.0 / g_inf) * np.exp(-g_inf * t / (g0 * tau1))


# Lee-Radok creep of a paraboloid under a step force F: the contact grows, so
# d(t)^(3/2) = 3 F / (4 sqrt(R)) J*(t), with the contact compliance J*(t) = (1 - nu) J(t) / 2.
# Measured worst relative depth errors (nu = 0.3): MDR n = 4001 4.2e-7, BEM n = 129 9.1e-5.
@pytest.mark.parametrize("method, n, tolerance", [("mdr", 4001, 2e-6), ("bem", 129, 5e-4)])
def test_lee_radok_creep_of_a_standard_solid_with_a_poisson_ratio(method, n, tolerance):
    g_inf, g1, tau1, force = 1.0, 2.0, 0.5, 0.05
    times = np.array([0.1, 0.3, 0.6, 1.0, 2.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C, edge=1.0),
                     medium=mv.StandardSolid(G_inf=g_inf, G1=g1, tau1=tau1, nu=NU),
                     force=force, duration=2.0, times=times)
    depth = mv.solve(scene, method, n).depth
    compliance = (1.0 - NU) / 2.0 * standard_solid_creep(times, g_inf, g1, tau1)
    exact = (3.0 * force * compliance / (4.0 * math.sqrt(R))) ** (2.0 / 3.0)
    assert np.max(np.abs(depth / exact - 1.0)) < tolerance, depth / exact - 1.0


# Radok: a viscous half-space is the elastic one with E* = 2 eta / (1 - nu) once the force is
# replaced by the impulse F t: d^(3/2) = 3 F t / (4 E* sqrt(R)).
# Measured worst relative depth errors: MDR n = 4001 5.5e-7, BEM n = 129 2.6e-4.
@pytest.mark.parametrize("method, n, tolerance", [("mdr", 4001, 3e-6), ("bem", 129, 1e-3)])
def test_viscous_paraboloid_with_a_poisson_ratio(method, n, tolerance):
    eta, force = 2.0, 0.01
    times = np.array([0.5, 1.0, 2.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C, edge=1.0), medium=mv.Viscous(eta=eta, nu=NU),
                     force=force, duration=2.0, times=times)
    depth = mv.solve(scene, method, n).depth
    exact = (3.0 * force * times * (1.0 - NU) / (8.0 * eta * math.sqrt(R))) ** (2.0 / 3.0)
    assert np.max(np.abs(depth / exact - 1.0)) < tolerance, depth / exact - 1.0


# A flat rod of radius a on a viscous half-space sinks at F / (2 a E*), E* = 2 eta / (1 - nu);
# its stiffness length F / (E* dd/dt) is the contact's diameter 2 a. Measured: MDR velocity
# 2.2e-16 and stiffness length 0; BEM n = 128 both 2.3e-3 (the grid's disc).
@pytest.mark.parametrize("method, n, tolerance", [("mdr", 2001, 1e-15), ("bem", 128, 1e-2)])
def test_viscous_rod_with_a_poisson_ratio(method, n, tolerance):
    a, eta, force = 0.5, 3.0, 2.0
    scene = mv.Scene(indenter=mv.Rod(radius=a), medium=mv.Viscous(eta=eta, nu=NU), force=force,
                     duration=1.0, outputs=["velocity", "stiffness_length"])
    result = mv.solve(scene, method, n)
    velocity = force * (1.0 - NU) / (4.0 * a * eta)
    assert np.max(np.abs(result.velocity / velocity - 1.0)) < tolerance, result.velocity
    assert np.max(np.abs(result.stiffness_length / (2.0 * a) - 1.0)) < tolerance, result.stiffness_length


# A power law G(t) = G0 (t / t0)^-beta under the depth d = v t on a paraboloid:
# F(t) = 4 / (1 - nu) sqrt(R) v^(3/2) G0 t0^beta t^(3/2 - beta) B(1 - beta, 3/2).
# Measured worst relative force error, MDR n = 2001, 400 steps: 3.2e-5.
def test_power_law_ramp_with_a_poisson_ratio():
    g0, beta, t0, v = 1.0, 0.3, 1.0, 0.01
    times = np.array([0.25, 0.5, 1.0])
    scene = mv.Scene(indenter=mv.Paraboloid(c=C, edge=1.0),
                     medium=mv.PowerLaw(G0=g0, beta=beta, t0=t0, nu=NU), depth=([0.0, 1.0], [0.0, v]),
                     duration=1.0, times=times, dt=1.0 / 400)
    force = mv.solve(scene, "mdr", 2001).force
    exact = (4.0 / (1.0 - NU) * math.sqrt(R) * v**1.5 * g0 * t0**beta * times ** (1.5 - beta)
             * special.beta(1.0 - beta, 1.5))
    assert np.max(np.abs(force / exact - 1.0)) < 1.5e-4, force / exact - 1.0


# Ting's closed form at nu = 0.3 against the hereditary integral by quadrature while loading,
# F(t) = 4 / (1 - nu) sqrt(R) v^(3/2) int_0^t G(t - s) s^(1/2) ds. Measured: 1.0e-15.
def test_ting_closed_form_with_a_poisson_ratio():
    medium = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2, nu=NU)
    radius, rate, t_peak = 5e-6, 1e-6, 1.0
    t = np.array([0.1, 0.4, 0.9])
    force, _, _ = ting_paraboloid_triangle(t, medium, radius, rate, t_peak)
    for now, f in zip(t, force):
        def integrand(s, now=now):
            return (1e3 + 2e3 * math.exp(-(now - s) / 0.2)) * math.sqrt(s)

        integral, _ = integrate.quad(integrand, 0.0, now, epsabs=0.0, epsrel=1e-13)
        exact = 4.0 / (1.0 - NU) * math.sqrt(radius) * rate**1.5 * integral
        assert abs(f / exact - 1.0) < 5e-15, (f, exact)


def triangle(samples=200, rate=1e-6, t_peak=1.0):
    t = np.linspace(0.0, 2.0 * t_peak, samples + 1)[1:]
    return t, np.where(t <= t_peak, rate * t, rate * (2.0 * t_peak - t))


# A standard solid fitted to Ting's curve made with nu = 0.3 (noise-free): the shear moduli
# and the time are recovered, from the class with nu=0.3 and from an instance of nu = 0.3;
# measured worst relative error 5.1e-6 (tau1; the stepping's at 4 substeps). E = 2 (1 + nu) G
# is reported beside G.
def test_fit_recovers_the_shear_moduli_at_a_poisson_ratio():
    true = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2, nu=NU)
    radius = 5e-6
    t, depth = triangle()
    force, _, _ = ting_paraboloid_triangle(t, true, radius, 1e-6, 1.0)
    tip = mv.Paraboloid(c=1 / (2 * radius))
    from_class = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=force, nu=NU, substeps=4)
    from_instance = mv.fit(tip, mv.StandardSolid(G_inf=500.0, G1=500.0, tau1=0.1, nu=NU), t, depth=depth,
                           force=force, substeps=4)
    for result in (from_class, from_instance):
        assert result.success, result.message
        assert result.medium.nu == NU and result.nu == NU
        for name in ("G_inf", "G1", "tau1"):
            assert abs(result.parameters[name] / getattr(true, name) - 1.0) < 3e-5, result
        assert abs(result.young_moduli["E_inf"] / (2.6 * true.G_inf) - 1.0) < 3e-5
        assert result.young_stderr["E1"] == pytest.approx(2.6 * result.stderr["G1"], rel=1e-14)
        text = repr(result)
        assert "E_inf" in text and "G_inf" in text and "nu" in text, text
    # the same curve read as incompressible gives moduli smaller by 2 (1 - nu) = 1.4: the
    # contact modulus is what the curve fixes
    wrong = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=force, substeps=4)
    assert abs(wrong.parameters["G_inf"] * 1.4 / true.G_inf - 1.0) < 3e-5, wrong


@pytest.mark.parametrize("make", MEDIA, ids=lambda m: type(m(0.5)).__name__)
@pytest.mark.parametrize("bad", [0.5000001, -1.0, 0.6, -3.0, float("nan"), float("inf"), "x", None, True])
def test_bad_poisson_ratios_are_refused(make, bad):
    with pytest.raises(mv.InvalidInputError, match="nu"):
        make(bad)


@pytest.mark.parametrize("bad", ["0.5000001", "-1.0", "nan", '"x"'])
def test_bad_poisson_ratios_are_refused_in_scene_files_and_fits(bad, tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text('method = "mdr"\nn = 65\nforce = 1.0\n[indenter]\ntype = "rod"\nradius = 1.0\n'
                    f'[medium]\ntype = "elastic"\nG = 1.0\nnu = {bad}\n')
    with pytest.raises(mv.InvalidInputError, match="nu"):
        mv.scenefile.load_scene(path)
    t, depth = triangle(20)
    with pytest.raises(mv.InvalidInputError, match="nu"):
        mv.fit(mv.Paraboloid(c=1e5), mv.Elastic, t, depth=depth, force=depth,
               nu=json.loads(bad.replace("nan", "NaN")))


def test_fit_refuses_nu_beside_an_instance():
    t, depth = triangle(20)
    with pytest.raises(mv.InvalidInputError, match="nu"):
        mv.fit(mv.Paraboloid(c=1e5), mv.Elastic(G=1.0, nu=0.3), t, depth=depth, force=depth, nu=0.3)


@pytest.mark.parametrize("make", MEDIA, ids=lambda m: type(m(0.5)).__name__)
def test_young_moduli_and_scene_round_trips(make, tmp_path):
    medium = make(NU)
    assert medium.nu == NU and f"nu={NU}" in repr(medium)
    shear = medium._parameters()
    assert len(medium.young_moduli) == sum(name.startswith("G") for name in shear)
    for name, value in medium.young_moduli.items():
        assert value == pytest.approx(2.6 * shear["G" + name[1:]], rel=1e-15)
    assert medium.young_modulus(0.7) == pytest.approx(2.6 * medium.relaxation_modulus(0.7), rel=1e-15)
    if isinstance(medium, mv.Elastic):
        scene = mv.Scene(indenter=mv.Rod(radius=1.0), medium=medium, force=1.0)
    else:
        scene = mv.Scene(indenter=mv.Rod(radius=1.0), medium=medium, force=1.0, duration=1.0)
    path = tmp_path / "scene.toml"
    text = scene.to_toml("mdr", 65, path)
    assert f"nu = {NU}" in text, text
    assert mv.scenefile.load_scene(path)[0].medium == medium
    # nu = 0.5, the default, is not written: incompressible scenes keep their text
    plain = mv.Scene(indenter=mv.Rod(radius=1.0), medium=make(0.5), force=1.0,
                     duration=None if isinstance(medium, mv.Elastic) else 1.0)
    assert "nu" not in plain.to_toml("mdr", 65)
    assert "nu" not in plain.medium._model()


def test_the_binary_and_the_package_agree_at_a_poisson_ratio(tmp_path):
    """The Python command line and `mv.solve` read nu the same way."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=C, edge=1.0), medium=mv.KelvinVoigt(G=1.0, eta=2.0, nu=NU),
                     force=0.01, duration=1.0)
    path = tmp_path / "scene.toml"
    path.write_text(scene.to_toml("mdr", 513))
    out = subprocess.run([sys.executable, "-m", "mdrvisc", "run", "--json", "--no-progress", str(path)],
                         capture_output=True, text=True, check=True).stdout
    document = json.loads(out)
    record = document[0] if isinstance(document, list) else document
    assert record["input"]["medium"]["nu"] == NU
    assert record["result"]["depth"] == mv.solve(scene, "mdr", 513).depth.tolist()


# Hertz data of a paraboloid at nu = 0.3 (E = 2.6 G): the command line's --nu holds it, and
# the fit gives G and E = 2 (1 + nu) G. Measured relative error of G: 2.3e-7 (the fit's 1D
# profile of 500 elements).
def test_the_fit_command_holds_nu(tmp_path):
    g, radius = 2e3, 5e-6
    t, depth = triangle(50)
    force = 4.0 / 3.0 * (2.0 * g * (1.0 + NU)) / (1.0 - NU**2) * math.sqrt(radius) * depth**1.5
    path = tmp_path / "curve.csv"
    np.savetxt(path, np.column_stack([t, depth, force]), delimiter=",", header="t,depth,force",
               comments="")
    command = [sys.executable, "-m", "mdrvisc", "fit", str(path), "--indenter",
               f"paraboloid:c={0.5 / radius}", "--model", "elastic", "--nu", str(NU), "--json"]
    out = subprocess.run(command, capture_output=True, text=True, check=True)
    document = json.loads(out.stdout)
    assert document["nu"] == NU
    # the forward model's area function at n = 500 (measured 1.6e-6 off)
    assert abs(document["parameters"]["G"] / g - 1.0) < 1e-5, document
    assert abs(document["young_moduli"]["E"] / (2.6 * g) - 1.0) < 1e-5, document


# The Rust binary reads nu from a scene file: examples/compressible_standard_solid_creep.toml
# (nu = 0.3) against Lee-Radok, d^(3/2) = 3 F (1 - nu) J(t) / (8 sqrt(R)). Measured: 2.8e-7.
def test_the_binary_solves_the_compressible_example():
    root = Path(__file__).resolve().parents[1]
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=root, check=True)
    out = subprocess.run([str(root / "target" / "release" / "mdrvisc"), "run", "--json", "--no-progress",
                          "examples/compressible_standard_solid_creep.toml"],
                         cwd=root, capture_output=True, text=True, check=True)
    result = json.loads(out.stdout)[0]["result"]
    t = np.array(result["t"])
    compliance = standard_solid_creep(t, 1.0, 3.0, 0.5)
    exact = (3.0 * 1.0 * (1.0 - NU) * compliance / (8.0 * math.sqrt(0.5))) ** (2.0 / 3.0)
    assert np.max(np.abs(np.array(result["depth"]) / exact - 1.0)) < 1.5e-6
