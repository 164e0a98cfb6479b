"""Random self-affine surfaces and the power spectrum: the measured spectrum and rms values
against the requested ones (statistics computed here with numpy, not by the package), and
reproducibility from the seed."""

import numpy as np
import pytest
from scipy import stats

import mdrvisc as mv
from mdrvisc.errors import InvalidInputError


def _spectral_slope(h, dx):
    """rms slope sqrt(sum |q|^2 |h_q|^2) of a periodic map, from numpy's FFT."""
    ny, nx = h.shape
    c = np.fft.fft2(h) / h.size
    qx = 2 * np.pi * np.fft.fftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dx)
    return np.sqrt(np.sum((qx[np.newaxis, :] ** 2 + qy[:, np.newaxis] ** 2) * np.abs(c) ** 2))


def test_same_seed_same_bits_other_seed_other_surface_any_thread_count():
    args = ((96, 128), 1e-6, 0.7)
    a = mv.surfaces.self_affine(*args, rms_slope=0.1, seed=42)
    b = mv.surfaces.self_affine(*args, rms_slope=0.1, seed=42)
    assert a.dtype == np.float64 and a.shape == (96, 128)
    assert np.array_equal(a, b)
    c = mv.surfaces.self_affine(*args, rms_slope=0.1, seed=43)
    assert not np.allclose(a, c)
    # the largest seed is taken and gives yet another surface
    d = mv.surfaces.self_affine(*args, rms_slope=0.1, seed=2**64 - 1)
    assert not np.allclose(a, d) and not np.allclose(c, d)
    threads = mv.num_threads()
    try:
        mv.set_num_threads(1)
        e = mv.surfaces.self_affine(*args, rms_slope=0.1, seed=42)
    finally:
        mv.set_num_threads(threads)
    assert np.array_equal(a, e)


@pytest.mark.parametrize("hurst", [0.3, 0.8])
def test_spectrum_follows_the_power_law_with_roll_off_and_cutoff(hurst):
    """Mean PSD of 8 surfaces (512^2): slope -2 (1 + H) between roll-off and cutoff
    (measured -2.6045 and -3.6051 for -2.6 and -3.6), flat below the roll-off (its seven
    rings within 1.68x of each other, the first ring holding 4 modes per surface; a power
    law would span ~1800x there), nothing above the cutoff."""
    n, dx = 512, 1.0
    rolloff, cutoff = n * dx / 8, 4 * dx
    spectra = []
    for seed in range(8):
        h = mv.surfaces.self_affine((n, n), dx, hurst, rms_height=1.0, rolloff=rolloff,
                                    short_cutoff=cutoff, seed=seed)
        q, c = mv.surfaces.psd(h, dx)
        spectra.append(c)
    c = np.mean(spectra, axis=0)
    q_r, q_s = 2 * np.pi / rolloff, 2 * np.pi / cutoff
    band = (q > 1.5 * q_r) & (q < 0.8 * q_s)
    slope = np.polyfit(np.log(q[band]), np.log(c[band]), 1)[0]
    assert abs(slope + 2 * (1 + hurst)) < 0.03, slope
    plateau = c[q < 0.9 * q_r]
    assert len(plateau) >= 5 and plateau.max() / plateau.min() < 2.5
    assert np.all(c[q > 1.02 * q_s] < 1e-25 * c.max())


def test_rms_height_and_slope_are_the_requested_ones():
    """The scale is exact: rms height (numpy std) and spectral rms slope to round-off; on a
    band-limited surface (cutoff 16 dx) central differences give the slope to 0.43 %
    (measured)."""
    h = mv.surfaces.self_affine((200, 256), 2e-6, 0.6, rms_height=3e-7, seed=7)
    assert abs(h.mean()) < 1e-12 * 3e-7
    assert abs(h.std() / 3e-7 - 1) < 1e-12
    dx = 1.0
    h = mv.surfaces.self_affine((512, 512), dx, 0.8, rms_slope=0.2, short_cutoff=16 * dx, seed=3)
    assert abs(_spectral_slope(h, dx) / 0.2 - 1) < 1e-12
    gx = (np.roll(h, -1, 1) - np.roll(h, 1, 1)) / (2 * dx)
    gy = (np.roll(h, -1, 0) - np.roll(h, 1, 0)) / (2 * dx)
    assert abs(np.sqrt(np.mean(gx**2 + gy**2)) / 0.2 - 1) < 0.02


