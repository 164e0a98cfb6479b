"""Bad input gets a clear exception naming the bad value."""

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import _core

VISCOUS = mv.Viscous(eta=1.0)
PARA = mv.Paraboloid(c=1.0, edge=2.56)


@pytest.mark.parametrize("make,match", [
    (lambda: mv.Viscous(eta=0.0), "eta"),
    (lambda: mv.Viscous(eta=-1.0), "eta"),
    (lambda: mv.Viscous(eta=float("nan")), "eta"),
    (lambda: mv.Elastic(G=float("inf")), "G"),
    (lambda: mv.Rod(radius=0.0), "radius"),
    (lambda: mv.Paraboloid(c=-1.0), "c"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=0.0, duration=1.0), "force"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=-1.0, duration=1.0), "force"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=0.0), "duration"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=-5.0), "duration"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1j), "duration"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0, dt=1j), "dt"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0), "duration"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0, times=[0.5, 0.2]), "times"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0, times=[np.nan]), "times"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0, times=[2.0]), "times"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=([0, 1], [1, -1]), duration=1.0), "forces"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=([0, 0], [1, 1]), duration=1.0), "times"),
    (lambda: mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0, outputs=("stress",)), "stress"),
    (lambda: mv.Scene(indenter="cone", medium=VISCOUS, force=1.0, duration=1.0), "indenter"),
])
def test_bad_parameters_raise_invalid_input(make, match):
    with pytest.raises(mv.InvalidInputError, match=match) as info:
        make()
    assert isinstance(info.value, ValueError)


@pytest.mark.parametrize("n", [0, -3, 2.5, True, "257", 10**6])
def test_bad_grid_sizes(n):
    scene = mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="n"):
        mv.solve(scene, "bem", n)


def test_bad_method_and_tolerances():
    scene = mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="method"):
        mv.solve(scene, "fem", 33)
    with pytest.raises(mv.InvalidInputError, match="tol must be a finite positive number"):
        mv.solve(scene, "bem", 33, tol=0.0)
    with pytest.raises(mv.InvalidInputError, match="max_iter"):
        mv.solve(scene, "bem", 33, max_iter=0)


@pytest.mark.parametrize("height,match", [
    (np.array([[0.0, np.nan], [0.0, 0.0]]), "finite"),
    (np.array([[0.0, np.inf], [0.0, 0.0]]), "finite"),
    (np.zeros((2, 2), dtype=complex), "real"),
    (np.array([["a", "b"]]), "real"),
    (np.zeros(4), "2-D"),
    (np.zeros((0, 3)), "2-D"),
    (-np.ones((2, 2)), ">= 0"),
])
def test_bad_height_maps(height, match):
    with pytest.raises(mv.InvalidInputError, match=match):
        mv.arrays.viscous(height, 0.1, 1.0, 1.0, [1.0])


def test_layouts_and_integer_dtypes_are_accepted():
    x = (np.arange(33) - 16) * 0.08
    h = x[None, :] ** 2 + x[:, None] ** 2
    ref = mv.arrays.viscous(h, 0.08, 1.0, 1.0, [1.0]).depth
    strided = np.zeros((66, 66))
    strided[::2, ::2] = h
    for view in (strided[::2, ::2], np.asfortranarray(h)):
        assert mv.arrays.viscous(view, 0.08, 1.0, 1.0, [1.0]).depth == pytest.approx(ref, rel=1e-12)
    flat = mv.arrays.viscous(np.zeros((5, 5), dtype=np.int32), 0.08, 1.0, 1.0, [1.0])
    assert flat.depth[0] > 0


