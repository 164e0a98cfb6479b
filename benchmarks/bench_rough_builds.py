"""Builds of mdrvisc side by side on bench_rough.py's surfaces: wall or CPU time through
``mv.Scene`` + ``mv.solve`` and the iterations of each level, build against build.

A change to the rough-contact solver is measured against the build before it on the same
machine in the same minutes: the VM's speed drifts by up to 1.5x between runs, more than
most changes move the time (``bench_user_path.py`` runs solves of every kind with one
build's Python at a time; this script alternates the builds on the rough solver's cases).

Each BUILD is a folder that holds an ``mdrvisc`` package (for example ``python/mdrvisc``
copied after ``maturin develop --release``, or a wheel installed with ``pip install
--no-deps --target BUILD``). Every round runs each build once, in turn, in a fresh process
that imports the package from its folder (checked), and each process solves every case
``--reps`` times. A case's time is its best over all rounds and repeats; the table sums the
cases per mode.

What is printed, per mode and build: the sum of the cases' best times (s) and the first
build's sum over it (above 1: this build is faster); the size-weighted iterations (each
level's iterations times its share of the finest grid's elements, summed over the levels and
the cases: the count the time follows);
the finest level's iterations per case; and each round's sum, which shows the noise. Cases
whose level iterations or pressure differ from the first build's are flagged: a change meant
to keep the solution bit for bit shows none.

Cases: up to 512^2, bench_rough's nine cells (H 0.3, 0.5, 0.8 at 2, 5, 20 % contact, loads from
the contact-fraction estimate pbar = fraction E* (rms slope) / 2); at larger sizes its main
case (H 0.8 / 5 %). Tolerance 1e-8.

Run: ``python benchmarks/bench_rough_builds.py BUILD [BUILD ...] [--sizes 512]
[--modes periodic free] [--rounds 4] [--reps 7] [--threads 2] [--cpu] [--seed S]``.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def cases(defaults: dict, n: int) -> list:
    """(Hurst exponent, contact fraction) of bench_rough's cases at size ``n``, from its
    ``defaults``: every pair up to its grid size, the main case beyond."""
    if n <= defaults["grid_up_to"]:
        return [(h, f) for h in defaults["hurst"] for f in defaults["fractions"]]
    return [tuple(defaults["main"])]


def size_weighted(levels: list) -> float:
    """Each level's iterations times its share of the finest grid's elements (levels
    coarsest first, each a quarter of the next), summed."""
    k = len(levels)
    return sum(it / 4 ** (k - 1 - i) for i, it in enumerate(levels))


def worker(build: str, n: int, modes: list, reps: int, cpu: bool, seed: int) -> None:
    """Runs in a fresh process: solves the cases with the package of ``build``; prints one
    JSON object."""
    sys.path.insert(0, build)
    sys.path.insert(1, str(HERE))
    import numpy as np

    import bench_rough as br
    import mdrvisc as mv

    where = Path(mv.__file__).resolve()
    if Path(build).resolve() not in where.parents:
        raise SystemExit(f"{build}: imported mdrvisc from {where}, not from the build")
    clock = time.process_time if cpu else time.perf_counter
    out = {}
    for mode in modes:
        for hurst, fraction in cases(br.DEFAULTS, n):
            z = br.self_affine(n, seed, hurst, br.DEFAULTS["short"])
            force = br.estimated_pressure(fraction) * br.EDGE**2
            best = float("inf")
            for _ in range(reps):
                start = clock()
                r = br.mv_solve(z, mode, force, 1e-8)
                best = min(best, clock() - start)
            p = np.ascontiguousarray(br.pressure(r))
            digest = hashlib.sha1(p.tobytes()).hexdigest()[:12]
            out[f"{mode} {hurst} {fraction}"] = dict(
                seconds=best, levels=list(r.level_iterations), pressure=digest)
    print(json.dumps(out))


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("builds", nargs="+", help="folders that each hold an mdrvisc package")
    ap.add_argument("--sizes", type=int, nargs="+", default=[512])
    ap.add_argument("--modes", nargs="+", default=["periodic", "free"],
                    choices=["periodic", "free"])
    ap.add_argument("--rounds", type=int, default=4, help="rounds over the builds (4)")
    ap.add_argument("--reps", type=int, default=7, help="solves per case per process (7)")
    ap.add_argument("--threads", type=int, default=2, help="RAYON_NUM_THREADS (2)")
    ap.add_argument("--cpu", action="store_true",
                    help="time the process's CPU time instead of wall time")
    ap.add_argument("--seed", type=int, default=20261127, help="bench_rough's surfaces")
    ap.add_argument("--worker", nargs=2, metavar=("BUILD", "N"), help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.worker:
        worker(args.worker[0], int(args.worker[1]), args.modes, args.reps, args.cpu, args.seed)
        return
    for b in args.builds:
        if not (Path(b) / "mdrvisc" / "__init__.py").is_file():
            ap.error(f"{b} holds no mdrvisc package (no {b}/mdrvisc/__init__.py)")
    if min(args.rounds, args.reps, args.threads) < 1:
        ap.error("--rounds, --reps and --threads must be at least 1")
    env = dict(os.environ, RAYON_NUM_THREADS=str(args.threads))
    clock = "process CPU time" if args.cpu else "wall time"
    print(f"== builds side by side: {clock}, {args.threads} thread(s), {args.rounds} rounds of "
          f"{args.reps} solves per case, seed {args.seed}")
    for n in args.sizes:
        runs = {b: [] for b in args.builds}
        for _ in range(args.rounds):
            for b in args.builds:
                cmd = [sys.executable, str(Path(__file__).resolve()), b, "--worker", b, str(n),
                       "--modes", *args.modes, "--reps", str(args.reps), "--seed",
                       str(args.seed)] + (["--cpu"] if args.cpu else [])
                done = subprocess.run(cmd, env=env, check=True, capture_output=True, text=True)
                runs[b].append(json.loads(done.stdout.strip().splitlines()[-1]))
        first = runs[args.builds[0]][0]
        for mode in args.modes:
            keys = [k for k in first if k.startswith(mode + " ")]
            named = [k.split()[1:] for k in keys]
            print(f"\n-- {n}^2, {mode}, cases: "
                  + ", ".join(f"H {h} / {100 * float(f):g} %" for h, f in named))
            print("| build | sum of best s | first / this | size-weighted iterations | finest "
                  "level per case | rounds' sums s | differs from first |")
            print("|---|---|---|---|---|---|---|")
            base = None
            for b in args.builds:
                best = {k: min(r[k]["seconds"] for r in runs[b]) for k in keys}
                total = sum(best.values())
                base = base or total
                last = runs[b][0]
                weighted = sum(size_weighted(last[k]["levels"]) for k in keys)
                finest = ", ".join(str(last[k]["levels"][-1]) for k in keys)
                sums = ", ".join(f"{sum(r[k]['seconds'] for k in keys):.3f}" for r in runs[b])
                differs = [k.split(" ", 1)[1] for k in keys
                           if (last[k]["levels"], last[k]["pressure"])
                           != (first[k]["levels"], first[k]["pressure"])]
                named_differs = ("all" if differs and len(differs) == len(keys)
                                 else "; ".join(differs) or "none")
                print(f"| {Path(b).name} | {total:.3f} | {base / total:.2f}x | {weighted:.1f} | "
                      f"{finest} | {sums} | {named_differs} |")


if __name__ == "__main__":
    main()
