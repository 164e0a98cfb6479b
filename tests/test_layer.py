"""A layer of the medium on a rigid base (``mv.Layer``) in scenes: a thick layer is the
periodic half-space, a thin one a Winkler foundation, the scene key round-trips through
TOML and JSON and runs alike from both command lines, and bad layers are refused by
name (MDR on a layer: ``tests/test_layer_mdr.py``). The crate's tests check the layer's
compliance itself (its boundary-value problem and limits) and a viscoelastic layer against Lee–Radok."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.errors import InvalidInputError

ROOT = Path(__file__).resolve().parents[1]


def _wavy(n, g=0.01, ny=4):
    """Heights (m) of a wavy surface of one wavelength (1 m): its separation before loading
    is g (1 - cos(2 pi x)); element size 1 / n."""
    dx = 1.0 / n
    x = (np.arange(n) - n // 2 + 0.5) * dx
    return np.tile(g * np.cos(2 * np.pi * x), (ny, 1)), dx


def _scene(body, n=128, G=1.0, nu=0.5, pressure=0.05):
    heights, dx = _wavy(n)
    return mv.Scene(indenter=mv.HeightMap(heights, dx, periodic=True), medium=mv.Elastic(G=G, nu=nu),
                    force=pressure * heights.size * dx * dx, body=body)


def test_a_thick_layer_is_the_periodic_half_space():
    """A layer 1000 contact half-widths thick (the contact half-width is about a quarter
    wavelength) gives the half-space's depth and mean gap to 1e-6, for both bases."""
    half = mv.solve(_scene(None), "bem")
    for base in mv.body.BASES:
        layer = mv.solve(_scene(mv.Layer(250.0, base)), "bem")
        assert abs(layer.depth[-1] / half.depth[-1] - 1) < 1e-6
        assert abs(layer.mean_gap[-1] / half.mean_gap[-1] - 1) < 1e-6


def test_a_thin_layer_is_a_winkler_foundation():
    """A bonded layer lambda / 100 thick (nu = 0.3): the mean gap is the Winkler
    foundation's (modulus of confined compression 2 G (1 - nu) / ((1 - 2 nu) h), the
    cell's mean mode removed) to 0.5 % (the error falls like h^2: the crate's tests), far
    from the half-space's; the thin layer is the stiffer."""
    n, G, nu, h, pbar = 256, 1.0, 0.3, 0.01, 0.05
    heights, dx = _wavy(n)
    sep = heights.max() - heights
    w = h * (1 - 2 * nu) / (2 * G * (1 - nu))
    lo, hi = -1.0, 1.0
    for _ in range(200):
        d = 0.5 * (lo + hi)
        lo, hi = (d, hi) if np.mean(np.maximum(pbar + (d - sep) / w, 0)) < pbar else (lo, d)
    winkler = np.mean(sep) - 0.5 * (lo + hi)
    layer = mv.solve(_scene(mv.Layer(h), n=n, G=G, nu=nu, pressure=pbar), "bem")
    half = mv.solve(_scene(None, n=n, G=G, nu=nu, pressure=pbar), "bem")
    assert abs(layer.mean_gap[-1] / winkler - 1) < 5e-3
    assert layer.mean_gap[-1] > 1.5 * half.mean_gap[-1]


def test_the_layer_key_round_trips_and_a_half_space_has_none(tmp_path):
    """The ``[layer]`` table is written and read back (TOML, JSON, pickling through the core
    model); a half-space scene's files have no layer key, as before layers existed."""
    scene = _scene(mv.Layer(0.05, "frictionless"))
    assert json.loads(scene.to_json())["layer"] == {"thickness": 0.05, "base": "frictionless"}
    text = scene.to_toml("bem")
    assert "[layer]" in text
    path = tmp_path / "layer.toml"
    scene.to_toml("bem", path=path)
    back = mv.Scene.from_toml(path)
    assert back == scene and back.body == mv.Layer(0.05, "frictionless")
    half = _scene(None)
    assert "layer" not in half.to_json() and "layer" not in half.to_toml("bem")
    assert mv.Scene.from_toml(_written(tmp_path, half)).body is None


def _written(tmp_path, scene, name="half.toml"):
    path = tmp_path / name
    scene.to_toml("bem", path=path)
    return path


@pytest.fixture(scope="module")
def binary():
    """The Rust binary, built (release) if it is not there yet."""
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=ROOT, check=True)
    return ROOT / "target" / "release" / "mdrvisc"


def test_a_layer_scene_runs_alike_from_python_and_both_command_lines(binary, tmp_path):
    """The same numbers from ``mv.solve``, ``mdrvisc run`` and the Rust binary."""
    scene = _scene(mv.Layer(0.03), n=128)
    path = _written(tmp_path, scene, "layer.toml")
    runs = [subprocess.run(command, capture_output=True, text=True, cwd=ROOT)
            for command in ([sys.executable, "-m", "mdrvisc", "run", str(path), "--json"],
                            [str(binary), "run", str(path), "--json"])]
    assert all(r.returncode == 0 for r in runs), [r.stderr for r in runs]
    py, rs = (json.loads(r.stdout)[0]["result"] for r in runs)
    direct = mv.solve(scene, "bem")
    for key in ("depth", "mean_gap", "contact_fraction"):
        assert py[key] == rs[key]
        np.testing.assert_allclose(py[key], getattr(direct, key), rtol=1e-12)


