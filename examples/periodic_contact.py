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

    python examples/periodic_contact.py
"""

import numpy as np

import mdrvisc as mv


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


if __name__ == "__main__":
    wavy_surface()
    rough_cell()
