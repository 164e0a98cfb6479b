"""Height-map scenes: a sampled paraboloid against the Paraboloid scene on the same grid and
against Hertz and Lee-Radok; a rough map's contact against the invariants of contact (force
balance, p >= 0, gap >= 0, complementarity, patches counted by scipy) and against the
elastic limits of a standard solid; scene files with their .npy; bad maps refused."""

import math
import warnings

import numpy as np
import pytest
from scipy import ndimage

import mdrvisc as mv

C = 1.0           # paraboloid h = c r^2 (1/m), R = 1 / (2c)
EDGE = 2.56       # side of the map (m)


def _paraboloid_map(n):
    """Heights -c r^2 of the rigid surface at the element centres of an n x n map of side
    EDGE, and the map (its apex, the highest point, on the centre element for odd n)."""
    dx = EDGE / n
    x = (np.arange(n) - 0.5 * (n - 1)) * dx
    heights = -C * (x[np.newaxis, :] ** 2 + x[:, np.newaxis] ** 2)
    return mv.HeightMap(heights, dx)


def _rough_map(n, dx, seed, rms=1.0):
    """A rough surface: Gaussian noise filtered in Fourier space to a self-affine spectrum
    (Hurst 0.8) between a roll-off at 1/8 and a cut-off at 1/4 of the grid's wavenumbers,
    scaled to the rms height ``rms`` (m)."""
    noise = np.random.default_rng(seed).standard_normal((n, n))
    q = np.hypot(*np.meshgrid(np.fft.fftfreq(n), np.fft.fftfreq(n)))
    amplitude = np.where(q > 0, np.maximum(q, 1 / 8) ** (-1.8), 0.0) * (q < 1 / 4)
    h = np.real(np.fft.ifft2(np.fft.fft2(noise) * amplitude))
    return mv.HeightMap(h * rms / h.std(), dx)


# ---------------------------------------------------------------------- sampled paraboloid
@pytest.mark.parametrize("medium, load", [
    (mv.Elastic(G=1.0), {"force": 0.2}),
    (mv.Viscous(eta=1.0), {"force": 0.3, "duration": 2.0, "times": [0.5, 2.0]}),
    (mv.StandardSolid(1.0, 2.0, 0.5), {"force": 0.3, "duration": 2.0, "times": [0.5, 2.0], "dt": 0.02}),
    (mv.Maxwell(G=1.0, eta=1.0), {"depth": 0.1, "duration": 1.0, "times": [0.5, 1.0], "dt": 0.02}),
], ids=["elastic", "viscous", "standard-solid", "maxwell-depth"])
def test_a_sampled_paraboloid_solves_as_the_paraboloid_scene(medium, load):
    n = 65
    outputs = ("depth", "pressure", "deflection")
    kw = {"outputs": outputs, **load}
    if "times" in load:
        kw["field_times"] = [load["times"][-1]]
    via_map = mv.solve(mv.Scene(indenter=_paraboloid_map(n), medium=medium, **kw))
    direct = mv.solve(mv.Scene(indenter=mv.Paraboloid(c=C, edge=EDGE), medium=medium, **kw), "bem", n)
    assert via_map.n == n and via_map.grid_shape == (n, n)
    # the same grid and solver; the windows differ (the paraboloid's are sized by MDR), so
    # the iterations do: measured at most 7.7e-13 relative in depth, 2.3e-11 of the peak in
    # pressure, 4.7e-12 of the largest in deflection (elastic; the others to round-off)
    np.testing.assert_allclose(via_map.depth, direct.depth, rtol=5e-12)
    np.testing.assert_allclose(via_map.force, direct.force, rtol=1e-14)
    np.testing.assert_array_equal(via_map.area, direct.area)
    (fm,), (fd,) = via_map.fields.values(), direct.fields.values()
    assert np.abs(fm.pressure - fd.pressure).max() < 1e-10 * fd.pressure.max()
    assert np.abs(fm.deflection - fd.deflection).max() < 2e-11 * np.abs(fd.deflection).max()
    assert np.all(via_map.patches == 1)


