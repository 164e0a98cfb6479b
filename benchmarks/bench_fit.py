"""Fits of media to a 2,000-point sphere curve (R = 5 um, approach and retract at 1 um/s
over 2 s, 1 % Gaussian noise, seed 0): ``mv.fit`` against the same fit done today's way,
``scipy.optimize.least_squares`` (trust-region reflective, 2-point finite differences, in
the logarithms of the parameters) around ``mv.solve(scene, "mdr", n)``. Both start from
the same guess (the true values times 1.6, 0.6, 2.5, ...) and use the same element count.
Targets: standard solid <= 0.2 s, Prony with 3 terms <= 1 s.

The data come from ``mv.solve`` (MDR, n = 4000, dt = 1e-4 s): a benchmark of speed; the
fit's accuracy against independent references is in ``tests/test_fit.py``.

A second table compares ``mv.fit`` with PyFMRheo's Ting fit on the curves PyFMRheo covers:
a power-law medium G(t) = G0 (t / t0)^-beta (G0 = 1 kPa, beta = 0.2, t0 = 1 s) under a
paraboloid (R = 5 um) and a cone (slope 0.5, half-angle 63.43 degrees), the same triangle
at 1 um/s, 2,000 samples, 1 % noise (seed 0), data from ``mv.solve`` (MDR, n = 4000,
dt = 1e-4 s). PyFMRheo runs in its own venv (``--pyfmrheo-python PATH``, or
$MDRVISC_PYFMRHEO_PYTHON; without it the rows say "not run") through
``pyfmrheo_worker.py``, whose docstring says what it runs and times. Conventions, from
PyFMRheo 0.1.3's source: its E0 is Young's modulus at t0 with the Poisson ratio 0.5 (the
paraboloid's coefficient 4/3 sqrt(R) / (1 - nu^2), the cone's 2/pi tan(theta) / (1 - nu^2),
theta the half-angle), so E0 = 2 (1 + nu) G0 = 3 G0 with mdrvisc's incompressible medium;
betaE is beta; its t0 is the same reference time (t measured from contact, given as
1 s to both). Both fit two parameters (PyFMRheo's contact time and force offset held at
0, mdrvisc's t0 held) from the same initial guess (G0 x 1.6, beta x 0.6). Columns: the
fitted G0 (PyFMRheo's E0 / 3) and beta with their standard errors, their difference from
mdrvisc's in PyFMRheo's standard errors, and PyFMRheo's closed form at the true values
against the noise-free curve (largest deviation over the largest force, approach / retract).

A third table fits raw AFM curves (piezo, deflection, spring constant k = 0.5 N/m; the
contact point and the baseline fitted with the medium): an 8,000-sample approach and retract
(0.5 s before contact, then the triangle above, 1 % deflection noise, seed 0; data from
``mv.solve`` as above, z = z_c + indentation + F / k), a standard solid and a power law,
each from its class alone; targets <= 50 ms a fit; and a Kelvin-Voigt solid (G = 1 kPa, eta =
200 Pa s: its dashpot on the same path). The forward model is Ting's solution with
the cantilever in series (row "hereditary"); the same fit with the MDR elements stepped one
by one under the spring (row "elements", one run) shows what it replaces. Beside them the
same curve's contact part fitted by depth control (the indentation and force at the true
contact point and baseline: Ting's solution, the millisecond path) and PyFMRheo's Ting fit
of that part (power law only; it fits force against time at a given indentation, neither
the contact point nor the cantilever).

Run: ``python benchmarks/bench_fit.py [--repeats 3] [--pyfmrheo-python PATH] [--skip-targets]
[--skip-raw]``.
"""

from __future__ import annotations

import argparse
import contextlib
import math
import os
import tempfile
import time
from pathlib import Path

import numpy as np
from scipy.optimize import least_squares

import mdrvisc as mv
from _bench import best_of, header, run_worker, table
from mdrvisc import fitting
from mdrvisc._fit_model import medium_of, parameters

HERE = Path(__file__).resolve().parent
RADIUS, RATE, T_PEAK, SAMPLES, N = 5e-6, 1e-6, 1.0, 2000, 500
CONE_SLOPE = 0.5
PYFMRHEO_PYTHON_ENV = "MDRVISC_PYFMRHEO_PYTHON"


