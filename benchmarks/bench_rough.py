"""Elastic rough contact, non-periodic and periodic, on held-out self-affine surfaces at
several Hurst exponents and contact fractions: mdrvisc through the users' path (``mv.Scene``
+ ``mv.solve``) against `tamaas`, `contactmechanics` and `aspher` (ASPHER), at equal accuracy.

Surfaces: Gaussian self-affine surfaces generated here with numpy from one fixed seed that
nothing else in the project uses (``--seed``; held out: no solver was tuned on them). For a
Hurst exponent H the random coefficients of the Fourier modes k = (kx, ky) (cycles per cell)
with 0 < |k| <= ``--short`` (128) are drawn in a fixed order whatever the grid, with power
spectrum C(q) ~ q^(-2 (1 + H)) above the roll-off |k| = 4 and flat below it; the heights are
the sum of those modes at the nodes (i dx, j dx) of an n x n grid over the cell of edge L =
1 m (periodic by construction, n > 2 ``--short``), scaled to an rms slope of 0.1 computed
from the coefficients. So every size samples the same continuous surface, and the surfaces
of different H share their random phases. Every code gets these heights (the highest point
touches first) and the same total force F = pbar L^2 on an incompressible half-space with
G = 1 Pa (E* = 4 Pa), frictionless.

Cases: every Hurst exponent of ``--hurst`` (0.3 0.5 0.8) at every contact fraction of
``--fractions`` (0.02 0.05 0.2) on the grids up to ``--grid-up-to`` (512); on larger grids
the case ``--main`` (H 0.8 at 0.05) alone. Loads: for each case pbar is set once, outside
every timed region, so that mdrvisc's periodic solution on the ``--calibrate-size`` grid
(512) has the case's contact fraction (secant steps on mdrvisc's tol-1e-6 solutions), and is
the same for both modes, every size and every code; the tables give each row's fraction.

Modes and kernels (only codes with the same kernel solve the same discrete problem):

* free (non-periodic, the n x n map is a finite body's whole surface): Love's coefficients of
  uniformly loaded squares by zero-padded FFT convolution in mdrvisc (``mv.HeightMap(z, dx)``),
  tamaas (``dcfft``), contactmechanics (``FreeFFTElasticHalfSpace``) and aspher backend
  "fft"; aspher's backend "h2" approximates the same matrix by an H2/FMM operator.
* periodic (the map is one period of a doubly periodic cell): the spectral compliance
  2 / (E* |q|) at the cell's discrete wavevectors in all four codes (mdrvisc
  ``mv.HeightMap(z, dx, periodic=True)``, tamaas' Westergaard operator, contactmechanics'
  ``PeriodicFFTElasticHalfSpace``, aspher backend "periodic"); their mean modes differ,
  which moves the rigid-body approach and not the pressure.

The column "K diff" measures the kernel: each peer's operator applied to the reference
pressure against mdrvisc's (``mv.arrays.SurfaceOperator``), max |u - u_mv| / max |u_mv|
(periodic: means removed). Round-off there (~1e-15) means the same discrete problem.

Accuracy: the reference of each case, mode and size is mdrvisc's solution at tol 1e-12
(``--ref-tol``; its own discretisation: Love's squares for free, the spectral kernel for
periodic). "dev max" is max |p - p_ref| / max p_ref and "dev L1" sum |p - p_ref| / sum p_ref
for every code, its own answer at ``--tol`` against that reference; for a peer with the same
kernel it is the distance between the two codes' answers, for aspher "h2" it includes the
H2 approximation (K diff). Every code runs with the same relative tolerance ``--tol`` (1e-8)
on its own stopping criterion:

* mdrvisc (Polonsky-Keer, preconditioned): sum |p_k - p_(k-1)| / sum p < tol;
* tamaas ``PolonskyKeerRey``: its complementarity error < tol;
* contactmechanics: penetration and displacement change < tol (max Z - min Z), tensile
  pixel force < tol F / (fraction n^2), relative change of the offset < tol;
* aspher: Frank-Wolfe certificate G / (P g_ref) and penetration / g_ref <= tol, g_ref =
  max Z - min Z.

The criteria measure different things, so equal tolerances need not give equal accuracy:
the deviation columns show the accuracy each code actually reached.

Timings: wall clock. mdrvisc: ``mv.Scene(indenter=mv.HeightMap(...), medium=mv.Elastic(G),
force=F, outputs=("pressure",))`` + ``mv.solve(scene, "bem", tol=...)`` end to end, the
scene's build (the heights' copy into the core) included. Peers: model/operator set-up from
the height array + solve ("solve s" is their solve call alone). Best of ``--rounds`` rounds
(default 3) of ``--repeats`` back-to-back runs (default 1), the rounds interleaved: mdrvisc,
then each peer in its subprocess, then again, so that every code's runs spread over the same
machine states; a run longer than ``--single-above`` (60 s) is not repeated ("[1 run]").
mdrvisc runs its rayon pool on all cores, aspher OpenMP on all cores, tamaas and
contactmechanics are serial. Iterations: the finest level's for mdrvisc
(``Result.level_iterations``) and aspher's nested solves, the notes giving every level; CG
iterations of the other peers (contactmechanics does two operator applies per iteration).
"t / t_mv" is the row's wall time over mdrvisc's in the same case, mode and size.

Limits: a peer run is skipped, with the reason printed, when its time predicted from its
last size (wall x (n / n_last)^2 x 1.5) exceeds ``--peer-limit`` (300 s; ``--aspher-limit``,
3600 s, for aspher) or its peak memory predicted likewise (resident peak x (n / n_last)^2
x 1.1, measured per worker process) exceeds ``--memory-limit`` (GB; default 3/4 of the
memory available at the start). A size that mdrvisc's installed build refuses (a grid above
its height-map limit, or a solve whose estimated peak exceeds the memory it may take) is
skipped with mdrvisc's message.

Summary: one row per size, mode and case with mdrvisc's time, aspher's best variant (the
fastest converged one that ran) and the ratios t / t_mv of aspher's best, tamaas and
contactmechanics; then, per size and mode, the smallest of each ratio over the cases.

Peers run in their own venv, through ``rough_worker.py`` (its interpreter:
``--peers-python PATH`` or $MDRVISC_PEERS_PYTHON), one subprocess per code, variant, case,
mode and size. Run: ``python benchmarks/bench_rough.py --peers-python PATH`` (the whole
protocol, hours on 2 cores), ``--quick`` (256^2 and 512^2, two Hurst exponents at two
fractions, one round, aspher's nested variants: minutes), ``--peers`` (none for mdrvisc
alone), ``--sizes``, ``--modes``, ``--hurst``, ``--fractions``, ``--grid-up-to``,
``--main``, ``--aspher-variants``, ``--rounds``.
"""

