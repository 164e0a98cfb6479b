"""Scenes cross into the compiled core in parts: the model's numbers as JSON text, its arrays
(height maps, tabulated profiles, sampled histories) as numpy arrays. The parts build the
scene the JSON text of the whole model builds; sweeps set values on the compiled scene;
scenes pickle as their parts; the store's key hashes the arrays' bytes."""

import hashlib
import json
import pickle

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import _core
from mdrvisc.many import scene_parameters
from mdrvisc.store import scene_key

RNG = np.random.default_rng(7)
HEIGHTS = RNG.normal(scale=1e-3, size=(12, 9))


def map_scene(heights=HEIGHTS, **kwargs):
    return mv.Scene(indenter=mv.HeightMap(heights, dx=1e-3, periodic=True), medium=mv.Viscous(eta=1.0),
                    force=kwargs.pop("force", ([0.0, 0.5, 1.0], [0.0, 1e-3, 1e-3])), duration=1.0, **kwargs)


def profile_scene():
    r = np.linspace(0.0, 2.0, 21)
    return mv.Scene(indenter=mv.Profile(r=r, h=0.5 * r**2, slope=r, edge=2.0),
                    medium=mv.Maxwell(G=1.0, eta=1.0), depth=([0.0, 1.0], [0.0, 0.2]), duration=1.0)


def test_the_parts_build_the_scene_the_whole_models_json_builds():
    paraboloid = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Viscous(eta=1.0), force=1.0, duration=1.0)
    for scene in (map_scene(), profile_scene(), paraboloid):
        core = scene._model
        assert _core.Scene.from_json(core.to_json()) == core
        assert _core.Scene.build(core.model(), **core.arrays()) == core
        model = json.loads(core.model())
        assert all(key not in model["indenter"] for key in ("heights", "r", "h", "slope"))
    core = map_scene()._model
    assert np.array_equal(core.arrays()["heights"], HEIGHTS)
    assert core.arrays()["force"].tolist() == [[0.0, 0.0], [0.5, 1e-3], [1.0, 1e-3]]


def test_history_is_read_from_the_core():
    t, f = map_scene().history
    assert t.tolist() == [0.0, 0.5, 1.0] and f.tolist() == [0.0, 1e-3, 1e-3]
    t, d = profile_scene().history
    assert profile_scene().controlled_by == "depth" and d.tolist() == [0.0, 0.2]
    t, f = map_scene(force=2e-3).history
    assert t.tolist() == [0.0] and f.tolist() == [2e-3]


def test_an_array_and_the_models_key_together_are_refused_naming_it():
    core = map_scene()._model
    model = json.loads(core.model())
    with pytest.raises(mv.InvalidInputError, match="force is given twice"):
        _core.Scene.build(json.dumps({**model, "force": 1.0}), **core.arrays())
    with pytest.raises(mv.InvalidInputError, match="indenter.r"):
        _core.Scene.build(core.model(), r=np.array([0.0, 1.0]), **core.arrays())
    with pytest.raises(mv.InvalidInputError, match=r"\(k, 2\)"):
        _core.Scene.build(core.model(), heights=HEIGHTS, force=np.zeros((3, 3)))
    with pytest.raises(mv.InvalidInputError, match="finite"):
        _core.Scene.build(core.model(), heights=np.full((2, 2), np.nan), force=core.arrays()["force"])


def test_a_core_scene_is_held_not_built_again():
    core = map_scene()._model
    scene = mv.Scene._from_core(core)
    assert scene._model is core and scene == map_scene()
    assert np.array_equal(scene.indenter.heights, HEIGHTS) and not scene.indenter.heights.flags.writeable
    assert scene.times.tolist() == map_scene().times.tolist()


def test_scenes_pickle_as_their_parts():
    for scene in (map_scene(), profile_scene()):
        blob = pickle.dumps(scene)
        back = pickle.loads(blob)
        assert back == scene and back.to_json() == scene.to_json()
        assert pickle.loads(pickle.dumps(scene._model)) == scene._model
    big = RNG.normal(size=(200, 200))
    blob = pickle.dumps(map_scene(big))
    # the heights as their 8 bytes each (JSON text would be about 20), once
    assert big.nbytes < len(blob) < 1.1 * big.nbytes


