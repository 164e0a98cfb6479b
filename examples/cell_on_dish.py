"""A cell on a dish: the bottom effect of a thin viscoelastic layer
==================================================================

A cell 5 µm thick on a glass dish, indented by a sphere of radius 5 µm: a standard solid
(G_inf = 1 kPa, G_1 = 2 kPa, tau_1 = 0.1 s, incompressible) as a bonded layer on a rigid
base (``body=mv.Layer(5e-6)``) against the same material as a half-space, under the same
depth ramp to 1.5 µm in 1 s, both by BEM.

A half-space model fitted to the layer's curve reports a modulus too high by the ratio of
the two forces at the same depth history (the half-space's force scales with the modulus):
printed against sqrt(R d) / h, with Dimitriadis et al.'s (2002) elastic bottom-effect
factor phi for a bonded incompressible layer beside it. The viscoelastic ratio exceeds the
elastic factor at the same depth: by Lee–Radok the force sums the increments of the elastic
force weighted by G(t - s), the recent ones most, and on a layer each increment stiffens by
phi + chi phi'(chi) / 3 (chi = sqrt(R d) / h), more than phi itself.

    python examples/cell_on_dish.py [OUT.png] [--quick]   (default OUT: cell_on_dish.png)
"""

import sys

import numpy as np

import mdrvisc as mv

quick = "--quick" in sys.argv
out = next((a for a in sys.argv[1:] if not a.startswith("--")), "cell_on_dish.png")
n = 49 if quick else 97

radius, thickness, depth, ramp = 5e-6, 5e-6, 1.5e-6, 1.0
cell = mv.StandardSolid(G_inf=1e3, G1=2e3, tau1=0.1)
times = np.linspace(0.4, 1.0, 4)
results = {}
for name, body in (("half-space", None), ("layer", mv.Layer(thickness))):
    scene = mv.Scene(indenter=mv.Sphere(radius=radius), medium=cell, depth=([0.0, ramp], [0.0, depth]),
                     duration=ramp, times=times, dt=0.01, body=body)
    results[name] = mv.solve(scene, "bem", n)

half, layer = results["half-space"], results["layer"]
chi = np.sqrt(radius * half.depth) / thickness
dimitriadis = 1 + 1.133 * chi + 1.283 * chi**2 + 0.769 * chi**3 + 0.0975 * chi**4
print(" t (s)   d (um)  sqrt(R d)/h  F half (nN)  F layer (nN)  apparent / true modulus  Dimitriadis")
for k, t in enumerate(half.t):
    print(f"{t:6.2f}  {half.depth[k] * 1e6:7.3f}  {chi[k]:11.3f}  {half.force[k] * 1e9:11.3f}"
          f"  {layer.force[k] * 1e9:12.3f}  {layer.force[k] / half.force[k]:23.3f}  {dimitriadis[k]:11.3f}")
print(f"BEM n = {n}: half-space {half.wall_time:.2f} s, layer {layer.wall_time:.2f} s")

import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

fig, (left, right) = plt.subplots(1, 2, figsize=(9, 3.6))
left.plot(half.depth * 1e6, half.force * 1e9, "o-", label="half-space")
left.plot(layer.depth * 1e6, layer.force * 1e9, "s-", label="layer 5 µm, bonded")
left.set(xlabel="depth (µm)", ylabel="force (nN)", title="standard solid, 1.5 µm in 1 s")
left.legend()
right.plot(chi, layer.force / half.force, "s-", label="mdrvisc layer / half-space")
right.plot(chi, dimitriadis, "--", label="Dimitriadis et al. 2002 (elastic)")
right.set(xlabel="sqrt(R d) / h", ylabel="apparent / true modulus", title="what a half-space fit reports")
right.legend()
fig.tight_layout()
fig.savefig(out, dpi=120)
plt.close(fig)
print(f"wrote {out}")
