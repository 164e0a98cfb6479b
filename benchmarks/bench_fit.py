"""Fits of media to a 2,000-point sphere curve (R = 5 um, approach and retract at 1 um/s
over 2 s, 1 % Gaussian noise, seed 0): ``mv.fit`` against the same fit done today's way,
``scipy.optimize.least_squares`` (trust-region reflective, 2-point finite differences, in
the logarithms of the parameters) around ``mv.solve(scene, "mdr", n)``. Both start from
the same guess (the true values times 1.6, 0.6, 2.5, ...) and use the same element count.
Targets: standard solid <= 0.2 s, Prony with 3 terms <= 1 s.

The data come from ``mv.solve`` (MDR, n = 4000, dt = 1e-4 s): a benchmark of speed; the
fit's accuracy against independent references is in ``tests/test_fit.py``. PyFMRheo is
not compared here: its Ting fit covers the power law on a paraboloid or cone only.

Run: ``python benchmarks/bench_fit.py [--repeats 3]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
from scipy.optimize import least_squares

import mdrvisc as mv
from _bench import best_of, header, table
from mdrvisc.fitting import _medium, _parameters

RADIUS, RATE, T_PEAK, SAMPLES, N = 5e-6, 1e-6, 1.0, 2000, 500


def curve(true):
    t = np.linspace(0.0, 2.0 * T_PEAK, SAMPLES + 1)[1:]
    scene = mv.Scene(indenter=mv.Sphere(radius=RADIUS), medium=true,
                     depth=([0.0, T_PEAK, 2.0 * T_PEAK], [0.0, RATE * T_PEAK, 0.0]), duration=2.0 * T_PEAK,
                     times=t, dt=1e-4)
    force = mv.solve(scene, "mdr", 4000).force
    depth = np.where(t <= T_PEAK, RATE * t, RATE * (2 * T_PEAK - t))
    rng = np.random.default_rng(0)
    return t, depth, force + 0.01 * force.max() * rng.standard_normal(t.size)


def scipy_fit(guess, t, depth, force):
    """Today's way: least_squares around mv.solve, parameters in logs."""
    names = list(_parameters(guess))
    base = _parameters(guess)
    solves = 0

    def residuals(x):
        nonlocal solves
        solves += 1
        medium = _medium(type(guess), {**base, **dict(zip(names, np.exp(x)))})
        history = (np.concatenate([[0.0], t]), np.concatenate([[0.0], depth]))
        scene = mv.Scene(indenter=mv.Sphere(radius=RADIUS), medium=medium, depth=history,
                         duration=float(t[-1]), times=t, dt=float(t[1] - t[0]))
        return (mv.solve(scene, "mdr", 2 * N).force - force) / force.max()

    result = least_squares(residuals, np.log([base[k] for k in names]), method="trf")
    return _medium(type(guess), dict(zip(names, np.exp(result.x)))), solves


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args(argv)
    cases = [
        ("standard solid", mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.2), 0.2),
        ("Prony, 3 terms", mv.Prony(G_inf=1e3, terms=((2e3, 0.01), (1.5e3, 0.08), (1e3, 0.5))), 1.0),
    ]
    header(f"Fits to a {SAMPLES}-point sphere curve, 1 % noise, MDR n = {2 * N} (best of {args.repeats})")
    rows = []
    for label, true, target in cases:
        t, depth, force = curve(true)
        factors = np.resize([1.6, 0.6, 2.5, 0.7], len(_parameters(true)))
        guess = _medium(type(true), {k: v * f for (k, v), f in zip(_parameters(true).items(), factors)})
        ours_s, ours = best_of(lambda g=guess, t=t, d=depth, f=force: mv.fit(
            mv.Sphere(radius=RADIUS), g, t, depth=d, force=f, n=N), args.repeats)
        start = time.perf_counter()
        theirs, solves = scipy_fit(guess, t, depth, force)
        scipy_s = time.perf_counter() - start
        mine, other = _parameters(ours.medium), _parameters(theirs)
        in_errors = max(abs(mine[k] - other[k]) / ours.stderr[k] for k in mine)
        truth = max(abs(mine[k] / v - 1) for k, v in _parameters(true).items())
        rows.append([label, "mv.fit", ours.solves, ours_s, target, truth, in_errors])
        rows.append([label, "least_squares + mv.solve", solves, scipy_s, None, None, None])
        rows.append([label, "ratio", None, scipy_s / ours_s, None, None, None])
    table(["case", "method", "solves", "wall s", "target s", "max rel. err vs true", "|diff| / stderr"], rows,
          ["{}", "{}", "{}", "{:.3f}", "{:.1f}", "{:.2e}", "{:.2f}"])


if __name__ == "__main__":
    main()
