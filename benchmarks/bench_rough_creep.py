"""Creep of a rough surface on a standard solid, periodic cell: mdrvisc against tamaas'
``MaxwellViscoelastic``, at equal accuracy.

Problem: one periodic cell (edge L = 1 m, n x n elements) of a Gaussian self-affine surface
from ``mv.surfaces.self_affine`` (Hurst 0.8, roll-off wavelength L / 4, shortest
wavelength L / 128, 4 elements at 512^2 (4 elements on coarser grids), rms slope 0.1, a
seed nothing else in the project uses), pressed from t = 0 with a constant mean pressure
pbar into an incompressible standard linear solid, G(t) = G_inf + G1 exp(-t / tau1) with
G_inf = 1 Pa (tamaas' viscoelastic solver is correct only then, see below), G1 = 4 Pa,
tau1 = 1 s, for a duration T = 10 s (the creep's retardation time tau1 (G_inf + G1) /
G_inf is 5 s). pbar is fixed so that the rubbery (G_inf) elastic contact has the contact
fraction ``--fraction`` (5 %); the creep starts from the glassy contact (about a fifth of
it) and reaches about 4.5 % at T.

Both codes use the spectral compliance 2 / (E* |q|) of the periodic cell (E* = 4 G), and
the same hereditary law; they integrate it differently:

* mdrvisc (``mv.Scene(indenter=mv.HeightMap(h, dx, periodic=True), medium=
  mv.StandardSolid(G_inf, G1, tau1), force=pbar L^2, dt=T / steps)``): a zero-length step
  at t = 0 (the glassy response to the load's jump), then ``steps`` steps, each the exact
  exponential update of the Maxwell branch for a strain interpolated quadratically through
  the step's end and the two states before it (linear on the first step after the jump).
  With contact elements entering at every step, whose histories kink where they touch,
  its error falls as dt^2 here (as dt^3 on a smooth history), about 4 times below that of
  a strain linear over each step.
* tamaas: model E = 3 G_inf, nu = 0.5, ``MaxwellViscoelastic(model, h, tol, time_step=dt,
  shear_moduli=[G1], characteristic_times=[tau1])``, ``steps`` calls of ``solve(pbar)``,
  each one backward-Euler step (first order in dt), the first from the unloaded body.

Accuracy: the reference is mdrvisc with ``--ref-steps`` (800) steps at tol 1e-12; its own
time error is estimated from a second run with half the steps (the "reference check" line:
for a second-order scheme the reference's error is about a third of that difference). At
T / 2 and T, "dA" is |A - A_ref| / A_ref (A the real contact area), "dev max" max |p -
p_ref| / max p_ref and "dev L1" sum |p - p_ref| / sum p_ref. Every code's solves run at
``--tol`` (1e-8) on its own criterion (mdrvisc: relative L1 change of the pressure; tamaas:
its complementarity error), far below the time-discretisation error. Since the two schemes
reach different accuracies with the same steps, the table also has mdrvisc at the fewest
steps (from ``--mv-steps``) whose dA, dev max and dev L1, at both times, are no larger
than tamaas' at ``--steps`` ("equal accuracy"), and estimates the steps tamaas would need to reach
mdrvisc's accuracy at ``--steps`` (its error is first order: steps x its dev L1 / mdrvisc's).

Independent check of the two codes' agreement (``--conv-size``, 128, a surface of that size
with the same spectrum; 0 skips it): both codes at ``--conv-steps`` (100 200 400 800)
against mdrvisc at 4 x the largest count and tol 1e-12; the deviations of each fall at its
order, and tamaas' Richardson extrapolate 2 p(2N) - p(N) of its two finest runs, made
without mdrvisc, lands on mdrvisc's reference.

Material-law check (no timing): a wavy surface g cos(2 pi x / L) (64^2) held in full
contact, where the pressure amplitude measures the relaxation modulus directly, over 400
steps of the benchmark's dt: tamaas' after k steps against the backward-Euler recursion
G_inf + G1 (1 + dt / tau1)^-k and mdrvisc's against G(k dt), at G_inf = 1 Pa and at G_inf
= 1/3 Pa (model E = 1, the value tamaas' users often set). tamaas follows its recursion to
round-off only at G_inf = 1 Pa; otherwise it relaxes at the wrong rate and to the wrong
long-time modulus.

Build against build at equal accuracy (``--ladder STEPS ...``, mdrvisc alone, no peers):
mdrvisc at each step count, best of ``--rounds``, with its deviations from the reference
stored in ``--reference FILE`` (an .npz made by the first run that names it, read by the
next). Run it with each build's Python against the same file: the fewest steps of one
build whose deviations are all within another's at its step count give the two builds'
times at equal accuracy.

Timings: wall clock, scene or model set-up from the height array + all steps (mdrvisc:
``mv.Scene(...)`` + ``mv.solve`` end to end, both field times included), best of
``--rounds`` (2) interleaved rounds (mdrvisc, tamaas, mdrvisc at equal accuracy, then
again); a run over ``--single-above`` (60 s) is not repeated. mdrvisc runs its rayon pool on
all cores, tamaas (the PyPI wheel, cpp backend) on one; ``--mv-threads1`` adds mdrvisc's
times on one thread (this script in a subprocess with RAYON_NUM_THREADS=1, best of
``--rounds``). "cpu s" is mdrvisc's CPU time (user + system, all threads) over the same
runs, the steadier measure on a busy machine. Iterations: CG iterations summed over the
steps. mdrvisc's resolution warning (the patches span about 8 elements: the shortest
wavelength is 4 elements at 512^2) is printed once as a note: the two codes solve the same
discrete problem, and its convergence in the map's sampling is not what is measured.

Peers run in their own venv, through ``creep_worker.py`` (its interpreter: ``--peers-python
PATH`` or $MDRVISC_PEERS_PYTHON). Run: ``python benchmarks/bench_rough_creep.py
--peers-python PATH [--size 512] [--steps 100] [--rounds 2] [--single-above 60]
[--ref-steps 800] [--conv-size 128] [--mv-threads1]``, or ``python
benchmarks/bench_rough_creep.py --ladder 100 64 50 --reference FILE [--rounds 3]``.
"""

