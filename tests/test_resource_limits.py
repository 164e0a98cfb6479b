"""Sizes a user controls, under a memory cap: every call that would outgrow the process's
memory is a typed error before anything large is allocated, never an abort (an allocation
failure) or an out-of-memory kill; both command lines exit 2 on such input. Each case runs
in a subprocess limited to 3 GiB of address space."""

import resource
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
LIMIT = 3 << 30

CALLS = {
    "dt MDR": "mv.solve(SLS, 'mdr', 201, dt=1e-308)",
    "dt BEM": "mv.solve(SLS, 'bem', 33, dt=1e-300)",
    "dt Scene": "mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.StandardSolid(1, 3, 0.5), force=1.0,"
                " duration=2.0, dt=1e-308)",
    "operator 20000^2": "mv.arrays.SurfaceOperator((20000, 20000), 1.0)",
    "operator 1 x 1e9": "mv.arrays.SurfaceOperator((1, 10**9), 1.0)",
    "operator 2^40": "mv.arrays.SurfaceOperator((2**40, 2**40), 1.0)",
    "BEM n 100000": "mv.solve(VISCOUS, 'bem', 100000)",
    "BEM n 8192": "mv.solve(VISCOUS, 'bem', 8192)",
    "MDR n 1e12": "mv.solve(VISCOUS, 'mdr', 10**12)",
    "MDR n 2^26": "mv.solve(SLS, 'mdr', 1 << 26, dt=0.5)",
    "explicit step": "mv.solve(VISCOUS, 'mdr', 201, integrator='explicit', step=1e-9)",
    "fit substeps 1e9": "mv.fit(mv.Paraboloid(1.0), mv.StandardSolid, [0.5, 1.0], depth=[0.1, 0.2],"
                        " force=[1.0, 2.0], substeps=10**9)",
}

SCRIPT = """
import resource, sys
resource.setrlimit(resource.RLIMIT_AS, ({limit}, {limit}))
import mdrvisc as mv
SLS = mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.StandardSolid(1, 3, 0.5), force=1.0, duration=2.0)
VISCOUS = mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.Viscous(1.0), force=1.0, duration=2.0)
try:
    {call}
except mv.MdrviscError as e:
    print(type(e).__name__, e)
    sys.exit(0)
sys.exit(3)
"""


def capped():
    resource.setrlimit(resource.RLIMIT_AS, (LIMIT, LIMIT))


@pytest.mark.parametrize("name", CALLS)
def test_sizes_beyond_memory_are_typed_errors(name):
    code = SCRIPT.format(limit=LIMIT, call=CALLS[name])
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, f"rc {out.returncode}: {out.stdout}{out.stderr[-2000:]}"
    assert "InvalidInputError" in out.stdout


def test_python_command_line_exits_2_on_an_endless_scene_file_and_a_run_too_big(tmp_path):
    scene = tmp_path / "big.toml"
    scene.write_text('method = "bem"\nn = 8192\n[indenter]\ntype = "paraboloid"\nc = 1.0\nedge = 2.56\n'
                     '[medium]\ntype = "viscous"\neta = 1.0\n\nforce = 1.0\nduration = 2.0\n')
    for path in ("/dev/zero", str(scene)):
        out = subprocess.run([sys.executable, "-m", "mdrvisc", "run", path], capture_output=True, text=True,
                             timeout=120, preexec_fn=capped)
        assert out.returncode == 2, out.stderr[-2000:]
        assert out.stderr.startswith("error:"), out.stderr[-2000:]


def test_binary_exits_2_on_an_endless_scene_file_and_a_run_too_big(tmp_path):
    subprocess.run(["cargo", "build", "--release", "--quiet", "--bin", "mdrvisc"], cwd=ROOT, check=True)
    scene = tmp_path / "big.toml"
    scene.write_text('method = "bem"\nn = 8192\n[indenter]\ntype = "paraboloid"\nc = 1.0\nedge = 2.56\n'
                     '[medium]\ntype = "viscous"\neta = 1.0\n\nforce = 1.0\nduration = 2.0\n')
    for path in ("/dev/zero", str(scene)):
        out = subprocess.run([str(ROOT / "target" / "release" / "mdrvisc"), "run", path], capture_output=True,
                             text=True, timeout=120, preexec_fn=capped)
        assert out.returncode == 2, out.stderr[-2000:]
        assert "error" in out.stderr and "memory allocation" not in out.stderr, out.stderr[-2000:]
