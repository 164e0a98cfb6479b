"""The paper's Section 6 viscous BEM run: mdrvisc against the plain numpy reference.

Problem (the paper's Section 6): paraboloid h = c r^2 on a 2.56 m x 2.56 m square footprint, n x n
= 257 x 257 elements, F = 1 N from t = 0, eta = 1 Pa s, outputs t = 1, 2, 3, 4, 5 s; c = 1
(the paper's figure case), 5 and 20; CG tolerance 1e-10 and 1e-8. Both codes use the same
implicit impulse stepping (one Polonsky-Keer solve per output time, warm-started) on the same
grid (``scene.bem_grid``) and the same stopping rule (relative L1 change of p).

mdrvisc preconditions Polonsky-Keer's search directions with a truncated (7 x 7) inverse-kernel
stencil (``rust/src/precondition.rs``). The numpy reference runs the same algorithm
(``numpy_reference.polonsky_keer(precondition=True)``, column "np-pc"), and the paper's plain
Polonsky-Keer (column "np", what a numpy user following the paper would write). mdrvisc's own
plain solve (``precondition=False``) is timed as well, to separate the preconditioner's gain
from the implementation's.

What is timed (wall clock):

* mdrvisc: ``mv.solve(scene, "bem", n, tol=tol)`` end to end (grid set-up included), best
  of 3 (after one warm-up run). It windows each implicit step to the part of the grid the
  step can touch (exact), and does one operator apply per CG iteration while the active set
  holds (plus one when it changes). "mv plain": ``_core.bem_viscous`` on the scene's grid
  with the depth bounds ``mv.solve`` uses (``scene._model.depth_bounds()``) and
  ``precondition=False``.
* numpy: ``numpy_reference.viscous_bem`` on the same h, mask, dx and tol (scipy.fft
  workers=-1), best of 2. It works on the full grid and does two applies per CG iteration
  (K[p] and K[t]) plus one per solve.

All four alternate run by run (mv, mv plain, np-pc, np, ...) so that they see the same machine
state; a shared VM's speed can drift by up to 2x over minutes.

Columns: wall times, end-to-end ratios, solves, total CG iterations, per-CG-iteration times,
d(5 s) relative error against Lee-Radok (``mv.analytic.paraboloid_depth``). A second table
gives the operator-apply ratio on the full 257^2 grid and splits the same-algorithm ratio into
that apply ratio and the work mdrvisc avoids (fewer / smaller applies). A third gives the
first implicit step alone and mdrvisc's CG iterations per step of the full run (from runs
over the first 1, 2, ... output times: differences of their total iterations).

Run: ``python benchmarks/bench_bem.py [--c 1 5 20] [--tol 1e-10 1e-8] [--quick]``;
``--mv-only --json`` prints mdrvisc's numbers as JSON (used by bench_threads.py).
"""

from __future__ import annotations

import argparse
import json

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, interleaved, table

EDGE, FORCE, ETA, DURATION = 2.56, 1.0, 1.0, 5.0


def scene(c: float):
    return mv.Scene(indenter=mv.Paraboloid(c=c, edge=EDGE), medium=mv.Viscous(eta=ETA),
                    force=FORCE, duration=DURATION)


def run_mdrvisc(c: float, n: int, tol: float, repeats: int) -> dict:
    sc = scene(c)
    wall, res = best_of(lambda: mv.solve(sc, "bem", n, tol=tol), repeats, warmup=1)
    return summarise_mv(c, n, tol, wall, res)


def summarise_mv(c, n, tol, wall, res) -> dict:
    exact = mv.analytic.paraboloid_depth(DURATION, FORCE, c, ETA)
    return dict(c=c, n=n, tol=tol, wall=wall, solves=int(res.solves),
                iterations=int(res.iterations), d5=float(res.depth[-1]),
                err=float(res.depth[-1] - exact) / exact)


def _get(res, key):
    """``key`` of a ``numpy_reference.viscous_bem`` dict or of a ``_core.Report``."""
    return res[key] if isinstance(res, dict) else getattr(res, key)


def summarise_raw(c, wall, res) -> dict:
    """Summary of a ``_core.bem_viscous`` report or a ``numpy_reference.viscous_bem`` result."""
    exact = mv.analytic.paraboloid_depth(DURATION, FORCE, c, ETA)
    d5 = float(_get(res, "depth")[-1])
    return dict(wall=wall, solves=int(_get(res, "solves")),
                iterations=int(np.sum(_get(res, "iterations"))), d5=d5, err=(d5 - exact) / exact)


