"""Sweeps: parameter grids, solve_many on this machine and on a Dask LocalCluster, the store
of finished scenes, and what survives Ctrl-C, a killed worker and a scene that raises."""

import json
import multiprocessing
import os
import signal
import subprocess
import sys
import textwrap
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import cli
from mdrvisc.many import SOLVE_OPTIONS
from mdrvisc.result import SERIES
from mdrvisc.store import Store, scene_key

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"


def base_scene(tau=1.0, force=0.5):
    """A paraboloid under a constant force on a standard linear solid."""
    return mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=tau),
                    force=force, duration=2.0, times=[0.5, 1.0, 2.0])


def assert_same(a, b):
    """Every series of two results equal bit for bit."""
    for name in SERIES:
        x, y = getattr(a, name), getattr(b, name)
        assert (x is None) == (y is None), name
        if x is not None:
            assert x.dtype == y.dtype and np.array_equal(x, y), name


def test_sweep_scenes_is_the_product_last_axis_fastest():
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.1, 1.0, 10.0], force=[0.5, 2.0])
    got = [(s.medium.tau1, s.history[1][0]) for s in scenes]
    assert got == [(t, f) for t in (0.1, 1.0, 10.0) for f in (0.5, 2.0)]
    assert scenes[3] == base_scene(tau=1.0, force=2.0)


def test_a_duration_axis_rescales_default_output_times_and_refuses_given_ones_beyond_it():
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0)
    short, long = mv.sweep_scenes(base, duration=[1.0, 4.0])
    assert np.allclose(short.times, [0.2, 0.4, 0.6, 0.8, 1.0]) and long.times[-1] == 4.0
    with pytest.raises(mv.InvalidInputError, match="duration"):
        mv.sweep_scenes(base_scene(), duration=[1.0])


def test_zip_scenes_pairs_the_axes_and_needs_equal_lengths():
    scenes = mv.zip_scenes(base_scene(), **{"medium.tau1": [0.1, 1.0], "force": [0.5, 2.0]})
    assert scenes == [base_scene(0.1, 0.5), base_scene(1.0, 2.0)]
    with pytest.raises(mv.InvalidInputError, match="equal length"):
        mv.zip_scenes(base_scene(), medium__tau1=[0.1, 1.0], force=[0.5])


def test_axes_with_bad_names_or_values_are_errors_naming_them():
    with pytest.raises(mv.InvalidInputError, match="indentor"):
        mv.sweep_scenes(base_scene(), indentor__c=[1.0])
    with pytest.raises(mv.InvalidInputError, match="tau1"):
        mv.sweep_scenes(base_scene(), medium__tau1=[1.0, -1.0])
    with pytest.raises(mv.InvalidInputError, match="no values"):
        mv.sweep_scenes(base_scene(), force=[])


def test_local_sweep_equals_one_at_a_time_solves_in_order():
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.1, 0.5, 2.0], force=[0.5, 1.0])
    sweep = mv.solve_many(scenes, "mdr", 2001, progress=False, workers=2)
    assert sweep.failures == [] and sweep.computed == len(scenes)
    for scene, result in zip(scenes, sweep.results):
        assert_same(result, mv.solve(scene, "mdr", 2001))
    # a physical check of the order: a longer relaxation time leaves the depth smaller at t=0.5 s
    depth = [r.depth[0] for r in sweep.results]
    assert depth[0] > depth[2] > depth[4] and depth[1] > depth[3] > depth[5]


def test_a_scene_that_raises_is_reported_and_the_sweep_goes_on():
    good = base_scene()
    # a small sphere pushed past its equator: valid to build, refused by the solve (DomainError)
    bad = mv.Scene(indenter=mv.Sphere(radius=0.05), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                   force=0.5, duration=2.0, times=[0.5, 1.0, 2.0])
    with pytest.raises(mv.MdrviscError) as direct:
        mv.solve(bad, "mdr", 2001)
    sweep = mv.solve_many([good, bad, good], "mdr", 2001, progress=False, workers=2)
    assert [f.index for f in sweep.failures] == [1]
    assert type(sweep.failures[0].error) is type(direct.value)
    assert sweep.failures[0].scene == bad and sweep.results[1] is None
    assert_same(sweep.results[0], sweep.results[2])