def test_heights_are_gaussian():
    """Skewness and excess kurtosis of surfaces of many independent modes (roll-off at
    L/64): measured |skew| <= 0.0053, |kurtosis| <= 0.0094 over four seeds."""
    for seed in range(4):
        h = mv.surfaces.self_affine((512, 512), 1.0, 0.3, rms_height=1.0, rolloff=8.0, seed=seed)
        assert abs(stats.skew(h.ravel())) < 0.03
        assert abs(stats.kurtosis(h.ravel())) < 0.04


def test_psd_of_a_harmonic_and_parseval():
    """A single harmonic a cos(2 pi 5 x / L) puts A (a/2)^2 / (2 pi)^2 into each of its two
    modes, averaged over the modes of ring 5 (counted here); the rings' sums give back the
    mean square height of a surface without modes beyond the Nyquist circle."""
    n, dx, a = 64, 0.5, 2e-3
    x = np.arange(n) * dx
    h = np.tile(a * np.cos(2 * np.pi * 5 * x / (n * dx)), (n, 1))
    q, c = mv.surfaces.psd(h, dx)
    k = np.fft.fftfreq(n, 1.0 / n)
    ring = np.rint(np.hypot(k[np.newaxis, :], k[:, np.newaxis]))
    in_ring = np.count_nonzero(ring == 5)
    area = (n * dx) ** 2
    expected = 2 * area * (a / 2) ** 2 / (2 * np.pi) ** 2 / in_ring
    five = np.argmin(np.abs(q - 2 * np.pi * 5 / (n * dx)))
    assert abs(c[five] / expected - 1) < 1e-12
    assert np.all(np.delete(c, five) < 1e-20 * expected)
    h = mv.surfaces.self_affine((n, n), dx, 0.5, rms_height=1.0, seed=1)
    q, c = mv.surfaces.psd(h, dx)
    counts = np.array([np.count_nonzero((ring == r) & (np.hypot(*np.meshgrid(k, k)) <= n / 2))
                       for r in range(1, int(ring.max()) + 1)])
    counts = counts[counts > 0][: len(c)]
    total = np.sum(c * counts) * (2 * np.pi) ** 2 / area
    assert abs(total - 1.0) < 1e-12


@pytest.mark.parametrize("kwargs", [
    {"rms_slope": 0.1, "rms_height": 1.0},
    {},
    {"rms_slope": 0.1, "hurst": 1.0},
    {"rms_slope": -0.1},
    {"rms_slope": 0.1, "short_cutoff": 1.0},
    {"rms_slope": 0.1, "rolloff": 4.0, "short_cutoff": 8.0},
    {"rms_slope": 0.1, "seed": -1},
    {"rms_slope": 0.1, "seed": 2**64},
    {"rms_slope": 0.1, "seed": 1.5},
    {"rms_slope": 0.1, "shape": (0, 4)},
])
def test_bad_arguments_are_refused_by_name(kwargs):
    args = {"shape": (16, 16), "dx": 1.0, "hurst": 0.8, **kwargs}
    with pytest.raises(InvalidInputError):
        mv.surfaces.self_affine(**args)


def test_psd_refuses_bad_maps():
    with pytest.raises(InvalidInputError):
        mv.surfaces.psd(np.zeros(5), 1.0)
    with pytest.raises(InvalidInputError):
        mv.surfaces.psd(np.full((4, 4), np.nan), 1.0)
    with pytest.raises(InvalidInputError):
        mv.surfaces.psd(np.zeros((4, 4)), -1.0)
    # a 1 x N map has no ring below the Nyquist wavevector: it returned two empty arrays
    for shape in [(1, 64), (64, 1)]:
        with pytest.raises(InvalidInputError, match="at least 2 elements"):
            mv.surfaces.psd(np.random.default_rng(0).random(shape), 1.0)


def test_an_empty_spectrum_is_refused_with_the_cutoff_in_words():
    """No mode in the band: the message names the cutoff and the grid, not Rust's Option."""
    with pytest.raises(InvalidInputError, match=r"short cutoff \(100 m\)") as e:
        mv.surfaces.self_affine((64, 64), 1 / 64, 0.8, rms_height=1.0, short_cutoff=100.0)
    assert "Some(" not in str(e.value)
    with pytest.raises(InvalidInputError, match="the grid's own") as e:
        mv.surfaces.self_affine((1, 1), 1 / 64, 0.8, rms_height=1.0)
