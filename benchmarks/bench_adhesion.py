"""Adhesive contact by MDR (JKR by Heß's rule): pull-off convergence under refinement and the
cost of one approach-retract curve, the forward model a fit of a retract curve would call.

Scene: a paraboloid of radius R = 1 m on an elastic body (E* = 1 Pa) with w = 1/pi J/m^2
(so JKR's pull-off under force control is -3/2 pi w R = -1.5 N), force up to 32/3 N and down
to -3 N, 2000 steps through the pull-off; and one AFM-like depth-controlled curve on a standard
solid (sphere R = 10 um, 2100 steps), the case a fit evaluates.

Columns: n (MDR elements over 5 R), the pull-off force's relative error against -3/2 pi w R,
and the wall time of one curve (best of N, ``mv.solve`` end to end).

BEM with a cohesive-zone law (``mv.arrays.adhesive_pull_off``): a sphere R = 1 m on E* = 4 Pa
(G = 1 Pa), w = 0.01 J/m^2. Maugis–Dugdale's pull-off against Maugis's (1992) parametric
solution at transition parameters lambda (Johnson & Greenwood's 1997 form, solved here) as
the grid is refined, with the elements across the cohesive zone at the pull-off and the wall
time; and the exponential law (potential -w exp(-g / rho)) against the ContactEngineering
Adhesion package (``BoundedSmoothContactSystem``: L-BFGS-B on the displacements with the
hard wall, same grid, same potential, same depths), when it is importable (install it into
a separate environment and pass its site-packages with ``--adhesion-path``).

Fits: ``mv.fit(..., contact=mv.JKR(...))`` of a depth-controlled approach and retract made
by JKR's closed form (sphere-like paraboloid R = 5 um, G = 1 kPa, w = 1 mJ/m^2, 1 % noise):
wall time of the whole fit and the recovered G and w.

BEM against MDR's JKR and fits of BEM curves: a depth-controlled approach (-0.02 to 0.08 m)
and retract (to -0.04 m) of the same sphere under Maugis–Dugdale at lambda = 2, 3, 4 on grids
of 1.2 and 1.8 times the law's resolution limit (the element E* h0 / (1.12 sigma0)): the
largest difference of the BEM force from JKR's closed form on its equilibrium branch (the
curve MDR's equilibrium approach gives) at the depths both are in contact, the samples
where one is in contact and the other not (the jumps of a zone of finite range), the
largest change of the BEM force from the coarser grid (in the force's range), the least
force against Maugis and JKR, and a fit by ``contact=mv.JKR(..., approach="equilibrium")`` at
1 % noise (G and w relative errors).

Run: ``python benchmarks/bench_adhesion.py [--sizes 501 2001 8001 32001] [--repeats 5]
[--bem-sizes 32 64 128] [--lambdas 0.3 1 3] [--md-side 0.8] [--adhesion-sizes 32]
[--adhesion-path DIR] [--jkr-lambdas 2 3 4] [--jkr-refinements 1.2 1.8]``.
"""

from __future__ import annotations

import argparse
import math
import sys
import time

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, table

W = 1.0 / math.pi


def force_scene() -> mv.Scene:
    times = np.union1d(np.linspace(0.01, 2.0, 200), np.linspace(1.85, 1.95, 2000))
    return mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25),
                    contact=mv.JKR(work_of_adhesion=W),
                    force=([0.0, 1.0, 2.0], [0.0, 32.0 / 3.0, -3.0]), duration=2.0,
                    times=times, dt=0.01)


def afm_scene() -> mv.Scene:
    t_in, t_end = 0.2, 1.0
    times = np.concatenate([np.linspace(0.002, t_in, 100), np.linspace(t_in, t_end, 2001)[1:]])
    return mv.Scene(indenter=mv.Sphere(radius=10e-6),
                    medium=mv.StandardSolid(G_inf=0.2e6, G1=0.6e6, tau1=0.01),
                    contact=mv.JKR(work_of_adhesion=0.05),
                    depth=([0.0, t_in, t_end], [0.0, 1.6e-6, -1.6e-6]), duration=t_end, times=times)


