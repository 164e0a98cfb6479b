"""Flat punch on a fixed k x k square contact set: dense faer Cholesky against CG on the FFT
operator, to find the crossover set size (``dense_limit`` of the solvers, default 144).

``_core.bem_punch(mask, dx, eta=1, force=1, dense_limit=K)`` solves K_SS p = 1 on the set S =
mask: densely (faer Cholesky of the |S| x |S| Love matrix) when |S| <= K, else by CG with the
DC-FFT operator of the whole grid. Timed (wall clock, best of N) with K huge (dense) and
K = 0 (CG), tol 1e-10, in two layouts:

* ``in 257^2``: the set centred in a 257 x 257 grid (the CG's FFT works on the whole grid;
  ``bem_punch`` builds the 257^2 FFT operator in both modes, so the dense time includes that
  build too);
* ``alone``: the set is the whole k x k grid.

The two modes are timed interleaved (dense, CG, dense, CG, ...); short calls are repeated
within a sample (~20 ms samples). Also prints the CG iterations and the relative difference
of the punch stiffness (velocity) between the two modes. The crossover is the smallest k from
which CG is faster.

Run: ``python benchmarks/bench_dense_crossover.py [--ks 4 8 11 16 23 32 45] [--grid 257]``.
"""

from __future__ import annotations

import argparse

import numpy as np

from _bench import header, interleaved, table
from mdrvisc import _core

HUGE = 10**9


def punch_times(mask, dx, repeats):
    def run(limit):
        return _core.bem_punch(mask, dx, 1.0, 1.0, tol=1e-10, max_iter=100000, dense_limit=limit)

    res = interleaved({"dense": (lambda: run(HUGE), 0), "cg": (lambda: run(0), 0)}, repeats)
    (t_dense, r_dense), (t_cg, r_cg) = res["dense"], res["cg"]
    v_cg, v_dense = r_cg.velocity[0], r_dense.velocity[0]
    return t_dense, t_cg, r_cg.iterations, abs(v_cg - v_dense) / v_dense


def crossover(ks, dense, cg):
    """Smallest k from which CG stays faster (None if dense always wins)."""
    for j, k in enumerate(ks):
        if all(c < d for d, c in zip(dense[j:], cg[j:])):
            return k
    return None


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--ks", type=int, nargs="+", default=[4, 8, 11, 16, 23, 32, 45])
    parser.add_argument("--grid", type=int, default=257)
    parser.add_argument("--repeats", type=int, default=5)
    args = parser.parse_args(argv)
    n = args.grid
    dx = 2.56 / n
    header(f"Flat punch on a k x k set: dense Cholesky (faer) vs CG (FFT operator), tol 1e-10, "
           f"best of {args.repeats}")
    rows = []
    d_in, c_in, d_al, c_al = [], [], [], []
    for k in args.ks:
        big = np.zeros((n, n), dtype=bool)
        lo = (n - k) // 2
        big[lo:lo + k, lo:lo + k] = True
        td, tc, it, diff = punch_times(big, dx, args.repeats)
        alone = np.ones((k, k), dtype=bool)
        tda, tca, ita, diffa = punch_times(alone, dx, args.repeats)
        d_in.append(td), c_in.append(tc), d_al.append(tda), c_al.append(tca)
        rows.append([k, k * k, td * 1e3, tc * 1e3, it, "dense" if td < tc else "CG",
                     tda * 1e3, tca * 1e3, ita, "dense" if tda < tca else "CG", max(diff, diffa)])
    table(["k", "|S|", f"in {n}^2 dense ms", "CG ms", "CG its", "faster",
           "alone dense ms", "CG ms", "CG its", "faster", "stiffness diff"], rows,
          ["{}", "{}", "{:.3f}", "{:.3f}", "{}", "{}", "{:.3f}", "{:.3f}", "{}", "{}", "{:.1e}"])
    for name, d, c in ((f"in a {n}^2 grid", d_in, c_in), ("alone (k x k grid)", d_al, c_al)):
        k = crossover(args.ks, d, c)
        where = (f"CG faster from k = {k} (|S| = {k * k})" if k is not None
                 else f"dense faster up to k = {args.ks[-1]} (|S| = {args.ks[-1] ** 2})")
        print(f"   crossover {name}: {where}")
    print("   current default dense_limit = 144 elements (k = 12).")


if __name__ == "__main__":
    main()