def test_to_dataframe_has_a_row_per_scene_and_time_with_the_parameters():
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.1, 1.0])
    sweep = mv.solve_many(scenes, "mdr", 2001, progress=False, workers=1)
    frame = sweep.to_dataframe()
    assert len(frame) == 2 * 3
    assert list(frame["medium.tau1"]) == [0.1] * 3 + [1.0] * 3
    assert list(frame["t"]) == [0.5, 1.0, 2.0] * 2
    assert np.array_equal(frame["depth"].to_numpy()[3:], sweep.results[1].depth)


def test_bad_arguments_of_solve_many_are_errors_naming_them():
    scenes = [base_scene()]
    for kwargs, word in (({"n": 0}, "n must"), ({"n": True}, "n must"), ({"method": "fem"}, "method"),
                         ({"tolerance": 1e-3}, "tolerance"), ({"workers": 0}, "workers")):
        with pytest.raises(mv.InvalidInputError, match=word):
            mv.solve_many(scenes, **{"method": "mdr", "n": 101, **kwargs})
    with pytest.raises(mv.InvalidInputError, match=r"scenes\[1\]"):
        mv.solve_many([base_scene(), "scene"], "mdr", 101)


def test_progress_without_tqdm_is_a_plain_line_and_a_summary(monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "tqdm", None)
    monkeypatch.setitem(sys.modules, "tqdm.auto", None)
    mv.solve_many([base_scene(), base_scene(2.0)], "mdr", 101, workers=1)
    err = capsys.readouterr().err
    assert "scenes [" in err and "2/2" in err
    assert "sweep: 2/2 scenes done (2 computed, 0 from the store), 0 failed" in err


def test_store_keeps_every_result_and_a_rerun_computes_only_what_is_missing(tmp_path):
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.1, 0.5, 2.0])
    first = mv.solve_many(scenes[:2], "mdr", 2001, store=tmp_path, progress=False, workers=2)
    assert first.computed == 2
    files = sorted(p.name for p in tmp_path.iterdir())
    assert files == sorted(f"{scene_key(s, 'mdr', 2001, SOLVE_OPTIONS)}.npz" for s in scenes[:2])
    second = mv.solve_many(scenes, "mdr", 2001, store=tmp_path, progress=False, workers=2)
    assert (second.loaded, second.computed) == (2, 1)
    for scene, result in zip(scenes, second.results):
        assert_same(result, mv.solve(scene, "mdr", 2001))
    # a default named is the same key; other options, another key
    named = mv.solve_many(scenes[:1], "mdr", 2001, store=tmp_path, progress=False, tol=1e-10)
    assert (named.loaded, named.computed) == (1, 0)
    third = mv.solve_many(scenes[:1], "mdr", 2001, store=tmp_path, progress=False, dt=0.001)
    assert third.computed == 1


def test_store_writes_are_atomic(tmp_path):
    store = Store(tmp_path)
    result = mv.solve(base_scene(), "mdr", 2001)

    class Boom(Exception):
        pass

    def failing_save(path):
        Path(path).write_bytes(b"half a file")
        raise Boom

    result.save = failing_save
    with pytest.raises(Boom):
        store.save("k", result)
    assert list(tmp_path.iterdir()) == [] and "k" not in store


DRIVER = textwrap.dedent("""
    import signal
    import sys
    # a child started from a shell's background job inherits an ignored SIGINT
    signal.signal(signal.SIGINT, signal.default_int_handler)
    import mdrvisc as mv
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0, dt=0.001)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.1 * (1 + k) for k in range(40)])
    if __name__ == "__main__":
        mv.solve_many(scenes, "mdr", 4001, store=sys.argv[1], progress=False, workers=2)
""")


