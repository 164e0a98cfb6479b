"""The field's bottom-effect corrections against mdrvisc's layer, and what a layer costs.

Elastic incompressible layers of thickness h on a rigid base, indented by a sphere (radius
R, chi = sqrt(R d) / h) and a flat punch (radius a, chi = a / h), by BEM on free grids. For
each chi, the layer's depth d under a force F and the half-space's at the same grid give
the bottom-effect factor F / F_half(d), F_half(d) = F (d / d_half)^k (k = 3/2 sphere, 1
punch: discretisation cancels); printed against the corrections as PyFMRheo implements
them (``pyfmrheo.models.bec``): Dimitriadis et al., Biophys. J. 82 (2002), bonded and not
bonded; Garcia & Garcia, Biophys. J. 114 (2018), paraboloid and flat punch (bonded). Each
entry is the correction's relative error against the layer's factor.

Cost: the wall time of one elastic sphere solve on a free layer against the half-space at
the same n (the layer's first solve builds its correction table, once per Poisson ratio
and base in the process: timed apart; a layer is solved on the whole grid, the half-space
on a window around the contact), and the iterations and wall time of a periodic cell's
solve on a layer against the periodic half-space (the same operator cost per iteration: one
FFT pair and a spectrum product).

Run: ``python benchmarks/bench_layer.py [--n 129] [--chi 0.1 0.2 0.3 0.5 0.7 1.0]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

import mdrvisc as mv

CORRECTIONS = {
    "dimitriadis bonded": (1.133, 1.283, 0.769, 0.0975),
    "dimitriadis not bonded": (0.884, 0.781, 0.386, 0.0048),
    "garcia paraboloid": (1.133, 1.497, 1.469, 0.755),
    "garcia flat punch": (1.133, 1.283, 0.598, -0.291),
}
APPLIES = {
    ("sphere", "bonded"): ("dimitriadis bonded", "garcia paraboloid"),
    ("sphere", "frictionless"): ("dimitriadis not bonded",),
    ("punch", "bonded"): ("dimitriadis bonded", "garcia flat punch"),
    ("punch", "frictionless"): ("dimitriadis not bonded",),
}


def correction(name: str, chi: np.ndarray) -> np.ndarray:
    """1 + c1 chi + c2 chi^2 + c3 chi^3 + c4 chi^4 of the named correction."""
    return 1 + sum(c * chi ** (k + 1) for k, c in enumerate(CORRECTIONS[name]))


def factor(tip: str, base: str, chi: float, n: int) -> tuple[float, float, float, float]:
    """(chi at the layer's depth, the layer's bottom-effect factor, layer and half-space
    solve times (s)) for a target chi (G = 1 Pa, nu = 0.5)."""
    if tip == "sphere":
        indenter, h, force, k = mv.Sphere(radius=1.0), 1.0, 16 / 3 * chi**3, 1.5
    else:
        indenter, h, force, k = mv.Rod(radius=0.2), 0.2 / chi, 0.016, 1.0
    depth, wall = {}, {}
    for body in (None, mv.Layer(h, base)):
        scene = mv.Scene(indenter=indenter, medium=mv.Elastic(G=1.0), force=force, body=body)
        result = mv.solve(scene, "bem", n)
        depth[body is None], wall[body is None] = result.depth[-1], result.wall_time
    layer, half = depth[False], depth[True]
    chi_layer = (np.sqrt(layer) if tip == "sphere" else 0.2) / h
    return chi_layer, (half / layer) ** k, wall[False], wall[True]


def cost(n: int) -> None:
    """Times of a free sphere solve and of a periodic cell's iterations, layer and half-space."""
    sphere = mv.Sphere(radius=1.0)
    for base in ("bonded",):
        start = time.perf_counter()
        mv.solve(mv.Scene(indenter=sphere, medium=mv.Elastic(G=1.0, nu=0.3), force=0.1,
                          body=mv.Layer(1.0, base)), "bem", n)
        print(f"first free layer solve (nu = 0.3, {base}; builds the correction table): "
              f"{time.perf_counter() - start:.2f} s")
    print(f"\nfree grid, n = {n}: wall time (s) of one elastic sphere solve")
    for chi in (0.3, 1.0):
        _, _, layer, half = factor("sphere", "bonded", chi, n)
        print(f"  chi {chi}: half-space {half:.3f}, layer {layer:.3f}, ratio {layer / half:.2f}")
    size = 256
    dx = 1.0 / size
    x = (np.arange(size) - size // 2 + 0.5) * dx
    heights = np.tile(0.01 * np.cos(2 * np.pi * x), (4, 1))
    print(f"\nperiodic cell {size} x 4 (wavy surface, half of full contact): Polonsky–Keer iterations "
          "(all levels) and wall time of the solve")
    for body in (None, mv.Layer(0.05), mv.Layer(0.05, "frictionless")):
        scene = mv.Scene(indenter=mv.HeightMap(heights, dx, periodic=True), medium=mv.Elastic(G=1.0),
                         force=0.5 * np.pi * 4 * 0.01 * heights.size * dx * dx, body=body)
        result = mv.solve(scene, "bem")
        print(f"  {'half-space' if body is None else f'layer h = 0.05, {body.base}':32s}"
              f" {int(result.iterations):4d} iterations, {result.wall_time * 1e3:8.1f} ms")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=129, help="BEM grid size (default 129)")
    parser.add_argument("--chi", type=float, nargs="+", default=[0.1, 0.2, 0.3, 0.5, 0.7, 1.0])
    args = parser.parse_args()
    print(__doc__.splitlines()[0])
    print(f"bottom-effect factor F / F_half at the layer's depth (nu = 0.5, BEM n = {args.n}) and the "
          "corrections' relative errors")
    for (tip, base), names in APPLIES.items():
        print(f"\n{tip}, {base} base")
        print("   chi   layer  " + "  ".join(f"{name:>22s}" for name in names))
        for target in args.chi:
            chi, value, _, _ = factor(tip, base, target, args.n)
            errors = "  ".join(f"{correction(name, np.array(chi)) / value - 1:+22.2%}" for name in names)
            print(f"{chi:6.3f} {value:7.3f}  {errors}")
    print()
    cost(args.n)


if __name__ == "__main__":
    main()
