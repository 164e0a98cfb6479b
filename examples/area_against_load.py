"""Real contact area against load
================================

A rigid rough surface pressed onto an elastic half-space at ten loads, in one call of
``mv.load_curve``: each solve starts from the pressure of the one before and gives the same
result as a solve of its own. On a periodic cell this large the solver's nested coarse grids
already start each solve well, so the warm start saves few iterations (printed below); on a
non-periodic map it saves more.

The surface is one periodic cell of a Gaussian self-affine surface
(``mv.surfaces.self_affine``: Hurst exponent 0.8, rms slope 0.1, roll-off wavelength 64 um,
shortest wavelength 16 um, on 256 x 256 elements of 1 um). At light loads the real contact
area grows in proportion to the load, A / A0 = kappa p / (E* h'), with p the nominal
pressure, E* the contact modulus and h' the rms slope; for surfaces whose spectrum spans many
decades the theories put kappa between sqrt(8 / pi) = 1.6 (Persson) and sqrt(2 pi) = 2.5
(Bush, Gibson and Thomas). This cell's spectrum spans a factor of 4 in wavelength, and its
kappa at light loads, printed below, comes out above both. The curve bends over as the
contact approaches full contact.

Run: python examples/area_against_load.py [OUT.png]   (default OUT: area_against_load.png)
"""

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description="Real contact area against load")
    parser.add_argument("out", nargs="?", default="area_against_load.png")
    args = parser.parse_args()

    n, dx, slope = 256, 1e-6, 0.1                     # elements, m, rms slope
    heights = mv.surfaces.self_affine((n, n), dx, hurst=0.8, rms_slope=slope, rolloff=64e-6,
                                      short_cutoff=16e-6, seed=7)
    surface = mv.HeightMap(heights, dx, periodic=True)
    G = 1e6                                           # Pa: shear modulus, E* = 4 G
    e_star = 4.0 * G
    cell = (n * dx) ** 2                              # m^2, the nominal area A0
    pressures = e_star * slope * np.geomspace(0.01, 1.0, 10)   # Pa, nominal
    scene = mv.Scene(indenter=surface, medium=mv.Elastic(G=G), force=pressures[0] * cell)

    curve = mv.load_curve(scene, pressures * cell, tol=1e-8)
    print(curve.summary())
    table = curve.to_dataframe()
    table["p / (E* h')"] = table["force"] / cell / (e_star * slope)
    print(table[["force", "p / (E* h')", "contact_fraction", "patches", "mean_gap"]].to_string(index=False))
    reduced = table["p / (E* h')"].to_numpy()
    print(f"kappa at the lightest load: {table['contact_fraction'].iloc[0] / reduced[0]:.2f}")

    # The warm starts: iterations of each solve (coarse levels included) against those of
    # the same loads solved one at a time (the first solve of the curve is a cold one).
    warm = [r.iterations for r in curve.results]
    cold = [mv.solve(s, tol=1e-8).iterations for s in curve.scenes]
    print("iterations, load curve:", warm, "sum", sum(warm))
    print("iterations, one by one:", cold, "sum", sum(cold))

    # The figure: the contact fraction against the reduced pressure, with the light-load
    # slopes of the theories.
    x = table["p / (E* h')"].to_numpy()
    fraction = table["contact_fraction"].to_numpy()
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.loglog(x, fraction, "o-", label="BEM, periodic cell (mv.load_curve)")
    for kappa, name, style in ((math.sqrt(8.0 / math.pi), "Persson, kappa = 1.6", ":"),
                               (math.sqrt(2.0 * math.pi), "Bush et al., kappa = 2.5", "--")):
        ax.loglog(x, np.minimum(kappa * x, 1.0), style, color="0.4", lw=1.0, label=name)
    ax.set_xlabel("nominal pressure / (E* rms slope)")
    ax.set_ylabel("real contact area / nominal area")
    ax.set_title("Self-affine surface, H = 0.8, on an elastic half-space")
    ax.legend()
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