def test_a_sampled_paraboloid_follows_hertz():
    """Elastic, E* = 4G: d = a^2 / R, F = 16/3 G sqrt(R) d^(3/2), p0 = 3F / (2 pi a^2)."""
    n, G, force = 129, 1.0, 0.05
    r = mv.solve(mv.Scene(indenter=_paraboloid_map(n), medium=mv.Elastic(G=G), force=force,
                          outputs=("depth", "pressure")))
    R = 1.0 / (2.0 * C)
    d = (3.0 * force / (16.0 * G * math.sqrt(R))) ** (2.0 / 3.0)
    a = math.sqrt(R * d)
    # measured (2a spans 17 elements): depth 4.9e-4, area 7.0e-3, central pressure 7.3e-4
    assert r.depth[0] == pytest.approx(d, rel=3e-3)
    assert r.area[0] == pytest.approx(math.pi * a * a, rel=3e-2)
    p = r.fields[0.0].pressure
    assert p[n // 2, n // 2] == pytest.approx(3.0 * force / (2.0 * math.pi * a * a), rel=5e-3)
    assert r.contact_fraction[0] == pytest.approx(r.area[0] / EDGE**2, rel=1e-14)


def test_a_sampled_paraboloid_creeps_as_lee_radok_on_a_viscous_body():
    """Viscous, constant F: d^(3/2) = 3 F t / (16 eta sqrt(R))."""
    eta, force = 2.0, 0.05
    r = mv.solve(mv.Scene(indenter=_paraboloid_map(129), medium=mv.Viscous(eta=eta), force=force,
                          duration=4.0, times=[1.0, 2.0, 4.0]))
    R = 1.0 / (2.0 * C)
    exact = (3.0 * force * r.t / (16.0 * eta * math.sqrt(R))) ** (2.0 / 3.0)
    # measured: 1.07e-3 relative at 1 s, 3.5e-4 at 4 s
    np.testing.assert_allclose(r.depth, exact, rtol=5e-3)


# ---------------------------------------------------------------------- rough map
def _check_contact(r, fields, heights, force, tol):
    """Force balance, p >= 0, gap >= 0, complementarity, and the series against the fields."""
    dx = r.dx
    p, gap = fields.pressure, fields.gap
    assert p.sum() * dx * dx == pytest.approx(force, rel=1e-13)
    assert p.min() >= 0.0
    scale = heights.max() - heights.min()
    assert gap.min() >= -tol * scale
    contact = p > 0
    assert np.abs(gap[contact]).max() <= tol * scale
    assert np.all(gap[~contact] >= -tol * scale)
    return contact


def test_rough_elastic_contact_keeps_the_invariants():
    n, dx, G, force = 128, 1.0 / 128, 1.0, 2e-3
    hm = _rough_map(n, dx, seed=1, rms=1e-3)
    r = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=G), force=force,
                          outputs=("depth", "pressure", "gap", "deflection")), tol=1e-12)
    f = r.fields[0.0]
    # measured: force 1.6e-15 off, |gap| in contact 1.8e-16 of the height range, no
    # negative gap outside it
    contact = _check_contact(r, f, hm.heights, force, tol=1e-15)
    # the gap is the height below the highest point plus deflection minus depth
    np.testing.assert_allclose(f.gap, hm.heights.max() - hm.heights + f.deflection - r.depth[0],
                               rtol=0, atol=1e-14)
    assert r.area[0] == contact.sum() * dx * dx
    assert r.contact_fraction[0] == pytest.approx(contact.mean(), rel=1e-14)
    assert 0.005 < r.contact_fraction[0] < 0.2
    labels, count = ndimage.label(contact)  # 4-connectivity, no wrap
    assert r.patches[0] == count > 5
    assert r.mean_gap[0] == pytest.approx(f.gap.mean(), rel=1e-12)


@pytest.mark.parametrize("periodic", [False, True])
def test_a_large_map_reports_the_iterations_of_each_nested_level(periodic):
    # a 512 x 512 map is solved on nested grids (coarse levels first); each level's
    # iterations are reported and add up to the solve's (a map too small to nest reports one
    # level, MDR none)
    n, dx = 512, 1.0 / 512
    hm = mv.HeightMap(_rough_map(n, dx, seed=2, rms=1e-3).heights, dx, periodic=periodic)
    r = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=2e-3))
    assert len(r.level_iterations) >= 2
    assert sum(r.level_iterations) == r.iterations and min(r.level_iterations) > 0
    small = mv.solve(mv.Scene(indenter=_rough_map(64, 1.0 / 64, seed=2, rms=1e-3),
                              medium=mv.Elastic(G=1.0), force=2e-3))
    assert small.level_iterations == (small.iterations,)
    assert mv.solve(mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Elastic(G=1.0),
                             force=1.0), "mdr", 101).level_iterations is None


