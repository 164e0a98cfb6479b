"""Fitting a standard solid to a raw AFM force curve
=================================================

A raw AFM curve as the instrument records it: the piezo displacement z (increasing towards
the sample) and the cantilever deflection, with the cantilever's spring constant. A 5 um
sphere approaches a soft viscoelastic gel from 0.3 um away at 0.5 um/s, presses 0.5 um into
it and is pulled back at the same rate; 1,300 samples with deflection noise of 1 % of the
largest deflection change. ``mv.fit`` takes the tip, the medium's class and the raw curve,
estimates the deflection baseline and the contact point from the curve, and fits them
together with the medium: the indentation is (z - z_c) - (deflection - b) and the force
k (deflection - b). The figure shows the raw curve, then force against the fitted
indentation with the fit, and the residuals.

The "measured" curve is made here by a fine MDR solve of a known gel (G_inf = 800 Pa,
G1 = 1.2 kPa, tau1 = 0.3 s), contact at z_c = 3.2 um, baseline 20 nm, k = 0.5 N/m, so that
the fit can be checked against it.

    python examples/fit_afm_curve.py [FIGURE.png]
"""

import sys

import matplotlib.pyplot as plt
import numpy as np

import mdrvisc as mv


def main(out=None):
    tip = mv.Sphere(radius=5e-6)
    gel = mv.StandardSolid(G_inf=800.0, G1=1200.0, tau1=0.3)
    k, z_c, baseline, rate, t_contact = 0.5, 3.2e-6, 2e-8, 5e-7, 0.6

    # the instrument's record: indentation from the moment of contact, by a fine MDR solve
    t = np.linspace(0.0, t_contact + 2.0, 1301)
    s = t - t_contact
    indentation = np.where(s <= 1.0, rate * s, rate * (2.0 - s))
    inside = s > 0
    scene = mv.Scene(indenter=tip, medium=gel, depth=([0.0, 1.0, 2.0], [0.0, 5e-7, 0.0]), duration=2.0,
                     times=s[inside], dt=5e-4)
    force = np.zeros_like(t)
    force[inside] = mv.solve(scene, "mdr", 8000).force
    bend = force / k
    rng = np.random.default_rng(1)
    deflection = baseline + bend + 0.01 * bend.max() * rng.standard_normal(t.size)
    piezo = z_c + indentation + bend

    result = mv.fit(tip, mv.StandardSolid, t, piezo=piezo, deflection=deflection, spring_constant=k)
    print(result)
    for name, true in (("G_inf", gel.G_inf), ("G1", gel.G1), ("tau1", gel.tau1)):
        value, err = result.parameters[name], result.stderr[name]
        print(f"{name:>13}: true {true:8.4g}, fitted {value:8.4g} +- {err:.2g} "
              f"({(value - true) / err:+.2f} standard errors)")
    err = result.stderr["contact_point"]
    print(f"contact point: true {z_c * 1e6:.4f} um, fitted {result.contact_point * 1e6:.4f} um +- "
          f"{err * 1e9:.2f} nm ({(result.contact_point - z_c) / err:+.2f} standard errors)")

    fig, (raw, top, bottom) = plt.subplots(3, 1, figsize=(6, 7), height_ratios=[2, 2, 1])
    raw.plot(piezo * 1e6, deflection * 1e9, ".", ms=2, color="0.6", label="raw curve")
    raw.axvline(result.contact_point * 1e6, color="C3", lw=0.8, label="fitted contact point")
    raw.axhline(result.baseline * 1e9, color="C0", lw=0.8, label="fitted baseline")
    raw.set_xlabel("piezo z [um]")
    raw.set_ylabel("deflection [nm]")
    raw.legend(fontsize=8)
    top.plot(result.depth * 1e9, result.data * 1e9, ".", ms=2, color="0.6", label="data (1 % noise)")
    top.plot(result.depth * 1e9, result.model * 1e9, "-", color="C3", label="fitted standard solid")
    top.set_ylabel("force [nN]")
    top.legend(fontsize=8)
    bottom.plot(result.depth * 1e9, result.residuals * 1e9, ".", ms=2, color="C0")
    bottom.axhline(0.0, color="k", lw=0.5)
    bottom.set_xlabel("indentation at the fitted contact point [nm]")
    bottom.set_ylabel("residual [nN]")
    fig.tight_layout()
    if out:
        fig.savefig(out, dpi=120)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