def test_a_sweep_sets_values_and_keeps_the_arrays():
    base = map_scene()
    scenes = mv.sweep_scenes(base, medium__eta=[1.0, 2.0], duration=[1.0, 2.0])
    assert [(s.medium.eta, s.duration) for s in scenes] == [(1.0, 1.0), (1.0, 2.0), (2.0, 1.0), (2.0, 2.0)]
    for s in scenes:
        assert s.indenter is base.indenter  # the map is not read back
        assert np.array_equal(s._model.arrays()["heights"], HEIGHTS)
        assert s.history[1].tolist() == [0.0, 1e-3, 1e-3]
    assert scenes[2] == mv.Scene(indenter=mv.HeightMap(HEIGHTS, dx=1e-3, periodic=True),
                                 medium=mv.Viscous(eta=2.0), force=([0.0, 0.5, 1.0], [0.0, 1e-3, 1e-3]),
                                 duration=1.0)
    constant = mv.sweep_scenes(base, force=[5e-4])[0]
    assert constant.history[1].tolist() == [5e-4] and "force" not in constant._model.arrays()
    maps = mv.sweep_scenes(base, indenter__heights=[HEIGHTS, 2.0 * HEIGHTS])
    assert np.array_equal(maps[1].indenter.heights, 2.0 * HEIGHTS)
    assert maps[1].indenter.dx == 1e-3 and maps[1].indenter.periodic
    listed = mv.sweep_scenes(base, indenter__heights=[(3.0 * HEIGHTS).tolist()])[0]
    assert np.array_equal(listed.indenter.heights, 3.0 * HEIGHTS)
    steeper = mv.sweep_scenes(profile_scene(), indenter__h=[np.linspace(0.0, 2.0, 21) ** 2])[0]
    assert steeper.indenter.h.tolist() == (np.linspace(0.0, 2.0, 21) ** 2).tolist()
    with pytest.raises(mv.InvalidInputError, match="finite"):
        mv.sweep_scenes(base, medium__eta=[float("nan")])
    assert scene_parameters(scenes[3]) == {"indenter.type": "heightmap", "indenter.dx": 1e-3,
                                           "medium.type": "viscous", "medium.eta": 2.0, "duration": 2.0}


def test_the_store_key_hashes_every_value_arrays_included():
    options = {"tol": 1e-10}
    key = scene_key(map_scene(), "bem", 12, options)
    assert key == scene_key(map_scene(HEIGHTS.copy()), "bem", 12, options)
    changed = HEIGHTS.copy()
    changed[3, 4] = np.nextafter(changed[3, 4], 1.0)
    assert scene_key(map_scene(changed), "bem", 12, options) != key
    assert scene_key(map_scene(HEIGHTS.reshape(9, 12)), "bem", 12, options) != key
    assert scene_key(map_scene(force=([0.0, 0.5, 1.0], [0.0, 1e-3, 2e-3])), "bem", 12, options) != key
    # a scene without arrays keeps the key of its whole model's JSON
    plain = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Viscous(eta=1.0), force=1.0, duration=1.0)
    text = json.dumps({"scene": json.loads(plain.to_json()), "method": "mdr", "n": 101, "options": options},
                      sort_keys=True, separators=(",", ":"))
    assert scene_key(plain, "mdr", 101, options) == hashlib.sha256(text.encode()).hexdigest()


def test_solves_of_scenes_from_parts_match_the_json_scenes_bit_for_bit():
    scene = map_scene(outputs=("depth", "contact_length", "gap"))
    by_json = mv.Scene._from_core(_core.Scene.from_json(scene.to_json()))
    a, b = mv.solve(scene, "bem"), mv.solve(by_json, "bem")
    assert a.depth.tolist() == b.depth.tolist() and a.patches.tolist() == b.patches.tolist()
    assert np.array_equal(a.fields[1.0].gap, b.fields[1.0].gap)
