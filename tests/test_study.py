"""The error-vs-run-time study: quick mode runs in seconds, errors fall with
resolution where they must, the paper's settings are marked, and its files are written."""

import csv
import json
import math

import numpy as np
import pytest

from mdrvisc import analytic
from mdrvisc.paper import report, studies


@pytest.fixture(scope="module")
def study():
    labels = []
    result = studies.error_vs_runtime(quick=True, progress=labels.append)
    result["labels"] = labels
    return result


def pick(study, **match):
    """The study's rows whose keys equal ``match``, coarse to fine (n up, step down)."""
    rows = [r for r in study["rows"] if all(r[k] == v for k, v in match.items())]
    return sorted(rows, key=lambda r: (r["n"], -(r["step"] or 0.0)))


def order(study, **match):
    (entry,) = [o for o in study["orders"] if all(o[k] == v for k, v in match.items())]
    return entry


def test_quick_study_covers_methods_integrators_and_quantities(study):
    rows = study["rows"]
    assert study["quick"] is True and study["total_wall_time"] < 30
    kinds = {(r["case"], r["method"], r["integrator"], r["quantity"]) for r in rows}
    for c in ("paraboloid c=1", "paraboloid c=5"):
        for integrator in ("implicit", "explicit"):
            for q in ("depth", "contact_length", "stiffness_length"):
                assert (c, "BEM", integrator, q) in kinds
            for q in ("depth", "contact_length"):
                assert (c, "MDR", integrator, q) in kinds
    for method in ("BEM", "MDR"):
        for q in ("velocity", "central_pressure"):
            assert ("rod", method, "one solve", q) in kinds
    assert {r["area_change"] for r in rows if r["method"] == "MDR" and r["step"]} == {0.0, 0.01}
    assert all(r["wall_time"] > 0 and math.isfinite(r["error"]) for r in rows)
    assert len(study["labels"]) == len({(r["case"], r["method"], r["n"], r["step"],
                                         r["area_change"]) for r in rows})


def test_errors_are_against_the_closed_forms(study):
    for r in study["rows"]:
        assert r["error"] == pytest.approx(r["value"] / r["exact"] - 1, rel=1e-9, abs=1e-15)
    depth = pick(study, case="paraboloid c=5", quantity="depth")[0]
    assert depth["exact"] == pytest.approx(analytic.paraboloid_depth(5.0, 1.0, 5.0, 1.0))
    rod = pick(study, case="rod", quantity="central_pressure")[0]
    assert rod["exact"] == pytest.approx(1 / (2 * math.pi))


def test_implicit_bem_depth_converges_with_resolution(study):
    errs = [abs(r["error"]) for r in pick(study, case="paraboloid c=1", quantity="depth",
                                          method="BEM", integrator="implicit")]
    assert len(errs) >= 3 and all(a > b for a, b in zip(errs, errs[1:]))
    c5 = [abs(r["error"]) for r in pick(study, case="paraboloid c=5", quantity="depth",
                                        method="BEM", integrator="implicit")]
    assert c5[-1] < c5[0] / 3
    p = order(study, case="paraboloid c=1", quantity="depth", method="BEM",
              integrator="implicit", variable="dx")
    assert 1.2 < p["order"] < 2.5


def test_explicit_mdr_without_area_rule_converges_first_order_in_the_step(study):
    for case in ("paraboloid c=1", "paraboloid c=5"):
        rows = pick(study, case=case, quantity="depth", method="MDR", integrator="explicit",
                    n=66049, area_change=0.0)
        errs = [abs(r["error"]) for r in rows]
        assert len(errs) >= 3 and all(a > b for a, b in zip(errs, errs[1:]))
        p = order(study, case=case, quantity="depth", method="MDR", integrator="explicit",
                  variable="step", against="closed form", fixed="n=66049, area_change=0")
        assert 0.9 < p["order"] < 1.1 and 0.9 < p["order_last"] < 1.1