def test_the_resolution_warning_of_a_rough_contact_measures_its_patches():
    # the same 128 x 128 map: many small patches warn (measured: 98 patches of 1.9 elements'
    # mean diameter at 1.7 % contact), one large contact (65 % of the map) does not
    hm = _rough_map(128, 1.0 / 128, seed=1, rms=1e-3)
    with pytest.warns(mv.ResolutionWarning, match="patches span fewer than 10 elements") as record:
        rough = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=2e-3))
    assert "refine n" not in str(record[0].message) and "sampled finer" in str(record[0].message)
    assert rough.patches[0] > 50
    with warnings.catch_warnings():
        warnings.simplefilter("error", mv.ResolutionWarning)
        full = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=0.2))
    assert full.contact_fraction[0] > 0.5


def test_a_sweep_of_height_maps_solves_each_on_its_own_grid():
    scenes = [mv.Scene(indenter=_rough_map(n, 1.0 / n, seed=1, rms=1e-3), medium=mv.Elastic(G=1.0),
                       force=2e-3) for n in (32, 48)]
    sweep = mv.solve_many(scenes, workers=1, progress=False)
    assert not sweep.failures and sweep.n is None
    for scene, result in zip(scenes, sweep.results):
        alone = mv.solve(scene)
        assert result.n == alone.n == scene.indenter.n
        assert result.depth[0] == alone.depth[0]


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")  # the instant contact is small
def test_rough_creep_on_a_standard_solid_goes_from_the_instant_to_the_relaxed_elastic_contact():
    """Constant force on G(t) = G_inf + G1 exp(-t/tau): the contact grows monotonically from
    the elastic one at G0 = G_inf + G1 to the elastic one at G_inf, independent solves."""
    n, dx, force = 64, 1.0 / 64, 4e-3
    hm = _rough_map(n, dx, seed=2, rms=1e-3)
    g_inf, g1, tau = 1.0, 3.0, 0.1
    times = np.linspace(0.15, 6.0, 40)
    creep = mv.solve(mv.Scene(indenter=hm, medium=mv.StandardSolid(g_inf, g1, tau), force=force,
                              duration=6.0, times=times, dt=0.01, outputs=("depth", "pressure", "gap"),
                              field_times=[6.0]), tol=1e-12)
    assert np.all(np.diff(creep.area) >= 0.0) and creep.area[-1] > 1.5 * creep.area[0]
    assert np.all(np.diff(creep.depth) > 0.0)
    _check_contact(creep, creep.fields[6.0], hm.heights, force, tol=1e-14)
    assert creep.mean_gap[-1] == pytest.approx(creep.fields[6.0].gap.mean(), rel=1e-12)

    def elastic(G):
        return mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=G), force=force), tol=1e-12)
    relaxed, instant = elastic(g_inf), elastic(g_inf + g1)
    # the creep time is tau G0 / G_inf = 0.4 s: at 6 s = 15 creep times it is complete to
    # exp(-15) = 3e-7; measured depth 9e-8 relative off the relaxed elastic solve, area equal
    assert creep.depth[-1] == pytest.approx(relaxed.depth[0], rel=1e-6)
    assert creep.area[-1] == relaxed.area[0] and creep.patches[-1] == relaxed.patches[0]
    # the first output, 0.15 s, has crept already: the instant elastic contact is smaller
    assert instant.area[0] < creep.area[0]


