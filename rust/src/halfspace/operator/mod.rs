//! The surface operator: deflections of a non-periodic half-space (G = 1 Pa) under
//! element pressures, by zero-padded FFT convolution (DC-FFT) or by a dense matrix (faer).
//!
//! Grids are row-major: element (ix, iy) at index iy * nx + ix, centres dx apart.
//!
//! Kept in one file past 500 lines: both operators apply the same kernel, and the tests
//! check one against the other.

pub mod precondition;

use crate::halfspace::influence::{self, KernelTable};
use crate::support::error::{check_positive, Error, Result};
use faer::{Accum, ColMut, ColRef, Mat, Par};
use rayon::prelude::*;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::num_complex::Complex;
use rustfft::{Fft, FftPlanner};
use std::sync::Arc;

/// A linear map from element pressures (Pa) to element-centre deflections (m) at G = 1 Pa.
pub trait SurfaceOperator {
    /// Number of elements along x.
    fn nx(&self) -> usize;
    /// Number of elements along y.
    fn ny(&self) -> usize;
    /// Element side (m).
    fn dx(&self) -> f64;
    /// Writes K[p] into `u` (both nx * ny long).
    fn apply(&mut self, p: &[f64], u: &mut [f64]);
    /// Writes K[p] into `u` as `apply` does, with the transforms in single precision where
    /// the operator has them (an error of about 1e-7 of the largest |K[p]|), else exactly
    /// as `apply`.
    fn apply_single(&mut self, p: &[f64], u: &mut [f64]) {
        self.apply(p, u);
    }
    /// Adds K[q] to `u` with the transforms in single precision (an error of about 1e-7 of
    /// the largest |K[q]|) where the operator has them; returns false with `u` unchanged
    /// where it does not (the caller applies the operator then).
    fn add_single(&mut self, q: &[f64], u: &mut [f64]) -> bool {
        let _ = (q, u);
        false
    }
    /// The operator's matrix (m/Pa at G = 1) among the elements `idx` (grid indices), for
    /// dense solves on a contact set.
    fn submatrix(&mut self, idx: &[usize]) -> Result<Mat<f64>>;
    /// Writes z = S g, S the conjugate gradients' preconditioner (an approximate inverse of
    /// the operator times dx, `precondition`): by default the inverse-kernel stencil with
    /// g zero beyond the grid.
    fn precondition(&mut self, g: &[f64], z: &mut [f64]) {
        crate::halfspace::operator::precondition::apply(self.nx(), self.ny(), g, z);
    }
    /// Adds to `u` the deflections K[q] of the pressures `values` (Pa) on the elements `idx`
    /// (q zero elsewhere) by direct summation, one pass over the grid per element, where
    /// the operator holds its kernel in real space; returns false with `u` unchanged where
    /// it does not (the caller applies the operator then).
    fn add_point_loads(&mut self, idx: &[usize], values: &[f64], u: &mut [f64]) -> bool {
        let _ = (idx, values, u);
        false
    }
    /// Most point loads for which `add_point_loads` costs less than an `apply` (0 where it
    /// is not supported).
    fn point_load_limit(&self) -> usize {
        0
    }
    /// Whether the grid is a periodic cell (its edges wrap around).
    fn periodic(&self) -> bool {
        false
    }
}

/// Smallest even m >= n of the form 2^a 3^b 5^c with c <= 1 (n itself when n <= 1): the
/// lengths at which rustfft and realfft run fastest. Odd lengths take realfft's slow path,
/// and factors 7 and 25 cost 15-50 % more per point than the next such size up
/// (`benchmarks/bench_operator.py --sizes`, 129..257).
pub(crate) fn fast_size(n: usize) -> usize {
    if n <= 1 {
        return 1;
    }
    let mut m = n + n % 2;
    loop {
        let mut r = m;
        for f in [2, 3] {
            while r % f == 0 {
                r /= f;
            }
        }
        if r == 1 || r == 5 {
            return m;
        }
        m += 2;
    }
}

/// Padded length for a linear convolution over `n` elements with an even kernel: offsets
/// +(n-1) and -(n-1) may share a slot, so 2n - 2 suffices (1 for a single element).
pub fn padded_size(n: usize) -> usize {
    fast_size(2 * n - 2)
}

/// Rows or columns moved together in the blocked transposes.
const TILE: usize = 16;

/// The floating-point type of an FFT operator's transforms and buffers: f64 for the
/// operator itself, f32 for the preconditioners (an approximate inverse loses nothing by
/// single precision, and its FFTs take half the memory traffic and twice the SIMD lanes).
/// Pressures come in and deflections go out as f64 either way.
pub trait Real: rustfft::FftNum + Default {
    /// `x` rounded to this type.
    fn of(x: f64) -> Self;
    /// This value as f64.
    fn to_f64(self) -> f64;
    /// The plan caches of this type in `plans`.
    fn planners(plans: &mut FftPlans) -> (&mut RealFftPlanner<Self>, &mut FftPlanner<Self>);
}

impl Real for f64 {
    fn of(x: f64) -> Self {
        x
    }
    fn to_f64(self) -> f64 {
        self
    }
    fn planners(plans: &mut FftPlans) -> (&mut RealFftPlanner<Self>, &mut FftPlanner<Self>) {
        (&mut plans.real, &mut plans.complex)
    }
}

impl Real for f32 {
    fn of(x: f64) -> Self {
        x as f32
    }
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    fn planners(plans: &mut FftPlans) -> (&mut RealFftPlanner<Self>, &mut FftPlanner<Self>) {
        (&mut plans.real_single, &mut plans.complex_single)
    }
}

/// Per-worker buffers, allocated once with the operator.
struct Worker<T: Real> {
    real: Vec<T>,
    /// TILE half-spectra of rows, for the blocked transpose.
    halves: Vec<Complex<T>>,
    r2c_scratch: Vec<Complex<T>>,
    c2r_scratch: Vec<Complex<T>>,
    col_scratch: Vec<Complex<T>>,
}

/// FFT plan caches (rustfft and realfft planners keep every length they planned), in
/// double and single precision, shared by the operators of one run.
pub struct FftPlans {
    real: RealFftPlanner<f64>,
    complex: FftPlanner<f64>,
    real_single: RealFftPlanner<f32>,
    complex_single: FftPlanner<f32>,
}

impl Default for FftPlans {
    fn default() -> Self {
        FftPlans {
            real: RealFftPlanner::new(),
            complex: FftPlanner::new(),
            real_single: RealFftPlanner::new(),
            complex_single: FftPlanner::new(),
        }
    }
}

/// Largest grid (elements) of an FFT operator: 8192 x 8192, whose zero-padded spectra and
/// buffers take about 4 GB (a whole free solve about 11 GB; `crate::support::memory` checks
/// what the machine has first).
pub const MAX_FFT_ELEMENTS: usize = 1 << 26;
/// Largest grid (elements) of a dense operator: its matrix of 8 n^2 bytes is 2 GB.
pub const MAX_DENSE_ELEMENTS: usize = 1 << 14;

/// Fails unless the `nx` x `ny` grid is non-empty and holds at most `limit` elements, before
/// anything of that size is allocated.
fn check_elements(nx: usize, ny: usize, limit: usize, what: &str) -> Result<()> {
    match nx.checked_mul(ny) {
        Some(n) if n > 0 && n <= limit => Ok(()),
        _ => Err(Error::InvalidInput(format!(
            "the {what} takes 1 to {limit} elements, got nx = {nx}, ny = {ny}"
        ))),
    }
}

