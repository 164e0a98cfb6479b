"""A sweep on a Dask cluster, with a store and a resume
=====================================================

``mv.solve_many`` runs many scenes on a Dask cluster when given a client
(``pip install 'mdrvisc[dask]'``): each chunk of scenes is one task, and the cluster
reschedules the tasks of a worker that dies. With ``store=DIR`` each result is written to
``DIR`` as soon as it arrives, under a key of its scene, method, resolution and options; a
rerun loads what is there and solves only the rest. A sweep that was interrupted (Ctrl-C, a
lost job, a time limit) is resumed by running it again.

On a real cluster the client connects to its scheduler, e.g.
``Client("tcp://scheduler-host:8786")`` for ``dask scheduler`` / ``dask worker`` started by
hand, or a ``dask_jobqueue.SLURMCluster`` / ``PBSCluster``; the store is written by the
calling process, so it needs no shared file system. Here a local cluster stands in for it.

The sweep: a spherical tip (radius 5 um) pushed 1 um into a standard solid and pulled out,
over its relaxation time and its relaxed modulus; the figure shows the force curves.

Run: python examples/sweep_dask_store.py [OUT.png] [--scheduler ADDRESS]
(default OUT: sweep_dask_store.png)
"""

import argparse
import tempfile
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from distributed import Client, LocalCluster  # noqa: E402

import mdrvisc as mv  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description="A sweep on a Dask cluster, stored and resumed")
    parser.add_argument("out", nargs="?", default="sweep_dask_store.png")
    parser.add_argument("--scheduler", help="address of a Dask scheduler (default: a local cluster)")
    args = parser.parse_args()

    base = mv.Scene(indenter=mv.Sphere(radius=5e-6),
                    medium=mv.StandardSolid(G_inf=1e3, G1=3e3, tau1=0.1),
                    depth=([0.0, 1.0, 2.0], [0.0, 1e-6, 0.0]), duration=2.0,
                    times=np.linspace(0.02, 2.0, 100))
    scenes = mv.sweep_scenes(base, medium__tau1=[0.01, 0.1, 1.0, 10.0], medium__G_inf=[1e3, 2e3])

    if args.scheduler:
        client = Client(args.scheduler)
    else:   # two workers of one thread each, in this process
        client = Client(LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                     dashboard_address=None))
    client.run(mv.set_num_threads, 1)   # one mdrvisc thread per worker thread
    store = Path(tempfile.mkdtemp()) / "runs"

    # A first run that stops after half the scenes (as if its job ran out of time) ...
    first = mv.solve_many(scenes[:4], method="mdr", n=4001, client=client, store=store,
                          progress=False)
    print("first run: ", first.summary())
    # ... and the whole sweep, run again: the finished scenes come from the store.
    sweep = mv.solve_many(scenes, method="mdr", n=4001, client=client, store=store,
                          progress=False)
    print("second run:", sweep.summary())
    print(f"{len(list(store.glob('*.npz')))} results in the store")
    client.close()

    table = sweep.to_dataframe()
    print(table.groupby(["medium.G_inf", "medium.tau1"])["force"].max().rename("peak force (N)"))

    fig, axes = plt.subplots(1, 2, figsize=(10.0, 4.0), sharey=True)
    for ax, (g_inf, rows) in zip(axes, table.groupby("medium.G_inf")):
        for tau, curve in rows.groupby("medium.tau1"):
            ax.plot(curve["t"], curve["force"] * 1e9, label=f"tau1 = {tau:g} s")
        ax.set_title(f"G_inf = {g_inf:g} Pa, G1 = 3000 Pa")
        ax.set_xlabel("t (s)")
    axes[0].set_ylabel("force (nN)")
    axes[0].legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
