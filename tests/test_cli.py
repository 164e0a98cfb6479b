"""The command line (`mdrvisc paper`, `mdrvisc run`), its files, and scene files."""

import contextlib
import csv
import io
import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import analytic, cli
from mdrvisc.scenefile import load_scene, parse_scene

EXAMPLES = Path(__file__).resolve().parent.parent / "examples"
FILES = ("rod.csv", "paraboloids.csv", "viscoelastic.csv", "paper.json", "fig3_rod.png",
         "fig4_paraboloids.png", "fig_viscoelastic.png")
STUDY_FILES = ("error_vs_runtime.csv", "error_vs_runtime_orders.csv", "error_vs_runtime.json",
               "error_vs_runtime.png")


def run_cli(*argv):
    """(exit status, stdout, stderr) of ``cli.main(argv)`` run in this process."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(list(argv))
    return status, out.getvalue(), err.getvalue()


@pytest.fixture(scope="module")
def paper_quick(tmp_path_factory):
    """`mdrvisc paper --quick --json` into a fresh folder: (folder, stdout document)."""
    folder = tmp_path_factory.mktemp("paper")
    status, out, err = run_cli("paper", "--quick", "--json", "--out", str(folder))
    assert status == 0, err
    return folder, json.loads(out)


# ------------------------------------------------------------------ mdrvisc paper
def test_paper_writes_all_files(paper_quick):
    folder, _ = paper_quick
    assert sorted(p.name for p in folder.iterdir()) == sorted(FILES + STUDY_FILES)
    for name in FILES + STUDY_FILES:
        assert (folder / name).stat().st_size > 0, name
    for name in ("fig3_rod.png", "fig4_paraboloids.png", "fig_viscoelastic.png",
                 "error_vs_runtime.png"):
        assert (folder / name).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_paper_json_file_matches_stdout(paper_quick):
    folder, doc = paper_quick
    assert json.loads((folder / "paper.json").read_text()) == doc
    assert doc["quick"] is True
    study = doc["error_vs_runtime"]
    assert study["quick"] is True and study["rows"] and study["orders"]
    assert json.loads((folder / "error_vs_runtime.json").read_text()) == study


def test_paper_rod_numbers(paper_quick):
    _, doc = paper_quick
    closed, paper_bem, bem, paper_mdr, mdr = doc["rod"]["rows"]
    assert [closed["source"], paper_bem["source"], paper_mdr["source"]] == [
        "closed form", "paper BEM", "paper MDR"]
    assert bem["source"] == "BEM n=50" and mdr["source"] == "MDR n=4097"
    assert abs(bem["velocity"] / 0.125 - 1) < 0.01
    assert abs(bem["central_pressure"] / analytic.rod_central_pressure(1, 1) - 1) < 0.02
    assert mdr["velocity"] == pytest.approx(0.125, rel=1e-12)
    assert mdr["central_pressure"] == pytest.approx(1 / (2 * math.pi), rel=1e-3)
    assert paper_bem["elements"] == 31417
    assert paper_bem["velocity_error"] == pytest.approx(0.0016)
    assert paper_mdr["central_pressure"] is None


def test_paper_paraboloid_numbers(paper_quick):
    _, doc = paper_quick
    rows = doc["paraboloids"]["rows"]
    assert len(rows) == 25
    for r in rows:
        closed_length = analytic.paraboloid_contact_length(r["t"], 1.0, r["c"], 1.0)
        if closed_length > 2.56:  # the contact left the square: no closed form
            assert r["depth_lee_radok"] is None and r["length_lee_radok"] is None
            continue
        lee_radok = analytic.paraboloid_depth(r["t"], 1.0, r["c"], 1.0)
        assert r["depth_lee_radok"] == pytest.approx(lee_radok, rel=1e-12)
        assert abs(r["depth_mdr"] - lee_radok) < 1e-5
        assert abs(r["depth_bem"] / lee_radok - 1) < 5e-3
        assert abs(r["length_bem"] / closed_length - 1) < 0.03
        assert r["depth_bem_vs_mdr"] == pytest.approx(r["depth_bem"] / r["depth_mdr"] - 1)
    saturated = [r for r in rows if r["c"] == 0.05 and r["t"] >= 3]
    assert all(r["mdr_saturated"] and r["bem_at_edge"] for r in saturated)
    assert all(r["length_mdr"] == pytest.approx(2 * 2.56 / math.sqrt(math.pi)) for r in saturated)


# Quick viscoelastic section (MDR 2001, BEM 33 x 33, dt = 0.01 s) against Ting: bounds on
# (force error loading, unloading, contact-radius error in dx) per (medium, method), from the
# errors measured at these resolutions (in brackets) with some headroom:
# * Kelvin-Voigt loading: the dashpot's first-order step error (~dt / 4t, see
#   test_viscoelastic.py) dominates both methods [MDR 9.5e-3, BEM 8.9e-3; 3.9e-3 and 3.8e-3
#   at the full run's dt = 0.005 s]; the same 1.2e-2 bound as the BEM test there at dt = 0.01.
# * standard solid, MDR: second order in the step [7.2e-6, 3.9e-6]; Kelvin-Voigt unloading,
#   MDR: exact but for round-off and the step [1.5e-7].
# * BEM: the spatial error ~dx^2 [standard solid 4.8e-4 / 4.5e-4, Kelvin-Voigt unloading
#   2.8e-4; 1.1e-4 / 1.0e-4 / 6.6e-5 at n = 65].
# * radius: the MDR edge is exact to the element (l / 2 within dx / 2, measured 0.5 to 1e-12);
#   BEM's 2 sqrt(A / pi) is within a fraction of an element [0.41, 0.36], as at n = 65 (0.34).
VISCOELASTIC_BOUNDS = {("StandardSolid", "MDR"): (1e-5, 5e-6, 0.5 + 1e-6),
                       ("StandardSolid", "BEM"): (6e-4, 6e-4, 0.45),
                       ("KelvinVoigt", "MDR"): (1.2e-2, 3e-7, 0.5 + 1e-6),
                       ("KelvinVoigt", "BEM"): (1.2e-2, 4e-4, 0.45)}


def sls_separation(g_inf, g1, tau, t_peak):
    """Ting's separation time of a paraboloid pushed in at v until t_peak and pulled out at v
    on a standard solid, written afresh: the edge balance int_0^ts G(ts - s) ddot(s) ds = 0,
    i.e. G_inf t_p + G1 tau (e^-(ts-tp)/tau - e^-ts/tau) = G_inf (ts - tp) + G1 tau
    (1 - e^-(ts-tp)/tau), solved by scipy's brentq on [t_peak, 2 t_peak]."""
    from scipy.optimize import brentq

    def balance(ts):
        rise = g_inf * t_peak + g1 * tau * (np.exp(-(ts - t_peak) / tau) - np.exp(-ts / tau))
        fall = g_inf * (ts - t_peak) + g1 * tau * (1 - np.exp(-(ts - t_peak) / tau))
        return rise - fall

    return brentq(balance, t_peak, 2 * t_peak, xtol=1e-14)