def curve(true, indenter=None, clean=False):
    """Times, depths and 1 %-noise forces of the triangle (and the noise-free forces)."""
    t = np.linspace(0.0, 2.0 * T_PEAK, SAMPLES + 1)[1:]
    scene = mv.Scene(indenter=indenter or mv.Sphere(radius=RADIUS), medium=true,
                     depth=([0.0, T_PEAK, 2.0 * T_PEAK], [0.0, RATE * T_PEAK, 0.0]), duration=2.0 * T_PEAK,
                     times=t, dt=1e-4)
    force = mv.solve(scene, "mdr", 4000).force
    depth = np.where(t <= T_PEAK, RATE * t, RATE * (2 * T_PEAK - t))
    rng = np.random.default_rng(0)
    noisy = force + 0.01 * force.max() * rng.standard_normal(t.size)
    return (t, depth, noisy, force) if clean else (t, depth, noisy)


def scipy_fit(guess, t, depth, force):
    """Today's way: least_squares around mv.solve, parameters in logs."""
    names = list(parameters(guess))
    base = parameters(guess)
    solves = 0

    def residuals(x):
        nonlocal solves
        solves += 1
        medium = medium_of(type(guess), {**base, **dict(zip(names, np.exp(x)))}, guess.nu)
        history = (np.concatenate([[0.0], t]), np.concatenate([[0.0], depth]))
        scene = mv.Scene(indenter=mv.Sphere(radius=RADIUS), medium=medium, depth=history,
                         duration=float(t[-1]), times=t, dt=float(t[1] - t[0]))
        return (mv.solve(scene, "mdr", 2 * N).force - force) / force.max()

    result = least_squares(residuals, np.log([base[k] for k in names]), method="trf")
    return medium_of(type(guess), dict(zip(names, np.exp(result.x))), guess.nu), solves


def pyfmrheo_fit(python, tip, tip_param, t, depth, force, clean, true, guess, repeats):
    """PyFMRheo's Ting fit in its venv (pyfmrheo_worker.py): a dict of its results, or
    {"failed": why}."""
    with tempfile.TemporaryDirectory() as folder:
        path = os.path.join(folder, "curve.npz")
        np.savez(path, t=t, depth=depth, force=force, clean=clean, turn=int(np.argmax(depth)))
        cmd = [python, str(HERE / "pyfmrheo_worker.py"), "--curve", path, "--tip", tip,
               "--tip-param", repr(tip_param), "--rate", repr(RATE), "--t0", repr(true.t0),
               "--e0", repr(3.0 * guess.G0), "--beta", repr(guess.beta), "--true-e0", repr(3.0 * true.G0),
               "--true-beta", repr(true.beta), "--repeats", str(repeats)]
        return run_worker(cmd, 600.0)


def power_law_table(python, repeats) -> None:
    true = mv.PowerLaw(G0=1e3, beta=0.2, t0=1.0)
    guess = mv.PowerLaw(G0=1.6e3, beta=0.12, t0=1.0)
    half_angle = math.degrees(math.atan(1.0 / CONE_SLOPE))
    header(f"Power-law fits against PyFMRheo's Ting fit ({SAMPLES} samples, 1 % noise, MDR n = {2 * N} "
           f"for mv.fit, best of {repeats})")
    rows = []
    for label, tip, name, param in (("paraboloid", mv.Paraboloid(c=1 / (2 * RADIUS)), "paraboloid", RADIUS),
                                    ("cone", mv.Cone(slope=CONE_SLOPE), "cone", half_angle)):
        t, depth, force, clean = curve(true, tip, clean=True)
        ours_s, ours = best_of(
            lambda tip=tip, t=t, d=depth, f=force: mv.fit(tip, guess, t, depth=d, force=f, n=N), repeats)
        fitted = ours.parameters
        rows.append([label, "mv.fit", ours.nfev, ours_s, fitted["G0"], ours.stderr["G0"], fitted["beta"],
                     ours.stderr["beta"], None, None])
        if python is None:
            rows.append([label, "PyFMRheo (not run: no --pyfmrheo-python)"] + [None] * 8)
            continue
        theirs = pyfmrheo_fit(python, name, param, t, depth, force, clean, true, guess, repeats)
        if "failed" in theirs:
            rows.append([label, f"PyFMRheo (failed: {theirs['failed']})"] + [None] * 8)
            continue
        g0, g0_err = theirs["E0"] / 3.0, theirs["E0_stderr"] / 3.0
        diff = max(abs(g0 - fitted["G0"]) / g0_err,
                   abs(theirs["betaE"] - fitted["beta"]) / theirs["betaE_stderr"])
        rows.append([label, f"PyFMRheo {theirs['version']} Ting", theirs["evaluations"], theirs["seconds"],
                     g0, g0_err, theirs["betaE"], theirs["betaE_stderr"], diff,
                     f"{theirs['deviation_approach']:.1e} / {theirs['deviation_retract']:.1e}"])
        rows.append([label, "time ratio mv.fit / PyFMRheo", None, ours_s / theirs["seconds"]] + [None] * 6)
    table(["tip", "method", "evaluations", "wall s", "G0 Pa", "+- Pa", "beta", "+-", "|diff| / their stderr",
           "closed form at true vs data"], rows,
          ["{}", "{}", "{}", "{:.4f}", "{:.2f}", "{:.2f}", "{:.5f}", "{:.5f}", "{:.1f}", "{}"])


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--pyfmrheo-python", default=os.environ.get(PYFMRHEO_PYTHON_ENV) or None,
                        help=f"interpreter of a venv with PyFMRheo (default: ${PYFMRHEO_PYTHON_ENV}; without "
                             "it PyFMRheo's rows say 'not run')")
    parser.add_argument("--skip-targets", action="store_true", help="without the first table")
    parser.add_argument("--skip-raw", action="store_true", help="without the raw-curve table")
    args = parser.parse_args(argv)
    if not args.skip_targets:
        target_table(args.repeats)
    power_law_table(args.pyfmrheo_python, args.repeats)
    if not args.skip_raw:
        raw_table(args.pyfmrheo_python, args.repeats)


