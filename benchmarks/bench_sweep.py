"""Sweeps: ``mv.solve_many`` on this machine and on a Dask LocalCluster against a loop of
one-at-a-time ``mv.solve`` calls (each on every core), for many small scenes.

Workloads: ``--scenes`` (default 200) paraboloids under a constant force on a standard
linear solid, relaxation time varied (500 steps each), solved by MDR at n = 8001 (about
0.1 s a scene) and by BEM at 65^2 (about 0.5 s a scene). Targets on 2 cores: local
parallel >= 1.7x and a LocalCluster of 2 single-threaded worker processes >= 1.6x the loop;
overhead per scene on this machine <= 5 ms, measured as the sweep's wall time per scene for
trivial scenes (an elastic static MDR solve at n = 65, microseconds of work), pool start
included. Every sweep's results are checked equal bit for bit to the loop's.

What is timed: the wall time of each whole sweep (one run each: minutes in all; the loop and
the sweeps run one after the other, so load on the machine shows in the header's numbers).

Run: ``python benchmarks/bench_sweep.py [--scenes 200] [--no-dask]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import mdrvisc as mv
from _bench import header, table
from mdrvisc.result import SERIES


def viscoelastic_scenes(count: int):
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=1.0),
                    force=0.5, duration=2.0)
    return mv.sweep_scenes(base, medium__tau1=np.geomspace(0.05, 20.0, count))


def trivial_scenes(count: int):
    base = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Elastic(G=1.0), force=1.0)
    return mv.sweep_scenes(base, force=np.geomspace(0.2, 2.0, count))


def same(a, b) -> bool:
    """Every series of two results equal bit for bit."""
    return all((getattr(a, k) is None and getattr(b, k) is None)
               or np.array_equal(getattr(a, k), getattr(b, k)) for k in SERIES)


def timed(fn):
    start = time.perf_counter()
    value = fn()
    return time.perf_counter() - start, value


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--scenes", type=int, default=200)
    parser.add_argument("--no-dask", action="store_true", help="skip the LocalCluster rows")
    args = parser.parse_args()
    header("bench_sweep: solve_many (local processes, Dask LocalCluster) vs one at a time")
    client = None
    if not args.no_dask:
        from distributed import Client, LocalCluster
        cluster = LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None)
        client = Client(cluster)
        client.run(mv.set_num_threads, 1)
    rows = []
    scenes = viscoelastic_scenes(args.scenes)
    workloads = (("MDR viscoelastic n=8001", scenes, "mdr", 8001),
                 ("BEM viscoelastic 65^2", scenes, "bem", 65),
                 ("trivial (elastic MDR n=65)", trivial_scenes(1000), "mdr", 65))
    for name, scenes, method, n in workloads:
        loop_time, loop = timed(lambda: [mv.solve(s, method, n) for s in scenes])  # noqa: B023
        local_time, local = timed(lambda: mv.solve_many(scenes, method, n, progress=False))  # noqa: B023
        assert all(same(a, b) for a, b in zip(loop, local.results)), f"{name}: local results differ"
        rows.append((name, len(scenes), "loop of mv.solve", loop_time, 1e3 * loop_time / len(scenes), 1.0))
        rows.append((name, len(scenes), "solve_many local", local_time, 1e3 * local_time / len(scenes),
                     loop_time / local_time))
        if client is not None:
            dask_time, remote = timed(lambda: mv.solve_many(scenes, method, n, client=client,  # noqa: B023
                                                            progress=False))
            assert all(same(a, b) for a, b in zip(loop, remote.results)), f"{name}: Dask results differ"
            rows.append((name, len(scenes), "solve_many Dask 2x1", dask_time, 1e3 * dask_time / len(scenes),
                         loop_time / dask_time))
    table(["workload", "scenes", "run", "wall s", "ms/scene", "speed-up"], rows,
          ["{}", "{}", "{}", "{:.2f}", "{:.2f}", "{:.2f}x"])
    print("   results of every sweep equal bit for bit to the loop's")
    if client is not None:
        client.close()
        cluster.close()


if __name__ == "__main__":
    main()