def test_paper_viscoelastic_rows_follow_ting(paper_quick):
    _, doc = paper_quick
    ve = doc["viscoelastic"]
    assert ve["parameters"]["n_mdr"] == 2001 and ve["parameters"]["n_bem"] == 33
    assert ve["units"]["radius_error"] == "dx" and ve["units"]["t_separation"] == "s"
    rows = ve["rows"]
    assert {(r["medium"].split("(")[0], r["method"]) for r in rows} == set(VISCOELASTIC_BOUNDS)
    assert len(rows) == 4
    ting = {"StandardSolid": (mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5),
                              sls_separation(1.0, 3.0, 0.5, 1.0)),
            "KelvinVoigt": (mv.KelvinVoigt(G=1.5, eta=0.4), 2 - 0.4 / 1.5)}
    for r in rows:
        name = r["medium"].split("(")[0]
        loading, unloading, radius = VISCOELASTIC_BOUNDS[(name, r["method"])]
        assert r["force_error_loading"] < loading, r
        assert r["force_error_unloading"] < unloading, r
        assert r["radius_error"] < radius, r
        medium, t_sep = ting[name]
        force, _, exact_sep = analytic.ting_paraboloid_triangle(np.linspace(0, 2, 201), medium,
                                                                0.5, 0.2, 1.0)
        assert r["t_separation"] == pytest.approx(exact_sep, rel=1e-12)
        assert r["t_separation"] == pytest.approx(t_sep, rel=1e-10)
        assert r["peak_force"] == pytest.approx(force.max(), rel=1e-12)
        # the force vanishes from the first output after Ting's separation, not before
        assert r["t_last_contact"] < r["t_separation"] <= r["t_first_free"], r
        assert r["t_first_free"] - r["t_last_contact"] == pytest.approx(0.01)
        assert r["dt"] == 0.01 and r["wall_time"] > 0