RAW_SAMPLES, RAW_K, RAW_Z_C, RAW_BASELINE, RAW_BEFORE = 8000, 0.5, 2e-6, 3e-8, 0.5


def raw_curve(true):
    """(t, piezo, deflection) of the raw approach and retract, and the contact part (times
    from contact, indentation, force, noise-free force)."""
    total = RAW_BEFORE + 2.0 * T_PEAK
    t = np.linspace(0.0, total, RAW_SAMPLES)
    s = t - RAW_BEFORE
    inside = s > 0
    depth = np.where(s <= T_PEAK, RATE * s, RATE * (2.0 * T_PEAK - s))
    scene = mv.Scene(indenter=mv.Paraboloid(c=1 / (2 * RADIUS)), medium=true,
                     depth=([0.0, T_PEAK, 2.0 * T_PEAK], [0.0, RATE * T_PEAK, 0.0]), duration=2.0 * T_PEAK,
                     times=s[inside], dt=1e-4)
    force = np.zeros_like(t)
    force[inside] = mv.solve(scene, "mdr", 4000).force
    bend = force / RAW_K
    rng = np.random.default_rng(0)
    deflection = bend + RAW_BASELINE + 0.01 * np.max(bend) * rng.standard_normal(t.size)
    z = RAW_Z_C + depth + bend
    measured = RAW_K * (deflection - RAW_BASELINE)
    return (t, z, deflection), (s[inside], depth[inside], measured[inside], force[inside])


@contextlib.contextmanager
def elements_stepped():
    """``mv.fit`` with its forward model's Ting solution off (every curve's elements stepped):
    the path that raw curves took before Ting's solution covered the cantilever."""
    original = fitting.curves

    def stepped(*args, **kwargs):
        curve, estimate = original(*args, **kwargs)
        return curve.elements_only(), estimate

    fitting.curves = stepped
    try:
        yield
    finally:
        fitting.curves = original


