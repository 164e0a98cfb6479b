"""The typed result: one type for solve, arrays.contact and arrays.viscous; a short repr;
lossless save/load without pickle; a pandas table of the series."""

import numpy as np
import pandas as pd
import pytest

import mdrvisc as mv


def _results():
    para = mv.Paraboloid(c=1.0, edge=2.56)
    fields = ("depth", "contact_length", "velocity", "pressure", "surface_velocity", "deflection")
    yield mv.solve(mv.Scene(indenter=para, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0,
                            outputs=fields, field_times=[2.0, 5.0]), "bem", 33)
    yield mv.solve(mv.Scene(indenter=para, medium=mv.Viscous(eta=1.0), force=1.0, duration=5.0,
                            outputs=fields), "mdr", 2001)
    yield mv.solve(mv.Scene(indenter=mv.Rod(radius=1.0), medium=mv.Viscous(eta=1.0), force=1.0,
                            duration=1.0, outputs=("depth", "pressure", "surface_velocity")), "bem", 20)
    yield mv.solve(mv.Scene(indenter=mv.Sphere(radius=1.0), medium=mv.StandardSolid(1.0, 2.0, 0.3),
                            depth=0.05, duration=1.0), "mdr", 501)
    x = (np.arange(32) - 15.5) * 0.05
    h = x[None, :] ** 2 + x[:, None] ** 2
    yield mv.arrays.contact(h, 0.05, 1.0, force=0.01)
    yield mv.arrays.viscous(h, 0.05, 1.0, 1.0, [0.5, 1.0], rates=True)


@pytest.mark.parametrize("result", list(_results()), ids=lambda r: f"{r.method}-{r.integrator}")
def test_results_round_trip_through_npz(tmp_path, result):
    path = result.save(tmp_path / "run.npz")
    with np.load(path, allow_pickle=False):  # nothing in it needs pickle
        pass
    back = mv.Result.load(path)
    a, b = result.to_dict(), back.to_dict()
    assert set(a) == set(b)
    for key, value in a.items():
        if key == "fields":
            assert len(value) == len(b[key])
            for fa, fb in zip(value, b[key]):
                assert set(fa) == set(fb)
                for name, array in fa.items():
                    if array is None:
                        assert fb[name] is None
                    else:
                        np.testing.assert_array_equal(array, fb[name])
        elif isinstance(value, np.ndarray):
            assert value.dtype == b[key].dtype
            np.testing.assert_array_equal(value, b[key])
        else:
            assert value == b[key] and type(value) is type(b[key])


@pytest.mark.parametrize("result", list(_results()), ids=lambda r: f"{r.method}-{r.integrator}")
def test_repr_is_a_short_summary_and_the_series_make_a_table(result):
    text = repr(result)
    assert "\n" not in text and len(text) < 400 and "[" not in text.split(";")[0]
    frame = result.to_dataframe()
    assert isinstance(frame, pd.DataFrame) and len(frame) == len(result.t)
    np.testing.assert_array_equal(frame["depth"].to_numpy(), result.depth)
    assert result.units["depth"] == "m" and result.units["pressure"] == "Pa"


def test_fields_are_typed_and_shaped():
    bem, mdr, rod = list(_results())[:3]
    f = bem.fields[2.0]
    assert isinstance(f, mv.Fields) and f.pressure.shape == (33, 33) == f.deflection.shape
    assert set(bem.fields) == {2.0, 5.0}
    g = mdr.fields[5.0]
    assert g.r.ndim == 1 and g.pressure.shape == g.r.shape and g.x is None
    punch = rod.fields[1.0]
    n = punch.x_extended.size
    assert punch.surface_velocity.shape == (n, n) and n > punch.x.size
    assert rod.central_pressure.shape == rod.velocity.shape == rod.t.shape


def test_files_that_are_not_saved_results_are_named_data_errors(tmp_path):
    """Garbage, a truncated or empty file, another program's .npz, a .npy and a pickle raised
    numpy's and zipfile's own errors (one suggesting allow_pickle); each is now a DataError
    naming the file. A missing file stays FileNotFoundError; no pickle is ever executed."""
    import pickle

    good = next(iter(_results())).save(tmp_path / "good.npz")
    cases = {
        "garbage.npz": b"\x00not a zip at all" * 10,
        "empty.npz": b"",
        "truncated.npz": good.read_bytes()[: good.stat().st_size // 2],
        "pickle.npz": pickle.dumps({"depth": [1.0]}),
    }
    for name, content in cases.items():
        (tmp_path / name).write_bytes(content)
    np.savez(tmp_path / "foreign.npz", something=np.arange(3))
    np.save(tmp_path / "array.npy", np.arange(3))
    for name in [*cases, "foreign.npz", "array.npy"]:
        with pytest.raises(mv.DataError, match=name):
            mv.Result.load(tmp_path / name)
    with pytest.raises(FileNotFoundError):
        mv.Result.load(tmp_path / "missing.npz")
    assert mv.Result.load(good).method == next(iter(_results())).method