def test_ctrl_c_of_the_driver_keeps_the_finished_scenes(tmp_path):
    store = tmp_path / "store"
    script = tmp_path / "driver.py"
    script.write_text(DRIVER)
    process = subprocess.Popen([sys.executable, str(script), str(store)], stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and len(list(store.glob("*.npz"))) < 2:
        time.sleep(0.05)
    process.send_signal(signal.SIGINT)
    _, err = process.communicate(timeout=60)
    assert process.returncode != 0 and "KeyboardInterrupt" in err
    stored = list(store.glob("*.npz"))
    assert 2 <= len(stored) < 40, "the interrupt came too late to test anything"
    assert not list(store.glob("*.tmp"))
    namespace = {}
    exec(DRIVER, namespace)
    done = {p.stem for p in stored}
    scenes = [s for s in namespace["scenes"] if scene_key(s, "mdr", 4001, SOLVE_OPTIONS) in done]
    scenes += [s for s in namespace["scenes"] if scene_key(s, "mdr", 4001, SOLVE_OPTIONS) not in done][:2]
    rerun = mv.solve_many(scenes, "mdr", 4001, store=store, progress=False, workers=2)
    assert (rerun.loaded, rerun.computed) == (len(stored), 2)
    for scene, result in zip(scenes, rerun.results):
        assert_same(result, mv.solve(scene, "mdr", 4001))


def test_a_killed_local_worker_is_replaced_and_its_scenes_solved_again(tmp_path):
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0, dt=0.001)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.2 * (1 + k) for k in range(10)])
    killed = []

    def kill_a_worker():
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not list(tmp_path.glob("*.npz")):
            time.sleep(0.01)
        children = multiprocessing.active_children()
        if children:
            os.kill(children[0].pid, signal.SIGKILL)
            killed.append(children[0].pid)

    killer = threading.Thread(target=kill_a_worker)
    killer.start()
    sweep = mv.solve_many(scenes, "mdr", 4001, store=tmp_path, progress=False, workers=2)
    killer.join()
    assert killed, "no worker was running when the first result arrived"
    assert sweep.failures == [] and sweep.computed == len(scenes)
    for scene, result in zip(scenes, sweep.results):
        assert_same(result, mv.solve(scene, "mdr", 4001))


