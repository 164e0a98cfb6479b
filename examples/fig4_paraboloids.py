"""Fig. 4: paraboloids on a viscous half-space
===========================================

Fig. 4 of Kürschner & Filippov (2012): paraboloids h = c r^2 (c = 0.05 ... 20 1/m) on a
2.56 m square pressed by F = 1 N into a viscous half-space (eta = 1 Pa s) for 5 s: depth d(t)
and contact length l(t) by BEM (symbols) and MDR (lines).

Run: python examples/fig4_paraboloids.py [OUT.png] [--quick]   (default OUT: fig4_paraboloids.png)
"""

import sys
from pathlib import Path

import mdrvisc as mv
from mdrvisc import analytic
from mdrvisc.paper import report, studies

quick = "--quick" in sys.argv
out = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig4_paraboloids.png")
n_bem, n_mdr = (65, 4097) if quick else (257, 66049)

# The plain API for one paraboloid: BEM (with the paper's Eq. 23 contact length) and MDR.
scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0),
                 force=1.0, duration=5.0, outputs=("depth", "contact_length", "stiffness_length"))
bem = mv.solve(scene, method="bem", n=n_bem)
mdr = mv.solve(scene, method="mdr", n=n_mdr)
lee_radok = analytic.paraboloid_depth(bem.t, 1.0, 1.0, 1.0)
print("c = 1 1/m:  t [s]   d BEM [m]   d MDR [m]   d Lee-Radok [m]   l BEM [m]   l MDR [m]")
for row in zip(bem.t, bem.depth, mdr.depth, lee_radok, bem.stiffness_length, mdr.contact_length):
    print("          {:5.1f} {:11.6f} {:11.6f} {:17.6f} {:11.5f} {:11.5f}".format(*row))
print(bem.summary())
print(mdr.summary())

# The figure: all five paraboloids as data (studies) and as a PNG (report).
report.plot_paraboloids(studies.paper_paraboloids(n_bem=n_bem, n_mdr=n_mdr), out)
print(f"wrote {Path(out).name}")
