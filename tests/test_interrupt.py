"""Ctrl-C stops a run within a second, inside the time-step loops too, and progress is
reported from inside them (not only at output times)."""

import signal
import subprocess
import sys
import time

import pytest

import mdrvisc as mv

LONG = """
import signal, sys, time
# a child started from a shell's background job inherits an ignored SIGINT: take Ctrl-C back
signal.signal(signal.SIGINT, signal.default_int_handler)
import mdrvisc as mv
scene = mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.StandardSolid(1, 3, 0.5), force=1.0,
                 duration=2.0, times=[2.0])
method, n, dt = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
print('started', flush=True)
try:
    mv.solve(scene, method, n, dt=dt)
except KeyboardInterrupt:
    print('interrupted', flush=True)
    sys.exit(0)
sys.exit(3)
"""


@pytest.mark.parametrize("method,n,dt", [("mdr", 20001, 1e-6), ("bem", 129, 1e-5)])
def test_ctrl_c_stops_a_viscoelastic_run_within_a_second(method, n, dt):
    proc = subprocess.Popen([sys.executable, "-c", LONG, method, str(n), str(dt)], stdout=subprocess.PIPE,
                            text=True)
    assert proc.stdout.readline().strip() == "started"
    time.sleep(1.5)
    sent = time.monotonic()
    proc.send_signal(signal.SIGINT)
    try:
        out, _ = proc.communicate(timeout=30)
    finally:
        proc.kill()
    stopped = time.monotonic() - sent
    assert proc.returncode == 0 and out.strip() == "interrupted", (proc.returncode, out)
    assert stopped < 1.0, f"stopped {stopped:.2f} s after SIGINT"


def test_progress_is_reported_inside_the_step_loop():
    scene = mv.Scene(indenter=mv.Paraboloid(1.0, 2.56), medium=mv.StandardSolid(1, 3, 0.5), force=1.0,
                     duration=2.0, times=[2.0])
    calls = []
    r = mv.solve(scene, "mdr", 2001, dt=1e-3,
                 progress=lambda stage, done, total: calls.append((stage, done, total)))
    steps = [c for c in calls if c[0] == "time steps"]
    assert r.steps > 2000  # 2000 steps of 1 ms and the load's jump at t = 0
    assert len(steps) >= 2 and steps[0][1] < steps[0][2] == r.steps and steps[-1][1] == r.steps
