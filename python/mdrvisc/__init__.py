"""mdrvisc: normal contact of rigid indenters with viscous half-spaces, solved by boundary
elements (BEM) and by the method of dimensionality reduction (MDR), side by side.

>>> import mdrvisc as mv
>>> scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0),
...                  force=1.0, duration=5.0)
>>> bem = mv.solve(scene, method="bem", n=257)       # doctest: +SKIP
>>> mdr = mv.solve(scene, method="mdr", n=66049)     # doctest: +SKIP

Units are SI: m, s, N, Pa, Pa s. Depths and deflections are positive into the body.
Diagnostics (each solve, its resolution and run time) go to the logger ``"mdrvisc"``, silent
until logging is configured, e.g. ``logging.basicConfig(level=logging.INFO)``.
"""

import logging

from . import afm, analytic, arrays, scenefile, store, surfaces
from ._core import num_threads, set_num_threads
from .body import Layer
from .contact import DMT, JKR, Exponential, Hard, MaugisDugdale
from .errors import (
    ConvergenceError,
    DataError,
    DomainError,
    IdentifiabilityWarning,
    InvalidInputError,
    MdrviscError,
    ResolutionWarning,
)
from .fitting import FitResult, fit
from .geometry import Cone, Indenter, Paraboloid, Pyramid, Rod, Sphere
from .grids import load_sweep, sweep_scenes, zip_scenes
from .heightmap import HeightMap
from .loads import load_curve
from .many import SceneFailure, Sweep, solve_many
from .media import Elastic, KelvinVoigt, Maxwell, PowerLaw, Prony, StandardSolid, Viscous
from .profiles import Axisymmetric, Profile
from .result import Fields, Result
from .scene import OUTPUTS, Scene
from .solve import solve

__version__ = "0.1.0"

logging.getLogger("mdrvisc").addHandler(logging.NullHandler())

__all__ = ["Scene", "Result", "Fields", "OUTPUTS", "solve", "load_curve", "set_num_threads", "num_threads",
           "Rod", "Paraboloid", "Cone", "Sphere", "Pyramid", "Axisymmetric", "Profile", "Indenter",
           "HeightMap", "Layer", "Hard", "JKR", "DMT", "MaugisDugdale", "Exponential",
           "Viscous", "Elastic", "KelvinVoigt", "Maxwell", "StandardSolid", "Prony", "PowerLaw", "fit",
           "FitResult", "afm", "analytic", "arrays", "scenefile", "store", "surfaces", "solve_many", "Sweep",
           "SceneFailure", "sweep_scenes", "zip_scenes", "load_sweep", "MdrviscError", "InvalidInputError",
           "ConvergenceError", "DomainError", "ResolutionWarning", "DataError", "IdentifiabilityWarning",
           "__version__"]
