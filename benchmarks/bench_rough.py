"""Elastic rough contact at about 5 % contact fraction, non-periodic and periodic: mdrvisc
against `tamaas`, `contactmechanics` and `aspher` (ASPHER), at equal accuracy.

Surface: one Gaussian self-affine surface (Hurst exponent 0.8), generated here with numpy
from a fixed seed, the same continuous surface sampled at every grid size: the random
coefficients of the Fourier modes k = (kx, ky) (cycles per cell) with 0 < |k| <= 128 are
drawn in a fixed order whatever the grid, with power spectrum C(q) ~ q^(-2 (1 + H)) above the
roll-off |k| = 4 and flat below it; the heights are the sum of those modes at the nodes
(i dx, j dx) of an n x n grid over the cell of edge L = 1 m (periodic by construction, n >
256), scaled to an rms slope of 0.1 computed from the coefficients. Every code gets these
heights (the highest point touches first) and the same total force F = pbar L^2 on an
incompressible half-space with G = 1 Pa (E* = 4 Pa), frictionless. pbar is set once, so
that mdrvisc's periodic solution on the 512 x 512 grid has a contact fraction of 5 %
(secant steps at tol 1e-6; ``--pressure`` fixes it instead), and is the same for both
modes and every size; the table gives each row's contact fraction.

Modes and kernels (only codes with the same kernel solve the same discrete problem):

* free (non-periodic, the n x n map is a finite body's whole surface): Love's coefficients of
  uniformly loaded squares by zero-padded FFT convolution in mdrvisc (``mv.arrays.contact``),
  tamaas (``dcfft``), contactmechanics (``FreeFFTElasticHalfSpace``) and aspher backend
  "fft"; aspher's default backend "h2" approximates the same matrix by an H2/FMM operator.
* periodic (the map is one period of a doubly periodic cell): the spectral compliance
  2 / (E* |q|) at the cell's discrete wavevectors in all four codes (mdrvisc
  ``mv.arrays.contact(..., periodic=True)``, tamaas' Westergaard operator,
  contactmechanics' ``PeriodicFFTElasticHalfSpace``, aspher backend "periodic"); their mean
  modes differ, which moves the rigid-body approach and not the pressure.

The column "K diff" measures the kernel: each peer's operator applied to the reference
pressure against mdrvisc's (``mv.arrays.SurfaceOperator``), max |u - u_mv| / max |u_mv|
(periodic: means removed). Round-off there (~1e-15) means the same discrete problem.

Accuracy: the reference of each mode and size is mdrvisc's solution at tol 1e-12 (its own
discretisation: Love's squares for free, the spectral kernel for periodic). "dev max" is
max |p - p_ref| / max p_ref and "dev L1" sum |p - p_ref| / sum p_ref for every code, its
own answer at ``--tol`` against that reference; for a peer with the same kernel it is the
distance between the two codes' answers, for aspher "h2" it includes the H2 approximation
(K diff). Every code runs with the same relative tolerance ``--tol`` (1e-8) on its own
stopping criterion:

* mdrvisc (Polonsky-Keer, preconditioned): sum |p_k - p_(k-1)| / sum p < tol;
* tamaas ``PolonskyKeerRey``: its complementarity error < tol;
* contactmechanics: penetration and displacement change < tol (max Z - min Z), tensile
  pixel force < tol F / (0.05 n^2), relative change of the offset < tol;
* aspher: Frank-Wolfe certificate G / (P g_ref) and penetration / g_ref <= tol, g_ref =
  max Z - min Z.

The criteria measure different things, so equal tolerances need not give equal accuracy:
the deviation columns show the accuracy each code actually reached (rerun a code at a
tighter ``--tol`` to compare times at matched deviation).

Timings: wall clock, model/operator set-up from the height array + solve (mdrvisc:
``mv.arrays.contact`` end to end; "solve s" is the peers' solve call alone), best of
``--rounds`` rounds (default 3) of ``--repeats`` back-to-back runs (default 1), the rounds
interleaved: mdrvisc, then each peer in its subprocess, then again, so that every code's
runs spread over the same machine states; a run longer than ``--single-above`` (60 s) is not
repeated ("[1 run]"). mdrvisc runs its rayon pool on all cores, aspher OpenMP on all cores, tamaas and
contactmechanics are serial. Iterations: CG iterations (contactmechanics does two operator
applies per iteration; aspher's nested solves report the finest level, the notes give every
level). "peer / mv" is the row's wall time over mdrvisc's in the same mode and size.

Peers run in their own venv, through ``rough_worker.py`` (its interpreter:
``--peers-python PATH`` or $MDRVISC_PEERS_PYTHON), one subprocess per code, variant, mode
and size. Run: ``python benchmarks/bench_rough.py --peers-python PATH [--sizes 512 1024
2048] [--modes free periodic] [--tol 1e-8] [--rounds 3]``; ``--peers`` selects codes.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
from pathlib import Path

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, load, pressure_for_fraction, run_worker, table

HERE = Path(__file__).resolve().parent
EDGE, G = 1.0, 1.0
E_STAR = 4.0 * G
HURST, ROLLOFF, SHORT, RMS_SLOPE = 0.8, 4, 128, 0.1
REF_TOL = 1e-12
PEERS_PYTHON_ENV = "MDRVISC_PEERS_PYTHON"
# (code, variant) per mode; aspher's variants are described in rough_worker.py
PEER_RUNS = {"free": [("tamaas", ""), ("contactmechanics", ""), ("aspher", "fft"),
                      ("aspher", "h2"), ("aspher", "nested-fft"), ("aspher", "nested-h2")],
             "periodic": [("tamaas", ""), ("contactmechanics", ""), ("aspher", "periodic"),
                          ("aspher", "nested-periodic")]}
KERNEL = {("mdrvisc", "free"): "Love DC-FFT", ("mdrvisc", "periodic"): "spectral",
          ("tamaas", "free"): "Love DC-FFT", ("tamaas", "periodic"): "spectral",
          ("contactmechanics", "free"): "Love DC-FFT",
          ("contactmechanics", "periodic"): "spectral", "fft": "Love DC-FFT",
          "h2": "Love H2/FMM", "periodic": "spectral"}


def self_affine(n: int, seed: int) -> np.ndarray:
    """Heights (m, (n, n)) of the benchmark's surface at the nodes of an n x n grid over the
    cell: sum over the modes 0 < |k| <= SHORT of the upper half plane of
    amp(k) (a_k cos(q.x) + b_k sin(q.x)), q = 2 pi k / EDGE, a_k, b_k standard normal drawn
    in a fixed order from ``seed`` (the same surface at every n), amp ~ max(|k|, ROLLOFF)^-(1+H),
    scaled so that the rms slope over the cell is RMS_SLOPE exactly."""
    if n <= 2 * SHORT:
        raise SystemExit(f"--sizes: the surface has modes up to |k| = {SHORT}, so n must be "
                         f"> {2 * SHORT}, got {n}")
    rng = np.random.default_rng(seed)
    k = np.arange(-SHORT, SHORT + 1)
    ky, kx = np.meshgrid(k, k, indexing="ij")
    a = rng.standard_normal(kx.shape)
    b = rng.standard_normal(kx.shape)
    kk = np.hypot(kx, ky)
    keep = ((ky > 0) | ((ky == 0) & (kx > 0))) & (kk <= SHORT)
    amp = np.where(keep, np.maximum(kk, ROLLOFF) ** -(1.0 + HURST), 0.0)
    # rms slope of sum amp (a cos + b sin): sqrt(sum amp^2 |q|^2 (a^2 + b^2) / 2)
    q2 = (2.0 * np.pi / EDGE) ** 2 * kk**2
    slope = np.sqrt(0.5 * np.sum(amp**2 * q2 * (a**2 + b**2)))
    spectrum = np.zeros((n, n), dtype=complex)
    np.add.at(spectrum, (ky[keep] % n, kx[keep] % n),
              (RMS_SLOPE / slope) * amp[keep] * (a[keep] - 1j * b[keep]))
    return np.real(np.fft.ifft2(spectrum)) * (n * n)


def mv_solve(z: np.ndarray, mode: str, force: float, tol: float):
    """mdrvisc's solution on the whole grid (heights above the highest point, G = 1 Pa)."""
    n = z.shape[0]
    return mv.arrays.contact(z.max() - z, EDGE / n, G, force=force, tol=tol,
                             max_iter=100000, deflection=False, periodic=(mode == "periodic"))


