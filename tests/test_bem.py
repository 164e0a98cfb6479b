"""BEM against closed forms: rod, viscous paraboloid, elastic Hertz."""

import os
import threading

import numpy as np
import pytest

import mdrvisc as mv
from mdrvisc import _core, analytic

VISCOUS = mv.Viscous(eta=1.0)


def rod(n):
    scene = mv.Scene(indenter=mv.Rod(radius=1.0), medium=VISCOUS, force=1.0, duration=1.0)
    return mv.solve(scene, "bem", n)


def test_rod_paper_grid_matches_closed_form_and_refines():
    errors = []
    for n in (200, 300, 400):
        r = rod(n)
        ev = abs(r.velocity[0] / analytic.rod_velocity(1.0, 1.0, 1.0) - 1)
        ep = abs(r.central_pressure[0] / analytic.rod_central_pressure(1.0, 1.0) - 1)
        errors.append((ev, ep))
        if n == 200:
            assert r.grid_shape == (201, 201)
            assert r.area[0] == pytest.approx(31417 * 0.01**2)
            assert ev < 1.5e-3 and ep < 3e-3
            assert r.solves == 1 and r.steps == 0
    assert errors[0][0] > errors[1][0] > errors[2][0]
    assert errors[0][1] > errors[1][1] > errors[2][1]


def test_paraboloid_paper_case_matches_lee_radok():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0)
    r = mv.solve(scene, "bem", 257)
    d = analytic.paraboloid_depth(r.t, 1.0, 1.0, 1.0)
    l_exact = analytic.paraboloid_contact_length(r.t, 1.0, 1.0, 1.0)
    # measured 5.95e-6 and 1.55e-3 (257^2)
    assert abs(r.depth[-1] / d[-1] - 1) < 3e-5
    assert abs(r.contact_length[-1] / l_exact[-1] - 1) < 2e-3
    assert r.solves == 5  # one contact solve per output time: no rate solves asked for
    assert r.velocity is None and r.fields is None
    assert np.all(np.diff(r.depth) > 0)


def test_rates_and_stiffness_length_follow_the_rod_law():
    scene = mv.Scene(indenter=mv.Paraboloid(c=5.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0,
                     outputs=("depth", "contact_length", "velocity", "stiffness_length"))
    r = mv.solve(scene, "bem", 129)
    # Any circular contact moves at F / (8 a eta): l = 2a = F / (4 eta ddot), against
    # Lee-Radok's contact length (measured 6.1e-3 at 129^2)
    exact = analytic.paraboloid_contact_length(r.t, 1.0, 5.0, 1.0)
    assert np.all(np.abs(r.stiffness_length / exact - 1) < 0.01)
    assert r.solves == 10


def test_depth_scales_with_force_time_over_viscosity():
    base = None
    for force, eta, t in ((1.0, 1.0, 5.0), (1e3, 10.0, 0.05), (2.0, 1e-3, 2.5e-3)):
        scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=eta),
                         force=force, duration=t, times=[t])
        d = mv.solve(scene, "bem", 65).depth[-1]
        if base is None:
            base = d
        assert d == pytest.approx(base, rel=1e-9)


def test_fields_are_physical():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0,
                     outputs=("depth", "contact_length", "pressure", "surface_velocity", "deflection"),
                     field_times=[5.0])
    r = mv.solve(scene, "bem", 129)
    f = r.fields[5.0]
    p, v, u = f.pressure, f.surface_velocity, f.deflection
    dx = r.dx
    assert np.all(p >= 0)
    assert p.sum() * dx * dx == pytest.approx(1.0, rel=1e-10)
    x = f.x
    h = 1.0 * (x[None, :] ** 2 + x[:, None] ** 2)
    gap = u - r.depth[-1] + h
    assert gap.min() > -1e-6 * r.depth[-1]
    contact = p > 0
    # inside the contact every point moves with the indenter
    assert np.ptp(v[contact]) < 1e-6 * v[contact].mean()


