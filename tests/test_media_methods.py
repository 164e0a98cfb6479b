"""Cells of the verification matrix that no other file covers, each against a closed form
written here: elastic x MDR, viscous x BEM x depth control, Kelvin-Voigt x BEM x force,
Prony x BEM x depth control (paraboloid c = 1 1/m, R = 0.5 m, E* = 4 G)."""

import json
import subprocess
from pathlib import Path

import numpy as np
import pytest

import mdrvisc as mv

C, R = 1.0, 0.5
TIMES = np.array([0.5, 1.0, 2.0])


def paraboloid_scene(medium, **loading):
    return mv.Scene(indenter=mv.Paraboloid(c=C), medium=medium, duration=2.0, times=TIMES, **loading)


def test_elastic_mdr_is_hertz():
    # d = (3 F / (16 G sqrt R))^(2/3); measured 1.9e-9 at n = 8001, 1.2e-10 at 32001
    force, g = 1.5, 2.0
    exact = (3 * force / (16 * g * np.sqrt(R))) ** (2 / 3)
    errors = [
        abs(
            mv.solve(
                mv.Scene(indenter=mv.Paraboloid(c=C), medium=mv.Elastic(G=g), force=force), "mdr", n
            ).depth[0]
            / exact
            - 1
        )
        for n in (8001, 32001)
    ]
    assert errors[0] < 6e-9 and errors[1] < errors[0] / 4


def viscous_ramp_force(t, rate, eta=1.0):
    """Depth d = v t on a viscous body: F = 16/3 sqrt(R) eta d(d^(3/2))/dt = 8 sqrt(R) eta v sqrt(v t)."""
    return 8 * np.sqrt(R) * eta * rate * np.sqrt(rate * t)


def test_viscous_depth_control_by_bem_and_mdr():
    scene = paraboloid_scene(mv.Viscous(eta=1.0), depth=([0.0, 2.0], [0.0, 0.2]))
    exact = viscous_ramp_force(TIMES, 0.1)
    # the dashpot is stepped by backward Euler: first order in dt (MDR: 5.0e-3 -> 1.26e-3)
    mdr = [np.max(np.abs(mv.solve(scene, "mdr", 8001, dt=dt).force / exact - 1)) for dt in (0.01, 0.0025)]
    assert mdr[1] < 4e-3 and 3.5 < mdr[0] / mdr[1] < 4.5
    # BEM 129^2 at dt = 2.5 ms: measured 6.6e-4
    bem = mv.solve(scene, "bem", 129, dt=0.0025)
    assert np.max(np.abs(bem.force / exact - 1)) < 2e-3


def test_kelvin_voigt_creep_by_bem():
    # d^(3/2) = 3 F J(t) / (16 sqrt R), J = (1 - exp(-t G / eta)) / G; measured 1.06e-3 (65^2, 2.5 ms)
    medium = mv.KelvinVoigt(G=1.0, eta=0.5)
    r = mv.solve(paraboloid_scene(medium, force=1.0), "bem", 65, dt=0.0025)
    compliance = (1 - np.exp(-TIMES * medium.G / medium.eta)) / medium.G
    exact = (3 * compliance / (16 * np.sqrt(R))) ** (2 / 3)
    assert np.max(np.abs(r.depth / exact - 1)) < 3e-3


@pytest.mark.parametrize("n,tol", [(65, 2.2e-4), (129, 6e-5)])
def test_prony_held_depth_by_bem(n, tol):
    # F = 16/3 sqrt(R) G(t) d^(3/2); measured 7.2e-5 (65^2) and 1.8e-5 (129^2), any dt
    medium = mv.Prony(G_inf=0.5, terms=[(1.0, 0.1), (2.0, 2.0)])
    r = mv.solve(paraboloid_scene(medium, depth=0.1), "bem", n, dt=0.01)
    modulus = 0.5 + np.exp(-TIMES / 0.1) + 2.0 * np.exp(-TIMES / 2.0)
    assert np.max(np.abs(r.force / (16 / 3 * np.sqrt(R) * modulus * 0.1**1.5) - 1)) < tol


ROOT = Path(__file__).resolve().parents[1]


def maxwell_creep_depth(t, g, eta, force=1.0):
    return (3 * force * (1 / g + t / eta) / (16 * np.sqrt(R))) ** (2 / 3)


def kelvin_voigt_creep_depth(t, g, eta, force=1.0):
    return (3 * force * (1 - np.exp(-t * g / eta)) / (g * 16 * np.sqrt(R))) ** (2 / 3)


def prony_held_force(t, depth=0.1):
    return 16 / 3 * np.sqrt(R) * (0.5 + np.exp(-t / 0.1) + 2.0 * np.exp(-t / 2.0)) * depth**1.5


# scene file, quantity, closed form, bound (measured)
BINARY_SCENES = [
    ("maxwell_creep.toml", "depth", lambda t: maxwell_creep_depth(t, 2.0, 1.0), 3e-8),  # 8.9e-9
    ("kelvin_voigt_creep.toml", "depth", lambda t: kelvin_voigt_creep_depth(t, 1.0, 0.5), 3e-3),  # 1.1e-3
    ("prony_relaxation.toml", "force", prony_held_force, 1e-8),  # 2.8e-9
]


@pytest.mark.parametrize("name,quantity,exact,bound", BINARY_SCENES, ids=[s[0] for s in BINARY_SCENES])
def test_the_binary_solves_the_maxwell_kelvin_voigt_and_prony_scene_files(name, quantity, exact, bound):
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=ROOT, check=True)
    out = subprocess.run(
        [str(ROOT / "target" / "release" / "mdrvisc"), "run", "--json", "--no-progress", f"examples/{name}"],
        cwd=ROOT,
        capture_output=True,
        text=True,
        check=True,
    )
    result = json.loads(out.stdout)[0]["result"]
    t = np.array(result["t"])
    assert np.max(np.abs(np.array(result[quantity]) / exact(t) - 1)) < bound
