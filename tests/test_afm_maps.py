"""mdrvisc.afm.fit_map: every curve of a simulated force map fitted, in worker processes and on a
Dask cluster, failures isolated with their reason, rows kept in a store, maps drawn."""

import numpy as np
import pytest

import mdrvisc as mv

pd = pytest.importorskip("pandas")

R, K = 5e-6, 0.05
SPHERE = mv.Sphere(radius=R)


def _map(nx=3, ny=2, broken=(1, 1)):
    """Noise-free elastic curves on an nx x ny grid, G rising with the column and the contact
    point with the row; the curve at ``broken`` never touches (its deflection is flat)."""
    t, z, segment = mv.afm.piezo_ramp(1.5e-6, speed=1e-5, rate=1000.0, start=-0.5e-6, retract=False)
    curves, truth = [], {}
    for iy in range(ny):
        for ix in range(nx):
            G, z_c = 400.0 * (ix + 1), 1e-7 * iy
            sim = mv.afm.simulate(SPHERE, mv.Elastic(G=G), t, z, K, contact_point=z_c, baseline=1e-9, n=300)
            curve = sim.curve
            if (ix, iy) == broken:
                curve.deflection = np.full_like(curve.deflection, 1e-9)
            curve.grid_index, curve.position = (ix, iy), (1e-6 * ix, 1e-6 * iy)
            curves.append(curve)
            truth[(ix, iy)] = (G, z_c)
    return curves, truth


def _check(fitted, curves, truth, broken=(1, 1)):
    table = fitted.table
    assert list(table["index"]) == list(range(len(curves)))
    assert fitted.shape == (2, 3)
    for _, row in table.iterrows():
        where = (row["grid_x"], row["grid_y"])
        if where == broken:
            assert not row["success"] and "never reaches contact" in row["reason"]
            assert np.isnan(row["G"])
            continue
        G, z_c = truth[where]
        assert row["success"] and pd.isna(row["reason"])
        assert row["G"] == pytest.approx(G, rel=1e-3)
        assert row["contact_point"] == pytest.approx(z_c, abs=2e-9)
        assert row["E"] == pytest.approx(3 * row["G"], rel=1e-12)       # nu = 0.5
    assert [f.grid_index for f in fitted.failures] == [broken]
    image = fitted.image("G")
    assert np.isnan(image[broken[1], broken[0]])
    assert image[0, 2] == pytest.approx(truth[(2, 0)][0], rel=1e-3)


def test_fit_map_fits_every_curve_and_isolates_the_one_that_fails(tmp_path):
    curves, truth = _map()
    store = tmp_path / "rows"
    fitted = mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=2, store=store, progress=False, n=300)
    _check(fitted, curves, truth)
    assert (fitted.computed, fitted.loaded) == (5, 0)
    # a rerun reads the five fitted rows from the store and tries the failed curve again
    again = mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=1, store=store, progress=False, n=300)
    assert (again.computed, again.loaded) == (0, 5) and len(again.failures) == 1
    pd.testing.assert_series_equal(fitted.table["G"], again.table["G"])
    # other options are other rows
    other = mv.afm.fit_map(curves[:1], SPHERE, mv.Elastic, store=store, progress=False, n=301)
    assert other.computed == 1


def test_fit_map_on_a_dask_cluster_gives_the_local_table():
    distributed = pytest.importorskip("distributed")
    curves, truth = _map()
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=2,
                            dashboard_address=None) as client:
        fitted = mv.afm.fit_map(curves, SPHERE, mv.Elastic, client=client, progress=False, n=300)
    _check(fitted, curves, truth)
    local = mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=1, progress=False, n=300)
    columns = ["G", "contact_point", "baseline", "rms"]
    pd.testing.assert_frame_equal(fitted.table[columns], local.table[columns])


