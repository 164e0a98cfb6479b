"""Surface operator (DC-FFT, G = 1) apply: mdrvisc (Rust, rustfft/realfft + rayon) against the
same zero-padded FFT convolution in numpy/scipy.fft (benchmarks/numpy_reference.FftOperator).

What is timed (all best of N, wall clock):

* ``np apply w=1`` / ``np apply w=-1``: ``FftOperator.apply`` alone (operator built once
  outside the timing, pocketfft plans warm), scipy.fft ``workers=1`` / ``workers=-1``.
* ``np build+apply``: ``FftOperator(n, n, dx).apply(p)`` (Love kernel, kernel rfft2, one apply;
  workers=-1).
* ``mv build+apply``: ``mdrvisc._core.surface_deflection(p, dx)``, which builds the operator
  (Love kernel, kernel FFT, plans, buffers) on every call, applies it once, and copies p in
  and u out.
* ``mv apply``: one apply of mdrvisc's operator alone, from the flat-punch CG of
  ``_core.bem_punch`` on the full n x n square with ``dense_limit=0`` timed at two
  tolerances (differential: (T_hi - T_lo) / (iters_hi - iters_lo); see
  ``_bench.mdrvisc_apply_time``). Each CG iteration is one apply plus four O(n^2) passes over
  the set, so this slightly over-states the apply (the O(n^2) work is < 5 % at these sizes).
* ``mv per-iter``: the naive T_hi / iters_hi of the same call (includes the build).

All timings of one grid size are interleaved (each round runs every measurement once) and
the best of the rounds is kept, so that the compared numbers see the same machine state.

Ratios: apply-only numpy / apply-only mdrvisc (the operator as used inside a solver), and
build+apply numpy / build+apply mdrvisc (one-shot use).

Run: ``python benchmarks/bench_operator.py [--sizes 129 257 513 1025] [--quick]``;
``--mv-only --json`` prints mdrvisc's numbers as JSON (used by bench_threads.py).
"""

from __future__ import annotations

import argparse
import json

import numpy as np
import scipy.fft as sfft

from _bench import (TOL_HI, TOL_LO, differential, header, interleaved, punch_runner,
                    table)

REPEATS = {129: 20, 257: 10, 513: 5, 1025: 3}


def repeats_for(n: int, quick: bool) -> int:
    r = REPEATS.get(n, 3 if n > 700 else 10)
    return max(2, r // 3) if quick else r


def measure(n: int, rounds: int, with_numpy: bool = True) -> dict:
    """All timings of one grid size, interleaved round by round (see _bench.interleaved)."""
    from mdrvisc import _core

    dx = 2.56 / n
    p = np.random.default_rng(0).random((n, n))
    run = punch_runner(n)
    funcs = {"mv_ba": (lambda: _core.surface_deflection(p, dx), 0),
             "mv_lo": lambda: run(TOL_LO), "mv_hi": lambda: run(TOL_HI)}
    if with_numpy:
        import numpy_reference as ref

        op = ref.FftOperator(n, n, dx)

        def np_apply(workers):
            ref.FFT_WORKERS = workers
            return op.apply(p)

        def np_build(apply):
            ref.FFT_WORKERS = -1
            o = ref.FftOperator(n, n, dx)
            return o.apply(p) if apply else o

        funcs.update(np1=(lambda: np_apply(1), 0), npall=(lambda: np_apply(-1), 0),
                     np_build=(lambda: np_build(False), 0), np_ba=(lambda: np_build(True), 0))
    res = interleaved(funcs, rounds)
    out = dict(n=n, build_apply=res["mv_ba"][0], **differential(*res["mv_lo"], *res["mv_hi"]))
    if with_numpy:
        out.update(np1=res["np1"][0], npall=res["npall"][0], np_build=res["np_build"][0],
                   np_ba=res["np_ba"][0])
    return out


def measure_mdrvisc(n: int, rounds: int) -> dict:
    return measure(n, rounds, with_numpy=False)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[129, 257, 513, 1025])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--mv-only", action="store_true", help="mdrvisc only")
    parser.add_argument("--json", action="store_true", help="print JSON (with --mv-only)")
    args = parser.parse_args(argv)

    if args.mv_only:
        out = [measure_mdrvisc(n, repeats_for(n, args.quick)) for n in args.sizes]
        if args.json:
            print(json.dumps(out))
        else:
            for o in out:
                print(o)
        return

    header("Surface operator apply: mdrvisc vs numpy/scipy.fft DC-FFT (G = 1, n x n grid)")
    rows, rows2 = [], []
    for n in args.sizes:
        rounds = repeats_for(n, args.quick)
        m = measure(n, rounds)
        pad = sfft.next_fast_len(2 * n - 2, real=True)
        rows.append([f"{n}^2", f"{pad}^2", rounds, m["np1"] * 1e3, m["npall"] * 1e3,
                     m["per_apply"] * 1e3, m["per_iter"] * 1e3,
                     f"{m['iters_lo']}/{m['iters_hi']}", m["np1"] / m["per_apply"],
                     m["npall"] / m["per_apply"]])
        rows2.append([f"{n}^2", m["np_build"] * 1e3, m["np_ba"] * 1e3, m["build_apply"] * 1e3,
                      m["fixed"] * 1e3, m["np_ba"] / m["build_apply"]])
    print("\nApply only (operator built once; mdrvisc from flat-punch CG, differential; all "
          "timings of a size interleaved, best of 'rounds'):")
    table(["grid", "padded", "rounds", "np w=1 ms", "np w=-1 ms", "mv apply ms",
           "mv per-iter ms", "CG iters lo/hi", "ratio vs w=1", "ratio vs w=-1"], rows,
          ["{}", "{}", "{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{}", "{:.2f}x",
           "{:.2f}x"])
    print("\nBuild + one apply (one-shot use; mdrvisc = _core.surface_deflection):")
    table(["grid", "np build ms", "np build+apply ms", "mv build+apply ms",
           "mv punch fixed cost ms", "ratio"], rows2,
          ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.2f}x"])
    print("   'mv punch fixed cost' = bem_punch time minus its CG iterations: operator build + "
          "first apply + call overhead.")


if __name__ == "__main__":
    main()
