"""Preconditioners for the contact set's own operator, against the grid: preconditioned
conjugate gradients on a rough contact's final contact set held fixed, for several
preconditioners, on the grids of ``bench_rough.py``'s surfaces.

Why: the finest level of a nested rough solve needs more iterations as the grid grows (the
issue's "iterations flat" target), and a trace of Polonsky-Keer shows the growth in the
rate of its conjugate gradients, fixed set or not. This script isolates that rate. It is a
diagnostic of the preconditioner, in NumPy, not a timing of mdrvisc: mdrvisc provides the
contact set (``mv.solve`` at tol 1e-10 through ``mv.Scene``) and the operator
(``mv.arrays.SurfaceOperator``); the conjugate gradients and the preconditioners are here.

Problem, per grid n and mode: the surface of ``bench_rough.py`` (``--seed``, by default
``bench_rough.py``'s own 20261127; Hurst ``--hurst``, modes to ``--short`` cycles, rms slope
0.1) under the mean pressure
fraction E* slope / 2 (about ``--fraction`` of the cell in contact). S is the fine solution's
contact set. The system is the contact set's operator under force control, A = P K P with P
the restriction to S followed by the removal of the mean over S (the force constraint), and
its right-hand side A e with e the difference between the fine solution and the solution on
the grid coarsened by two repeated over each element's four children (the error a nested
solve's finest level starts from, up to the start's rule), so the error has the shape the
solver meets. Conjugate gradients start from zero and stop, as Polonsky-Keer does, on the
first iteration whose step changes the solution by less than ``--tol`` (1e-8) of the
pressure, in L1.

Preconditioners (each followed and preceded by P):

* ``none``;
* ``spectral``: the half-space's inverse, |q| (cell: on the cell; free: on the grid
  zero-padded by 8 elements on each side, so that nothing wraps, as in mdrvisc, which takes
  the wrap back instead);
* ``band``: mdrvisc's residual band, E^T |q| E, where E continues the residual from S onto
  the elements within 3 of it, each taking its nearest set element's value times
  exp(-d / 2), d its distance in elements (``rust/src/bem/contact/extension.rs``);
* ``patches`` and ``patches+band``: the balancing preconditioner of a coarse space of one
  constant per contact patch (4-connected; across the cell's edges on a cell) around
  ``spectral`` or ``band``: Q + (I - Q A) M (I - A Q), Q = Z (Z^T A Z)^+ Z^T, Z the patches'
  indicators. Its coarse matrix takes one operator apply per patch to build (``--preconditioners``
  chooses), and each application two more applies: it measures what such a coarse
  space can do for the count, not a cost mdrvisc could pay as it stands.

``bench_rough.py``'s surfaces are held out from tuning: a lever chosen from this diagnosis
is to be checked on another ``--seed`` before it is measured there.

The last column is what mdrvisc's own solve (``mv.solve`` at ``--tol``, nested levels,
Polonsky-Keer) takes on its finest level on the same case: its excess over the fixed set's
count is what finding the contact set costs.

Run: ``python benchmarks/bench_fixed_set.py --sizes 512 1024 2048 --modes periodic free``
(2048^2 takes a few minutes, most of it the patches' coarse matrix).
"""

from __future__ import annotations

import argparse
import time
from functools import cached_property

import numpy as np
from scipy import ndimage

import mdrvisc as mv
from _bench import header, table
from bench_rough import EDGE, estimated_pressure, mv_solve, pressure, self_affine

BAND_RADIUS, BAND_DECAY = 3, 2.0
FREE_PAD = 8
PRECONDITIONERS = ["none", "spectral", "band", "patches", "patches+band"]


def wavenumbers(shape: tuple[int, int], dx: float) -> np.ndarray:
    """|q| (1/m) at the real FFT's wavevectors of a grid of ``shape``."""
    qy = np.fft.fftfreq(shape[0], dx)[:, None]
    qx = np.fft.rfftfreq(shape[1], dx)[None, :]
    return 2.0 * np.pi * np.hypot(qy, qx)


