"""Fitting a standard solid to an AFM force curve
==============================================

An AFM-style force curve: a 5 um sphere pressed 0.5 um into a soft viscoelastic gel at
0.5 um/s and pulled back at the same rate, 1,000 samples with 1 % force noise. ``mv.fit``
takes the tip, the medium's class and the curve (depth prescribed, force measured),
estimates an initial guess from the data, and returns the fitted standard solid with
standard errors; the figure shows data, fit and residuals.

The "measured" curve is made here by a fine MDR solve of a known gel (G_inf = 800 Pa,
G1 = 1.2 kPa, tau1 = 0.3 s) so that the fit can be checked against it.

    python examples/fit_afm_curve.py [FIGURE.png]
"""

import sys

import matplotlib.pyplot as plt
import numpy as np

import mdrvisc as mv


def main(out=None):
    tip = mv.Sphere(radius=5e-6)
    gel = mv.StandardSolid(G_inf=800.0, G1=1200.0, tau1=0.3)
    t = np.linspace(0.0, 2.0, 1001)[1:]
    scene = mv.Scene(indenter=tip, medium=gel, depth=([0.0, 1.0, 2.0], [0.0, 5e-7, 0.0]), duration=2.0,
                     times=t, dt=5e-4)
    measured = mv.solve(scene, "mdr", 8000)
    rng = np.random.default_rng(1)
    force = measured.force + 0.01 * measured.force.max() * rng.standard_normal(t.size)
    depth = np.where(t <= 1.0, 5e-7 * t, 5e-7 * (2.0 - t))

    result = mv.fit(tip, mv.StandardSolid, t, depth=depth, force=force)
    print(result)
    for name, true in (("G_inf", gel.G_inf), ("G1", gel.G1), ("tau1", gel.tau1)):
        value, err = result.parameters[name], result.stderr[name]
        print(f"{name:>6}: true {true:8.4g}, fitted {value:8.4g} +- {err:.2g} "
              f"({(value - true) / err:+.2f} standard errors)")

    fig, (top, bottom) = plt.subplots(2, 1, sharex=True, figsize=(6, 5), height_ratios=[3, 1])
    top.plot(depth * 1e9, force * 1e9, ".", ms=2, color="0.6", label="data (1 % noise)")
    top.plot(depth * 1e9, result.model * 1e9, "-", color="C3", label="fitted standard solid")
    top.set_ylabel("force [nN]")
    top.legend()
    bottom.plot(depth * 1e9, result.residuals * 1e9, ".", ms=2, color="C0")
    bottom.axhline(0.0, color="k", lw=0.5)
    bottom.set_xlabel("indentation depth [nm]")
    bottom.set_ylabel("residual [nN]")
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