from __future__ import annotations

import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np

import mdrvisc as mv
from _bench import header, pressure_for_fraction, table

HERE = Path(__file__).resolve().parent
EDGE, G = 1.0, 1.0
E_STAR = 4.0 * G
ROLLOFF, RMS_SLOPE = 4, 0.1
PEERS_PYTHON_ENV = "MDRVISC_PEERS_PYTHON"
# (code, variant) per mode; aspher's variants are described in rough_worker.py
PEER_RUNS = {"free": [("tamaas", ""), ("contactmechanics", ""), ("aspher", "fft"),
                      ("aspher", "h2"), ("aspher", "nested-fft"), ("aspher", "nested-h2")],
             "periodic": [("tamaas", ""), ("contactmechanics", ""), ("aspher", "periodic"),
                          ("aspher", "nested-periodic")]}
DEFAULT_ASPHER = ["fft", "nested-fft", "periodic", "nested-periodic"]
KERNEL = {("mdrvisc", "free"): "Love DC-FFT", ("mdrvisc", "periodic"): "spectral",
          ("tamaas", "free"): "Love DC-FFT", ("tamaas", "periodic"): "spectral",
          ("contactmechanics", "free"): "Love DC-FFT",
          ("contactmechanics", "periodic"): "spectral", "fft": "Love DC-FFT",
          "h2": "Love H2/FMM", "periodic": "spectral"}
# the whole protocol, and --quick; an option given on the command line wins
DEFAULTS = dict(sizes=[512, 1024, 2048, 4096, 8192], hurst=[0.3, 0.5, 0.8],
                fractions=[0.02, 0.05, 0.2], grid_up_to=512, main=[0.8, 0.05], rounds=3,
                short=128, aspher_variants=DEFAULT_ASPHER)
