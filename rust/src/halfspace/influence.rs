//! Love's (1929) closed-form influence coefficients of uniformly loaded rectangles.
//!
//! For an incompressible half-space (E* = 4G) with shear modulus G = 1 Pa, a uniform
//! pressure of 1 Pa on a square element of side `dx` deflects the surface at a point by
//! (1 / (4 pi)) * integral over the element of 1 / distance. Scale by 1/G for other moduli
//! (by 1/eta for deflection rates of a viscous half-space).

use rayon::prelude::*;
use std::f64::consts::PI;
use std::sync::Arc;

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

/// Coefficients for offsets 0..nx-1 by 0..ny-1 (row-major, index ky * nx + kx) of square
/// elements of side `dx` (m): `dx` times the unit element's ([`unit_quarter`]). The kernel
/// is even in each offset, so this quarter holds all of it.
pub fn quarter_kernel(nx: usize, ny: usize, dx: f64) -> Vec<f64> {
    let mut k = unit_quarter(nx, ny);
    k.par_iter_mut().for_each(|v| *v *= dx);
    k
}

/// Love's coefficients of the unit element (side 1 m, m/Pa at G = 1) for offsets 0..nx-1
/// by 0..ny-1 (row-major, index ky * nx + kx); those of elements of side dx are dx times
/// them (the antiderivative `phi` is homogeneous of degree 1). Neighbouring elements share
/// corners, so the antiderivative is evaluated once per corner of the (nx + 1) x (ny + 1)
/// lattice at k - 1/2 (a quarter of the asinh calls of four corners per element), and as it
/// is symmetric in its arguments, once per pair of corners (i, j), (j, i) of the lattice;
/// the coefficients are symmetric likewise (c(kx, ky) = c(ky, kx)): those below the
/// diagonal are copied from above it. Rows in parallel.
pub fn unit_quarter(nx: usize, ny: usize) -> Vec<f64> {
    let (cx, cy) = (nx + 1, ny + 1);
    let corner = |k: usize| k as f64 - 0.5;
    // corner (i, j) is evaluated where i >= j or its mirror (j, i) is off the lattice
    let first = |j: usize| if j < cx { j } else { 0 };
    let mut lattice = vec![0.0; cx * cy];
    lattice.par_chunks_mut(cx).enumerate().for_each(|(j, row)| {
        for (i, v) in row.iter_mut().enumerate().skip(first(j)) {
            *v = phi(corner(i), corner(j));
        }
    });
    let at = |i: usize, j: usize| {
        if i >= first(j) {
            lattice[j * cx + i]
        } else {
            lattice[i * cx + j]
        }
    };
    // coefficient (kx, ky) is computed where kx >= ky or its mirror is off the table
    let from = |ky: usize| if ky < nx { ky } else { 0 };
    let mut k = vec![0.0; nx * ny];
    k.par_chunks_mut(nx.max(1))
        .enumerate()
        .for_each(|(ky, row)| {
            for (kx, v) in row.iter_mut().enumerate().skip(from(ky)) {
                *v = (at(kx + 1, ky + 1) - at(kx, ky + 1) - at(kx + 1, ky) + at(kx, ky))
                    / (4.0 * PI);
            }
        });
    // the rest from their mirrors, in square blocks (a row of one is a column of the other)
    const BLOCK: usize = 32;
    let m = nx.min(ny);
    for by in (0..m).step_by(BLOCK) {
        for bx in (0..=by).step_by(BLOCK) {
            for ky in by..(by + BLOCK).min(m) {
                for kx in bx..(bx + BLOCK).min(ky) {
                    k[ky * nx + kx] = k[kx * nx + ky];
                }
            }
        }
    }
    k
}

/// A quarter kernel of a grid, computed once and shared (its values behind an `Arc`) by the
/// operators of all its sub-grids (windows) with the same element size and, for Love's
/// coefficients, which scale with the element size, by those of the coarser grids of a
/// nested solve.
#[derive(Debug, Clone, PartialEq)]
pub struct KernelTable {
    nx: usize,
    ny: usize,
    dx: f64,
    /// Row length of `values`.
    stride: usize,
    /// Factor from `values` to the coefficients (m/Pa at G = 1): dx for Love's unit-element
    /// coefficients, 1 for another table.
    scale: f64,
    /// Whether `values` are Love's unit-element coefficients (which scale with dx).
    love: bool,
    values: Arc<Vec<f64>>,
}

impl KernelTable {
    /// Love's coefficients (m/Pa at G = 1) for offsets up to `nx` - 1 by `ny` - 1 elements of
    /// side `dx` (m).
    pub fn new(nx: usize, ny: usize, dx: f64) -> Self {
        KernelTable {
            nx,
            ny,
            dx,
            stride: nx,
            scale: dx,
            love: true,
            values: Arc::new(unit_quarter(nx, ny)),
        }
    }

