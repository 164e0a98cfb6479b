"""Adhesive contact laws from Python, scene files and the command line: JKR and DMT by MDR
against their closed forms (Johnson, Kendall & Roberts 1971; Derjaguin, Muller & Toporov
1975), the report's pull-off and jumps, round trips, and what is refused.

Units: R = 1 m (c = 1/2), E* = 4 G = 1 Pa, w = 1/pi J/m^2, so pi w R = 1 N."""

import contextlib
import io
import json
import math

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import cli
from mdrvisc.errors import InvalidInputError

W = 1.0 / math.pi


def cycle(f_max=32.0 / 3.0, f_min=-3.0):
    """A force ramp up to f_max over [0, 1] s and down to f_min over [1, 2] s."""
    return ([0.0, 1.0, 2.0], [0.0, f_max, f_min])


def adhesive_scene(contact, times=None, **kw):
    args = dict(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25), contact=contact,
                force=cycle(), duration=2.0, times=times, dt=0.01)
    args.update(kw)
    return mv.Scene(**args)


def dense_times(lo, hi, k=2000):
    """Output times every 0.01 s and k of them through [lo, hi] (each output is a step)."""
    return np.union1d(np.linspace(0.01, 2.0, 200), np.linspace(lo, hi, k))


def test_jkr_pull_off_under_force_control():
    """-3/2 pi w R, found where the contact lets go, its depth and time with it."""
    r = mv.solve(adhesive_scene(mv.JKR(work_of_adhesion=W), dense_times(1.85, 1.95)), "mdr", 8001)
    assert r.pull_off_force == pytest.approx(-1.5, rel=2e-3)
    assert r.jump_out.size == 1 and r.jump_in.size == 0
    assert r.pull_off_time < r.jump_out[0] and 1.85 < r.pull_off_time < 1.95
    k = np.searchsorted(r.t, r.pull_off_time)
    assert r.depth[k] == r.pull_off_depth and r.force[k] == r.pull_off_force
    after = r.t > r.jump_out[0]
    assert np.all(np.isnan(r.depth[after])) and np.all(r.contact_length[after] == 0.0)
    assert np.any(r.force < 0.0)


def test_jkr_contact_radius_at_zero_load():
    """On the unloading branch a^3 = 9 pi w R^2 / (2 E*)."""
    f_max, f_min = 32.0 / 3.0, -3.0
    t0 = 1.0 + f_max / (f_max - f_min)
    r = mv.solve(adhesive_scene(mv.JKR(work_of_adhesion=W), [1.0, t0, 2.0]), "mdr", 8001)
    k = np.searchsorted(r.t, t0)
    assert r.force[k] == pytest.approx(0.0, abs=1e-12)
    assert r.contact_length[k] / 2 == pytest.approx(4.5 ** (1 / 3), rel=2e-3)


def test_jkr_under_depth_control():
    """-5/6 pi w R at d = -3/4 sqrt(2 pi w a / E*), a^3 = pi w R^2 / (8 E*). The release is
    a fold of d(a): near it F - F_c = -2 sqrt(2 (d - d_c) / 3) (F'(a) = -2, d''(a) = 3 there),
    so the force converges as the square root of the depth's error: 1e-5 m of depth (the step
    here) is already 0.5 % of force, and the force is checked to 1 %, the depth to 0.1 %."""
    d_c = -0.75 * math.sqrt(2 * 0.5)
    depth = ([0.0, 1.0, 2.0, 3.0], [0.0, 4.0, d_c + 0.02, d_c - 0.02])
    times = np.union1d(np.linspace(0.01, 2.0, 200), np.linspace(2.0, 3.0, 4001)[1:])
    scene = mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25),
                     contact=mv.JKR(work_of_adhesion=W), depth=depth, duration=3.0, times=times,
                     dt=0.01)
    r = mv.solve(scene, "mdr", 8001)
    assert r.pull_off_force == pytest.approx(-5.0 / 6.0, rel=1e-2)
    assert r.pull_off_depth == pytest.approx(d_c, rel=1e-3)
    assert r.force.min() == pytest.approx(-1.5, rel=3e-3)


def test_kendall_flat_punch():
    """A rod of radius a lets go at -sqrt(8 pi a^3 w E*), by MDR at any n."""
    a, e_star = 0.5, 1.0
    limit = math.sqrt(2 * math.pi * a * W / e_star)
    scene = mv.Scene(indenter=mv.Rod(radius=a), medium=mv.Elastic(G=0.25),
                     contact=mv.JKR(work_of_adhesion=W),
                     depth=([0.0, 1.0, 2.0], [0.01, -0.9 * limit, -1.1 * limit]), duration=2.0,
                     dt=1e-4)
    r = mv.solve(scene, "mdr", 50)
    assert r.pull_off_force == pytest.approx(-math.sqrt(8 * math.pi * a**3 * W * e_star), rel=1e-4)