QUICK = dict(sizes=[256, 512], hurst=[0.3, 0.8], fractions=[0.02, 0.2], grid_up_to=512,
             main=[0.8, 0.2], rounds=1, short=64, aspher_variants=["nested-fft", "nested-periodic"])


def self_affine(n: int, seed: int, hurst: float, short: int) -> np.ndarray:
    """Heights (m, (n, n)) of the benchmark's surface of Hurst exponent ``hurst`` at the nodes
    of an n x n grid over the cell: sum over the modes 0 < |k| <= ``short`` of the upper half
    plane of amp(k) (a_k cos(q.x) + b_k sin(q.x)), q = 2 pi k / EDGE, a_k, b_k standard normal
    drawn in a fixed order from ``seed`` (the same surface at every n),
    amp ~ max(|k|, ROLLOFF)^-(1+H), scaled so that the rms slope over the cell is RMS_SLOPE
    exactly."""
    if n <= 2 * short:
        raise SystemExit(f"--sizes: the surface has modes up to |k| = {short} (--short), so n "
                         f"must be > {2 * short}, got {n}")
    rng = np.random.default_rng(seed)
    k = np.arange(-short, short + 1)
    ky, kx = np.meshgrid(k, k, indexing="ij")
    a = rng.standard_normal(kx.shape)
    b = rng.standard_normal(kx.shape)
    kk = np.hypot(kx, ky)
    keep = ((ky > 0) | ((ky == 0) & (kx > 0))) & (kk <= short)
    amp = np.where(keep, np.maximum(kk, ROLLOFF) ** -(1.0 + hurst), 0.0)
    # rms slope of sum amp (a cos + b sin): sqrt(sum amp^2 |q|^2 (a^2 + b^2) / 2)
    q2 = (2.0 * np.pi / EDGE) ** 2 * kk**2
    slope = np.sqrt(0.5 * np.sum(amp**2 * q2 * (a**2 + b**2)))
    spectrum = np.zeros((n, n), dtype=complex)
    np.add.at(spectrum, (ky[keep] % n, kx[keep] % n),
              (RMS_SLOPE / slope) * amp[keep] * (a[keep] - 1j * b[keep]))
    return np.real(np.fft.ifft2(spectrum)) * (n * n)


def mv_solve(z: np.ndarray, mode: str, force: float, tol: float):
    """mdrvisc's answer through the users' path: the scene (a height map on an elastic
    half-space, G = 1 Pa, under ``force``) built and solved; returns the Result."""
    n = z.shape[0]
    scene = mv.Scene(indenter=mv.HeightMap(z, EDGE / n, periodic=(mode == "periodic")),
                     medium=mv.Elastic(G=G), force=force, outputs=("pressure",))
    with warnings.catch_warnings():
        # rough contact patches span few elements: expected here (the codes are compared
        # on the same discrete problem, not against the continuous surface)
        warnings.simplefilter("ignore", mv.ResolutionWarning)
        return mv.solve(scene, "bem", tol=tol, max_iter=100000)


def pressure(r) -> np.ndarray:
    return np.asarray(r.fields[0.0].pressure)


def estimated_pressure(fraction: float) -> float:
    """Mean pressure (Pa) at which a self-affine surface of the benchmark's rms slope is
    estimated to have the contact fraction ``fraction``: pbar = fraction E* (rms slope) / 2."""
    return fraction * E_STAR * RMS_SLOPE / 2.0


def calibrate(seed: int, hurst: float, fraction: float, size: int,
              short: int) -> tuple[float, list[str]]:
    """Mean pressure (Pa) at which mdrvisc's periodic ``size``^2 solution (tol 1e-6) has the
    contact fraction ``fraction``: secant steps on the contact fraction from the estimate
    fraction = 2 pbar / (E* rms slope)."""
    z = self_affine(size, seed, hurst, short)
    return pressure_for_fraction(
        lambda pbar: pressure(mv_solve(z, "periodic", pbar * EDGE**2, 1e-6)),
        fraction, estimated_pressure(fraction), tries=8)


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


