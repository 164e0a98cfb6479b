"""Random rough surfaces and their power spectra.

:func:`self_affine` makes Gaussian self-affine height maps on a periodic cell (in Rust,
bit-for-bit reproducible from the seed on every machine); :func:`psd` measures the
radially averaged power spectral density of any height map. Height maps are (ny, nx)
arrays (m) on square elements of side ``dx`` (m).
"""

import operator
import warnings

import numpy as np
from numpy.typing import ArrayLike

from . import _core
from ._validate import _integer, _optional_positive, _positive
from .errors import InvalidInputError, ResolutionWarning

__all__ = ["self_affine", "psd"]

#: Fewest independent Fourier modes below the short cutoff for which :func:`self_affine`
#: does not warn: with fewer, the heights are a sum of a handful of cosines, far from
#: Gaussian, and their spectrum has too few rings to follow the power law.
MIN_MODES = 16


def self_affine(shape: tuple[int, int], dx: float, hurst: float, rms_slope: float | None = None,
                rms_height: float | None = None, rolloff: float | None = None,
                short_cutoff: float | None = None, seed: int = 0) -> np.ndarray:
    """A Gaussian self-affine random surface on a periodic cell.

    The isotropic power spectrum is C(q) ~ q^(-2 (1 + H)) between the roll-off wavevector
    2 pi / ``rolloff`` (flat below it; without a roll-off the power law reaches the cell's
    longest wave) and the short cutoff 2 pi / ``short_cutoff`` (zero above it; by default
    the Nyquist wavevector pi / dx), and zero at q = 0. Each Fourier mode gets an
    independent complex Gaussian amplitude, so the heights are Gaussian and the map is
    periodic by construction; the map is then scaled so that its rms height or its rms
    slope equals the request exactly. The rms slope is spectral,
    sqrt(sum over modes of abs(q)^2 abs(h_q)^2): the slope of the trigonometric
    interpolant of the heights.

    The random numbers come from SplitMix64 (53-bit uniforms, Box–Muller), the
    transcendental functions from a pure-Rust libm, and the inverse FFT is the crate's own
    fixed-order code: the same arguments give the same array, bit for bit, on every
    machine and thread count.

    Parameters
    ----------
    shape : (int, int)
        Grid shape (ny, nx), >= 1 each (at most 8192 x 8192 elements).
    dx : float
        Element side (m), > 0.
    hurst : float
        Hurst exponent H, 0 < H < 1.
    rms_slope : float, optional
        Root-mean-square slope (dimensionless) to scale to.
    rms_height : float, optional
        Root-mean-square height (m) to scale to; give exactly one of the two.
    rolloff : float, optional
        Roll-off wavelength (m), > ``short_cutoff``.
    short_cutoff : float, optional
        Shortest wavelength (m), >= 2 dx.
    seed : int
        Seed of the generator, 0 <= seed < 2**64.

    Returns
    -------
    numpy.ndarray
        Heights (m), shape (ny, nx), zero mean.

    Warns
    -----
    ResolutionWarning
        Fewer than :data:`MIN_MODES` independent Fourier modes lie below the short cutoff
        (a small grid, or a cutoff close to the cell's size): the surface is a few cosines,
        not a Gaussian self-affine one.

    Examples
    --------
    >>> import mdrvisc as mv
    >>> h = mv.surfaces.self_affine((256, 256), 1e-6, 0.8, rms_slope=0.1, seed=1)
    >>> h.shape
    (256, 256)
    """
    try:
        ny, nx = shape
    except (TypeError, ValueError):
        raise InvalidInputError(f"self_affine: shape must be (ny, nx), got {shape!r:.200}") from None
    ny = _integer("self_affine", "shape[0]", ny, 1)
    nx = _integer("self_affine", "shape[1]", nx, 1)
    if (rms_slope is None) == (rms_height is None):
        raise InvalidInputError("self_affine: give exactly one of rms_slope and rms_height")
    hurst = _positive("self_affine", "hurst", hurst)
    if hurst >= 1.0:
        raise InvalidInputError(f"self_affine: hurst must lie in (0, 1), got {hurst!r}")
    seed = _seed(seed)
    dx = _positive("self_affine", "dx", dx)
    cutoff = _optional_positive("self_affine", "short_cutoff", short_cutoff)
    heights = _core.self_affine(nx, ny, dx, hurst,
                             rms_height=_optional_positive("self_affine", "rms_height", rms_height),
                             rms_slope=_optional_positive("self_affine", "rms_slope", rms_slope),
                             rolloff=_optional_positive("self_affine", "rolloff", rolloff),
                             short_cutoff=cutoff, seed=seed)
    modes = _modes(nx, ny, dx, cutoff)
    if modes < MIN_MODES:
        warnings.warn(f"self_affine: only about {modes} independent Fourier modes of the {ny} x {nx} grid "
                      f"lie below the short cutoff: the surface is a sum of {modes} cosines, far from "
                      f"Gaussian and self-affine (enlarge the grid or shorten the cutoff)", ResolutionWarning,
                      stacklevel=2)
    return heights


