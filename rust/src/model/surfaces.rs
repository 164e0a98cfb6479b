//! Gaussian self-affine random surfaces on a periodic cell, reproducible bit for bit from a
//! seed on every machine.
//!
//! The height map is the real part of the inverse DFT of independent complex Gaussian
//! amplitudes times sqrt(C(q)), C the isotropic power spectrum: C(q) ~ q^(-2(1+H)) between
//! the roll-off wavevector q_r = 2 pi / rolloff (C flat below it) and the short cutoff
//! q_s = 2 pi / short_cutoff (C zero above it; default the Nyquist wavevector pi / dx),
//! C(0) = 0. The real part of such a field is Gaussian, stationary and periodic, with the
//! spectrum (C(q) + C(-q)) / 2 = C(q). The map is then scaled so that its rms height, or
//! its rms slope (spectral: sqrt(sum over modes of |q|^2 |h_q|^2), the slope of the
//! trigonometric interpolant), equals the request exactly.
//!
//! Reproducibility: the random numbers come from SplitMix64 (Steele, Lea and Flood 2014:
//! state += 0x9E3779B97F4A7C15, then two xor-shift-multiply rounds), 53-bit uniform
//! doubles, and the Box–Muller transform; the transcendental functions (log, sin, cos, pow)
//! are the pure-Rust `libm` crate's (a port of musl's), not the platform's, the inverse
//! DFT is this module's own mixed-radix FFT (no SIMD code paths chosen at run time), and
//! every sum runs in a fixed order. Floating-point operations are IEEE-754 and Rust fuses
//! none, so the same inputs give the same bits on every platform.

use crate::support::error::{check_positive, Error, Result};
use crate::support::monitor::Stop;
use rayon::prelude::*;
use rustfft::num_complex::Complex;
use std::f64::consts::PI;

/// What a self-affine surface is scaled to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Roughness {
    /// Root-mean-square height (m).
    RmsHeight(f64),
    /// Root-mean-square slope (dimensionless, spectral definition).
    RmsSlope(f64),
}

/// A self-affine surface's parameters: `nx` x `ny` elements of side `dx` (m), Hurst
/// exponent `hurst` in (0, 1), roll-off and short-cutoff wavelengths (m, None: none and the
/// Nyquist wavelength 2 dx), and its scale.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SelfAffine {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Element side (m).
    pub dx: f64,
    /// Hurst exponent (dimensionless), 0 < H < 1.
    pub hurst: f64,
    /// Wavelength (m) above which the spectrum is flat; None: a power law down to the
    /// cell's longest wave.
    pub rolloff: Option<f64>,
    /// Shortest wavelength (m), >= 2 dx; None: 2 dx (the Nyquist wavelength).
    pub short_cutoff: Option<f64>,
    /// The rms height or slope the map is scaled to.
    pub roughness: Roughness,
}

/// Largest surface (elements): 8192 x 8192, the largest grid of a BEM run
/// (`crate::model::settings::MAX_BEM_N`).
pub const MAX_SURFACE_ELEMENTS: usize = 1 << 26;

impl SelfAffine {
    /// Fails with a message naming the parameter unless the sizes are 1..`MAX_SURFACE_ELEMENTS`,
    /// dx > 0, 0 < H < 1, the wavelengths positive with short_cutoff >= 2 dx and
    /// rolloff > short_cutoff, and the rms value positive.
    pub fn validate(&self) -> Result<()> {
        match self.nx.checked_mul(self.ny) {
            Some(n) if n > 0 && n <= MAX_SURFACE_ELEMENTS => {}
            _ => {
                return Err(Error::InvalidInput(format!(
                    "a surface takes 1 to {MAX_SURFACE_ELEMENTS} elements, got {} x {}",
                    self.nx, self.ny
                )))
            }
        }
        check_positive("element size dx", self.dx)?;
        if !(self.hurst > 0.0 && self.hurst < 1.0) {
            return Err(Error::InvalidInput(format!(
                "hurst must lie in (0, 1), got {}",
                self.hurst
            )));
        }
        let short = self.short_cutoff.unwrap_or(2.0 * self.dx);
        if let Some(s) = self.short_cutoff {
            check_positive("short_cutoff", s)?;
            if s < 2.0 * self.dx {
                return Err(Error::InvalidInput(format!(
                    "short_cutoff must be >= 2 dx = {} m (the shortest wave the grid holds), got {s} m",
                    2.0 * self.dx
                )));
            }
        }
        if let Some(r) = self.rolloff {
            check_positive("rolloff", r)?;
            if r <= short {
                return Err(Error::InvalidInput(format!(
                    "rolloff must exceed the short cutoff {short} m, got {r} m"
                )));
            }
        }
        match self.roughness {
            Roughness::RmsHeight(v) => check_positive("rms_height", v),
            Roughness::RmsSlope(v) => check_positive("rms_slope", v),
        }
    }

