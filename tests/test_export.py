"""Export of results to formats other programs read: CSV of the series (the standard
library's csv reader and numpy read it back exactly), and an xarray Dataset of the series and
fields with their units, which round-trips through netCDF (skipped without xarray)."""

import csv

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.result import SERIES


def _results():
    para = mv.Paraboloid(c=1.0, edge=2.56)
    fields = ("depth", "contact_length", "velocity", "pressure", "surface_velocity", "deflection")
    yield mv.solve(mv.Scene(indenter=para, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0,
                            outputs=fields, field_times=[2.0, 5.0]), "bem", 33)
    yield mv.solve(mv.Scene(indenter=para, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0,
                            outputs=fields, field_times=[1.0, 5.0]), "mdr", 2001)
    yield mv.solve(mv.Scene(indenter=mv.Rod(radius=1.0), medium=mv.Viscous(eta=1.0), force=1.0,
                            duration=1.0, outputs=("depth", "pressure", "surface_velocity")), "bem", 20)
    x = (np.arange(32) - 15.5) * 0.05
    heights = -(x[None, :] ** 2 + x[:, None] ** 2)
    yield mv.solve(mv.Scene(indenter=mv.HeightMap(heights, 0.05), medium=mv.Elastic(G=1.0), force=0.5,
                            outputs=("depth", "pressure", "gap")))


RESULTS = list(_results())
IDS = ["bem-viscous", "mdr-viscous", "bem-punch", "bem-heightmap"]


@pytest.mark.parametrize("result", RESULTS, ids=IDS)
def test_csv_holds_every_series_exactly(tmp_path, result):
    path = result.to_csv(tmp_path / "series.csv")
    with open(path, newline="") as handle:
        header = next(csv.reader(handle))
    names = [k for k in SERIES if getattr(result, k) is not None]
    assert header == names and header[0] == "t"
    table = np.loadtxt(path, delimiter=",", skiprows=1, ndmin=2)
    assert table.shape == (len(result.t), len(names))
    for column, name in zip(table.T, names):
        np.testing.assert_array_equal(column, np.asarray(getattr(result, name), dtype=np.float64))
    with_units = result.to_csv(tmp_path / "units.csv", units=True)
    with open(with_units, newline="") as handle:
        header = next(csv.reader(handle))
    assert header[:3] == ["t [s]", "depth [m]", "contact_length [m]"]


@pytest.mark.parametrize("result", RESULTS, ids=IDS)
def test_xarray_holds_series_fields_units_and_round_trips_through_netcdf(tmp_path, result):
    pytest.importorskip("xarray")
    import xarray as xr

    data = result.to_xarray()
    np.testing.assert_array_equal(data["t"].values, result.t)
    for name in SERIES[1:]:
        value = getattr(result, name)
        if value is None:
            assert name not in data
        else:
            np.testing.assert_array_equal(data[name].values, value)
            assert data[name].dims == ("t",)
            assert data[name].attrs.get("units") == result.units.get(name)
    assert data.attrs["method"] == result.method and data.attrs["n"] == result.n
    assert data.attrs["dx"] == result.dx
    times = sorted(result.fields)
    np.testing.assert_array_equal(data["field_t"].values, times)
    for i, t in enumerate(times):
        fields = result.fields[t]
        for name in ("pressure", "surface_velocity", "deflection", "gap"):
            value = getattr(fields, name)
            if value is None:
                assert name not in data
                continue
            got = data[name].isel(field_t=i)
            np.testing.assert_array_equal(got.values, value)
            if value.ndim == 1:
                np.testing.assert_array_equal(got["r"].values, fields.r)
            elif got.dims == ("y", "x"):
                np.testing.assert_array_equal(got["x"].values, fields.x)
                np.testing.assert_array_equal(got["y"].values, fields.y)
            else:
                assert got.dims == ("y_extended", "x_extended")
                np.testing.assert_array_equal(got["x_extended"].values, fields.x_extended)
    assert data["pressure"].attrs["units"] == "Pa"

    pytest.importorskip("scipy")
    path = tmp_path / "result.nc"
    data.to_netcdf(path, engine="scipy")
    with xr.open_dataset(path, engine="scipy") as back:
        for name, variable in data.variables.items():
            np.testing.assert_array_equal(back[name].values, variable.values)
            assert back[name].attrs.get("units") == variable.attrs.get("units")
        assert back.attrs["method"] == result.method


def test_xarray_missing_names_the_extra(monkeypatch):
    import builtins

    real = builtins.__import__

    def without_xarray(name, *args, **kwargs):
        if name == "xarray":
            raise ImportError("no xarray")
        return real(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", without_xarray)
    with pytest.raises(ImportError, match=r"mdrvisc\[xarray\]"):
        RESULTS[0].to_xarray()