def sphere(n: int, side: float) -> tuple[np.ndarray, float]:
    """The separation of a sphere R = 1 m on an n x n grid spanning ``side`` (m), and dx."""
    dx = side / n
    x = (np.arange(n) - (n - 1) / 2) * dx
    return (x[:, None] ** 2 + x[None, :] ** 2) / 2.0, dx


def md_rows(lambdas, sizes, side=None):
    """Maugis–Dugdale pull-off by BEM against Maugis, per lambda and grid (of ``side`` m, or
    sized from the law's range)."""
    w, e_star = 0.01, 4.0
    k = 4.0 * e_star / 3.0
    rows = []
    for lam in lambdas:
        stress = lam / 2 * (math.pi * w * k * k) ** (1 / 3)
        law = mv.MaugisDugdale(work_of_adhesion=w, stress=stress)
        h0 = w / stress
        # the zone ends near the rigid gap h0 + |pull-off depth|; the grid spans 2.5 times it
        span = side or max(1.2, 2.5 * math.sqrt(2 * (h0 + 0.05)))
        reference = mv.analytic.maugis_pull_off(lam)
        for n in sizes:
            h, dx = sphere(n, span)
            t0 = time.perf_counter()
            try:
                r = mv.arrays.adhesive_pull_off(h, dx, 1.0, law, 0.02, -0.1, steps=30)
            except (mv.InvalidInputError, mv.ConvergenceError):  # refused, or stalled
                rows.append((lam, n, math.nan, reference, math.nan, math.nan, 0, math.nan))
                continue
            seconds = time.perf_counter() - t0
            p = -r["force"] / (math.pi * w)
            # elements across the zone: c - a, radii of the areas it and the contact cover
            across = math.sqrt((r["contact"] + r["zone"]) / math.pi) - math.sqrt(r["contact"] / math.pi)
            rows.append((lam, n, p, reference, p / reference - 1.0, across, r["solves"], seconds))
    return rows


def adhesion_package_curve(h, dx, w, rho, depths):
    """Forces (N) of the Adhesion package's bounded smooth system with the exponential
    potential at ``depths``, each solve started from the last displacements; and the time."""
    from Adhesion.Interactions import Exponential
    from Adhesion.System import BoundedSmoothContactSystem, make_system
    from ContactMechanics import FreeFFTElasticHalfSpace
    from SurfaceTopography import Topography

    n = h.shape[0]
    size = (n * dx, n * dx)
    substrate = FreeFFTElasticHalfSpace((n, n), 4.0, size)
    system = make_system(substrate=substrate, interaction=Exponential(w, rho),
                         surface=Topography(-h, size), system_class=BoundedSmoothContactSystem)
    disp = None
    forces = []
    t0 = time.perf_counter()
    for d in depths:
        r = system.minimize_proxy(offset=d, initial_displacements=disp,
                                  options=dict(gtol=1e-9 * w / rho * dx * dx, ftol=0, maxcor=3,
                                               maxiter=100000))
        disp = r.x.reshape(system.substrate.nb_subdomain_grid_pts)
        forces.append(system.compute_normal_force())
    return np.array(forces), time.perf_counter() - t0