def run_all(c: float, n: int, tol: float, repeats: int, np_repeats: int):
    """mdrvisc (best of ``repeats``), mdrvisc plain, numpy preconditioned and numpy plain
    (best of ``np_repeats``), interleaved run by run so that all see the same machine state."""
    import numpy_reference as ref
    from mdrvisc import _core

    ref.FFT_WORKERS = -1
    sc = scene(c)
    _, dx, h, mask = sc.bem_grid(n)
    ft, fv = sc.history
    bounds = depth_bounds(sc)
    mv_run = lambda: mv.solve(sc, "bem", n, tol=tol)  # noqa: E731
    runs = {
        "mv": mv_run,
        "mv plain": lambda: _core.bem_viscous(h, mask, dx, ETA, sc.times, ft, fv, tol=tol,
                                              depth_bounds=bounds, precondition=False),
        "np-pc": lambda: ref.viscous_bem(h, mask, dx, ETA, FORCE, sc.times, tol=tol,
                                         max_iter=5000, precondition=True),
        "np": lambda: ref.viscous_bem(h, mask, dx, ETA, FORCE, sc.times, tol=tol, max_iter=5000),
    }
    mv_run()  # warm-up (first use of the pool, page faults)
    out = interleaved(runs, np_repeats, warmup=False)
    wall = out["mv"][0]
    if repeats > np_repeats:
        wall = min(wall, best_of(mv_run, repeats - np_repeats)[0])
    return (summarise_mv(c, n, tol, wall, out["mv"][1]),
            {k: summarise_raw(c, *out[k]) for k in ("mv plain", "np-pc", "np")})


def depth_bounds(sc) -> list[float]:
    """The depth bounds (m) at the output times that ``mv.solve`` gives the BEM run (NaN: no
    bound)."""
    return sc._model.depth_bounds().tolist()


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--c", type=float, nargs="+", default=[1.0, 5.0, 20.0])
    parser.add_argument("--tol", type=float, nargs="+", default=[1e-10, 1e-8])
    parser.add_argument("--n", type=int, default=257)
    parser.add_argument("--repeats", type=int, default=3, help="mdrvisc best of (3)")
    parser.add_argument("--np-repeats", type=int, default=2, help="numpy best of (2)")
    parser.add_argument("--quick", action="store_true", help="best of 2 / 1")
    parser.add_argument("--mv-only", action="store_true", help="mdrvisc only")
    parser.add_argument("--json", action="store_true", help="print JSON (with --mv-only)")
    args = parser.parse_args(argv)
    if args.quick:
        args.repeats, args.np_repeats = 2, 1

    if args.mv_only:
        out = [run_mdrvisc(c, args.n, tol, args.repeats) for c in args.c for tol in args.tol]
        print(json.dumps(out) if args.json else "\n".join(map(str, out)))
        return

    n = args.n
    header(f"Viscous BEM, paper Section 6: paraboloid on 2.56 m square, {n} x {n}, F = 1 N, "
           f"eta = 1 Pa s, t = 1..5 s")
    rows, pairs = [], []
    for c in args.c:
        for tol in args.tol:
            m, o = run_all(c, n, tol, args.repeats, args.np_repeats)
            pairs.append((m, o["np-pc"]))
            rows.append([c, f"{tol:.0e}", m["wall"], o["mv plain"]["wall"], o["np-pc"]["wall"],
                         o["np"]["wall"], o["np-pc"]["wall"] / m["wall"], o["np"]["wall"] / m["wall"],
                         o["mv plain"]["wall"] / m["wall"], m["solves"],
                         f"{m['iterations']}/{o['mv plain']['iterations']}/"
                         f"{o['np-pc']['iterations']}/{o['np']['iterations']}",
                         m["wall"] / m["iterations"] * 1e3,
                         o["np-pc"]["wall"] / o["np-pc"]["iterations"] * 1e3,
                         m["err"], o["np-pc"]["err"], o["np"]["err"]])
    print(f"\nEnd to end (mdrvisc best of {args.repeats}, the others best of {args.np_repeats}; "
          "mv = preconditioned, as mv.solve runs it):")
    table(["c", "tol", "mv s", "mv plain s", "np-pc s", "np s", "np-pc/mv", "np/mv",
           "plain/mv", "solves", "CG iters mv/plain/np-pc/np", "mv ms/iter", "np-pc ms/iter",
           "mv d(5) err", "np-pc d(5) err", "np d(5) err"], rows,
          ["{:g}", "{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.1f}x", "{:.1f}x", "{:.2f}x",
           "{}", "{}", "{:.2f}", "{:.2f}", "{:+.2e}", "{:+.2e}", "{:+.2e}"])
    print("   np-pc/mv: the same (preconditioned) algorithm in numpy; np/mv: the paper's plain "
          "Polonsky-Keer in numpy; plain/mv: mdrvisc's own gain from the preconditioner.")

    # Operator-apply ratio on the full grid, and what the rest of the speed-up comes from.
    from bench_operator import measure

    cg = measure(n, 5)
    np_apply = cg["npall"]
    apply_ratio = np_apply / cg["per_apply"]
    print(f"\nOperator apply on the full {n}^2 grid (padded {2 * n - 2}^2), interleaved, best "
          f"of 5: numpy {np_apply * 1e3:.3f} ms (FftOperator.apply, workers=-1), mdrvisc "
          f"{cg['per_apply'] * 1e3:.3f} ms (SurfaceOperator.apply): apply ratio "
          f"{apply_ratio:.2f}x")
    rows = []
    for m, r in pairs:
        np_applies = 2 * r["iterations"] + r["solves"]
        np_in_apply = np_applies * np_apply
        # full-grid apply-equivalents mdrvisc's wall time would buy
        mv_equiv = m["wall"] / cg["per_apply"]
        rows.append([m["c"], f"{m['tol']:.0e}", r["wall"] / m["wall"], apply_ratio,
                     r["wall"] / m["wall"] / apply_ratio, np_applies, np_in_apply / r["wall"],
                     mv_equiv, mv_equiv / m["iterations"]])
    table(["c", "tol", "np-pc/mv", "apply ratio", "rest (work avoided)", "np-pc applies",
           "np-pc time in applies", "mv wall in full applies", "per mv CG iter"], rows,
          ["{:g}", "{}", "{:.1f}x", "{:.2f}x", "{:.1f}x", "{}", "{:.0%}", "{:.0f}", "{:.2f}"])
    print("   'rest' = same-algorithm ratio / apply ratio: the factor from doing fewer and smaller "
          "applies (windowing, one apply per CG iteration)\n   and from the O(n) work. 'mv wall in "
          "full applies' = mdrvisc wall time / one full-grid mdrvisc apply; numpy needs "
          "2 iters + solves full applies.")
    first_step_table(args.c, args.tol[0], n, args.repeats, args.np_repeats)