def run_measured(cmd: list[str], timeout: float) -> dict:
    """Runs a peer's worker ``cmd`` outside this venv (no PYTHONPATH, no VIRTUAL_ENV); returns
    the JSON of its last output line with ``peak_bytes`` (the process's resident peak), or
    ``{"failed": why}`` when it timed out or exited with an error."""
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    with tempfile.TemporaryFile("w+") as out, tempfile.TemporaryFile("w+") as err:
        proc = subprocess.Popen(cmd, stdout=out, stderr=err, text=True, env=env)
        start = time.perf_counter()
        while True:
            pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
            if pid:
                break
            if time.perf_counter() - start > timeout:
                proc.kill()
                _, status, _ = os.wait4(proc.pid, 0)
                proc.returncode = os.waitstatus_to_exitcode(status)
                return {"failed": f"timed out after {timeout:.0f} s"}
            time.sleep(0.05)
        proc.returncode = os.waitstatus_to_exitcode(status)
        out.seek(0)
        err.seek(0)
        stdout, stderr = out.read(), err.read()
    if proc.returncode != 0:
        tail = (stderr or stdout).strip().splitlines()[-3:]
        return {"failed": f"rc {proc.returncode}: " + " | ".join(tail)}
    res = json.loads(stdout.strip().splitlines()[-1])
    res["peak_bytes"] = usage.ru_maxrss * 1024.0  # KiB on Linux
    return res


def run_peer(args, code, variant, mode, n, heights, force, fraction, folder, apply):
    cmd = [args.peers_python, str(HERE / "rough_worker.py"), "--code", code, "--mode", mode,
           "--heights", heights, "--edge", repr(EDGE), "--e-star", repr(E_STAR), "--force",
           repr(force), "--fraction", repr(fraction), "--tol", repr(args.tol), "--repeats",
           str(args.repeats), "--single-above", repr(args.single_above), "--out", folder]
    if variant:
        cmd += ["--variant", variant]
    if apply:
        cmd += ["--apply", apply]
    limit = args.aspher_limit if code == "aspher" else args.peer_limit
    return run_measured(cmd, timeout=max(4 * limit, 600))


def predicted_skip(args, code, last, n) -> str | None:
    """Why a peer's run at size n is skipped (its time or memory predicted from its last
    size ``last`` = (n, wall, peak bytes) beyond the limits), or None."""
    if last is None:
        return None
    scale = (n / last[0]) ** 2
    limit = args.aspher_limit if code == "aspher" else args.peer_limit
    flag = "--aspher-limit" if code == "aspher" else "--peer-limit"
    if last[1] * scale * 1.5 > limit:
        return f"skipped: predicted {last[1] * scale * 1.5:.0f} s > {flag} {limit:.0f} s"
    if last[2] * scale * 1.1 > args.memory_limit * 1e9:
        return (f"skipped: predicted peak {last[2] * scale * 1.1 / 1e9:.1f} GB > "
                f"--memory-limit {args.memory_limit:.1f} GB")
    return None


