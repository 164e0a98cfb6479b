"""The periodic half-space at the array level: the operator against the spectral response
of a harmonic load, Westergaard's wavy surface (pressure, contact half-width, mean
separation), and a rough periodic contact's complementarity."""

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc.errors import InvalidInputError


def test_a_harmonic_pressure_gives_the_half_space_response():
    """u = p / (2 G |q|) for p = cos(q . x) (G = 1 Pa), measured to 1.2e-14 of the
    amplitude; a uniform pressure gives no deflection (measured 4e-18 of the cell size)."""
    ny, nx, dx = 24, 40, 0.25
    op = mv.arrays.SurfaceOperator((ny, nx), dx, periodic=True)
    assert op.periodic and op.padded == (ny, nx) and "periodic=True" in repr(op)
    y, x = np.meshgrid(np.arange(ny) * dx, np.arange(nx) * dx, indexing="ij")
    for kx, ky in [(1, 0), (3, -5), (20, 0), (7, 12)]:
        qx, qy = 2 * np.pi * kx / (nx * dx), 2 * np.pi * ky / (ny * dx)
        p = np.cos(qx * x + qy * y)
        amp = 1 / (2 * np.hypot(qx, qy))
        assert np.max(np.abs(op.apply(p) - amp * p)) < 1e-13 * amp
    assert np.max(np.abs(op.apply(np.ones((ny, nx))))) < 2e-17 * nx * dx