def test_paper_area_rule_stalls_explicit_mdr(study):
    def finest(area_change):
        rows = pick(study, case="paraboloid c=1", quantity="depth", method="MDR",
                    integrator="explicit", n=66049, area_change=area_change)
        return abs(rows[-1]["error"])

    assert finest(0.01) > 5 * finest(0.0)


def test_mdr_rod_is_exact_and_bem_rod_converges(study):
    for q in ("velocity", "central_pressure"):
        assert all(abs(r["error"]) < 1e-12 for r in pick(study, case="rod", quantity=q,
                                                          method="MDR"))
        bem = [abs(r["error"]) for r in pick(study, case="rod", quantity=q, method="BEM")]
        assert all(a > b for a, b in zip(bem, bem[1:]))
    assert order(study, case="rod", quantity="velocity", method="MDR")["order"] is None


def test_paper_settings_are_marked(study):
    marked = {(r["case"], r["method"], r["integrator"], r["n"], r["step"]) for r in study["rows"]
              if r["paper"]}
    assert ("rod", "BEM", "one solve", 200, None) in marked
    assert ("rod", "MDR", "one solve", 66049, None) in marked
    assert ("paraboloid c=1", "MDR", "implicit", 66049, None) in marked
    assert ("paraboloid c=1", "MDR", "explicit", 66049, 0.01) in marked
    # quick mode leaves out the slow BEM 257 explicit run
    assert not any(r["method"] == "BEM" and r["case"] != "rod" for r in study["rows"] if r["paper"])


def test_explicit_rows_carry_their_time_error(study):
    for r in study["rows"]:
        if r["integrator"] == "explicit":
            assert r["error_vs_implicit"] is not None
        else:
            assert r["error_vs_implicit"] is None
    # MDR's implicit answer is exact to ~1e-8 here: the explicit error is all time error
    for r in pick(study, method="MDR", integrator="explicit", quantity="depth", n=66049):
        assert r["error_vs_implicit"] == pytest.approx(r["error"], abs=1e-8)


def test_files_and_text(study, tmp_path):
    paths = report.write_error_vs_runtime(study, tmp_path)
    assert sorted(p.name for p in paths) == sorted(
        ["error_vs_runtime.csv", "error_vs_runtime_orders.csv", "error_vs_runtime.json",
         "error_vs_runtime.png"])
    with open(tmp_path / "error_vs_runtime.csv", newline="") as handle:
        table = list(csv.DictReader(handle))
    assert len(table) == len(study["rows"])
    assert "wall_time [s]" in table[0] and "dx [m]" in table[0]
    assert float(table[0]["error [1]"]) == study["rows"][0]["error"]
    with open(tmp_path / "error_vs_runtime_orders.csv", newline="") as handle:
        assert len(list(csv.DictReader(handle))) == len(study["orders"])
    doc = json.loads((tmp_path / "error_vs_runtime.json").read_text())
    assert doc["quick"] is True and len(doc["rows"]) == len(study["rows"])
    assert doc["units"]["wall_time"] == "s"
    assert (tmp_path / "error_vs_runtime.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    text = report.error_table(study)
    assert "paraboloid c=1: d(5 s) [m]" in text and "*" in text
    assert "order (fit)" in report.orders_table(study)


def test_settings_override():
    small = studies.error_vs_runtime(settings={
        "cs": (1.0,), "bem_n": (17, 33), "bem_explicit": {17: (0.1,)}, "mdr_n": (257, 1025),
        "mdr_steps": (0.1, 0.03), "mdr_area_changes": (0.0,), "mdr_explicit_n": 1025,
        "mdr_explicit_cross_n": (), "rod_bem_n": (20,), "rod_mdr_n": (257,)})
    assert {r["n"] for r in small["rows"] if r["method"] == "BEM" and r["case"] != "rod"} == {17, 33}
    assert np.all([r["case"] in ("paraboloid c=1", "rod") for r in small["rows"]])
