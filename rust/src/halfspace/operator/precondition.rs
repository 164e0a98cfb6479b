//! The preconditioner of the contact conjugate gradients: a local approximate inverse of
//! the surface operator (Vollebregt 2014 uses an FFT-based one to the same end).
//!
//! K (Love's kernel, ~1/r) has the spectrum ~1/|k|, so CG on a contact set of diameter D
//! elements needs ~sqrt(D) iterations. Its inverse has the spectrum ~|k| and coefficients
//! that decay like 1/r^3: truncated to a (2R+1)^2 stencil, it still approximates K^-1 at
//! the high wavenumbers that slow CG down, costs (2R+1)^2 multiply-adds per element (no
//! FFT), and stays positive definite (its symbol is smallest at k = 0, where it is the sum
//! of the coefficients, > 0). On the paper's viscous runs it cuts Polonsky–Keer iterations
//! 2.5–3x (`benchmarks/bench_bem.py`). Free grids of at least `SPECTRAL_MIN_ELEMENTS` are
//! preconditioned by the spectral inverse instead (`FftOperator`'s `precondition`), whose
//! symbol also goes like |q| at long wavelengths, where the stencil's is flat.

use crate::halfspace::operator::FftOperator;
use rayon::prelude::*;
use std::sync::OnceLock;

/// Stencil radius (elements).
pub const RADIUS: usize = 3;

/// Side of the grid whose circulant inverse gives the coefficients. It is odd, so that the
/// padded size 2n - 2 = 128 leaves no zeros between the kernel's wrapped halves; such grids
/// agree with each other to ~5 digits from 33 x 33 on (a zero gap shifts them by ~1 %).
const REFERENCE_GRID: usize = 65;

/// Inverse-kernel coefficients (Pa/m) of an element of side 1 m at G = 1 Pa for offsets
/// 0..=RADIUS in x and y (row-major, (RADIUS + 1)^2), kept once per process. For side
/// dx they scale by 1/dx.
pub fn coefficients() -> &'static [f64] {
    static COEFFS: OnceLock<Vec<f64>> = OnceLock::new();
    if let Some(c) = COEFFS.get() {
        return c;
    }
    // Computed outside the lock: the computation runs rayon loops, and a worker that waits on
    // the lock while its holder waits, inside such a loop, for a job that worker stole would
    // never wake. Threads racing here each compute it; the first value is kept.
    let computed = FftOperator::new(REFERENCE_GRID, REFERENCE_GRID, 1.0)
        .and_then(|mut op| op.inverse_kernel(RADIUS))
        .expect("the reference grid is valid and larger than the stencil");
    COEFFS.get_or_init(|| computed)
}

/// Writes z = S * g on an `nx` x `ny` grid (row-major), S the truncated inverse-kernel
/// stencil of `coefficients()` and g zero beyond the grid: z ~ dx K^-1 g where g varies on
/// the scale of an element. Rows are computed in parallel; each sums its rows at offsets
/// +-k first (the stencil is even), then the columns at +-j.
pub fn apply(nx: usize, ny: usize, g: &[f64], z: &mut [f64]) {
    assert_eq!(g.len(), nx * ny, "input length");
    assert_eq!(z.len(), nx * ny, "output length");
    let c = coefficients();
    let w = RADIUS + 1;
    let rows_per_task = (4096 / nx.max(1)).max(1);
    z.par_chunks_mut(rows_per_task * nx)
        .enumerate()
        .for_each_init(
            || vec![0.0; w * (nx + 2 * RADIUS)],
            |pairs, (chunk, out)| {
                let stride = nx + 2 * RADIUS;
                for (r, row) in out.chunks_mut(nx).enumerate() {
                    let iy = chunk * rows_per_task + r;
                    // pairs[k] = g[iy - k] + g[iy + k] (g[iy] for k = 0), padded by RADIUS
                    // zeros
                    for k in 0..w {
                        let pk = &mut pairs[k * stride..(k + 1) * stride];
                        pk.fill(0.0);
                        let (below, above) =
                            (iy.checked_sub(k), (k > 0 && iy + k < ny).then_some(iy + k));
                        for sy in [below, above].into_iter().flatten() {
                            let src = &g[sy * nx..(sy + 1) * nx];
                            pk[RADIUS..RADIUS + nx]
                                .iter_mut()
                                .zip(src)
                                .for_each(|(a, &b)| *a += b);
                        }
                    }
                    row.fill(0.0);
                    for k in 0..w {
                        let pk = &pairs[k * stride..(k + 1) * stride];
                        let ck = &c[k * w..(k + 1) * w];
                        let centre = &pk[RADIUS..RADIUS + nx];
                        row.iter_mut()
                            .zip(centre)
                            .for_each(|(o, &s)| *o += ck[0] * s);
                        for (j, &cj) in ck.iter().enumerate().skip(1) {
                            let left = &pk[RADIUS - j..RADIUS - j + nx];
                            let right = &pk[RADIUS + j..RADIUS + j + nx];
                            row.iter_mut()
                                .zip(left.iter().zip(right))
                                .for_each(|(o, (&a, &b))| *o += cj * (a + b));
                        }
                    }
                }
            },
        );
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::halfspace::operator::SurfaceOperator;

    /// The stencil inverts K at high wavenumbers, where plain CG converges slowly:
    /// S * (K p) = dx p to 3 % for a checkerboard pressure (the Nyquist mode), away from
    /// the grid's edges; and its symbol is positive at every wavenumber, smallest at 0.
    #[test]
    fn stencil_inverts_the_operator_at_high_wavenumbers_and_is_positive() {
        let (n, dx) = (64, 0.5);
        let p: Vec<f64> = (0..n * n)
            .map(|i| if (i % n + i / n) % 2 == 0 { 1.0 } else { -1.0 })
            .collect();
        let mut u = vec![0.0; n * n];
        FftOperator::new(n, n, dx).unwrap().apply(&p, &mut u);
        let mut back = vec![0.0; n * n];
        apply(n, n, &u, &mut back);
        let centre = (n / 2) * n + n / 2;
        let ratio = back[centre] / (dx * p[centre]);
        assert!((ratio - 1.0).abs() < 0.03, "S K p / (dx p) = {ratio}");
        let c = coefficients();
        let w = RADIUS + 1;
        let symbol = |tx: f64, ty: f64| -> f64 {
            (0..w * w)
                .map(|i| {
                    let (kx, ky) = (i % w, i / w);
                    let fx = if kx > 0 {
                        2.0 * (kx as f64 * tx).cos()
                    } else {
                        1.0
                    };
                    let fy = if ky > 0 {
                        2.0 * (ky as f64 * ty).cos()
                    } else {
                        1.0
                    };
                    c[i] * fx * fy
                })
                .sum()
        };
        let at_zero = symbol(0.0, 0.0);
        assert!(at_zero > 0.0, "symbol at 0: {at_zero}");
        for a in 0..=40 {
            for b in 0..=40 {
                let (tx, ty) = (
                    a as f64 * std::f64::consts::PI / 40.0,
                    b as f64 * std::f64::consts::PI / 40.0,
                );
                assert!(
                    symbol(tx, ty) >= at_zero,
                    "symbol at ({tx}, {ty}) below its value at 0"
                );
            }
        }
    }
}