from __future__ import annotations

import argparse
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
from _bench import header, load, pressure_for_fraction, run_worker, table

HERE = Path(__file__).resolve().parent
EDGE = 1.0
HURST, ROLLOFF, SHORT, RMS_SLOPE = 0.8, 4, 128, 0.1
REF_TOL = 1e-12
CHECK_STEPS = 400  # steps of the material-law check (to t = 40 s at dt = 0.1 s)
PEERS_PYTHON_ENV = "MDRVISC_PEERS_PYTHON"


def surface(n: int, seed: int) -> np.ndarray:
    """Heights (m, (n, n)) of the benchmark's surface on an n x n grid over the cell; the
    shortest wavelength is L / SHORT, or 4 elements on a coarser grid."""
    return mv.surfaces.self_affine((n, n), EDGE / n, HURST, rms_slope=RMS_SLOPE,
                                   rolloff=EDGE / ROLLOFF,
                                   short_cutoff=max(EDGE / SHORT, 4.0 * EDGE / n), seed=seed)


def calibrate(z: np.ndarray, g: float, fraction: float) -> tuple[float, list[str]]:
    """Mean pressure (Pa) at which the elastic (shear modulus g) periodic contact of ``z``
    has the contact fraction ``fraction`` (tol 1e-6): secant steps from the estimate
    fraction = 2 pbar / (E* rms slope)."""
    n = z.shape[0]

    def pressure_at(pbar):
        r = mv.arrays.contact(z.max() - z, EDGE / n, g, force=pbar * EDGE**2, tol=1e-6,
                              deflection=False, periodic=True)
        return np.asarray(r.fields[0.0].pressure)

    return pressure_for_fraction(pressure_at, fraction, fraction * 4.0 * g * RMS_SLOPE / 2.0)


def cpu_seconds() -> float:
    """CPU time (s) of this process so far, user + system, all its threads."""
    t = os.times()
    return t.user + t.system