def test_cli_sweep_runs_a_sweep_file_and_resumes_from_its_store(tmp_path, capsys):
    path = EXAMPLES / "sweeps" / "relaxation_times.toml"
    status = cli.main(["sweep", str(path), "--store", str(tmp_path), "--json"])
    captured = capsys.readouterr()
    assert status == 0, captured.err
    rows = json.loads(captured.out)
    scenes, method, n = mv.load_sweep(path)
    assert len(scenes) == 10 and len(rows) == 10 * 8
    assert sorted({(r["medium.tau1"], r["force"]) for r in rows}) == sorted(
        (t, f) for t in (0.1, 0.3, 1.0, 3.0, 10.0) for f in (0.5, 1.0))
    assert "10 computed" in captured.err
    assert cli.main(["sweep", str(path), "--store", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    assert "0 computed, 10 from the store" in captured.err and "medium.tau1" in captured.out


def test_cli_sweep_names_a_bad_sweep_file(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    text = (EXAMPLES / "sweeps" / "relaxation_times.toml").read_text()
    path.write_text(text.replace('"product"', '"grid"'))
    assert cli.main(["sweep", str(path)]) == 2
    assert "sweep.mode" in capsys.readouterr().err


LONG_SWEEP = textwrap.dedent("""
    import multiprocessing
    import signal
    import sys
    import threading
    import time
    signal.signal(signal.SIGINT, signal.default_int_handler)
    import mdrvisc as mv
    # scenes of many seconds each: the pool is busy with them when the test acts
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0, dt=1e-6)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.1 * (1 + k) for k in range(8)])

    def announce():
        while len(multiprocessing.active_children()) < 2:
            time.sleep(0.05)
        time.sleep(0.5)
        print(" ".join(str(p.pid) for p in multiprocessing.active_children()), flush=True)

    if __name__ == "__main__":
        threading.Thread(target=announce, daemon=True).start()
        try:
            mv.solve_many(scenes, "mdr", 20001, progress=False, workers=2)
        except KeyboardInterrupt:
            print("interrupted", flush=True)
            sys.exit(0)
        sys.exit(3)
""")


def _gone(pid: int) -> bool:
    """Whether the process ``pid`` has ended (a zombie not yet reaped counts as ended)."""
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().rsplit(")", 1)[1].split()[0] == "Z"
    except FileNotFoundError:
        return True


def _start_long_sweep(tmp_path):
    script = tmp_path / "long_sweep.py"
    script.write_text(LONG_SWEEP)
    process = subprocess.Popen([sys.executable, str(script)], stdout=subprocess.PIPE,
                               stderr=subprocess.PIPE, text=True)
    workers = [int(p) for p in process.stdout.readline().split()]
    assert len(workers) == 2 and not any(_gone(p) for p in workers), process.stderr.read()[-2000:]
    return process, workers


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_the_workers_die_with_their_killed_parent(tmp_path):
    """When the process running a local sweep was killed (SIGKILL, the OOM killer), its
    workers kept solving the queued scenes as orphans (two were alive 13 minutes later)."""
    process, workers = _start_long_sweep(tmp_path)
    process.kill()
    process.wait(timeout=30)  # not communicate: surviving workers would hold its pipes open
    process.stdout.close()
    process.stderr.close()
    deadline = time.monotonic() + 5
    while time.monotonic() < deadline and not all(_gone(p) for p in workers):
        time.sleep(0.05)
    alive = [p for p in workers if not _gone(p)]
    for pid in alive:
        os.kill(pid, signal.SIGKILL)
    assert not alive, f"workers {alive} outlived their parent"


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_ctrl_c_of_the_parent_alone_stops_a_local_sweep_within_a_second(tmp_path):
    """Ctrl-C waited for the running and the queued chunks (41 s when only the parent got
    the signal); the workers are now ended at once."""
    process, workers = _start_long_sweep(tmp_path)
    sent = time.monotonic()
    process.send_signal(signal.SIGINT)
    try:
        out, err = process.communicate(timeout=60)
    finally:
        process.kill()
        for pid in workers:
            if not _gone(pid):
                os.kill(pid, signal.SIGKILL)
    stopped = time.monotonic() - sent
    assert process.returncode == 0 and out.strip() == "interrupted", (process.returncode, out, err[-2000:])
    assert stopped < 1.0, f"stopped {stopped:.2f} s after SIGINT"
    assert all(_gone(p) for p in workers)


def test_a_store_entry_under_another_scenes_key_is_solved_again(tmp_path):
    """A store file copied under another scene's key was loaded silently as that scene's
    result; the key stored in the file is now checked."""
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.5, 2.0])
    store = tmp_path / "store"
    first = mv.solve_many(scenes, "mdr", 2001, store=store, progress=False)
    keys = [scene_key(s, "mdr", 2001, SOLVE_OPTIONS) for s in scenes]
    shelf = Store(store)
    shelf.file(keys[1]).write_bytes(shelf.file(keys[0]).read_bytes())
    with pytest.raises(mv.DataError, match="another scene"):
        shelf.load(keys[1])
    with pytest.warns(UserWarning, match=shelf.file(keys[1]).name):
        again = mv.solve_many(scenes, "mdr", 2001, store=store, progress=False)
    assert (again.loaded, again.computed) == (1, 1)
    assert not np.array_equal(first.results[0].depth, first.results[1].depth)
    for a, b in zip(first.results, again.results):
        np.testing.assert_array_equal(a.depth, b.depth)
    assert_same(shelf.load(keys[1]), first.results[1])


def test_a_store_path_that_is_a_file_is_a_typed_error(tmp_path):
    path = tmp_path / "file"
    path.write_text("")
    with pytest.raises(mv.InvalidInputError, match="is a file"):
        mv.solve_many([base_scene()], "mdr", 2001, store=path, progress=False)


def test_a_sweep_warns_once_at_the_callers_line(recwarn):
    """A sweep printed one ResolutionWarning per scene, attributed to a line of the
    package; now one warning for the sweep, at the line that called solve_many."""
    coarse = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                      force=0.5, duration=2.0)
    with pytest.warns(mv.ResolutionWarning) as single:
        mv.solve(coarse, "mdr", 11)
    assert single[0].filename == __file__
    scenes = mv.sweep_scenes(coarse, medium__tau1=[0.5, 1.0, 2.0])
    recwarn.clear()
    sweep = mv.solve_many(scenes, "mdr", 11, progress=False, workers=1)
    caught = [w for w in recwarn if issubclass(w.category, mv.ResolutionWarning)]
    assert len(caught) == 1, [str(w.message) for w in caught]
    assert caught[0].filename == __file__
    assert "3 of 3 scenes" in str(caught[0].message)
    assert all(r.warnings for r in sweep.results)


distributed = pytest.importorskip("distributed", reason="the Dask tests need mdrvisc[dask]")


