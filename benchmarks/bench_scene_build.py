"""Scene building with a height map: the map crosses into the compiled core as a numpy array,
copied once, against the JSON text it crossed as before (``tolist()``, ``json.dumps``, the
core's JSON parser, which scene files given as JSON still use).

Columns, per map of n x n heights (float64):

* ``json``: the JSON path: the scene model with its heights as a list, dumped to text and
  parsed by ``_core.Scene.from_json`` (only up to ``--json-up-to``; it takes seconds).
* ``scene``: ``mv.Scene(indenter=mv.HeightMap(heights, dx=...), medium=..., force=...)``,
  the height map's own checks and copy included. Target: under 0.2 s at 4096^2.
* ``sweep``: one scene of ``mv.sweep_scenes(scene, force=[...])``: a value set on the compiled
  scene, the map copied in the core, not read again.
* ``pickle``: ``pickle.dumps`` of the scene (what a sweep sends a worker process) and its size.
* ``key``: the store's key of the scene (a SHA-256 of the heights' bytes among the rest).

Each time is the best of ``--repeats`` runs (default 3). Run:
``python benchmarks/bench_scene_build.py [--sizes 1024 2048 4096] [--json-up-to 2048]``.
"""

from __future__ import annotations

import argparse
import json
import pickle

import numpy as np

import mdrvisc as mv
from _bench import best_of, header, table
from mdrvisc import _core
from mdrvisc.store import scene_key


def json_path(heights: np.ndarray, dx: float):
    """The scene built as before: the heights as JSON text, parsed by the core."""
    model = {"indenter": {"type": "heightmap", "heights": heights.tolist(), "dx": dx},
             "medium": {"type": "elastic", "G": 1.0}, "force": 1e-3, "outputs": ["depth", "contact_length"]}
    return _core.Scene.from_json(json.dumps(model, allow_nan=False))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=[1024, 2048, 4096])
    parser.add_argument("--json-up-to", type=int, default=2048,
                        help="largest n timed on the JSON path (default 2048)")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()
    header("scene building with a height map: arrays against JSON text")
    rng = np.random.default_rng(1)
    rows = []
    for n in args.sizes:
        heights = rng.normal(scale=1e-6, size=(n, n))
        dx = 1e-6

        def build(heights=heights, dx=dx):
            return mv.Scene(indenter=mv.HeightMap(heights, dx=dx), medium=mv.Elastic(G=1.0), force=1e-3)

        t_json = None
        if n <= args.json_up_to:
            t_json, by_json = best_of(lambda: json_path(heights, dx), 1)  # noqa: B023
        t_scene, scene = best_of(build, args.repeats)
        if n <= args.json_up_to:
            assert by_json == scene._model, "the JSON path built another scene"
        t_sweep, swept = best_of(lambda: mv.sweep_scenes(scene, force=[2e-3])[0], args.repeats)  # noqa: B023
        assert np.array_equal(swept.indenter.heights, heights) and swept.history[1][0] == 2e-3
        t_pickle, blob = best_of(lambda: pickle.dumps(scene), args.repeats)  # noqa: B023
        assert pickle.loads(blob) == scene
        t_key, _ = best_of(lambda: scene_key(scene, "bem", n, {}), args.repeats)  # noqa: B023
        rows.append((f"{n}^2", t_json, t_scene, None if t_json is None else t_json / t_scene,
                     t_sweep, t_pickle, len(blob) / 2**20, t_key))
    table(["map", "json [s]", "scene [s]", "speed-up", "sweep [s]", "pickle [s]", "pickle [MiB]", "key [s]"],
          rows, ["{}", "{:.3f}", "{:.3f}", "{:.0f}x", "{:.3f}", "{:.3f}", "{:.1f}", "{:.3f}"])


if __name__ == "__main__":
    main()
