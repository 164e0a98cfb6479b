"""PyFMRheo side of bench_fit.py: Ting's power-law fit of one indentation curve, run in
PyFMRheo's own environment.

This file imports neither mdrvisc nor the benchmark helpers, so that it runs in a venv
that holds only PyFMRheo (``pip install pyfmrheo``; see benchmarks/README.md). The driver
writes the curve to an .npz file (t in s, depth in m, the measured force and the
noise-free force in N, the sample of the turning point) and calls, with PYTHON that venv's
interpreter,

    PYTHON pyfmrheo_worker.py --curve CURVE.npz --tip paraboloid --tip-param 5e-6 \\
        --rate 1e-6 --t0 1 --e0 4800 --beta 0.12 --true-e0 3000 --true-beta 0.2 --repeats 3

and reads one JSON document from the last line of stdout.

What runs: ``pyfmrheo.models.ting.TingModel(tip, tip_param, "analytical").model`` (Ting's
closed forms for a power-law modulus E(t) = E0 (t / t0)^-betaE, approach at v0t and
retract at v0r, the retract's hypergeometric function by Butler and Wood's approximation)
fitted with ``lmfit.Model`` exactly as ``TingModel.fit`` does (which keeps the fit's
result, and so the standard errors, to itself): free E0 and betaE from the given
initial values, bounds as PyFMRheo's own TingFit routine sets them (E0 > 0, betaE in
[0.01, 0.49] on a paraboloid, [0.01, 0.99] on a cone), the contact time tc and the force
offset F0 held at 0 (the curve starts at contact with zero force, as mdrvisc's fit is
given it), v0t = v0r = the rate, idx_tm the turning point. Timed: the ``fit`` call (best
of --repeats, wall clock); standard errors: lmfit's, from the covariance of its
least-squares solution scaled by the reduced chi-square. Besides, PyFMRheo's curve at the
true values (--true-e0, --true-beta) against the noise-free force: its largest deviation
on the approach and on the retract, relative to the largest force (the accuracy of its
closed forms, and a check of the conventions below).

Conventions (PyFMRheo 0.1.3, ``models/geom_coeffs.py``): E0 is Young's modulus E at t0
(not the contact modulus), with the Poisson ratio 0.5: the paraboloid's coefficient
4/3 sqrt(R) / (1 - nu^2), the cone's 2/pi tan(theta) / (1 - nu^2) with theta the
half-angle in degrees. The time t is measured from contact, t0 is a reference time.
"""

from __future__ import annotations

import argparse
import json
import time

import numpy as np


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--curve", required=True)
    ap.add_argument("--tip", choices=("paraboloid", "cone"), required=True)
    ap.add_argument("--tip-param", type=float, required=True,
                    help="radius (m) of a paraboloid, half-angle (degrees) of a cone")
    ap.add_argument("--rate", type=float, required=True, help="approach and retract rate (m/s)")
    ap.add_argument("--t0", type=float, required=True, help="reference time of the power law (s)")
    ap.add_argument("--e0", type=float, required=True, help="initial E0 (Pa)")
    ap.add_argument("--beta", type=float, required=True, help="initial betaE")
    ap.add_argument("--true-e0", type=float, required=True, help="E0 of the noise-free curve (Pa)")
    ap.add_argument("--true-beta", type=float, required=True, help="betaE of the noise-free curve")
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()

    from importlib.metadata import version

    import lmfit
    from pyfmrheo.models.ting import TingModel

    data = np.load(args.curve)
    t, depth, force, turn = data["t"], data["depth"], data["force"], int(data["turn"])
    clean = data["clean"]
    ting = TingModel(args.tip, args.tip_param, "analytical")
    held = {"t0": args.t0, "F": force, "delta": depth, "modelFt": "analytical", "vdrag": 0.0,
            "smooth_w": None, "idx_tm": turn, "v0t": args.rate, "v0r": args.rate}

    def curve(time, E0, tc, betaE, F0):  # noqa: N803 (PyFMRheo's names)
        return ting.model(time, E0, tc, betaE, F0, **held)

    model = lmfit.Model(curve)
    params = lmfit.Parameters()
    params.add("E0", value=args.e0, min=0.0, max=np.inf)
    params.add("tc", value=0.0, vary=False)
    params.add("betaE", value=args.beta, min=0.01, max=0.49 if args.tip == "paraboloid" else 0.99)
    params.add("F0", value=0.0, vary=False)

    best, result = float("inf"), None
    for _ in range(args.repeats):
        start = time.perf_counter()
        result = model.fit(force, params, time=t)
        best = min(best, time.perf_counter() - start)
    at_true = curve(t, args.true_e0, 0.0, args.true_beta, 0.0)
    deviation = np.abs(at_true - clean) / np.max(clean)
    out = {
        "deviation_approach": float(np.max(deviation[: turn + 1])),
        "deviation_retract": float(np.max(deviation[turn + 1:])),
        "version": version("pyfmrheo"),
        "seconds": best,
        "evaluations": int(result.nfev),
        "success": bool(result.success),
        "E0": float(result.params["E0"].value),
        "E0_stderr": float(result.params["E0"].stderr or float("nan")),
        "betaE": float(result.params["betaE"].value),
        "betaE_stderr": float(result.params["betaE"].stderr or float("nan")),
        "rms": float(np.sqrt(np.mean(result.residual ** 2))),
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
