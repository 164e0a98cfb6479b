"""Elastic Hertz contact: mdrvisc against the peer codes `tamaas` and `contactmechanics`.

Problem: rigid paraboloid h = r^2 / (2 R), R = 10 m, on a square footprint of edge 2.56 m cut
into n x n elements (n = 256, 512, 1024), pressed with force F onto a non-periodic elastic,
incompressible half-space with E* = 4 Pa (G = 1 Pa), frictionless. F = 4 a^3 E* / (3 R) with
a = 0.64 m, a quarter of the edge (F = 0.13981 N, d = 0.04096 m, p0 = 0.16297 Pa).

* mdrvisc: ``mv.solve(Scene(Paraboloid(c=1/(2R), edge=2.56), Elastic(G=1), force=F), "bem",
  n, tol=tol)`` in this process, end to end (grid, operator build, Polonsky-Keer CG);
  convergence: relative L1 change of the pressure between iterations,
  sum |p_k - p_{k-1}| / sum p < tol. It solves on the window that can touch: the elements
  with h + (a lower bound of the deflection) <= 1.05 times MDR's (here Hertz's) depth, about
  0.7 n wide; the solution is the whole grid's, exactly (contact lies where h <= d). The row
  "mdrvisc whole grid" solves the same problem on all n x n elements
  (``mv.arrays.contact`` without a depth bound), as the peers do.
* tamaas and contactmechanics run in their own venv (its interpreter: ``--peers-python PATH``
  or the environment variable MDRVISC_PEERS_PYTHON) through ``peers_worker.py``, one
  subprocess per code and size; the worker times model set-up + solve (the same work as
  mdrvisc's end-to-end time) and the solve alone, and documents each code's convergence
  criterion and how ``--tol`` maps to it. All three get the same height array and use the
  same discretisation (uniform-pressure elements, Love's kernel, DC-FFT on the 2n x 2n
  zero-padded grid).

Columns: wall (best of --repeats, s), solve (the peers' solve call alone), iterations (CG
iterations; contactmechanics does two operator applies per iteration), errors against Hertz
(a from the contact area sqrt(N dx^2 / pi), p0 as the largest element pressure, d the
depth), "vs ref": max |p - p_ref| / p0 against mdrvisc's solution of the same discrete
problem at tol 1e-12 (it shows whether the codes stopped equally converged: the Hertz
errors are discretisation errors, the same for all three), and mdrvisc's time over the
fastest peer's. A second table splits mdrvisc's time into a fixed part and a per-iteration
part (timings at two tolerances) and gives every code's time per iteration.

Run: ``python benchmarks/bench_peers.py [--sizes 256 512 1024] [--tol 1e-8] [--repeats 3]
[--mv-threads1]``. Set-up of the peers' venv: benchmarks/README.md, "Peer codes".
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, load, run_worker, table

HERE = Path(__file__).resolve().parent
EDGE, RADIUS, G = 2.56, 10.0, 1.0
E_STAR = 4.0 * G
A_TARGET = EDGE / 4
FORCE = 4.0 * A_TARGET**3 * E_STAR / (3.0 * RADIUS)
PEERS = ("tamaas", "contactmechanics")
PEERS_PYTHON_ENV = "MDRVISC_PEERS_PYTHON"


def scene():
    return mv.Scene(indenter=mv.Paraboloid(c=1.0 / (2.0 * RADIUS), edge=EDGE),
                    medium=mv.Elastic(G=G), force=FORCE,
                    outputs=("depth", "contact_length", "pressure"))


def errors(p: np.ndarray, depth: float, n: int, p_ref: np.ndarray | None) -> dict:
    """Relative errors against Hertz (a from the contact area, p0 = max p, d) and the largest
    pressure deviation from the reference solution (relative to Hertz p0)."""
    a_h, d_h, p0_h = mv.analytic.hertz(FORCE, RADIUS, E_STAR)
    dx = EDGE / n
    a = math.sqrt(np.count_nonzero(p > 0) * dx * dx / math.pi)
    out = dict(a=a, p0=float(p.max()), err_a=a / a_h - 1, err_p0=float(p.max()) / p0_h - 1,
               err_d=depth / d_h - 1, force_sum=float(p.sum()) * dx * dx)
    out["vs_ref"] = None if p_ref is None else float(np.abs(p - p_ref).max() / p0_h)
    return out


def run_mdrvisc(n: int, tol: float, repeats: int) -> dict:
    sc = scene()
    wall, r = best_of(lambda: mv.solve(sc, "bem", n, tol=tol, max_iter=100000), repeats)
    return dict(code="mdrvisc", n=n, wall=wall, solve=None, iterations=int(r.iterations),
                depth=float(r.depth[0]), pressure=np.asarray(r.fields[0.0].pressure),
                residual=float(r.residual), runs=repeats)


def run_mdrvisc_whole_grid(n: int, tol: float, repeats: int) -> dict:
    """mdrvisc on the whole n x n grid: grid set-up + ``mv.arrays.contact`` without a depth
    bound (the peers' work)."""
    def run():
        _, dx, h, mask = scene().bem_grid(n)
        return mv.arrays.contact(h, dx, G, force=FORCE, mask=mask, tol=tol, max_iter=100000,
                                 deflection=False)

    wall, r = best_of(run, repeats)
    return dict(code="mdrvisc whole grid", n=n, wall=wall, solve=None,
                iterations=int(r.iterations), depth=float(r.depth[0]),
                pressure=np.asarray(r.fields[0.0].pressure), residual=float(r.residual),
                runs=repeats)


def reference(n: int, tol: float = 1e-12) -> np.ndarray:
    r = mv.solve(scene(), "bem", n, tol=tol, max_iter=100000)
    return np.asarray(r.fields[0.0].pressure), float(r.depth[0]), int(r.iterations)


def run_peer(code: str, n: int, tol: float, repeats: int, python: str, folder: str,
             timeout: float) -> dict:
    cmd = [python, str(HERE / "peers_worker.py"), "--code", code, "--n", str(n), "--tol",
           repr(tol), "--force", repr(FORCE), "--edge", repr(EDGE), "--radius", repr(RADIUS),
           "--e-star", repr(E_STAR), "--repeats", str(repeats), "--out", folder]
    res = run_worker(cmd, timeout)
    if "failed" in res:
        return dict(code=code, n=n, **res)
    res["pressure"] = np.load(res.pop("pressure_file"))
    return res


def mdrvisc_split(n: int, tol: float, repeats: int) -> dict:
    """Fixed cost and cost per CG iteration of mv.solve at n: timings at tol 1e-3 and ``tol``
    (best of ``repeats``); their difference over the difference of iterations is the cost of
    one iteration, the rest of the tol-1e-3 run the fixed part (grid, build, first apply)."""
    sc = scene()
    t_lo, r_lo = best_of(lambda: mv.solve(sc, "bem", n, tol=1e-3), repeats)
    t_hi, r_hi = best_of(lambda: mv.solve(sc, "bem", n, tol=tol, max_iter=100000), repeats)
    per_iter = (t_hi - t_lo) / max(int(r_hi.iterations) - int(r_lo.iterations), 1)
    return dict(per_iter=per_iter, fixed=t_lo - int(r_lo.iterations) * per_iter,
                it_lo=int(r_lo.iterations), it_hi=int(r_hi.iterations), t_hi=t_hi)


def build_apply_time(n: int, repeats: int) -> float:
    """mdrvisc: operator build + one apply on n x n (``_core.surface_deflection``)."""
    from mdrvisc import _core

    p = np.random.default_rng(0).random((n, n))
    return best_of(lambda: _core.surface_deflection(p, EDGE / n), repeats, warmup=1)[0]


def mv_one_thread(sizes, tol, repeats) -> dict:
    """mdrvisc's wall times with RAYON_NUM_THREADS=1 (a subprocess of this script)."""
    env = dict(os.environ, RAYON_NUM_THREADS="1")
    cmd = [sys.executable, __file__, "--mv-only", "--json", "--tol", repr(tol), "--repeats",
           str(repeats), "--sizes", *map(str, sizes)]
    out = subprocess.run(cmd, capture_output=True, text=True, env=env, check=True).stdout
    return {int(k): v for k, v in json.loads(out.strip().splitlines()[-1]).items()}


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[256, 512, 1024])
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--peers", nargs="+", default=list(PEERS), choices=PEERS)
    ap.add_argument("--peers-python", default=os.environ.get(PEERS_PYTHON_ENV) or None,
                    metavar="PATH",
                    help="Python interpreter of the venv holding tamaas and contactmechanics "
                         f"(default: ${PEERS_PYTHON_ENV}; set-up in benchmarks/README.md)")
    ap.add_argument("--peer-limit", type=float, default=180.0,
                    help="skip a peer at a size when its predicted single run exceeds this (s)")
    ap.add_argument("--mv-threads1", action="store_true",
                    help="also time mdrvisc with RAYON_NUM_THREADS=1 (the peers are serial)")
    ap.add_argument("--no-split", action="store_true", help="skip the per-iteration table")
    ap.add_argument("--mv-only", action="store_true")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args(argv)

    if args.mv_only:
        res = {n: run_mdrvisc(n, args.tol, args.repeats) for n in args.sizes}
        out = {n: dict(wall=r["wall"], iterations=r["iterations"]) for n, r in res.items()}
        print(json.dumps(out) if args.json else out)
        return
    if not args.peers_python:
        ap.error(f"no interpreter for the peers: pass --peers-python PATH or set "
                 f"{PEERS_PYTHON_ENV} (the venv with tamaas and contactmechanics; "
                 f"benchmarks/README.md, \"Peer codes\")")
    if shutil.which(args.peers_python) is None:
        ap.error(f"the peers' interpreter {args.peers_python!r} is not an executable")

    header(f"Hertz contact, non-periodic, E* = {E_STAR}, R = {RADIUS}, edge {EDGE}, "
           f"F = {FORCE:.6g} (a = {A_TARGET}), tol {args.tol:g}: mdrvisc vs peers")
    a_h, d_h, p0_h = mv.analytic.hertz(FORCE, RADIUS, E_STAR)
    print(f"   Hertz: a = {a_h:.6g} m, d = {d_h:.6g} m, p0 = {p0_h:.6g} Pa; peers run by "
          f"{args.peers_python}")
    rows, notes, per_iter_rows = [], [], []
    last_wall: dict[str, tuple[int, float]] = {}
    with tempfile.TemporaryDirectory() as folder:
        for n in args.sizes:
            p_ref, d_ref, it_ref = reference(n)
            results = [run_mdrvisc(n, args.tol, args.repeats),
                       run_mdrvisc_whole_grid(n, args.tol, args.repeats)]
            for code in args.peers:
                prev = last_wall.get(code)
                if prev is not None:
                    predicted = prev[1] * (n / prev[0]) ** 2 * 1.5  # ~n^2 log n, more iterations
                    if predicted > args.peer_limit:
                        results.append(dict(code=code, n=n, failed=f"skipped (predicted "
                                            f"{predicted:.0f} s > {args.peer_limit:.0f} s)"))
                        continue
                res = run_peer(code, n, args.tol, args.repeats, args.peers_python, folder,
                               timeout=max(4 * args.peer_limit, 600))
                results.append(res)
                if "failed" not in res:
                    last_wall[code] = (n, res["walls"][0])
            ok_peers = [r for r in results[2:] if "failed" not in r]
            fastest = min(ok_peers, key=lambda r: r["wall"]) if ok_peers else None
            for r in results:
                if "failed" in r:
                    rows.append([n, r["code"], None, None, None, None, None, None, None, None])
                    notes.append(f"{r['code']} at n = {n}: {r['failed']}")
                    continue
                e = errors(r["pressure"], r["depth"], n, p_ref)
                ratio = None
                if r["code"].startswith("mdrvisc") and fastest is not None:
                    ratio = f"{r['wall'] / fastest['wall']:.3f} ({fastest['code']})"
                runs = r.get("runs", args.repeats)
                rows.append([n, r["code"] + ("" if runs >= args.repeats else f" [{runs} run]"),
                             r["wall"], r.get("solve"), r["iterations"], e["err_a"],
                             e["err_p0"], e["err_d"], e["vs_ref"], ratio])
                per_iter_rows.append((n, r["code"], r["wall"] / max(r["iterations"], 1)))
                if not r["code"].startswith("mdrvisc") and not r.get("converged", True):
                    notes.append(f"{r['code']} at n = {n}: NOT converged")
            notes.append(f"n = {n}: reference = mdrvisc at tol 1e-12 ({it_ref} iterations, "
                         f"d_ref/d_Hertz - 1 = {d_ref / d_h - 1:+.2e})")
    table(["n", "code", "wall s", "solve s", "iters", "a err", "p0 err", "d err", "vs ref",
           "mdrvisc / fastest peer"], rows,
          ["{}", "{}", "{:.3f}", "{:.3f}", "{}", "{:+.2e}", "{:+.2e}", "{:+.2e}", "{:.1e}", "{}"])
    for note in notes:
        print("   " + note)

    if args.mv_threads1:
        one = mv_one_thread(args.sizes, args.tol, args.repeats)
        print("\n== mdrvisc with RAYON_NUM_THREADS=1 (the peers run on one thread)")
        best = {}
        for row in rows:
            if not row[1].startswith("mdrvisc") and row[2] is not None:
                best[row[0]] = min(best.get(row[0], float("inf")), row[2])
        table(["n", "wall s (1 thread)", "iters", "/ fastest peer"],
              [[n, v["wall"], v["iterations"], v["wall"] / best[n] if n in best else None]
               for n, v in sorted(one.items())], ["{}", "{:.3f}", "{}", "{:.3f}"])

    if not args.no_split:
        print("\n== time per CG iteration (wall / iterations, set-up included) and mdrvisc's "
              "split into fixed + per-iteration cost")
        split_rows = []
        for n in args.sizes:
            s = mdrvisc_split(n, args.tol, args.repeats)
            ba = build_apply_time(n, args.repeats)
            peers = {code: t for (m, code, t) in per_iter_rows
                     if m == n and not code.startswith("mdrvisc")}
            split_rows.append([n, s["t_hi"], s["it_hi"], s["fixed"], s["per_iter"] * 1e3,
                               ba * 1e3, peers.get("tamaas", None) and peers["tamaas"] * 1e3,
                               peers.get("contactmechanics", None)
                               and peers["contactmechanics"] * 1e3])
        table(["n", "mv wall s", "mv iters", "mv fixed s", "mv ms/iter", "mv build+apply ms",
               "tamaas ms/iter", "CM ms/iter"], split_rows,
              ["{}", "{:.3f}", "{}", "{:.3f}", "{:.1f}", "{:.1f}", "{:.1f}", "{:.1f}"])
        print("   mv fixed / ms/iter: from mv.solve at tol 1e-3 and at --tol (difference over the "
              "difference of iterations); build+apply: _core.surface_deflection (operator build "
              "+ one apply); peers: their wall / their iterations (contactmechanics: two applies "
              "per iteration)")
    print(f"   ({load()})")


if __name__ == "__main__":
    main()