def first_step_table(cs, tol, n, repeats, np_repeats):
    """The first implicit step (t = 0 -> 1 s) alone: mdrvisc solves it on the whole grid from a
    uniform start (no window yet), like numpy; the later steps are windowed and warm-started.
    The report gives the run's total of CG iterations; the per-step counts are the differences
    of the totals of runs over the first 1, 2, ... output times (the steps are the same)."""
    import numpy_reference as ref
    from mdrvisc import _core

    rows = []
    for c in cs:
        sc = scene(c)
        _, dx, h, mask = sc.bem_grid(n)
        ft, fv = sc.history
        bounds = depth_bounds(sc)
        full = _core.bem_viscous(h, mask, dx, ETA, sc.times, ft, fv, tol=tol, depth_bounds=bounds)
        totals = [_core.bem_viscous(h, mask, dx, ETA, sc.times[:k], ft, fv, tol=tol,
                                    depth_bounds=bounds[:k]).iterations
                  for k in range(1, len(sc.times))] + [full.iterations]
        per_step = np.diff([0, *totals])
        one = np.array([1.0])
        # the closures run within this iteration, so the loop variables they use are current
        res = interleaved(
            {"mv": lambda: _core.bem_viscous(h, mask, dx, ETA, one, ft, fv, tol=tol),  # noqa: B023
             "np": lambda: ref.viscous_bem(h, mask, dx, ETA, FORCE, one, tol=tol,  # noqa: B023
                                           precondition=True)},
            max(repeats, np_repeats))
        (t1, r1), (tn1, rn1) = res["mv"], res["np"]
        rows.append([c, f"{tol:.0e}", " ".join(str(int(i)) for i in per_step),
                     int(full.solves), t1, int(r1.iterations), tn1,
                     int(rn1["iterations"]), tn1 / t1])
    print("\nFirst step alone (t = 0 -> 1 s, whole grid, cold start; numpy preconditioned too) "
          "and mdrvisc's per-step CG iterations of the full run:")
    table(["c", "tol", "mv iters per step", "mv solves", "mv step-1 s", "mv step-1 iters",
           "np step-1 s", "np step-1 iters", "np/mv step 1"], rows,
          ["{:g}", "{}", "{}", "{}", "{:.3f}", "{}", "{:.3f}", "{}", "{:.1f}x"])


if __name__ == "__main__":
    main()
