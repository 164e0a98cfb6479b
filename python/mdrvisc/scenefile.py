"""Scene files (TOML), the format of ``mdrvisc run SCENE.toml`` in the Python and the Rust
command lines alike: the scene's keys (see :class:`mdrvisc.Scene`) plus ``method`` and ``n``.

::

    method = "bem"          # "bem" or "mdr"
    n = 257                 # BEM: n x n grid; MDR: elements
    force = 1.0             # N, constant from t = 0; or [[t, F], ...] (s, N); or depth = ...
    duration = 5.0          # s (absent for an elastic medium: one static solve)
    times = [1, 2, 3, 4, 5] # s, optional
    outputs = ["depth", "contact_length", "pressure"]   # optional
    field_times = [5.0]     # s, optional
    dt = 0.01               # s, optional: longest step of the viscoelastic stepping

    [indenter]
    type = "paraboloid"     # rod (radius) | paraboloid (c, edge) | cone (slope, edge)
    c = 1.0                 # | sphere (radius) | pyramid (half_angle, edge)
                            # | profile (r, h, slope, edge, radius)
    edge = 2.56

    [medium]
    type = "viscous"        # elastic (G) | viscous (eta) | kelvinvoigt (G, eta)
    eta = 1.0               # | maxwell (G, eta) | standardsolid (G_inf, G1, tau1)
                            # | prony (G_inf, terms = [[G_k, tau_k], ...])

Units: lengths in m, c in 1/m, angles in radians, forces in N, times in s, moduli in Pa, eta
in Pa s. Unknown, missing and mistyped keys raise :class:`mdrvisc.InvalidInputError` naming
the key. The compiled scene model parses and validates the file, for both command lines.
"""

from __future__ import annotations

import json

from . import _core
from .errors import InvalidInputError
from .scene import Scene

__all__ = ["load_scene", "parse_scene"]


def load_scene(path) -> tuple[Scene, str, int]:
    """``(Scene, method, n)`` of the scene file at ``path``."""
    core, method, n = _core.load_scene_file(str(path))
    return Scene._from_core(core), method, n


def parse_scene(data: dict, source: str = "scene") -> tuple[Scene, str, int]:
    """``(Scene, method, n)`` of a scene file's table ``data`` (as ``tomllib`` reads it);
    ``source`` names it in errors."""
    try:
        text = json.dumps(data, allow_nan=False)
    except (TypeError, ValueError) as exc:
        raise InvalidInputError(f"{source}: {exc}") from None
    core, method, n = _core.parse_scene_table(text, source)
    return Scene._from_core(core), method, n
