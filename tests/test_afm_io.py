"""mdrvisc.afm: instrument files read through afmformats (files written here through its HDF5
export and read back), and the raw-curve simulator against closed forms and the scene solver."""

import sys

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.errors import DataError, InvalidInputError

R = 5e-6          # tip radius (m)
K = 0.05          # spring constant (N/m)


def _write_hdf5(path, curves, *, restart_retract=False, spring_constant=True, times=True):
    """Writes ``curves`` [(t, piezo, deflection, segment, metadata)] as afmformats' HDF5: force
    = k deflection, height = -piezo; with ``restart_retract`` the retract's times start at 0
    as some instruments write them; without ``times`` no time column."""
    afmformats = pytest.importorskip("afmformats")
    h5py = pytest.importorskip("h5py")
    with h5py.File(path, "w") as h5:
        for enum, (t, z, deflection, segment, extra) in enumerate(curves):
            time = t.copy()
            if restart_retract:
                retract = segment == segment.max()
                time[retract] -= time[retract][0]
            metadata = {"path": str(path), "enum": enum, "imaging mode": "force-distance",
                        "duration": float(t[-1] - t[0]), "point count": int(t.size),
                        "segment count": int(segment.max()) + 1, **extra}
            if spring_constant:
                metadata["spring constant"] = K
            data = {"force": K * deflection, "height (piezo)": -z, "segment": segment.astype(np.uint8)}
            if times:
                data["time"] = time
            afmformats.AFMForceDistance(data, metadata).export_data(h5, fmt="hdf5")
    return path


def _hertz_through_spring(z, contact_point, k, E_star):
    """Force (N) of a paraboloid tip of radius R on an elastic half-space, pushed through a
    spring k by the piezo at z: F = k (z - z_c - d) = (4/3) E* sqrt(R) d^1.5, by bisection."""
    drive = np.maximum(z - contact_point, 0.0)
    lo, hi = np.zeros_like(drive), drive.copy()
    for _ in range(200):
        d = 0.5 * (lo + hi)
        excess = 4.0 / 3.0 * E_star * np.sqrt(R) * d**1.5 - k * (drive - d)
        lo, hi = np.where(excess < 0, d, lo), np.where(excess < 0, hi, d)
    d = 0.5 * (lo + hi)
    return k * (drive - d)


def test_simulated_elastic_curve_is_hertz_through_the_spring():
    """An elastic half-space: at every sample the force equals Hertz's at the indentation and
    the spring's at the rest of the drive; the MDR error falls under refinement."""
    t, z, segment = mv.afm.piezo_ramp(3e-6, speed=1e-5, rate=4000.0, start=-1e-6)
    G, nu = 800.0, 0.5
    exact = _hertz_through_spring(z, 0.0, K, 2 * G / (1 - nu))
    errors = []
    for n in (250, 1000):
        sim = mv.afm.simulate(mv.Paraboloid(c=1 / (2 * R)), mv.Elastic(G=G, nu=nu), t, z, K, n=n)
        errors.append(np.max(np.abs(sim.force - exact)) / exact.max())
        assert np.allclose(sim.depth + sim.force / K, np.maximum(z, sim.depth + sim.force / K))
    assert errors[1] < 1e-3
    assert errors[1] < errors[0] / 4          # second order in the element size
    assert np.array_equal(sim.curve.segment, segment)
    assert sim.curve.segments[:1] == ("approach",)


def test_simulated_viscoelastic_curve_matches_the_scene_solver_at_its_depths():
    """A standard solid, approach - dwell - retract through a soft cantilever: the force the
    simulator balances equals the depth-controlled MDR scene's at the simulated indentation."""
    t, z, _ = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=2000.0, dwell=0.2, start=-0.5e-6)
    medium = mv.StandardSolid(G_inf=500.0, G1=1500.0, tau1=0.05)
    indenter = mv.Paraboloid(c=1 / (2 * R))
    sim = mv.afm.simulate(indenter, medium, t, z, 0.01, n=500)
    assert sim.curve.segments == ("approach", "dwell", "retract")
    # the indentation creeps during the dwell while the piezo holds: the soft spring relaxes
    assert np.all(np.diff(sim.depth[sim.curve.mask("dwell")]) > 0)
    scene = mv.Scene(indenter=indenter, medium=medium, depth=(t, np.maximum(sim.depth, 0.0)),
                     duration=t[-1], times=t[1:])
    solved = mv.solve(scene, method="mdr", n=1000)
    assert np.max(np.abs(solved.force - sim.force[1:])) < 1e-4 * sim.force.max()