def pressure(r) -> np.ndarray:
    return np.asarray(r.fields[0.0].pressure)


def calibrate(seed: int, fraction: float) -> tuple[float, list[str]]:
    """Mean pressure (Pa) at which mdrvisc's periodic 512 x 512 solution (tol 1e-6) has the
    contact fraction ``fraction``: secant steps on the contact fraction from the estimate
    fraction = 2 pbar / (E* rms slope)."""
    z = self_affine(512, seed)
    return pressure_for_fraction(lambda pbar: pressure(mv_solve(z, "periodic", pbar * EDGE**2, 1e-6)),
                                 fraction, fraction * E_STAR * RMS_SLOPE / 2.0, tries=6)


def deviation(p: np.ndarray, p_ref: np.ndarray) -> tuple[float, float]:
    """(max |p - p_ref| / max p_ref, sum |p - p_ref| / sum p_ref)."""
    d = np.abs(p - p_ref)
    return float(d.max() / p_ref.max()), float(d.sum() / p_ref.sum())


def kernel_diff(u: np.ndarray, p_ref: np.ndarray, mode: str) -> float:
    """max |u - u_mv| / max |u_mv|, u_mv = mdrvisc's deflection under p_ref (periodic: both
    with their means removed)."""
    n = p_ref.shape[0]
    u_mv = mv.arrays.SurfaceOperator((n, n), EDGE / n, periodic=(mode == "periodic")).apply(p_ref)
    u_mv = u_mv / G
    if mode == "periodic":
        u, u_mv = u - u.mean(), u_mv - u_mv.mean()
    return float(np.abs(u - u_mv).max() / np.abs(u_mv).max())


