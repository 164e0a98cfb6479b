"""Elastic contact of a rough surface, non-periodic and periodic: mdrvisc's static solver.

Problem: a Gaussian self-affine surface (``mv.surfaces.self_affine``: Hurst exponent 0.8,
rms slope 0.1, roll-off at a quarter of the cell, cutoff at the Nyquist wavelength, seed
--seed; the same surface for both modes) on n x n elements of side 1 um, pressed by a rigid
flat onto an incompressible elastic half-space (G = 1 MPa, E* = 4 MPa), frictionless, at the
mean pressure --pressure times G (0.0095 G gives about 5 % contact), i.e. the total force
p A on the n x n cell. The separation is h = max(z) - z.

* non-periodic: ``mv.arrays.contact(h, dx, G, force=...)`` on the whole grid (Love's
  kernel, DC-FFT on the zero-padded 2n x 2n grid);
* periodic: the same with ``periodic=True`` (spectral kernel on the n x n cell).

Both run Polonsky–Keer with the inverse-kernel preconditioner (the dense active set
declines contacts this large); convergence: sum |p_k - p_{k-1}| / sum p < tol. Columns:
wall (best of --repeats, s, end to end: operator build and solve), iterations, contact
fraction, "vs ref": max |p - p_ref| / max p_ref against the same mode's solution at
tol 1e-12 (the accuracy the time buys), and the time per iteration.

Peer codes (tamaas, contactmechanics, ASPHER) are not run by this script.

Run: ``python benchmarks/bench_rough.py [--sizes 512 1024] [--tol 1e-8] [--repeats 3]``.
"""

from __future__ import annotations

import argparse

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, load, table

DX, G = 1e-6, 1e6


def surface(n: int, seed: int) -> np.ndarray:
    """The separation h = max(z) - z (m) of the benchmark's self-affine surface."""
    z = mv.surfaces.self_affine((n, n), DX, 0.8, rms_slope=0.1, rolloff=n * DX / 4, seed=seed)
    return z.max() - z


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    parser.add_argument("--tol", type=float, default=1e-8)
    parser.add_argument("--pressure", type=float, default=0.0095, help="mean pressure / G")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--seed", type=int, default=2024)
    args = parser.parse_args()
    header("Elastic rough contact: non-periodic and periodic (mdrvisc)")
    rows = []
    for n in args.sizes:
        h = surface(n, args.seed)
        force = args.pressure * G * (n * DX) ** 2
        for periodic in (False, True):
            def run(tol, h=h, force=force, periodic=periodic):
                return mv.arrays.contact(h, DX, G, force=force, periodic=periodic, tol=tol,
                                         deflection=False)

            ref = run(1e-12).fields[0.0].pressure
            wall, r = best_of(lambda: run(args.tol), args.repeats)
            p = r.fields[0.0].pressure
            rows.append([n, "periodic" if periodic else "non-periodic", wall, r.iterations,
                         np.count_nonzero(p > 0) / p.size,
                         np.max(np.abs(p - ref)) / np.max(ref), wall / max(r.iterations, 1) * 1e3])
    table(["n", "mode", "wall (s)", "iterations", "contact", "vs ref", "ms/iter"], rows,
          ["{}", "{}", "{:.3f}", "{}", "{:.3f}", "{:.1e}", "{:.1f}"])
    print(load())


if __name__ == "__main__":
    main()
