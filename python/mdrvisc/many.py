"""``solve_many(scenes, ...)``: many scenes at once, in parallel on this machine or on a Dask
cluster, each finished result stored at once when a store is given.

On this machine the scenes go in chunks to a pool of worker processes, one per core, each
solving one scene at a time on ``cores / workers`` threads of the compiled core: a process
starts once per worker, not once per scene; a worker that dies is replaced and its chunks
solved again. With a ``dask.distributed.Client`` each chunk of scenes is one task of that
cluster; Dask reschedules the tasks of a worker that dies. Results are
gathered (and stored) by the calling process as they finish, so an interrupted sweep keeps
every scene that finished. Ctrl-C ends the local worker processes at once (the scenes they
were solving are lost, the finished ones kept) and cancels a cluster's tasks; worker
processes also end when the process that started them dies (killed included).

The scenes' warnings (e.g. :class:`mdrvisc.errors.ResolutionWarning`) are gathered: one
warning per kind for the whole sweep, at the caller's line, each result keeping its own in
``Result.warnings``.
"""

from __future__ import annotations

import concurrent.futures
import ctypes
import dataclasses
import inspect
import json
import operator
import os
import pickle
import signal
import sys
import threading
import time
import warnings
from collections.abc import Iterable
from typing import TYPE_CHECKING

from . import _core
from .errors import DataError, InvalidInputError, MdrviscError, ResolutionWarning
from .progress import ProgressBar
from .result import SERIES, Result
from .scene import Scene
from .solve import DEFAULT_N, resolution, solve
from .store import Store, scene_key

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["solve_many", "Sweep", "SceneFailure"]

#: Options of :func:`mdrvisc.solve` that :func:`solve_many` passes on to every solve, with
#: their defaults.
SOLVE_OPTIONS = {name: p.default for name, p in inspect.signature(solve).parameters.items()
                 if name not in ("scene", "method", "n", "progress")}


@dataclasses.dataclass(frozen=True)
class SceneFailure:
    """A scene that raised: its position ``index`` in the sweep, the ``scene`` and the
    exception ``error``."""

    index: int
    scene: Scene
    error: BaseException

    def __repr__(self) -> str:
        message = str(self.error)[:160]
        return f"SceneFailure(index={self.index}, error={type(self.error).__name__}({message!r}))"


@dataclasses.dataclass
class Sweep:
    """The outcome of :func:`solve_many`.

    ``results``: one :class:`Result` per scene, in the order of the scenes; None where the
    scene failed (or was not reached when the sweep was interrupted). ``failures``: a
    :class:`SceneFailure` per scene that raised. ``computed``, ``loaded``: how many results
    were solved now and read from the store. ``wall_time``: seconds of the whole sweep.
    ``n``: the resolution of every solve, None where the scenes' height maps fixed different
    ones.
    """

    scenes: list[Scene]
    method: str
    n: int | None
    results: list[Result | None]
    failures: list[SceneFailure]
    computed: int = 0
    loaded: int = 0
    wall_time: float = 0.0

    def __repr__(self) -> str:
        return f"<Sweep {self.method.upper()} n={self.n}: {self.summary()}>"

    def summary(self) -> str:
        """One line: scenes done (computed, from the store), failed, wall time."""
        done = sum(r is not None for r in self.results)
        return (f"{done}/{len(self.scenes)} scenes done ({self.computed} computed, {self.loaded} "
                f"from the store), {len(self.failures)} failed, wall {self.wall_time:.2f} s")

    def rows(self) -> list[dict]:
        """One dict per scene and output time: ``scene`` (its index), the scene's parameters
        (every number or string of its model, nested keys joined by ``.``, e.g.
        ``medium.tau1``), then the result's series at that time (see :class:`Result`).
        Failed scenes have no rows."""
        rows = []
        for index, (scene, result) in enumerate(zip(self.scenes, self.results)):
            if result is None:
                continue
            parameters = {"scene": index, **scene_parameters(scene)}
            series = {k: getattr(result, k) for k in SERIES if getattr(result, k) is not None}
            for i in range(len(result.t)):
                rows.append({**parameters, **{k: v[i].item() for k, v in series.items()}})
        return rows

    def to_dataframe(self) -> pd.DataFrame:
        """:meth:`rows` as a pandas DataFrame (needs pandas)."""
        try:
            import pandas as pd
        except ImportError as exc:
            raise ImportError("Sweep.to_dataframe needs pandas: pip install pandas") from exc
        return pd.DataFrame(self.rows())


