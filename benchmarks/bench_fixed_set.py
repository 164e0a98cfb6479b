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
* ``split+band``: ``band`` with abs(q) split into a near part, its real-space kernel cut to
  offsets within 3 elements along each axis (a 7 x 7 stencil), and a far part, the rest of
  its symbol applied on the grid coarsened by ``--coarsening`` (8): the residual's block means
  go through an FFT pair of that small grid and come back constant over each block. Whether
  the preconditioner's FFT pair on the whole grid can give way to a stencil on the set and
  its band plus a small FFT pair at equal iterations;
* ``patches`` and ``patches+band``: the balancing preconditioner of a coarse space of one
  constant per contact patch (4-connected; across the cell's edges on a cell) around
  ``spectral`` or ``band``: Q + (I - Q A) M (I - A Q), Q = Z (Z^T A Z)^+ Z^T, Z the patches'
  indicators. Its coarse matrix takes one operator apply per patch to build (``--preconditioners``
  chooses), and each application two more applies: it measures what such a coarse
  space can do for the count, not a cost mdrvisc could pay as it stands;
* ``deflated+band`` and ``deflated-far+band``: the same coarse space in the deflation form
  that takes one apply per application, (I - Q A) M + Q around ``band``, started from Q b
  (Tang, Nabben, Vuik and Erlangga 2009, "A-DEF2"); in ``deflated-far+band`` the coarse
  matrix's entries of every two patches whose bounding boxes lie more than 2 elements apart
  are their monopole terms, the patches' areas times the point-load deflection between their
  centroids (no apply), which tests how exact the coarse matrix must be.

``bench_rough.py``'s surfaces are held out from tuning: a lever chosen from this diagnosis
is to be checked on another ``--seed`` before it is measured there.

The last column is what mdrvisc's own solve (``mv.solve`` at ``--tol``, nested levels,
Polonsky-Keer) takes on its finest level on the same case: its excess over the fixed set's
count is what finding the contact set costs.

