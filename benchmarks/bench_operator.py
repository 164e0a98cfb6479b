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

from _bench import best_of, header, mdrvisc_apply_time, numpy_apply_time, table

REPEATS = {129: 20, 257: 10, 513: 5, 1025: 3}


def repeats_for(n: int, quick: bool) -> int:
    r = REPEATS.get(n, 3 if n > 700 else 10)
    return max(2, r // 3) if quick else r


def measure_mdrvisc(n: int, repeats: int, cg_repeats: int) -> dict:
    from mdrvisc import _core

    dx = 2.56 / n
    p = np.random.default_rng(0).random((n, n))
    build_apply, _ = best_of(lambda: _core.surface_deflection(p, dx), repeats, warmup=1)
    cg = mdrvisc_apply_time(n, repeats=cg_repeats)
    return dict(n=n, build_apply=build_apply, **cg)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[129, 257, 513, 1025])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--mv-only", action="store_true", help="mdrvisc only")
    parser.add_argument("--json", action="store_true", help="print JSON (with --mv-only)")
    args = parser.parse_args(argv)
    cg_repeats = 2 if args.quick else 3

    if args.mv_only:
        out = [measure_mdrvisc(n, repeats_for(n, args.quick), cg_repeats) for n in args.sizes]
        if args.json:
            print(json.dumps(out))
        else:
            for o in out:
                print(o)
        return

    import numpy_reference as ref

    header("Surface operator apply: mdrvisc vs numpy/scipy.fft DC-FFT (G = 1, n x n grid)")
    rows, rows2 = [], []
    for n in args.sizes:
        rep = repeats_for(n, args.quick)
        dx = 2.56 / n
        p = np.random.default_rng(0).random((n, n))
        np1, _ = numpy_apply_time(n, 1, rep)
        npall, np_build = numpy_apply_time(n, -1, rep)
        ref.FFT_WORKERS = -1
        np_ba, _ = best_of(lambda: ref.FftOperator(n, n, dx).apply(p), max(2, rep // 2))
        mv = measure_mdrvisc(n, rep, cg_repeats)
        m = sfft.next_fast_len(2 * n - 2, real=True)
        rows.append([f"{n}^2", f"{m}^2", np1 * 1e3, npall * 1e3, mv["per_apply"] * 1e3,
                     mv["per_iter"] * 1e3, f"{mv['iters_lo']}/{mv['iters_hi']}",
                     np1 / mv["per_apply"], npall / mv["per_apply"]])
        rows2.append([f"{n}^2", np_build * 1e3, np_ba * 1e3, mv["build_apply"] * 1e3,
                      mv["fixed"] * 1e3, np_ba / mv["build_apply"]])
    print("\nApply only (operator built once; mdrvisc from flat-punch CG, differential):")
    table(["grid", "padded", "np w=1 ms", "np w=-1 ms", "mv apply ms", "mv per-iter ms",
           "CG iters lo/hi", "ratio vs w=1", "ratio vs w=-1"], rows,
          ["{}", "{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{}", "{:.2f}x", "{:.2f}x"])
    print("\nBuild + one apply (one-shot use; mdrvisc = _core.surface_deflection):")
    table(["grid", "np build ms", "np build+apply ms", "mv build+apply ms",
           "mv punch fixed cost ms", "ratio"], rows2,
          ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.2f}x"])
    print("   'mv punch fixed cost' = bem_punch time minus its CG iterations: operator build + "
          "first apply + call overhead.")


if __name__ == "__main__":
    main()
