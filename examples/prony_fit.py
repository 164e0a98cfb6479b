"""Fitting a Prony series to relaxation data
=========================================

Fit a Prony series to a relaxation curve given as data, then indent with it.

The data here are a measured-looking relaxation curve G(t) (Pa) sampled over six decades
(made from a stretched exponential with 0.5 % noise, so that no finite Prony series is
exact). The fit puts relaxation times tau_k on a log grid, two per decade, and finds
G_inf, G_k >= 0 by non-negative least squares (scipy.optimize.nnls) on the relative
residual. The fitted medium then indents a paraboloid by MDR and by BEM under a step force.

Run: python examples/prony_fit.py [OUT.png]   (default OUT: prony_fit.png)
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy.optimize import nnls  # noqa: E402

import mdrvisc as mv  # noqa: E402


def fit_prony(t, g, per_decade=2):
    """G_inf and terms [(G_k, tau_k)] with G_k >= 0 fitting G(t) at times t (s)."""
    count = int(per_decade * np.log10(t.max() / t.min())) + 1
    taus = np.logspace(np.log10(t.min()), np.log10(t.max()), count)
    basis = np.column_stack([np.ones_like(t)] + [np.exp(-t / tau) for tau in taus]) / g[:, None]
    coef, _ = nnls(basis, np.ones_like(t))
    terms = [(float(c), float(tau)) for c, tau in zip(coef[1:], taus) if c > 0]
    return float(coef[0]), terms


def main():
    parser = argparse.ArgumentParser(description="A Prony series fitted to relaxation data")
    parser.add_argument("out", nargs="?", default="prony_fit.png")
    args = parser.parse_args()
    rng = np.random.default_rng(7)
    t = np.geomspace(1e-3, 1e3, 60)
    data = 1e6 * (0.2 + 0.8 * np.exp(-(t / 1.0) ** 0.4)) * (1 + 0.005 * rng.standard_normal(t.size))
    g_inf, terms = fit_prony(t, data)
    medium = mv.Prony(G_inf=g_inf, terms=terms)
    fit = medium.relaxation_modulus(t)
    print(f"Prony fit: G_inf = {g_inf:.4g} Pa, {len(terms)} terms, "
          f"max relative misfit {np.max(np.abs(fit / data - 1)):.2%} (noise 0.5 %)")
    # a first output right after the load step captures the instantaneous (glassy) response
    scene = mv.Scene(indenter=mv.Paraboloid(c=50.0), medium=medium, force=0.1, duration=100.0,
                     times=np.concatenate([[1e-7], np.geomspace(1e-3, 100.0, 9)]))
    mdr = mv.solve(scene, "mdr", 20001, dt=0.5)
    bem = mv.solve(scene, "bem", 65, dt=0.5)
    lee_radok = (3 * 0.1 * medium.creep_compliance(scene.times) / (16 * np.sqrt(1 / 100.0))) ** (2 / 3)
    print(f"{'t [s]':>10} {'d MDR [m]':>12} {'d BEM [m]':>12} {'Lee-Radok [m]':>14}")
    for row in zip(scene.times, mdr.depth, bem.depth, lee_radok):
        print(f"{row[0]:>10.3g} {row[1]:>12.5e} {row[2]:>12.5e} {row[3]:>14.5e}")
    print(mdr.summary())
    print(bem.summary())

    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.0))
    left.semilogx(t, data / 1e6, "o", ms=3, color="0.5", label="data")
    left.semilogx(t, fit / 1e6, "-", label=f"Prony series, {len(terms)} terms")
    left.set_xlabel("t (s)")
    left.set_ylabel("G(t) (MPa)")
    left.set_title("relaxation modulus")
    left.legend()
    late = scene.times > 1e-6
    right.semilogx(scene.times[late], lee_radok[late] * 1e3, "-", color="0.6", lw=3,
                   label="Lee-Radok (closed form)")
    right.semilogx(scene.times[late], mdr.depth[late] * 1e3, "o", label="MDR, n = 20001")
    right.semilogx(scene.times[late], bem.depth[late] * 1e3, "x", label="BEM, 65 x 65")
    right.set_xlabel("t (s)")
    right.set_ylabel("depth (mm)")
    right.set_title("paraboloid under a step force of 0.1 N")
    right.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
