"""Fig. 3: a flat rod on a viscous half-space
==========================================

Fig. 3 of Kürschner & Filippov (2012): a flat rod (a = 1 m) pressed by F = 1 N into a
viscous half-space (eta = 1 Pa s): surface velocity and pressure through the centre.

Run: python examples/fig3_rod.py [OUT.png] [--quick]   (default OUT: fig3_rod.png)
"""

import sys
from pathlib import Path

import mdrvisc as mv
from mdrvisc import analytic
from mdrvisc.paper import report, studies

quick = "--quick" in sys.argv
out = next((a for a in sys.argv[1:] if not a.startswith("--")), "fig3_rod.png")
n_bem, n_mdr = (50, 4097) if quick else (200, 66049)

# The plain API: one scene, two methods. The rod's contact never changes: one solve each.
scene = mv.Scene(indenter=mv.Rod(radius=1.0), medium=mv.Viscous(eta=1.0), force=1.0,
                 duration=1.0, times=[1.0], outputs=("depth", "pressure", "surface_velocity"))
bem = mv.solve(scene, method="bem", n=n_bem)
mdr = mv.solve(scene, method="mdr", n=n_mdr)
print(f"closed form: p0 = {analytic.rod_central_pressure(1.0, 1.0):.4f} Pa, "
      f"dd/dt = {analytic.rod_velocity(1.0, 1.0, 1.0):.4f} m/s")
for r in (bem, mdr):
    # series are arrays, one entry per output time (here t = 1 s only)
    print(f"{r.method.upper()} n={r.n}: p0 = {r.central_pressure[0]:.4f} Pa, "
          f"dd/dt = {r.velocity[0]:.4f} m/s, {r.wall_time:.3f} s")
field = bem.fields[1.0]  # x (m), pressure (Pa) on the face; x_extended, surface_velocity (m/s)
print(f"BEM fields: pressure {field.pressure.shape}, surface velocity "
      f"{field.surface_velocity.shape} out to x = {field.x_extended[-1]:.2f} m")

# The figure: the same comparison as data (studies) and as a PNG (report).
report.plot_rod(studies.paper_rod(n_bem=n_bem, n_mdr=n_mdr), out)
print(f"wrote {Path(out).name}")
