"""Fitting a force map: the modulus of every pixel
===============================================

A force map is a grid of raw AFM curves, one per pixel. Here a 12 x 12 map of a soft cell on
a softer substrate is simulated with ``mv.afm.simulate`` (the forward model the raw-curve fit
inverts: the piezo drives the tip through a cantilever of k = 0.05 N/m into an elastic
half-space; 5 um sphere; deflection noise of 1 % of the largest deflection), then
``mv.afm.fit_map`` fits a Hertz (elastic) model to the approach of every curve, in worker
processes, and draws the maps of Young's modulus, contact point and rms residual.

Curves read from an instrument file go the same way:
``mv.afm.fit_map(mv.afm.load("cells.jpk-force-map"), tip, mv.Elastic)``.

    python examples/force_map.py [FIGURE.png]
"""

import sys

import numpy as np

import mdrvisc as mv


def main(out=None):
    tip, k, side = mv.Sphere(radius=5e-6), 0.05, 12
    t, z, segment = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=1000.0, start=-0.8e-6, retract=False)
    y, x = np.mgrid[0:side, 0:side] / (side - 1) - 0.5
    cell = np.clip(1.0 - (x**2 + y**2) / 0.12, 0.0, 1.0)       # 1 at the cell's centre, 0 off it
    G_true, z_c_true = 300.0 + 900.0 * cell, 0.3e-6 * cell
    rng = np.random.default_rng(3)
    curves = []
    for iy in range(side):
        for ix in range(side):
            sim = mv.afm.simulate(tip, mv.Elastic(G=G_true[iy, ix]), t, z, k, contact_point=z_c_true[iy, ix],
                                  baseline=5e-9, n=200)
            curve = sim.curve
            curve.deflection = curve.deflection + 0.01 * sim.force.max() / k * rng.standard_normal(len(t))
            curve.grid_index, curve.position = (ix, iy), (1e-6 * ix, 1e-6 * iy)
            curves.append(curve)

    fitted = mv.afm.fit_map(curves, tip, mv.Elastic, segments=["approach"], n=200, progress=False)
    print(fitted.summary())
    print(fitted.table[["grid_x", "grid_y", "E", "E_stderr", "contact_point", "rms", "success"]].head())
    error = fitted.image("G") / G_true - 1
    print(f"modulus: median |error| {np.median(np.abs(error)):.2%}, largest {np.max(np.abs(error)):.2%}")
    shift = (fitted.image("contact_point") - z_c_true) * 1e9
    print(f"contact point: median |error| {np.median(np.abs(shift)):.2f} nm")
    fitted.draw(path=out)


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
