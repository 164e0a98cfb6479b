"""The paper's explicit loop as a selectable integrator: first-order convergence, and the
implicit impulse step being exact in time."""

import warnings

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import analytic

SCENE = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0), force=1.0,
                 duration=5.0, outputs=("depth", "contact_length", "stiffness_length"))
EXACT = analytic.paraboloid_depth(5.0, 1.0, 1.0, 1.0)


def test_explicit_mdr_converges_first_order_in_the_step():
    errs = [abs(mv.solve(SCENE, "mdr", 66049, integrator="explicit", step=s, area_change=0.0)
                .depth[-1] / EXACT - 1) for s in (0.1, 0.01, 0.001)]
    for coarse, fine in zip(errs, errs[1:]):
        assert 5 < coarse / fine < 20


def test_paper_area_rule_limits_explicit_accuracy():
    strict = mv.solve(SCENE, "mdr", 66049, integrator="explicit", step=1e-3, area_change=0.0)
    paper = mv.solve(SCENE, "mdr", 66049, integrator="explicit", step=1e-3, area_change=0.01)
    assert abs(paper.depth[-1] / EXACT - 1) > 10 * abs(strict.depth[-1] / EXACT - 1)


def test_explicit_bem_approaches_the_implicit_answer():
    implicit = mv.solve(SCENE, "bem", 65)
    errs = [abs(mv.solve(SCENE, "bem", 65, integrator="explicit", step=s).depth[-1] / implicit.depth[-1] - 1)
            for s in (0.1, 0.01)]
    assert errs[1] < errs[0] < 0.01
    r = mv.solve(SCENE, "bem", 65, integrator="explicit", step=0.1)
    assert r.steps > 100 and r.solves > 10 and r.integrator == "explicit"


def test_explicit_steps_are_bounded_and_warned():
    """dt = step * t: a step of 1e6 gave depths 650 times the closed form without a word.
    Steps above 1 are refused; steps above 0.1 are solved with a warning, and their error
    against Lee–Radok shows why (first order: several times the error at 0.1)."""
    with pytest.raises(mv.InvalidInputError, match="explicit step"):
        mv.solve(SCENE, "mdr", 4097, integrator="explicit", step=2.0)
    errors = {}
    for step in (0.1, 1.0):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = mv.solve(SCENE, "mdr", 66049, integrator="explicit", step=step, area_change=0.0)
        warned = [w for w in r.warnings if "explicit step" in w]
        assert bool(warned) == (step > 0.1), r.warnings
        errors[step] = abs(r.depth[-1] / EXACT - 1)
    assert errors[1.0] > 3 * errors[0.1], errors


@pytest.mark.parametrize("method,n", [("bem", 65), ("mdr", 4097)])
def test_implicit_result_does_not_depend_on_output_times(method, n):
    coarse = mv.Scene(indenter=SCENE.indenter, medium=SCENE.medium, force=1.0, duration=5.0, times=[5.0])
    fine = mv.Scene(indenter=SCENE.indenter, medium=SCENE.medium, force=1.0, duration=5.0,
                    times=np.linspace(0.05, 5.0, 100))
    a = mv.solve(coarse, method, n).depth[-1]
    b = mv.solve(fine, method, n).depth[-1]
    assert a == pytest.approx(b, rel=1e-7)


def test_explicit_needs_a_viscous_medium_and_valid_controls():
    elastic = mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Elastic(G=1.0), force=1.0)
    with pytest.raises(mv.InvalidInputError):
        mv.solve(elastic, "bem", 33, integrator="explicit")
    with pytest.raises(mv.InvalidInputError, match="step"):
        mv.solve(SCENE, "mdr", 101, integrator="explicit", step=-1.0)
    with pytest.raises(mv.InvalidInputError, match="integrator"):
        mv.solve(SCENE, "mdr", 101, integrator="rk4")