/// DC-FFT operator: the kernel spectrum is computed once, FFT plans and buffers live with
/// the operator, and rows and columns are transformed in parallel with rayon. Its
/// transforms run in `T` (f64 for the surface operator, f32 for preconditioners).
pub struct FftOperator<T: Real = f64> {
    nx: usize,
    ny: usize,
    dx: f64,
    mx: usize,
    my: usize,
    half: usize,
    r2c: Arc<dyn RealToComplex<T>>,
    c2r: Arc<dyn ComplexToReal<T>>,
    col_fwd: Arc<dyn Fft<T>>,
    col_inv: Arc<dyn Fft<T>>,
    /// Real kernel spectrum, transposed (half x my), normalisation included.
    spectrum: Vec<T>,
    /// The largest grid whose offsets the spectrum's kernel table held.
    covered: (usize, usize),
    cols: Vec<Complex<T>>,
    workers: Vec<Worker<T>>,
    /// The spectral preconditioner (`SpectralInverse`), made on the first `precondition`
    /// of a grid of at least `SPECTRAL_MIN_ELEMENTS`.
    inverse: Option<Box<SpectralInverse>>,
    /// The kernel in real space at offsets 0..nx, 0..ny (m/Pa at G = 1, row-major), made by
    /// the first `kernel` call.
    kernel: Option<Vec<f64>>,
    /// This operator with its spectrum and transforms in single precision
    /// (`convolve_single`), made on the first call.
    single: Option<Box<FftOperator<f32>>>,
}

/// A free grid's spectral preconditioner: dx / K(q), the inverse of a body's continuum
/// kernel K(q) (m/Pa at G = 1; the half-space's 1 / (2 |q|), a layer's compliance), applied
/// as a circular convolution on the grid padded to fast FFT lengths (the residual zero
/// beyond it; its mean mode at the longest wave's value), in single precision, less what
/// the convolution passes across the period between elements at most `WRAP_RADIUS` apart
/// through it (`unwrap`).
pub(crate) struct SpectralInverse {
    fft: FftOperator<f32>,
    /// What `unwrap` takes back; None where no pair of elements is that near through the
    /// period (or a side is shorter than 2 WRAP_RADIUS + 2 elements).
    wrap: Option<Wrap>,
}

/// The pairs of a free grid's elements that the spectral preconditioner's convolution joins
/// through its period, made once per grid (`SpectralInverse::unwrap`).
struct Wrap {
    /// The convolution's kernel at offsets 0..=WRAP_RADIUS along x and y (row-major).
    near: Vec<f64>,
    /// The partners along x and along y.
    xs: Partners,
    ys: Partners,
}

/// Elements (along each axis) within which the spectral preconditioner's convolution,
/// periodic on a padded grid that is often the grid itself, is kept from reaching across the
/// period: otherwise a residual on one edge of a free grid acts on the opposite edge as on
/// its neighbours, which the free grid's operator does not do. On `benchmarks/
/// bench_rough.py`'s free maps (tol 1e-8) it cut the finest level's iterations of the main
/// case (Hurst 0.8, 5 % contact) from 23, 24, 29, 31 to 18, 20, 23, 25 at 512^2 to 4096^2,
/// and the nine 512^2 cases' level iterations weighted by size by 21 %. In a fixed-set
/// harness (conjugate gradients on the 512^2 cases' final contact sets) 2 elements did
/// nearly as well as 4 (a 20 % case: 23 iterations against 22), and padding the grid by 8
/// or 28 elements instead did as well but lengthened the FFTs (540 for 512: 1.47x the
/// time of a pair); the exact inverse of the padded operator (FFTs twice as long) did at
/// most one iteration better. The inverse kernel decays like 1/r^3, so the nearest pairs
/// are what count.
pub const WRAP_RADIUS: usize = 4;

impl SpectralInverse {
    /// The half-space's preconditioner 2 |q| dx of an `nx` x `ny` grid of elements of side
    /// `dx` (m).
    fn new(nx: usize, ny: usize, dx: f64, plans: &mut FftPlans) -> Self {
        Self::of_kernel(nx, ny, dx, plans, |q| 0.5 / q)
    }

    /// The preconditioner dx / K(|q|) of an `nx` x `ny` grid of elements of side `dx` (m)
    /// for the continuum kernel `kernel` of the wavenumber |q| (1/m).
    pub(crate) fn of_kernel(
        nx: usize,
        ny: usize,
        dx: f64,
        plans: &mut FftPlans,
        kernel: impl Fn(f64) -> f64 + Sync,
    ) -> Self {
        let period = (fast_size(nx), fast_size(ny));
        let (qx, qy) = (squared_waves(period.0, dx), squared_waves(period.1, dx));
        let longest = qx[1 % period.0].min(qy[1 % period.1]).sqrt();
        let mut fft = FftOperator::with_symbol(
            nx,
            ny,
            dx,
            period,
            |kx, ky| {
                let q = (qx[kx] + qy[ky]).sqrt();
                dx / kernel(if q > 0.0 { q } else { longest })
            },
            plans,
        );
        let w = WRAP_RADIUS;
        let wraps = period.0 < nx + w || period.1 < ny + w;
        let wrap = (wraps && nx.min(ny) >= 2 * w + 2).then(|| {
            let mut delta = vec![0.0; nx * ny];
            delta[0] = 1.0;
            let mut response = vec![0.0; nx * ny];
            fft.convolve(&delta, &mut response);
            Wrap {
                near: (0..=w)
                    .flat_map(|b| response[b * nx..b * nx + w + 1].to_vec())
                    .collect(),
                xs: Partners::new(nx, period.0),
                ys: Partners::new(ny, period.1),
            }
        });
        SpectralInverse { fft, wrap }
    }

    /// z = dx K^-1 g.
    pub(crate) fn apply(&mut self, g: &[f64], z: &mut [f64]) {
        self.fft.convolve(g, z);
        self.unwrap(g, z);
    }

    /// Takes back from `z` what the periodic convolution of `g` passed between pairs of
    /// elements that lie within `WRAP_RADIUS` of each other (along both axes) only through
    /// the period, across opposite edges or corners; only elements within that radius of an
    /// edge have such pairs.
    fn unwrap(&self, g: &[f64], z: &mut [f64]) {
        let Some(Wrap { near, xs, ys }) = &self.wrap else {
            return;
        };
        let (nx, ny, w) = (self.fft.nx, self.fft.ny, WRAP_RADIUS);
        let row_of = |iy: usize, sy: isize| &g[iy.wrapping_add_signed(sy) * nx..][..nx];
        z.par_chunks_mut(nx)
            .enumerate()
            .with_min_len(ny.div_ceil(2))
            .for_each(|(iy, row)| {
                let (direct_y, wrapped_y) = ys.of(iy);
                // pairs wrapped along y alone: whole rows, shifted along x
                for &(b, sy) in wrapped_y {
                    let src = row_of(iy, sy);
                    for &(a, sx) in xs.inside() {
                        let c = near[b * (w + 1) + a];
                        let (lo, hi) = if sx < 0 {
                            (sx.unsigned_abs(), nx)
                        } else {
                            (0, nx - sx as usize)
                        };
                        for (v, &s) in row[lo..hi]
                            .iter_mut()
                            .zip(&src[lo.wrapping_add_signed(sx)..])
                        {
                            *v -= c * s;
                        }
                    }
                }
                // pairs wrapped along x (and along y or not): the columns at the ends
                for ix in (0..w).chain(nx - w..nx) {
                    let wrapped_x = xs.of(ix).1;
                    let mut taken = 0.0;
                    for &(b, sy) in direct_y.iter().chain(wrapped_y) {
                        let (c, src) = (&near[b * (w + 1)..], row_of(iy, sy));
                        for &(a, sx) in wrapped_x {
                            taken += c[a] * src[ix.wrapping_add_signed(sx)];
                        }
                    }
                    row[ix] -= taken;
                }
            });
    }
}