class FixedSet:
    """The contact set's operator, its right-hand side and the preconditioners on one grid."""

    def __init__(self, n: int, mode: str, seed: int, hurst: float, fraction: float,
                 short: int):
        self.n, self.mode = n, mode
        z = self_affine(n, seed, hurst, short)
        force = estimated_pressure(fraction) * EDGE**2
        solved = mv_solve(z, mode, force, 1e-10)
        p = pressure(solved)
        self.heights, self.force = z, force
        self.patch_count = int(solved.patches[0])
        coarse = z.reshape(n // 2, 2, n // 2, 2).mean(axis=(1, 3))
        p_coarse = pressure(mv_solve(coarse, mode, force, 1e-10))
        self.set = p > 0
        start = np.kron(p_coarse, np.ones((2, 2))) * self.set
        self.p_sum = p.sum()
        self.operator = mv.arrays.SurfaceOperator((n, n), EDGE / n, periodic=mode == "periodic")
        self.rhs = self.apply(p - start * (self.p_sum / start.sum()))
        self._spectral_setup()
        self._band_setup()

    def restrict(self, x: np.ndarray) -> np.ndarray:
        """P x: x on the set, its mean over the set removed (the force constraint)."""
        x = x * self.set
        return x - self.set * x[self.set].mean()

    def apply(self, x: np.ndarray) -> np.ndarray:
        """A x = P K P x (K: mdrvisc's operator, deflections in m at G = 1 Pa)."""
        return self.restrict(self.operator.apply(self.restrict(x)))

    def _spectral_setup(self) -> None:
        pad = 0 if self.mode == "periodic" else FREE_PAD
        self.shape = (self.n + 2 * pad, self.n + 2 * pad)
        self.pad = pad
        self.inverse = wavenumbers(self.shape, EDGE / self.n)

    def spectral(self, r: np.ndarray) -> np.ndarray:
        """|q| r on the cell, or on the grid zero-padded by ``FREE_PAD``."""
        pad, n = self.pad, self.n
        out = np.fft.irfft2(self.inverse * np.fft.rfft2(np.pad(r, pad)), s=self.shape)
        return out[pad:pad + n, pad:pad + n]

    def _band_setup(self) -> None:
        n = self.n
        outside = ~self.set
        if self.mode == "periodic":
            dist, (iy, ix) = ndimage.distance_transform_edt(np.tile(outside, (3, 3)),
                                                            return_indices=True)
        else:
            dist, (iy, ix) = ndimage.distance_transform_edt(
                np.pad(outside, n, constant_values=True), return_indices=True)
        dist, iy, ix = (a[n:2 * n, n:2 * n] for a in (dist, iy, ix))
        self.band = (dist > 0) & (dist <= BAND_RADIUS)
        self.band_weight = np.exp(-dist[self.band] / BAND_DECAY)
        self.band_source = ((iy % n) * n + (ix % n))[self.band]

    def extend(self, r: np.ndarray) -> np.ndarray:
        """E r: r on the set, continued onto the band."""
        out = r * self.set
        out[self.band] = self.band_weight * r.ravel()[self.band_source]
        return out

    def fold(self, y: np.ndarray) -> np.ndarray:
        """E^T y: y on the set plus the band's values added back to their sources."""
        out = y * self.set
        np.add.at(out.ravel(), self.band_source, self.band_weight * y[self.band])
        return out

    def preconditioner(self, name: str):
        """The named preconditioner as a function of the residual."""
        base = {
            "none": lambda r: self.restrict(r),
            "spectral": lambda r: self.restrict(self.spectral(self.restrict(r))),
            "band": lambda r: self.restrict(self.fold(self.spectral(self.extend(self.restrict(r))))),
        }
        if name in base:
            return base[name]
        inner = base["spectral" if name == "patches" else "band"]
        coarse = self.coarse()

        def balanced(r):
            c = coarse(r)
            y = inner(r - self.apply(c))
            return c + y - coarse(self.apply(y))
        return balanced

    @cached_property
    def patch_index(self) -> np.ndarray:
        """Each set element's patch index (4-connected; across the edges on a cell), the
        patches mdrvisc counts."""
        labels, count = ndimage.label(self.set)
        parent = np.arange(count + 1)

        def root(a):
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a
        if self.mode == "periodic":
            edges = list(zip(labels[0], labels[-1])) + list(zip(labels[:, 0], labels[:, -1]))
            for a, b in edges:
                if a and b:
                    parent[root(a)] = root(b)
        roots = np.array([root(a) for a in range(count + 1)])
        _, index = np.unique(roots[labels[self.set]], return_inverse=True)
        if index.max() + 1 != self.patch_count:
            raise RuntimeError(f"{index.max() + 1} patches labelled, mdrvisc counts "
                               f"{self.patch_count}")
        return index

    @cached_property
    def coarse_inverse(self) -> np.ndarray:
        """(Z^T A Z)^+, the patches' coarse matrix inverted: one apply per patch."""
        index, m = self.patch_index, self.patch_count
        spread = np.zeros((self.n, self.n))
        matrix = np.empty((m, m))
        for k in range(m):
            spread[self.set] = index == k
            matrix[:, k] = np.bincount(index, weights=self.apply(spread)[self.set], minlength=m)
        return np.linalg.pinv(0.5 * (matrix + matrix.T), rcond=1e-12, hermitian=True)

    def coarse(self):
        """Q r = Z (Z^T A Z)^+ Z^T r for the patches' coarse space."""
        index, m, inverse = self.patch_index, self.patch_count, self.coarse_inverse

        def q(r):
            out = np.zeros((self.n, self.n))
            out[self.set] = (inverse @ np.bincount(index, weights=r[self.set], minlength=m))[index]
            return out
        return q

    def iterations(self, name: str, tol: float, max_iter: int = 1000) -> int:
        """Conjugate gradients' iterations from zero to a step below ``tol`` of the pressure
        (L1), under the named preconditioner."""
        precondition = self.preconditioner(name)
        x = np.zeros((self.n, self.n))
        r = self.rhs.copy()
        z = precondition(r)
        d = z.copy()
        rz = np.vdot(r, z)
        for it in range(1, max_iter + 1):
            ad = self.apply(d)
            alpha = rz / np.vdot(d, ad)
            x += alpha * d
            r -= alpha * ad
            if np.abs(alpha * d).sum() < tol * self.p_sum:
                return it
            z = precondition(r)
            rz_next = np.vdot(r, z)
            d = z + (rz_next / rz) * d
            rz = rz_next
        return max_iter


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    ap.add_argument("--modes", nargs="+", choices=["periodic", "free"],
                    default=["periodic", "free"])
    ap.add_argument("--seed", type=int, default=20261127)
    ap.add_argument("--hurst", type=float, default=0.8)
    ap.add_argument("--fraction", type=float, default=0.05)
    ap.add_argument("--short", type=int, default=128)
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--preconditioners", nargs="+", choices=PRECONDITIONERS,
                    default=PRECONDITIONERS,
                    help="the patch coarse space costs one operator apply per patch to build")
    args = ap.parse_args(argv)
    names = args.preconditioners
    header("fixed-set conjugate gradients: iterations per preconditioner against the grid")
    print(f"   surface seed {args.seed}, H {args.hurst}, pbar for ~{args.fraction:.0%} contact, "
          f"tol {args.tol:g}")
    rows = []
    for mode in args.modes:
        for n in args.sizes:
            start = time.perf_counter()
            case = FixedSet(n, mode, args.seed, args.hurst, args.fraction, args.short)
            counts = [case.iterations(name, args.tol) for name in names]
            finest = mv_solve(case.heights, mode, case.force, args.tol).level_iterations[-1]
            rows.append([mode, n, case.set.mean(), case.patch_count, *counts, finest,
                         time.perf_counter() - start])
            print(f"   {mode} {n}: done", flush=True)
    table(["mode", "n", "contact", "patches", *names, "mv.solve finest", "s"], rows,
          ["{}", "{}", "{:.4f}", "{}"] + ["{}"] * (len(names) + 1) + ["{:.1f}"])


if __name__ == "__main__":
    main()