def test_fft_operator_matches_dense_faer_operator():
    rng = np.random.default_rng(1)
    for shape in ((1, 1), (2, 3), (13, 9), (24, 24)):
        p = rng.random(shape)
        a = _core.surface_deflection(p, 0.1)
        b = _core.surface_deflection(p, 0.1, dense=True)
        assert np.max(np.abs(a - b)) < 1e-10 * np.max(np.abs(b))


def test_reusable_surface_operator_is_the_dense_operator_and_checks_input():
    rng = np.random.default_rng(2)
    op = mv.arrays.SurfaceOperator((13, 9), 0.1)
    assert op.shape == (13, 9) and op.padded == (24, 16)
    for _ in range(3):  # buffers are reused between calls
        p = rng.random((13, 9))
        b = _core.surface_deflection(p, 0.1, dense=True)
        assert np.max(np.abs(op.apply(p) - b)) < 1e-10 * np.max(np.abs(b))
    # a transposed view and integer pressures are copied, not misread
    q = rng.random((9, 13)).T
    assert np.array_equal(op.apply(q), op.apply(q.copy()))
    assert np.array_equal(op.apply(np.ones((13, 9), dtype=int)), op.apply(np.ones((13, 9))))
    # far field of a point load: u = F / (4 pi G r) for the incompressible half-space
    big = mv.arrays.SurfaceOperator((201, 201), 0.01)
    p = np.zeros((201, 201))
    p[100, 100] = 1.0 / 0.01**2
    assert big.apply(p)[100, 200] == pytest.approx(1 / (4 * np.pi * 1.0), rel=1e-4)
    out = np.empty((13, 9))
    assert op.apply(q, out=out) is out and np.array_equal(out, op.apply(q))
    with pytest.raises(mv.InvalidInputError, match="C-contiguous"):
        op.apply(q, out=np.empty((9, 13)).T)
    with pytest.raises(mv.InvalidInputError, match="float64"):
        op.apply(q, out=np.empty((13, 9), dtype=np.float32))
    frozen = np.empty((13, 9))
    frozen.flags.writeable = False
    with pytest.raises(mv.InvalidInputError, match="writable"):
        op.apply(q, out=frozen)
    same = np.ascontiguousarray(q)
    with pytest.raises(mv.InvalidInputError, match="must not be the pressure"):
        op.apply(same, out=same)
    with pytest.raises(mv.InvalidInputError, match="shape"):
        op.apply(np.ones((9, 13)))
    with pytest.raises(mv.InvalidInputError, match="finite"):
        op.apply(np.full((13, 9), np.nan))
    with pytest.raises(mv.InvalidInputError, match="real"):
        op.apply(np.ones((13, 9), dtype=complex))
    with pytest.raises(mv.InvalidInputError, match="dx"):
        mv.arrays.SurfaceOperator((4, 4), 0.0)
    with pytest.raises(mv.InvalidInputError, match="shape"):
        mv.arrays.SurfaceOperator((0, 4), 0.1)


def paraboloid_heights(n, dx, R):
    """h = r^2 / (2 R) at the centres of an n x n grid of elements of side dx, centred."""
    x = (np.arange(n) - (n - 1) / 2) * dx
    xx, yy = np.meshgrid(x, x)
    return (xx**2 + yy**2) / (2 * R)


def count(result):
    """Elements in contact of a static BEM result."""
    return int(round(result.area[0] / result.dx**2))


def test_small_contacts_are_solved_by_the_dense_active_set():
    n, dx, R, G = 128, 0.02, 10.0, 1.0
    h = paraboloid_heights(n, dx, R)
    a = 8 * dx
    force = 16 * G * a**3 / (3 * R)  # Hertz with E* = 4 G
    auto = mv.arrays.contact(h, dx, G, force=force)
    pk = mv.arrays.contact(h, dx, G, force=force, active_limit=0)
    assert auto.solver == "active-set" and pk.solver == "polonsky-keer"
    assert count(auto) == count(pk) and auto.residual < 1e-12
    p_auto, p_pk = auto.fields[0.0].pressure, pk.fields[0.0].pressure
    assert np.max(np.abs(p_auto - p_pk)) < 1e-8 * p_pk.max()
    assert auto.force[0] == pytest.approx(force, rel=1e-12)
    # Hertz depth a^2 / R; p >= 0 everywhere, no overlap outside the contact
    assert auto.depth[0] == pytest.approx(a * a / R, rel=2e-3)
    gap = auto.fields[0.0].deflection + h - auto.depth[0]
    assert np.all(auto.fields[0.0].pressure >= 0) and gap.min() > -1e-12 * h.max()
    assert np.all(np.abs(gap[auto.fields[0.0].pressure > 0]) < 1e-12 * h.max())
    # a contact beyond the crossover goes to Polonsky-Keer by itself
    big = mv.arrays.contact(h, dx, G, force=force * 27)
    assert big.solver == "polonsky-keer" and count(big) > 1000


