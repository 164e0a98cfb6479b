"""Thread scaling of mdrvisc, 1 vs 2 threads: the viscous BEM paper run (bench_bem.py) and the
surface operator apply (bench_operator.py). Target: >= 1.6x on 2 threads for 513^2 and up.

rayon sizes its global pool once, from RAYON_NUM_THREADS, when the pool first starts; so
each configuration runs in its own subprocess (``bench_bem.py --mv-only --json`` and
``bench_operator.py --mv-only --json``) with RAYON_NUM_THREADS=1 or 2. The two
configurations are run alternately ``--rounds`` times (default 2) and the best time of each is
kept, so that a burst of other work on the machine does not land on one configuration only.
On a 2-core machine, any other running process takes cores from the 2-thread run: check the
load average printed with the tables.

What is timed: see bench_bem.py (mv.solve end to end, best of 3) and bench_operator.py
(per apply by mv.arrays.SurfaceOperator.apply; build + one apply by a fresh SurfaceOperator).

Run: ``python benchmarks/bench_threads.py [--sizes 129 257 513 1025] [--rounds 2] [--quick]``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

from _bench import _busy_seconds, _own_seconds, header, table, wait_quiet

HERE = Path(__file__).resolve().parent


def run(script, threads, extra, quiet):
    """One subprocess; returns its JSON list, each entry tagged with ``others``: the CPU other
    processes used meanwhile (cores on average)."""
    wait_quiet(quiet)
    env = dict(os.environ, RAYON_NUM_THREADS=str(threads))
    b0, o0, t0 = _busy_seconds(), _own_seconds(), time.perf_counter()
    out = subprocess.run([sys.executable, str(HERE / script), "--mv-only", "--json", *extra],
                         env=env, check=True, capture_output=True, text=True)
    wall = time.perf_counter() - t0
    others = max(0.0, (_busy_seconds() - b0) - (_own_seconds() - o0)) / wall
    res = json.loads(out.stdout.strip().splitlines()[-1])
    for r in res:
        r["others"] = others
    return res


def best(results, key):
    """Element-wise minimum of ``key`` over the rounds' result lists."""
    return [min(r[i][key] for r in results) for i in range(len(results[0]))]


def others_of_best(results, key):
    """Other processes' CPU (cores) during the round that gave each minimum."""
    return [min((r[i] for r in results), key=lambda e: e[key])["others"]
            for i in range(len(results[0]))]


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[129, 257, 513, 1025])
    parser.add_argument("--c", type=float, nargs="+", default=[1.0, 5.0, 20.0])
    parser.add_argument("--rounds", type=int, default=2)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--only", choices=["bem", "operator"], help="run one part only")
    parser.add_argument("--wait-quiet", type=float, default=60.0,
                        help="before each subprocess, wait up to this many seconds for other "
                        "processes to use < 0.1 cores (0: do not wait)")
    args = parser.parse_args(argv)
    quick = ["--quick"] if args.quick else []
    header("Thread scaling of mdrvisc: RAYON_NUM_THREADS = 1 vs 2 (subprocesses)")

    bem_args = ["--c", *map(str, args.c), "--tol", "1e-10", "1e-8", *quick]
    op_args = ["--sizes", *map(str, args.sizes), *quick]
    bem = {1: [], 2: []}
    op = {1: [], 2: []}
    for _ in range(args.rounds):
        for threads in (1, 2):
            if args.only != "operator":
                bem[threads].append(run("bench_bem.py", threads, bem_args, args.wait_quiet))
            if args.only != "bem":
                op[threads].append(run("bench_operator.py", threads, op_args, args.wait_quiet))

    if args.only != "operator":
        bem_table(bem)
    if args.only != "bem":
        operator_table(op)


def bem_table(bem):
    print("\nViscous BEM paper run, 257 x 257, mv.solve end to end:")
    w1, w2 = best(bem[1], "wall"), best(bem[2], "wall")
    o1, o2 = others_of_best(bem[1], "wall"), others_of_best(bem[2], "wall")
    rows = [[r["c"], f"{r['tol']:.0e}", r["iterations"], a, b, a / b, f"{x:.2f}/{y:.2f}"]
            for r, a, b, x, y in zip(bem[1][0], w1, w2, o1, o2)]
    table(["c", "tol", "CG iters", "1 thread s", "2 threads s", "speed-up",
           "others 1t/2t"], rows,
          ["{:g}", "{}", "{}", "{:.3f}", "{:.3f}", "{:.2f}x", "{}"])


def operator_table(op):
    print("\nSurface operator (per apply: SurfaceOperator.apply; build+apply: a fresh "
          "SurfaceOperator):")
    a1, a2 = best(op[1], "per_apply"), best(op[2], "per_apply")
    b1, b2 = best(op[1], "build_apply"), best(op[2], "build_apply")
    o1, o2 = others_of_best(op[1], "per_apply"), others_of_best(op[2], "per_apply")
    rows = [[f"{r['n']}^2", x * 1e3, y * 1e3, x / y, u * 1e3, v * 1e3, u / v,
             "n/a" if r["n"] < 513 else "yes" if x / y >= 1.6 else "NO", f"{p:.2f}/{q:.2f}"]
            for r, x, y, u, v, p, q in zip(op[1][0], a1, a2, b1, b2, o1, o2)]
    table(["grid", "apply 1t ms", "apply 2t ms", "speed-up", "build+apply 1t ms",
           "build+apply 2t ms", "speed-up", ">=1.6x (513+)", "others 1t/2t"], rows,
          ["{}", "{:.3f}", "{:.3f}", "{:.2f}x", "{:.3f}", "{:.3f}", "{:.2f}x", "{}", "{}"])
    print("   'others 1t/2t': CPU (cores, average) other processes used during the subprocess "
          "that gave the best time;\n   on 2 cores, > ~0.1 during a 2-thread run means its "
          "speed-up is understated.")


if __name__ == "__main__":
    main()
