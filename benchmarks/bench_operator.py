"""Surface operator (DC-FFT, G = 1) apply: mdrvisc (Rust, rustfft/realfft + rayon) against the
same zero-padded FFT convolution in numpy/scipy.fft (benchmarks/numpy_reference.FftOperator).

What is timed (all best of N, wall clock):

* ``np apply w=1`` / ``np apply w=-1``: ``FftOperator.apply`` alone (operator built once
  outside the timing, pocketfft plans warm), scipy.fft ``workers=1`` / ``workers=-1``.
* ``mv apply``: ``mv.arrays.SurfaceOperator.apply(p, out)`` alone (operator and ``out`` made
  once outside the timing), through the public Python API: the call, the input check and the
  GIL release are included.
* ``mv CG iter``: one flat-punch CG iteration of ``_core.bem_punch`` on the full n x n square
  (``dense_limit=0``), from two tolerances, (T_hi - T_lo) / (iters_hi - iters_lo): one apply
  plus the preconditioner's stencil pass and the O(n^2) vector passes of an iteration, as a
  solver sees it.
* ``np build+apply``: ``FftOperator(n, n, dx).apply(p)`` (Love kernel, kernel rfft2, one apply;
  workers=-1); ``mv build+apply``: ``mv.arrays.SurfaceOperator((n, n), dx).apply(p)``.

All timings of one grid size are interleaved (each round runs every measurement once) and
the best of the rounds is kept, so that the compared numbers see the same machine state.

Ratios: apply-only numpy / apply-only mdrvisc, and build+apply numpy / build+apply mdrvisc
(one-shot use).

A third table times the apply alone in *separate* processes (``--one CODE N``, alternately
mdrvisc, numpy workers=-1, numpy workers=1, twice each; best of 10 samples of 5 calls in each
process), so that neither library's threads, caches or allocator state touch the other's
timing. On a 2-core VM the interleaved table has come out both ways: in some runs numpy up
to 1.6x faster than alone, in others mdrvisc 1.1-1.7x slower than alone; the cause was not
found, and the two tables bracket the ratio.

Run: ``python benchmarks/bench_operator.py [--sizes 129 257 513 1025] [--quick]``;
``--mv-only --json`` prints mdrvisc's numbers as JSON (used by bench_threads.py).
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys

import numpy as np
import scipy.fft as sfft

from _bench import best_of, header, interleaved, table

REPEATS = {129: 20, 257: 10, 513: 5, 1025: 3}


def repeats_for(n: int, quick: bool) -> int:
    r = REPEATS.get(n, 3 if n > 700 else 10)
    return max(2, r // 3) if quick else r


def cg_runner(n: int):
    """``run(tol)``: a flat punch on the full n x n square by CG (``dense_limit=0``)."""
    from mdrvisc import _core

    mask = np.ones((n, n), dtype=bool)

    def run(tol):
        return _core.bem_punch(mask, 2.56 / n, 1.0, 1.0, tol=tol, max_iter=100000, dense_limit=0)

    return run


def measure(n: int, rounds: int, with_numpy: bool = True) -> dict:
    """All timings of one grid size, interleaved round by round (see _bench.interleaved)."""
    import mdrvisc as mv

    dx = 2.56 / n
    p = np.random.default_rng(0).random((n, n))
    op, u = mv.arrays.SurfaceOperator((n, n), dx), np.empty((n, n))
    run = cg_runner(n)
    funcs = {"mv_apply": (lambda: op.apply(p, u), 0),
             "mv_ba": (lambda: mv.arrays.SurfaceOperator((n, n), dx).apply(p), 0),
             "cg_lo": lambda: run(1e-2), "cg_hi": lambda: run(1e-8)}
    if with_numpy:
        import numpy_reference as ref

        ref_op = ref.FftOperator(n, n, dx)

        def np_apply(workers):
            ref.FFT_WORKERS = workers
            return ref_op.apply(p)

        def np_build(apply):
            ref.FFT_WORKERS = -1
            o = ref.FftOperator(n, n, dx)
            return o.apply(p) if apply else o

        funcs.update(np1=(lambda: np_apply(1), 0), npall=(lambda: np_apply(-1), 0),
                     np_build=(lambda: np_build(False), 0), np_ba=(lambda: np_build(True), 0))
    res = interleaved(funcs, rounds)
    (t_lo, r_lo), (t_hi, r_hi) = res["cg_lo"], res["cg_hi"]
    cg_iter = (t_hi - t_lo) / max(r_hi.iterations - r_lo.iterations, 1)
    out = dict(n=n, per_apply=res["mv_apply"][0], build_apply=res["mv_ba"][0], cg_iter=cg_iter,
               mv_pad=op.padded[0])
    if with_numpy:
        out.update(np1=res["np1"][0], npall=res["npall"][0], np_build=res["np_build"][0],
                   np_ba=res["np_ba"][0])
    return out


def measure_mdrvisc(n: int, rounds: int) -> dict:
    return measure(n, rounds, with_numpy=False)


def apply_alone(code: str, n: int) -> float:
    """Seconds per apply of one library alone in this process: ``code`` "mv", or numpy with
    that many workers ("-1", "1"); best of 10 samples of 5 calls after 3 warm-up calls."""
    dx = 2.56 / n
    p = np.random.default_rng(0).random((n, n))
    if code == "mv":
        import mdrvisc as mv

        op, u = mv.arrays.SurfaceOperator((n, n), dx), np.empty((n, n))
        call = lambda: op.apply(p, u)  # noqa: E731
    else:
        import numpy_reference as ref

        ref.FFT_WORKERS = int(code)
        ref_op = ref.FftOperator(n, n, dx)
        call = lambda: ref_op.apply(p)  # noqa: E731
    best, _ = best_of(lambda: [call() for _ in range(5)], 10, warmup=1)
    return best / 5


def separate_processes(sizes) -> None:
    """The apply-only table from one process per measurement (see the module docstring)."""
    rows = []
    for n in sizes:
        best = {code: float("inf") for code in ("mv", "-1", "1")}
        for _ in range(2):
            for code in best:
                out = subprocess.run([sys.executable, __file__, "--one", code, str(n)],
                                     capture_output=True, text=True, check=True).stdout
                best[code] = min(best[code], float(out))
        rows.append([f"{n}^2", best["1"] * 1e3, best["-1"] * 1e3, best["mv"] * 1e3,
                     best["1"] / best["mv"], best["-1"] / best["mv"]])
    print("\nApply only, each library alone in its own process (best of 2 processes each):")
    table(["grid", "np w=1 ms", "np w=-1 ms", "mv apply ms", "ratio vs w=1", "ratio vs w=-1"],
          rows, ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.2f}x", "{:.2f}x"])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[129, 257, 513, 1025])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    parser.add_argument("--mv-only", action="store_true", help="mdrvisc only")
    parser.add_argument("--json", action="store_true", help="print JSON (with --mv-only)")
    parser.add_argument("--one", nargs=2, metavar=("CODE", "N"),
                        help="print seconds per apply of CODE (mv, -1, 1) alone at N^2")
    args = parser.parse_args(argv)

    if args.one:
        print(apply_alone(args.one[0], int(args.one[1])))
        return

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
        rows.append([f"{n}^2", f"{pad}^2 / {m['mv_pad']}^2", rounds, m["np1"] * 1e3, m["npall"] * 1e3,
                     m["per_apply"] * 1e3, m["cg_iter"] * 1e3, m["np1"] / m["per_apply"],
                     m["npall"] / m["per_apply"]])
        rows2.append([f"{n}^2", m["np_build"] * 1e3, m["np_ba"] * 1e3, m["build_apply"] * 1e3,
                      m["np_ba"] / m["build_apply"]])
    print("\nApply only (operator built once; all timings of a size interleaved, best of "
          "'rounds'):")
    table(["grid", "padded np / mv", "rounds", "np w=1 ms", "np w=-1 ms", "mv apply ms",
           "mv CG iter ms", "ratio vs w=1", "ratio vs w=-1"], rows,
          ["{}", "{}", "{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.2f}x", "{:.2f}x"])
    print("\nBuild + one apply (one-shot use):")
    table(["grid", "np build ms", "np build+apply ms", "mv build+apply ms", "ratio"], rows2,
          ["{}", "{:.3f}", "{:.3f}", "{:.3f}", "{:.2f}x"])
    separate_processes(args.sizes)


if __name__ == "__main__":
    main()