def run_peer(code, variant, mode, n, heights, force, tol, repeats, single_above, python,
             folder, apply, timeout):
    cmd = [python, str(HERE / "rough_worker.py"), "--code", code, "--mode", mode,
           "--heights", heights, "--edge", repr(EDGE), "--e-star", repr(E_STAR), "--force",
           repr(force), "--tol", repr(tol), "--repeats", str(repeats), "--single-above",
           repr(single_above), "--out", folder]
    if variant:
        cmd += ["--variant", variant]
    if apply:
        cmd += ["--apply", apply]
    res = run_worker(cmd, timeout)
    if "failed" in res:
        return res
    res["pressure"] = np.load(res.pop("pressure_file"))
    if "deflection_file" in res:
        res["deflection"] = np.load(res.pop("deflection_file"))
    return res


def solve_case(args, n, mode, z, heights, force, p_ref, ref_file, folder, last_wall, rows,
               notes) -> None:
    """Times mdrvisc and every selected peer on one mode and size, ``--rounds`` times
    alternately (mdrvisc, then each peer, then again), keeping each code's best wall time and
    its first answer; appends the table rows and the notes."""
    runs = [("mdrvisc", "")] + [
        (code, variant) for code, variant in PEER_RUNS[mode]
        if code in args.peers and not (code == "aspher" and args.aspher_variants is not None
                                       and variant not in args.aspher_variants)]
    best: dict[tuple, dict] = {}
    applied: set[tuple] = set()
    for round_ in range(args.rounds):
        for code, variant in runs:
            name = code + (f" {variant}" if variant else "")
            kernel = KERNEL.get(variant.removeprefix("nested-")) or KERNEL[(code, mode)]
            prev = best.get((code, variant))
            if prev is not None and ("failed" in prev or prev["wall"] > args.single_above):
                continue  # a failed or long run is not repeated
            if code == "mdrvisc":
                wall, r = best_of(lambda: mv_solve(z, mode, force, args.tol), args.repeats)
                res = dict(wall=wall, walls=[wall], pressure=pressure(r),
                           iterations=int(r.iterations), solver=r.solver)
            else:
                last = last_wall.get((name, mode))
                if round_ == 0 and last is not None:
                    predicted = last[1] * (n / last[0]) ** 2 * 1.5
                    if predicted > args.peer_limit:
                        best[(code, variant)] = dict(failed=(
                            f"skipped (predicted {predicted:.0f} s > --peer-limit "
                            f"{args.peer_limit:.0f} s)"))
                        continue
                res = run_peer(code, variant, mode, n, heights, force, args.tol, args.repeats,
                               args.single_above, args.peers_python, folder,
                               ref_file if (code, kernel) not in applied else None,
                               timeout=max(4 * args.peer_limit, 600))
                if "failed" in res:
                    best.setdefault((code, variant), res)
                    continue
                last_wall[(name, mode)] = (n, res["walls"][0])
                if "deflection" in res:
                    applied.add((code, kernel))
            print(f"   n = {n} {mode} round {round_ + 1}: {name} {res['wall']:.3f} s, "
                  f"{res['iterations']} iterations", file=sys.stderr)
            if prev is None or "failed" in prev:
                best[(code, variant)] = res
            else:
                prev["wall"] = min(prev["wall"], res["wall"])
                if res.get("solve") is not None:
                    prev["solve"] = min(prev["solve"], res["solve"])
                prev["walls"] = prev["walls"] + res["walls"]
    wall_mv = best[("mdrvisc", "")]["wall"]
    for code, variant in runs:
        res = best.get((code, variant))
        if res is None:
            continue
        name = code + (f" {variant}" if variant else "")
        kernel = KERNEL.get(variant.removeprefix("nested-")) or KERNEL[(code, mode)]
        if "failed" in res:
            rows.append([n, mode, name, kernel] + [None] * 8)
            notes.append(f"{name} at n = {n}, {mode}: {res['failed']}")
            continue
        p = res["pressure"]
        dmax, dl1 = deviation(p, p_ref)
        kdiff = kernel_diff(res["deflection"], p_ref, mode) if "deflection" in res else None
        timed = len(res["walls"]) if code != "mdrvisc" else None
        label = (f"mdrvisc ({res['solver']})" if code == "mdrvisc" else
                 name + (f" [{timed} run]" if timed is not None and timed < args.rounds
                         * args.repeats else ""))
        rows.append([n, mode, label, kernel, res["wall"], res.get("solve"), res["iterations"],
                     np.count_nonzero(p > 0) / p.size, dmax, dl1, kdiff,
                     None if code == "mdrvisc" else res["wall"] / wall_mv])
        if code == "mdrvisc":
            continue
        extra = f"; levels {', '.join(res['stages'])}" if res.get("stages") else ""
        applies = f", {res['applies']} operator applies" if res.get("applies") else ""
        notes.append(f"{name} {res.get('version', '')} at n = {n}, {mode}: "
                     f"{'converged' if res['converged'] else 'NOT converged'} "
                     f"({res['criterion']}{applies}){extra}; {res['threads']}")


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sizes", type=int, nargs="+", default=[512, 1024, 2048])
    ap.add_argument("--modes", nargs="+", default=["free", "periodic"],
                    choices=["free", "periodic"])
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--repeats", type=int, default=1,
                    help="timed runs per code and round, back to back (best kept)")
    ap.add_argument("--rounds", type=int, default=3,
                    help="rounds of all codes one after the other (best kept): interleaving "
                         "spreads every code's runs over the same machine states")
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="a run longer than this (s) is not repeated")
    ap.add_argument("--seed", type=int, default=20260118,
                    help="seed of the surface (held out: not used elsewhere in the project)")
    ap.add_argument("--fraction", type=float, default=0.05, help="target contact fraction")
    ap.add_argument("--pressure", type=float, default=None,
                    help="mean pressure pbar (Pa) instead of the calibrated one")
    ap.add_argument("--peers", nargs="*", default=["tamaas", "contactmechanics", "aspher"],
                    choices=["tamaas", "contactmechanics", "aspher"])
    ap.add_argument("--aspher-variants", nargs="*", default=None,
                    help="aspher variants to run (default all: fft h2 nested-fft nested-h2 "
                         "periodic nested-periodic)")
    ap.add_argument("--peers-python", default=os.environ.get(PEERS_PYTHON_ENV) or None,
                    metavar="PATH",
                    help="Python interpreter of the venv holding the peers "
                         f"(default: ${PEERS_PYTHON_ENV}; set-up in benchmarks/README.md)")
    ap.add_argument("--peer-limit", type=float, default=300.0,
                    help="skip a peer run whose predicted wall time (from the last size) "
                         "exceeds this (s)")
    args = ap.parse_args(argv)
    if args.peers and not args.peers_python:
        ap.error(f"no interpreter for the peers: pass --peers-python PATH or set "
                 f"{PEERS_PYTHON_ENV} (benchmarks/README.md, \"Peer codes\"), or --peers "
                 f"with no codes for mdrvisc alone")
    if args.peers and shutil.which(args.peers_python) is None:
        ap.error(f"the peers' interpreter {args.peers_python!r} is not an executable")

    if args.pressure is None:
        pbar, log = calibrate(args.seed, args.fraction)
    else:
        pbar, log = args.pressure, ["given by --pressure"]
    force = pbar * EDGE**2
    header(f"Elastic rough contact (self-affine, H = {HURST}, |k| {ROLLOFF}..{SHORT}, rms slope "
           f"{RMS_SLOPE}, seed {args.seed}), E* = {E_STAR} Pa, L = {EDGE} m, pbar = {pbar:.6g} "
           f"Pa, tol {args.tol:g}: mdrvisc vs peers")
    print(f"   pbar for a contact fraction of {args.fraction:g} (mdrvisc periodic 512^2, tol "
          f"1e-6): {'; '.join(log)}")
    if args.peers:
        print(f"   peers run by {args.peers_python}")
    rows, notes = [], []
    last_wall: dict[tuple, tuple[int, float]] = {}  # (name, mode) -> (n, first wall)
    with tempfile.TemporaryDirectory() as folder:
        for n in args.sizes:
            z = self_affine(n, args.seed)
            heights = os.path.join(folder, f"heights_{n}.npy")
            np.save(heights, z)
            for mode in args.modes:
                ref = mv_solve(z, mode, force, REF_TOL)
                p_ref = pressure(ref)
                ref_file = os.path.join(folder, f"ref_{mode}_{n}.npy")
                np.save(ref_file, p_ref)
                notes.append(f"n = {n}, {mode}: reference = mdrvisc at tol {REF_TOL:g} "
                             f"({int(ref.iterations)} iterations, residual "
                             f"{float(ref.residual):.1e}, contact fraction "
                             f"{np.count_nonzero(p_ref > 0) / p_ref.size:.4f})")
                solve_case(args, n, mode, z, heights, force, p_ref, ref_file, folder,
                           last_wall, rows, notes)
    table(["n", "mode", "code", "kernel", "wall s", "solve s", "iters", "fraction", "dev max",
           "dev L1", "K diff", "peer / mv"], rows,
          ["{}", "{}", "{}", "{}", "{:.3f}", "{:.3f}", "{}", "{:.4f}", "{:.1e}", "{:.1e}",
           "{:.1e}", "{:.1f}"])
    for note in notes:
        print("   " + note)
    print(f"   ({load()})")


if __name__ == "__main__":
    main()