@pytest.mark.parametrize("periodic", [False, True], ids=["map", "cell"])
def test_rough_relaxation_at_held_depth_keeps_the_contact_and_relaxes_the_force_as_g(periodic):
    """A depth step held on a standard solid: the contact set never changes (the pressure
    relaxes in proportion, p = G(t) x), so the force follows G(t) / G0 exactly and the
    contact area is constant. On a periodic cell the held depth is a held mean separation."""
    n, dx = 64, 1.0 / 64
    hm = _rough_map(n, dx, seed=3, rms=1e-3)
    hm = mv.HeightMap(hm.heights, dx, periodic=periodic)
    g_inf, g1, tau = 1.0, 3.0, 0.1
    times = np.linspace(0.02, 0.5, 25)
    r = mv.solve(mv.Scene(indenter=hm, medium=mv.StandardSolid(g_inf, g1, tau), depth=2.5e-3,
                          duration=0.5, times=times, dt=0.002), tol=1e-13)
    assert np.all(r.area == r.area[0]) and np.all(r.patches == r.patches[0]) and r.patches[0] > 1
    modulus = (g_inf + g1 * np.exp(-r.t / tau)) / (g_inf + g1)
    # the exponential update is exact for a fixed contact set, so the ratio is off by the
    # solves' own error alone, which follows their tolerance (cell: 1.8e-12, 2.2e-13, 9.8e-15
    # and 2.0e-15 relative at tol 1e-10 to 1e-14); measured here 1.9e-15 (map), 9.8e-15 (cell)
    np.testing.assert_allclose(r.force / r.force[0], modulus / modulus[0], rtol=1e-13)
    # depth control: the mean gap is fixed too (so is the deflection, K[x], x fixed);
    # measured: equal to the last bit
    np.testing.assert_allclose(r.mean_gap, r.mean_gap[0], rtol=1e-14)
    if periodic:
        mean_height = hm.heights.max() - hm.heights.mean()
        # measured 8e-15 relative
        assert r.mean_gap[0] == pytest.approx(mean_height - 2.5e-3, rel=5e-14)


# ---------------------------------------------------------------------- files and errors
def test_height_map_scenes_round_trip_through_a_scene_file_and_its_npy(tmp_path):
    hm = _rough_map(32, 0.01, seed=4, rms=1e-3)
    scene = mv.Scene(indenter=hm, medium=mv.KelvinVoigt(G=1.0, eta=0.5), force=2e-2, duration=1.0)
    path = tmp_path / "rough.toml"
    text = scene.to_toml("bem", path=path)
    assert 'heights = "rough.npy"' in text and path.read_text() == text
    np.testing.assert_array_equal(np.load(tmp_path / "rough.npy"), hm.heights)
    back, method, n = mv.scenefile.load_scene(path)
    assert (method, n) == ("bem", 32) and back == scene
    np.testing.assert_array_equal(back.indenter.heights, hm.heights)
    inline = tmp_path / "inline.toml"
    inline.write_text(scene.to_toml("bem", 32))
    assert mv.Scene.from_toml(inline) == scene
    np.testing.assert_array_equal(mv.solve(back).depth, mv.solve(scene).depth)


def test_a_scene_file_reads_heights_numpy_saved(tmp_path):
    """The reader against numpy's own writer, and its refusals."""
    h = np.random.default_rng(5).standard_normal((6, 9)) * 1e-3
    text = ('method = "bem"\nforce = 1e-6\n[indenter]\ntype = "heightmap"\nheights = "h.npy"\n'
            'dx = 0.01\n[medium]\ntype = "elastic"\nG = 1.0\n')
    (tmp_path / "s.toml").write_text(text)
    np.save(tmp_path / "h.npy", h)
    scene, method, n = mv.scenefile.load_scene(tmp_path / "s.toml")
    assert (method, n) == ("bem", 9)
    np.testing.assert_array_equal(scene.indenter.heights, h)
    for bad, word in [(h.astype(np.float32), "<f4"), (np.asfortranarray(h), "Fortran"),
                      (h[np.newaxis], "2-D"), (h.astype(">f8"), "float64"), (h[:0], "empty")]:
        np.save(tmp_path / "h.npy", bad)
        with pytest.raises(mv.InvalidInputError, match=word):
            mv.scenefile.load_scene(tmp_path / "s.toml")
    (tmp_path / "h.npy").unlink()
    with pytest.raises(mv.InvalidInputError, match="h.npy"):
        mv.scenefile.load_scene(tmp_path / "s.toml")
    np.save(tmp_path / "h.npy", h)
    (tmp_path / "s.toml").write_text(text.replace('method = "bem"', 'method = "bem"\nn = 6'))
    with pytest.raises(mv.InvalidInputError, match="n = 9"):
        mv.scenefile.load_scene(tmp_path / "s.toml")


@pytest.mark.parametrize("heights, dx, word", [
    (np.array([[0.0, np.nan], [1.0, 2.0]]), 0.1, "finite"),
    (np.zeros(5), 0.1, "2-D"),
    (np.zeros((0, 4)), 0.1, "empty"),
    (np.zeros((2, 2), dtype=complex), 0.1, "complex"),
    (np.zeros((2, 2), dtype=bool), 0.1, "bool"),
    (np.array([["a", "b"]]), 0.1, "real numbers"),
    (np.zeros((2, 2)), 0.0, "dx"),
    (np.zeros((2, 2)), None, "dx"),
], ids=["nan", "1-d", "empty", "complex", "bool", "strings", "dx-zero", "dx-missing"])
def test_bad_maps_are_refused_naming_what(heights, dx, word):
    with pytest.raises(mv.InvalidInputError, match=word):
        mv.HeightMap(heights, dx)


