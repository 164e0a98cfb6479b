"""Adhesive contact by MDR (JKR by Heß's rule): pull-off convergence under refinement and the
cost of one approach-retract curve, the forward model a fit of a retract curve would call.

Scene: a paraboloid of radius R = 1 m on an elastic body (E* = 1 Pa) with w = 1/pi J/m^2
(so JKR's pull-off under force control is -3/2 pi w R = -1.5 N), force up to 32/3 N and down
to -3 N, 2000 steps through the pull-off; and one AFM-like depth-controlled curve on a standard
solid (sphere R = 10 um, 2100 steps), the case a fit evaluates.

Columns: n (MDR elements over 5 R), the pull-off force's relative error against -3/2 pi w R,
and the wall time of one curve (best of N, ``mv.solve`` end to end).

BEM with a cohesive-zone law is not available yet, so there is no BEM row and no comparison
with the ContactEngineering Adhesion package.

Run: ``python benchmarks/bench_adhesion.py [--sizes 501 2001 8001 32001] [--repeats 5]``.
"""

from __future__ import annotations

import argparse
import math

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, table

W = 1.0 / math.pi


def force_scene() -> mv.Scene:
    times = np.union1d(np.linspace(0.01, 2.0, 200), np.linspace(1.85, 1.95, 2000))
    return mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25),
                    contact=mv.JKR(work_of_adhesion=W),
                    force=([0.0, 1.0, 2.0], [0.0, 32.0 / 3.0, -3.0]), duration=2.0,
                    times=times, dt=0.01)


def afm_scene() -> mv.Scene:
    t_in, t_end = 0.2, 1.0
    times = np.concatenate([np.linspace(0.002, t_in, 100), np.linspace(t_in, t_end, 2001)[1:]])
    return mv.Scene(indenter=mv.Sphere(radius=10e-6),
                    medium=mv.StandardSolid(G_inf=0.2e6, G1=0.6e6, tau1=0.01),
                    contact=mv.JKR(work_of_adhesion=0.05),
                    depth=([0.0, t_in, t_end], [0.0, 1.6e-6, -1.6e-6]), duration=t_end, times=times)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[501, 2001, 8001, 32001])
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    header(f"JKR by MDR: paraboloid under force control, pull-off vs -3/2 pi w R "
           f"(best of {args.repeats})")
    scene = force_scene()
    rows = []
    for n in args.sizes:
        seconds, r = best_of(lambda n=n: mv.solve(scene, "mdr", n), args.repeats, warmup=1)
        rows.append((n, r.pull_off_force, r.pull_off_force / -1.5 - 1.0, r.steps, seconds * 1e3))
    table(["n", "pull-off (N)", "rel. error", "steps", "ms per curve"], rows,
          ["{}", "{:.6f}", "{:+.2e}", "{}", "{:.2f}"])
    header(f"JKR by MDR: sphere on a standard solid, depth-controlled approach and retract "
           f"(best of {args.repeats})")
    scene = afm_scene()
    rows = []
    for n in (501, 2001):
        seconds, r = best_of(lambda n=n: mv.solve(scene, "mdr", n), args.repeats, warmup=1)
        rows.append((n, r.pull_off_force, -r.force.min(), r.steps, seconds * 1e3))
    table(["n", "pull-off (N)", "largest tension (N)", "steps", "ms per curve"], rows,
          ["{}", "{:.4e}", "{:.4e}", "{}", "{:.2f}"])


if __name__ == "__main__":
    main()
