"""Output times at the edge of what double precision resolves: times closer than 1e-9 of
their value are reported from one solved state, times below 1e-12 of the duration are
refused, and a short but resolvable interval advances the state by the rate times the gap."""

import numpy as np
import pytest

import mdrvisc as mv


def scene(times, medium=None, **kwargs):
    return mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=medium or mv.Viscous(eta=1.0),
                    force=1.0, duration=5.0, times=times, outputs=("depth", "contact_length", "velocity"),
                    **kwargs)


@pytest.mark.parametrize("medium", [mv.Viscous(eta=1.0), mv.StandardSolid(1.0, 3.0, 0.5)],
                         ids=["viscous", "standard-solid"])
@pytest.mark.parametrize("method,n", [("bem", 65), ("mdr", 4001)])
def test_coincident_times_are_reported_from_one_state(medium, method, n):
    near = mv.solve(scene([3.0, 3.0 + 1e-12, 5.0], medium), method, n)
    apart = mv.solve(scene([3.0, 5.0], medium), method, n)
    assert np.array_equal(near.t, [3.0, 3.0 + 1e-12, 5.0])
    for name in ("depth", "contact_length", "velocity"):
        got, ref = getattr(near, name), getattr(apart, name)
        assert got[0] == got[1] == ref[0]
        assert got[2] == pytest.approx(ref[1], rel=1e-9)


def test_a_field_time_at_a_coincident_time_is_the_state_there():
    s = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0), force=1.0,
                 duration=5.0, times=[3.0, 3.0 + 1e-12, 5.0],
                 outputs=("depth", "pressure"), field_times=[3.0 + 1e-12])
    r = mv.solve(s, "bem", 65)
    p = r.fields[3.0 + 1e-12].pressure
    assert p.sum() * r.dx**2 == pytest.approx(1.0, rel=1e-9)
    assert np.all(p >= 0)


@pytest.mark.parametrize("gap", [3e-8, 3e-4])
def test_a_short_interval_advances_the_depth_by_rate_times_gap(gap):
    r = mv.solve(scene([3.0, 3.0 + gap, 5.0]), "bem", 129)
    assert r.contact_length[1] == r.contact_length[0]
    # the rate changes over the gap by O(gap): measured 1.4e-4 at 3e-8 s, 1.3e-6 at 3e-4 s
    assert (r.depth[1] - r.depth[0]) / (r.velocity[0] * gap) == pytest.approx(1.0, abs=5e-4)


@pytest.mark.parametrize("first", [5e-324, 1e-300, 4e-12])
@pytest.mark.parametrize("key", ["times", "field_times"])
def test_times_too_close_to_the_start_are_refused(first, key):
    times = {"times": [first, 5.0]} if key == "times" else {"times": [5.0], "field_times": [first]}
    with pytest.raises(mv.InvalidInputError, match=f"{key}: .* too close to the start"):
        mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0), force=1.0,
                 duration=5.0, outputs=("depth", "pressure"), **times)