def _dimitriadis(chi):
    """The bottom-effect factor of a bonded incompressible layer, F_layer / F_half-space at
    the same depth: Dimitriadis et al., Biophys. J. 82 (2002) 2798, Eqs. 13 and 14 (the
    same series for a flat punch, chi = a / h, and a sphere, chi = sqrt(R d) / h)."""
    return 1 + 1.133 * chi + 1.283 * chi**2 + 0.769 * chi**3 + 0.0975 * chi**4


@pytest.mark.parametrize("indenter, exponent, tolerances", [
    (mv.Rod(radius=0.2), 1.0, {0.1: 2e-3, 0.3: 1e-2}),
    (mv.Sphere(radius=1.0), 1.5, {0.1: 3e-3, 0.3: 2e-2}),
], ids=["punch", "sphere"])
def test_a_bonded_layer_stiffens_as_dimitriadis_published(indenter, exponent, tolerances):
    """Free grids on a bonded incompressible layer: the force at the layer's depth over the
    half-space's force at that depth (BEM at the same n, so that discretisation cancels:
    F_half(d) scales as d for a punch and d^1.5 for a sphere) against Dimitriadis's series.
    Its leading coefficient 1.133 is a fit to Hayes et al.'s (1972) numerical solutions; the
    layer's exact one, (2 / pi) times the integral of 1 - ratio over |q| h, is 1.1270, 0.5 %
    lower, and the series is truncated at chi^4. Measured deviations (n = 65 and 129 agree
    to 7e-4): punch 0.10 % at chi = 0.1, 0.78 % at 0.3; sphere 0.19 % and 1.7 % (the series
    is stiffer)."""
    for chi, tolerance in tolerances.items():
        if isinstance(indenter, mv.Rod):
            h, force = 0.2 / chi, 0.016
        else:
            h, force = 1.0, 16 / 3 * chi**3
        depth = {}
        for body in (None, mv.Layer(h)):
            scene = mv.Scene(indenter=indenter, medium=mv.Elastic(G=1.0), force=force, body=body)
            depth[body is None] = mv.solve(scene, "bem", 129).depth[-1]
        layer, half = depth[False], depth[True]
        assert layer < half
        a = 0.2 if isinstance(indenter, mv.Rod) else np.sqrt(layer)
        published = force * (layer / half) ** exponent * _dimitriadis(a / h)
        assert abs(published / force - 1) < tolerance, (chi, published / force - 1)


def test_bad_layers_are_refused():
    """Bad thicknesses and bases, elements far larger than the layer is thick: errors that
    say so."""
    coarse = mv.Scene(indenter=mv.Sphere(radius=1e-3), medium=mv.Elastic(G=1e3), force=1e-6,
                      body=mv.Layer(1e-9))
    with pytest.raises(InvalidInputError, match="at most 8 thicknesses"):
        mv.solve(coarse, "bem", 33)
    for thickness in (0.0, -1.0, float("nan"), float("inf"), "thick"):
        with pytest.raises(InvalidInputError, match="thickness"):
            mv.Layer(thickness)
    with pytest.raises(InvalidInputError, match="base"):
        mv.Layer(1.0, "glued")
    with pytest.raises(InvalidInputError, match="body"):
        _scene("layer")


def test_depth_control_sizes_the_grid_from_the_layers_contact():
    """A paraboloid (R = 1) pressed 0.04 deep into a thin bonded incompressible layer of a
    standard solid. The layer's surface bulges around the indenter, so its contact is wider
    than the half-space's at the same depth, beyond the 1.2 sqrt(R d) that a grid sized
    for the half-space reaches (which failed with "the contact reached the edge of the
    grid"); the grid is sized from the layer's contact radius instead. Under depth control
    the contact at the deepest point is the elastic layer's at that depth, whatever the
    relaxation. h = 0.05 (a / h = 7): BEM's contact radius and force agree with MDR on the
    layer, an independent method, to 2 % and 0.5 %, at steps of 0.05 (BEM's quadratic steps
    and MDR's linear ones differ by 1.3 % at 0.5 and 1e-4 at 0.05, where both have
    converged in the step to 1e-3). h = 0.005 (a / h = 80, beyond MDR's
    table): the contact radius tends to the squeeze film's 2 sqrt(R d) (an incompressible
    film whose pressure leaves the contact with zero slope), sqrt(2) times the indenter's
    intersection with the undeformed surface: within 3 %, the film's error being of order
    h / a."""
    depth = 0.04
    hertz, film = np.sqrt(depth), 2 * np.sqrt(depth)

    def scene(h):
        return mv.Scene(indenter=mv.Paraboloid(c=0.5),
                        medium=mv.StandardSolid(G_inf=1.0, G1=1.0, tau1=1.0, nu=0.5),
                        depth=([0.0, 1.0], [0.0, depth]), duration=1.0, times=[1.0], body=mv.Layer(h))

    bem = mv.solve(scene(0.05), "bem", 65, dt=0.05)
    mdr = mv.solve(scene(0.05), "mdr", 2001, dt=0.05)
    radius = np.sqrt(bem.area[-1] / np.pi)
    assert not bem.at_edge[-1] and radius > 1.2 * hertz
    assert abs(radius / (0.5 * mdr.contact_length[-1]) - 1) < 0.02
    assert abs(bem.force[-1] / mdr.force[-1] - 1) < 0.005
    thin = mv.solve(scene(0.005), "bem", 65, dt=0.5)
    radius = np.sqrt(thin.area[-1] / np.pi)
    assert not thin.at_edge[-1] and abs(radius / film - 1) < 0.03
