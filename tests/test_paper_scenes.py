"""The paper's scenes as data: the scene files of examples/paper, the copy the package ships,
how mdrvisc.paper reads them (at call time, not import time), and mdrvisc paper without
matplotlib."""

import contextlib
import io
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mdrvisc as mv
from mdrvisc import _core, cli
from mdrvisc.paper import report, runs

EXAMPLES = Path(__file__).resolve().parent.parent / "examples" / "paper"


def test_the_package_ships_the_example_scene_files_unchanged():
    shipped = sorted(p.name for p in runs.SCENES.glob("*.toml"))
    assert shipped == sorted(p.name for p in EXAMPLES.glob("*.toml")) and shipped
    for name in shipped:
        assert (runs.SCENES / name).read_bytes() == (EXAMPLES / name).read_bytes(), name


def test_the_paper_scenes_are_its_runs():
    """Section 5: the rod (a = 1 m), BEM n = 200 (31417 elements in the disc) and MDR 66049;
    Section 6: paraboloids c = 0.05 ... 20 1/m on the 2.56 m square, BEM 257 x 257, MDR 66049;
    --quick: BEM 50 and 65, MDR 4097."""
    full, quick = runs.load_runs(), runs.load_runs(quick=True)
    assert [r.name for r in full] == [r.name for r in quick]
    assert [(r.name, r.method) for r in full[:2]] == [("rod a=1", "bem"), ("rod a=1", "mdr")]
    scenes = runs.load_scenes()
    assert scenes.curvatures == (0.05, 0.2, 1.0, 5.0, 20.0)
    assert scenes.rod_resolutions == runs.Resolutions(n_bem=200, n_mdr=66049)
    assert scenes.paraboloid_resolutions == runs.Resolutions(n_bem=257, n_mdr=66049)
    coarse = runs.load_scenes(quick=True)
    assert coarse.rod_resolutions == runs.Resolutions(n_bem=50, n_mdr=4097)
    assert coarse.paraboloid_resolutions == runs.Resolutions(n_bem=65, n_mdr=4097)
    assert isinstance(scenes.rod.indenter, mv.Rod) and scenes.rod.indenter.radius == 1.0
    assert scenes.paraboloid.indenter.edge == 2.56 and scenes.paraboloid.duration == 5.0
    assert scenes.paraboloid.outputs == ("depth", "contact_length", "stiffness_length")
    for r in full:
        assert r.scene.force == 1.0 and isinstance(r.scene.medium, mv.Viscous) and r.scene.medium.eta == 1.0


def test_scene_folders_and_files_are_checked(tmp_path):
    with pytest.raises(mv.InvalidInputError, match="no scene files"):
        runs.load_runs(directory=tmp_path)
    text = (EXAMPLES / "01_rod_bem.toml").read_text()
    (tmp_path / "rod.toml").write_text(text.replace('name = "rod a=1"\n', ""))
    with pytest.raises(mv.InvalidInputError, match="rod.toml.*'name'"):
        runs.load_runs(directory=tmp_path)
    named = 'name = "rod a=1"\n'
    (tmp_path / "rod.toml").write_text(text.replace(named, named + "colour = 1\n"))
    with pytest.raises(mv.InvalidInputError, match="colour"):
        runs.load_runs(directory=tmp_path)
    (tmp_path / "rod.toml").write_text(text.split("\n[quick]")[0].replace(named, named + "quick = 3\n"))
    with pytest.raises(mv.InvalidInputError, match="'quick' must be a table"):
        runs.load_runs(directory=tmp_path)
    (tmp_path / "rod.toml").write_text(text)
    with pytest.raises(mv.InvalidInputError, match="the rod by MDR at one resolution, got \\[\\]"):
        runs.load_scenes(directory=tmp_path)


def test_importing_the_paper_reads_no_scene():
    """mdrvisc.paper parses no scene at import: with the scene-file parser replaced by one that
    fails, the import succeeds and only reading the scenes fails."""
    code = ("import mdrvisc.scenefile as f\n"
            "def refuse(*args, **kwargs):\n"
            "    raise RuntimeError('parsed a scene')\n"
            "f.parse_scene = refuse\n"
            "import mdrvisc.paper\n"
            "from mdrvisc.paper import runs\n"
            "try:\n"
            "    runs.load_runs()\n"
            "except RuntimeError as exc:\n"
            "    print('refused:', exc)\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "refused: parsed a scene", out.stderr
    assert not hasattr(_core, "paper_scenes")


def test_figures_without_matplotlib_name_the_extra(monkeypatch, tmp_path):
    """Without matplotlib: the plotting functions raise ImportError naming mdrvisc[paper];
    mdrvisc paper writes the tables and CSV/JSON files, no figures, and says so."""
    for name in [m for m in sys.modules if m == "matplotlib" or m.startswith("matplotlib.")]:
        monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    assert not report.can_draw()
    with pytest.raises(ImportError, match=r"mdrvisc\[paper\]"):
        report.plot_rod({}, tmp_path / "rod.png")
    scenes = tmp_path / "scenes"
    scenes.mkdir()
    for name in ("01_rod_bem.toml", "02_rod_mdr.toml", "11_paraboloid_c20_bem.toml",
                 "12_paraboloid_c20_mdr.toml"):
        shutil.copy(EXAMPLES / name, scenes / name)
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(["paper", "--quick", "--no-study", "--scenes", str(scenes),
                           "--out", str(tmp_path / "out")])
    assert status == 0, err.getvalue()
    assert "matplotlib is not installed" in err.getvalue() and "mdrvisc[paper]" in err.getvalue()
    written = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert written == ["paper.json", "paraboloids.csv", "rod.csv", "viscoelastic.csv"]
    assert "Rod (Section 5)" in out.getvalue() and "Paraboloids (Section 6)" in out.getvalue()