def scene_parameters(scene: Scene) -> dict:
    """The numbers and strings of the scene's model, nested keys joined by ``.``."""
    out = {}

    def walk(value, prefix):
        if isinstance(value, dict):
            for key, item in value.items():
                walk(item, f"{prefix}.{key}" if prefix else key)
        elif isinstance(value, (int, float, str)) and not isinstance(value, bool):
            out[prefix] = value

    walk(json.loads(scene._model.model()), "")
    return out


def _solve_core(core, method: str, n: int, options: dict):
    """(Result, None) of the core scene ``core``, or (None, the exception) when it raised
    (an exception that cannot be pickled back is replaced by an MdrviscError saying it)."""
    try:
        scene = Scene._from_core(core)
        with warnings.catch_warnings():
            # kept in Result.warnings; the sweep issues one summary
            warnings.simplefilter("ignore", ResolutionWarning)
            return solve(scene, method, n, **options), None
    except Exception as exc:  # a failed scene is reported, the sweep goes on
        try:
            pickle.dumps(exc)
        except Exception:
            return None, MdrviscError(f"{type(exc).__name__}: {exc}")
        return None, exc


def _solve_chunk(chunk):
    """[(index, Result or None, exception or None)] of a chunk [(index, core scene, method, n,
    options)]; a core scene travels to a worker process as its model's text and its arrays."""
    return [(index, *_solve_core(core, method, n, options)) for index, core, method, n, options in chunk]


#: prctl's option that sends the calling process a signal when its parent dies (Linux).
_PR_SET_PDEATHSIG = 1
#: Seconds between a worker's checks that the process that started the sweep is alive.
WATCH_PERIOD = 0.5


def _start_worker(threads: int, parent: int) -> None:
    """A worker process: its solves use ``threads`` threads, and it ends when the process
    ``parent`` (the sweep's) dies, killed included: on Linux the kernel kills it with its
    parent process; everywhere, a thread checks every :data:`WATCH_PERIOD` seconds that the
    parent process it started under is still there."""
    if sys.platform.startswith("linux"):
        try:
            libc = ctypes.CDLL(None, use_errno=True)
            libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)
        except (OSError, AttributeError):  # pragma: no cover - a libc without prctl
            pass
    if not _alive(parent):  # died before the request above: nobody would kill this worker
        os._exit(1)
    started_under = os.getppid()

    def watch() -> None:
        while os.getppid() == started_under and _alive(parent):
            time.sleep(WATCH_PERIOD)
        os._exit(1)

    threading.Thread(target=watch, name="mdrvisc-parent-watch", daemon=True).start()
    _core.set_num_threads(threads)


def _alive(pid: int) -> bool:
    """Whether the process ``pid`` exists."""
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except PermissionError:  # pragma: no cover - exists, owned by another user
        return True
    return True


