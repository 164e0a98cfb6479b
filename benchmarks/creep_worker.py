"""Peer side of bench_rough_creep.py: creep of a rough surface on a standard solid solved by
tamaas' ``MaxwellViscoelastic``, run in the peers' own environment.

This file imports neither mdrvisc nor the benchmark helpers, so that it runs in a venv that
holds only the peers (benchmarks/README.md, "Peer codes"). The driver calls, with
PEERS_PYTHON that venv's interpreter,

    PEERS_PYTHON creep_worker.py creep --heights Z.npy --edge 1 --g-inf 1 --g1 4 --tau1 1
        --dt 0.1 --steps 100 --pbar P --tol 1e-8 --record 50 100 --out DIR
    PEERS_PYTHON creep_worker.py relax --g-inf 1 --g1 4 --tau1 1 --dt 0.1 --steps 10

and reads one JSON document from the last line of stdout.

``creep``: the rigid surface has heights Z (m, (n, n), the highest point touches first) on
one period of a doubly periodic cell of edge L, n x n elements; under the constant mean
pressure P (Pa) from t = 0 it creeps into an incompressible standard solid with relaxation
modulus G(t) = G_inf + G1 exp(-t / tau1) (shear moduli, Pa; contact modulus E* = 4 G). The
model: ``ModelFactory.createModel(basic_2d)`` with E = 2 (1 + nu) G_inf = 3 G_inf and nu =
0.5 (so its Westergaard operator has E* = 4 G_inf), and ``MaxwellViscoelastic(model, Z, tol,
time_step=dt, shear_moduli=[G1], characteristic_times=[tau1])``: one Maxwell branch of shear
modulus G1 and relaxation time tau1 in parallel with the model's elasticity. Each call of
``solve(P)`` advances the state by one backward-Euler step of dt (the first from the
unloaded body at t = 0 to t = dt), so step k is the state at t = k dt. The pressure fields
(Pa) after the steps named by ``--record`` are written to DIR/creep_pressure_<k>.npy; the
contact fraction after every step is in the JSON document.

``relax``: the check of the material law (no timing): a wavy surface Z = g cos(2 pi x / L)
(64 x 64, uniform in y) pressed into full contact, where the fluctuating deflection equals
the surface's for all time, so the pressure amplitude A_k after step k measures the
relaxation modulus: A_k / (pi g / L) = 4 G(t_k) in the exact law, and 4 (G_inf + G1 (1 +
dt / tau1)^-k) after k backward-Euler steps.

What is timed (``creep``; wall clock, best of ``--repeats``, everything after the imports):
the model's and the solver's set-up from the height array + the ``--steps`` solves.
Stopping criterion of every step's solve: ``PolonskyKeerRey``'s ``computeError`` < tol
(its normalised complementarity measure); iterations are parsed from tamaas' log lines (the
first and last iteration of each solve are printed when ``dump_freq`` is huge).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import time

import numpy as np

from peers_worker import CaptureFd

NU = 0.5


def model_and_solver(tm, surface, edge, g_inf, g1, tau1, dt, tol, max_iter):
    """tamaas' model (E = 2 (1 + nu) G_inf, nu = 1/2) and MaxwellViscoelastic solver."""
    n = surface.shape[0]
    model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [edge, edge], [n, n])
    model.E, model.nu = 2.0 * (1.0 + NU) * g_inf, NU
    solver = tm.MaxwellViscoelastic(model, surface, tol, time_step=dt, shear_moduli=[g1],
                                    characteristic_times=[tau1])
    solver.max_iter = max_iter
    solver.dump_freq = 10**9
    return model, solver


def iterations_per_solve(log: str) -> list[int]:
    """The last iteration number of each solve in tamaas' log (one block per " Iter" line)."""
    counts = []
    for block in log.split("Iter")[1:]:
        its = [int(m.group(1)) for m in re.finditer(r"^\s*(\d+)\s+\S+\s+\S+\s*$", block, re.M)]
        counts.append(max(its) if its else 0)
    return counts