def test_paper_csv(paper_quick):
    folder, doc = paper_quick
    with open(folder / "paraboloids.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    assert len(table) == 25
    assert float(table[0]["depth_mdr [m]"]) == doc["paraboloids"]["rows"][0]["depth_mdr"]
    with open(folder / "rod.csv", newline="") as handle:
        rod = list(csv.DictReader(handle))
    assert [r["source"] for r in rod][0] == "closed form"
    assert "velocity [m/s]" in rod[0]
    with open(folder / "viscoelastic.csv", newline="") as handle:
        ve = list(csv.DictReader(handle))
    assert len(ve) == 4 and "radius_error [dx]" in ve[0]
    assert float(ve[0]["force_error_loading [1]"]) == doc["viscoelastic"]["rows"][0][
        "force_error_loading"]


def test_paper_text_tables_without_the_study(tmp_path):
    status, out, err = run_cli("paper", "--quick", "--no-study", "--out", str(tmp_path))
    assert status == 0, err
    assert "p0 [Pa]" in out and "dd/dt [m/s]" in out and "Lee-Radok [m]" in out
    assert "Beyond the paper: viscoelastic" in out and "t_s Ting [s]" in out
    assert "paraboloid c=20 MDR" in err and "viscoelastic KelvinVoigt BEM n=33" in err  # progress
    assert "study:" not in err and "Error against run time" not in out
    assert sorted(p.name for p in tmp_path.iterdir()) == sorted(FILES)


# ------------------------------------------------------------------ mdrvisc run
def test_run_scene_json():
    status, out, err = run_cli("run", str(EXAMPLES / "paraboloid_c1_mdr.toml"), "--json")
    assert status == 0, err
    (doc,) = json.loads(out)
    assert doc["input"]["indenter"] == {"type": "paraboloid", "c": 1, "edge": 2.56}
    result = doc["result"]
    assert result["method"] == "mdr" and result["n"] == 66049
    np.testing.assert_allclose(result["depth"], analytic.paraboloid_depth(result["t"], 1, 1, 1),
                               rtol=1e-8)


def test_python_m_mdrvisc_run_and_bad_input(tmp_path):
    done = subprocess.run([sys.executable, "-m", "mdrvisc", "run", str(EXAMPLES / "rod_mdr.toml")],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 0, done.stderr
    assert "central pressure p0 = 0.159155 Pa" in done.stdout
    bad = tmp_path / "bad.toml"
    bad.write_text((EXAMPLES / "rod.toml").read_text().replace("force = 1.0", "forse = 1.0"))
    done = subprocess.run([sys.executable, "-m", "mdrvisc", "run", str(bad)],
                          capture_output=True, text=True, check=False)
    assert done.returncode == 2
    assert done.stderr.startswith("error: ") and "`forse`" in done.stderr


def test_run_errors_exit_2(tmp_path):
    status, _, err = run_cli("run", str(tmp_path / "missing.toml"))
    assert status == 2 and err.startswith("error: invalid input: cannot read scene file")
    invalid = tmp_path / "invalid.toml"
    invalid.write_text("method = \n")
    status, _, err = run_cli("run", str(invalid))
    assert status == 2 and str(invalid) in err and "TOML parse error" in err


# ------------------------------------------------------------------ scene files
@pytest.mark.parametrize("path", sorted(p for p in EXAMPLES.glob("*.toml")
                                       if p.name.startswith(("rod", "paraboloid"))),
                         ids=lambda p: p.name)
def test_example_scene_files_load(path):
    scene, method, n = load_scene(path)
    assert method in ("bem", "mdr") and n > 0
    assert scene.force == 1.0 and scene.medium == mv.Viscous(eta=1.0)


def test_scene_file_builds_the_scene():
    scene, method, n = load_scene(EXAMPLES / "paraboloid_c0.2.toml")
    assert (method, n) == ("bem", 257)
    assert isinstance(scene.indenter, mv.Paraboloid)
    assert (scene.indenter.c, scene.indenter.edge) == (0.2, 2.56)
    np.testing.assert_array_equal(scene.times, [1, 2, 3, 4, 5])
    assert scene.duration == 5.0


def good():
    """A valid scene table (a fresh copy)."""
    return {"method": "mdr", "n": 101, "force": 1.0, "duration": 2.0, "times": [1, 2],
            "outputs": ["depth", "contact_length"],
            "indenter": {"type": "sphere", "radius": 3.0},
            "medium": {"type": "viscous", "eta": 2}}


def test_good_table_solves():
    scene, method, n = parse_scene(good())
    result = mv.solve(scene, method, n)
    assert result.depth.shape == (2,) and np.all(np.diff(result.depth) > 0)


def edit(path, value):
    """``good()`` with the dotted key ``path`` set to ``value`` (None: removed)."""
    data = good()
    *parents, key = path.split(".")
    table = data
    for parent in parents:
        table = table[parent]
    if value is None:
        del table[key]
    else:
        table[key] = value
    return data


@pytest.mark.parametrize("path", ["speed", "indenter.c", "medium.G"])
def test_unknown_key(path):
    """The error names the table and the unknown key."""
    *table, key = path.split(".")
    where = f"key '{table[0]}': " if table else f"key '{key}': "
    with pytest.raises(mv.InvalidInputError, match=f"{where}unknown field `{key}`"):
        parse_scene(edit(path, 1.0))


@pytest.mark.parametrize("path", ["method", "n", "force", "duration", "indenter", "medium",
                                  "indenter.type", "indenter.radius", "medium.eta"])
def test_missing_key(path):
    """The error names the table and the missing key."""
    *table, key = path.split(".")
    where = f"key '{table[0]}': " if table else ""
    with pytest.raises(mv.InvalidInputError, match=f"{where}missing (key '{key}'|field `{key}`)"):
        parse_scene(edit(path, None))


@pytest.mark.parametrize("path, value", [
    ("n", "101"), ("n", 101.0), ("n", True), ("force", "1"), ("force", [[0.0, 1.0, 2.0]]),
    ("duration", [2.0]),
    ("times", [1, "2"]), ("times", 2.0), ("outputs", "depth"), ("method", 1),
    ("indenter", "sphere"), ("indenter.radius", "3"), ("medium.eta", False),
    ("method", "fem"), ("indenter.type", "wedge"), ("n", 0)])
def test_wrong_type_or_value(path, value):
    """The error names the key (a nested table's values: the table) and what was wrong."""
    key = path if path.endswith(".type") else path.split(".")[0]
    named = rf"key '{key}(\[\d+\])?'( must|: (invalid|unknown|a number))"
    with pytest.raises(mv.InvalidInputError, match=named) as info:
        parse_scene(edit(path, value))
    if "." in path and not path.endswith(".type"):
        # the table alone is not enough: the nested key or the offending value is named too
        leaf, msg = path.rsplit(".", 1)[1], str(info.value)
        assert f"`{leaf}`" in msg or f"'{leaf}'" in msg or json.dumps(value) in msg, msg


def test_out_of_range_values_are_invalid_input():
    with pytest.raises(mv.InvalidInputError, match="radius"):
        parse_scene(edit("indenter.radius", -1.0))
    with pytest.raises(mv.InvalidInputError, match="outputs"):
        parse_scene(edit("outputs", ["depth", "temperature"]))


def test_scene_file_dt_is_the_scene_step(tmp_path):
    path = tmp_path / "dt.toml"
    path.write_text((EXAMPLES / "standard_solid_unloading.toml").read_text().replace(
        "duration = 3.0", "duration = 3.0\ndt = 0.05"))
    scene, method, n = load_scene(path)
    assert scene.dt == 0.05
    assert np.array_equal(mv.solve(scene, method, n).force, mv.solve(scene, method, n, dt=0.05).force)
    assert not np.array_equal(mv.solve(scene, method, n).force, mv.solve(scene, method, n, dt=0.01).force)
    with pytest.raises(mv.InvalidInputError, match="dt"):
        parse_scene(edit("dt", -1.0))


def test_viscoelastic_scene_file_with_a_depth_history(tmp_path):
    scene, method, n = load_scene(EXAMPLES / "standard_solid_unloading.toml")
    assert scene.controlled_by == "depth" and isinstance(scene.medium, mv.StandardSolid)
    r = mv.solve(scene, method, n)
    assert r.force.max() > 0 and r.force[-1] == 0
    prony = tmp_path / "prony.toml"
    prony.write_text((EXAMPLES / "standard_solid_unloading.toml").read_text().replace(
        'type = "standardsolid"\nG_inf = 1.0\nG1 = 3.0\ntau1 = 0.5',
        'type = "prony"\nG_inf = 1.0\nterms = [[3.0, 0.5]]'))
    scene_p, _, _ = load_scene(prony)
    assert np.allclose(mv.solve(scene_p, method, n).force, r.force, rtol=1e-12)
    both = tmp_path / "both.toml"
    unloading = (EXAMPLES / "standard_solid_unloading.toml").read_text()
    both.write_text(unloading.replace("duration", "force = 1.0\nduration"))
    with pytest.raises(mv.InvalidInputError, match="only one"):
        load_scene(both)


def test_force_history_in_a_scene_file_is_the_scene_force_history():
    scene, method, n = parse_scene(edit("force", [[0.0, 0.0], [1.0, 2.0]]))
    same = mv.Scene(indenter=scene.indenter, medium=scene.medium, force=([0.0, 1.0], [0.0, 2.0]),
                    duration=scene.duration, times=scene.times)
    assert np.array_equal(mv.solve(scene, method, n).depth, mv.solve(same, method, n).depth)
    # viscous: the depth depends on the impulse alone, 1 N s at t = 1 s as for a constant 1 N
    # (the grids, sized by the final impulse, differ: fine enough that this is ~1e-8)
    constant = mv.solve(parse_scene(edit("force", 1.0))[0], method, 20001)
    assert mv.solve(scene, method, 20001).depth[0] == pytest.approx(constant.depth[0], rel=1e-6)


def _one_line_error(status, err, *words):
    """Exit 2 with a single ``error: ...`` line containing each of ``words``."""
    lines = [line for line in err.splitlines() if line.startswith("error:")]
    assert status == 2 and len(lines) == 1 and "Traceback" not in err, (status, err[-2000:])
    for word in words:
        assert word in lines[0], (word, lines[0])


@pytest.fixture(scope="module")
def curve_file(tmp_path_factory):
    """A CSV curve (t, depth, force) of a standard solid under a sphere, made by mv.solve."""
    t = np.linspace(0.02, 1.0, 50)
    scene = mv.Scene(indenter=mv.Sphere(5e-6), medium=mv.StandardSolid(1e3, 2e3, 0.2),
                     depth=([0.0, 1.0], [0.0, 1e-6]), duration=1.0, times=t)
    r = mv.solve(scene, "mdr", 2001)
    path = tmp_path_factory.mktemp("curve") / "curve.csv"
    np.savetxt(path, np.c_[r.t, r.depth, r.force], delimiter=",", header="t,depth,force", comments="")
    return path


SPHERE = ("--indenter", "sphere:radius=5e-6")


@pytest.mark.skipif(not Path("/dev/zero").exists(), reason="needs /dev/zero")
@pytest.mark.parametrize("command", ["fit", "sweep", "run"])
def test_endless_input_files_stop_at_the_size_bound(command):
    """fit and sweep read /dev/zero without a bound and exited with an empty 'error: '."""
    extra = (*SPHERE, "--model", "elastic") if command == "fit" else ()
    # in a child: an unbounded read never ends
    out = subprocess.run([sys.executable, "-m", "mdrvisc", command, "/dev/zero", *extra],
                         capture_output=True, text=True, timeout=120)
    _one_line_error(out.returncode, out.stderr, "/dev/zero", str(mv._core.MAX_FILE_BYTES))


@pytest.mark.parametrize("text,words", [
    ("", ["empty", "header"]),
    ("t,depth,force\n", ["no rows"]),
    ("t;depth;force\n0.1;1e-7;1e-9\n", ["comma", "semicolon"]),
    ("t,depth,force\n0.1,1e-7\n", ["line 2", "2 values", "3 columns"]),
    ("t,depth,force\n0.1,1e-7,abc\n", ["line 2", "'abc'"]),
])
def test_bad_csv_files_are_one_line_errors(tmp_path, text, words):
    """An empty CSV printed a Python traceback; wrong column counts numpy's 51-line 'Some
    errors were detected !'; a semicolon CSV numpy's 'could not convert'."""
    path = tmp_path / "curve.csv"
    path.write_text(text)
    status, _, err = run_cli("fit", str(path), *SPHERE, "--model", "elastic")
    _one_line_error(status, err, str(path), *words)


@pytest.mark.parametrize("command", ["fit", "sweep"])
def test_non_utf8_files_are_reported_with_their_name(tmp_path, command):
    path = tmp_path / "latin1.csv"
    path.write_bytes("t,depth,force\n# \xe9\n".encode("latin-1"))
    extra = (*SPHERE, "--model", "elastic") if command == "fit" else ()
    status, _, err = run_cli(command, str(path), *extra)
    _one_line_error(status, err, str(path), "UTF-8")


def test_a_byte_order_mark_is_accepted_in_sweep_files_as_in_scene_files(tmp_path):
    source = EXAMPLES / "sweeps" / "relaxation_times.toml"
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + source.read_bytes())
    assert len(mv.load_sweep(path)[0]) == len(mv.load_sweep(source)[0])


def test_unknown_indenter_keys_list_the_accepted_ones(curve_file):
    """--indenter sphere:r=5e-6 answered 'Sphere.__init__() got an unexpected keyword
    argument 'r''."""
    status, _, err = run_cli("fit", str(curve_file), "--indenter", "sphere:r=5e-6", "--model", "elastic")
    _one_line_error(status, err, "'r'", "radius")
    status, _, err = run_cli("fit", str(curve_file), "--indenter", "cone:", "--model", "elastic")
    _one_line_error(status, err, "slope")


def test_too_many_prony_terms_is_a_terms_error(curve_file):
    """--terms 100000 was reported as a tau_k range error."""
    status, _, err = run_cli("fit", str(curve_file), *SPHERE, "--model", "prony", "--terms", "100000")
    _one_line_error(status, err, "terms")
    assert "tau" not in err


def test_the_fit_table_has_no_relative_error_for_a_parameter_at_zero(curve_file):
    """A parameter that ran to 0 printed a relative error of +inf beside a standard error 0."""
    result = mv.fit(mv.Sphere(5e-6), mv.StandardSolid, *np.loadtxt(curve_file, delimiter=",",
                                                                   skiprows=1).T[:1],
                    depth=np.loadtxt(curve_file, delimiter=",", skiprows=1)[:, 1],
                    force=np.loadtxt(curve_file, delimiter=",", skiprows=1)[:, 2])
    result.parameters["G_inf"] = 0.0
    result.stderr["G_inf"] = 0.0
    text = repr(result)
    row = next(line for line in text.splitlines() if line.strip().startswith("G_inf"))
    assert "inf" not in row.replace("G_inf", "") and "undetermined" in row, row


def test_run_out_writes_json_csv_and_npz(tmp_path):
    scene = EXAMPLES / "paraboloid_c1_mdr.toml"
    status, out, _ = run_cli("run", str(scene), "--json", "--no-progress")
    assert status == 0
    for suffix in (".json", ".csv", ".npz"):
        path = tmp_path / f"out{suffix}"
        assert run_cli("run", str(scene), "--no-progress", "--out", str(path))[0] == 0
        document = json.loads(out)[0]["result"]
        if suffix == ".json":
            written = json.loads(path.read_text())[0]["result"]
            assert written["depth"] == document["depth"] and written["t"] == document["t"]
        elif suffix == ".csv":
            rows = list(csv.DictReader(path.open()))
            assert [float(r["depth"]) for r in rows] == document["depth"]
            assert [float(r["t"]) for r in rows] == document["t"]
        else:
            result = mv.Result.load(path)
            assert result.depth is not None and len(result.t) == len(rows)
    status, _, err = run_cli("run", str(scene), "--no-progress", "--out", str(tmp_path / "out.txt"))
    _one_line_error(status, err, ".csv")


def test_sweep_out_writes_the_table(tmp_path):
    path = EXAMPLES / "sweeps" / "relaxation_times.toml"
    status, out, _ = run_cli("sweep", str(path), "--json", "--no-progress", "--out", str(tmp_path / "t.csv"))
    assert status == 0
    rows = json.loads(out)
    written = list(csv.DictReader((tmp_path / "t.csv").open()))
    assert len(written) == len(rows) and set(written[0]) == set(rows[0])
    assert [float(r["depth"]) for r in written] == [r["depth"] for r in rows]
