"""Depth control on a periodic cell: the depth is the approach from the deflected surface's
mean plane, so the mean gap is the mean height below the highest point minus the depth, and
full contact is reached where that is zero. A depth at or past it takes an unbounded force:
it is refused (it returned forces of 1e28 N and gaps of -4e12 m); a depth short of it is
solved with gaps >= 0 and the mean gap the closed relation says."""

import numpy as np
import pytest

import mdrvisc as mv


def wavy_cell(n=32):
    """A smooth 2D wave on an n x n periodic cell of side 1 m, heights in m."""
    x = (np.arange(n) + 0.5) / n
    return 1e-3 * np.cos(2 * np.pi * x)[None, :] * np.ones((n, 1))


def scene(depth):
    cell = mv.HeightMap(wavy_cell(), dx=1.0 / 32, periodic=True)
    return mv.Scene(indenter=cell, medium=mv.StandardSolid(1.0, 4.0, 1.0), depth=depth,
                    duration=1.0, times=[0.5, 1.0], outputs=("depth", "contact_length", "gap"))


def full_contact_depth():
    h = wavy_cell()
    return float(np.mean(h.max() - h))


@pytest.mark.parametrize("factor", [1.0, 1.01, 2.0])
def test_a_depth_at_or_past_full_contact_is_refused(factor):
    with pytest.raises(mv.InvalidInputError, match="mean separation of a periodic cell"):
        mv.solve(scene(factor * full_contact_depth()), "bem")


def test_a_depth_short_of_full_contact_keeps_gaps_open_and_the_mean_gap_closed():
    d = 0.9 * full_contact_depth()
    r = mv.solve(scene(d), "bem")
    assert np.all(np.isfinite(r.force)) and np.all(r.force > 0)
    np.testing.assert_allclose(r.mean_gap, full_contact_depth() - d, rtol=1e-9)
    gap = r.fields[1.0].gap
    assert gap.min() >= -1e-12 * full_contact_depth()
