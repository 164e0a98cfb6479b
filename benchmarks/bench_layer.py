"""The field's bottom-effect corrections against mdrvisc's layer, and what a layer costs.

Elastic incompressible layers of thickness h on a rigid base, indented by a sphere (radius
R, chi = sqrt(R d) / h) and a flat punch (radius a, chi = a / h), by BEM on free grids. For
each chi, the layer's depth d under a force F and the half-space's at the same grid give
the bottom-effect factor F / F_half(d), F_half(d) = F (d / d_half)^k (k = 3/2 sphere, 1
punch: discretisation cancels); printed against the corrections as PyFMRheo implements
them (``pyfmrheo.models.bec``): Dimitriadis et al., Biophys. J. 82 (2002), bonded and not
bonded; Garcia & Garcia, Biophys. J. 114 (2018), paraboloid and flat punch (bonded). Each
entry is the correction's relative error against the layer's factor.

Cost (``--cost``): the CPU time of the process (all threads) of a sphere under a force on
a free layer against the half-space at the same n, elastic (one static solve) and viscous
(implicit steps), both on windows around the contact (the layer's widened by the most its
surface can rise), with their iterations and last windows; the layer's first solve builds
its correction table, once per Poisson ratio and base in the process: timed apart. Then the
iterations and CPU time of a periodic cell's solve on a layer against the periodic
half-space (the same operator cost per iteration: one FFT pair and a spectrum product).

MDR on a layer against BEM (``--mdr``): a paraboloid (R = 1) and a cone (slope 1) on
layers of both bases, nu = 0.3 and 0.5, under forces that give contact radii of about chi
thicknesses; each method's bottom-effect factor F / F_half(d) at its own depth against its
own half-space (so that each one's discretisation cancels), and the relative difference of
the two factors, at two BEM grids to show BEM's share.

Run: ``python benchmarks/bench_layer.py [--n 129] [--chi 0.1 0.2 0.3 0.5 0.7 1.0]
[--mdr [--mdr-chi 0.1 0.3 1 3]] [--cost]``.
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


def timed(scene: mv.Scene, n: int | None) -> tuple[float, mv.Result]:
    """CPU time (s, all threads of the process) of one BEM solve of `scene` at n, and its result."""
    start = time.process_time()
    result = mv.solve(scene, "bem", n)
    return time.process_time() - start, result


def cost(n: int) -> None:
    """CPU times of free solves (layer against half-space, force and depth control) and of a
    periodic cell's iterations, layer and half-space."""
    sphere = mv.Sphere(radius=1.0)
    for nu in (0.3, 0.5):
        start = time.process_time()
        mv.solve(mv.Scene(indenter=sphere, medium=mv.Elastic(G=1.0, nu=nu), force=0.1,
                          body=mv.Layer(1.0)), "bem", 33)
        print(f"correction table (nu = {nu}, bonded; once per process): "
              f"{time.process_time() - start:.2f} s CPU")
    print(f"\nfree grid, n = {n}: CPU time (s) of a sphere (R = h = 1) under a force on an elastic "
          "medium (G = 1, one static solve) and a viscous one (eta = 1, a constant force for 1 s, "
          "20 implicit steps), Polonsky–Keer iterations and the window (elements) of the last solve")
    print(f"{'nu':>4s} {'medium':>8s} {'chi':>4s} {'half-space':>10s} {'layer':>8s} {'ratio':>6s}"
          f" {'its half':>8s} {'its layer':>9s} {'window half':>11s} {'window layer':>12s}")
    for nu in (0.3, 0.5):
        for kind in ("elastic", "viscous"):
            medium = mv.Elastic(G=1.0, nu=nu) if kind == "elastic" else mv.Viscous(eta=1.0, nu=nu)
            timing = {} if kind == "elastic" else {"duration": 1.0, "times": np.linspace(0.05, 1.0, 20)}
            for chi in (0.3, 1.0):
                times, results = [], []
                for body in (None, mv.Layer(1.0)):
                    scene = mv.Scene(indenter=sphere, medium=medium, body=body, force=16 / 3 * chi**3,
                                     **timing)
                    seconds, result = timed(scene, n)
                    times.append(seconds)
                    results.append(result)
                windows = [f"{r.window[2]}x{r.window[3]}" if r.window else "-" for r in results]
                print(f"{nu:4.1f} {kind:>8s} {chi:4.1f} {times[0]:10.3f} {times[1]:8.3f} "
                      f"{times[1] / times[0]:6.2f} {results[0].iterations:8d} {results[1].iterations:9d}"
                      f" {windows[0]:>11s} {windows[1]:>12s}", flush=True)
    size = 256
    dx = 1.0 / size
    x = (np.arange(size) - size // 2 + 0.5) * dx
    heights = np.tile(0.01 * np.cos(2 * np.pi * x), (4, 1))
    print(f"\nperiodic cell {size} x 4 (wavy surface, half of full contact): Polonsky–Keer iterations "
          "(all levels) and CPU time of the solve")
    for body in (None, mv.Layer(0.05), mv.Layer(0.05, "frictionless")):
        scene = mv.Scene(indenter=mv.HeightMap(heights, dx, periodic=True), medium=mv.Elastic(G=1.0),
                         force=0.5 * np.pi * 4 * 0.01 * heights.size * dx * dx, body=body)
        seconds, result = timed(scene, None)
        print(f"  {'half-space' if body is None else f'layer h = 0.05, {body.base}':32s}"
              f" {int(result.iterations):4d} iterations, {seconds * 1e3:8.1f} ms CPU")


def mdr_factor(tip: str, base: str, nu: float, chi: float, method: str, n: int) -> tuple[float, float]:
    """(a / h, the bottom-effect factor) of a paraboloid (R = 1) or a cone (slope 1) on a
    layer h = 1 under the force that gives the half-space a contact radius chi (G = 1 Pa), by
    `method` at size n; a / h from MDR's contact length."""
    e_star = 2.0 / (1.0 - nu)
    if tip == "paraboloid":
        indenter, force, k = mv.Paraboloid(c=0.5), 4 / 3 * e_star * chi**3, 1.5
    else:
        indenter, force, k = mv.Cone(slope=1.0), 0.5 * np.pi * e_star * chi**2, 2.0
    depth = {}
    for body in (None, mv.Layer(1.0, base)):
        scene = mv.Scene(indenter=indenter, medium=mv.Elastic(G=1.0, nu=nu), force=force, body=body)
        result = mv.solve(scene, method, n)
        depth[body is None] = result.depth[-1]
        if body is not None:
            radius = 0.5 * result.contact_length[-1] if method == "mdr" else np.sqrt(result.area[-1] / np.pi)
    return radius, (depth[True] / depth[False]) ** k


def mdr_against_bem(n: int, chis: list[float]) -> None:
    """MDR's bottom-effect factor on a layer against BEM's at n and 2 n - 1."""
    print(f"\nMDR on a layer (n = 4001) against BEM (n = {n} and {2 * n - 1}): bottom-effect "
          "factors and MDR's relative difference")
    print(f"{'tip':>10s} {'base':>12s} {'nu':>4s} {'a/h':>6s} {'MDR':>8s} {'BEM n':>8s} {'BEM 2n-1':>8s}"
          f" {'diff n':>8s} {'diff 2n-1':>9s}")
    for tip in ("paraboloid", "cone"):
        for base in ("bonded", "frictionless"):
            for nu in (0.3, 0.5):
                for chi in chis:
                    a, mdr = mdr_factor(tip, base, nu, chi, "mdr", 4001)
                    _, coarse = mdr_factor(tip, base, nu, chi, "bem", n)
                    _, fine = mdr_factor(tip, base, nu, chi, "bem", 2 * n - 1)
                    print(f"{tip:>10s} {base:>12s} {nu:4.1f} {a:6.3f} {mdr:8.4f} {coarse:8.4f} {fine:8.4f}"
                          f" {mdr / coarse - 1:+8.2%} {mdr / fine - 1:+9.2%}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=129, help="BEM grid size (default 129)")
    parser.add_argument("--chi", type=float, nargs="+", default=[0.1, 0.2, 0.3, 0.5, 0.7, 1.0])
    parser.add_argument("--mdr", action="store_true", help="MDR on a layer against BEM only")
    parser.add_argument("--mdr-chi", type=float, nargs="+", default=[0.1, 0.3, 1.0, 3.0])
    parser.add_argument("--cost", action="store_true", help="the cost of a layer against a half-space only")
    args = parser.parse_args()
    print(__doc__.splitlines()[0])
    if args.cost:
        cost(args.n)
        return
    if args.mdr:
        mdr_against_bem(args.n, args.mdr_chi)
        return
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
