"""Polonsky-Keer in NumPy on bench_rough.py's surfaces: the finest level's iteration count
of the crate's algorithm, and of changes to it that the crate does not have, before any is
built. A diagnostic of the count, not a timing.

Why: ``bench_fixed_set.py`` measures preconditioners on the final contact set held fixed,
where a coarse space of one constant per contact patch takes the count from 15-18 to 11-13.
A solve must also find the set. This script runs the whole iteration to see what such a
change does to the count then.

The iteration (force control, double precision throughout), as the crate's
(``rust/src/bem/contact/polonsky_keer.rs``):

* It starts from the solution on the grid coarsened by two (``mv.solve`` at tol 1e-4),
  repeated over each element's four children and scaled to the force.
* At each iteration, on the contact set {p > 0}:
  - the gradient g is the gap less its mean over the set;
  - z is the residual band's preconditioner (``bench_fixed_set.SetOperators``, the band
    found for the current set) at mdrvisc's scale, 2 dx abs(q): the pressure an element
    that enters the set is given, -tau times its gap, depends on it;
  - the direction t = z + beta t_old uses Polak-Ribiere's beta, clipped at 0;
  - the step tau is the exact line search under the force constraint.
* Elements off the set whose gap after the step is negative enter it with the pressure
  -tau gap. Then the pressure is rescaled to the force and u = K p is applied anew.
* It stops at the first iteration whose relative change of the pressure (L1) is below
  ``--tol``.

It differs from the crate in its start (the crate shares each coarse element's pressure
among its children by their heights) and in the crate's single-precision work. On the main
case (H 0.8, 5 %, periodic) it takes 17, 18 and 19 iterations at 512^2, 1024^2 and 2048^2,
where the crate's finest level takes 16, 18 and 19.

Variants (``--variants``):

* ``plain``: the iteration above;
* ``coarse``: z from the balancing preconditioner of the current set's patches around the
  band (``bench_fixed_set.py``'s ``patches+band``), its coarse matrix built exactly at
  every set change (one apply per patch). ``--balance`` weighs the band's part of it
  against the coarse part (1: mdrvisc's scale, where the band's preconditioner is about
  the operator's inverse);
* ``coarse-settled``: the same only in iterations that follow a step that changed no
  element, with beta = 0 at each switch;
* ``shaped``, ``shaped-settled``: as ``coarse`` and ``coarse-settled``, but each patch's
  coarse function is the current pressure on it raised to ``--shape-exponent`` (1), not a
  constant: a correction in that space scales a patch's pressure and leaves its edge,
  where the pressure falls to zero, where it is. Built anew at every iteration that uses it
  (the pressure changes), one apply per patch;
* ``gcr-K``: each new direction made A-orthogonal to the last K directions (K >= 1),
  restricted to the current set, with exact products (one apply each), in place of
  Polak-Ribiere's beta.

A variant that has not converged within ``--max-iter`` iterations prints as ``>N``.

Run: ``python benchmarks/bench_polonsky_keer.py --sizes 512 1024 --variants plain
coarse-settled gcr-3`` (the coarse variants take one apply per patch whenever they build
their coarse matrix: ``coarse`` at 512^2 about 2 minutes; ``plain`` and ``coarse-settled``
together about 1 and 4 minutes at 1024^2 and 2048^2, on 2 cores; the shaped variants build
theirs at every iteration that uses them: ``shaped`` at 512^2 about 1.5 minutes to
``--max-iter 60``, ``plain`` and ``shaped-settled`` about 1 and 5 minutes at 1024^2 and
2048^2).
"""

from __future__ import annotations

import argparse
import time
from functools import cached_property

import numpy as np

import mdrvisc as mv
from _bench import header, table
from bench_fixed_set import SetOperators, surface_arguments, surface_line
from bench_rough import EDGE, estimated_pressure, mv_solve, pressure, self_affine

COARSE_TOL = 1e-4


def variant_ok(name: str) -> str:
    """``name`` if it is a known variant, else an argparse error."""
    if name in ("plain", "coarse", "coarse-settled", "shaped", "shaped-settled"):
        return name
    if name.startswith("gcr-") and name[4:].isdigit() and int(name[4:]) >= 1:
        return name
    raise argparse.ArgumentTypeError(f"unknown variant {name!r}")