    /// A table of other influence coefficients (m/Pa at G = 1; a layer's): `values` at
    /// offsets (kx, ky), kx < nx, ky < ny, row-major, even in both offsets, independent of
    /// the table's extent.
    pub(crate) fn from_values(nx: usize, ny: usize, dx: f64, values: Vec<f64>) -> Self {
        assert_eq!(values.len(), nx * ny, "kernel table length");
        KernelTable {
            nx,
            ny,
            dx,
            stride: nx,
            scale: 1.0,
            love: false,
            values: Arc::new(values),
        }
    }

    /// The table of the same body for offsets up to `nx` - 1 by `ny` - 1 elements of side
    /// `dx` (m), sharing this one's values, where they hold it: when it covers that extent
    /// and has the same element side or holds Love's coefficients, which scale with it
    /// (c(kx, ky; dx) = dx c(kx, ky; 1), so a grid coarsened by two takes twice the
    /// fine grid's coefficients at the same offsets); None otherwise.
    pub fn part(&self, nx: usize, ny: usize, dx: f64) -> Option<KernelTable> {
        let scale = if dx == self.dx {
            self.scale
        } else if self.love {
            dx
        } else {
            return None;
        };
        self.covers(nx, ny).then(|| KernelTable {
            nx,
            ny,
            dx,
            scale,
            ..self.clone()
        })
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
        self.scale * self.values[ky * self.stride + kx]
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

    /// The round-off of a coefficient (m/Pa): a difference of four antiderivative values
    /// (each to a few ulps) that cancel to dx^2 / r far from the element, so that two
    /// evaluations at other corner coordinates (k - 1/2) dx and (k - 1/2) times dx differ by
    /// up to about eps times their magnitude (measured up to 0.19 of this bound; where they
    /// differed most relative to the coefficient, by 1.2e-12, 80-bit arithmetic put the
    /// exact value between them).
    fn roundoff(kx: usize, ky: usize, dx: f64) -> f64 {
        let c = |k: usize, s: f64| (k as f64 + s) * dx;
        let corners = [(0.5, 0.5), (-0.5, 0.5), (0.5, -0.5), (-0.5, -0.5)];
        let size: f64 = corners
            .iter()
            .map(|&(a, b)| phi(c(kx, a), c(ky, b)).abs())
            .sum();
        4.0 * f64::EPSILON * size / (4.0 * PI)
    }

    /// The lattice evaluation gives the per-element coefficients, on wide, tall, square and
    /// single-row grids (the evaluation by symmetry covers each
    /// corner and coefficient once, mirrored or not), to round-off.
    #[test]
    fn quarter_kernel_matches_the_element_coefficients() {
        for (nx, ny, dx) in [(40, 23, 0.013), (23, 40, 0.013), (33, 33, 2.5), (1, 7, 0.1)] {
            let table = quarter_kernel(nx, ny, dx);
            for ky in 0..ny {
                for kx in 0..nx {
                    let c = coefficient(kx as i64, ky as i64, dx);
                    let v = table[ky * nx + kx];
                    let tol = roundoff(kx, ky, dx);
                    assert!((v - c).abs() <= tol, "({kx}, {ky}): {v} vs {c} ({tol:e})");
                }
            }
        }
    }

    /// A part of a Love table at another element side holds that side's coefficients
    /// (the coarse level of a nested solve: twice the side, half the extent), one at the
    /// same side its own values; a layer's table gives no part at another side, and no
    /// table a part beyond its extent.
    #[test]
    fn parts_of_a_table_hold_the_coefficients_of_their_element_side() {
        let (n, dx) = (48, 0.02);
        let fine = KernelTable::new(n, n + 3, dx);
        for (nx, ny, side) in [(n / 2, n / 2, 2.0 * dx), (n / 4, 5, 4.0 * dx), (n, 9, dx)] {
            let part = fine.part(nx, ny, side).unwrap();
            assert_eq!((part.extent(), part.dx()), ((nx, ny), side));
            for ky in 0..ny {
                for kx in 0..nx {
                    let c = coefficient(kx as i64, ky as i64, side);
                    let v = part.get(kx, ky);
                    let tol = roundoff(kx, ky, side);
                    assert!((v - c).abs() <= tol, "({kx}, {ky}): {v} vs {c} ({tol:e})");
                }
            }
        }
        assert!(fine.part(n + 1, 4, dx).is_none());
        let other = KernelTable::from_values(4, 4, dx, quarter_kernel(4, 4, dx));
        assert!(other.part(2, 2, 2.0 * dx).is_none());
        assert_eq!(other.part(3, 2, dx).unwrap().get(2, 1), other.get(2, 1));
    }

    #[test]
    fn kernel_is_even_and_scales_with_dx() {
        assert_eq!(coefficient(3, -2, 0.1), coefficient(-3, 2, 0.1));
        let ratio = coefficient(4, 1, 0.2) / coefficient(4, 1, 0.1);
        assert!((ratio - 2.0).abs() < 1e-12);
    }
}