    /// The unscaled amplitude sqrt(C(q)) of the mode with wavevector magnitude q (rad/m).
    fn amplitude(&self, q: f64) -> f64 {
        let q_s = PI / self.dx.max(self.short_cutoff.unwrap_or(0.0) / 2.0);
        if q <= 0.0 || q > q_s * (1.0 + 1e-12) {
            return 0.0;
        }
        let q_r = self.rolloff.map_or(0.0, |r| 2.0 * PI / r);
        libm::pow(q.max(q_r), -(1.0 + self.hurst))
    }
}

/// SplitMix64 (Steele, Lea and Flood 2014), the generator of `self_affine`.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform on (0, 1]: the top 53 bits plus one, over 2^53.
    fn uniform(&mut self) -> f64 {
        ((self.next() >> 11) + 1) as f64 / (1u64 << 53) as f64
    }

    /// Two independent standard normal numbers (Box–Muller with `libm`).
    fn normal_pair(&mut self) -> (f64, f64) {
        let (u1, u2) = (self.uniform(), self.uniform());
        let r = (-2.0 * libm::log(u1)).sqrt();
        let angle = 2.0 * PI * u2;
        (r * libm::cos(angle), r * libm::sin(angle))
    }
}

/// Wavevector (rad/m) of DFT index k of n elements of side dx (indices above n/2 stand for
/// k - n).
fn wavevector(k: usize, n: usize, dx: f64) -> f64 {
    let k = if k <= n / 2 {
        k as f64
    } else {
        k as f64 - n as f64
    };
    2.0 * PI * k / (n as f64 * dx)
}

/// A Gaussian self-affine height map (m), row-major (ny rows of nx), zero mean, periodic,
/// from the seed `seed`: bit for bit the same on every machine (see the module's doc).
/// Stops with `Error::Interrupted` within a row of work once `stop` is requested.
pub fn self_affine(surface: &SelfAffine, seed: u64, stop: &Stop) -> Result<Vec<f64>> {
    surface.validate()?;
    let (nx, ny, dx) = (surface.nx, surface.ny, surface.dx);
    crate::support::memory::check(&format!("a {nx} x {ny} surface"), 40.0 * (nx * ny) as f64)?;
    // amplitudes in row-major order of (ky, kx), the random numbers drawn in that order
    let mut rng = SplitMix64(seed);
    let mut z: Vec<Complex<f64>> = (0..nx * ny)
        .map(|i| {
            if i % nx == 0 {
                stop.check()?;
            }
            let (kx, ky) = (i % nx, i / nx);
            let q = libm::hypot(wavevector(kx, nx, dx), wavevector(ky, ny, dx));
            let (a, b) = rng.normal_pair();
            Ok(Complex::new(a, b) * surface.amplitude(q))
        })
        .collect::<Result<_>>()?;
    // The real field's DFT coefficients c_k = (z_k + conj(z_-k)) / 2 give its rms height
    // and slope (sum of |c_k|^2 and of |q_k|^2 |c_k|^2), summed in index order.
    let (mut height2, mut slope2) = (0.0, 0.0);
    for i in 0..nx * ny {
        let (kx, ky) = (i % nx, i / nx);
        let mirror = ((ny - ky) % ny) * nx + (nx - kx) % nx;
        let c = (z[i] + z[mirror].conj()) * 0.5;
        let (qx, qy) = (wavevector(kx, nx, dx), wavevector(ky, ny, dx));
        height2 += c.norm_sqr();
        slope2 += (qx * qx + qy * qy) * c.norm_sqr();
    }
    let scale = match surface.roughness {
        Roughness::RmsHeight(v) => v / height2.sqrt(),
        Roughness::RmsSlope(v) => v / slope2.sqrt(),
    };
    if !scale.is_finite() {
        let cutoff = surface.short_cutoff.map_or_else(
            || format!("the grid's own, {} m", 2.0 * dx),
            |c| format!("{c} m"),
        );
        return Err(Error::InvalidInput(format!(
            "the spectrum holds no mode of the {nx} x {ny} grid of side {dx} m: no wavelength between the cell's and the short cutoff ({cutoff}) fits on it; enlarge the grid or shorten the cutoff"
        )));
    }
    inverse_dft_2d(&mut z, nx, ny, stop)?;
    Ok(z.iter().map(|c| c.re * scale).collect())
}