/// The partners of the elements of one axis of a free grid in the spectral preconditioner's
/// convolution (`SpectralInverse::unwrap`): for an element i, the pairs (|offset|, shift)
/// of the elements i + shift within `WRAP_RADIUS` of it reached directly, and of those
/// reached through the period.
struct Partners {
    n: usize,
    /// Per element within `WRAP_RADIUS` of either end (the first ones, then the last
    /// ones): direct and wrapped partners.
    ends: Vec<(Vec<Partner>, Vec<Partner>)>,
    /// The direct partners of every other element.
    inside: Vec<Partner>,
}

/// An (|offset|, shift) pair of `Partners`.
type Partner = (usize, isize);

impl Partners {
    /// The partners along an axis of `n` elements (at least 2 `WRAP_RADIUS` + 2) whose
    /// convolution has the period `p` (>= n).
    fn new(n: usize, p: usize) -> Self {
        let w = WRAP_RADIUS as isize;
        let (n, p) = (n as isize, p as isize);
        let ends = (0..w)
            .chain(n - w..n)
            .map(|i| {
                let (mut direct, mut wrapped) = (vec![], vec![]);
                for d in -w..=w {
                    let k = i - d;
                    let (j, list) = match k {
                        k if k < 0 => (k + p, &mut wrapped),
                        k if k >= p => (k - p, &mut wrapped),
                        k => (k, &mut direct),
                    };
                    if (0..n).contains(&j) {
                        list.push((d.unsigned_abs(), j - i));
                    }
                }
                (direct, wrapped)
            })
            .collect();
        let inside = (-w..=w).map(|d| (d.unsigned_abs(), -d)).collect();
        Partners {
            n: n as usize,
            ends,
            inside,
        }
    }

    /// The direct partners of an element farther than `WRAP_RADIUS` from both ends.
    fn inside(&self) -> &[Partner] {
        &self.inside
    }

    /// The direct and wrapped partners of element `i`.
    fn of(&self, i: usize) -> (&[Partner], &[Partner]) {
        let (w, n) = (WRAP_RADIUS, self.n);
        let slot = if i < w {
            Some(i)
        } else if i + w >= n {
            Some(i + 2 * w - n)
        } else {
            None
        };
        match slot {
            Some(k) => (&self.ends[k].0, &self.ends[k].1),
            None => (&self.inside, &[]),
        }
    }
}

/// Memory (bytes) an FFT operator of an `nx` x `ny` grid holds while it solves: its kernel
/// spectrum and column buffer (12 per padded element) and their single-precision copy
/// (`FftOperator::single`, 6), its kernel in real space (8 per element) and, on grids of at
/// least `SPECTRAL_MIN_ELEMENTS`, the spectral preconditioner (6 per element of its grid).
pub fn held_bytes(nx: usize, ny: usize) -> f64 {
    let padded = (padded_size(nx) * padded_size(ny)) as f64;
    18.0 * padded + 8.0 * (nx * ny) as f64 + inverse_bytes(nx, ny)
}

/// Memory (bytes) of the spectral preconditioner of an `nx` x `ny` FFT operator, part of
/// `held_bytes`: 6 per element of its grid (its single-precision spectrum and column
/// buffer over the half spectrum) on grids of at least `SPECTRAL_MIN_ELEMENTS` (made by
/// the first `precondition`), none on smaller ones.
pub fn inverse_bytes(nx: usize, ny: usize) -> f64 {
    if nx * ny >= SPECTRAL_MIN_ELEMENTS {
        6.0 * (fast_size(nx) * fast_size(ny)) as f64
    } else {
        0.0
    }
}

/// Smallest free grid (elements) preconditioned by the spectral inverse (`SpectralInverse`,
/// an FFT pair on the grid per iteration) instead of the inverse-kernel stencil.
pub const SPECTRAL_MIN_ELEMENTS: usize = 128 * 128;

/// Memory of an FFT operator per element of its padded grid (bytes): the kernel's spectrum
/// and the column buffer (12), the kernel table on the way (8 per element of the grid, at
/// most 4 per padded element on grids of more than a few elements).
const BYTES_PER_PADDED_ELEMENT: f64 = 16.0;

/// The squared wavenumbers (1/m^2) of the DFT indices 0..m of a period of `m` elements of
/// side `dx` (m), indices above m/2 standing for the negative wavevectors k - m: per-axis
/// tables whose sums give |q|^2 on the grid of wavevectors.
pub(crate) fn squared_waves(m: usize, dx: f64) -> Vec<f64> {
    (0..m)
        .map(|k| {
            let k = if k <= m / 2 { k } else { m - k };
            let q = 2.0 * std::f64::consts::PI * k as f64 / (m as f64 * dx);
            q * q
        })
        .collect()
}

impl FftOperator {
    /// Builds the operator for an `nx` x `ny` grid of square elements of side `dx` (m).
    pub fn new(nx: usize, ny: usize, dx: f64) -> Result<Self> {
        check_positive("element size dx", dx)?;
        check_elements(nx, ny, MAX_FFT_ELEMENTS, "FFT operator")?;
        let padded = (padded_size(nx) * padded_size(ny)) as f64;
        crate::support::memory::check(
            &format!("a {nx} x {ny} surface operator"),
            BYTES_PER_PADDED_ELEMENT * padded,
        )?;
        Self::with_kernel(
            nx,
            ny,
            &KernelTable::new(nx, ny, dx),
            &mut FftPlans::default(),
        )
    }

    /// Builds the operator for an `nx` x `ny` grid from a kernel table that covers it (its
    /// element size) and a plan cache: the windows of a grid share the grid's table, and
    /// FFT lengths planned once are not planned again.
    pub fn with_kernel(
        nx: usize,
        ny: usize,
        table: &KernelTable,
        plans: &mut FftPlans,
    ) -> Result<Self> {
        if nx == 0 || ny == 0 {
            return Err(Error::InvalidInput(format!(
                "grid size must be at least 1 x 1, got {nx} x {ny}"
            )));
        }
        if !table.covers(nx, ny) {
            return Err(Error::InvalidInput(format!(
                "the kernel table does not cover a {nx} x {ny} grid"
            )));
        }
        let mut op = Self::unfilled(
            nx,
            ny,
            table.dx(),
            (padded_size(nx), padded_size(ny)),
            plans,
        );
        op.covered = table.extent();
        op.kernel_spectrum(table);
        Ok(op)
    }