def solve_case(args, case, n, mode, z, heights, force, p_ref, ref_file, folder, last_run,
               rows, notes) -> dict:
    """Times mdrvisc and every selected peer on one case, mode and size, ``--rounds`` times
    alternately (mdrvisc, then each peer, then again), keeping each code's best wall time and
    its first answer's deviations; appends the table rows and the notes and returns
    {name: (wall, converged)}."""
    hurst, fraction = case
    runs = [("mdrvisc", "")] + [
        (code, variant) for code, variant in PEER_RUNS[mode]
        if code in args.peers and not (code == "aspher" and variant not in args.aspher_variants)]
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
                walls = []
                for _ in range(args.repeats):
                    start = time.perf_counter()
                    r = mv_solve(z, mode, force, args.tol)
                    walls.append(time.perf_counter() - start)
                res = dict(wall=min(walls), walls=walls, iterations=int(r.level_iterations[-1]),
                           levels=r.level_iterations, converged=True)
                if prev is None:
                    p = pressure(r)
                    res.update(dev=deviation(p, p_ref), fraction=np.count_nonzero(p > 0) / p.size,
                               solver=r.solver)
                del r
            else:
                if round_ == 0:
                    why = predicted_skip(args, code, last_run.get((name, mode, case)), n)
                    if why:
                        best[(code, variant)] = dict(failed=why)
                        continue
                res = run_peer(args, code, variant, mode, n, heights, force, fraction, folder,
                               ref_file if (code, kernel) not in applied else None)
                if "failed" in res:
                    best.setdefault((code, variant), res)
                    continue
                last_run[(name, mode, case)] = (n, res["walls"][0], res["peak_bytes"])
                p = np.load(res.pop("pressure_file"))
                if prev is None:
                    res.update(dev=deviation(p, p_ref),
                               fraction=np.count_nonzero(p > 0) / p.size)
                    if "deflection_file" in res:
                        res["kdiff"] = kernel_diff(np.load(res.pop("deflection_file")), p_ref,
                                                   mode)
                        applied.add((code, kernel))
                del p
            print(f"   n = {n} {mode} H {hurst:g} fraction {fraction:g} round {round_ + 1}: "
                  f"{name} {res['wall']:.3f} s, {res['iterations']} iterations", file=sys.stderr)
            if prev is None or "failed" in prev:
                best[(code, variant)] = res
            else:
                prev["wall"] = min(prev["wall"], res["wall"])
                if res.get("solve") is not None:
                    prev["solve"] = min(prev["solve"], res["solve"])
                prev["walls"] = prev["walls"] + res["walls"]
    wall_mv = best[("mdrvisc", "")]["wall"]
    out = {}
    for code, variant in runs:
        res = best.get((code, variant))
        if res is None:
            continue
        name = code + (f" {variant}" if variant else "")
        kernel = KERNEL.get(variant.removeprefix("nested-")) or KERNEL[(code, mode)]
        if "failed" in res:
            rows.append([hurst, fraction, f"{name}: {res['failed']}", kernel] + [None] * 9)
            notes.append(f"{name} at n = {n}, {mode}, H {hurst:g}, fraction {fraction:g}: "
                         f"{res['failed']}")
            continue
        out[name] = (res["wall"], res["converged"])
        timed = len(res["walls"])
        label = (f"mdrvisc ({res['solver']})" if code == "mdrvisc" else
                 name + (f" [{timed} run]" if timed < args.rounds * args.repeats else ""))
        rows.append([hurst, fraction, label, kernel, res["wall"], res.get("solve"),
                     res["iterations"], res["fraction"], *res["dev"], res.get("kdiff"),
                     None if code == "mdrvisc" else res["peak_bytes"] / 1e9,
                     None if code == "mdrvisc" else res["wall"] / wall_mv])
        if code == "mdrvisc":
            notes.append(f"mdrvisc at n = {n}, {mode}, H {hurst:g}, fraction {fraction:g}: "
                         f"levels {', '.join(map(str, res['levels']))} "
                         f"({sum(res['levels'])} iterations in all)")
            continue
        extra = f"; levels {', '.join(res['stages'])}" if res.get("stages") else ""
        applies = f", {res['applies']} operator applies" if res.get("applies") else ""
        notes.append(f"{name} {res.get('version', '')} at n = {n}, {mode}, H {hurst:g}, "
                     f"fraction {fraction:g}: "
                     f"{'converged' if res['converged'] else 'NOT converged'} "
                     f"({res['criterion']}{applies}){extra}; {res['threads']}")
    return out


def summary_rows(n, mode, case, walls) -> list:
    """The summary's row of one case: mdrvisc's time, aspher's best converged variant, and
    the ratios t / t_mv."""
    wall_mv = walls["mdrvisc"][0]
    aspher = {k: w for k, (w, ok) in walls.items() if k.startswith("aspher") and ok}
    best = min(aspher, key=aspher.get) if aspher else None

    def ratio(name):
        return walls[name][0] / wall_mv if name in walls else None

    return [n, mode, case[0], case[1], wall_mv, best.removeprefix("aspher ") if best else None,
            aspher[best] if best else None, aspher[best] / wall_mv if best else None,
            ratio("tamaas"), ratio("contactmechanics")]