def test_height_map_runs_are_refused_where_they_cannot_run():
    hm = _paraboloid_map(9)
    scene = mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=0.01)
    with pytest.raises(mv.InvalidInputError, match="MDR needs an axisymmetric indenter"):
        mv.solve(scene, "mdr")
    with pytest.raises(mv.InvalidInputError, match="n = 9"):
        mv.solve(scene, "bem", 17)
    with pytest.raises(mv.InvalidInputError, match="patches"):
        mv.solve(mv.Scene(indenter=mv.Paraboloid(c=1.0), medium=mv.Elastic(G=1.0), force=0.01,
                          outputs=("depth", "patches")), "bem", 33)
    with pytest.raises(mv.InvalidInputError, match="MDR"):
        scene.to_toml("mdr")


class _Topography:
    """A stand-in with SurfaceTopography's interface: heights() indexed (x, y), pixel_size
    (sx, sy), is_periodic."""

    def __init__(self, heights_xy, pixel_size, periodic):
        self._h, self.pixel_size, self.is_periodic = heights_xy, pixel_size, periodic
        self.dim = 2

    def heights(self):
        return self._h


def test_a_topography_is_read_through_its_interface():
    h_xy = np.arange(12.0).reshape(4, 3)  # nx = 4, ny = 3
    hm = mv.HeightMap(_Topography(h_xy, (0.5, 0.5), False))
    assert hm.shape == (3, 4) and hm.dx == 0.5 and not hm.periodic
    np.testing.assert_array_equal(hm.heights, h_xy.T)
    with pytest.raises(mv.InvalidInputError, match="square"):
        mv.HeightMap(_Topography(h_xy, (0.5, 0.25), False))
    with pytest.raises(mv.InvalidInputError, match="pixel size"):
        mv.HeightMap(_Topography(h_xy, (0.5, 0.5), False), dx=0.4)


def test_surface_topography_when_installed():
    st = pytest.importorskip("SurfaceTopography")
    h_xy = np.random.default_rng(6).standard_normal((8, 6))
    topo = st.Topography(h_xy, physical_sizes=(4.0, 3.0), periodic=True)
    hm = mv.HeightMap(topo)
    assert hm.shape == (6, 8) and hm.dx == 0.5 and hm.periodic
    np.testing.assert_array_equal(hm.heights, h_xy.T)


# ---------------------------------------------------------------------- periodic cells
def _corner_paraboloid(n, dx, shift):
    """Heights -c r^2 of a paraboloid apex, r the periodic distance to the element ``shift``
    (its apex on that element), on an n x n periodic cell."""
    i = np.arange(n)
    d = np.minimum((i - shift) % n, (shift - i) % n) * dx
    return mv.HeightMap(-C * (d[np.newaxis, :] ** 2 + d[:, np.newaxis] ** 2), dx, periodic=True)