    /// Writes the spectrum of the circulant kernel of period (mx, my): the coefficient at
    /// offset min(i, m - i) in each direction, wherever the table holds it. Offsets from n
    /// to m - n never meet in a linear convolution over n elements, so it serves every grid
    /// of the same padded sizes (see `resize`).
    ///
    /// The kernel is real and even in x and y, so its spectrum is too: rows iy and my - iy
    /// are equal (only rows 0..=my/2 are made and transformed, in the workers), each row's
    /// spectrum is real, and each column of those is real and even, so two columns pack into
    /// one complex FFT (the first's spectrum its real part, the second's its imaginary part).
    fn kernel_spectrum(&mut self, table: &KernelTable) {
        let (mx, my, half) = (self.mx, self.my, self.half);
        let (rows, pairs) = (my / 2 + 1, half.div_ceil(2));
        let (tx, ty) = table.extent();
        let nw = self.workers.len();
        let r2c = &self.r2c;
        let chunk = rows.div_ceil(nw).max(1);
        let cols = ColumnWriter(self.cols.as_mut_ptr());
        self.workers.par_iter_mut().enumerate().for_each(|(c, w)| {
            let (lo, hi) = (c * chunk, ((c + 1) * chunk).min(rows));
            for b in (lo..hi).step_by(TILE) {
                let end = (b + TILE).min(hi);
                for iy in b..end {
                    for ix in 0..=mx / 2 {
                        w.real[ix] = if ix < tx && iy < ty {
                            table.get(ix, iy)
                        } else {
                            0.0
                        };
                    }
                    for ix in mx / 2 + 1..mx {
                        w.real[ix] = w.real[mx - ix];
                    }
                    let spec = &mut w.halves[(iy - b) * half..(iy - b + 1) * half];
                    r2c.process_with_scratch(&mut w.real, spec, &mut w.r2c_scratch)
                        .expect("buffer sizes are fixed at construction");
                }
                for p in 0..pairs {
                    for iy in b..end {
                        let spec = &w.halves[(iy - b) * half..(iy - b + 1) * half];
                        let second = if 2 * p + 1 < half {
                            spec[2 * p + 1].re
                        } else {
                            0.0
                        };
                        // SAFETY: rows lo..hi belong to this worker alone, so element
                        // (p, iy) of `cols` is written by one thread; p < pairs <= half and
                        // iy < rows <= my keep it inside the buffer (half * my).
                        unsafe { cols.write(p * my + iy, Complex::new(spec[2 * p].re, second)) };
                    }
                }
            }
        });
        let norm = 1.0 / (mx * my) as f64;
        let col_fwd = &self.col_fwd;
        let chunk = pairs.div_ceil(nw).max(1);
        self.cols[..pairs * my]
            .par_chunks_mut(chunk * my)
            .zip(self.spectrum.par_chunks_mut(2 * chunk * my))
            .zip(self.workers.par_iter_mut())
            .for_each(|((cols, spectrum), w)| {
                for (col, out) in cols.chunks_mut(my).zip(spectrum.chunks_mut(2 * my)) {
                    for iy in rows..my {
                        col[iy] = col[my - iy];
                    }
                    col_fwd.process_with_scratch(col, &mut w.col_scratch);
                    let (first, second) = out.split_at_mut(my);
                    first
                        .iter_mut()
                        .zip(&*col)
                        .for_each(|(s, v)| *s = v.re * norm);
                    second
                        .iter_mut()
                        .zip(&*col)
                        .for_each(|(s, v)| *s = v.im * norm);
                }
            });
    }
}

impl FftOperator {
    /// The circular convolutions of period `mx` x `my` on an `nx` x `ny` grid with the real,
    /// even spectra `symbols(kx, ky)` = (operator's, preconditioner's) (as `with_symbol`),
    /// the operator in double and the preconditioner in single precision: one parallel
    /// evaluation of the symbols per wavevector writes both.
    pub(crate) fn with_symbol_pair(
        nx: usize,
        ny: usize,
        dx: f64,
        (mx, my): (usize, usize),
        symbols: impl Fn(usize, usize) -> (f64, f64) + Sync,
        plans: &mut FftPlans,
    ) -> (Self, FftOperator<f32>) {
        let mut op = Self::unfilled(nx, ny, dx, (mx, my), plans);
        let mut inverse = FftOperator::<f32>::unfilled(nx, ny, dx, (mx, my), plans);
        let norm = 1.0 / (mx * my) as f64;
        op.spectrum
            .par_chunks_mut(my)
            .zip(inverse.spectrum.par_chunks_mut(my))
            .enumerate()
            .for_each(|(kx, (s, t))| {
                for (ky, (s, t)) in s.iter_mut().zip(t.iter_mut()).enumerate() {
                    let (a, b) = symbols(kx, ky);
                    *s = a * norm;
                    *t = f32::of(b * norm);
                }
            });
        (op, inverse)
    }
}

impl<T: Real> FftOperator<T> {
    /// The circular convolution of period `mx` x `my` (>= nx, ny) on an `nx` x `ny` grid
    /// whose kernel has the real, even spectrum `symbol(kx, ky)` (m/Pa at G = 1; kx in
    /// 0..=mx/2, ky in 0..my, unnormalised DFT indices). With (mx, my) = (nx, ny) it is the
    /// operator of a periodic cell.
    pub(crate) fn with_symbol(
        nx: usize,
        ny: usize,
        dx: f64,
        (mx, my): (usize, usize),
        symbol: impl Fn(usize, usize) -> f64 + Sync,
        plans: &mut FftPlans,
    ) -> Self {
        let mut op = Self::unfilled(nx, ny, dx, (mx, my), plans);
        let norm = 1.0 / (mx * my) as f64;
        op.spectrum
            .par_chunks_mut(my)
            .enumerate()
            .for_each(|(kx, s)| {
                s.iter_mut()
                    .enumerate()
                    .for_each(|(ky, s)| *s = T::of(symbol(kx, ky) * norm));
            });
        op
    }

    /// Writes into `u` the convolution of `p` with the operator's kernel (both nx * ny
    /// long), the transforms in `T`.
    pub(crate) fn convolve(&mut self, p: &[f64], u: &mut [f64]) {
        self.convolve_into(p, u, false);
    }

    /// Adds to `u` the convolution of `q` with the operator's kernel (both nx * ny long),
    /// the transforms in `T`.
    pub(crate) fn add_convolved(&mut self, q: &[f64], u: &mut [f64]) {
        self.convolve_into(q, u, true);
    }

    /// The convolution of `p` written into `u`, or added to it with `add`.
    fn convolve_into(&mut self, p: &[f64], u: &mut [f64], add: bool) {
        assert_eq!(p.len(), self.nx * self.ny, "pressure length");
        assert_eq!(u.len(), self.nx * self.ny, "deflection length");
        self.rows_forward(p, self.nx, self.ny);
        self.columns(Columns::Convolve { nrows: self.ny });
        self.rows_inverse(u, add);
    }

    /// Plans, buffers and a zero spectrum for an `nx` x `ny` grid in the period `mx` x `my`.
    fn unfilled(
        nx: usize,
        ny: usize,
        dx: f64,
        (mx, my): (usize, usize),
        plans: &mut FftPlans,
    ) -> Self {
        let half = mx / 2 + 1;
        let (real, complex) = T::planners(plans);
        let r2c = real.plan_fft_forward(mx);
        let c2r = real.plan_fft_inverse(mx);
        let col_fwd = complex.plan_fft_forward(my);
        let col_inv = complex.plan_fft_inverse(my);
        let nworkers = rayon::current_num_threads().max(1) * 2;
        let workers = (0..nworkers)
            .map(|_| Worker {
                real: vec![T::default(); mx],
                halves: vec![Complex::default(); TILE * half],
                r2c_scratch: r2c.make_scratch_vec(),
                c2r_scratch: c2r.make_scratch_vec(),
                col_scratch: vec![Complex::default(); col_fwd.get_inplace_scratch_len()],
            })
            .collect();
        FftOperator {
            nx,
            ny,
            dx,
            mx,
            my,
            half,
            r2c,
            c2r,
            col_fwd,
            col_inv,
            spectrum: vec![T::default(); half * my],
            covered: (nx, ny),
            cols: huge_zeroed(half * my),
            workers,
            inverse: None,
            kernel: None,
            single: None,
        }
    }

    /// Padded FFT sizes (x, y).
    pub fn padded(&self) -> (usize, usize) {
        (self.mx, self.my)
    }

    /// Makes this the operator of an `nx` x `ny` grid with the same padded sizes (its
    /// kernel table must have covered that grid), keeping spectrum, plans and buffers.
    pub fn resize(&mut self, nx: usize, ny: usize) -> Result<()> {
        if (padded_size(nx), padded_size(ny)) != (self.mx, self.my)
            || nx > self.covered.0
            || ny > self.covered.1
        {
            return Err(Error::InvalidInput(format!(
                "a {nx} x {ny} grid does not pad to {} x {} or exceeds the kernel table ({:?})",
                self.mx, self.my, self.covered
            )));
        }
        if (self.nx, self.ny) != (nx, ny) {
            self.inverse = None;
            self.kernel = None;
        }
        if let Some(single) = self.single.as_mut() {
            single.resize(nx, ny)?;
        }
        self.nx = nx;
        self.ny = ny;
        Ok(())
    }

