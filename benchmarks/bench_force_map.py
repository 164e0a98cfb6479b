"""Force maps: ``mv.afm.fit_map`` on a synthetic map of noisy raw curves made with
``mv.afm.simulate``, and (optionally) on the force curves of real instrument files.

Synthetic map: ``--side`` x ``--side`` curves (default 64 x 64 = 4,096), a spherical tip
(R = 5 µm) on a cantilever of k = 0.05 N/m, a "cell" in the middle of the map (moduli and
contact points varying over it), Gaussian deflection noise of ``--noise`` (default 1 %) of
the largest deflection. Elastic map: the approach (``--samples`` samples, default 300) fitted
with ``mv.Elastic``; standard-solid map: approach and retract fitted with
``mv.StandardSolid``. Targets on this 2-core machine: 4,096 elastic curves <= 60 s and 4,096
standard-solid curves <= 5 min (``fit_map`` on local worker processes, one per core).

Reported per map: the wall time of the simulation and of the fit (the two do not overlap),
curves per second, the failures and fits that did not converge, and the accuracy over the
map: the median and 95th percentile of |fitted - true| / true per parameter, and the
spread of (fitted - true) / stderr (1 where the standard errors are right).

``--profile``: where one curve's fit spends its time (cProfile of 20 fits in this process).
``--data DIR``: every force curve of the AFM files under DIR (e.g. afmformats' test data)
loaded with ``mv.afm.load`` and its approach fitted with a Hertz sphere (``--radius``):
E, contact point, rms, success and time per curve.

``--pyfmrheo-python PYTHON --pyfmrheo-map FILE.jpk-force-map``: PyFMRheo's power-law Ting fit
of the map's curves (``pyfmrheo_map_worker.py``, run by that interpreter, with the
parameters of PyFMRheo's viscoelastic example notebook: paraboloid R = 5 µm, t0 = 1 s, a
window from 1 µm before contact downsampled to 300 points, viscous drag 2.5e-6 N s/m), and
mdrvisc's power-law fits of the same window (PyFMRheo's indentation, force and time from
its contact time) and of variants that take PyFMRheo's modelling choices one at a time:
(A) the measured indentation, as mdrvisc fits it; (B) the indentation replaced by
PyFMRheo's idealised one, the piezo speeds v0t and v0r times the time from contact (its
"analytical" model assumes it); (C) that and its viscous-drag force subtracted from the
data. Printed per curve: E0 (Young's modulus at t0, Pa) and beta of each fit, and both
fitted moduli at 20 ms (within the contact's duration) instead of t0 = 1 s.

Run: ``python benchmarks/bench_force_map.py [--side 64] [--models elastic,standardsolid]
[--workers 2] [--profile] [--data DIR] [--pyfmrheo-python PYTHON --pyfmrheo-map FILE]``.
"""

from __future__ import annotations

import argparse
import cProfile
import json
import pstats
import subprocess
import time
import warnings
from pathlib import Path

import numpy as np

import mdrvisc as mv
from _bench import header, table

R, K = 5e-6, 0.05
SPHERE = mv.Sphere(radius=R)


def truth(side: int, model: str):
    """The true medium and contact point of every pixel: a round cell (stiffer, higher) on a
    softer substrate, the contact point rising towards the cell's centre."""
    y, x = np.mgrid[0:side, 0:side] / max(side - 1, 1) - 0.5
    cell = np.clip(1.0 - (x**2 + y**2) / 0.16, 0.0, 1.0)
    G = 300.0 + 900.0 * cell
    z_c = 0.3e-6 * cell
    if model == "elastic":
        media = [mv.Elastic(G=g) for g in G.ravel()]
    else:
        tau = 0.02 + 0.05 * cell
        media = [mv.StandardSolid(G_inf=g, G1=2 * g, tau1=t) for g, t in zip(G.ravel(), tau.ravel())]
    return media, z_c.ravel()