def nested_start(z: np.ndarray, mode: str, force: float) -> np.ndarray:
    """The pressure (Pa) a finest level starts from: the solution on the grid coarsened by
    two (tol ``COARSE_TOL``), repeated over each element's four children."""
    n = z.shape[0]
    coarse = z.reshape(n // 2, 2, n // 2, 2).mean(axis=(1, 3))
    return np.kron(pressure(mv_solve(coarse, mode, force, COARSE_TOL)), np.ones((2, 2)))


class ShapedPatches(SetOperators):
    """``SetOperators`` whose coarse function on each patch is ``shape`` (one value per set
    element, in the set's order) instead of a constant."""

    def __init__(self, mask: np.ndarray, mode: str, operator, shape: np.ndarray,
                 scale: float):
        super().__init__(mask, mode, operator, scale=scale)
        self.patch_shape = shape

    @cached_property
    def coarse_matrix(self) -> np.ndarray:
        """Z^T A Z = (P Z)^T K (P Z), P Z = Z - 1 a^T / s (a = Z^T 1, s the set's size): the
        constant functions' shortcut, Z^T K 1 as the kernel's row sums, does not hold."""
        index, m, w = self.patch_index, self.patch_count, self.patch_shape
        a = np.bincount(index, weights=w, minlength=m)
        s = float(self.set.sum())
        ones = self.operator.apply(self.set.astype(float))[self.set]
        b = np.bincount(index, weights=w * ones, minlength=m)
        return (self.patch_kernel - np.outer(a, b) / s - np.outer(b, a) / s
                + np.outer(a, a) * ones.sum() / s**2)

    def coarse(self, far: bool = False):
        """Q r = Z (Z^T A Z)^+ Z^T r; the monopole matrix (``far``) is for constants only."""
        if far:
            raise ValueError("shaped patches have no monopole coarse matrix")
        return super().coarse()


def polonsky_keer(z: np.ndarray, mode: str, force: float, start: np.ndarray, variant: str,
                  tol: float, max_iter: int, balance: float = 1.0,
                  trace: bool = False, exponent: float = 1.0) -> int | None:
    """Iterations of the NumPy Polonsky-Keer (``variant``) on heights ``z`` (m) under
    ``force`` (N) from the pressure ``start`` (scaled to the force) to a relative change
    below ``tol``; None if ``max_iter`` did not do.
    ``balance`` weighs the band's preconditioner inside the coarse variants' balancing
    form, in units of mdrvisc's 2 dx abs(q). ``trace`` prints each iteration's relative
    change and the elements that entered and left the set. ``exponent``: the shaped
    variants' coarse functions are the pressure to this power on each patch."""
    n = z.shape[0]
    area = (EDGE / n) ** 2
    operator = mv.arrays.SurfaceOperator((n, n), EDGE / n, periodic=mode == "periodic")
    h = z.max() - z
    p = start * (force / (start.sum() * area))
    u = operator.apply(p)
    t, z_old, g_old = np.zeros((n, n)), np.zeros((n, n)), 1.0
    history: list[np.ndarray] = []
    changed, coarse_on, ops, weighted = True, False, None, None
    for it in range(1, max_iter + 1):
        if changed:
            ops = SetOperators(p > 0, mode, operator, scale=2.0 * EDGE / n)
            weighted = None
        on = ops.set
        gap = u + h
        gap -= gap[on].mean()
        g = np.where(on, gap, 0.0)
        family = variant.removesuffix("-settled")
        use_coarse = family in ("coarse", "shaped") and (
            family == variant or not changed)
        if use_coarse and family == "shaped":
            shape = p[on] ** exponent
            zz = ShapedPatches(on, mode, operator, shape / shape.mean(),
                               scale=2.0 * EDGE / n * balance).preconditioner("patches+band")(g)
        elif use_coarse:
            if weighted is None:
                weighted = SetOperators(on, mode, operator, scale=2.0 * EDGE / n * balance)
            zz = weighted.preconditioner("patches+band")(g)
        else:
            zz = ops.preconditioner("band")(g)
        gz, gz_old = np.vdot(g, zz), np.vdot(g, z_old)
        beta = max((gz - gz_old) / g_old, 0.0) if it > 1 else 0.0
        if use_coarse != coarse_on:
            beta = 0.0
        coarse_on = use_coarse
        g_old, z_old = gz, zz
        if variant.startswith("gcr-"):
            t = a_orthogonal(ops, zz, history[-int(variant[4:]):])
            history.append(t)
        else:
            t = ops.restrict(zz + beta * t)
        r = operator.apply(t)
        rbar = r[on].mean()
        tau = np.vdot(g, t) / np.vdot((r - rbar) * on, t)
        p_old = p
        p = np.where(on, np.maximum(p - tau * t, 0.0), 0.0)
        after = gap - tau * (r - rbar)
        enter = ~on & (after < 0)
        p[enter] = -tau * after[enter]
        p *= force / (p.sum() * area)
        u = operator.apply(p)
        changed = bool(((p > 0) != on).any())
        change = np.abs(p - p_old).sum() / p.sum()
        if trace:
            print(f"     {variant} iteration {it}: relative change {change:.2e}, "
                  f"{int(enter.sum())} entered, {int((on & (p == 0)).sum())} left", flush=True)
        if change < tol:
            return it
    return None


def a_orthogonal(ops: SetOperators, z: np.ndarray, directions: list) -> np.ndarray:
    """z on the set, made A-orthogonal (A = the set's operator) to ``directions``, each
    restricted to the set and orthogonalised in turn."""
    basis = []
    for d in directions:
        d = ops.restrict(d)
        for b, ab in basis:
            d = d - (np.vdot(d, ab) / np.vdot(b, ab)) * b
        ad = ops.apply(d)
        if np.vdot(d, ad) > 0.0:
            basis.append((d, ad))
    t = ops.restrict(z)
    for b, ab in basis:
        t = t - (np.vdot(t, ab) / np.vdot(b, ab)) * b
    return t


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512])
    ap.add_argument("--modes", nargs="+", choices=["periodic", "free"], default=["periodic"])
    surface_arguments(ap)
    ap.add_argument("--max-iter", type=int, default=80)
    ap.add_argument("--balance", type=float, default=1.0,
                    help="the band's weight inside the coarse variants' balancing form, in "
                         "units of mdrvisc's preconditioner 2 dx abs(q) (1)")
    ap.add_argument("--shape-exponent", type=float, default=1.0,
                    help="the shaped variants' coarse functions: the pressure on each patch "
                         "to this power (1)")
    ap.add_argument("--trace", action="store_true",
                    help="print each iteration's relative change and set changes")
    ap.add_argument("--variants", nargs="+", type=variant_ok,
                    default=["plain", "coarse-settled", "gcr-3"],
                    help="plain, coarse, coarse-settled, shaped, shaped-settled, gcr-K (K >= 1)")
    args = ap.parse_args(argv)
    header("NumPy Polonsky-Keer: the finest level's iterations per variant against the grid")
    print(f"   {surface_line(args)}, balance {args.balance:g}, "
          f"shape exponent {args.shape_exponent:g}")
    rows = []
    for mode in args.modes:
        for n in args.sizes:
            start = time.perf_counter()
            z = self_affine(n, args.seed, args.hurst, args.short)
            force = estimated_pressure(args.fraction) * EDGE**2
            counts, p0 = [], nested_start(z, mode, force)
            for variant in args.variants:
                it = polonsky_keer(z, mode, force, p0, variant, args.tol, args.max_iter,
                                   args.balance, args.trace, args.shape_exponent)
                counts.append(f">{args.max_iter}" if it is None else str(it))
            finest = mv_solve(z, mode, force, args.tol).level_iterations[-1]
            rows.append([mode, n, *counts, finest, time.perf_counter() - start])
            print(f"   {mode} {n}: done", flush=True)
    table(["mode", "n", *args.variants, "mv.solve finest", "s"], rows,
          ["{}", "{}"] + ["{}"] * (len(args.variants) + 1) + ["{:.1f}"])


if __name__ == "__main__":
    main()