def mv_creep(z, medium, pbar, duration, steps, tol):
    """mdrvisc's creep run; returns (wall s, {t: pressure}, result), the result's
    ``cpu`` attribute set to the run's CPU time (s, all threads: on a busy machine the
    steadier measure)."""
    n = z.shape[0]
    if steps % 2:
        raise SystemExit(f"step counts must be even (T / 2 is an output), got {steps}")
    cpu = cpu_seconds()
    start = time.perf_counter()
    scene = mv.Scene(indenter=mv.HeightMap(z, EDGE / n, periodic=True), medium=medium,
                     force=pbar * EDGE**2, duration=duration, times=[duration / 2, duration],
                     dt=duration / steps, outputs=("pressure",),
                     field_times=[duration / 2, duration])
    with warnings.catch_warnings():
        # the patches of this surface span about 8 elements (its shortest wavelength is 4
        # elements at 512^2): the area is not converged in the map's sampling, which both
        # codes share; the results keep the message (``r.warnings``), printed once below
        warnings.simplefilter("ignore", mv.ResolutionWarning)
        r = mv.solve(scene, tol=tol, max_iter=100000)
    wall = time.perf_counter() - start
    r.cpu = cpu_seconds() - cpu
    fields = {k: np.asarray(r.fields[t].pressure) for k, t in zip(("mid", "end"), sorted(r.fields))}
    return wall, fields, r


def one_thread(args, pbar, steps) -> float:
    """mdrvisc's wall (s) for ``steps`` steps with RAYON_NUM_THREADS=1: this script in a
    subprocess (rayon sizes its pool once per process) with ``--time-mv``."""
    cmd = [sys.executable, str(Path(__file__).resolve()), "--time-mv", str(steps), "--size",
           str(args.size), "--seed", str(args.seed), "--pressure", repr(pbar), "--duration",
           repr(args.duration), "--g-inf", repr(args.g_inf), "--g1", repr(args.g1), "--tau1",
           repr(args.tau1), "--tol", repr(args.tol), "--no-peers"]
    proc = subprocess.run(cmd, capture_output=True, text=True, check=True,
                          env=dict(os.environ, RAYON_NUM_THREADS="1"))
    return float(proc.stdout.strip().splitlines()[-1])


def peer(args, *worker_args, timeout=3600.0) -> dict:
    cmd = [args.peers_python, str(HERE / "creep_worker.py"), *map(str, worker_args)]
    return run_worker(cmd, timeout)


