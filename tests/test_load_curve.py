"""Load curves: a static scene under several forces in one call, each BEM solve started from
the pressure of the one before. The results are those of cold solves of each load (to the
solver's tolerance; MDR's bit for bit), the warm starts save iterations on a rough surface,
and bad input raises typed errors."""

import warnings

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import analytic


def _rough(periodic):
    heights = mv.surfaces.self_affine((128, 128), 1e-6, hurst=0.8, rms_height=1e-6, rolloff=32e-6,
                                      short_cutoff=8e-6, seed=5)
    return mv.Scene(indenter=mv.HeightMap(heights, 1e-6, periodic=periodic), medium=mv.Elastic(G=1e6),
                    force=1e-3, outputs=("depth", "pressure"))


def _cold(scene, force, **options):
    return mv.solve(mv.zip_scenes(scene, force=[force])[0], **options)


@pytest.mark.parametrize("periodic", [True, False], ids=["periodic", "free"])
def test_rough_load_curve_matches_cold_solves_in_fewer_iterations(periodic):
    scene = _rough(periodic)
    forces = np.geomspace(1e-3, 1e-2, 5) * (0.25 if periodic else 0.025)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", mv.ResolutionWarning)  # small patches at the lightest loads
        curve = mv.load_curve(scene, forces, tol=1e-10)
        cold = [_cold(scene, f, tol=1e-10) for f in forces]
    assert len(curve.results) == len(forces) and not curve.failures
    for scene_at, warm, ref, force in zip(curve.scenes, curve.results, cold, forces):
        assert scene_at.force == force and warm.force[0] == pytest.approx(force, rel=1e-12)
        assert warm.depth[0] == pytest.approx(ref.depth[0], rel=1e-8)
        assert warm.mean_gap[0] == pytest.approx(ref.mean_gap[0], rel=1e-6)
        p, q = warm.fields[0.0].pressure, ref.fields[0.0].pressure
        assert np.abs(p - q).max() <= 1e-6 * q.max()
        assert abs(warm.contact_fraction[0] - ref.contact_fraction[0]) * p.size <= 2
    # the contact grows with the load, and every solve after the first starts warm
    assert np.all(np.diff([r.contact_fraction[0] for r in curve.results]) > 0)
    warm_iterations = sum(r.iterations for r in curve.results[1:])
    cold_iterations = sum(r.iterations for r in cold[1:])
    assert warm_iterations < cold_iterations


def test_hertz_load_curve_by_both_methods():
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5, edge=2.56), medium=mv.Elastic(G=1.0), force=0.1)
    forces = [0.1, 0.2, 0.4, 0.8]
    bem = mv.load_curve(scene, forces, "bem", 129, tol=1e-10)
    mdr = mv.load_curve(scene, forces, "mdr", 20001)
    for force, b, m in zip(forces, bem.results, mdr.results):
        depth = analytic.hertz(force, 1.0, 4.0)[1]           # R = 1 / (2 c), E* = 4 G
        assert b.depth[0] == pytest.approx(depth, rel=5e-3)
        assert m.depth[0] == pytest.approx(depth, rel=1e-3)
        assert b.depth[0] == pytest.approx(_cold(scene, force, method="bem", n=129, tol=1e-10).depth[0],
                                           rel=1e-8)
        one = _cold(scene, force, method="mdr", n=20001)
        np.testing.assert_array_equal(m.depth, one.depth)
        np.testing.assert_array_equal(m.contact_length, one.contact_length)
    table = bem.to_dataframe()
    assert list(table["force"]) == forces and len(table) == len(forces)


@pytest.mark.parametrize("forces", [[], [1.0, -1.0], [1.0, float("nan")], [[1.0], "x"]])
def test_bad_forces_are_refused(forces):
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=1.0), force=0.1)
    with pytest.raises(mv.InvalidInputError, match="load_curve"):
        mv.load_curve(scene, forces)


def test_a_load_curve_needs_a_static_scene_and_a_method():
    viscous = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Viscous(eta=1.0), force=0.1, duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="Elastic"):
        mv.load_curve(viscous, [0.1, 0.2])
    static = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=1.0), force=0.1)
    with pytest.raises(mv.InvalidInputError, match="method"):
        mv.load_curve(static, [0.1], method="fem")
    with pytest.raises(mv.InvalidInputError, match="Scene"):
        mv.load_curve("scene.toml", [0.1])