def _wavy(n, ny=2, g=0.01):
    dx = 1.0 / n
    x = (np.arange(n) - n // 2 + 0.5) * dx
    return np.tile(g * (1 - np.cos(2 * np.pi * x)), (ny, 1)), x, dx


def test_westergaard_wavy_surface():
    """At mean pressure p = p* sin^2(3 pi / 16) (E* = 4 G): the contact half-width is
    3 lambda / 16 exactly, the pressure profile within 9.7e-5 in relative L1 and 5.6e-3 of
    the peak at worst (measured, n = 512; the Rust tests show both falling under
    refinement), and the mean separation is g (1 - P (1 - ln P)) to 7.5e-6 (measured);
    holding that mean separation gives back the force (measured 6.8e-6)."""
    n, g, G = 512, 0.01, 3.0
    h, x, dx = _wavy(n, g=g)
    p_star = np.pi * 4 * G * g
    ratio = np.sin(3 * np.pi / 16) ** 2
    pbar = ratio * p_star
    force = pbar * h.size * dx * dx
    r = mv.arrays.contact(h, dx, G, force=force, periodic=True, tol=1e-12)
    p = r.fields[0.0].pressure[0]
    s = np.sin(np.pi * x)
    exact = np.where(s**2 < ratio,
                     2 * pbar * np.cos(np.pi * x) / ratio * np.sqrt(np.clip(ratio - s**2, 0, None)), 0)
    assert np.count_nonzero(p > 0) == 3 * n // 8
    assert np.sum(np.abs(p - exact)) / np.sum(exact) < 4e-4
    assert np.max(np.abs(p - exact)) / np.max(exact) < 2e-2
    separation = np.mean(h) - r.depth[0]
    closed = g * (1 - ratio * (1 - np.log(ratio)))
    assert abs(separation / closed - 1) < 3e-5
    back = mv.arrays.contact(h, dx, G, mean_separation=closed, periodic=True, tol=1e-12)
    assert abs(back.force[0] / force - 1) < 3e-5
    assert not r.at_edge[0]


def test_rough_periodic_contact_is_complementary():
    """A self-affine cell pressed to 4.5 % contact: p >= 0, the gap h + u / G - d (u from
    the periodic operator here) vanishes on the contact (measured 6.8e-14 of the height
    range) and is > 0 elsewhere, and the pressures sum to the force (measured 2e-16)."""
    n, dx, G = 128, 1e-6, 1e6
    z = mv.surfaces.self_affine((n, n), dx, 0.8, rms_slope=0.1, seed=3)
    h = z.max() - z
    force = 0.07 * G * 0.1 * (n * dx) ** 2
    r = mv.arrays.contact(h, dx, G, force=force, periodic=True, tol=1e-12)
    p = r.fields[0.0].pressure
    fraction = np.count_nonzero(p > 0) / p.size
    assert 0.02 < fraction < 0.1
    u = mv.arrays.SurfaceOperator((n, n), dx, periodic=True).apply(p) / G
    np.testing.assert_allclose(u, r.fields[0.0].deflection, rtol=0, atol=1e-15 * np.ptp(h))
    gap = h + u - r.depth[0]
    assert np.all(p >= 0)
    assert np.max(np.abs(gap[p > 0])) < 5e-13 * np.ptp(h)
    assert np.min(gap[p == 0]) > 0
    assert abs(np.sum(p) * dx * dx / force - 1) < 2e-15


@pytest.mark.parametrize("kwargs", [
    {"mean_separation": 1e-3},
    {"force": 1.0, "mean_separation": 1e-3, "periodic": True},
    {"depth": 1e-3, "mean_separation": 1e-3, "periodic": True},
    {"mean_separation": -1e-3, "periodic": True},
    {"force": 1.0, "periodic": True, "depth_bound": 1.0},
    {"depth": 0.02, "periodic": True},
    {"force": 1.0, "periodic": 1},
])
def test_bad_periodic_arguments_are_refused(kwargs):
    h, _, dx = _wavy(32)
    with pytest.raises(InvalidInputError):
        mv.arrays.contact(h, dx, 1.0, **kwargs)


def test_scenes_held_at_a_depth():
    """An elastic scene given a depth: Westergaard's wavy cell held at the depth of the
    closed-form mean separation reports that mean gap and carries the closed-form force (to
    3e-5, the discretisation's error as above); a rough free map held at a depth (2 %
    contact) has p >= 0, a gap >= 0 that vanishes on its contact (measured 1.5e-14 of the
    height range), and held at the force it carried comes back to that depth (measured
    7e-15) and pressure (measured 1.6e-13 in L1)."""
    n, g, G = 512, 0.01, 3.0
    h, _, dx = _wavy(n, g=g)
    ratio = np.sin(3 * np.pi / 16) ** 2
    force = ratio * np.pi * 4 * G * g * h.size * dx * dx
    closed = g * (1 - ratio * (1 - np.log(ratio)))
    # the map's depth counts from its highest sample, h.min() below the continuous crest
    depth = np.mean(h) - closed - h.min()
    wavy = mv.HeightMap(-h, dx, periodic=True)
    r = mv.solve(mv.Scene(indenter=wavy, medium=mv.Elastic(G=G), depth=depth), tol=1e-12)
    assert r.depth[0] == depth and abs(r.mean_gap[0] / closed - 1) < 1e-14
    assert abs(r.force[0] / force - 1) < 3e-5

    n, dx = 128, 1e-6
    z = mv.surfaces.self_affine((n, n), dx, 0.8, rms_slope=0.1, seed=3)
    rough = mv.HeightMap(z, dx)
    depth = 0.25 * np.ptp(z)
    held = mv.solve(mv.Scene(indenter=rough, medium=mv.Elastic(G=G), depth=depth,
                             outputs=("pressure", "gap")), tol=1e-12)
    p, gap = held.fields[0.0].pressure, held.fields[0.0].gap
    assert held.depth[0] == depth and 0.01 < held.contact_fraction[0] < 0.05
    assert np.all(p >= 0) and np.min(gap) > -1e-13 * np.ptp(z)
    assert np.max(np.abs(gap[p > 0])) < 1e-13 * np.ptp(z)
    assert abs(np.sum(p) * dx * dx / held.force[0] - 1) < 1e-14
    loaded = mv.solve(mv.Scene(indenter=rough, medium=mv.Elastic(G=G), force=held.force[0],
                               outputs=("pressure",)), tol=1e-12)
    assert abs(loaded.depth[0] / depth - 1) < 1e-10
    assert np.sum(np.abs(loaded.fields[0.0].pressure - p)) / np.sum(p) < 1e-10
