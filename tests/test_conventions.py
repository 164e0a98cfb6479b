"""The conventions users expect: a readable repr on every public class, the version on the
command line, diagnostics through the "mdrvisc" logger, and a progress bar with the time left."""

import inspect
import io
import logging
import re
import subprocess
import sys

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.progress import ProgressBar

_SCENE = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.5),
                  force=1.0, duration=1.0, times=[0.5, 1.0])
#: Sample times of the fitted curve (s): an elastic paraboloid (G = 2 Pa, R = 0.5 m) at 0.1 m/s.
_T = np.array([0.25, 0.5, 0.75, 1.0])

#: One instance of every concrete public class, with strings its repr must show (its
#: parameters).
EXAMPLES = {
    "Scene": (lambda: _SCENE, ["Paraboloid", "1.5"]),
    "Result": (lambda: mv.solve(_SCENE, "mdr", 257), ["MDR", "n=257", "depth="]),
    "Fields": (lambda: mv.Fields(t=0.25, pressure=np.zeros((3, 3))), ["0.25"]),
    "Rod": (lambda: mv.Rod(radius=0.75), ["0.75"]),
    "Paraboloid": (lambda: mv.Paraboloid(c=0.2, edge=3.5), ["0.2", "3.5"]),
    "Cone": (lambda: mv.Cone(slope=0.3), ["0.3"]),
    "Sphere": (lambda: mv.Sphere(radius=2.5), ["2.5"]),
    "Pyramid": (lambda: mv.Pyramid(half_angle=0.6, edge=1.5), ["0.6", "1.5"]),
    "Axisymmetric": (lambda: mv.Axisymmetric(lambda r: 0.5 * r**2, edge=2.0), ["2"]),
    "Profile": (lambda: mv.Profile([0.0, 1.0, 2.0], [0.0, 0.5, 2.0]), ["3"]),
    "HeightMap": (lambda: mv.HeightMap(np.zeros((3, 5)), 0.25, periodic=True), ["(3, 5)", "0.25", "True"]),
    "Layer": (lambda: mv.Layer(5e-6, "frictionless"), ["5e-06", "frictionless"]),
    "Viscous": (lambda: mv.Viscous(eta=2.5), ["2.5"]),
    "Hard": (lambda: mv.Hard(), []),
    "JKR": (lambda: mv.JKR(work_of_adhesion=0.05), ["0.05"]),
    "DMT": (lambda: mv.DMT(work_of_adhesion=0.07), ["0.07"]),
    "MaugisDugdale": (lambda: mv.MaugisDugdale(work_of_adhesion=0.05, stress=2e7), ["0.05", "20000000.0"]),
    "Exponential": (lambda: mv.Exponential(work_of_adhesion=0.05, range=3e-9), ["0.05", "3e-09"]),
    "Elastic": (lambda: mv.Elastic(G=7.0), ["7"]),
    "KelvinVoigt": (lambda: mv.KelvinVoigt(G=1.5, eta=0.4), ["1.5", "0.4"]),
    "Maxwell": (lambda: mv.Maxwell(G=1.5, eta=0.4), ["1.5", "0.4"]),
    "StandardSolid": (lambda: mv.StandardSolid(G_inf=1.0, G1=3.0, tau1=0.5), ["3", "0.5"]),
    "Prony": (lambda: mv.Prony(G_inf=1.0, terms=((2.0, 0.25),)), ["2", "0.25"]),
    "PowerLaw": (lambda: mv.PowerLaw(G0=2.0, beta=0.2, t0=1.5), ["2", "0.2", "1.5"]),
    "FitResult": (lambda: mv.fit(mv.Paraboloid(c=1.0), mv.Elastic, _T, depth=0.1 * _T,
                                 force=16 / 3 * 2.0 * np.sqrt(0.5) * (0.1 * _T) ** 1.5),
                  ["Elastic", "4 samples", "G ", "stderr"]),
    "MdrviscError": (lambda: mv.MdrviscError("bad n"), ["bad n"]),
    "InvalidInputError": (lambda: mv.InvalidInputError("bad n"), ["bad n"]),
    "ConvergenceError": (lambda: mv.ConvergenceError("no convergence"), ["no convergence"]),
    "DomainError": (lambda: mv.DomainError("outside"), ["outside"]),
    "ResolutionWarning": (lambda: mv.ResolutionWarning("coarse"), ["coarse"]),
    "DataError": (lambda: mv.DataError("unsorted times"), ["unsorted times"]),
    "IdentifiabilityWarning": (lambda: mv.IdentifiabilityWarning("tau1"), ["tau1"]),
    "SurfaceOperator": (lambda: mv.arrays.SurfaceOperator((8, 16), 0.1), ["8", "16", "0.1"]),
    "ProgressBar": (lambda: ProgressBar(file=io.StringIO(), use_tqdm=False), ["stage"]),
    "Sweep": (lambda: mv.Sweep([_SCENE, _SCENE], "mdr", 257, [None, None], []), ["MDR", "n=257", "0/2"]),
    "SceneFailure": (lambda: mv.SceneFailure(3, _SCENE, mv.DomainError("outside")),
                     ["3", "DomainError", "outside"]),
}


