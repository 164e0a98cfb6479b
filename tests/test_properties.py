"""Property tests (hypothesis) of the physical invariants over random viscous scenes."""

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import mdrvisc as mv
from mdrvisc import analytic

positive = st.floats(min_value=1e-3, max_value=1e3)
scenes = st.fixed_dictionaries({
    "c": st.floats(min_value=0.1, max_value=50.0),
    "force": positive,
    "eta": positive,
    "duration": st.floats(min_value=1e-2, max_value=1e2),
    "n": st.sampled_from([25, 33, 48]),
})


def scene(p, outputs=("depth", "contact_length")):
    return mv.Scene(indenter=mv.Paraboloid(c=p["c"]), medium=mv.Viscous(eta=p["eta"]), force=p["force"],
                    duration=p["duration"], outputs=outputs)


@settings(max_examples=25, deadline=None)
@given(scenes)
def test_bem_fields_satisfy_the_contact_conditions(p):
    s = scene(p, ("depth", "contact_length", "pressure", "deflection"))
    r = mv.solve(s, "bem", p["n"])
    f = r.fields[s.duration]
    pres, u, x = f.pressure, f.deflection, f.x
    assert np.all(pres >= 0)
    assert abs(pres.sum() * r.dx**2 / p["force"] - 1) < 1e-9          # force balance
    h = p["c"] * (x[None, :] ** 2 + x[:, None] ** 2)
    gap = u - r.depth[-1] + h
    assert gap.min() > -1e-6 * r.depth[-1]                               # no penetration
    assert np.abs(gap[pres > 0]).max() < 1e-6 * r.depth[-1]              # closed where loaded
    assert np.all(np.diff(r.depth) > 0)                                  # monotone under constant force


@settings(max_examples=15, deadline=None)
@given(scenes)
def test_bem_and_mdr_agree_within_the_measured_discretisation_error(p):
    s = scene(p)
    coarse, fine = mv.solve(s, "bem", p["n"]), mv.solve(s, "bem", 2 * p["n"])
    mdr = mv.solve(s, "mdr", 20001)
    exact = analytic.paraboloid_depth(s.times, p["force"], p["c"], p["eta"])
    assert np.max(np.abs(mdr.depth / exact - 1)) < 1e-5
    # Richardson-style estimate: the coarse BEM error is at most a few times its change
    # under refinement.
    estimate = np.abs(coarse.depth - fine.depth)
    assert np.all(np.abs(coarse.depth - mdr.depth) <= 4 * estimate + 1e-9 * mdr.depth)


@settings(max_examples=25, deadline=None)
@given(scenes, st.floats(min_value=1e-4, max_value=1e4))
def test_depth_scales_with_force_time_over_viscosity(p, k):
    a = mv.solve(scene(p), "mdr", 4097).depth
    q = dict(p, force=p["force"] * k, eta=p["eta"] * k)
    b = mv.solve(scene(q), "mdr", 4097).depth
    assert np.allclose(a, b, rtol=1e-12)
    t = mv.solve(scene(dict(p, duration=p["duration"] * 8)), "mdr", 4097).depth
    assert np.allclose(t / a, 4.0, rtol=1e-9)                            # d ~ t^(2/3)