def raw_table(python, repeats) -> None:
    cases = [("standard solid", mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2)),
             ("power law", mv.PowerLaw(G0=1e3, beta=0.2, t0=1.0)),
             ("Kelvin-Voigt", mv.KelvinVoigt(G=1e3, eta=200.0))]
    header(f"Raw AFM curves: {RAW_SAMPLES} samples (approach + retract), k = {RAW_K} N/m, 1 % noise, "
           f"MDR n = {N}, best of {repeats}; target <= 0.050 s a fit")
    tip = mv.Paraboloid(c=1 / (2 * RADIUS))
    rows = []
    for label, true in cases:
        (t, z, deflection), (s, depth, force, clean) = raw_curve(true)
        cls = type(true)
        seconds, raw = best_of(lambda t=t, z=z, d=deflection, cls=cls: mv.fit(
            tip, cls, t, piezo=z, deflection=d, spring_constant=RAW_K, n=N), repeats)
        truth = max(abs(raw.parameters[k] / v - 1) for k, v in parameters(true).items() if k != "t0")
        rows.append([label, f"mv.fit raw ({raw.forward})", raw.nfev, seconds, 0.05, truth,
                     (raw.contact_point - RAW_Z_C) * 1e9, raw.success])
        with elements_stepped():
            seconds, raw = best_of(lambda t=t, z=z, d=deflection, cls=cls: mv.fit(
                tip, cls, t, piezo=z, deflection=d, spring_constant=RAW_K, n=N), 1)
        truth = max(abs(raw.parameters[k] / v - 1) for k, v in parameters(true).items() if k != "t0")
        rows.append([label, f"mv.fit raw ({raw.forward})", raw.nfev, seconds, None, truth,
                     (raw.contact_point - RAW_Z_C) * 1e9, raw.success])
        seconds, ting = best_of(lambda s=s, d=depth, f=force, cls=cls: mv.fit(
            tip, cls, s, depth=d, force=f, n=N), repeats)
        truth = max(abs(ting.parameters[k] / v - 1) for k, v in parameters(true).items() if k != "t0")
        rows.append([label, f"mv.fit contact part, depth control ({ting.forward})", ting.nfev, seconds, None,
                     truth, None, ting.success])
        if not isinstance(true, mv.PowerLaw):
            continue
        if python is None:
            rows.append([label, "PyFMRheo (not run: no --pyfmrheo-python)"] + [None] * 6)
            continue
        guess = mv.PowerLaw(G0=1.6e3, beta=0.12, t0=1.0)
        theirs = pyfmrheo_fit(python, "paraboloid", RADIUS, s, depth, force, clean, true, guess, repeats)
        if "failed" in theirs:
            rows.append([label, f"PyFMRheo (failed: {theirs['failed']})"] + [None] * 6)
            continue
        truth = max(abs(theirs["E0"] / 3.0 / true.G0 - 1), abs(theirs["betaE"] / true.beta - 1))
        rows.append([label, f"PyFMRheo {theirs['version']} Ting, contact part", theirs["evaluations"],
                     theirs["seconds"], None, truth, None, theirs["success"]])
    table(["medium", "method", "evaluations", "wall s", "target s", "max rel. err vs true", "z_c - true nm",
           "success"], rows, ["{}", "{}", "{}", "{:.4f}", "{:.3f}", "{:.2e}", "{:+.2f}", "{}"])


def target_table(repeats) -> None:
    args = argparse.Namespace(repeats=repeats)
    cases = [
        ("standard solid", mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2), 0.2),
        ("Prony, 3 terms", mv.Prony(G_inf=1e3, terms=((2e3, 0.01), (1.5e3, 0.08), (1e3, 0.5))), 1.0),
    ]
    header(f"Fits to a {SAMPLES}-point sphere curve, 1 % noise, MDR n = {2 * N} (best of {args.repeats})")
    rows = []
    for label, true, target in cases:
        t, depth, force = curve(true)
        factors = np.resize([1.6, 0.6, 2.5, 0.7], len(parameters(true)))
        scaled = {k: v * f for (k, v), f in zip(parameters(true).items(), factors)}
        guess = medium_of(type(true), scaled, true.nu)
        ours_s, ours = best_of(lambda g=guess, t=t, d=depth, f=force: mv.fit(
            mv.Sphere(radius=RADIUS), g, t, depth=d, force=f, n=N), args.repeats)
        start = time.perf_counter()
        theirs, solves = scipy_fit(guess, t, depth, force)
        scipy_s = time.perf_counter() - start
        mine, other = parameters(ours.medium), parameters(theirs)
        in_errors = max(abs(mine[k] - other[k]) / ours.stderr[k] for k in mine)
        truth = max(abs(mine[k] / v - 1) for k, v in parameters(true).items())
        rows.append([label, "mv.fit", ours.nfev, ours_s, target, truth, in_errors])
        rows.append([label, "least_squares + mv.solve", solves, scipy_s, None, None, None])
        rows.append([label, "ratio", None, scipy_s / ours_s, None, None, None])
    table(["case", "method", "nfev", "wall s", "target s", "max rel. err vs true", "|diff| / stderr"], rows,
          ["{}", "{}", "{}", "{:.3f}", "{:.1f}", "{:.2e}", "{:.2f}"])


if __name__ == "__main__":
    main()