/// In-place unnormalised inverse DFT (sum of z_k e^(+i q x)) of `nx` x `ny` row-major data:
/// rows, then columns (through a transpose), each transform by `dft` with `libm` twiddles;
/// `stop` is polled before each row and column.
fn inverse_dft_2d(z: &mut [Complex<f64>], nx: usize, ny: usize, stop: &Stop) -> Result<()> {
    let (tw_x, tw_y) = (twiddles(nx), twiddles(ny));
    z.par_chunks_mut(nx).try_for_each_init(
        || vec![Complex::default(); nx],
        |out, row| {
            stop.check()?;
            dft(row, 1, nx, out, &tw_x, 1);
            row.copy_from_slice(out);
            Ok::<(), Error>(())
        },
    )?;
    let mut t = vec![Complex::default(); nx * ny];
    for (i, v) in z.iter().enumerate() {
        t[(i % nx) * ny + i / nx] = *v;
    }
    t.par_chunks_mut(ny).try_for_each_init(
        || vec![Complex::default(); ny],
        |out, col| {
            stop.check()?;
            dft(col, 1, ny, out, &tw_y, 1);
            col.copy_from_slice(out);
            Ok::<(), Error>(())
        },
    )?;
    for (j, v) in t.iter().enumerate() {
        z[(j % ny) * nx + j / ny] = *v;
    }
    Ok(())
}

/// e^(+2 pi i k / n) for k in 0..n, by `libm`.
fn twiddles(n: usize) -> Vec<Complex<f64>> {
    (0..n)
        .map(|k| {
            let a = 2.0 * PI * k as f64 / n as f64;
            Complex::new(libm::cos(a), libm::sin(a))
        })
        .collect()
}

/// Writes out[k] = sum over j < n of x[j stride] w^(j k) (w = e^(2 pi i / n)), by mixed-radix
/// decimation in time over the smallest prime factor; `tw` holds the twiddles of a length
/// N = n `tw_stride`.
fn dft(
    x: &[Complex<f64>],
    stride: usize,
    n: usize,
    out: &mut [Complex<f64>],
    tw: &[Complex<f64>],
    tw_stride: usize,
) {
    if n == 1 {
        out[0] = x[0];
        return;
    }
    let p = (2..)
        .take_while(|p| p * p <= n)
        .find(|p| n % p == 0)
        .unwrap_or(n);
    let m = n / p;
    for r in 0..p {
        dft(
            &x[r * stride..],
            stride * p,
            m,
            &mut out[r * m..(r + 1) * m],
            tw,
            tw_stride * p,
        );
    }
    // out[r m + k] = Y_r[k]; X[k + s m] = sum_r w_n^(r (k + s m)) Y_r[k], in place per k
    let mut y = vec![Complex::default(); p];
    for k in 0..m {
        for r in 0..p {
            y[r] = out[r * m + k];
        }
        for s in 0..p {
            let mut acc = y[0];
            for (r, yr) in y.iter().enumerate().skip(1) {
                acc += *yr * tw[(r * (k + s * m) % n) * tw_stride];
            }
            out[s * m + k] = acc;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The FFT equals the direct sum of the DFT (to round-off) for prime, composite and
    /// power-of-two lengths.
    #[test]
    fn the_fft_is_the_dft() {
        for n in [1usize, 2, 3, 6, 7, 12, 30, 64, 97, 100] {
            let x: Vec<Complex<f64>> = (0..n)
                .map(|j| Complex::new((j as f64 * 0.7).sin(), (j as f64 * 1.3).cos()))
                .collect();
            let tw = twiddles(n);
            let mut out = vec![Complex::default(); n];
            dft(&x, 1, n, &mut out, &tw, 1);
            for (k, o) in out.iter().enumerate() {
                let mut exact = Complex::new(0.0, 0.0);
                for (j, v) in x.iter().enumerate() {
                    let a = 2.0 * PI * (j * k) as f64 / n as f64;
                    exact += v * Complex::new(a.cos(), a.sin());
                }
                assert!((o - exact).norm() < 1e-12 * n as f64, "n = {n}, k = {k}");
            }
        }
    }

    /// SplitMix64 from seed 0 gives the published first outputs of the reference
    /// implementation (Vigna's splitmix64.c).
    #[test]
    fn splitmix_matches_the_reference_sequence() {
        let mut r = SplitMix64(0);
        assert_eq!(r.next(), 0xE220_A839_7B1D_CDAF);
        assert_eq!(r.next(), 0x6E78_9E6A_A1B9_65F4);
        assert_eq!(r.next(), 0x06C4_5D18_8009_454F);
    }

    /// Bad parameters are refused by name.
    #[test]
    fn bad_parameters_are_refused() {
        let ok = SelfAffine {
            nx: 16,
            ny: 16,
            dx: 1.0,
            hurst: 0.8,
            rolloff: None,
            short_cutoff: None,
            roughness: Roughness::RmsHeight(1.0),
        };
        assert!(self_affine(&ok, 1, &Stop::default()).is_ok());
        for bad in [
            SelfAffine { hurst: 1.0, ..ok },
            SelfAffine { nx: 0, ..ok },
            SelfAffine {
                short_cutoff: Some(1.5),
                ..ok
            },
            SelfAffine {
                rolloff: Some(2.0),
                short_cutoff: Some(4.0),
                ..ok
            },
            SelfAffine {
                roughness: Roughness::RmsSlope(-1.0),
                ..ok
            },
        ] {
            assert!(matches!(
                self_affine(&bad, 1, &Stop::default()),
                Err(Error::InvalidInput(_))
            ));
        }
    }
}
