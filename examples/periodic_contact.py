"""Periodic contact: Westergaard's wavy surface and a self-affine cell
=====================================================================

A periodic cell is solved whole with ``periodic=True``: the half-space's spectral kernel
u_q = p_q / (2 G abs(q)) at the cell's wavevectors, with deflections of zero mean, so that
the force is the total on the cell and the depth is the approach from the deflected
surface's mean plane (mean separation = mean(h) - depth).

First the wavy surface h(x) = g (1 - cos(2 pi x / lambda)) on a cell of one wavelength,
uniform in y, against Westergaard: at mean pressure p = p* sin^2(pi a / lambda),
p* = pi E* g / lambda (E* = 4 G), the contact half-width is a and the mean separation
g (1 - P (1 - ln P)), P = p / p*. Then a Gaussian self-affine surface from
``mv.surfaces.self_affine``, its measured spectrum, and its contact at about 5 % of the
cell, periodic and not.

Run: python examples/periodic_contact.py [OUT.png]   (default OUT: periodic_contact.png)
"""

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import mdrvisc as mv  # noqa: E402


def wavy_surface(n=512, g=1e-6, wavelength=1e-4, G=1e6, ratio=0.3):
    """Westergaard's wavy surface at p = ratio p*: printed against the closed forms."""
    dx = wavelength / n
    x = (np.arange(n) - n // 2 + 0.5) * dx
    h = np.tile(g * (1 - np.cos(2 * np.pi * x / wavelength)), (4, 1))
    p_star = np.pi * 4 * G * g / wavelength
    pbar = ratio * p_star
    r = mv.arrays.contact(h, dx, G, force=pbar * h.size * dx * dx, periodic=True)
    p = r.fields[0.0].pressure[0]
    half_width = np.count_nonzero(p > 0) * dx / 2
    a = wavelength / np.pi * np.arcsin(np.sqrt(ratio))
    s = np.sin(np.pi * x / wavelength) ** 2
    exact = np.where(s < ratio, 2 * pbar * np.cos(np.pi * x / wavelength) / ratio
                     * np.sqrt(np.clip(ratio - s, 0, None)), 0)
    separation = h.mean() - r.depth[0]
    closed = g * (1 - ratio * (1 - np.log(ratio)))
    print(f"Westergaard, {n} elements per wavelength, p = {ratio} p*:")
    print(f"  half-width a / lambda {half_width / wavelength:.4f} (exact {a / wavelength:.4f}, "
          f"element {dx / wavelength:.4f})")
    print(f"  pressure error: {np.sum(np.abs(p - exact)) / np.sum(exact):.1e} (relative L1), "
          f"{np.max(np.abs(p - exact)) / exact.max():.1e} of the peak at worst")
    print(f"  mean separation {separation:.6e} m (exact {closed:.6e} m); "
          f"{r.iterations} iterations, {r.solver}")
    return x, p, exact


def rough_cell(n=256, dx=1e-6, G=1e6):
    """A self-affine cell: its spectrum, and its contact at ~5 % periodic and not."""
    z = mv.surfaces.self_affine((n, n), dx, 0.8, rms_slope=0.1, rolloff=n * dx / 4, seed=7)
    q, c = mv.surfaces.psd(z, dx)
    band = (q > 1.5 * 2 * np.pi / (n * dx / 4)) & (q < 0.8 * np.pi / dx)
    slope = np.polyfit(np.log(q[band]), np.log(c[band]), 1)[0]
    print(f"self-affine {n} x {n}: rms height {z.std():.3e} m, PSD slope {slope:.2f} "
          f"(-2 (1 + H) = -3.6)")
    h = z.max() - z
    force = 0.0095 * G * (n * dx) ** 2
    for periodic in (False, True):
        r = mv.arrays.contact(h, dx, G, force=force, periodic=periodic, deflection=False)
        p = r.fields[0.0].pressure
        print(f"  {'periodic' if periodic else 'non-periodic':>12}: contact fraction "
              f"{np.count_nonzero(p > 0) / p.size:.3f}, {r.iterations} iterations, "
              f"{r.wall_time:.2f} s")
    return z, p, dx


def main():
    parser = argparse.ArgumentParser(description="Periodic contact against Westergaard")
    parser.add_argument("out", nargs="?", default="periodic_contact.png")
    args = parser.parse_args()
    x, p, exact = wavy_surface()
    z, pressure, dx = rough_cell()

    fig, (left, right) = plt.subplots(1, 2, figsize=(10.0, 4.2))
    left.plot(x * 1e6, exact / 1e3, "-", color="0.6", lw=3, label="Westergaard")
    left.plot(x * 1e6, p / 1e3, "--", label="BEM, periodic, 512 elements")
    left.set_xlabel("x (um)")
    left.set_ylabel("pressure (kPa)")
    left.set_title("wavy surface at p = 0.3 p*")
    left.legend()
    extent = np.array([0, z.shape[1], 0, z.shape[0]]) * dx * 1e6
    left_map = right.imshow(z * 1e6, origin="lower", extent=extent, cmap="Greys_r")
    right.contour(pressure > 0, levels=[0.5], colors="tab:red", linewidths=0.8, extent=extent)
    fig.colorbar(left_map, ax=right, label="height (um)")
    right.set_xlabel("x (um)")
    right.set_ylabel("y (um)")
    right.set_title("self-affine cell, periodic contact (red)")
    fig.tight_layout()
    fig.savefig(args.out, dpi=100)
    plt.close(fig)
    print(f"wrote {Path(args.out).name}")


if __name__ == "__main__":
    main()
