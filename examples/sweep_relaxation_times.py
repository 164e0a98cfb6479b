"""A sweep over relaxation times
==============================

A paraboloid under a constant force on a standard linear solid, for a range of relaxation
times, solved in parallel by ``mv.solve_many`` and plotted from its DataFrame.

The depth creeps from the glassy (instantaneous, modulus G_inf + G1) Hertz depth to the
rubbery (long-time, modulus G_inf) one; the relaxation time sets how fast. Both limits are
drawn from the Hertz closed form (``mv.analytic.hertz``, radius of curvature 1 / (2 c) of
z = c r^2, E* = 4 G of an incompressible medium).

Run: python examples/sweep_relaxation_times.py [OUT.png] [--store DIR] [--scheduler ADDRESS]
(default OUT: sweep_relaxation_times.png). With ``--store DIR`` a rerun loads the finished
scenes instead of solving them again; with ``--scheduler`` it runs on an existing Dask
cluster (``pip install 'mdrvisc[dask]'``; e.g. ``dask scheduler`` and ``dask worker
tcp://HOST:8786`` started by hand, or by dask-jobqueue / dask-kubernetes).
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402
from mdrvisc import analytic  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description="A sweep over relaxation times, plotted")
    parser.add_argument("out", nargs="?", default="sweep_relaxation_times.png")
    parser.add_argument("--store", help="folder of finished results")
    parser.add_argument("--scheduler", help="address of a Dask scheduler")
    args = parser.parse_args()

    force, c, g_inf, g1 = 0.5, 1.0, 1.0, 3.0
    base = mv.Scene(indenter=mv.Paraboloid(c=c), medium=mv.StandardSolid(G_inf=g_inf, G1=g1, tau1=1.0),
                    force=force, duration=10.0, times=np.geomspace(0.01, 10.0, 40))
    scenes = mv.sweep_scenes(base, medium__tau1=[0.1, 0.3, 1.0, 3.0, 10.0])
    client = None
    if args.scheduler:
        from distributed import Client
        client = Client(args.scheduler)
    sweep = mv.solve_many(scenes, method="mdr", n=8001, client=client, store=args.store)
    for failure in sweep.failures:
        print(f"scene {failure.index} failed: {failure.error}")
    table = sweep.to_dataframe()

    def hertz_depth(g):
        return analytic.hertz(force, 1.0 / (2.0 * c), 4.0 * g)[1]

    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    for tau, rows in table.groupby("medium.tau1"):
        ax.semilogx(rows["t"], rows["depth"], label=f"tau1 = {tau:g} s")
    for g, name in ((g_inf + g1, "glassy"), (g_inf, "rubbery")):
        ax.axhline(hertz_depth(g), color="0.5", ls="--", lw=0.8)
        ax.annotate(f"{name} Hertz", (0.011, hertz_depth(g)), va="bottom", color="0.4", fontsize=8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("depth (m)")
    ax.set_title(f"Paraboloid on a standard linear solid, F = {force} N (MDR, n = 8001)")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=120)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