def exponential_rows(sizes, adhesion_sizes, adhesion_path):
    """The exponential law's approach-retract curve by mdrvisc and by the Adhesion package."""
    w, rho = 0.01, 0.02
    law = mv.Exponential(work_of_adhesion=w, range=rho)
    depths = np.concatenate([np.linspace(-0.05, 0.02, 15), np.linspace(0.02, -0.1, 49)[1:]])
    if adhesion_path:
        sys.path.insert(0, adhesion_path)
    try:
        import Adhesion  # noqa: F401
        have_package = True
    except ImportError:
        have_package = False
    rows = []
    for n in sizes:
        h, dx = sphere(n, 1.6)
        t0 = time.perf_counter()
        c = mv.arrays.adhesive_curve(h, dx, 1.0, law, depths)
        ours = time.perf_counter() - t0
        theirs, seconds, diff = float("nan"), float("nan"), float("nan")
        if have_package and n in adhesion_sizes:
            try:
                forces, seconds = adhesion_package_curve(h, dx, w, rho, depths)
                theirs = -forces.min() / (math.pi * w)
                diff = np.max(np.abs(forces - c["force"])) / (math.pi * w)
            except Exception as exc:  # the package's own failure is reported, not fatal
                print(f"Adhesion package failed at n = {n}: {exc}")
        rows.append((n, -c["force"].min() / (math.pi * w), theirs, diff, ours, seconds))
    return rows, have_package


def jkr_retract(d: np.ndarray, radius: float, e_star: float, w: float) -> np.ndarray:
    """JKR's closed form for a paraboloid of radius ``radius`` (m) under prescribed depths d
    (m), one approach and one retract (N): Hertz in, the contact held at its largest radius,
    then the JKR branch to its unstable end under depth control (Johnson, Kendall & Roberts
    1971), independent of the fit's model."""
    top = int(np.argmax(d))
    a_m = math.sqrt(radius * d[top])
    grid = np.linspace(1e-6 * a_m, a_m, 200001)
    depth = grid**2 / radius - np.sqrt(2.0 * math.pi * w * grid / e_star)
    force = 4.0 * e_star * grid**3 / (3.0 * radius) - np.sqrt(8.0 * math.pi * w * e_star * grid**3)
    stable = grid >= grid[int(np.argmin(depth))]
    out = 4.0 / 3.0 * e_star * math.sqrt(radius) * np.maximum(d, 0.0) ** 1.5
    for i in range(top + 1, d.size):
        if d[i] >= depth[-1]:
            out[i] = 2.0 * e_star * (a_m * d[i] - a_m**3 / (3.0 * radius))
        elif d[i] >= depth[stable].min():
            out[i] = np.interp(d[i], depth[stable], force[stable])
        else:
            out[i:] = 0.0
            break
    return out


def jkr_fit_rows(repeats: int):
    """Fits of a JKR approach-retract curve (closed form, 1 % noise): wall time and the
    recovered shear modulus and work of adhesion."""
    radius, g, w = 5e-6, 1e3, 1e-3
    rows = []
    for samples in (600, 2000, 8000):
        t = np.linspace(0.0, 2.0, samples + 1)
        d = np.where(t <= 1.0, 3e-6 * t, 3e-6 - 4.5e-6 * (t - 1.0))
        force = jkr_retract(d, radius, 4.0 * g, w)
        force = force + 0.01 * np.ptp(force) * np.random.default_rng(1).standard_normal(force.size)
        seconds, fit = best_of(lambda t=t, d=d, f=force: mv.fit(
            mv.Paraboloid(c=0.5 / radius), mv.Elastic, t, depth=d, force=f,
            contact=mv.JKR(work_of_adhesion=w)), repeats, warmup=1)
        rows.append((samples + 1, fit.parameters["G"] / g - 1.0,
                     fit.parameters["work_of_adhesion"] / w - 1.0, fit.nfev, seconds * 1e3))
    return rows