def creep(args, tm) -> dict:
    z = np.load(args.heights)
    if z.ndim != 2 or z.shape[0] != z.shape[1]:
        raise SystemExit(f"heights must be a square 2-D array, got shape {z.shape}")
    surface = np.ascontiguousarray(z - z.max())
    n = z.shape[0]
    record = set(args.record)
    tm.set_log_level(tm.LogLevel.info)

    def once(keep: bool):
        fields, fractions = {}, []
        start = time.perf_counter()
        model, solver = model_and_solver(tm, surface, args.edge, args.g_inf, args.g1,
                                         args.tau1, args.dt, args.tol, args.max_iter)
        error = 0.0
        for k in range(1, args.steps + 1):
            error = max(error, float(solver.solve(args.pbar)))
            if keep:  # outside the timing below
                pause = time.perf_counter()
                p = np.array(model.traction, dtype=np.float64, copy=True).reshape(n, n)
                fractions.append(float(np.count_nonzero(p > 0)) / p.size)
                if k in record:
                    fields[k] = p
                start += time.perf_counter() - pause
        return time.perf_counter() - start, error, fields, fractions

    with CaptureFd() as cap:
        wall, error, fields, fractions = once(True)
    iters = iterations_per_solve(cap.text)
    walls = [wall]
    if wall <= args.single_above:
        for _ in range(args.repeats - 1):
            with CaptureFd():
                walls.append(once(False)[0])
    files = {}
    for k, p in fields.items():
        files[k] = os.path.join(args.out, f"creep_pressure_{k}.npy")
        np.save(files[k], p)
    return dict(wall=min(walls), walls=walls, steps=args.steps, dt=args.dt,
                iterations=int(sum(iters)), solves=len(iters), max_error=error,
                converged=bool(error < args.tol), fractions=fractions, pressure_files=files,
                version=tm.__version__, threads="serial (cpp backend)")


def relax(args, tm) -> dict:
    n, edge, g = 64, 1.0, 1e-3
    x = np.arange(n) * edge / n
    surface = np.ascontiguousarray(np.tile(g * np.cos(2.0 * np.pi * x / edge), (n, 1)))
    model, solver = model_and_solver(tm, surface, edge, args.g_inf, args.g1, args.tau1,
                                     args.dt, 1e-12, args.max_iter)
    # full contact needs pbar > pi E* g / L at the glassy modulus; 10x that
    pbar = 10.0 * np.pi * 4.0 * (args.g_inf + args.g1) * g / edge
    moduli = []
    with CaptureFd():
        for _ in range(args.steps):
            solver.solve(pbar)
            p = np.array(model.traction, dtype=np.float64).reshape(n, n)
            if np.count_nonzero(p > 0) != p.size:
                raise SystemExit("relax: the wavy surface lost full contact")
            moduli.append(float((p[0].max() - p[0].min()) / 2.0 / (np.pi * g / edge)) / 4.0)
    return dict(shear_modulus=moduli, version=tm.__version__)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("task", choices=["creep", "relax"])
    ap.add_argument("--heights", help="creep: .npy file of the heights Z (m), (n, n)")
    ap.add_argument("--edge", type=float, default=1.0, help="cell edge L (m)")
    ap.add_argument("--g-inf", type=float, required=True, help="equilibrium shear modulus (Pa)")
    ap.add_argument("--g1", type=float, required=True, help="Maxwell branch's shear modulus (Pa)")
    ap.add_argument("--tau1", type=float, required=True, help="its relaxation time (s)")
    ap.add_argument("--dt", type=float, required=True, help="time step (s)")
    ap.add_argument("--steps", type=int, required=True)
    ap.add_argument("--pbar", type=float, help="creep: mean pressure (Pa)")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--max-iter", type=int, default=100000)
    ap.add_argument("--record", type=int, nargs="*", default=[],
                    help="creep: steps after which to write the pressure field")
    ap.add_argument("--repeats", type=int, default=1)
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="no repeats when the first run took longer than this (s)")
    ap.add_argument("--out", default=".", help="creep: folder for the fields (.npy)")
    args = ap.parse_args(argv)
    import tamaas as tm

    if args.task == "creep":
        if args.heights is None or args.pbar is None:
            ap.error("creep needs --heights and --pbar")
        print(json.dumps(creep(args, tm)))
    else:
        print(json.dumps(relax(args, tm)))


if __name__ == "__main__":
    main()
