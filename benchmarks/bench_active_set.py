"""Static Hertz contact with a growing contact set: the dense primal-dual active-set solve
(faer Cholesky on the set) against Polonsky–Keer (FFT-CG on the whole grid), and what the
automatic choice picks.

``_core.contact_solve(h, mask, dx, 1/G, force=F, active_limit=L)``: L = huge forces the dense
active-set solve (it still falls back to Polonsky–Keer if the set cycles), L = 0 forces
Polonsky–Keer, L = None (default) picks by the crossover model
``contact::Tuning::active_crossover`` (m* = (230 n log2(4 n))^(1/3) for n grid elements). Paraboloid
R = 10 m, G = 1 Pa, edge 2.56 m, force chosen for a Hertz contact radius a; tol 1e-10. Times are
wall clock, best of N, the three modes interleaved. The table also prints both solvers'
iterations, the contact-set size, the largest pressure difference between the two solutions
(relative to the peak) and the crossover set size: the smallest set from which
Polonsky–Keer stays faster, against the model's m*.

Run: ``python benchmarks/bench_active_set.py [--grids 128 256 512] [--repeats 3]``.
"""

from __future__ import annotations

import argparse

import numpy as np

from _bench import header, interleaved, table
from mdrvisc import _core

HUGE = 10**9
RADIUS, G, EDGE = 10.0, 1.0, 2.56


def hertz_problem(n: int, a: float):
    """(h, mask, dx, force) of a paraboloid whose Hertz contact radius is ``a`` (m)."""
    dx = EDGE / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x)
    h = (xx**2 + yy**2) / (2 * RADIUS)
    force = 4 * (4 * G) * a**3 / (3 * RADIUS)
    return h, np.ones((n, n), dtype=bool), dx, force


def model_crossover(n_elements: int) -> int:
    """``contact::Tuning::active_crossover`` of the Rust core, for the table."""
    return int((230.0 * n_elements * np.log2(4.0 * n_elements)) ** (1 / 3))


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--grids", type=int, nargs="+", default=[128, 256, 512])
    parser.add_argument("--radii", type=float, nargs="+", default=[3, 5, 8, 11, 14, 18, 24],
                        help="Hertz contact radii in elements")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    header(f"Hertz contact: dense active set (faer) vs Polonsky-Keer (FFT-CG), tol 1e-10, "
           f"best of {args.repeats}")
    for n in args.grids:
        rows, sizes, dense_t, pk_t = [], [], [], []
        for radius in args.radii:
            h, mask, dx, force = hertz_problem(n, radius * EDGE / n)

            def run(limit, h=h, mask=mask, dx=dx, force=force):
                return _core.contact_solve(h, mask, dx, 1 / G, force=force, tol=1e-10,
                                           active_limit=limit)

            res = interleaved({"dense": lambda: run(HUGE), "pk": lambda: run(0),
                               "auto": lambda: run(None)}, args.repeats)
            (td, rd), (tp, rp), (ta, ra) = res["dense"], res["pk"], res["auto"]
            p_dense, p_pk = rd.fields[0].pressure, rp.fields[0].pressure
            diff = np.abs(p_dense - p_pk).max() / p_pk.max()
            count = int(round(rp.area[0] / dx**2))  # contact-set size (elements)
            sizes.append(count), dense_t.append(td), pk_t.append(tp)
            rows.append([n, radius, count, td * 1e3, rd.iterations, rd.solver,
                         tp * 1e3, rp.iterations, ta * 1e3, ra.solver, tp / td, diff])
        table(["grid", "a/dx", "|S|", "dense ms", "its", "ran", "PK ms", "its", "auto ms",
               "auto picked", "PK/dense", "p diff"], rows,
              ["{}", "{}", "{}", "{:.2f}", "{}", "{}", "{:.2f}", "{}", "{:.2f}", "{}", "{:.2f}",
               "{:.1e}"])
        faster = [j for j in range(len(sizes)) if all(p < d for d, p in
                                                      zip(dense_t[j:], pk_t[j:]))]
        measured = f"|S| = {sizes[faster[0]]}" if faster else f"beyond |S| = {sizes[-1]}"
        print(f"   {n}^2: Polonsky-Keer faster from {measured}; model m* = "
              f"{model_crossover(n * n)}")


if __name__ == "__main__":
    main()