def tamaas_creep(args, heights_file, folder, pbar, steps, repeats, tag) -> dict:
    out = os.path.join(folder, tag)
    os.makedirs(out, exist_ok=True)
    res = peer(args, "creep", "--heights", heights_file, "--edge", EDGE, "--g-inf", args.g_inf,
               "--g1", args.g1, "--tau1", args.tau1, "--dt", repr(args.duration / steps),
               "--steps", steps, "--pbar", repr(pbar), "--tol", args.tol, "--record",
               steps // 2, steps, "--repeats", repeats, "--single-above", args.single_above,
               "--out", out)
    if "failed" not in res:
        files = res.pop("pressure_files")
        res["fields"] = {"mid": np.load(files[str(steps // 2)]), "end": np.load(files[str(steps)])}
    return res


def deviations(fields: dict, ref: dict) -> dict:
    """dA, dev max, dev L1 at "mid" and "end" against the reference fields."""
    out = {}
    for k in ("mid", "end"):
        p, q = fields[k], ref[k]
        a, a_ref = np.count_nonzero(p > 0), np.count_nonzero(q > 0)
        d = np.abs(p - q)
        out[k] = (abs(a - a_ref) / a_ref, float(d.max() / q.max()), float(d.sum() / q.sum()))
    return out


def worst(dev: dict) -> float:
    """The larger dev L1 of the two times."""
    return max(dev["mid"][2], dev["end"][2])


def material_check(args, rows, notes) -> None:
    """Relaxation modulus read from a wavy surface in full contact, both codes, two G_inf,
    ``CHECK_STEPS`` steps of the benchmark's dt."""
    steps, dt, g1, tau = CHECK_STEPS, args.duration / args.steps, args.g1, args.tau1
    t = dt * np.arange(1, steps + 1)
    n, g = 64, 1e-3
    x = np.arange(n) * EDGE / n
    wavy = np.tile(g * np.cos(2.0 * np.pi * x / EDGE), (n, 1))
    for g_inf in (args.g_inf, args.g_inf / 3.0):
        exact = g_inf + g1 * np.exp(-t / tau)
        euler = g_inf + g1 * (1.0 + dt / tau) ** -np.arange(1, steps + 1)
        pbar = 10.0 * np.pi * 4.0 * (g_inf + g1) * g / EDGE
        scene = mv.Scene(indenter=mv.HeightMap(wavy, EDGE / n, periodic=True),
                         medium=mv.StandardSolid(G_inf=g_inf, G1=g1, tau1=tau),
                         force=pbar * EDGE**2, duration=t[-1], times=t, dt=dt,
                         outputs=("pressure",), field_times=t)
        r = mv.solve(scene, tol=1e-12)
        mv_g = np.array([np.ptp(r.fields[tk].pressure[0]) / 2.0 / (np.pi * g / EDGE) / 4.0
                         for tk in sorted(r.fields)])
        rows.append([f"{g_inf:.4g}", "mdrvisc", "exact G(t_k)",
                     float(np.max(np.abs(mv_g / exact - 1))), mv_g[9], exact[9], mv_g[-1],
                     exact[-1]])
        if args.peers_python:
            res = peer(args, "relax", "--g-inf", repr(g_inf), "--g1", g1, "--tau1", tau, "--dt",
                       repr(dt), "--steps", steps, timeout=600.0)
            if "failed" in res:
                notes.append(f"tamaas material check at G_inf = {g_inf:.4g}: {res['failed']}")
                continue
            tm_g = np.array(res["shear_modulus"])
            rows.append([f"{g_inf:.4g}", "tamaas", "BE recursion",
                         float(np.max(np.abs(tm_g / euler - 1))), tm_g[9], euler[9], tm_g[-1],
                         euler[-1]])


def convergence(args, rows, notes) -> None:
    """Both codes at --conv-steps on a --conv-size surface against a fine mdrvisc run."""
    n = args.conv_size
    z = surface(n, args.seed)
    medium = mv.StandardSolid(G_inf=args.g_inf, G1=args.g1, tau1=args.tau1)
    pbar, _ = calibrate(z, args.g_inf, args.fraction)
    ref_steps = 4 * max(args.conv_steps)
    _, ref, r = mv_creep(z, medium, pbar, args.duration, ref_steps, REF_TOL)
    notes.append(f"convergence at n = {n}: pbar {pbar:.6g} Pa, reference mdrvisc {ref_steps} "
                 f"steps at tol {REF_TOL:g} ({r.iterations} iterations, residual "
                 f"{r.residual:.1e}), contact fraction {np.mean(ref['mid'] > 0):.4f} (T/2), "
                 f"{np.mean(ref['end'] > 0):.4f} (T)")
    with tempfile.TemporaryDirectory() as folder:
        heights_file = os.path.join(folder, "heights.npy")
        np.save(heights_file, z)
        tamaas_fields = {}
        for steps in args.conv_steps:
            _, fields, _ = mv_creep(z, medium, pbar, args.duration, steps, args.tol)
            dev = deviations(fields, ref)
            rows.append([n, "mdrvisc", steps, *dev["mid"], *dev["end"]])
            if args.peers_python:
                res = tamaas_creep(args, heights_file, folder, pbar, steps, 1, f"conv{steps}")
                if "failed" in res:
                    notes.append(f"tamaas at n = {n}, {steps} steps: {res['failed']}")
                    continue
                tamaas_fields[steps] = res["fields"]
                dev = deviations(res["fields"], ref)
                rows.append([n, "tamaas", steps, *dev["mid"], *dev["end"]])
        done = sorted(tamaas_fields)
        if len(done) >= 2:
            coarse, fine = tamaas_fields[done[-2]], tamaas_fields[done[-1]]
            if done[-1] == 2 * done[-2]:
                extra = {k: np.maximum(2.0 * fine[k] - coarse[k], 0.0) for k in ("mid", "end")}
                dev = deviations(extra, ref)
                rows.append([n, "tamaas Richardson", f"2x{done[-1]}-{done[-2]}", *dev["mid"],
                             *dev["end"]])


def odd_step_count(counts) -> str | None:
    """The message for the first of ``counts`` that is not an even step count >= 2 (T / 2
    is an output), or None."""
    for s in counts:
        if s < 2 or s % 2:
            return f"step counts must be even and >= 2 (T / 2 is an output), got {s}"
    return None


def ladder(args) -> None:
    """mdrvisc at each of ``args.ladder``'s step counts: best wall and CPU of
    ``args.rounds`` runs, iterations and deviations from the reference in
    ``args.reference`` (made there first if the file does not exist)."""
    odd = odd_step_count([*args.ladder, args.ref_steps])
    if odd:
        raise SystemExit(odd)
    z = surface(args.size, args.seed)
    medium = mv.StandardSolid(G_inf=args.g_inf, G1=args.g1, tau1=args.tau1)
    pbar = args.pressure if args.pressure is not None else calibrate(z, args.g_inf,
                                                                     args.fraction)[0]
    header(f"Rough creep, build against build: periodic {args.size}^2, pbar = {pbar:.6g} Pa, "
           f"T = {args.duration:g} s, tol {args.tol:g}, reference {args.reference}")
    path = Path(args.reference)
    if path.exists():
        saved = np.load(path)
        ref = {"mid": saved["mid"], "end": saved["end"]}
        if ref["mid"].shape != z.shape or not np.isclose(float(saved["pbar"]), pbar):
            raise SystemExit(f"{path} holds another problem's reference (shape "
                             f"{ref['mid'].shape}, pbar {float(saved['pbar']):.6g} Pa)")
        print(f"   reference read from {path}: {saved['made_by']}")
    else:
        _, ref, r = mv_creep(z, medium, pbar, args.duration, args.ref_steps, REF_TOL)
        made_by = (f"mdrvisc {mv.__version__} ({Path(mv.__file__).parent}), "
                   f"{args.ref_steps} steps at tol {REF_TOL:g}, {r.iterations} iterations")
        np.savez(path, mid=ref["mid"], end=ref["end"], pbar=pbar, made_by=made_by)
        print(f"   reference made and saved to {path}: {made_by}")
    rows = []
    for steps in args.ladder:
        walls, cpus = [], []
        for _ in range(args.rounds):
            wall, fields, r = mv_creep(z, medium, pbar, args.duration, steps, args.tol)
            walls.append(wall)
            cpus.append(r.cpu)
        dev = deviations(fields, ref)
        rows.append([steps, min(walls), min(cpus), r.iterations, *dev["mid"], *dev["end"]])
    print(f"\nmdrvisc {mv.__version__} ({Path(mv.__file__).parent}): best of {args.rounds}")
    table(["steps", "wall s", "cpu s", "iters", "dA T/2", "dev max T/2", "dev L1 T/2", "dA T",
           "dev max T", "dev L1 T"], rows,
          ["{}", "{:.2f}", "{:.2f}", "{}", "{:.1e}", "{:.3e}", "{:.3e}", "{:.1e}", "{:.3e}",
           "{:.3e}"])
    sys.stdout.flush()


def main(argv=None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--size", type=int, default=512, help="grid n (n x n elements)")
    ap.add_argument("--steps", type=int, default=100, help="time steps of both codes over T")
    ap.add_argument("--duration", type=float, default=10.0, help="T (s)")
    ap.add_argument("--g-inf", type=float, default=1.0, help="G_inf (Pa); tamaas needs 1")
    ap.add_argument("--g1", type=float, default=4.0, help="G1 (Pa)")
    ap.add_argument("--tau1", type=float, default=1.0, help="tau1 (s)")
    ap.add_argument("--fraction", type=float, default=0.05,
                    help="contact fraction of the rubbery (G_inf) elastic contact at pbar")
    ap.add_argument("--pressure", type=float, default=None,
                    help="mean pressure pbar (Pa) instead of the calibrated one")
    ap.add_argument("--seed", type=int, default=20260219,
                    help="seed of the surface (held out: not used elsewhere in the project)")
    ap.add_argument("--tol", type=float, default=1e-8, help="both codes' solver tolerance")
    ap.add_argument("--ref-steps", type=int, default=800,
                    help="steps of the reference (mdrvisc at tol 1e-12; checked at half)")
    ap.add_argument("--mv-steps", type=int, nargs="+", default=[50, 20, 10, 6, 4, 2],
                    help="mdrvisc step counts tried for the accuracy of tamaas at --steps")
    ap.add_argument("--rounds", type=int, default=2,
                    help="interleaved timing rounds (best kept)")
    ap.add_argument("--single-above", type=float, default=60.0,
                    help="a run longer than this (s) is not repeated")
    ap.add_argument("--conv-size", type=int, default=128,
                    help="grid of the convergence study (0: skip it)")
    ap.add_argument("--conv-steps", type=int, nargs="+", default=[100, 200, 400, 800])
    ap.add_argument("--peers-python", default=os.environ.get(PEERS_PYTHON_ENV) or None,
                    metavar="PATH",
                    help="Python interpreter of the venv holding tamaas "
                         f"(default: ${PEERS_PYTHON_ENV}; set-up in benchmarks/README.md)")
    ap.add_argument("--no-peers", action="store_true", help="mdrvisc alone")
    ap.add_argument("--mv-threads1", action="store_true",
                    help="also time mdrvisc's runs with RAYON_NUM_THREADS=1 (tamaas is serial)")
    ap.add_argument("--ladder", type=int, nargs="+", default=None, metavar="STEPS",
                    help="mdrvisc alone at these step counts against --reference, then stop")
    ap.add_argument("--reference", default=None, metavar="FILE",
                    help="(with --ladder) the reference's .npz: made if absent, else read")
    ap.add_argument("--time-mv", type=int, default=None, metavar="STEPS",
                    help="(used by --mv-threads1) print the wall of one mdrvisc run and stop")
    args = ap.parse_args(argv)
    if args.time_mv is not None:
        z = surface(args.size, args.seed)
        medium = mv.StandardSolid(G_inf=args.g_inf, G1=args.g1, tau1=args.tau1)
        print(mv_creep(z, medium, args.pressure, args.duration, args.time_mv, args.tol)[0])
        return
    if args.ladder is not None:
        if not args.reference:
            ap.error("--ladder needs --reference FILE (made if absent)")
        ladder(args)
        return
    if args.no_peers:
        args.peers_python = None
    elif not args.peers_python:
        ap.error(f"no interpreter for the peers: pass --peers-python PATH or set "
                 f"{PEERS_PYTHON_ENV} (benchmarks/README.md, \"Peer codes\"), or --no-peers")
    elif shutil.which(args.peers_python) is None:
        ap.error(f"the peers' interpreter {args.peers_python!r} is not an executable")
    odd = odd_step_count([args.steps, args.ref_steps, *args.mv_steps, *args.conv_steps])
    if odd:
        ap.error(odd)

    n, duration = args.size, args.duration
    z = surface(n, args.seed)
    medium = mv.StandardSolid(G_inf=args.g_inf, G1=args.g1, tau1=args.tau1)
    if args.pressure is None:
        pbar, log = calibrate(z, args.g_inf, args.fraction)
    else:
        pbar, log = args.pressure, ["given by --pressure"]
    header(f"Rough creep (self-affine, H = {HURST}, wavelengths L/{SHORT}..L/{ROLLOFF}, rms "
           f"slope {RMS_SLOPE}, seed {args.seed}, periodic {n}^2), standard solid G_inf = "
           f"{args.g_inf:g} Pa, G1 = {args.g1:g} Pa, tau1 = {args.tau1:g} s, pbar = {pbar:.6g} "
           f"Pa, T = {duration:g} s, tol {args.tol:g}: mdrvisc vs tamaas MaxwellViscoelastic")
    print(f"   pbar for a rubbery contact fraction of {args.fraction:g} (mdrvisc elastic, "
          f"G = G_inf, tol 1e-6): {'; '.join(log)}")
    if args.peers_python:
        print(f"   peers run by {args.peers_python}")
    sys.stdout.flush()

    # material law
    rows, notes = [], []
    material_check(args, rows, notes)
    print(f"\nMaterial law: relaxation modulus from a wavy surface in full contact, "
          f"{CHECK_STEPS} steps of dt = {duration / args.steps:g} s (G1 = {args.g1:g} Pa, tau1 = "
          f"{args.tau1:g} s)")
    table(["G_inf Pa", "code", "against", "max rel dev", "G(t_10) Pa", "expected",
           f"G(t_{CHECK_STEPS}) Pa", "expected"], rows,
          ["{}", "{}", "{}", "{:.1e}", "{:.5f}", "{:.5f}", "{:.5f}", "{:.5f}"])
    for note in notes:
        print("   " + note)
    sys.stdout.flush()

    # reference and its check
    _, ref, r_ref = mv_creep(z, medium, pbar, duration, args.ref_steps, REF_TOL)
    _, half, r_half = mv_creep(z, medium, pbar, duration, args.ref_steps // 2, REF_TOL)
    ref_check = deviations(half, ref)
    notes = [f"reference: mdrvisc {args.ref_steps} steps at tol {REF_TOL:g} ({r_ref.iterations} "
             f"iterations, residual {r_ref.residual:.1e}); contact fraction "
             f"{np.mean(ref['mid'] > 0):.4f} at T/2, {np.mean(ref['end'] > 0):.4f} at T",
             f"reference check: {args.ref_steps // 2} steps against {args.ref_steps}: dA "
             f"{ref_check['mid'][0]:.1e} / {ref_check['end'][0]:.1e}, dev max "
             f"{ref_check['mid'][1]:.1e} / {ref_check['end'][1]:.1e}, dev L1 "
             f"{ref_check['mid'][2]:.1e} / {ref_check['end'][2]:.1e} (T/2 / T)"]

    with tempfile.TemporaryDirectory() as folder:
        heights_file = os.path.join(folder, "heights.npy")
        np.save(heights_file, z)
        runs: dict[str, dict] = {}
        # accuracy of tamaas at --steps first: it picks mdrvisc's equal-accuracy count
        if args.peers_python:
            res = tamaas_creep(args, heights_file, folder, pbar, args.steps, 1, "round1")
            if "failed" in res:
                notes.append(f"tamaas: {res['failed']}")
            else:
                runs["tamaas"] = dict(res, dev=deviations(res["fields"], ref))
        wall, fields, r = mv_creep(z, medium, pbar, duration, args.steps, args.tol)
        runs["mdrvisc"] = dict(wall=wall, walls=[wall], cpus=[r.cpu], dev=deviations(fields, ref),
                               iterations=r.iterations, steps=args.steps, fields=fields)
        notes += [f"mdrvisc's note at {args.steps} steps: {w}" for w in r.warnings]
        equal = None
        if "tamaas" in runs:
            target = runs["tamaas"]["dev"]
            for steps in sorted(args.mv_steps):
                w, f, rr = mv_creep(z, medium, pbar, duration, steps, args.tol)
                dev = deviations(f, ref)
                if all(dev[k][i] <= target[k][i] for k in ("mid", "end") for i in (0, 1, 2)):
                    equal = f"mdrvisc {steps} steps"
                    runs[equal] = dict(wall=w, walls=[w], cpus=[rr.cpu], dev=dev,
                                       iterations=rr.iterations, steps=steps, fields=f)
                    break
            if equal is None:
                notes.append(f"no step count of --mv-steps {args.mv_steps} gives mdrvisc "
                             f"deviations within tamaas' at {args.steps} steps")
        # further interleaved rounds
        for _ in range(args.rounds - 1):
            for name, run in runs.items():
                if run["walls"][0] > args.single_above:
                    continue
                if name == "tamaas":
                    res = tamaas_creep(args, heights_file, folder, pbar, args.steps, 1, "rounds")
                    if "failed" not in res:
                        run["walls"].append(res["wall"])
                else:
                    w, _, rr = mv_creep(z, medium, pbar, duration, run["steps"], args.tol)
                    run["walls"].append(w)
                    run["cpus"].append(rr.cpu)
        if args.mv_threads1:
            for name, run in runs.items():
                if name != "tamaas":
                    run["threads1"] = min(one_thread(args, pbar, run["steps"])
                                          for _ in range(args.rounds))

    wall_mv = min(runs["mdrvisc"]["walls"])
    rows = []
    order = ["mdrvisc", "tamaas"] + [k for k in runs if k not in ("mdrvisc", "tamaas")]
    for name in (k for k in order if k in runs):
        run = runs[name]
        wall = min(run["walls"])
        dev = run["dev"]
        p_mid, p_end = run["fields"]["mid"], run["fields"]["end"]
        label = name if name != "tamaas" else f"tamaas {run['version']}"
        rows.append([label, run["steps"], wall, min(run["cpus"]) if "cpus" in run else None,
                     wall / run["steps"], run["iterations"],
                     np.mean(p_mid > 0), np.mean(p_end > 0), *dev["mid"], *dev["end"],
                     None if name == "mdrvisc" else wall / wall_mv])
    print(f"\nCreep at n = {n}: wall = set-up + all steps, best of {args.rounds} interleaved "
          f"rounds (cpu: mdrvisc's process CPU time over the same runs, all threads); "
          f"deviations from the reference at T/2 and at T")
    table(["code", "steps", "wall s", "cpu s", "s / step", "iters", "frac T/2", "frac T", "dA T/2",
           "dev max T/2", "dev L1 T/2", "dA T", "dev max T", "dev L1 T", "t / t_mv"], rows,
          ["{}", "{}", "{:.2f}", "{:.2f}", "{:.3f}", "{}", "{:.4f}", "{:.4f}", "{:.1e}", "{:.1e}",
           "{:.1e}", "{:.1e}", "{:.1e}", "{:.1e}", "{:.1f}"])
    if "tamaas" in runs:
        tm_run = runs["tamaas"]
        wall_tm = min(tm_run["walls"])
        if equal is not None:
            notes.append(f"equal accuracy (mdrvisc's dA, dev max and dev L1 at T/2 and T no larger "
                         f"than tamaas' at "
                         f"{args.steps} steps): {equal}, tamaas / mdrvisc = "
                         f"{wall_tm / min(runs[equal]['walls']):.1f}")
        need = args.steps * worst(tm_run["dev"]) / worst(runs["mdrvisc"]["dev"])
        notes.append(f"tamaas would need about {need:.0f} steps for mdrvisc's dev L1 at "
                     f"{args.steps} steps (first order: steps x dev ratio), about "
                     f"{need * wall_tm / args.steps:.0f} s at its time per step, "
                     f"{need * wall_tm / args.steps / wall_mv:.0f}x mdrvisc's wall (estimate)")
        notes.append(f"tamaas: solves {'converged' if tm_run['converged'] else 'NOT converged'} "
                     f"(largest error {tm_run['max_error']:.1e}), {tm_run['threads']}; "
                     f"walls {', '.join(f'{w:.1f}' for w in tm_run['walls'])} s")
    for name, run in runs.items():
        if "threads1" in run:
            ratio = (f", tamaas / it = {min(runs['tamaas']['walls']) / run['threads1']:.1f}"
                     if "tamaas" in runs else "")
            notes.append(f"{name} on one thread (RAYON_NUM_THREADS=1, best of {args.rounds}): "
                         f"{run['threads1']:.2f} s{ratio}")
    notes.append("mdrvisc walls: " + "; ".join(
        f"{k}: {', '.join(f'{w:.2f}' for w in v['walls'])} s" for k, v in runs.items()
        if k != "tamaas"))
    for note in notes:
        print("   " + note)
    sys.stdout.flush()

    if args.conv_size:
        rows, notes = [], []
        convergence(args, rows, notes)
        print(f"\nConvergence in the step count at n = {args.conv_size} (deviations from "
              f"mdrvisc at 4 x {max(args.conv_steps)} steps)")
        table(["n", "code", "steps", "dA T/2", "dev max T/2", "dev L1 T/2", "dA T", "dev max T",
               "dev L1 T"], rows,
              ["{}", "{}", "{}", "{:.1e}", "{:.1e}", "{:.1e}", "{:.1e}", "{:.1e}", "{:.1e}"])
        for note in notes:
            print("   " + note)
    print(f"   ({load()}; RAYON_NUM_THREADS={os.environ.get('RAYON_NUM_THREADS', 'unset')})")


if __name__ == "__main__":
    main()