Run: ``python benchmarks/bench_fixed_set.py --sizes 512 1024 2048 --modes periodic free``
(2048^2 takes a few minutes, most of it the patches' coarse matrix; ``--preconditioners``
picks some, ``--coarsening`` sets split+band's coarse grid).
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
PRECONDITIONERS = ["none", "spectral", "band", "split+band", "patches", "patches+band",
                   "deflated+band", "deflated-far+band"]
SPLIT_RADIUS = 3
FAR_GAP = 2


def wavenumbers(shape: tuple[int, int], dx: float) -> np.ndarray:
    """|q| (1/m) at the real FFT's wavevectors of a grid of ``shape``."""
    qy = np.fft.fftfreq(shape[0], dx)[:, None]
    qx = np.fft.rfftfreq(shape[1], dx)[None, :]
    return 2.0 * np.pi * np.hypot(qy, qx)


class SetOperators:
    """The operator of a contact set ``mask`` (n x n, boolean) under force control and the
    preconditioners on it; ``operator`` is mdrvisc's surface operator of the grid, and the
    preconditioners' abs(q) is taken times ``scale`` (m; mdrvisc's is 2 dx abs(q))."""

    def __init__(self, mask: np.ndarray, mode: str, operator, coarsening: int = 8,
                 scale: float = 1.0):
        self.n, self.mode, self.coarsening = mask.shape[0], mode, coarsening
        self.set, self.operator, self.scale = mask, operator, scale
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
        self.inverse = self.scale * wavenumbers(self.shape, EDGE / self.n)

    def spectral(self, r: np.ndarray) -> np.ndarray:
        """|q| r on the cell, or on the grid zero-padded by ``FREE_PAD``."""
        pad, n = self.pad, self.n
        out = np.fft.irfft2(self.inverse * np.fft.rfft2(np.pad(r, pad)), s=self.shape)
        return out[pad:pad + n, pad:pad + n]

    @cached_property
    def split(self):
        """The split of abs(q): (near, far) as functions of the (padded) residual."""
        shape, f = self.shape, self.coarsening
        if shape[0] % f or shape[1] % f:
            raise ValueError(f"--coarsening {f} does not divide the FFT grid {shape}")
        kernel = np.fft.irfft2(self.inverse, s=shape)
        near = np.zeros(shape)
        reach = np.r_[0:SPLIT_RADIUS + 1, -SPLIT_RADIUS:0]
        near[np.ix_(reach, reach)] = kernel[np.ix_(reach, reach)]
        near_symbol = np.fft.rfft2(near).real
        coarse = (shape[0] // f, shape[1] // f)
        rows = np.r_[0:coarse[0] // 2 + 1, shape[0] - (coarse[0] - coarse[0] // 2 - 1):shape[0]]
        far_symbol = (self.inverse - near_symbol)[rows][:, :coarse[1] // 2 + 1]

        def far(r):
            means = r.reshape(coarse[0], f, coarse[1], f).mean(axis=(1, 3))
            out = np.fft.irfft2(far_symbol * np.fft.rfft2(means), s=coarse)
            return np.repeat(np.repeat(out, f, axis=0), f, axis=1)
        return (lambda r: np.fft.irfft2(near_symbol * np.fft.rfft2(r), s=shape)), far

    def split_inverse(self, r: np.ndarray) -> np.ndarray:
        """abs(q) r as its near stencil plus its far part on the coarsened grid."""
        pad, n = self.pad, self.n
        near, far = self.split
        padded = np.pad(r, pad)
        out = near(padded) + far(padded)
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
            "split+band": lambda r: self.restrict(
                self.fold(self.split_inverse(self.extend(self.restrict(r))))),
        }
        if name in base:
            return base[name]
        inner = base["spectral" if name == "patches" else "band"]
        if name.startswith("deflated"):
            coarse = self.coarse(far=name == "deflated-far+band")

            def deflated(r):
                y = inner(r)
                return y - coarse(self.apply(y)) + coarse(r)
            return deflated
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
        return np.unique(roots[labels[self.set]], return_inverse=True)[1]

    @cached_property
    def patch_count(self) -> int:
        """The number of contact patches."""
        return int(self.patch_index.max()) + 1 if self.set.any() else 0

    @cached_property
    def patch_shape(self) -> np.ndarray:
        """The coarse functions' values on the set's elements, in the set's order (Z_j is
        this on patch j and 0 elsewhere): 1, one constant per patch."""
        return np.ones(int(self.set.sum()))

    @cached_property
    def patch_kernel(self) -> np.ndarray:
        """Z^T K Z: the patches' mutual deflections (one apply per patch)."""
        index, m, w = self.patch_index, self.patch_count, self.patch_shape
        spread = np.zeros((self.n, self.n))
        matrix = np.empty((m, m))
        for k in range(m):
            spread[self.set] = (index == k) * w
            matrix[:, k] = np.bincount(index, weights=w * self.operator.apply(spread)[self.set],
                                       minlength=m)
        return 0.5 * (matrix + matrix.T)

    def projected(self, kernel: np.ndarray) -> np.ndarray:
        """Z^T A Z from Z^T K Z: A = P K P, P the removal of the mean over the set, which
        maps Z to Z (I - 1 a^T / s), a the patches' areas (elements) and s their sum."""
        area = np.bincount(self.patch_index, minlength=self.patch_count).astype(float)
        s, rows = area.sum(), kernel.sum(axis=1)
        return (kernel - np.outer(area, rows) / s - np.outer(rows, area) / s
                + np.outer(area, area) * rows.sum() / s**2)

    @cached_property
    def coarse_matrix(self) -> np.ndarray:
        """Z^T A Z, the patches' coarse matrix."""
        return self.projected(self.patch_kernel)

    @cached_property
    def monopoles(self) -> tuple[np.ndarray, np.ndarray]:
        """(far, terms): which two patches' bounding boxes lie more than ``FAR_GAP`` elements
        apart (across the edges on a cell), and their monopole terms a_i a_j G(c_j - c_i),
        a the patches' areas (elements), c their centroids and G the deflection of a unit
        point load, read bilinearly between elements."""
        n, index, m = self.n, self.patch_index, self.patch_count
        periodic = self.mode == "periodic"
        ys, xs = (c.astype(float) for c in np.nonzero(self.set))
        if periodic:  # each patch unwrapped around one of its elements
            anchor = np.zeros((m, 2))
            anchor[index] = np.column_stack([ys, xs])
            ys = anchor[index, 0] + (ys - anchor[index, 0] + n / 2) % n - n / 2
            xs = anchor[index, 1] + (xs - anchor[index, 1] + n / 2) % n - n / 2
        area = np.bincount(index, minlength=m).astype(float)
        cy, cx = np.bincount(index, ys, m) / area, np.bincount(index, xs, m) / area
        half = []
        for c in (ys, xs):
            lo, hi = np.full(m, np.inf), np.full(m, -np.inf)
            np.minimum.at(lo, index, c)
            np.maximum.at(hi, index, c)
            half.append((hi - lo) / 2)
        dy, dx = cy[None, :] - cy[:, None], cx[None, :] - cx[:, None]
        if periodic:
            dy, dx = (dy + n / 2) % n - n / 2, (dx + n / 2) % n - n / 2
        gap = np.maximum(np.abs(dy) - half[0][:, None] - half[0][None, :],
                         np.abs(dx) - half[1][:, None] - half[1][None, :])
        size = n if periodic else 2 * n
        point = np.zeros((size, size))
        point[0, 0] = 1.0
        operator = (self.operator if periodic
                    else mv.arrays.SurfaceOperator((size, size), EDGE / n))
        response = operator.apply(point)
        oy, ox = np.floor(dy).astype(int), np.floor(dx).astype(int)
        fy, fx = dy - oy, dx - ox

        def at(a, b):
            return response[np.abs(a) % size, np.abs(b) % size]
        green = ((1 - fy) * (1 - fx) * at(oy, ox) + fy * (1 - fx) * at(oy + 1, ox)
                 + (1 - fy) * fx * at(oy, ox + 1) + fy * fx * at(oy + 1, ox + 1))
        return gap > FAR_GAP, np.outer(area, area) * green

    @cached_property
    def coarse_matrix_far(self) -> np.ndarray:
        """Z^T A Z with Z^T K Z's entries of far patches taken as their monopoles."""
        far, terms = self.monopoles
        return self.projected(np.where(far, terms, self.patch_kernel))

    @cached_property
    def coarse_inverse(self) -> np.ndarray:
        """(Z^T A Z)^+."""
        return np.linalg.pinv(self.coarse_matrix, rcond=1e-12, hermitian=True)

    @cached_property
    def coarse_inverse_far(self) -> np.ndarray:
        """(Z^T A Z)^+ with far patches' entries as monopoles."""
        return np.linalg.pinv(self.coarse_matrix_far, rcond=1e-12, hermitian=True)

    def coarse(self, far: bool = False):
        """Q r = Z (Z^T A Z)^+ Z^T r for the patches' coarse space (its matrix with far
        patches' entries as monopoles with ``far``)."""
        index, m, w = self.patch_index, self.patch_count, self.patch_shape
        inverse = self.coarse_inverse_far if far else self.coarse_inverse

        def q(r):
            out = np.zeros((self.n, self.n))
            out[self.set] = w * (inverse @ np.bincount(index, weights=w * r[self.set],
                                                       minlength=m))[index]
            return out
        return q


class FixedSet(SetOperators):
    """The contact set's operator, its right-hand side and the preconditioners on one grid:
    the final contact set of bench_rough.py's surface."""

    def __init__(self, n: int, mode: str, seed: int, hurst: float, fraction: float,
                 short: int, coarsening: int = 8):
        z = self_affine(n, seed, hurst, short)
        force = estimated_pressure(fraction) * EDGE**2
        solved = mv_solve(z, mode, force, 1e-10)
        p = pressure(solved)
        self.heights, self.force = z, force
        coarse = z.reshape(n // 2, 2, n // 2, 2).mean(axis=(1, 3))
        p_coarse = pressure(mv_solve(coarse, mode, force, 1e-10))
        operator = mv.arrays.SurfaceOperator((n, n), EDGE / n, periodic=mode == "periodic")
        super().__init__(p > 0, mode, operator, coarsening)
        if self.patch_count != int(solved.patches[0]):
            raise RuntimeError(f"{self.patch_count} patches labelled, mdrvisc counts "
                               f"{int(solved.patches[0])}")
        start = np.kron(p_coarse, np.ones((2, 2))) * self.set
        self.p_sum = p.sum()
        self.rhs = self.apply(p - start * (self.p_sum / start.sum()))

    def iterations(self, name: str, tol: float, max_iter: int = 1000) -> int:
        """Conjugate gradients' iterations from zero (the deflated ones: from Q b) to a step
        below ``tol`` of the pressure (L1), under the named preconditioner."""
        precondition = self.preconditioner(name)
        x = np.zeros((self.n, self.n))
        if name.startswith("deflated"):
            x = self.coarse(far=name == "deflated-far+band")(self.rhs)
        r = self.rhs - self.apply(x)
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


def surface_arguments(ap: argparse.ArgumentParser) -> None:
    """The options that choose bench_rough.py's surface, load and tolerance."""
    ap.add_argument("--seed", type=int, default=20261127)
    ap.add_argument("--hurst", type=float, default=0.8)
    ap.add_argument("--fraction", type=float, default=0.05)
    ap.add_argument("--short", type=int, default=128)
    ap.add_argument("--tol", type=float, default=1e-8)


def surface_line(args: argparse.Namespace) -> str:
    """The surface, load and tolerance that ``surface_arguments`` chose, in a line."""
    return (f"surface seed {args.seed}, H {args.hurst}, pbar for ~{args.fraction:.0%} contact, "
            f"tol {args.tol:g}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024])
    ap.add_argument("--modes", nargs="+", choices=["periodic", "free"],
                    default=["periodic", "free"])
    surface_arguments(ap)
    ap.add_argument("--coarsening", type=int, default=8,
                    help="split+band: the far part's grid is coarsened by this factor (8)")
    ap.add_argument("--preconditioners", nargs="+", choices=PRECONDITIONERS,
                    default=PRECONDITIONERS,
                    help="the patch coarse space costs one operator apply per patch to build")
    args = ap.parse_args(argv)
    names = args.preconditioners
    header("fixed-set conjugate gradients: iterations per preconditioner against the grid")
    print(f"   {surface_line(args)}")
    rows = []
    for mode in args.modes:
        for n in args.sizes:
            start = time.perf_counter()
            case = FixedSet(n, mode, args.seed, args.hurst, args.fraction, args.short,
                            args.coarsening)
            counts = [case.iterations(name, args.tol) for name in names]
            if "deflated-far+band" in names:
                print(f"   {mode} {n}: {case.monopoles[0].mean():.1%} of the coarse matrix's entries "
                      "taken as monopoles", flush=True)
            finest = mv_solve(case.heights, mode, case.force, args.tol).level_iterations[-1]
            rows.append([mode, n, case.set.mean(), case.patch_count, *counts, finest,
                         time.perf_counter() - start])
            print(f"   {mode} {n}: done", flush=True)
    table(["mode", "n", "contact", "patches", *names, "mv.solve finest", "s"], rows,
          ["{}", "{}", "{:.4f}", "{}"] + ["{}"] * (len(names) + 1) + ["{:.1f}"])


if __name__ == "__main__":
    main()