def test_simulate_refuses_bad_input():
    t, z, _ = mv.afm.piezo_ramp(1e-6, speed=1e-5, rate=1000.0, start=-0.5e-6)
    sphere, medium = mv.Sphere(radius=R), mv.Elastic(G=1e3)
    with pytest.raises(InvalidInputError, match="spring_constant"):
        mv.afm.simulate(sphere, medium, t, z, -1.0)
    with pytest.raises(DataError, match="before the contact point"):
        mv.afm.simulate(sphere, medium, t, z + 1e-6, K)
    with pytest.raises(DataError, match="never passes"):
        mv.afm.simulate(sphere, medium, t, z, K, contact_point=2e-6)
    with pytest.raises(DataError, match="strictly increasing"):
        mv.afm.simulate(sphere, medium, t[::-1], z, K)
    with pytest.raises(InvalidInputError, match="medium"):
        mv.afm.simulate(sphere, mv.Elastic, t, z, K)


def test_noise_is_reproducible_and_of_the_asked_size():
    t, z, _ = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=5000.0, start=-1e-6)
    sphere, medium = mv.Sphere(radius=R), mv.Elastic(G=1e3)
    clean = mv.afm.simulate(sphere, medium, t, z, K, baseline=3e-9)
    a = mv.afm.simulate(sphere, medium, t, z, K, baseline=3e-9, noise=1e-10, seed=7)
    b = mv.afm.simulate(sphere, medium, t, z, K, baseline=3e-9, noise=1e-10, seed=7)
    assert np.array_equal(a.curve.deflection, b.curve.deflection)
    residual = a.curve.deflection - clean.curve.deflection
    assert abs(np.std(residual) / 1e-10 - 1) < 0.05          # 2,000 draws: 1.6 % standard error
    assert np.allclose(clean.curve.deflection, clean.force / K + 3e-9, rtol=0, atol=1e-21)


def test_load_reads_an_hdf5_export_back_in_mdrvisc_conventions(tmp_path):
    """Two curves of a 2 x 1 map written through afmformats (force, falling height, retract times
    restarting at 0) read back as piezo rising, deflection = force / k, continuous times."""
    t, z, segment = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=2000.0, start=-1e-6)
    segment = np.where(segment == 2, 1, segment)      # approach 0, retract 1 as files number them
    sims = [mv.afm.simulate(mv.Sphere(radius=R), mv.Elastic(G=g), t, z, K, baseline=2e-9) for g in (500, 900)]
    curves = [(t, z, s.curve.deflection, segment,
               {"grid index x": i, "grid index y": 0, "grid shape x": 2, "grid shape y": 1,
                "position x": 1e-6 * i, "position y": 5e-7})
              for i, s in enumerate(sims)]
    path = _write_hdf5(tmp_path / "map.h5", curves, restart_retract=True)
    loaded = mv.afm.load(path)
    assert len(loaded) == 2
    for i, (curve, sim) in enumerate(zip(loaded, sims)):
        assert curve.spring_constant == K
        assert np.array_equal(curve.piezo, z)
        assert np.allclose(curve.deflection, sim.curve.deflection, rtol=1e-15, atol=0)
        assert np.allclose(curve.time, t, rtol=0, atol=1e-12)     # the retract continued
        assert curve.segments == ("approach", "retract")
        assert np.array_equal(curve.segment, segment)
        assert curve.grid_index == (i, 0) and curve.position == (1e-6 * i, 5e-7)
        assert curve.metadata["grid shape x"] == 2
        assert curve.path == path
        assert np.all(np.diff(curve.select("approach").piezo) > 0)


def test_loaded_curve_fits_back_its_modulus(tmp_path):
    """The loaded curve's fit finds the modulus it was simulated with (noise-free)."""
    t, z, segment = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=2000.0, start=-1e-6)
    segment = np.where(segment == 2, 1, segment)
    sim = mv.afm.simulate(mv.Sphere(radius=R), mv.Elastic(G=700.0), t, z, K, contact_point=0.1e-6,
                          baseline=2e-9, n=1000)
    path = _write_hdf5(tmp_path / "one.h5", [(t, z, sim.curve.deflection, segment, {})])
    (curve,) = mv.afm.load(path)
    result = curve.fit(mv.Sphere(radius=R), mv.Elastic, segments=["approach"], n=1000)
    assert result.parameters["G"] == pytest.approx(700.0, rel=1e-4)
    assert result.contact_point == pytest.approx(0.1e-6, abs=1e-11)


def test_load_needs_a_spring_constant_and_takes_one(tmp_path):
    t, z, segment = mv.afm.piezo_ramp(1e-6, speed=1e-5, rate=1000.0, start=-0.5e-6)
    path = _write_hdf5(tmp_path / "nok.h5", [(t, z, np.zeros_like(t), segment, {})], spring_constant=False)
    with pytest.raises(DataError, match="spring constant"):
        mv.afm.load(path)
    with pytest.raises(DataError, match="no such file"):
        mv.afm.load(tmp_path / "absent.jpk-force")
    with pytest.raises(InvalidInputError, match="spring_constant"):
        mv.afm.load(path, spring_constant=-1.0)