    /// Row R2C of `nrows` rows of `src` (row stride `stride`), written transposed into
    /// `cols` TILE rows at a time (rows nrows.. of `cols` are left as they were).
    fn rows_forward(&mut self, src: &[f64], stride: usize, nrows: usize) {
        let (half, my, ncols_in) = (self.half, self.my, stride.min(self.mx));
        let nw = self.workers.len();
        let r2c = &self.r2c;
        let chunk = nrows.div_ceil(nw).max(1);
        let cols = ColumnWriter(self.cols.as_mut_ptr());
        self.workers.par_iter_mut().enumerate().for_each(|(c, w)| {
            let (lo, hi) = (c * chunk, ((c + 1) * chunk).min(nrows));
            for b in (lo..hi).step_by(TILE) {
                let end = (b + TILE).min(hi);
                for iy in b..end {
                    let spec = &mut w.halves[(iy - b) * half..(iy - b + 1) * half];
                    w.real[..ncols_in]
                        .iter_mut()
                        .zip(&src[iy * stride..iy * stride + ncols_in])
                        .for_each(|(r, &s)| *r = T::of(s));
                    w.real[ncols_in..].fill(T::default());
                    r2c.process_with_scratch(&mut w.real, spec, &mut w.r2c_scratch)
                        .expect("buffer sizes are fixed at construction");
                }
                for kx in 0..half {
                    for iy in b..end {
                        // SAFETY: rows lo..hi belong to this worker alone, so element
                        // (kx, iy) of `cols` is written by one thread; kx < half and
                        // iy < nrows <= my keep it inside the buffer (half * my).
                        unsafe { cols.write(kx * my + iy, w.halves[(iy - b) * half + kx]) };
                    }
                }
            }
        });
    }

    /// The column pass over `cols`, in parallel over blocks of columns: each column is
    /// transformed while it is in cache (for a convolution: forward, times the kernel
    /// spectrum, inverse).
    fn columns(&mut self, pass: Columns) {
        let (half, my) = (self.half, self.my);
        let nw = self.workers.len();
        let (col_fwd, col_inv, spectrum) = (&self.col_fwd, &self.col_inv, &self.spectrum);
        let chunk = half.div_ceil(nw).max(1);
        self.cols
            .par_chunks_mut(chunk * my)
            .zip(self.workers.par_iter_mut())
            .enumerate()
            .for_each(|(c, (out, w))| {
                for (k, col) in out.chunks_mut(my).enumerate() {
                    if let Columns::Convolve { nrows } = pass {
                        col[nrows..].fill(Complex::default());
                        col_fwd.process_with_scratch(col, &mut w.col_scratch);
                        let kx = c * chunk + k;
                        let s = &spectrum[kx * my..(kx + 1) * my];
                        col.iter_mut().zip(s).for_each(|(v, &s)| *v = v.scale(s));
                    }
                    col_inv.process_with_scratch(col, &mut w.col_scratch);
                }
            });
    }
}

/// A buffer of `n` default values, asked to live on transparent huge pages (2 MB) where the
/// system offers them on request (Linux with THP "madvise", the common default): the row
/// passes write and read the column buffer transposed, one short run per 4 KB page, and
/// huge pages spare them the TLB misses (7-10 % of a 2048^2 apply). The advice is given
/// before the first touch; elsewhere, or where refused, it is an ordinary buffer.
fn huge_zeroed<T: Clone + Default>(n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    #[cfg(target_os = "linux")]
    {
        const PAGE: usize = 4096;
        let start = v.as_mut_ptr() as usize;
        let end = start + n * std::mem::size_of::<T>();
        let first = start.next_multiple_of(PAGE);
        if end > first + PAGE {
            // SAFETY: madvise only advises on pages of this fresh, unused allocation
            // (page-aligned, inside it); it neither reads nor frees them, and a refusal
            // leaves them as they were.
            unsafe {
                libc::madvise(
                    first as *mut libc::c_void,
                    (end - first) / PAGE * PAGE,
                    libc::MADV_HUGEPAGE,
                );
            }
        }
    }
    v.resize(n, T::default());
    v
}

/// What `FftOperator::columns` does to each column (`nrows`: the rows the row pass wrote;
/// the rest are zeroed first).
#[derive(Clone, Copy)]
enum Columns {
    /// Forward FFT, multiplication by the kernel spectrum, inverse FFT.
    Convolve { nrows: usize },
    /// Inverse FFT.
    Inverse,
}

/// Raw access to the column buffer for the transposed writes of `FftOperator::rows_forward`,
/// where each worker writes the rows it transformed and no element twice.
struct ColumnWriter<T>(*mut Complex<T>);

// SAFETY: only used for writes to disjoint elements from the workers of one parallel loop,
// while the buffer it points into is exclusively borrowed by `rows_forward`.
unsafe impl<T> Send for ColumnWriter<T> {}
unsafe impl<T> Sync for ColumnWriter<T> {}

impl<T> Clone for ColumnWriter<T> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<T> Copy for ColumnWriter<T> {}

impl<T> ColumnWriter<T> {
    /// Writes `v` at element `i`.
    ///
    /// # Safety
    /// `i` must lie inside the buffer and no other thread may access element `i` meanwhile.
    unsafe fn write(self, i: usize, v: Complex<T>) {
        unsafe { *self.0.add(i) = v };
    }
}

impl<T: Real> FftOperator<T> {
    /// Row C2R of the first ny rows of `cols` (after the column pass), writing their first
    /// nx columns into `u`, or adding them to it with `add`.
    fn rows_inverse(&mut self, u: &mut [f64], add: bool) {
        let (nx, ny, half, my, mx) = (self.nx, self.ny, self.half, self.my, self.mx);
        let nw = self.workers.len();
        let cols = &self.cols;
        let c2r = &self.c2r;
        let chunk = ny.div_ceil(nw).max(1);
        u.par_chunks_mut(chunk * nx)
            .zip(self.workers.par_iter_mut())
            .enumerate()
            .for_each(|(c, (out, w))| {
                // Gather TILE rows at a time: each column segment is read contiguously.
                let nrow = out.len() / nx;
                for b in (0..nrow).step_by(TILE) {
                    let end = (b + TILE).min(nrow);
                    let iy0 = c * chunk + b;
                    for kx in 0..half {
                        let seg = &cols[kx * my + iy0..kx * my + iy0 + (end - b)];
                        for (r, v) in seg.iter().enumerate() {
                            w.halves[r * half + kx] = *v;
                        }
                    }
                    for r in 0..end - b {
                        let spec = &mut w.halves[r * half..(r + 1) * half];
                        spec[0].im = T::default();
                        if mx % 2 == 0 {
                            spec[half - 1].im = T::default();
                        }
                        c2r.process_with_scratch(spec, &mut w.real, &mut w.c2r_scratch)
                            .expect("buffer sizes are fixed at construction");
                        let row = out[(b + r) * nx..(b + r + 1) * nx].iter_mut();
                        if add {
                            row.zip(&w.real[..nx]).for_each(|(o, &v)| *o += v.to_f64());
                        } else {
                            row.zip(&w.real[..nx]).for_each(|(o, &v)| *o = v.to_f64());
                        }
                    }
                }
            });
    }
}

impl FftOperator {
    /// This operator with its spectrum and transforms in single precision (an error of
    /// about 1e-7 of the largest deflection, in half the memory traffic and twice the SIMD
    /// lanes), made on the first call.
    fn single(&mut self) -> &mut FftOperator<f32> {
        let (nx, ny, dx, period, covered) =
            (self.nx, self.ny, self.dx, (self.mx, self.my), self.covered);
        let spectrum = &self.spectrum;
        self.single.get_or_insert_with(|| {
            let mut single =
                FftOperator::<f32>::unfilled(nx, ny, dx, period, &mut FftPlans::default());
            single
                .spectrum
                .iter_mut()
                .zip(spectrum)
                .for_each(|(s, &v)| *s = f32::of(v));
            single.covered = covered;
            Box::new(single)
        })
    }

