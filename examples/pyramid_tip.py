"""A four-sided pyramid tip: the exact BEM against MDR's equivalent cone
=======================================================================

AFM cantilever tips are four-sided pyramids, h = max(``|x|``, ``|y|``) / tan(alpha), alpha the
face half-angle. The BEM solves that shape exactly; MDR, which needs an axisymmetric indenter,
solves an equivalent cone: Bilodeau's, tan(psi) = 0.7453 (pi/2) tan(alpha), whose elastic
force is F = 0.7453 E* tan(alpha) d^2 (E* = 4 G for an incompressible body).

First the elastic constant k = F pi / (8 G tan(alpha) d^2) of the exact pyramid as the BEM grid
is refined, against Bilodeau's cone and the cone of equal projected area; then the contact's
shape; then a tip pressed 1 um into a standard linear solid and held, by both methods.

Run: python examples/pyramid_tip.py [OUT.png]   (default OUT: pyramid_tip.png)
"""

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402

ALPHA = math.radians(35.0)


def elastic_constant(n):
    """k of the exact pyramid by BEM on an n x n grid (G = 1 Pa, F = 1 N)."""
    scene = mv.Scene(indenter=mv.Pyramid(half_angle=ALPHA), medium=mv.Elastic(G=1.0), force=1.0)
    result = mv.solve(scene, "bem", n)
    return math.pi / (8.0 * result.depth[-1] ** 2 * math.tan(ALPHA))


def contact_shape(n=128):
    """The extents of the BEM contact along the diagonal and along an axis."""
    scene = mv.Scene(indenter=mv.Pyramid(half_angle=ALPHA), medium=mv.Elastic(G=1.0), force=1.0,
                     outputs=("depth", "contact_length", "pressure"))
    result = mv.solve(scene, "bem", n)
    fields = result.fields[0.0]
    contact = fields.pressure > 0
    x = fields.x
    axis = np.max(np.abs(x[contact[n // 2]])) + 0.5 * result.dx
    diagonal = math.sqrt(2.0) * (np.max(np.abs(x[np.diagonal(contact)])) + 0.5 * result.dx)
    return axis, diagonal, result.contact_length[-1] / 2, fields


def relaxation(n_bem=48, n_mdr=4001):
    """A tip pressed 1 um into a standard solid in 1 s and held for 1 s: forces (N)."""
    scene = mv.Scene(indenter=mv.Pyramid(half_angle=ALPHA),
                     medium=mv.StandardSolid(G_inf=4e8, G1=8e8, tau1=0.5),
                     depth=([0.0, 1.0, 2.0], [0.0, 1e-6, 1e-6]), duration=2.0, times=[1.0, 1.5, 2.0])
    return scene.times, mv.solve(scene, "bem", n_bem).force, mv.solve(scene, "mdr", n_mdr).force


def main():
    parser = argparse.ArgumentParser(description="A pyramid tip by BEM and MDR")
    parser.add_argument("out", nargs="?", default="pyramid_tip.png")
    args = parser.parse_args()
    bilodeau, equal_area = 0.7453 * math.pi / 2, 2.0 / math.sqrt(math.pi)
    print("elastic pyramid, alpha = 35 deg: k = F pi / (8 G tan(alpha) d^2)")
    for n in (32, 64, 128, 256):
        k = elastic_constant(n)
        print(f"  BEM {n:4d}^2: k = {k:.6f}; Bilodeau's cone {bilodeau / k - 1:+.2%}, "
              f"equal-area cone {equal_area / k - 1:+.2%}")
    axis, diagonal, radius, fields = contact_shape()
    print(f"contact (BEM 128^2): extent {axis:.4f} m along an axis, {diagonal:.4f} m along the "
          f"diagonal (ratio {diagonal / axis:.2f}; a square's is 1.41); equal-area radius {radius:.4f} m")
    t, bem, mdr = relaxation()
    print("standard solid, depth ramped to 1 um and held:")
    for ti, fb, fm in zip(t, bem, mdr):
        print(f"  t = {ti:.1f} s: BEM {fb:.4e} N, MDR {fm:.4e} N (MDR/BEM {fm / fb:.4f})")

    fig, ax = plt.subplots(figsize=(5.6, 4.6))
    half = 1.3 * diagonal
    inside = np.abs(fields.x) <= half
    pressure = fields.pressure[np.ix_(inside, inside)]
    extent = [fields.x[inside][0], fields.x[inside][-1], fields.y[inside][0], fields.y[inside][-1]]
    shown = ax.imshow(np.ma.masked_where(pressure <= 0, pressure), origin="lower", extent=extent,
                      cmap="viridis")
    ax.add_patch(plt.Circle((0, 0), radius, fill=False, ls="--", color="0.3",
                            label="disc of the same area"))
    fig.colorbar(shown, ax=ax, label="pressure (Pa)")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("pyramid, alpha = 35 deg: contact pressure (BEM 128^2)")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
