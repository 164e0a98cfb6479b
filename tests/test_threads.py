"""The crate's thread pool: its size can be set at run time, results do not depend on it,
and a process forked after a solve (multiprocessing's default on Linux) solves too."""

import re
import subprocess
import sys

import numpy as np
import pytest

import mdrvisc as mv

SCENE = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0), force=1.0,
                 duration=5.0)


def test_thread_count_is_set_and_results_repeat_bit_for_bit():
    runs = {}
    try:
        for n in (1, 2):
            mv.set_num_threads(n)
            assert mv.num_threads() == n
            runs[n] = mv.solve(SCENE, "bem", 65).depth
    finally:
        mv.set_num_threads(None)
    np.testing.assert_array_equal(runs[1], runs[2])
    with pytest.raises(mv.InvalidInputError, match="number of threads must be"):
        mv.set_num_threads(0)


@pytest.mark.parametrize("n", [10**9, 2**64, -1, -(2**70), 2.0, "4", True, [2]])
def test_thread_counts_out_of_range_or_not_integers_are_refused(n):
    """A billion threads would be spawned until the OS refuses (the machine's whole thread
    budget); negative, huge, float, string and bool counts are not counts. Each is refused
    before anything changes, with the bound in the message."""
    before = mv.num_threads()
    with pytest.raises(mv.InvalidInputError, match="number of threads"):
        mv.set_num_threads(n)
    assert mv.num_threads() == before


def test_a_few_threads_per_core_are_allowed():
    with pytest.raises(mv.InvalidInputError, match="at most") as refused:
        mv.set_num_threads(10**6)
    most = int(re.search(r"at most (\d+)", str(refused.value)).group(1))
    assert most >= 8
    try:
        mv.set_num_threads(most)
        assert mv.num_threads() == most
        with pytest.raises(mv.InvalidInputError, match=f"at most {most}"):
            mv.set_num_threads(most + 1)
    finally:
        mv.set_num_threads(None)


def test_a_forked_child_solves_after_the_parent_did(tmp_path):
    """Without its own pool rebuilt after fork, the child's first solve waits forever for
    threads the fork did not copy (the timeout turns that into a failure)."""
    script = tmp_path / "fork.py"
    script.write_text(
        "import multiprocessing as mp\n"
        "import mdrvisc as mv\n"
        "sc = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0),"
        " force=1.0, duration=5.0)\n"
        "def child(q):\n"
        "    q.put(float(mv.solve(sc, 'bem', 33).depth[-1]))\n"
        "if __name__ == '__main__':\n"
        "    parent = float(mv.solve(sc, 'bem', 33).depth[-1])\n"
        "    ctx = mp.get_context('fork')\n"
        "    q = ctx.Queue()\n"
        "    p = ctx.Process(target=child, args=(q,))\n"
        "    p.start()\n"
        "    value = q.get(timeout=60)\n"
        "    p.join(60)\n"
        "    assert value == parent and p.exitcode == 0\n"
        "    print('ok')\n")
    out = subprocess.run([sys.executable, str(script)], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr


def test_one_surface_operator_serves_several_threads():
    """Calls from 4 threads on one operator all succeed and equal the sequential result."""
    from concurrent.futures import ThreadPoolExecutor

    op = mv.arrays.SurfaceOperator((65, 65), 0.04)
    rng = np.random.default_rng(3)
    pressures = [rng.random((65, 65)) for _ in range(16)]
    expected = [op.apply(p) for p in pressures]
    with ThreadPoolExecutor(4) as pool:
        got = list(pool.map(op.apply, pressures))
    for a, b in zip(expected, got):
        np.testing.assert_array_equal(a, b)


NESTED = """
import sys, threading
import mdrvisc as mv
mv.set_num_threads(int(sys.argv[1]))
sc = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.StandardSolid(1.0, 3.0, 0.5),
              force=1.0, duration=2.0)
inner = []
def progress(stage, done, total):
    if len(inner) < 2:
        t = threading.Thread(target=lambda: inner.append(mv.solve(sc, 'mdr', 2001, dt=1e-3).depth[-1]))
        t.start()
        t.join()
outer = []
def run():
    outer.append(mv.solve(sc, 'mdr', 4001, dt=1e-3, progress=progress).depth[-1])
threads = [threading.Thread(target=run) for _ in range(2)]
for t in threads:
    t.start()
for t in threads:
    t.join()
assert len(outer) == 2 and len(inner) >= 2, (outer, inner)
print('ok')
"""


@pytest.mark.parametrize("threads", [1, 2])
def test_a_callback_that_joins_another_solve_does_not_deadlock(tmp_path, threads):
    """Two outer solves whose progress callbacks each run a solve on another thread and join
    it: with callbacks served on the calling threads no worker of the pool waits on Python,
    so the inner solves get workers (the timeout turns a deadlock into a failure)."""
    script = tmp_path / "nested.py"
    script.write_text(NESTED)
    out = subprocess.run([sys.executable, str(script), str(threads)], capture_output=True, text=True,
                         timeout=120)
    assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