def simulate_map(side: int, model: str, samples: int, noise: float, seed: int = 1):
    """The curves of the map (mv.afm.Curve, with grid positions) and the true values."""
    travel = 2.0e-6
    speed = 1e-5
    rate = samples * speed / travel
    t, z, segment = mv.afm.piezo_ramp(travel, speed=speed, rate=rate, start=-0.8e-6,
                                      retract=model != "elastic")
    media, z_c = truth(side, model)
    rng = np.random.default_rng(seed)
    curves = []
    for i, (medium, zc) in enumerate(zip(media, z_c)):
        sim = mv.afm.simulate(SPHERE, medium, t, z, K, contact_point=zc, baseline=5e-9, segment=segment,
                              n=300)
        scale = noise * float(np.max(sim.force)) / K
        curve = sim.curve
        curve.deflection = curve.deflection + rng.normal(0.0, scale, curve.deflection.size)
        curve.grid_index = (i % side, i // side)
        curve.position = (1e-6 * (i % side), 1e-6 * (i // side))
        curve.index = i
        curves.append(curve)
    return curves, media, z_c


def accuracy(fitted, media, z_c):
    """Rows (parameter, median |rel error|, p95 |rel error|, std of (fit - true)/stderr)."""
    table_ = fitted.table
    ok = table_["success"].to_numpy(bool)
    rows = []
    names = list(media[0]._parameters())
    true = {name: np.array([m._parameters()[name] for m in media]) for name in names}
    true["contact_point"] = z_c
    for name in names + ["contact_point"]:
        fit = table_[name].to_numpy(float)[ok]
        err = table_[f"{name}_stderr"].to_numpy(float)[ok]
        ref = true[name][ok]
        if name == "contact_point":  # absolute errors, in nm
            rows.append((name, f"{np.median(np.abs(fit - ref)) * 1e9:.3g} nm",
                         f"{np.percentile(np.abs(fit - ref), 95) * 1e9:.3g} nm",
                         f"{np.std((fit - ref) / err):.2f}"))
            continue
        rel = np.abs(fit / ref - 1)
        rows.append((name, f"{np.median(rel):.2e}", f"{np.percentile(rel, 95):.2e}",
                     f"{np.std((fit - ref) / err):.2f}"))
    return rows


def run_map(side: int, model: str, samples: int, noise: float, workers: int | None):
    start = time.perf_counter()
    curves, media, z_c = simulate_map(side, model, samples, noise)
    simulated = time.perf_counter() - start
    cls = mv.Elastic if model == "elastic" else mv.StandardSolid
    segments = ["approach"] if model == "elastic" else ["approach", "retract"]
    start = time.perf_counter()
    fitted = mv.afm.fit_map(curves, SPHERE, cls, segments=segments, workers=workers, progress=False, n=300)
    wall = time.perf_counter() - start
    return curves, fitted, simulated, wall, accuracy(fitted, media, z_c)


def profile_one(model: str, samples: int, noise: float) -> None:
    curves, _, _ = simulate_map(2, model, samples, noise)
    cls = mv.Elastic if model == "elastic" else mv.StandardSolid
    segments = ["approach"] if model == "elastic" else ["approach", "retract"]
    profiler = cProfile.Profile()
    profiler.enable()
    for _ in range(5):
        for curve in curves:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                curve.fit(SPHERE, cls, segments, n=300)
    profiler.disable()
    print(f"\n   profile of 20 {model} fits (cumulative time, top 12):")
    pstats.Stats(profiler).sort_stats("cumulative").print_stats(12)


def real_data(directory: Path, radius: float) -> None:
    """Loads every AFM file under ``directory`` and fits a Hertz sphere to each curve's approach."""
    rows = []
    for path in sorted(p for p in directory.rglob("*") if p.is_file()):
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                curves = mv.afm.load(path)
        except (mv.DataError, ImportError) as exc:
            rows.append((path.name[:44], "-", "-", "-", "-", "-", f"not loaded: {str(exc)[:60]}"))
            continue
        for curve in curves[:4]:
            start = time.perf_counter()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    result = curve.fit(mv.Sphere(radius=radius), mv.Elastic, ["approach"])
                note = "" if result.success else result.message[:40]
                rows.append((path.name[:44], curve.index, len(curve.select("approach")),
                             f"{result.young_moduli['E']:.4g}", f"{result.contact_point * 1e6:.4f}",
                             f"{time.perf_counter() - start:.3f}", note or "ok"))
            except mv.MdrviscError as exc:
                rows.append((path.name[:44], curve.index, len(curve), "-", "-",
                             f"{time.perf_counter() - start:.3f}", f"{type(exc).__name__}: {str(exc)[:60]}"))
    table(["file", "curve", "approach samples", "E (Pa)", "z_c (µm)", "fit s", "note"], rows)


def _power_law(t, depth, force, guess):
    """(E0 at t0 = 1 s, beta, success) of mdrvisc's depth-controlled power-law fit."""
    sphere = mv.Paraboloid(c=1 / (2 * R))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        result = mv.fit(sphere, mv.PowerLaw(G0=guess[0] / 3, beta=guess[1], t0=1.0), t,
                        depth=np.maximum(depth, 0.0), force=force)
    return 3 * result.parameters["G0"], result.parameters["beta"], result.success


def _smooth(a, width):
    """PyFMRheo's smoothing: a moving average over ``width`` samples (same length)."""
    return np.convolve(a, np.ones(width) / width, mode="same")


def pyfmrheo_comparison(python: str, path: Path, curves: list[int]) -> None:
    """PyFMRheo's Ting fit of ``curves`` of the map against mdrvisc's fits of the same window."""
    worker = Path(__file__).with_name("pyfmrheo_map_worker.py")
    done = subprocess.run([python, str(worker), "--map", str(path), "--curves", *map(str, curves)],
                          capture_output=True, text=True, timeout=1800)
    if done.returncode != 0:
        print(f"   PyFMRheo worker failed: {done.stderr[-400:]}")
        return
    document = json.loads(done.stdout.strip().splitlines()[-1])
    print(f"   PyFMRheo {document['pyfmrheo']}, k = {document['spring_constant']:.4g} N/m, "
          f"vdrag 2.5e-6 N s/m, window from 1 µm before contact, 300 points")
    rows = []
    for c in document["curves"]:
        t, ind, force = (np.array(c[k]) for k in ("t", "indentation", "force"))
        E0, beta, tc, F0 = c["E0"], c["betaE"], c["tc"], c["F0"]
        inside = t - tc > 0
        tt, ff = t[inside] - tc, force[inside] - F0
        dd = ind[inside] - np.interp(tc, t, ind)
        tm = t[c["idx_tm"]] - tc
        ideal = np.where(tt <= tm, c["v0t"] * tt, c["v0t"] * tm - c["v0r"] * (tt - tm))
        drag = _smooth(np.gradient(ind, t) * 2.5e-6, 21)[inside]
        fits = {"A measured": _power_law(tt, dd, ff, (E0, beta)),
                "B ideal ramp": _power_law(tt, ideal, ff, (E0, beta)),
                "C ideal ramp, drag": _power_law(tt, ideal, ff - drag, (E0, beta))}
        rows.append((c["index"], "PyFMRheo", f"{E0:.4g}", f"{beta:.3f}", f"{E0 * 0.02 ** -beta:.4g}",
                     f"{c['wall']:.3f}"))
        for name, (e0, b, ok) in fits.items():
            rows.append(("", f"mdrvisc {name}" + ("" if ok else " (not converged)"), f"{e0:.4g}", f"{b:.3f}",
                         f"{e0 * 0.02 ** -b:.4g}", ""))
    table(["curve", "fit", "E0 (Pa, t0 = 1 s)", "beta", "E(20 ms) (Pa)", "PyFMRheo s"], rows)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--side", type=int, default=64, help="curves per side of the map (default 64)")
    parser.add_argument("--models", default="elastic,standardsolid")
    parser.add_argument("--samples", type=int, default=300, help="samples of the approach (default 300)")
    parser.add_argument("--noise", type=float, default=0.01, help="noise / largest deflection (default 0.01)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--profile", action="store_true", help="profile one curve's fit")
    parser.add_argument("--data", type=Path, default=None, help="a folder of AFM files to load and fit")
    parser.add_argument("--radius", type=float, default=5e-6, help="tip radius (m) for --data (default 5 µm)")
    parser.add_argument("--pyfmrheo-python", default=None, help="the interpreter of a venv with PyFMRheo")
    parser.add_argument("--pyfmrheo-map", type=Path, default=None, help="PyFMRheo's example force map")
    parser.add_argument("--pyfmrheo-curves", type=int, nargs="+", default=list(range(8)))
    args = parser.parse_args()
    header(f"bench_force_map: mv.afm.fit_map on {args.side}x{args.side} synthetic maps")
    targets = {"elastic": 60.0, "standardsolid": 300.0}
    rows, details = [], []
    for model in filter(None, args.models.split(",")):
        curves, fitted, simulated, wall, acc = run_map(args.side, model, args.samples, args.noise,
                                                       args.workers)
        target = targets[model] * len(curves) / 4096
        unconverged = int((~fitted.table["success"].to_numpy(bool)).sum()) - len(fitted.failures)
        fitted_segments = ("approach", "retract") if model != "elastic" else ("approach",)
        samples = len(curves[0].select(*fitted_segments))
        rows.append((model, len(curves), samples, f"{simulated:.1f}", f"{wall:.1f}",
                     f"{len(curves) / wall:.1f}", len(fitted.failures), unconverged, f"{target:.0f}",
                     "met" if wall <= target else "MISSED"))
        details.append((model, acc))
        if args.profile:
            profile_one(model, args.samples, args.noise)
    if rows:
        table(["model", "curves", "samples fitted", "simulate s", "fit_map s", "curves/s", "failed",
               "not converged", "target s", ""], rows)
    for model, acc in details:
        print(f"\n   {model}: accuracy over the map (converged curves)")
        table(["parameter", "median |rel. error|", "p95 |rel. error|", "std((fit - true) / stderr)"], acc)
    if args.data is not None:
        print()
        real_data(args.data, args.radius)
    if args.pyfmrheo_python is not None and args.pyfmrheo_map is not None:
        print()
        pyfmrheo_comparison(args.pyfmrheo_python, args.pyfmrheo_map, args.pyfmrheo_curves)


if __name__ == "__main__":
    main()
