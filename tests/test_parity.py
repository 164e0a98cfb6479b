"""One scene model: the Python command line and the Rust binary accept the same files, print
the same JSON keys and numbers and the same tables, and fail alike; scenes round-trip
through TOML."""

import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mdrvisc as mv

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = sorted((ROOT / "examples").glob("*.toml"))


@pytest.fixture(scope="module")
def binary():
    """The Rust binary, built (release) if it is not there yet."""
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=ROOT, check=True)
    return ROOT / "target" / "release" / "mdrvisc"


def _python(*args):
    return subprocess.run([sys.executable, "-m", "mdrvisc", *args], capture_output=True, text=True, cwd=ROOT)


def _rust(binary, *args):
    return subprocess.run([str(binary), *args], capture_output=True, text=True, cwd=ROOT)


def _same(a, b, path="", rel=1e-12):
    """Asserts that two JSON values have the same keys and the same numbers (relative
    ``rel``), wall times aside."""
    if isinstance(a, dict):
        assert isinstance(b, dict) and set(a) == set(b), f"{path}: keys {sorted(a)} != {sorted(b)}"
        for k in a:
            if k != "wall_time":
                _same(a[k], b[k], f"{path}.{k}", rel)
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            _same(x, y, f"{path}[{i}]", rel)
    elif isinstance(a, float) and isinstance(b, float):
        assert math.isclose(a, b, rel_tol=rel, abs_tol=0.0), f"{path}: {a!r} != {b!r}"
    else:
        assert a == b, f"{path}: {a!r} != {b!r}"


def _masked(text):
    return re.sub(r"wall=[0-9.]+ s", "wall=? s", text)


@pytest.mark.parametrize("path", EXAMPLES, ids=lambda p: p.name)
def test_every_example_gives_the_same_json_and_table_from_both_command_lines(binary, path):
    name = str(path.relative_to(ROOT))
    py, rs = _python("run", name, "--json"), _rust(binary, "run", name, "--json")
    assert py.returncode == rs.returncode == 0, py.stderr + rs.stderr
    a, b = json.loads(py.stdout), json.loads(rs.stdout)
    _same(a, b)
    result = a[0]["result"]
    assert result["t"] and len(result["depth"]) == len(result["t"]) and result["wall_time"] > 0
    py, rs = _python("run", name), _rust(binary, "run", name)
    assert py.returncode == rs.returncode == 0
    assert _masked(py.stdout) == _masked(rs.stdout)


def _write(tmp_path, name, text):
    path = tmp_path / name
    path.write_text(text)
    return str(path)


GOOD = """method = "mdr"
n = 2001
force = 1.0
duration = 5.0
[indenter]
type = "paraboloid"
c = 1.0
[medium]
type = "viscous"
eta = 1.0
"""


@pytest.mark.parametrize("edit, word", [
    (("n = 2001", "n = 2001\ncolour = 1"), "colour"),
    (("force = 1.0\n", ""), "force"),
    (("duration = 5.0", "duration = 5.0\ntimes = [1.0, 6.0]"), "times"),
    (("duration = 5.0", "duration = 5.0\noutputs = [\"temperature\"]"), "temperature"),
    (("paraboloid", "teapot"), "teapot"),
    (("eta = 1.0", "eta = -1.0"), "eta"),
    (("n = 2001", "n = 0"), "n"),
    (("method = \"mdr\"\nn = 2001", "method = \"bem\"\nn = 100000"), "8192"),
])
def test_bad_files_fail_alike_in_both_command_lines(binary, tmp_path, edit, word):
    path = _write(tmp_path, "bad.toml", GOOD.replace(*edit))
    py, rs = _python("run", path), _rust(binary, "run", path)
    assert py.returncode == rs.returncode == 2
    assert py.stderr.strip().splitlines()[-1] == rs.stderr.strip().splitlines()[-1]
    assert word in rs.stderr


def test_a_byte_order_mark_is_read_alike(binary, tmp_path):
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + GOOD.encode())
    py, rs = _python("run", str(path), "--json"), _rust(binary, "run", str(path), "--json")
    assert py.returncode == rs.returncode == 0
    _same(json.loads(py.stdout), json.loads(rs.stdout))


def test_both_command_lines_print_the_version(binary):
    py, rs = _python("--version"), _rust(binary, "--version")
    assert py.returncode == rs.returncode == 0
    assert py.stdout.strip() == rs.stdout.strip() == f"mdrvisc {mv.__version__}"


def _scenes():
    """Scenes of every indenter, medium and loading kind."""
    square = mv.Paraboloid(c=1.0, edge=2.56)
    yield mv.Scene(indenter=square, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0)
    yield mv.Scene(indenter=mv.Rod(radius=1.0), medium=mv.Viscous(eta=2.0), force=([0, 1, 2], [0, 1, 0.5]),
                   duration=2.0, times=[0.5, 1.0, 2.0], outputs=("depth", "pressure"), field_times=[1.0])
    yield mv.Scene(indenter=mv.Cone(slope=0.3), medium=mv.Elastic(G=5.0), force=2.0,
                   outputs=("depth", "deflection"))
    yield mv.Scene(indenter=mv.Sphere(radius=2.0), medium=mv.Maxwell(G=1.0, eta=2.0), force=lambda t: 0.1 * t,
                   duration=1.0, dt=0.01)
    yield mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Prony(G_inf=1.0, terms=[(2.0, 0.1), (1.0, 3.0)]),
                   depth=([0.0, 1.0, 2.0], [0.0, 0.2, 0.0]), duration=2.0)
    yield mv.Scene(indenter=mv.Axisymmetric(lambda r: 0.5 * r**2 + 0.1 * r**4, radius=1.5),
                   medium=mv.KelvinVoigt(G=1.0, eta=0.3), force=0.5, duration=1.0)
    yield mv.Scene(indenter=mv.Profile([0.0, 0.5, 1.0], [0.0, 0.1, 0.4]),
                   medium=mv.StandardSolid(1.0, 3.0, 0.5), depth=0.05, duration=1.0)
    yield mv.Scene(indenter=mv.Pyramid(half_angle=0.6, edge=2.0),
                   medium=mv.PowerLaw(G0=1.0, beta=0.2, t0=1.0), depth=([0.0, 1.0], [0.0, 0.3]), duration=1.0)


@pytest.mark.parametrize("scene", list(_scenes()), ids=lambda s: type(s.indenter).__name__)
def test_scenes_round_trip_through_toml(tmp_path, scene):
    path = tmp_path / "scene.toml"
    path.write_text(scene.to_toml("mdr", 501))
    back = mv.Scene.from_toml(path)
    assert back == scene and back.to_json() == scene.to_json()
    loaded, method, n = mv.scenefile.load_scene(path)
    assert (method, n) == ("mdr", 501) and loaded == scene
    np.testing.assert_array_equal(mv.solve(back, "mdr", 501).depth, mv.solve(scene, "mdr", 501).depth)
