"""Peer side of bench_rough.py: one elastic rough contact solved by `tamaas`,
`contactmechanics` (ContactMechanics) or `aspher` (ASPHER), run in the peers' own environment.

This file imports neither mdrvisc nor the benchmark helpers, so that it runs in a venv that
holds only the peers (benchmarks/README.md, "Peer codes"). The driver calls, with
PEERS_PYTHON that venv's interpreter,

    PEERS_PYTHON rough_worker.py --code tamaas --mode periodic --heights Z.npy --edge 1
        --e-star 4 --force F --tol 1e-8 --repeats 3 --out DIR [--apply P.npy]

and reads one JSON document from the last line of stdout; the final pressure field (Pa) is
written to DIR/pressure_<code>_<mode>_<n>.npy. With ``--apply P.npy`` the worker also writes
the deflection (m) of the pressure field P under the code's own surface operator
(DIR/deflection_...npy), from which the driver measures how far each code's discretisation
is from mdrvisc's.

Problem: the rigid surface has heights Z (m, (n, n), the highest point touches first) on a
square of edge L cut into n x n square elements (dx = L / n), pressed with total force F (N)
onto an elastic half-space of contact modulus E* (Pa), frictionless; ``--mode free`` is the
finite (non-periodic) body, ``--mode periodic`` makes the n x n map one period of a
doubly periodic cell. Every code gets the same array Z (shifted by a constant where the code
wants the highest point at 0).

Kernels (what each code discretises):

* tamaas: free: ``registerNonPeriodic(model, "dcfft")``, Love's uniform-pressure squares by
  zero-padded FFT; periodic: the Westergaard operator, spectral compliance 2 / (E* |q|) at
  the cell's discrete wavevectors, mean mode 0.
* contactmechanics: free: ``FreeFFTElasticHalfSpace`` (Love's squares, zero-padded FFT);
  periodic: ``PeriodicFFTElasticHalfSpace``, 2 / (E* |q|) and, at q = 0, a finite stiffness
  (its default, the lowest non-zero one): that shifts the rigid-body offset, not the pressure.
* aspher: free: Love's squares, exactly (backend "fft", zero-padded FFT) or approximated by
  the matrix-free H2/FMM operator (backend "h2", Chebyshev order q = 6); periodic: backend
  "periodic", 2 / (E* |q|), mean mode 0.

Variants of aspher (``--variant``): ``fft`` and ``h2``: ``ContactSolver(...).solve(gap,
p_nominal, tol, precond="fourier")`` (the |q| preconditioner as a 13-tap stencil on the
contact set); ``nested-fft`` and ``nested-h2``: ``solve_nested(..., backend=...)`` (coarse
to fine from 64 x 64, each level warm-started from the last, preconditioned, coarse levels
at tol 1e-4); ``periodic``: ``ContactSolver(backend="periodic").solve(...,
precond="fourier-fft")``; ``nested-periodic``: ``solve_nested(backend="periodic")``.

What is timed (wall clock, best of --repeats, everything after the imports): model or
operator set-up from the height array + solve; the solve call alone is a second number.

Stopping criteria (each code's own; all get the same relative ``--tol``):

* tamaas ``PolonskyKeerRey``: its ``computeError`` < tol (a complementarity measure of the
  pressure/gap pair, normalised). Iterations: parsed from tamaas' log line of the last one.
* contactmechanics ``constrained_conjugate_gradients`` (all at once): rms and max
  penetration in the contact and max displacement change < pentol, max tensile pixel force
  < forcetol, relative change of the rigid-body offset < thermotol, mapped from the
  relative tol as pentol = tol * (max Z - min Z), forcetol = tol * (F / (fraction * n^2))
  (the mean pixel force in the contact, ``--fraction`` the expected contact fraction),
  thermotol = tol. Iterations: ``result.nit`` (two operator applies each, ``nfev``).
* aspher: the Frank-Wolfe certificate G / (P g_ref) <= tol and the penetration
  max(0, -min gap) / g_ref <= tol, g_ref = max Z - min Z, verified on the returned pressure.
  Iterations: ``result.iterations`` (the finest level's for a nested solve; every level's in
  ``stages``).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import time
from importlib import metadata

import numpy as np

from peers_worker import CaptureFd

VARIANTS = {"free": ("fft", "h2", "nested-fft", "nested-h2"),
            "periodic": ("periodic", "nested-periodic")}


def run_tamaas(z, edge, e_star, force, mode, tol, max_iter, **_):
    import tamaas as tm

    n = z.shape[0]
    surface = np.ascontiguousarray(z - z.max())
    tm.set_log_level(tm.LogLevel.info)  # prints iteration 0 and the last one (dump_freq huge)
    op_name = "dcfft" if mode == "free" else "Westergaard::neumann"

    def once():
        start = time.perf_counter()
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [edge, edge], [n, n])
        model.E, model.nu = 0.75 * e_star, 0.5  # E* = E / (1 - nu^2)
        if mode == "free":
            tm.ModelFactory.registerNonPeriodic(model, "dcfft")
        solver = tm.PolonskyKeerRey(model, surface, tol)
        if mode == "free":
            solver.setIntegralOperator("dcfft")
        solver.max_iter = max_iter
        solver.dump_freq = 10**9
        built = time.perf_counter()
        error = solver.solve(force / edge**2)  # mean pressure over the cell
        end = time.perf_counter()
        return end - start, end - built, dict(model=model, error=error)

    def apply(p):
        out = once_state["model"]
        u = np.zeros((n, n, 1))
        out.operators[op_name](np.ascontiguousarray(p, dtype=float).reshape(n, n, 1), u)
        return u.reshape(n, n)

    with CaptureFd() as cap:
        wall, solve, state = once()
    once_state = state
    iters = [int(m.group(1)) for m in re.finditer(r"^\s*(\d+)\s+\S+\s+\S+\s*$", cap.text, re.M)]
    p = np.array(state["model"].traction, dtype=np.float64, copy=True).reshape(n, n)
    error = float(state["error"])
    info = dict(wall=wall, solve=solve, iterations=max(iters) if iters else None, applies=None,
                converged=bool(error < tol), criterion=f"error {error:.2e}", pressure=p,
                version=tm.__version__, threads="serial (cpp backend)")

    def again():
        with CaptureFd():
            return once()[:2]
    return info, again, apply


def run_contactmechanics(z, edge, e_star, force, mode, tol, max_iter, fraction, **_):
    import ContactMechanics as cm
    from ContactMechanics import FreeFFTElasticHalfSpace, PeriodicFFTElasticHalfSpace, make_system
    from SurfaceTopography import Topography

    n = z.shape[0]
    dx = edge / n
    surface = z - z.max()
    half_space = FreeFFTElasticHalfSpace if mode == "free" else PeriodicFFTElasticHalfSpace
    pentol = tol * float(z.max() - z.min())
    forcetol = tol * force / (fraction * n * n)
    state = {}

    def once():
        start = time.perf_counter()
        substrate = half_space((n, n), e_star, (edge, edge))
        system = make_system(substrate=substrate,
                             surface=Topography(surface, (edge, edge),
                                                periodic=(mode == "periodic")))
        built = time.perf_counter()
        res = system.minimize_proxy(external_force=force, pentol=pentol, forcetol=forcetol,
                                    thermotol=tol, maxiter=max_iter)
        end = time.perf_counter()
        state.update(substrate=substrate, res=res)
        return end - start, end - built

    def apply(p):
        u = -np.asarray(state["substrate"].evaluate_disp(p * dx * dx), dtype=np.float64)
        return u[:n, :n]

    wall, solve = once()
    res = state["res"]
    p = np.asarray(res.jac, dtype=np.float64)[:n, :n] / (dx * dx)
    info = dict(wall=wall, solve=solve, iterations=int(res.nit), applies=int(res.nfev),
                converged=bool(res.success),
                criterion=f"pentol {pentol:.2e}, forcetol {forcetol:.2e}, thermotol {tol:.0e}",
                pressure=p, version=cm.__version__, threads="serial (numpy + muFFT)")
    return info, once, apply


def run_aspher(z, edge, e_star, force, mode, tol, max_iter, variant, **_):
    import aspher as hc

    n = z.shape[0]
    if variant not in VARIANTS[mode]:
        raise SystemExit(f"aspher variant {variant!r} is not one of {VARIANTS[mode]} ({mode})")
    gap = np.ascontiguousarray((z.max() - z).ravel())
    p_nominal = force / edge**2
    backend = variant.removeprefix("nested-")
    state = {}

    def once():
        start = time.perf_counter()
        if variant.startswith("nested-"):
            built = start
            res = hc.solve_nested(grid_size=n, gap=gap, p_nominal=p_nominal, domain_size=edge,
                                  E_star=e_star, tol=tol, max_iter=max_iter, backend=backend)
        else:
            kw = dict(q=6) if backend == "h2" else {}
            solver = hc.ContactSolver(grid_size=n, domain_size=edge, E_star=e_star,
                                      backend=backend, **kw)
            built = time.perf_counter()
            res = solver.solve(gap, p_nominal=p_nominal, tol=tol, max_iter=max_iter,
                               precond="fourier-fft" if backend == "periodic" else "fourier")
            state["solver"] = solver
        end = time.perf_counter()
        state["res"] = res
        return end - start, end - built

    def apply(p):
        solver = state.get("solver")
        if solver is None:  # nested: the finest level's operator, built alone
            kw = dict(q=6) if backend == "h2" else {}
            solver = hc.ContactSolver(grid_size=n, domain_size=edge, E_star=e_star,
                                      backend=backend, **kw)
        return np.asarray(solver.matvec(np.ascontiguousarray(p, dtype=float)),
                          dtype=np.float64).reshape(n, n)

    wall, solve = once()
    res = state["res"]
    p = np.array(res.pressure, dtype=np.float64, copy=True).reshape(n, n)
    stages = [f"{s['name']}: {s['iterations']}" for s in res.stage_stats]
    info = dict(wall=wall, solve=solve if not variant.startswith("nested-") else None,
                iterations=int(res.iterations), applies=int(res.matvec_count),
                converged=bool(res.converged),
                criterion=f"{res.status}, fw_error {res.fw_error:.2e}, "
                          f"penetration {res.penetration_error:.2e}",
                stages=stages, pressure=p, version=metadata.version("aspher"),
                threads=f"OpenMP, OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}, "
                            f"OMP_WAIT_POLICY={os.environ.get('OMP_WAIT_POLICY', 'unset')}")
    return info, once, apply


RUNNERS = {"tamaas": run_tamaas, "contactmechanics": run_contactmechanics,
           "aspher": run_aspher}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--code", choices=sorted(RUNNERS), required=True)
    ap.add_argument("--variant", default="", help="aspher only: " + ", ".join(
        f"{m}: {' '.join(v)}" for m, v in VARIANTS.items()))
    ap.add_argument("--mode", choices=["free", "periodic"], required=True)
    ap.add_argument("--heights", required=True, help=".npy file of the heights Z (m), (n, n)")
    ap.add_argument("--edge", type=float, required=True, help="cell edge L (m)")
    ap.add_argument("--e-star", type=float, required=True, help="contact modulus E* (Pa)")
    ap.add_argument("--force", type=float, required=True, help="total force F (N)")
    ap.add_argument("--fraction", type=float, default=0.05,
                    help="expected contact fraction (contactmechanics' forcetol)")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--max-iter", type=int, default=100000)
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="no repeats when the first run took longer than this (s)")
    ap.add_argument("--apply", default=None,
                    help=".npy pressure field (Pa) to apply the code's operator to")
    ap.add_argument("--out", required=True, help="folder for the fields (.npy)")
    args = ap.parse_args(argv)

    z = np.load(args.heights)
    if z.ndim != 2 or z.shape[0] != z.shape[1]:
        raise SystemExit(f"heights must be a square 2-D array, got shape {z.shape}")
    first, once, apply = RUNNERS[args.code](
        z, args.edge, args.e_star, args.force, args.mode, args.tol, args.max_iter,
        fraction=args.fraction, variant=args.variant)
    walls, solves = [first["wall"]], [first["solve"]]
    if first["wall"] <= args.single_above:
        for _ in range(args.repeats - 1):
            w, s = once()
            walls.append(w)
            solves.append(s)
    n = z.shape[0]
    tag = f"{args.code}{('-' + args.variant) if args.variant else ''}_{args.mode}_{n}"
    path = os.path.join(args.out, f"pressure_{tag}.npy")
    np.save(path, first.pop("pressure"))
    if args.apply:
        u_path = os.path.join(args.out, f"deflection_{tag}.npy")
        np.save(u_path, apply(np.load(args.apply)))
        first["deflection_file"] = u_path
    first.update(wall=min(walls), solve=None if solves[0] is None else min(solves),
                 walls=walls, runs=len(walls), pressure_file=path, code=args.code,
                 variant=args.variant, mode=args.mode, n=n, tol=args.tol)
    print(json.dumps(first))


if __name__ == "__main__":
    main()