def parse(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true",
                    help="a short run: " + ", ".join(f"--{k.replace('_', '-')} {v}"
                                                     for k, v in QUICK.items()))
    ap.add_argument("--sizes", type=int, nargs="+", default=None,
                    help=f"grid sides n (default {DEFAULTS['sizes']})")
    ap.add_argument("--modes", nargs="+", default=["free", "periodic"],
                    choices=["free", "periodic"])
    ap.add_argument("--hurst", type=float, nargs="+", default=None,
                    help=f"Hurst exponents of the cases (default {DEFAULTS['hurst']})")
    ap.add_argument("--fractions", type=float, nargs="+", default=None,
                    help=f"contact fractions of the cases (default {DEFAULTS['fractions']})")
    ap.add_argument("--grid-up-to", type=int, default=None,
                    help="largest n that runs every case (Hurst x fraction); larger grids run "
                         f"--main alone (default {DEFAULTS['grid_up_to']})")
    ap.add_argument("--main", type=float, nargs=2, default=None, metavar=("HURST", "FRACTION"),
                    help=f"the case of the larger grids (default {DEFAULTS['main']})")
    ap.add_argument("--short", type=int, default=None,
                    help=f"largest mode |k| of the surfaces (cycles per cell; n > 2 short; "
                         f"default {DEFAULTS['short']})")
    ap.add_argument("--calibrate-size", type=int, default=512,
                    help="grid of the load calibration (or the smallest of --sizes)")
    ap.add_argument("--pressure", type=float, default=None,
                    help="mean pressure pbar (Pa) of every case instead of the calibrated ones")
    ap.add_argument("--tol", type=float, default=1e-8)
    ap.add_argument("--ref-tol", type=float, default=1e-12,
                    help="mdrvisc's tolerance for the reference solutions")
    ap.add_argument("--repeats", type=int, default=1,
                    help="timed runs per code and round, back to back (best kept)")
    ap.add_argument("--rounds", type=int, default=None,
                    help="rounds of all codes one after the other (best kept): interleaving "
                         f"spreads every code's runs over the same machine states (default "
                         f"{DEFAULTS['rounds']})")
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="a run longer than this (s) is not repeated")
    ap.add_argument("--seed", type=int, default=20261127,
                    help="seed of the surfaces (held out: not used elsewhere in the project)")
    ap.add_argument("--peers", nargs="*", default=["tamaas", "contactmechanics", "aspher"],
                    choices=["tamaas", "contactmechanics", "aspher"])
    ap.add_argument("--aspher-variants", nargs="*", default=None,
                    choices=sorted({v for runs in PEER_RUNS.values() for c, v in runs if v}),
                    help=f"aspher variants to run (default {' '.join(DEFAULT_ASPHER)}; the "
                         "H2 variants are slower and less accurate)")
    ap.add_argument("--peers-python", default=os.environ.get(PEERS_PYTHON_ENV) or None,
                    metavar="PATH",
                    help="Python interpreter of the venv holding the peers "
                         f"(default: ${PEERS_PYTHON_ENV}; set-up in benchmarks/README.md)")
    ap.add_argument("--peer-limit", type=float, default=300.0,
                    help="skip a tamaas or contactmechanics run whose predicted wall time "
                         "(from its last size) exceeds this (s)")
    ap.add_argument("--aspher-limit", type=float, default=3600.0,
                    help="skip an aspher run whose predicted wall time exceeds this (s)")
    ap.add_argument("--memory-limit", type=float, default=None,
                    help="skip a peer run whose predicted peak memory exceeds this (GB; "
                         "default 3/4 of the memory available at the start)")
    args = ap.parse_args(argv)
    preset = QUICK if args.quick else DEFAULTS
    for key, value in preset.items():
        if getattr(args, key) is None:
            setattr(args, key, value)
    if args.peers and not args.peers_python:
        ap.error(f"no interpreter for the peers: pass --peers-python PATH or set "
                 f"{PEERS_PYTHON_ENV} (benchmarks/README.md, \"Peer codes\"), or --peers "
                 f"with no codes for mdrvisc alone")
    if args.peers and shutil.which(args.peers_python) is None:
        ap.error(f"the peers' interpreter {args.peers_python!r} is not an executable")
    for n in args.sizes:
        if n <= 2 * args.short:
            ap.error(f"--sizes: n must be > 2 --short = {2 * args.short}, got {n}")
    args.calibrate_size = min(args.calibrate_size, min(args.sizes))
    if args.memory_limit is None:
        args.memory_limit = 0.75 * available_memory() / 1e9
    return args


def available_memory() -> float:
    """MemAvailable of /proc/meminfo (bytes), or 16 GB where unreadable."""
    try:
        with open("/proc/meminfo") as f:
            for line in f:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except OSError:
        pass
    return 16e9


