"""Peer side of bench_peers.py: one elastic Hertz contact solved by `tamaas` or
`contactmechanics` (ContactMechanics), run in the peers' own environment.

This file imports neither mdrvisc nor the benchmark helpers, so that it runs in a venv that
holds only the peers (see benchmarks/README.md, "Peer codes"). The driver calls, with
PEERS_PYTHON that venv's interpreter (its ``--peers-python`` or $MDRVISC_PEERS_PYTHON),

    PEERS_PYTHON peers_worker.py --code tamaas --n 512 --tol 1e-8 --repeats 3 --out DIR

and reads one JSON document from the last line of stdout; the final pressure field is
written to DIR/pressure_<code>_<n>.npy for the driver's comparison with a reference.

Problem (the same as the driver's mdrvisc side): rigid paraboloid h = (x^2 + y^2) / (2 R)
sampled at the centres of n x n square elements over a square of edge L (x_i = (i - (n-1)/2)
dx, dx = L / n), non-periodic (free) elastic half-space of contact modulus E*, total force F,
frictionless. Both peers get this exact height array (negated: their rigid surface points
up), so all three codes solve the same discrete problem (uniform-pressure elements, Love's
kernel, DC-FFT on a 2n x 2n zero-padded grid).

What is timed (wall clock, best of --repeats, everything after the imports):

* tamaas: ``ModelFactory.createModel(basic_2d)`` + ``registerNonPeriodic`` (the DC-FFT
  Boussinesq operator) + ``PolonskyKeerRey(model, -h, tol)`` + ``setIntegralOperator`` +
  ``solve(F / L^2)`` (the argument is the mean pressure over the domain).
  Convergence: PolonskyKeerRey's own ``computeError`` < tol (a normalised complementarity
  measure of the pressure/gap pair; its C++ source is not in the wheel). Iterations: parsed
  from tamaas' own log line of the last iteration.
* contactmechanics: ``FreeFFTElasticHalfSpace((n, n), E*, (L, L))`` + ``Topography(-h)`` +
  ``make_system`` + ``minimize_proxy(external_force=F, ...)`` (Polonsky-Keer constrained CG,
  ``Optimization/ConstrainedConjugateGradients.py``). Convergence (all at once): rms and max
  penetration in the contact < pentol, max change of the displacement field < pentol,
  max tensile (and padding-region) pixel force < forcetol, relative change of the rigid-body
  offset < thermotol. Mapped from the relative tol as pentol = tol * d_Hertz,
  forcetol = tol * p0_Hertz * dx^2, thermotol = tol. Iterations: ``result.nit`` (each does
  two operator applies, ``result.nfev``).

Depth: ContactMechanics returns the rigid-body offset (= depth with this sign convention).
tamaas stores the displacement minus the rigid-body approach, so the depth is taken after the
timing from the true deflection K[p] (tamaas' own operator) as the mean of K[p] + h over the
contact (its spread there is reported as depth_spread).
"""

from __future__ import annotations

import argparse
import json
import os
import re
import sys
import tempfile
import time

import numpy as np


def problem(n: int, edge: float, radius: float, e_star: float, force: float):
    dx = edge / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    h = (x[:, None] ** 2 + x[None, :] ** 2) / (2.0 * radius)
    a = (3.0 * force * radius / (4.0 * e_star)) ** (1.0 / 3.0)
    return dx, h, a * a / radius, 3.0 * force / (2.0 * np.pi * a * a)


class CaptureFd:
    """Captures what C++ code writes to fd 1 and 2 (tamaas logs there, not via Python)."""

    def __enter__(self):
        sys.stdout.flush()
        sys.stderr.flush()
        self.file = tempfile.TemporaryFile(mode="w+b")
        self.saved = [os.dup(1), os.dup(2)]
        os.dup2(self.file.fileno(), 1)
        os.dup2(self.file.fileno(), 2)
        return self

    def __exit__(self, *exc):
        sys.stdout.flush()
        sys.stderr.flush()
        os.dup2(self.saved[0], 1)
        os.dup2(self.saved[1], 2)
        for fd in self.saved:
            os.close(fd)
        self.file.seek(0)
        self.text = self.file.read().decode(errors="replace")
        self.file.close()
        return False