@pytest.fixture(scope="module")
def client():
    """A LocalCluster of two single-threaded worker processes."""
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  dashboard_address=None) as cluster, distributed.Client(cluster) as c:
        c.run(mv.set_num_threads, 1)
        yield c


def test_dask_sweep_equals_one_at_a_time_solves(client, tmp_path):
    scenes = mv.sweep_scenes(base_scene(), medium__tau1=[0.1, 0.5, 2.0], force=[0.5, 1.0])
    bad = mv.Scene(indenter=mv.Sphere(radius=0.05), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                   force=0.5, duration=2.0, times=[0.5, 1.0, 2.0])
    sweep = mv.solve_many(scenes + [bad], "mdr", 2001, client=client, store=tmp_path, progress=False)
    assert [f.index for f in sweep.failures] == [len(scenes)]
    for scene, result in zip(scenes, sweep.results):
        assert_same(result, mv.solve(scene, "mdr", 2001))
    assert len(list(tmp_path.glob("*.npz"))) == len(scenes)


def test_dask_retries_the_scenes_of_a_killed_worker(client, tmp_path):
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0, dt=0.001)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.2 * (1 + k) for k in range(8)])
    pids = client.run(os.getpid)
    victim = sorted(pids.values())[0]

    def kill_once_busy():
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not client.processing(list(pids)).get(
                next(a for a, p in pids.items() if p == victim)):
            time.sleep(0.01)
        time.sleep(0.1)
        os.kill(victim, signal.SIGKILL)

    killer = threading.Thread(target=kill_once_busy)
    killer.start()
    sweep = mv.solve_many(scenes, "mdr", 4001, client=client, store=tmp_path, progress=False)
    killer.join()
    assert sweep.failures == [] and all(r is not None for r in sweep.results)
    for scene, result in zip(scenes, sweep.results):
        assert_same(result, mv.solve(scene, "mdr", 4001))
    client.wait_for_workers(2, timeout=60)
    assert victim not in client.run(os.getpid).values()
    client.run(mv.set_num_threads, 1)


def test_a_damaged_store_entry_is_solved_again_with_a_warning(tmp_path):
    """A garbage, truncated or empty file in the store aborted every later rerun of the
    sweep before anything was solved; now the damaged entry is solved again, with a warning
    naming its file, and the other entries are loaded."""
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=1.0)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.5, 1.0, 2.0])
    store = tmp_path / "store"
    first = mv.solve_many(scenes, "mdr", 2001, store=store, progress=False)
    files = sorted(store.glob("*.npz"))
    assert len(files) == 3
    files[0].write_bytes(files[0].read_bytes()[:100])
    with pytest.warns(UserWarning, match=files[0].name):
        again = mv.solve_many(scenes, "mdr", 2001, store=store, progress=False)
    assert again.loaded == 2 and again.computed == 1
    for a, b in zip(first.results, again.results):
        np.testing.assert_array_equal(a.depth, b.depth)


@pytest.mark.skipif(sys.platform == "win32", reason="sends SIGINT to this process")
def test_ctrl_c_cancels_a_dask_sweep_within_a_second(client):
    """Ctrl-C of a Dask sweep raises at once and cancels its tasks on the cluster."""
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0, dt=1e-6)
    scenes = mv.sweep_scenes(base, medium__tau1=[0.1 * (1 + k) for k in range(6)])
    sent = []

    def interrupt_once_busy():
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline and not any(client.processing().values()):
            time.sleep(0.01)
        time.sleep(0.5)
        sent.append(time.monotonic())
        signal.pthread_kill(threading.main_thread().ident, signal.SIGINT)

    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    interrupter = threading.Thread(target=interrupt_once_busy)
    try:
        interrupter.start()
        with pytest.raises(KeyboardInterrupt):
            mv.solve_many(scenes, "mdr", 20001, client=client, progress=False)
        stopped = time.monotonic() - sent[0]
        interrupter.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert stopped < 1.0, f"stopped {stopped:.2f} s after SIGINT"
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(client.processing().values()):
        time.sleep(0.05)
    assert not any(client.processing().values()), client.processing()
    client.restart()  # the workers' threads still run the cancelled chunks: start them afresh
    client.run(mv.set_num_threads, 1)