def test_load_without_afmformats_says_how_to_install(monkeypatch, tmp_path):
    monkeypatch.setitem(sys.modules, "afmformats", None)
    with pytest.raises(ImportError, match=r"pip install 'mdrvisc\[afm\]'"):
        mv.afm.load(tmp_path / "x.jpk-force")


def test_curve_checks_its_arrays_and_segments():
    with pytest.raises(DataError, match="different lengths"):
        mv.afm.Curve(time=np.arange(3.0), piezo=np.arange(3.0), deflection=np.zeros(2), spring_constant=K,
                     segment=np.zeros(3), segments=("approach",))
    curve = mv.afm.Curve(time=None, piezo=np.arange(4.0), deflection=np.zeros(4), spring_constant=K,
                         segment=[0, 0, 1, 1], segments=("approach", "retract"))
    with pytest.raises(InvalidInputError, match="segments must be some of"):
        curve.select("dwell")
    with pytest.raises(DataError, match="no times"):
        curve.times(mv.StandardSolid)
    assert np.array_equal(curve.times(mv.Elastic), np.arange(4.0))


def test_command_line_fits_an_afm_file(tmp_path, capsys):
    """``mdrvisc fit FILE.h5``: the curve of a file read through afmformats, the contact point
    held or guessed, the fitted curve written with its residuals, the arrays in the JSON."""
    import json

    from mdrvisc.cli import main

    t, z, segment = mv.afm.piezo_ramp(2e-6, speed=1e-5, rate=2000.0, start=-1e-6)
    segment = np.where(segment == 2, 1, segment)
    sims = [mv.afm.simulate(mv.Sphere(radius=R), mv.Elastic(G=g), t, z, K, contact_point=1e-7, baseline=2e-9,
                            n=1000) for g in (600.0, 900.0)]
    path = _write_hdf5(tmp_path / "two.h5", [(t, z, s.curve.deflection, segment, {}) for s in sims])
    out = tmp_path / "fit.csv"
    args = ["fit", str(path), "--indenter", f"sphere:radius={R}", "--model", "elastic", "--curve", "1"]
    assert main([*args, "--out", str(out), "--json"]) == 0
    document = json.loads(capsys.readouterr().out)
    assert document["parameters"]["G"] == pytest.approx(900.0, rel=1e-4)
    assert document["contact_point"] == pytest.approx(1e-7, abs=1e-11)
    approach = segment == 0
    arrays = document["arrays"]
    assert np.allclose(arrays["t"], t[approach] - t[0], rtol=0, atol=1e-12)
    assert np.allclose(np.subtract(arrays["model"], arrays["data"]), arrays["residuals"], rtol=0, atol=1e-24)
    written = np.genfromtxt(out, delimiter=",", names=True)
    assert written.dtype.names == ("t", "data", "model", "residual", "weight", "piezo", "deflection", "depth")
    assert np.allclose(written["piezo"], z[approach])
    assert np.allclose(written["residual"], arrays["residuals"])
    # the contact point held at a wrong value: the fit moves the modulus instead, and says it held it
    assert main([*args, "--contact-point", "0.5e-7", "--fix", "contact_point", "--json"]) == 0
    held = json.loads(capsys.readouterr().out)
    assert held["contact_point"] == 0.5e-7 and held["stderr"]["contact_point"] == 0.0
    assert "contact_point" not in held["free"]
    assert held["parameters"]["G"] != pytest.approx(900.0, rel=1e-3)
    # a medium parameter held needs its value
    assert main([*args, "--fix", "G"]) == 2
    assert "instance" in capsys.readouterr().err
    assert main([*args, "--guess", "G=800", "--fix", "G", "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["parameters"]["G"] == 800.0
    assert main([*args, "--guess", "E=800"]) == 2
    assert "Elastic takes ['G']" in capsys.readouterr().err
    assert main([*args[:-1], "7"]) == 2
    assert "has 2 curves" in capsys.readouterr().err


def test_load_takes_times_from_the_sampling_rates_and_splits_a_joined_curve(tmp_path):
    """A file without times but with its sampling rates gets times from them; a curve whose
    approach and retract share one segment number (as Igor files write them) is split at the
    deepest piezo position."""
    t, z, segment = mv.afm.piezo_ramp(1e-6, speed=1e-5, rate=1000.0, start=-0.5e-6)
    deflection = np.zeros_like(t)
    rates = {"rate approach": 1000.0, "rate retract": 1000.0, "segment count": 2}
    path = _write_hdf5(tmp_path / "joined.h5", [(t, z, deflection, np.zeros_like(segment), rates)],
                       times=False)
    (curve,) = mv.afm.load(path)
    assert curve.segments == ("approach", "retract")
    top = int(np.argmax(z))
    assert np.array_equal(curve.segment, (np.arange(t.size) > top).astype(int))
    assert np.allclose(curve.time, np.arange(t.size) / 1000.0, rtol=0, atol=1e-12)
    assert np.allclose(curve.time, t, rtol=0, atol=1e-12)