def test_preconditioned_polonsky_keer_matches_the_plain_method_and_hertz():
    """The inverse-kernel preconditioner changes the path, not the solution: same contact
    set, pressures to the tolerance, Hertz's depth; and at most half the iterations on a
    contact of ~2800 elements (force control)."""
    n, dx, R, G = 128, 0.02, 10.0, 1.0
    h = paraboloid_heights(n, dx, R)
    a = 30 * dx
    force = 16 * G * a**3 / (3 * R)
    pre = mv.arrays.contact(h, dx, G, force=force)
    plain = mv.arrays.contact(h, dx, G, force=force, precondition=False)
    assert pre.solver == plain.solver == "polonsky-keer"
    assert count(pre) == count(plain) > 2500
    p_pre, p_plain = pre.fields[0.0].pressure, plain.fields[0.0].pressure
    assert np.max(np.abs(p_pre - p_plain)) < 1e-8 * p_plain.max()
    assert pre.depth[0] == pytest.approx(a * a / R, rel=2e-3)
    assert 2 * pre.iterations <= plain.iterations
    gap = pre.fields[0.0].deflection + h - pre.depth[0]
    assert np.all(pre.fields[0.0].pressure >= 0) and gap.min() > -1e-9 * h.max()


def test_preconditioning_leaves_the_viscous_run_unchanged():
    """The paper's c = 1 run at 65^2: depths agree to 1e-9 with and without the
    preconditioner, which takes at most 2/3 of the iterations."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0)
    _, dx, h, mask = scene.bem_grid(65)
    runs = [mv.arrays.viscous(h, dx, 1.0, 1.0, scene.times, mask=mask, precondition=p)
            for p in (True, False)]
    np.testing.assert_allclose(runs[0].depth, runs[1].depth, rtol=1e-9)
    assert 3 * runs[0].iterations <= 2 * runs[1].iterations


def test_elastic_hertz_contact():
    n, edge, G, force, R = 128, 2.56, 1.0, 0.0215, 10.0
    scene = mv.Scene(indenter=mv.Paraboloid(c=1 / (2 * R), edge=edge), medium=mv.Elastic(G=G), force=force,
                     outputs=("depth", "contact_length", "pressure"))
    r = mv.solve(scene, "bem", n)
    a, d, p0 = analytic.hertz(force, R, 4 * G)
    assert r.depth[0] == pytest.approx(d, rel=2e-3)
    assert r.contact_length[0] == pytest.approx(2 * a, rel=2e-2)
    p = r.fields[0.0].pressure
    assert p.max() == pytest.approx(p0, rel=1e-2)
    assert np.all(p >= 0)


def test_non_convergence_raises_with_iterations_and_residual():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=1.0)
    with pytest.raises(mv.ConvergenceError) as info:
        mv.solve(scene, "bem", 65, max_iter=3)
    assert info.value.iterations == 3
    assert info.value.residual > 0


def test_progress_callback_and_interrupt():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0)
    seen = []
    mv.solve(scene, "bem", 65, progress=lambda stage, done, total: seen.append((stage, done, total)))
    assert seen[-1] == ("time steps", 5, 5)

    def stop(stage, done, total):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        mv.solve(scene, "bem", 65, progress=stop)


def test_ctrl_c_stops_a_run_within_a_fraction_of_a_second():
    """The computation runs on a rayon worker; a signal reaching the calling thread (Ctrl-C,
    here simulated by _thread.interrupt_main 0.3 s in) stops it at its next progress report
    and raises KeyboardInterrupt, well before the ~4 s the whole run takes."""
    import _thread
    import signal
    import time

    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0,
                     duration=20.0, times=np.linspace(0.01, 20.0, 2000))
    # interrupt_main does nothing where SIGINT is ignored (a test run started from a
    # non-interactive shell's background job inherits that): handle it for this test
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        timer = threading.Timer(0.3, _thread.interrupt_main)
        start = time.perf_counter()
        timer.start()
        with pytest.raises(KeyboardInterrupt):
            mv.solve(scene, "bem", 129)
        timer.join()
    finally:
        signal.signal(signal.SIGINT, previous)
    assert time.perf_counter() - start < 1.5


def test_solve_releases_the_gil():
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0)
    ticks = []
    done = threading.Event()

    def count():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    worker = threading.Thread(target=count)
    worker.start()
    try:
        mv.solve(scene, "bem", 257, tol=1e-8)
    finally:
        done.set()
        worker.join()
    assert len(ticks) > 20


def test_bem_results_repeat_bit_for_bit_on_one_and_two_threads():
    """The solver's parallel sums run over fixed chunks in a fixed order, so a run gives the
    same bits whatever the thread count (rayon sizes its pool once per process, hence the
    subprocesses). The grid (129^2) holds several chunks."""
    import os
    import subprocess
    import sys

    code = ("import mdrvisc as mv; s = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), "
            "medium=mv.Viscous(eta=1.0), force=1.0, duration=3.0, "
            "outputs=('depth', 'contact_length', 'velocity')); r = mv.solve(s, 'bem', 129); "
            "print(r.depth.tobytes().hex(), r.velocity.tobytes().hex(), r.iterations)")
    out = []
    for threads in ("1", "2"):
        env = {**os.environ, "RAYON_NUM_THREADS": threads}
        run = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True,
                             text=True, check=True)
        out.append(run.stdout)
    assert out[0] == out[1]


def test_depth_bounds_size_the_windows_but_not_the_result():
    """Steps solved on windows from MDR's depths, on windows from far too small bounds (each
    solved again on a larger window) and on the linear extrapolation alone agree to the
    solver's tolerance."""
    scene = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=VISCOUS, force=1.0, duration=5.0)
    _, dx, h, mask = scene.bem_grid(97)
    ft, fv = scene.history
    bounds = scene._model.depth_bounds()
    assert np.all(np.isfinite(bounds))
    runs = [_core.bem_viscous(h, mask, dx, 1.0, scene.times, ft, fv, depth_bounds=b)
            for b in (bounds.tolist(), [1e-3] * 5, None)]
    assert runs[1].solves > runs[0].solves == 5
    for r in runs[1:]:
        np.testing.assert_allclose(r.depth, runs[0].depth, rtol=1e-9)
        np.testing.assert_allclose(r.area, runs[0].area, rtol=0)


