"""AFM force curves: instrument files in (:func:`load`, through afmformats:
``pip install 'mdrvisc[afm]'``), raw curves simulated with the fit's forward model
(:func:`simulate`, :func:`piezo_ramp`), and force maps fitted curve by curve in parallel
(:func:`fit_map`, :func:`draw_maps`).

Signs and units: SI throughout; the piezo position rises towards the sample and the
deflection is positive when the sample pushes the tip back (afmformats' height falls towards
the sample and its force is k times the deflection: :class:`Curve` converts).

>>> import mdrvisc as mv
>>> t, z, _ = mv.afm.piezo_ramp(3e-6, speed=1e-5, rate=5000.0, start=-1e-6)
>>> sim = mv.afm.simulate(mv.Sphere(radius=5e-6), mv.Elastic(G=1e3), t, z, 0.05)
>>> result = sim.curve.fit(mv.Sphere(radius=5e-6), mv.Elastic, segments=["approach"])
>>> round(result.parameters["G"])
1000
"""

from ._files import AFM_EXTRA, Curve, load
from ._maps import CurveFailure, MapFit, draw_maps, fit_map
from ._simulate import SEGMENTS, Simulation, piezo_ramp, simulate

__all__ = ["load", "Curve", "simulate", "piezo_ramp", "Simulation", "SEGMENTS", "fit_map", "MapFit",
           "CurveFailure", "draw_maps", "AFM_EXTRA"]