    /// Writes into `u` the convolution of `p` with the operator's kernel as `convolve`
    /// does, in single precision (`single`).
    pub(crate) fn convolve_single(&mut self, p: &[f64], u: &mut [f64]) {
        self.single().convolve(p, u);
    }

    /// Adds to `u` the convolution of `q` with the operator's kernel, in single precision
    /// (`single`).
    pub(crate) fn add_convolved_single(&mut self, q: &[f64], u: &mut [f64]) {
        self.single().add_convolved(q, u);
    }

    /// Coefficients (Pa/m at G = 1) of the inverse of this operator's circulant embedding
    /// for offsets 0..=radius in x and y (row-major, (radius + 1)^2, even in each offset):
    /// p = sum of them times u over the neighbourhood. Away from the grid's edges they are
    /// those of the inverse of the infinite-lattice operator (to ~5 digits from 33 x 33 on,
    /// for odd grids, whose padded size 2n - 2 leaves no zero gap in the kernel).
    pub fn inverse_kernel(&mut self, radius: usize) -> Result<Vec<f64>> {
        let (nx, ny) = (self.nx, self.ny);
        if radius >= nx.min(ny) {
            return Err(Error::InvalidInput(format!(
                "inverse-kernel radius {radius} must be below the grid size {nx} x {ny}"
            )));
        }
        // The transform of a unit pressure at the origin is 1: the inverse's spectrum is the
        // reciprocal of the kernel's (spectrum holds it divided by mx my; the C2R and column
        // inverses are unnormalised).
        let norm = (self.mx * self.my) as f64;
        for (c, &s) in self.cols.iter_mut().zip(&self.spectrum) {
            *c = Complex::new(1.0 / (s * norm * norm), 0.0);
        }
        let mut u = vec![0.0; nx * ny];
        self.columns(Columns::Inverse);
        self.rows_inverse(&mut u, false);
        let w = radius + 1;
        Ok((0..w * w).map(|i| u[(i / w) * nx + i % w]).collect())
    }

    /// The kernel k(|ix|, |iy|) in real space (m/Pa at G = 1) at offsets 0..nx, 0..ny,
    /// row-major: the deflection of a unit pressure at the origin, the inverse transform of
    /// the spectrum, made once per grid. The spectrum is real and even, so is the
    /// circulant kernel: offsets -i and i share a value, and on a periodic cell (period =
    /// grid) offset i is offset i - n.
    pub(crate) fn kernel(&mut self) -> &[f64] {
        if self.kernel.is_none() {
            for (c, &s) in self.cols.iter_mut().zip(&self.spectrum) {
                *c = Complex::new(s, 0.0);
            }
            self.columns(Columns::Inverse);
            let mut k = vec![0.0; self.nx * self.ny];
            self.rows_inverse(&mut k, false);
            self.kernel = Some(k);
        }
        self.kernel.as_deref().unwrap_or_default()
    }
}

/// Adds to `u` (an `nx`-wide row-major grid) the deflections of the pressures `values` on
/// the elements `idx` under the even kernel `kernel` (`FftOperator::kernel`): u_i +=
/// sum_j values_j k(|ix - jx|, |iy - jy|), rows in parallel, each element's terms added in
/// the order of `idx`.
fn add_point_loads_with(kernel: &[f64], nx: usize, idx: &[usize], values: &[f64], u: &mut [f64]) {
    u.par_chunks_mut(nx).enumerate().for_each(|(iy, row)| {
        for (&j, &v) in idx.iter().zip(values) {
            let (jx, jy) = (j % nx, j / nx);
            let k = &kernel[iy.abs_diff(jy) * nx..(iy.abs_diff(jy) + 1) * nx];
            // ix >= jx at offsets 0..nx - jx; ix < jx at offsets jx - ix, jx..1
            row[jx..]
                .iter_mut()
                .zip(&k[..nx - jx])
                .for_each(|(u, &k)| *u += v * k);
            row[..jx]
                .iter_mut()
                .zip(k[1..=jx].iter().rev())
                .for_each(|(u, &k)| *u += v * k);
        }
    });
}

impl SurfaceOperator for FftOperator {
    fn nx(&self) -> usize {
        self.nx
    }
    fn ny(&self) -> usize {
        self.ny
    }
    fn dx(&self) -> f64 {
        self.dx
    }

    fn apply(&mut self, p: &[f64], u: &mut [f64]) {
        self.convolve(p, u);
    }

    fn apply_single(&mut self, p: &[f64], u: &mut [f64]) {
        self.convolve_single(p, u);
    }

    fn add_single(&mut self, q: &[f64], u: &mut [f64]) -> bool {
        self.add_convolved_single(q, u);
        true
    }

    /// Love's coefficients among `idx` (`DenseOperator::subset_matrix`); for an operator
    /// built by `with_symbol`, the caller's type supplies its own.
    fn submatrix(&mut self, idx: &[usize]) -> Result<Mat<f64>> {
        DenseOperator::subset_matrix(self.nx, self.dx, idx)
    }

    /// The spectral inverse (`SpectralInverse`) on grids of at least
    /// `SPECTRAL_MIN_ELEMENTS`, else the inverse-kernel stencil.
    fn precondition(&mut self, g: &[f64], z: &mut [f64]) {
        let (nx, ny) = (self.nx, self.ny);
        if nx * ny < SPECTRAL_MIN_ELEMENTS {
            precondition::apply(nx, ny, g, z);
            return;
        }
        let dx = self.dx;
        self.inverse
            .get_or_insert_with(|| {
                Box::new(SpectralInverse::new(nx, ny, dx, &mut FftPlans::default()))
            })
            .apply(g, z);
    }

    /// Direct summation of the kernel in real space (`FftOperator::kernel`, made on the
    /// first call).
    fn add_point_loads(&mut self, idx: &[usize], values: &[f64], u: &mut [f64]) -> bool {
        let nx = self.nx;
        add_point_loads_with(self.kernel(), nx, idx, values, u);
        true
    }

    /// An apply transforms ny rows of mx forward and back and mx / 2 + 1 columns of my
    /// forward and back, about 2 ny mx log2(mx) + 2 (mx / 2 + 1) my log2(my) operations; a
    /// point load one per element of the grid. The break-even count is about that ratio
    /// (measured 83 and 108 on free 1024^2 and 2048^2 grids, 35 and 37 on cells, CPU time,
    /// 2 cores); the limit takes `POINT_LOAD_SHARE` of it.
    fn point_load_limit(&self) -> usize {
        let (mx, my) = (self.mx as f64, self.my as f64);
        let apply = 2.0 * self.ny as f64 * mx * mx.log2() + 2.0 * (mx / 2.0 + 1.0) * my * my.log2();
        (POINT_LOAD_SHARE * apply / (self.nx * self.ny) as f64) as usize
    }
}

/// The share of the break-even number of point loads (`point_load_limit`) below which they
/// are summed directly: at the limit they cost half an apply.
const POINT_LOAD_SHARE: f64 = 0.5;

/// Dense influence matrix between chosen elements of a grid (faer), for small grids, for
/// direct solves on a contact set and for cross-checking the FFT operator.
pub struct DenseOperator {
    nx: usize,
    ny: usize,
    dx: f64,
    matrix: Mat<f64>,
}

impl DenseOperator {
    /// Full matrix of an `nx` x `ny` grid (size (nx ny)^2: small grids only).
    pub fn new(nx: usize, ny: usize, dx: f64) -> Result<Self> {
        check_elements(nx, ny, MAX_DENSE_ELEMENTS, "dense operator")?;
        let all: Vec<usize> = (0..nx * ny).collect();
        let matrix = Self::subset_matrix(nx, dx, &all)?;
        Ok(DenseOperator { nx, ny, dx, matrix })
    }