def test_static_windows_hold_the_contact_and_give_the_whole_grids_solution():
    """A static Hertz contact solved on the window from a depth bound (MDR's, or one below the
    depth, which is exceeded, widened and solved again) or from the depth itself equals the
    whole grid's solve: pressures to the tolerance, deflections, depth, and the set; the
    windows (radius sqrt(2.1) a around a paraboloid: h <= 1.05 d = 1.05 a^2 / R) are 70 % of
    the grid's side; deflection=False leaves the deflection out."""
    n, dx, R, G = 160, 0.016, 10.0, 1.0
    h = paraboloid_heights(n, dx, R)
    a = 36 * dx
    force = 16 * G * a**3 / (3 * R)
    opts = dict(tol=1e-12, active_limit=0)
    full = mv.arrays.contact(h, dx, G, force=force, **opts)
    assert full.window == (0, 0, n, n) and full.solves == 1
    d_mdr = analytic.hertz(force, R, 4 * G)[1]
    runs = [mv.arrays.contact(h, dx, G, force=force, depth_bound=1.05 * d_mdr, **opts),
            mv.arrays.contact(h, dx, G, force=force, depth_bound=0.7 * d_mdr, **opts),
            mv.arrays.contact(h, dx, G, depth=full.depth[0], **opts)]
    assert [r.solves for r in runs] == [1, 2, 1]
    for r in runs:
        y0, x0, wy, wx = r.window
        assert 2 * a / dx < wx <= 0.75 * n and 2 * a / dx < wy <= 0.75 * n
        assert count(r) == count(full)
        assert r.depth[0] == pytest.approx(full.depth[0], rel=1e-10)
        np.testing.assert_allclose(r.fields[0.0].pressure, full.fields[0.0].pressure, rtol=0,
                                   atol=1e-9 * full.fields[0.0].pressure.max())
        np.testing.assert_allclose(r.fields[0.0].deflection, full.fields[0.0].deflection, rtol=0,
                                   atol=1e-10 * full.fields[0.0].deflection.max())
    no_u = mv.arrays.contact(h, dx, G, force=force, depth_bound=d_mdr, deflection=False)
    assert no_u.fields[0.0].deflection is None
    with pytest.raises(mv.InvalidInputError):
        mv.arrays.contact(h, dx, G, force=force, depth_bound=float("nan"))