def test_core_rejects_non_contiguous_and_mismatched_arrays_clearly():
    h = np.zeros((8, 8))
    with pytest.raises(mv.InvalidInputError, match="shape"):
        _core.bem_viscous(h, np.ones((8, 7), bool), 0.1, 1.0, np.array([1.0]), np.array([0.0]),
                          np.array([1.0]))
    with pytest.raises(ValueError, match="contiguous"):
        _core.bem_viscous(h, np.ones((8, 8), bool), 0.1, 1.0, np.array([1.0, 9.0, 2.0, 9.0])[::2],
                          np.array([0.0]), np.array([1.0]))
    with pytest.raises(mv.InvalidInputError, match="dx"):
        _core.bem_viscous(h, np.ones((8, 8), bool), -0.1, 1.0, np.array([1.0]), np.array([0.0]),
                          np.array([1.0]))
    with pytest.raises(mv.InvalidInputError, match="footprint"):
        _core.bem_viscous(h, np.zeros((8, 8), bool), 0.1, 1.0, np.array([1.0]), np.array([0.0]),
                          np.array([1.0]))
    with pytest.raises(mv.InvalidInputError, match="depth bounds"):
        _core.bem_viscous(h, np.ones((8, 8), bool), 0.1, 1.0, np.array([1.0, 2.0]), np.array([0.0]),
                          np.array([1.0]), depth_bounds=[0.1])


def test_non_convergence_is_an_exception_with_its_numbers():
    scene = mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0)
    with pytest.raises(mv.ConvergenceError) as info:
        mv.solve(scene, "bem", 65, max_iter=2)
    assert info.value.iterations == 2 and np.isfinite(info.value.residual)
    assert "residual" in str(info.value) and "2 iterations" in str(info.value)


def test_sizes_are_checked_before_anything_is_allocated():
    """Step counts, grids and explicit steps beyond the stated limits are errors that say what
    they would cost, raised before any allocation (each case would otherwise take the
    machine's memory or run for days)."""
    scene = mv.Scene(indenter=PARA, medium=mv.StandardSolid(1.0, 3.0, 0.5), force=1.0, duration=2.0)
    for method, n in (("mdr", 201), ("bem", 33)):
        with pytest.raises(mv.InvalidInputError,
                           match=r"dt = 1e-308 s over 2 s is 2\.0e308 steps, more than 1e7"):
            mv.solve(scene, method, n, dt=1e-308)
    with pytest.raises(mv.InvalidInputError, match="2.000e300 steps"):
        mv.Scene(indenter=PARA, medium=mv.Maxwell(1.0, 1.0), force=1.0, duration=2.0, dt=1e-300)
    viscous = mv.Scene(indenter=PARA, medium=VISCOUS, force=1.0, duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="explicit step"):
        mv.solve(viscous, "mdr", 201, integrator="explicit", step=1e-9)
    for method, n in (("bem", 100000), ("mdr", 10**12)):
        with pytest.raises(mv.InvalidInputError, match="resolution n"):
            mv.solve(viscous, method, n)
    for shape in ((20000, 20000), (1, 10**9), (2**40, 2**40)):
        with pytest.raises(mv.InvalidInputError, match="elements"):
            mv.arrays.SurfaceOperator(shape, 1.0)


@pytest.mark.parametrize("medium", [mv.Viscous(eta=1.0), mv.KelvinVoigt(G=1.0, eta=1.0)])
@pytest.mark.parametrize("depth", [0.1, ([0.0, 1.0], [0.1, 0.2])])
def test_a_depth_held_from_t0_on_a_dashpot_is_refused(medium, depth):
    """A dashpot pressed to a depth at t = 0 takes an infinite impulse: the solvers returned
    a force of 3e-17 N (MDR) or ran into their iteration limit (BEM). A history that starts
    from 0 is solved."""
    indenter = mv.Paraboloid(c=1.0, edge=2.56)
    with pytest.raises(mv.InvalidInputError, match="infinite force"):
        mv.Scene(indenter=indenter, medium=medium, depth=depth, duration=1.0)
    ramp = mv.Scene(indenter=indenter, medium=medium, depth=([0.0, 1.0], [0.0, 0.2]), duration=1.0)
    assert mv.solve(ramp, "mdr", 2001).force[-1] > 0.0


@pytest.mark.parametrize("n", [0, -1, 2**64 - 1, 10**6, 2.0, True])
def test_to_toml_refuses_a_resolution_no_scene_file_takes(n):
    """n = 2**64 - 1 was written as n = -1, n = 0 as n = 0 (files the reader refuses), and
    n = -1 raised a raw OverflowError."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0), force=1.0,
                     duration=1.0)
    with pytest.raises(mv.InvalidInputError, match="n"):
        scene.to_toml("bem", n)
    assert "n = 33" in scene.to_toml("bem", 33)