def jkr_branch(d: np.ndarray, radius: float, e_star: float, w: float) -> np.ndarray:
    """JKR's force (N) on its stable equilibrium branch at depths d (m) for a paraboloid of
    radius ``radius``: F(a) = 4 E* a^3 / (3 R) - sqrt(8 pi w E* a^3) at the radius of
    d = a^2 / R - sqrt(2 pi w a / E*) beyond the branch's unstable end; NaN where the branch
    has no such radius (Johnson, Kendall & Roberts 1971)."""
    a_end = (radius / 4.0 * math.sqrt(2.0 * math.pi * w / e_star)) ** (2.0 / 3.0)
    grid = np.linspace(a_end, 3.0 * radius, 400001)
    depth = grid**2 / radius - np.sqrt(2.0 * math.pi * w * grid / e_star)
    force = 4.0 * e_star * grid**3 / (3.0 * radius) - np.sqrt(8.0 * math.pi * w * e_star * grid**3)
    return np.where(d >= depth[0], np.interp(d, depth, force), np.nan)


def bem_jkr_rows(lambdas, refinements):
    """Maugis–Dugdale approach-retract curves by BEM against JKR's equilibrium branch, and
    JKR fits of them (sphere R = 1 m, G = 1 Pa, w = 0.01 J/m^2, grid side 0.9 m)."""
    w, g, side = 0.01, 1.0, 0.9
    e_star = 4.0 * g
    k = 4.0 * e_star / 3.0
    unit = math.pi * w
    d = np.concatenate([np.linspace(-0.02, 0.08, 21), np.linspace(0.08, -0.04, 49)[1:]])
    top = int(np.argmax(d))
    reference = jkr_branch(d, 1.0, e_star, w)
    # before the touch and past the branch's end JKR's contact is open
    reference[:top][d[:top] < 0.0] = np.nan
    t = np.linspace(0.0, 2.0, d.size)
    rows = []
    for lam in lambdas:
        stress = lam / 2.0 * (math.pi * w * k * k) ** (1.0 / 3.0)
        law = mv.MaugisDugdale(work_of_adhesion=w, stress=stress)
        finest = e_star * law.range / (1.12 * stress)
        coarser = None
        for factor in refinements:
            n = 8 * math.ceil(factor * side / finest / 8)
            h, dx = sphere(n, side)
            t0 = time.perf_counter()
            force = None
            for tol in (1e-8, 1e-6):  # the looser one where the sweeps stall at the tighter
                try:
                    force = mv.arrays.adhesive_curve(h, dx, g, law, d, tol=tol)["force"]
                    break
                except (mv.InvalidInputError, mv.ConvergenceError) as exc:
                    print(f"lambda = {lam:g}, n = {n}, tol = {tol:g}: {exc}")
            if force is None:
                rows.append((lam, n, *([math.nan] * 8)))
                continue
            seconds = time.perf_counter() - t0
            # the change from the coarser grid, in the force's range (NaN on the first)
            moved = math.nan if coarser is None else float(np.max(np.abs(force - coarser)) / np.ptp(force))
            coarser = force
            both = np.isfinite(reference) & (force != 0.0)
            jumps = int(np.sum(np.isfinite(reference) != (force != 0.0)))
            diff = np.max(np.abs(force[both] - reference[both])) / unit
            data = force + 0.01 * np.ptp(force) * np.random.default_rng(1).standard_normal(force.size)
            fit = mv.fit(mv.Paraboloid(c=0.5), mv.Elastic, t, depth=d, force=data,
                         contact=mv.JKR(work_of_adhesion=0.3 * w, approach="equilibrium"))
            rows.append((lam, n, moved, diff, jumps, -force.min() / unit, mv.analytic.maugis_pull_off(lam),
                         fit.parameters["G"] / g - 1.0, fit.parameters["work_of_adhesion"] / w - 1.0,
                         seconds))
    return rows


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[501, 2001, 8001, 32001])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--bem-sizes", type=int, nargs="+", default=[32, 64, 128])
    parser.add_argument("--lambdas", type=float, nargs="+", default=[0.3, 1.0, 3.0])
    parser.add_argument("--md-side", type=float, default=None,
                        help="grid side (m) of the Maugis-Dugdale rows (default: from the range)")
    parser.add_argument("--adhesion-sizes", type=int, nargs="+", default=[32],
                        help="grids on which the Adhesion package runs too (it is slow)")
    parser.add_argument("--adhesion-path", default=None,
                        help="site-packages holding the Adhesion package (optional)")
    parser.add_argument("--jkr-lambdas", type=float, nargs="+", default=[2.0, 3.0, 4.0])
    parser.add_argument("--jkr-refinements", type=float, nargs="+", default=[1.2, 1.8],
                        help="grids as multiples of the elements the law's resolution limit needs")
    args = parser.parse_args(argv)
    header("Maugis-Dugdale by BEM against JKR's equilibrium branch (units of pi w R), and fits by "
           "mv.JKR(approach='equilibrium') at 1 % noise")
    table(["lambda", "n", "max |dF| vs coarser (range)", "max |F - F_JKR|", "jump samples",
           "BEM least force", "Maugis", "G rel. error", "w rel. error", "BEM s"],
          bem_jkr_rows(args.jkr_lambdas, args.jkr_refinements),
          ["{:g}", "{}", "{:.2e}", "{:.4f}", "{}", "{:.4f}", "{:.4f}", "{:+.2e}", "{:+.2e}", "{:.1f}"])
    header("Maugis-Dugdale by BEM: sphere, pull-off against Maugis (units of pi w R)")
    table(["lambda", "n", "BEM", "Maugis", "rel. error", "zone width (dx)", "solves", "s"],
          md_rows(args.lambdas, args.bem_sizes, args.md_side),
          ["{:g}", "{}", "{:.4f}", "{:.4f}", "{:+.2e}", "{:.1f}", "{}", "{:.2f}"])
    rows, have_package = exponential_rows(args.bem_sizes, args.adhesion_sizes, args.adhesion_path)
    header("Exponential law by BEM (w = 0.01 J/m^2, rho = 0.02 m) against the Adhesion package"
           + ("" if have_package else " (not importable: its columns are NaN)"))
    table(["n", "mdrvisc pull-off", "Adhesion pull-off", "max |dF| (pi w R)", "mdrvisc s",
           "Adhesion s"], rows, ["{}", "{:.4f}", "{:.4f}", "{:.2e}", "{:.2f}", "{:.2f}"])
    header(f"JKR by MDR: paraboloid under force control, pull-off vs -3/2 pi w R "
           f"(best of {args.repeats})")
    scene = force_scene()
    rows = []
    for n in args.sizes:
        seconds, r = best_of(lambda n=n: mv.solve(scene, "mdr", n), args.repeats, warmup=1)
        rows.append((n, r.pull_off_force, r.pull_off_force / -1.5 - 1.0, r.steps, seconds * 1e3))
    table(["n", "pull-off (N)", "rel. error", "steps", "ms per curve"], rows,
          ["{}", "{:.6f}", "{:+.2e}", "{}", "{:.2f}"])
    header(f"JKR by MDR: sphere on a standard solid, depth-controlled approach and retract "
           f"(best of {args.repeats})")
    scene = afm_scene()
    rows = []
    for n in (501, 2001):
        seconds, r = best_of(lambda n=n: mv.solve(scene, "mdr", n), args.repeats, warmup=1)
        rows.append((n, r.pull_off_force, -r.force.min(), r.steps, seconds * 1e3))
    table(["n", "pull-off (N)", "largest tension (N)", "steps", "ms per curve"], rows,
          ["{}", "{:.4e}", "{:.4e}", "{}", "{:.2f}"])
    header(f"Fits with JKR (mv.fit(..., contact=mv.JKR(...))): a depth-controlled approach and "
           f"retract by JKR's closed form, 1 % noise (best of {args.repeats})")
    table(["samples", "G rel. error", "w rel. error", "solves", "ms per fit"],
          jkr_fit_rows(args.repeats), ["{}", "{:+.2e}", "{:+.2e}", "{}", "{:.1f}"])


if __name__ == "__main__":
    main()