def main(argv=None) -> None:
    args = parse(argv)
    cases = [(h, f) for h in args.hurst for f in args.fractions]
    main_case = tuple(args.main)
    loads, log = {}, []
    needed = ((cases if min(args.sizes) <= args.grid_up_to else [])
              + ([main_case] if max(args.sizes) > args.grid_up_to else []))
    for case in dict.fromkeys(needed):
        if args.pressure is None:
            pbar, steps = calibrate(args.seed, *case, args.calibrate_size, args.short)
        else:
            pbar, steps = args.pressure, ["given by --pressure"]
        loads[case] = pbar * EDGE**2
        log.append(f"H {case[0]:g}, fraction {case[1]:g}: pbar {pbar:.6g} Pa ({'; '.join(steps)})")
    header(f"Elastic rough contact (self-affine, |k| {ROLLOFF}..{args.short}, rms slope "
           f"{RMS_SLOPE}, seed {args.seed}), E* = {E_STAR} Pa, L = {EDGE} m, tol {args.tol:g}: "
           f"mdrvisc (mv.Scene + mv.solve) vs peers")
    print(f"   loads (mdrvisc periodic {args.calibrate_size}^2, tol 1e-6; the same for every "
          f"code, mode and size):")
    for line in log:
        print("     " + line)
    if args.peers:
        print(f"   peers run by {args.peers_python}; memory limit {args.memory_limit:.1f} GB")
    sys.stdout.flush()
    summary = []
    last_run: dict[tuple, tuple] = {}  # (name, mode, case) -> (n, first wall, peak bytes)
    with tempfile.TemporaryDirectory() as folder:
        for n in args.sizes:
            size_cases = cases if n <= args.grid_up_to else [main_case]
            for mode in args.modes:
                rows, notes = [], []
                for case in size_cases:
                    z = self_affine(n, args.seed, case[0], args.short)
                    heights = os.path.join(folder, "heights.npy")
                    np.save(heights, z)
                    try:
                        ref = mv_solve(z, mode, loads[case], args.ref_tol)
                    except mv.errors.MdrviscError as e:
                        notes.append(f"H {case[0]:g}, fraction {case[1]:g}: skipped (peers "
                                     f"not run): the installed mdrvisc refused the scene: {e}")
                        continue
                    p_ref = pressure(ref)
                    ref_file = os.path.join(folder, "ref.npy")
                    np.save(ref_file, p_ref)
                    notes.append(f"H {case[0]:g}, fraction {case[1]:g}: reference = mdrvisc "
                                 f"at tol {args.ref_tol:g} ({int(ref.iterations)} iterations, "
                                 f"residual {float(ref.residual):.1e}, contact fraction "
                                 f"{np.count_nonzero(p_ref > 0) / p_ref.size:.4f}, "
                                 f"{ref.wall_time:.1f} s)")
                    del ref
                    walls = solve_case(args, case, n, mode, z, heights, loads[case], p_ref,
                                       ref_file, folder, last_run, rows, notes)
                    del z, p_ref
                    summary.append(summary_rows(n, mode, case, walls))
                print(f"\nn = {n}, {mode}")
                table(["H", "frac", "code", "kernel", "wall s", "solve s", "iters", "fraction",
                       "dev max", "dev L1", "K diff", "peak GB", "t / t_mv"], rows,
                      ["{:g}", "{:g}", "{}", "{}", "{:.3f}", "{:.3f}", "{}", "{:.4f}",
                       "{:.1e}", "{:.1e}", "{:.1e}", "{:.2f}", "{:.1f}"])
                for note in notes:
                    print("   " + note)
                sys.stdout.flush()
    print("\nSummary: t / t_mv against aspher's best variant, tamaas and contactmechanics "
          "(targets: >= 3, >= 20, >= 20)")
    table(["n", "mode", "H", "frac", "mdrvisc s", "aspher best", "aspher s", "aspher / mv",
           "tamaas / mv", "cm / mv"], summary,
          ["{}", "{}", "{:g}", "{:g}", "{:.3f}", "{}", "{:.3f}", "{:.2f}", "{:.1f}", "{:.1f}"])
    worst = []
    for n in args.sizes:
        for mode in args.modes:
            mine = [r for r in summary if r[0] == n and r[1] == mode]
            if not mine:
                continue
            cols = [[r[i] for r in mine if r[i] is not None] for i in (7, 8, 9)]
            worst.append([n, mode, len(mine), *(min(c) if c else None for c in cols)])
    print("\nSmallest ratio over the cases, per size and mode")
    table(["n", "mode", "cases", "aspher / mv", "tamaas / mv", "cm / mv"], worst,
          ["{}", "{}", "{}", "{:.2f}", "{:.1f}", "{:.1f}"])


if __name__ == "__main__":
    main()
