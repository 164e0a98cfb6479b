"""The memory every BEM run checks before it allocates (``mdrvisc._core.run_memory``, the
function ``mv.solve``'s check uses) is within 20 % of the peak the run reaches, both ways: an
estimate far below lets a run outgrow the machine, one far above refuses runs that fit.

Each case runs in a fresh subprocess on a grid where the run's buffers dominate the
interpreter's own allocations: the resident peak is reset (``/proc/self/clear_refs``) after
the scene is built, and the growth of the peak over the resident size before the run,
result arrays included, is the measured peak. Linux only."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

BENCH = Path(__file__).resolve().parents[1] / "benchmarks" / "bench_memory.py"

pytestmark = pytest.mark.skipif(not Path("/proc/self/clear_refs").exists(),
                                reason="needs Linux's /proc/self/clear_refs to reset the resident peak")


def measured(kind, mode, n, *extra):
    cmd = [sys.executable, str(BENCH), "--one", kind, mode, str(n), "--tol", "1e-4", *extra]
    out = subprocess.run(cmd, capture_output=True, text=True, timeout=1200)
    assert out.returncode == 0, out.stderr[-2000:]
    return json.loads(out.stdout.strip().splitlines()[-1])


@pytest.mark.parametrize("kind, mode, n, extra", [
    ("static", "free", 768, ()),
    ("static", "periodic", 1024, ()),
    ("static", "free", 512, ("--single-level",)),
    ("creep", "periodic", 512, ("--steps", "4")),
    ("creep", "free", 384, ("--steps", "4")),
    ("viscous", "free", 513, ()),
])
def test_estimate_within_20_percent_of_the_measured_peak(kind, mode, n, extra):
    r = measured(kind, mode, n, *extra)
    ratio = r["estimate"] / r["measured"]
    assert 0.8 <= ratio <= 1.2, f"{kind} {mode} {n}^2: estimate {r['estimate'] / 1e6:.1f} MB, " \
                                f"measured {r['measured'] / 1e6:.1f} MB (ratio {ratio:.2f})"