def test_draw_maps_draws_modulus_contact_point_and_rms(tmp_path):
    pytest.importorskip("matplotlib")
    curves, _ = _map()
    fitted = mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=1, progress=False, n=300)
    assert fitted.default_columns() == ["E", "contact_point", "rms"]
    figure = fitted.draw(path=tmp_path / "maps.png")
    assert (tmp_path / "maps.png").stat().st_size > 0
    titles = [ax.get_title() for ax in figure.axes if ax.get_title()]
    assert titles == ["E", "contact_point", "rms"]


def test_fit_map_refuses_bad_input():
    curves, _ = _map()
    with pytest.raises(mv.InvalidInputError, match="unknown fit option"):
        mv.afm.fit_map(curves, SPHERE, mv.Elastic, contact_point=0.0, progress=False)
    with pytest.raises(mv.InvalidInputError, match="mdrvisc.afm.Curve"):
        mv.afm.fit_map([1.0], SPHERE, mv.Elastic, progress=False)
    with pytest.raises(mv.InvalidInputError, match="workers"):
        mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=0, progress=False)
    fitted = mv.afm.fit_map(curves[:1], SPHERE, mv.Elastic, progress=False, n=300)
    with pytest.raises(mv.InvalidInputError, match="no column"):
        fitted.image("tau1")


def test_fit_map_fits_tilted_baselines_of_a_map_file(tmp_path):
    """A 3 x 2 map (QI data read by afmformats are force-distance curves on a grid, as here)
    written through afmformats' HDF5 export and read back, each curve's
    baseline tilted along the piezo by its own slope (a drift of 1-5 % of the piezo travel:
    over the approach up to 2.5 times the largest deflection), noise-free:
    ``fit_map(..., baseline_model="tilt")`` recovers every modulus (1e-3, as the untilted map),
    contact point (2 nm) and slope (1e-3 of it), and the table has the slopes' column; the
    offset baseline refuses these curves by name."""
    from test_afm_io import _write_hdf5

    t, z, segment = mv.afm.piezo_ramp(1.5e-6, speed=1e-5, rate=1000.0, start=-0.5e-6, retract=False)
    written, truth = [], {}
    for iy in range(2):
        for ix in range(3):
            G, z_c, slope = 400.0 * (ix + 1), 1e-7 * iy, 0.01 * (1 + ix + 2 * iy) * (-1) ** ix
            sim = mv.afm.simulate(SPHERE, mv.Elastic(G=G), t, z, K, contact_point=z_c, baseline=1e-9, n=300)
            deflection = sim.curve.deflection + slope * (z - z_c)
            written.append((t, z, deflection, segment,
                            {"grid index x": ix, "grid index y": iy,
                             "grid shape x": 3, "grid shape y": 2, "position x": 1e-6 * ix,
                             "position y": 1e-6 * iy}))
            truth[(ix, iy)] = (G, z_c, slope)
    curves = mv.afm.load(_write_hdf5(tmp_path / "qi.h5", written))
    fitted = mv.afm.fit_map(curves, SPHERE, mv.Elastic, workers=1, progress=False, n=300,
                            baseline_model="tilt")
    table = fitted.table
    assert fitted.shape == (2, 3) and not fitted.failures
    for _, row in table.iterrows():
        G, z_c, slope = truth[(row["grid_x"], row["grid_y"])]
        assert row["success"], row["message"]
        assert row["G"] == pytest.approx(G, rel=1e-3)
        assert row["contact_point"] == pytest.approx(z_c, abs=2e-9)
        assert row["baseline_slope"] == pytest.approx(slope, rel=1e-3)
        assert row["baseline_slope_stderr"] >= 0
    assert fitted.image("baseline_slope")[1, 2] == pytest.approx(truth[(2, 1)][2], rel=1e-3)
    offset = mv.afm.fit_map(curves[:1], SPHERE, mv.Elastic, workers=1, progress=False, n=300)
    assert not offset.table["success"][0] and 'baseline_model="tilt"' in offset.table["reason"][0]