def run_tamaas(n, edge, radius, e_star, force, tol, max_iter):
    import tamaas as tm

    dx, h, d_h, p0_h = problem(n, edge, radius, e_star, force)
    surface = np.ascontiguousarray(-h)
    tm.set_log_level(tm.LogLevel.info)  # prints iteration 0 and the last one (dump_freq huge)

    def once():
        start = time.perf_counter()
        model = tm.ModelFactory.createModel(tm.model_type.basic_2d, [edge, edge], [n, n])
        model.E, model.nu = 0.75 * e_star, 0.5  # E* = E / (1 - nu^2); incompressible like mdrvisc
        tm.ModelFactory.registerNonPeriodic(model, "dcfft")
        solver = tm.PolonskyKeerRey(model, surface, tol)
        solver.setIntegralOperator("dcfft")
        solver.max_iter = max_iter
        solver.dump_freq = 10**9
        built = time.perf_counter()
        error = solver.solve(force / edge**2)
        end = time.perf_counter()
        return end - start, end - built, model, error

    with CaptureFd() as cap:
        wall, solve, model, error = once()
    iters = [int(m.group(1)) for m in re.finditer(r"^\s*(\d+)\s+\S+\s+\S+\s*$", cap.text, re.M)]
    p = np.array(model.traction, dtype=np.float64, copy=True).reshape(n, n)
    deflection = np.zeros_like(p)
    model.operators["dcfft"](p.copy(), deflection)  # true K[p]; model.displacement is shifted
    contact = p > 0
    gap0 = (deflection + h)[contact]
    return dict(wall=wall, solve=solve, iterations=max(iters) if iters else None,
                applies=None, converged=bool(error < tol), error=float(error),
                depth=float(gap0.mean()), depth_spread=float(gap0.std()),
                pressure=p, version=tm.__version__,
                backend=str(tm.TamaasInfo.backend)), once


def run_contactmechanics(n, edge, radius, e_star, force, tol, max_iter):
    import ContactMechanics as cm
    from ContactMechanics import FreeFFTElasticHalfSpace, make_system
    from SurfaceTopography import Topography

    dx, h, d_h, p0_h = problem(n, edge, radius, e_star, force)

    def once():
        start = time.perf_counter()
        substrate = FreeFFTElasticHalfSpace((n, n), e_star, (edge, edge))
        system = make_system(substrate=substrate, surface=Topography(-h, (edge, edge)))
        built = time.perf_counter()
        res = system.minimize_proxy(external_force=force, pentol=tol * d_h,
                                    forcetol=tol * p0_h * dx * dx, thermotol=tol,
                                    maxiter=max_iter)
        end = time.perf_counter()
        return end - start, end - built, res, None

    wall, solve, res, _ = once()
    p = np.asarray(res.jac, dtype=np.float64) / (dx * dx)
    return dict(wall=wall, solve=solve, iterations=int(res.nit), applies=int(res.nfev),
                converged=bool(res.success), error=None, depth=float(res.offset),
                depth_spread=0.0, pressure=p, version=cm.__version__,
                backend="numpy + muGrid FFT (serial)"), once


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--code", choices=["tamaas", "contactmechanics"], required=True)
    ap.add_argument("--n", type=int, required=True)
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--edge", type=float, default=2.56)
    ap.add_argument("--radius", type=float, default=10.0)
    ap.add_argument("--e-star", type=float, default=4.0)
    ap.add_argument("--force", type=float, required=True)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--max-iter", type=int, default=100000)
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="no repeats when the first run took longer than this (s)")
    ap.add_argument("--out", required=True, help="folder for the pressure field (.npy)")
    args = ap.parse_args(argv)

    runner = run_tamaas if args.code == "tamaas" else run_contactmechanics
    first, once = runner(args.n, args.edge, args.radius, args.e_star, args.force, args.tol,
                         args.max_iter)
    walls, solves = [first["wall"]], [first["solve"]]
    if first["wall"] <= args.single_above:
        for _ in range(args.repeats - 1):
            if args.code == "tamaas":
                with CaptureFd():
                    w, s, *_ = once()
            else:
                w, s, *_ = once()
            walls.append(w)
            solves.append(s)
    path = os.path.join(args.out, f"pressure_{args.code}_{args.n}.npy")
    np.save(path, first.pop("pressure"))
    first.update(wall=min(walls), solve=min(solves), walls=walls, runs=len(walls),
                 pressure_file=path, code=args.code, n=args.n, tol=args.tol)
    print(json.dumps(first))


if __name__ == "__main__":
    main()