def test_dmt_pull_off_and_jump_in():
    """DMT lets go at -2 pi w R (F = 5 - 8 (t - 1) N passes it at t = 1.875 s: the last
    state in contact lies within one step's load above it) and jumps in with that tension at
    the touch."""
    r = mv.solve(adhesive_scene(mv.DMT(work_of_adhesion=W), dense_times(1.85, 1.9),
                                force=cycle(5.0, -3.0)), "mdr", 2001)
    step = 8.0 * 0.05 / 1999
    assert -2.0 <= r.pull_off_force < -2.0 + step * (1 + 1e-9)
    scene = mv.Scene(indenter=mv.Sphere(radius=1.0), medium=mv.Elastic(G=0.25),
                     contact=mv.DMT(work_of_adhesion=W), depth=([0.0, 1.0], [-0.1, 0.1]),
                     duration=1.0, dt=1e-3)
    r = mv.solve(scene, "mdr", 2001)
    assert r.jump_in.size == 1 and r.jump_in[0] == pytest.approx(0.5, abs=2e-3)
    assert r.force[-1] < 0.0


def test_hard_contact_reports_no_jumps():
    r = mv.solve(mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25), force=1.0),
                 "mdr", 201)
    assert r.jump_in is None and r.jump_out is None and r.pull_off_force is None


def test_round_trips(tmp_path):
    """The law survives TOML, pickling-free saving of the result, and the model's JSON."""
    scene = adhesive_scene(mv.JKR(work_of_adhesion=0.05))
    assert json.loads(scene.to_json())["contact"] == {"type": "jkr", "work_of_adhesion": 0.05}
    path = tmp_path / "jkr.toml"
    text = scene.to_toml("mdr", 401, path)
    assert "jkr" in text
    back = mv.Scene.from_toml(path)
    assert back == scene and back.contact == mv.JKR(work_of_adhesion=0.05)
    r = mv.solve(scene, "mdr", 401)
    loaded = mv.Result.load(r.save(tmp_path / "r.npz"))
    assert loaded.pull_off_force == r.pull_off_force
    np.testing.assert_array_equal(loaded.jump_out, r.jump_out)


def test_the_process_zone_stress_round_trips_and_an_elastic_body_does_not_use_it(tmp_path):
    """JKR's zone stress survives TOML and JSON; on an elastic body the edge lets go by Heß's
    rule with or without it (the crack's criterion is Heß's there: C_eff = 1 / E*)."""
    law = mv.JKR(work_of_adhesion=W, stress=2.0)
    scene = adhesive_scene(law)
    assert json.loads(scene.to_json())["contact"] == {"type": "jkr", "work_of_adhesion": W, "stress": 2.0}
    path = tmp_path / "jkr.toml"
    scene.to_toml("mdr", 401, path)
    assert mv.Scene.from_toml(path).contact == law
    with_zone = mv.solve(scene, "mdr", 401)
    without = mv.solve(adhesive_scene(mv.JKR(work_of_adhesion=W)), "mdr", 401)
    np.testing.assert_array_equal(with_zone.force, without.force)
    np.testing.assert_array_equal(with_zone.depth, without.depth)


def test_command_line_runs_an_adhesive_scene_file(tmp_path):
    path = tmp_path / "dmt.toml"
    path.write_text('method = "mdr"\nn = 501\nduration = 2.0\ndt = 0.001\n'
                    'force = [[0.0, 0.0], [1.0, 5.0], [2.0, -3.0]]\n'
                    'contact = { type = "dmt", work_of_adhesion = 0.3183098861837907 }\n'
                    '[indenter]\ntype = "paraboloid"\nc = 0.5\n[medium]\ntype = "elastic"\nG = 0.25\n')
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        status = cli.main(["run", str(path), "--json"])
    assert status == 0, err.getvalue()
    (doc,) = json.loads(out.getvalue())
    # steps of 1 ms, 8 mN each: the last state in contact lies within one of -2 pi w R
    assert -2.0 <= doc["result"]["pull_off_force"] < -2.0 + 0.008 * (1 + 1e-9)
    assert doc["input"]["contact"]["type"] == "dmt"


def test_refusals():
    with pytest.raises(InvalidInputError, match="work_of_adhesion"):
        mv.JKR(work_of_adhesion=-1.0)
    with pytest.raises(InvalidInputError, match="stress"):
        mv.JKR(work_of_adhesion=W, stress=0.0)
    with pytest.raises(InvalidInputError, match="contact"):
        mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25), force=1.0, contact="jkr")
    with pytest.raises(InvalidInputError, match="forces must be >= 0"):
        mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Viscous(eta=1.0), force=cycle(),
                 duration=2.0)
    with pytest.raises(InvalidInputError, match="duration"):
        mv.Scene(indenter=mv.Paraboloid(c=0.5), medium=mv.Elastic(G=0.25), force=cycle(),
                 contact=mv.JKR(work_of_adhesion=W))
    with pytest.raises(InvalidInputError, match="relaxed modulus"):
        mv.solve(adhesive_scene(mv.JKR(work_of_adhesion=W), medium=mv.Maxwell(G=1.0, eta=1.0)),
                 "mdr", 101)
    with pytest.raises(InvalidInputError, match="rounded tip"):
        mv.solve(adhesive_scene(mv.DMT(work_of_adhesion=W), indenter=mv.Cone(slope=0.5)), "mdr", 101)
    with pytest.raises(InvalidInputError, match="BEM solves hard contact only"):
        mv.solve(adhesive_scene(mv.JKR(work_of_adhesion=W), indenter=mv.Paraboloid(c=0.5, edge=4.0)),
                 "bem", 17)