def _modes(nx: int, ny: int, dx: float, short_cutoff: float | None) -> int:
    """Independent real Fourier modes (pairs of wavevectors +-q counted once) of an nx x ny
    grid of side dx with 0 < abs(q) <= the short cutoff's wavevector (as the core selects)."""
    q_s = np.pi / max(dx, (short_cutoff or 0.0) / 2.0) * (1 + 1e-12)
    qx = np.sort(np.abs(2 * np.pi * np.fft.fftfreq(nx, dx)))
    qy = np.abs(2 * np.pi * np.fft.fftfreq(ny, dx))
    room = q_s**2 - qy**2
    within = np.where(room >= 0, np.searchsorted(qx**2, np.maximum(room, 0.0), side="right"), 0)
    return int(within.sum()) // 2  # the nonzero wavevectors, halved, rounded up


def _seed(value: object) -> int:
    """``value`` as an int, or InvalidInputError unless it is an integer in [0, 2**64)."""
    try:
        number = None if isinstance(value, (bool, np.bool_)) else operator.index(value)  # type: ignore[arg-type]
    except TypeError:
        number = None
    if number is None or not 0 <= number < 2**64:
        raise InvalidInputError(f"self_affine: seed must be an integer in [0, 2**64 - 1], got {value!r:.80}")
    return number


def psd(heights: ArrayLike, dx: float) -> tuple[np.ndarray, np.ndarray]:
    """Radially averaged isotropic power spectral density of a height map.

    With h_q the map's discrete Fourier coefficients (``numpy.fft.fft2(h) / (nx ny)``) and
    A = nx ny dx^2 its area, each mode carries C(q) = A abs(h_q)^2 / (2 pi)^2, so that the
    sum of C over the modes times the area (2 pi)^2 / A of a mode is the mean square
    height. The modes are averaged over rings of width dq = 2 pi / min(nx dx, ny dx)
    centred on multiples of dq, up to the Nyquist wavevector pi / dx; the mean (q = 0) is
    left out. The map is taken as one period (no window is applied).

    Parameters
    ----------
    heights : array_like
        Heights (m), shape (ny, nx), at least 2 x 2, finite.
    dx : float
        Element side (m), > 0.

    Returns
    -------
    q : numpy.ndarray
        Mean wavevector magnitude of each ring (rad/m).
    C : numpy.ndarray
        Mean power spectral density of each ring (m^4).
    """
    h = np.asarray(heights)
    if h.dtype.kind not in "biuf" or h.ndim != 2 or h.size == 0:
        raise InvalidInputError(f"psd: heights must be a non-empty 2-D real array, got {h.dtype} {h.shape}")
    h = h.astype(np.float64)
    if not np.all(np.isfinite(h)):
        raise InvalidInputError("psd: heights must be finite")
    dx = _positive("psd", "dx", dx)
    ny, nx = h.shape
    if min(nx, ny) < 2:
        raise InvalidInputError(
            f"psd: a radially averaged spectrum needs at least 2 elements along each side, got a "
            f"{ny} x {nx} map (rings of width 2 pi / (min side) leave none below the Nyquist wavevector)")
    coeff = np.fft.fft2(h) / (nx * ny)
    area = nx * ny * dx * dx
    c = area * np.abs(coeff) ** 2 / (2 * np.pi) ** 2
    qx = 2 * np.pi * np.fft.fftfreq(nx, dx)
    qy = 2 * np.pi * np.fft.fftfreq(ny, dx)
    q = np.hypot(qx[np.newaxis, :], qy[:, np.newaxis])
    dq = 2 * np.pi / (min(nx, ny) * dx)
    ring = np.rint(q / dq).astype(np.int64)
    keep = (ring >= 1) & (q <= np.pi / dx * (1 + 1e-12))
    counts = np.bincount(ring[keep], minlength=1)
    filled = counts > 0
    q_mean = np.bincount(ring[keep], weights=q[keep], minlength=1)[filled] / counts[filled]
    c_mean = np.bincount(ring[keep], weights=c[keep], minlength=1)[filled] / counts[filled]
    if not (np.all(np.isfinite(q_mean)) and np.all(np.isfinite(c_mean))):
        raise InvalidInputError(f"psd: the spectrum of heights up to {float(np.max(np.abs(h))):.3g} m on "
                                f"elements of {dx:.3g} m overflows float64: rescale the units")
    return q_mean, c_mean
