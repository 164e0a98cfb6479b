"""Real contact area of a rough surface creeping on a standard solid
===================================================================

A rigid rough surface pressed with a constant force onto a standard linear solid (an
elastomer-like body: relaxation modulus G(t) = G_inf + G1 exp(-t / tau)). The body creeps
into the roughness: the real contact area grows from that of an elastic body with the glassy
modulus G_inf + G1 to that of one with the rubbery modulus G_inf, and the contact patches
multiply and merge on the way.

The surface is one periodic cell of a Gaussian self-affine surface from
``mv.surfaces.self_affine`` (Hurst exponent 0.8, rms height 1 um, roll-off wavelength 64 um,
shortest wavelength 16 um, on 256 x 256 elements of 1 um: the contact patches span more than
10 elements on average, so that their area is resolved). It is solved as a periodic
``mv.HeightMap`` by BEM on its own grid; the force is the total on the cell (the nominal
pressure times its area).
The two elastic limits are solved statically and drawn as dashed lines; the creep time
tau (G_inf + G1) / G_inf is 10 s, so at 100 s the creep is complete to exp(-10).

Run: python examples/rough_creep.py [OUT.png]   (default OUT: rough_creep.png)
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description="Rough contact creeping on a standard solid")
    parser.add_argument("out", nargs="?", default="rough_creep.png")
    args = parser.parse_args()

    n, dx = 256, 1e-6                                   # 256 x 256 elements of 1 um
    heights = mv.surfaces.self_affine((n, n), dx, hurst=0.8, rms_height=1e-6, rolloff=64e-6,
                                      short_cutoff=16e-6, seed=11)
    surface = mv.HeightMap(heights, dx, periodic=True)
    g_inf, g1, tau = 1e6, 9e6, 1.0                      # Pa, Pa, s: glassy modulus 10 MPa
    nominal = 0.1e6                                     # Pa, nominal pressure on the cell
    force = nominal * (n * dx) ** 2                     # N, the total on the cell
    times = np.geomspace(0.01, 100.0, 40)
    scene = mv.Scene(indenter=surface, medium=mv.StandardSolid(G_inf=g_inf, G1=g1, tau1=tau),
                     force=force, duration=100.0, times=times, dt=0.5,
                     outputs=("depth", "pressure"), field_times=[100.0])
    creep = mv.solve(scene, tol=1e-8)
    print(creep.summary())

    def elastic(g):
        return mv.solve(mv.Scene(indenter=surface, medium=mv.Elastic(G=g), force=force), tol=1e-8)
    glassy, rubbery = elastic(g_inf + g1), elastic(g_inf)
    print("            t [s]   A/A0     patches   mean gap [um]")
    for k in range(0, len(times), 8):
        print(f"  creep {creep.t[k]:9.3f} {creep.contact_fraction[k]:8.4f} {creep.patches[k]:9d}"
              f" {creep.mean_gap[k] * 1e6:12.4f}")
    for name, r in (("glassy", glassy), ("rubbery", rubbery)):
        print(f"  {name:7s} elastic {r.contact_fraction[0]:8.4f} {r.patches[0]:9d}"
              f" {r.mean_gap[0] * 1e6:12.4f}")

    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    extent = np.array([surface.x[0], surface.x[-1], surface.y[0], surface.y[-1]]) * 1e6
    left.imshow(surface.heights * 1e6, origin="lower", extent=extent, cmap="Greys_r")
    contact = np.ma.masked_where(creep.fields[100.0].pressure <= 0, creep.fields[100.0].pressure)
    shown = left.imshow(contact / 1e6, origin="lower", extent=extent, cmap="autumn")
    fig.colorbar(shown, ax=left, label="contact pressure at t = 100 s (MPa)")
    left.set_xlabel("x (um)")
    left.set_ylabel("y (um)")
    left.set_title("surface (grey) and contact at the end")
    right.semilogx(creep.t, creep.contact_fraction, "o-", ms=3, label="creep (BEM, periodic cell)")
    # each limit labelled where the curve is far from it
    for r, name, at, align in ((glassy, "elastic, glassy G_inf + G1", times[-1], "right"),
                               (rubbery, "elastic, rubbery G_inf", times[0], "left")):
        right.axhline(r.contact_fraction[0], ls="--", color="0.5", lw=0.9)
        right.annotate(name, (at, r.contact_fraction[0]), va="bottom", ha=align, fontsize=8, color="0.3")
    right.set_xlabel("t (s)")
    right.set_ylabel("real contact area / nominal area")
    right.set_title(f"standard solid, tau = {tau:g} s, nominal pressure {nominal / 1e6:g} MPa")
    right.legend(loc="center left")
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
