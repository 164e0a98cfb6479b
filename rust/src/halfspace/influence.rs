//! Love's (1929) closed-form influence coefficients of uniformly loaded rectangles.
//!
//! For an incompressible half-space (E* = 4G) with shear modulus G = 1 Pa, a uniform
//! pressure of 1 Pa on a square element of side `dx` deflects the surface at a point by
//! (1 / (4 pi)) * integral over the element of 1 / distance. Scale by 1/G for other moduli
//! (by 1/eta for deflection rates of a viscous half-space).

use rayon::prelude::*;
use std::f64::consts::PI;

/// Antiderivative of 1/sqrt(x^2 + y^2) in x and y: x asinh(y/|x|) + y asinh(x/|y|)
/// (x ln(y + r) + y ln(x + r) up to terms in one variable, without its cancellation).
fn phi(x: f64, y: f64) -> f64 {
    let a = if x == 0.0 {
        0.0
    } else {
        x * (y / x.abs()).asinh()
    };
    let b = if y == 0.0 {
        0.0
    } else {
        y * (x / y.abs()).asinh()
    };
    a + b
}

/// Deflection (m) at offset (`ox`, `oy`) (m) from the centre of a `wx` x `wy` rectangle
/// loaded by 1 Pa, on a half-space with G = 1 Pa.
pub fn rectangle_deflection(ox: f64, oy: f64, wx: f64, wy: f64) -> f64 {
    let (x1, x2) = (ox - 0.5 * wx, ox + 0.5 * wx);
    let (y1, y2) = (oy - 0.5 * wy, oy + 0.5 * wy);
    (phi(x2, y2) - phi(x1, y2) - phi(x2, y1) + phi(x1, y1)) / (4.0 * PI)
}

/// Influence coefficient (m/Pa at G = 1 Pa) between square elements of side `dx` (m)
/// whose centres are `kx`, `ky` elements apart.
pub fn coefficient(kx: i64, ky: i64, dx: f64) -> f64 {
    rectangle_deflection(kx as f64 * dx, ky as f64 * dx, dx, dx)
}

/// Coefficients for offsets 0..nx-1 by 0..ny-1 (row-major, index ky * nx + kx). The kernel
/// is even in each offset, so this quarter holds all of it. Neighbouring elements share
/// corners, so the antiderivative is evaluated once per corner of the (nx + 1) x (ny + 1)
/// lattice at (k - 1/2) dx (a quarter of the asinh calls of four corners per element);
/// rows in parallel.
pub fn quarter_kernel(nx: usize, ny: usize, dx: f64) -> Vec<f64> {
    let (cx, cy) = (nx + 1, ny + 1);
    let corner = |k: usize| (k as f64 - 0.5) * dx;
    let mut lattice = vec![0.0; cx * cy];
    lattice.par_chunks_mut(cx).enumerate().for_each(|(j, row)| {
        for (i, v) in row.iter_mut().enumerate() {
            *v = phi(corner(i), corner(j));
        }
    });
    let mut k = vec![0.0; nx * ny];
    k.par_chunks_mut(nx.max(1))
        .enumerate()
        .for_each(|(ky, row)| {
            let (lo, hi) = (&lattice[ky * cx..(ky + 1) * cx], &lattice[(ky + 1) * cx..]);
            for (kx, v) in row.iter_mut().enumerate() {
                *v = (hi[kx + 1] - hi[kx] - lo[kx + 1] + lo[kx]) / (4.0 * PI);
            }
        });
    k
}

/// The quarter kernel of a grid, computed once and shared by the operators of all its
/// sub-grids (windows) with the same element size.
#[derive(Debug, Clone, PartialEq)]
pub struct KernelTable {
    nx: usize,
    ny: usize,
    dx: f64,
    values: Vec<f64>,
}

impl KernelTable {
    /// Coefficients (m/Pa at G = 1) for offsets up to `nx` - 1 by `ny` - 1 elements of side
    /// `dx` (m).
    pub fn new(nx: usize, ny: usize, dx: f64) -> Self {
        KernelTable {
            nx,
            ny,
            dx,
            values: quarter_kernel(nx, ny, dx),
        }
    }

    /// A table of other influence coefficients (m/Pa at G = 1; a layer's): `values` at
    /// offsets (kx, ky), kx < nx, ky < ny, row-major, even in both offsets.
    pub(crate) fn from_values(nx: usize, ny: usize, dx: f64, values: Vec<f64>) -> Self {
        assert_eq!(values.len(), nx * ny, "kernel table length");
        KernelTable { nx, ny, dx, values }
    }

    /// Element side (m).
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// The largest grid (nx, ny) whose every offset the table holds.
    pub fn extent(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// Whether the table holds every offset of an `nx` x `ny` grid.
    pub fn covers(&self, nx: usize, ny: usize) -> bool {
        nx <= self.nx && ny <= self.ny
    }

    /// Coefficient at offset (`kx`, `ky`) elements (m/Pa at G = 1).
    pub fn get(&self, kx: usize, ky: usize) -> f64 {
        self.values[ky * self.nx + kx]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn far_field_is_boussinesq() {
        let dx = 0.01;
        let r = 50.0 * dx;
        let point = dx * dx / (4.0 * PI * r);
        assert!((coefficient(50, 0, dx) / point - 1.0).abs() < 1e-4);
    }

    #[test]
    fn centre_of_square_matches_closed_form() {
        // Centre of a square of side 2b, in polar coordinates: integral of dA / r
        // = 8 b ln(1 + sqrt 2), so u = 8 b ln(1 + sqrt 2) / (4 pi) at G = 1.
        let dx = 2.0;
        let b = 1.0;
        let exact = 8.0 * b * (1.0 + 2f64.sqrt()).ln() / (4.0 * PI);
        assert!((coefficient(0, 0, dx) / exact - 1.0).abs() < 1e-14);
    }

    /// The lattice evaluation gives the per-element coefficients (to round-off of the
    /// shared corners' coordinates).
    #[test]
    fn quarter_kernel_matches_the_element_coefficients() {
        let (nx, ny, dx) = (40, 23, 0.013);
        let table = quarter_kernel(nx, ny, dx);
        for ky in 0..ny {
            for kx in 0..nx {
                let c = coefficient(kx as i64, ky as i64, dx);
                let v = table[ky * nx + kx];
                assert!((v - c).abs() <= 1e-12 * c, "({kx}, {ky}): {v} vs {c}");
            }
        }
    }

    #[test]
    fn kernel_is_even_and_scales_with_dx() {
        assert_eq!(coefficient(3, -2, 0.1), coefficient(-3, 2, 0.1));
        let ratio = coefficient(4, 1, 0.2) / coefficient(4, 1, 0.1);
        assert!((ratio - 2.0).abs() < 1e-12);
    }
}