def test_static_scene_solves_on_the_mdr_window_and_computes_only_what_it_asks_for():
    """mv.solve on an elastic scene: one solve on MDR's window, the same depth and pressure as
    arrays.contact on the whole grid, and no deflection field unless asked for."""
    n, R, G, force = 128, 10.0, 1.0, 0.0215
    ind = mv.Paraboloid(c=1 / (2 * R), edge=2.56)
    scene = mv.Scene(indenter=ind, medium=mv.Elastic(G=G), force=force,
                     outputs=("depth", "pressure"))
    r = mv.solve(scene, "bem", n)
    held = {k for k, v in vars(r.fields[0.0]).items() if v is not None}
    assert r.solves == 1 and held == {"t", "x", "y", "pressure"}
    _, dx, h, mask = scene.bem_grid(n)
    full = mv.arrays.contact(h, dx, G, force=force, mask=mask)
    assert r.depth[0] == pytest.approx(full.depth[0], rel=1e-9)
    np.testing.assert_allclose(r.fields[0.0].pressure, full.fields[0.0].pressure, rtol=0,
                               atol=1e-8 * full.fields[0.0].pressure.max())
    both = mv.solve(mv.Scene(indenter=ind, medium=mv.Elastic(G=G), force=force,
                             outputs=("depth", "pressure", "deflection")), "bem", n)
    np.testing.assert_allclose(both.fields[0.0].deflection, full.fields[0.0].deflection, rtol=0,
                               atol=1e-8 * full.fields[0.0].deflection.max())


def test_a_solve_inside_a_progress_callback_runs_on_one_thread_too(tmp_path):
    """A progress callback that runs another solve (on a rayon worker, where the outer solve
    runs) finishes, also with a single rayon thread, where waiting on that thread for a job of
    the pool would deadlock."""
    import subprocess
    import sys

    script = tmp_path / "nested.py"
    script.write_text(
        "import mdrvisc as mv\n"
        "sc = mv.Scene(indenter=mv.Paraboloid(c=1.0, edge=2.56), medium=mv.Viscous(eta=1.0),"
        " force=1.0, duration=5.0)\n"
        "inner = []\n"
        "def cb(stage, done, total):\n"
        "    if not inner:\n"
        "        inner.append(mv.solve(sc, 'bem', 33).depth[-1])\n"
        "outer = mv.solve(sc, 'bem', 33, progress=cb)\n"
        "assert inner and abs(inner[0] - outer.depth[-1]) < 1e-12 * outer.depth[-1]\n"
        "print('ok')\n")
    for threads in ("1", "2"):
        env = dict(os.environ, RAYON_NUM_THREADS=threads)
        out = subprocess.run([sys.executable, str(script)], env=env, capture_output=True,
                             text=True, timeout=60)
        assert out.returncode == 0 and out.stdout.strip() == "ok", out.stderr