    /// Influence matrix (m/Pa at G = 1) among the elements `idx` of a grid `nx` wide.
    pub fn subset_matrix(nx: usize, dx: f64, idx: &[usize]) -> Result<Mat<f64>> {
        check_positive("element size dx", dx)?;
        if nx == 0 {
            return Err(Error::InvalidInput("grid width nx must be >= 1".into()));
        }
        let pos: Vec<(usize, usize)> = idx.iter().map(|&i| (i % nx, i / nx)).collect();
        let span = |f: fn(&(usize, usize)) -> usize| {
            let lo = pos.iter().map(f).min().unwrap_or(0);
            pos.iter().map(f).max().unwrap_or(0) - lo + 1
        };
        // The kernel depends on the offset only: tabulate it once over the set's extent.
        let (kx, ky) = (span(|p| p.0), span(|p| p.1));
        let table = influence::quarter_kernel(kx, ky, dx);
        Ok(Mat::from_fn(idx.len(), idx.len(), |i, j| {
            let (a, b) = (pos[i], pos[j]);
            table[a.1.abs_diff(b.1) * kx + a.0.abs_diff(b.0)]
        }))
    }
}

impl SurfaceOperator for DenseOperator {
    fn nx(&self) -> usize {
        self.nx
    }
    fn ny(&self) -> usize {
        self.ny
    }
    fn dx(&self) -> f64 {
        self.dx
    }
    fn apply(&mut self, p: &[f64], u: &mut [f64]) {
        faer::linalg::matmul::matmul(
            ColMut::from_slice_mut(u).as_mat_mut(),
            Accum::Replace,
            self.matrix.as_ref(),
            ColRef::from_slice(p).as_mat(),
            1.0,
            Par::rayon(0),
        );
    }
    fn submatrix(&mut self, idx: &[usize]) -> Result<Mat<f64>> {
        Ok(Mat::from_fn(idx.len(), idx.len(), |i, j| {
            self.matrix[(idx[i], idx[j])]
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pseudo_random(n: usize, seed: u64) -> Vec<f64> {
        let mut s = seed;
        (0..n)
            .map(|_| {
                s = s
                    .wrapping_mul(6364136223846793005)
                    .wrapping_add(1442695040888963407);
                (s >> 11) as f64 / (1u64 << 53) as f64
            })
            .collect()
    }

    /// The kernel spectrum made from the distinct rows and packed column pairs equals the
    /// plain two-dimensional complex DFT of the whole padded kernel (real part, normalised),
    /// on grids with odd and even half-spectrum widths, tables larger than the grid and a
    /// single column. Both FFTs err by at most about log2(mx my) eps times the sum of the
    /// kernel's magnitudes, which is the largest coefficient (the mean mode: every
    /// coefficient is positive), so 8 log2(mx my) eps of it bounds their difference.
    #[test]
    fn kernel_spectrum_matches_the_full_padded_transform() {
        for (nx, ny, tx, ty) in [
            (37, 20, 37, 20),
            (30, 41, 50, 60),
            (64, 64, 64, 64),
            (1, 7, 1, 7),
        ] {
            let table = KernelTable::new(tx, ty, 0.3);
            let op = FftOperator::with_kernel(nx, ny, &table, &mut FftPlans::default()).unwrap();
            let (mx, my) = op.padded();
            let fold = |i: usize, m: usize| if i <= m / 2 { i } else { m - i };
            let mut full: Vec<Complex<f64>> = (0..mx * my)
                .map(|i| {
                    let (kx, ky) = (fold(i % mx, mx), fold(i / mx, my));
                    let v = if table.covers(kx + 1, ky + 1) {
                        table.get(kx, ky)
                    } else {
                        0.0
                    };
                    Complex::new(v, 0.0)
                })
                .collect();
            let mut planner = FftPlanner::new();
            let (row, col) = (planner.plan_fft_forward(mx), planner.plan_fft_forward(my));
            full.chunks_mut(mx).for_each(|r| row.process(r));
            for kx in 0..mx {
                let mut c: Vec<_> = (0..my).map(|iy| full[iy * mx + kx]).collect();
                col.process(&mut c);
                (0..my).for_each(|ky| full[ky * mx + kx] = c[ky]);
            }
            let norm = 1.0 / (mx * my) as f64;
            let largest = full[0].re * norm;
            let bound = 8.0 * ((mx * my) as f64).log2().max(1.0) * f64::EPSILON * largest;
            for kx in 0..mx / 2 + 1 {
                for ky in 0..my {
                    let d = (op.spectrum[kx * my + ky] - full[ky * mx + kx].re * norm).abs();
                    assert!(d <= bound, "{nx} x {ny}, ({kx}, {ky}): {d:e} > {bound:e}");
                }
            }
        }
    }

    /// The single-precision copy convolves as the operator does to single precision (within
    /// 8 log2(mx my) f32 eps of the largest deflection, the bound of the FFTs' round-off),
    /// after a resize too, and its add form adds the same to what `u` held.
    #[test]
    fn the_single_precision_copy_convolves_as_the_operator() {
        for (nx, ny, resized) in [(48, 40, None), (33, 17, Some((32, 17)))] {
            let mut op = FftOperator::new(nx, ny, 0.2).unwrap();
            let (nx, ny) = match resized {
                Some((wx, wy)) => {
                    op.convolve_single(&vec![0.0; nx * ny], &mut vec![0.0; nx * ny]);
                    op.resize(wx, wy).unwrap();
                    (wx, wy)
                }
                None => (nx, ny),
            };
            let p = pseudo_random(nx * ny, 5);
            let (mut exact, mut single) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
            op.convolve(&p, &mut exact);
            op.convolve_single(&p, &mut single);
            let (mx, my) = op.padded();
            let largest = exact.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let bound = 8.0 * ((mx * my) as f64).log2() * f64::from(f32::EPSILON) * largest;
            let diff = max_abs(&exact, &single);
            assert!(diff <= bound, "{nx} x {ny}: {diff:e} > {bound:e}");
            assert!(diff > 0.0, "{nx} x {ny}: the copy ran in double precision");
            let held = pseudo_random(nx * ny, 6);
            let mut added = held.clone();
            op.add_convolved_single(&p, &mut added);
            let sum: Vec<f64> = held.iter().zip(&single).map(|(a, b)| a + b).collect();
            assert!(max_abs(&added, &sum) <= 4.0 * f64::EPSILON * (largest + 1.0));
        }
    }

    /// Largest |a_i - b_i|.
    fn max_abs(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    }

    fn max_rel_diff(nx: usize, ny: usize) -> f64 {
        let dx = 0.37;
        let p = pseudo_random(nx * ny, (nx * 31 + ny) as u64);
        let (mut a, mut b) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
        FftOperator::new(nx, ny, dx).unwrap().apply(&p, &mut a);
        DenseOperator::new(nx, ny, dx).unwrap().apply(&p, &mut b);
        let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(&b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs() / scale))
    }

    /// An operator resized to a smaller grid of the same padded sizes applies the dense
    /// operator of that grid; a grid that pads differently or exceeds the kernel table is
    /// refused.
    #[test]
    fn resized_operator_is_the_smaller_grids_operator() {
        let dx = 0.37;
        let table = KernelTable::new(40, 36, dx);
        let mut op = FftOperator::with_kernel(40, 36, &table, &mut FftPlans::default()).unwrap();
        assert_eq!(op.padded(), (80, 72));
        for (nx, ny) in [(38, 35), (40, 36), (39, 34)] {
            op.resize(nx, ny).unwrap();
            let p = pseudo_random(nx * ny, 7);
            let (mut a, mut b) = (vec![0.0; nx * ny], vec![0.0; nx * ny]);
            op.apply(&p, &mut a);
            DenseOperator::new(nx, ny, dx).unwrap().apply(&p, &mut b);
            let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (x, y) in a.iter().zip(&b) {
                assert!((x - y).abs() < 1e-12 * scale, "{nx} x {ny}");
            }
        }
        assert!(op.resize(30, 36).is_err());
        let small = KernelTable::new(39, 36, dx);
        let mut op = FftOperator::with_kernel(39, 36, &small, &mut FftPlans::default()).unwrap();
        assert_eq!(op.padded(), (80, 72));
        assert!(op.resize(40, 36).is_err());
    }

    #[test]
    fn fft_matches_dense_on_odd_even_and_tiny_grids() {
        for (nx, ny) in [
            (1, 1),
            (2, 2),
            (3, 3),
            (1, 5),
            (13, 9),
            (16, 16),
            (17, 12),
            (33, 31),
        ] {
            let d = max_rel_diff(nx, ny);
            assert!(d < 1e-12, "{nx}x{ny}: {d}");
        }
    }

    /// Point loads added by direct summation deflect as the operator's apply does, on a
    /// free grid (odd, even, window-resized) and on a periodic cell (the same kernel
    /// code, periodic offsets).
    #[test]
    fn point_loads_match_the_apply() {
        let dx = 0.37;
        let table = KernelTable::new(33, 31, dx);
        let mut plans = FftPlans::default();
        let mut resized = FftOperator::with_kernel(33, 31, &table, &mut plans).unwrap();
        resized.apply(&[0.0; 33 * 31], &mut [0.0; 33 * 31]);
        resized.resize(32, 30).unwrap();
        let ops: Vec<Box<dyn SurfaceOperator>> = vec![
            Box::new(FftOperator::new(13, 9, dx).unwrap()),
            Box::new(FftOperator::new(16, 16, dx).unwrap()),
            Box::new(resized),
            Box::new(crate::halfspace::periodic::PeriodicOperator::new(24, 20, dx).unwrap()),
            Box::new(crate::halfspace::periodic::PeriodicOperator::new(15, 9, dx).unwrap()),
        ];
        for mut op in ops {
            let (nx, ny) = (op.nx(), op.ny());
            let n = nx * ny;
            let idx = [0, 1, nx - 1, n / 2 + 3, n - nx, n - 1];
            let values = [1.0, -0.5, 2.0, 0.25, 3.0, -1.5];
            let mut q = vec![0.0; n];
            idx.iter().zip(values).for_each(|(&i, v)| q[i] += v);
            let mut expected = pseudo_random(n, 3);
            let mut u = expected.clone();
            let mut kq = vec![0.0; n];
            op.apply(&q, &mut kq);
            expected.iter_mut().zip(&kq).for_each(|(e, k)| *e += k);
            assert!(op.point_load_limit() >= 1, "{nx} x {ny}");
            assert!(op.add_point_loads(&idx, &values, &mut u));
            let scale = kq.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (a, b) in u.iter().zip(&expected) {
                assert!((a - b).abs() < 1e-13 * scale, "{nx} x {ny}: {a} vs {b}");
            }
        }
    }

    /// On a free grid of fast FFT sizes the spectral preconditioner (single precision) of a
    /// harmonic residual cos(q . x) periodic on the grid is 2 |q| dx cos(q . x), the
    /// half-space's inverse times dx, to the round-off of a single-precision FFT pair
    /// (8 eps32 log2(n) of the amplitude; measured 3.7e-6 of it, 2.2 eps32 log2(n)), farther
    /// than `WRAP_RADIUS` from the edges (nearer, the wrap is taken back).
    #[test]
    fn spectral_preconditioner_inverts_a_harmonic_in_single_precision() {
        let (nx, ny, dx) = (160, 128, 0.25);
        assert!(nx * ny >= SPECTRAL_MIN_ELEMENTS);
        assert_eq!((fast_size(nx), fast_size(ny)), (nx, ny));
        let mut op = FftOperator::new(nx, ny, dx).unwrap();
        let bound = 8.0 * f64::from(f32::EPSILON) * ((nx * ny) as f64).log2();
        for (kx, ky) in [(1i64, 0i64), (0, 1), (3, -2), (80, 0), (17, 40)] {
            let (lx, ly) = (nx as f64 * dx, ny as f64 * dx);
            let (qx, qy) = (
                2.0 * std::f64::consts::PI * kx as f64 / lx,
                2.0 * std::f64::consts::PI * ky as f64 / ly,
            );
            let phase = |i: usize| qx * (i % nx) as f64 * dx + qy * (i / nx) as f64 * dx;
            let g: Vec<f64> = (0..nx * ny).map(|i| phase(i).cos()).collect();
            let mut z = vec![0.0; nx * ny];
            op.precondition(&g, &mut z);
            let amp = 2.0 * qx.hypot(qy) * dx;
            let w = WRAP_RADIUS;
            let inside =
                |i: usize| (w..nx - w).contains(&(i % nx)) && (w..ny - w).contains(&(i / nx));
            for (i, v) in z.iter().enumerate().filter(|(i, _)| inside(*i)) {
                let exact = amp * phase(i).cos();
                assert!(
                    (v - exact).abs() < bound * amp,
                    "({kx},{ky}): {v} vs {exact}"
                );
            }
        }
    }

    /// On a free grid the spectral preconditioner keeps opposite edges apart: a point
    /// residual next to one edge acts on the element next to it as at the grid's middle and
    /// as on a grid twice as wide (to the round-off of a single-precision FFT pair and the
    /// kernel's 1/r^3 tail), and on the element across the opposite edge, one element away
    /// in the convolution periodic on the grid, less than a hundredth as much; so do the
    /// corners.
    #[test]
    fn spectral_preconditioner_keeps_opposite_edges_apart() {
        let (nx, ny, dx) = (160, 128, 0.25);
        assert!(nx * ny >= SPECTRAL_MIN_ELEMENTS);
        let response = |nx: usize, ny: usize, at: (usize, usize)| {
            let mut op = FftOperator::new(nx, ny, dx).unwrap();
            let mut g = vec![0.0; nx * ny];
            g[at.1 * nx + at.0] = 1.0;
            let mut z = vec![0.0; nx * ny];
            op.precondition(&g, &mut z);
            move |ix: usize, iy: usize| z[iy * nx + ix]
        };
        let mid = ny / 2;
        let edge = response(nx, ny, (0, mid));
        let centre = response(nx, ny, (nx / 2, mid));
        let wide = response(2 * nx, 2 * ny, (nx, ny));
        let corner = response(nx, ny, (0, 0));
        // the inverse kernel: positive on the element, negative off it, like -1/r^3
        let (own, next) = (centre(nx / 2, mid), centre(nx / 2 + 1, mid));
        assert!(own > 0.0 && next < 0.0, "{own} {next}");
        let tol = 1e-4 * own;
        for (a, b) in [
            (edge(0, mid), own),
            (edge(1, mid), next),
            (wide(nx, ny), own),
            (wide(nx + 1, ny), next),
            (corner(0, 1), next),
        ] {
            assert!((a - b).abs() < tol, "{a} vs {b}");
        }
        for across in [
            edge(nx - 1, mid),
            edge(nx - 2, mid + 1),
            corner(nx - 1, ny - 1),
            corner(0, ny - 1),
            corner(nx - 1, 0),
        ] {
            assert!(across.abs() < 0.01 * next.abs(), "{across} vs {next}");
        }
    }

    #[test]
    fn fast_sizes() {
        assert_eq!(padded_size(1), 1);
        assert_eq!(padded_size(2), 2);
        assert_eq!(padded_size(257), 512);
        assert_eq!(padded_size(176), 360);
        assert_eq!(padded_size(200), 400 + 32);
        assert_eq!(fast_size(11 * 13), 144);
        assert_eq!(fast_size(7), 8);
        for n in 2..3000 {
            let m = fast_size(n);
            assert!(
                m >= n && m % 2 == 0 && m as f64 <= 1.2 * n as f64 + 2.0,
                "{n} -> {m}"
            );
        }
    }
}