def _public_classes():
    """Every concrete class named in ``mdrvisc.__all__``, plus those of the public modules
    that are not exported at the top level."""
    names = [n for n in mv.__all__ if inspect.isclass(getattr(mv, n))]
    found = {n: getattr(mv, n) for n in names if not inspect.isabstract(getattr(mv, n))}
    found["SurfaceOperator"] = mv.arrays.SurfaceOperator
    found["ProgressBar"] = ProgressBar
    return found


def test_every_public_class_has_an_example():
    missing = sorted(set(_public_classes()) - set(EXAMPLES))
    assert not missing, f"give these public classes an example in EXAMPLES: {missing}"


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")
@pytest.mark.parametrize("name", sorted(EXAMPLES))
def test_repr_is_readable(name):
    make, shown = EXAMPLES[name]
    obj = make()
    assert type(obj).__name__ == name or isinstance(obj, _public_classes()[name])
    text = repr(obj)
    assert " object at 0x" not in text, text
    assert name in text, text
    assert len(text) < 400, text
    for value in shown:
        assert value in text, f"{value!r} not in {text!r}"


def test_version_on_the_python_command_line():
    out = subprocess.run([sys.executable, "-m", "mdrvisc", "--version"], capture_output=True,
                         text=True, check=True).stdout
    assert out.strip() == f"mdrvisc {mv.__version__}"


def test_solves_are_logged_to_the_mdrvisc_logger(caplog):
    with caplog.at_level(logging.INFO, logger="mdrvisc"):
        result = mv.solve(_SCENE, "mdr", 257)
    records = [r for r in caplog.records if r.name == "mdrvisc"]
    assert len(records) == 2, records
    assert "MDR n=257" in records[0].getMessage()
    assert f"steps={result.steps}" in records[1].getMessage()


def test_the_library_logs_nothing_unless_logging_is_configured():
    code = ("import mdrvisc as mv\n"
            "s = mv.Scene(indenter=mv.Rod(radius=1.0), medium=mv.Viscous(eta=1.0), force=1.0,"
            " duration=1.0)\n"
            "mv.solve(s, 'mdr', 65)\n")
    err = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True).stderr
    assert err == ""


def test_plain_progress_line_shows_the_time_left_from_the_mean_rate(monkeypatch):
    clock = iter([0.0, 4.0, 10.0])
    monkeypatch.setattr("mdrvisc.progress.time.perf_counter", lambda: next(clock))
    out = io.StringIO()
    bar = ProgressBar(file=out, use_tqdm=False)
    bar("time steps", 0, 100)   # stage starts at t = 0
    bar("time steps", 20, 100)  # 20 steps in 4 s: 80 left at 0.2 s each, 16 s
    bar("time steps", 100, 100)
    lines = out.getvalue().split("\r")
    assert "20/100 4.0 s, 16.0 s left" in lines[-2]
    assert lines[-1].rstrip().endswith("100/100 10.0 s") and out.getvalue().endswith("\n")
    assert "#" * 24 in lines[-1]


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")
def test_progress_true_draws_a_bar_on_stderr(capsys):
    mv.solve(_SCENE, "bem", 33, progress=True)
    err = capsys.readouterr().err
    assert re.search(r"\d+/\d+", err), err


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")
def test_the_command_line_run_shows_a_bar_and_can_be_silenced(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_text(_SCENE.to_toml("bem", 33))
    shown = subprocess.run([sys.executable, "-m", "mdrvisc", "run", str(path)],
                           capture_output=True, text=True, check=True).stderr
    assert re.search(r"\d+/\d+", shown), shown
    quiet = subprocess.run([sys.executable, "-m", "mdrvisc", "run", "--no-progress", str(path)],
                           capture_output=True, text=True, check=True).stderr
    assert not re.search(r"\d+/\d+ ", quiet), quiet


def test_tqdm_bar_when_tqdm_is_installed():
    pytest.importorskip("tqdm", reason="tqdm (the 'progress' extra) is optional")
    out = io.StringIO()
    bar = ProgressBar(file=out, use_tqdm=True)
    for k in range(1, 6):
        bar("time steps", k, 5)
        bar("contact iterations", 3 * k, 5000)
    text = out.getvalue()
    assert "time steps" in text and "5/5" in text, text
    assert repr(bar).endswith("tqdm=True)")