def test_a_periodic_cell_is_translation_invariant_and_joins_patches_across_its_edges():
    """The same periodic surface with its apex at the centre and at the corner: the same
    depth, area and mean gap, the pressure moved with it; one patch in both, where the
    cell cut open counts four."""
    n, dx, force = 64, 1.0 / 64, 0.02
    centre, corner = _corner_paraboloid(n, dx, n // 2), _corner_paraboloid(n, dx, 0)
    np.testing.assert_array_equal(np.roll(corner.heights, n // 2, axis=(0, 1)), centre.heights)
    run = {}
    for name, hm in (("centre", centre), ("corner", corner)):
        run[name] = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=1.0), force=force,
                                      outputs=("depth", "pressure", "gap")), tol=1e-12)
    a, b = run["centre"], run["corner"]
    assert a.patches[0] == b.patches[0] == 1 and a.at_edge is None
    # measured: depth 9e-16 relative, pressure 1.1e-14 of the peak
    assert b.depth[0] == pytest.approx(a.depth[0], rel=5e-15)
    assert b.area[0] == a.area[0]
    pa, pb = a.fields[0.0].pressure, b.fields[0.0].pressure
    assert np.abs(np.roll(pb, n // 2, axis=(0, 1)) - pa).max() < 5e-14 * pa.max()
    _check_contact(b, b.fields[0.0], corner.heights, force, tol=1e-14)
    # zero-mean deflection: the mean gap is the mean height below the apex minus the depth
    assert b.mean_gap[0] == pytest.approx(corner.heights.max() - corner.heights.mean() - b.depth[0],
                                          rel=1e-12)
    assert b.mean_gap[0] == pytest.approx(b.fields[0.0].gap.mean(), rel=1e-12)
    cut = mv.solve(mv.Scene(indenter=mv.HeightMap(corner.heights, dx), medium=mv.Elastic(G=1.0),
                            force=force))
    assert cut.patches[0] == 4


def test_a_periodic_wavy_surface_follows_westergaard():
    """h = g cos(2 pi x / lambda), uniform in y, at mean pressure pbar below full contact:
    the contact fraction 2a / lambda with pbar = p* sin^2(pi a / lambda), p* = pi E* g /
    lambda, E* = 4 G."""
    nx, ny, wavelength, g, G = 256, 4, 1.0, 1e-3, 1.0
    dx = wavelength / nx
    x = (np.arange(nx) - 0.5 * (nx - 1)) * dx
    heights = np.tile(g * np.cos(2 * np.pi * x / wavelength), (ny, 1))
    p_star = np.pi * 4 * G * g / wavelength
    pbar = 0.3 * p_star
    hm = mv.HeightMap(heights, dx, periodic=True)
    r = mv.solve(mv.Scene(indenter=hm, medium=mv.Elastic(G=G), force=pbar * nx * ny * dx * dx), tol=1e-12)
    a = wavelength / np.pi * np.arcsin(np.sqrt(pbar / p_star))
    # measured 0.47 elements off the contact width 2a (the width is sampled by elements)
    assert r.contact_fraction[0] == pytest.approx(2 * a / wavelength, abs=1.5 / nx)
    assert r.patches[0] == 1


def test_periodic_creep_on_a_standard_solid_ends_in_the_relaxed_periodic_contact():
    n, dx, force = 64, 1.0 / 64, 4e-3
    hm = _rough_map(n, dx, seed=7, rms=1e-3)
    cell = mv.HeightMap(hm.heights, dx, periodic=True)
    creep = mv.solve(mv.Scene(indenter=cell, medium=mv.StandardSolid(1.0, 3.0, 0.1), force=force,
                              duration=6.0, times=np.linspace(0.15, 6.0, 40), dt=0.01), tol=1e-12)
    relaxed = mv.solve(mv.Scene(indenter=cell, medium=mv.Elastic(G=1.0), force=force), tol=1e-12)
    assert np.all(np.diff(creep.area) >= 0.0) and np.all(np.diff(creep.mean_gap) < 0.0)
    # as in the non-periodic test: complete to exp(-15); measured 7e-8 relative
    assert creep.mean_gap[-1] == pytest.approx(relaxed.mean_gap[0], rel=1e-6)
    assert creep.area[-1] == relaxed.area[0] and creep.patches[-1] == relaxed.patches[0]


@pytest.mark.filterwarnings("ignore::mdrvisc.ResolutionWarning")  # the first and last contacts are small
def test_rough_loading_and_unloading_separates_before_the_depth_returns():
    """A depth ramp up and down on a standard solid: the contact grows while loading and
    shrinks while unloading, the force never turns tensile, and the surface, not yet
    recovered, loses the indenter while the depth is still half its peak."""
    hm = _rough_map(64, 1.0 / 64, seed=8, rms=1e-3)
    r = mv.solve(mv.Scene(indenter=hm, medium=mv.StandardSolid(1.0, 3.0, 0.1),
                          depth=([0.0, 0.5, 1.0], [0.0, 3e-3, 0.0]), duration=1.0,
                          times=np.linspace(0.05, 1.0, 20), dt=0.0025), tol=1e-12)
    loading, unloading = r.t <= 0.5, r.t >= 0.5
    assert np.all(np.diff(r.area[loading]) > 0) and np.all(np.diff(r.area[unloading]) <= 0)
    assert np.all(np.diff(r.patches[unloading]) <= 0)
    assert r.force.min() >= 0.0
    apart = r.t >= 0.75
    assert np.all(r.force[apart] == 0) and np.all(r.area[apart] == 0) and np.all(r.patches[apart] == 0)
    assert r.depth[r.t == 0.75][0] == pytest.approx(1.5e-3, rel=1e-12)