def _stop_pool(pool: concurrent.futures.ProcessPoolExecutor) -> None:
    """Cancels the chunks not started and ends the worker processes now, without waiting for
    the chunks they are solving (a Ctrl-C must not wait for them)."""
    # the executor's own processes: no public way to end them before Python 3.14
    processes = list((getattr(pool, "_processes", None) or {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for process in processes:
        if process.is_alive():
            process.kill()
    for process in processes:
        process.join(timeout=5)


def _cores() -> int:
    """Cores this process may run on."""
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not Linux
        return os.cpu_count() or 1


#: Times the local pool is restarted after a worker process died, before the scenes of the
#: chunks it had not finished are reported failed.
POOL_RESTARTS = 2


def _run_local(tasks, workers: int, advance, collect, work=_solve_chunk) -> None:
    """Solves ``tasks`` [(index, core scene, method, n, options)] in ``workers`` processes; when a
    worker dies (killed, out of memory), the chunks not finished go to a new pool, at most
    :data:`POOL_RESTARTS` times. ``work`` maps a chunk of tasks (each starting with its index)
    to [(index, result or None, exception or None)] (default: solves of scenes)."""
    if workers <= 1 or len(tasks) <= 1:
        for task in tasks:
            for item in work([task]):
                collect(*item)
                advance(1)
        return
    chunks = _chunks(tasks, workers)
    threads = max(1, _cores() // workers)
    for _ in range(POOL_RESTARTS + 1):
        unfinished = []
        with concurrent.futures.ProcessPoolExecutor(workers, initializer=_start_worker,
                                                    initargs=(threads, os.getpid())) as pool:
            futures = {pool.submit(work, chunk): chunk for chunk in chunks}
            try:
                for future in concurrent.futures.as_completed(futures):
                    try:
                        items = future.result()
                    except concurrent.futures.process.BrokenProcessPool as exc:
                        unfinished.append((futures[future], exc))
                        continue
                    for item in items:
                        collect(*item)
                    advance(len(items))
            except BaseException:
                _stop_pool(pool)
                raise
        if not unfinished:
            return
        chunks = [chunk for chunk, _ in unfinished]
    for chunk, error in unfinished:
        for index, *_ in chunk:
            collect(index, None, error)
        advance(len(chunk))


def _chunks(tasks: list, slots: int) -> list:
    """``tasks`` in chunks of up to 16, at least 16 chunks per slot (worker process or thread)
    while there are enough tasks: few messages per scene, and slots that finish together (the
    last chunks, a 16th of each slot's share at most, are what one slot may wait for)."""
    size = max(1, min(16, len(tasks) // (16 * slots)))
    return [tasks[i:i + size] for i in range(0, len(tasks), size)]


def _run_dask(tasks, client, advance, collect, work=_solve_chunk) -> None:
    """Solves ``tasks`` on ``client``'s cluster, one task per chunk of scenes (``work``: as
    in :func:`_run_local`)."""
    from distributed import as_completed

    slots = max(1, sum(w.get("nthreads", 1) for w in client.scheduler_info()["workers"].values()))
    futures = {}
    for chunk in _chunks(tasks, slots):
        futures[client.submit(work, chunk, pure=False)] = chunk
    try:
        for future in as_completed(list(futures)):
            try:
                items = future.result()
            except Exception as exc:  # the task itself failed, e.g. its workers kept dying
                items = [(index, None, exc) for index, *_ in futures[future]]
            for item in items:
                collect(*item)
            advance(len(items))
    except BaseException:
        client.cancel(list(futures))
        raise


def solve_many(scenes: Iterable[Scene], method: str = "bem", n: int | None = None, client=None,
               store=None, progress: bool = True, workers: int | None = None,
               **solve_options) -> Sweep:
    """Solves every scene of ``scenes`` by ``method`` at resolution ``n``, in parallel.

    Parameters
    ----------
    scenes : iterable of Scene
        E.g. from :func:`mdrvisc.sweep_scenes`.
    method, n :
        As in :func:`mdrvisc.solve`, the same for every scene; without ``n``, each height
        map's own and the method's default for other indenters.
    client : dask.distributed.Client, optional
        Run on that cluster (``pip install 'mdrvisc[dask]'``); default: this machine.
    store : str or Path, optional
        A folder of finished results (:class:`mdrvisc.store.Store`): each result is written
        there as soon as it arrives, and scenes already there are loaded, not solved.
    progress : bool
        A progress bar with the time left (:class:`mdrvisc.progress.ProgressBar`: tqdm's, with
        the rate, when installed) and a closing summary on stderr.
    workers : int, optional
        Worker processes on this machine (default: the cores available); ignored with a
        client.
    **solve_options :
        ``tol``, ``max_iter``, ``integrator``, ``step``, ``area_change``, ``dt`` of
        :func:`mdrvisc.solve`.

    Returns
    -------
    Sweep
        Results in the order of the scenes, bit for bit those of one-at-a-time solves; a
        scene that raised is a :class:`SceneFailure` in ``failures`` and None in ``results``.
        Ctrl-C stops the sweep (KeyboardInterrupt) after the stored results are safe.

    Examples
    --------
    >>> base = mv.Scene(indenter=mv.Paraboloid(c=1.0), force=1.0, duration=5.0,
    ...                 medium=mv.StandardSolid(G_inf=1.0, G1=1.0, tau1=1.0))
    >>> sweep = mv.solve_many(mv.sweep_scenes(base, medium__tau1=[0.1, 1, 10]),
    ...                       method="mdr", n=4001, store="runs")     # doctest: +SKIP
    >>> sweep.to_dataframe()                                           # doctest: +SKIP
    """
    start = time.perf_counter()
    scenes = list(scenes)
    for i, scene in enumerate(scenes):
        if not isinstance(scene, Scene):
            raise InvalidInputError(f"solve_many: scenes[{i}] must be a Scene, got {scene!r}")
    if method not in DEFAULT_N:
        raise InvalidInputError(f"solve_many: method must be 'bem' or 'mdr', got {method!r}")
    if n is not None:
        try:
            count = -1 if isinstance(n, bool) else operator.index(n)
        except TypeError:
            count = -1
        if count < 1:
            raise InvalidInputError(f"solve_many: n must be a positive integer, got {n!r}")
        n = count
    ns = [resolution(scene, method, n) for scene in scenes]
    unknown = set(solve_options) - set(SOLVE_OPTIONS)
    if unknown:
        raise InvalidInputError(f"solve_many: unknown solve option(s) {sorted(unknown)}; "
                                f"known: {list(SOLVE_OPTIONS)}")
    if workers is not None and (isinstance(workers, bool) or not isinstance(workers, int) or workers < 1):
        raise InvalidInputError(f"solve_many: workers must be a positive integer, got {workers!r}")
    shelf = None if store is None else Store(store)
    # the key sees every option, so that a default named or not is the same result
    keys = [scene_key(scene, method, k, {**SOLVE_OPTIONS, **solve_options}) for scene, k in zip(scenes, ns)]
    common = ns[0] if ns and all(k == ns[0] for k in ns) else None
    sweep = Sweep(scenes, method, common, [None] * len(scenes), [])
    tasks = []
    for index, (scene, key) in enumerate(zip(scenes, keys)):
        if shelf is not None and key in shelf:
            try:
                sweep.results[index] = shelf.load(key)
                sweep.loaded += 1
                continue
            except DataError as exc:
                warnings.warn(f"solve_many: {exc}; solving scene {index} again", stacklevel=2)
        tasks.append((index, scene._model, method, ns[index], solve_options))

    def collect(index: int, result: Result | None, error: BaseException | None) -> None:
        if error is not None:
            sweep.failures.append(SceneFailure(index, scenes[index], error))
            return
        if shelf is not None:
            shelf.save(keys[index], result)
        sweep.results[index] = result
        sweep.computed += 1

    bar = ProgressBar() if progress and scenes else None
    done = [sweep.loaded]

    def advance(count: int) -> None:
        done[0] += count
        if bar is not None:
            bar("scenes", done[0], len(scenes))

    advance(0)
    try:
        if client is not None:
            _run_dask(tasks, client, advance, collect)
        else:
            _run_local(tasks, min(workers or _cores(), max(1, len(tasks))), advance, collect)
    finally:
        if bar is not None:
            bar.close()
        sweep.failures.sort(key=lambda f: f.index)
        sweep.wall_time = time.perf_counter() - start
        if progress:
            print(f"sweep: {sweep.summary()}", file=sys.stderr, flush=True)
    _warn_once(sweep)
    return sweep


def _warn_once(sweep: Sweep) -> None:
    """One :class:`ResolutionWarning` for the sweep's results that carry warnings, at the
    caller of :func:`solve_many`: how many scenes, which, and the first scene's messages."""
    warned = [(i, r.warnings) for i, r in enumerate(sweep.results) if r is not None and r.warnings]
    if not warned:
        return
    indices = ", ".join(str(i) for i, _ in warned[:10]) + (", ..." if len(warned) > 10 else "")
    first, messages = warned[0]
    warnings.warn(f"solve_many: {len(warned)} of {len(sweep.scenes)} scenes warned (scenes "
                  f"{indices}; each result's .warnings has its own); scene {first}: "
                  f"{'; '.join(messages)}", ResolutionWarning, stacklevel=3)
