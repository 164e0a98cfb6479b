//! Rectangular sub-grids ("windows") that hold everything a step can touch, so that a solve
//! runs on the smallest FFT grid that represents it exactly, and a cache of solvers per
//! window size so that FFT plans and buffers are made once per size, not once per step.

use crate::contact::ContactSolver;
use crate::error::{check_positive, Result};
use crate::influence::KernelTable;
use crate::operator::{FftOperator, FftPlans};
use std::collections::HashMap;

/// A sub-grid with origin (x0, y0) and size wx x wy inside a grid `nx` x `ny`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Window {
    /// Grid width.
    pub nx: usize,
    /// Grid height.
    pub ny: usize,
    /// First column.
    pub x0: usize,
    /// First row.
    pub y0: usize,
    /// Columns.
    pub wx: usize,
    /// Rows.
    pub wy: usize,
}

/// Smallest size >= n of the form m 2^k with 8 <= m < 16 (or n itself below 16): at most
/// 12.5 % larger, and few distinct sizes per run.
fn bucket(n: usize) -> usize {
    if n <= 16 {
        return n;
    }
    let k = usize::BITS - 1 - n.leading_zeros() - 3;
    let m = n.div_ceil(1 << k);
    m << k
}

impl Window {
    /// The whole grid.
    pub fn full(nx: usize, ny: usize) -> Self {
        Window {
            nx,
            ny,
            x0: 0,
            y0: 0,
            wx: nx,
            wy: ny,
        }
    }

    /// The bounding box of the elements where `inside` holds, grown by `margin` elements and
    /// rounded up to a cached size; the whole grid when nothing is inside.
    pub fn around(nx: usize, ny: usize, margin: usize, inside: impl Fn(usize) -> bool) -> Self {
        let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (usize::MAX, 0, usize::MAX, 0);
        for i in (0..nx * ny).filter(|&i| inside(i)) {
            let (x, y) = (i % nx, i / nx);
            x_lo = x_lo.min(x);
            x_hi = x_hi.max(x);
            y_lo = y_lo.min(y);
            y_hi = y_hi.max(y);
        }
        if x_lo == usize::MAX {
            return Window::full(nx, ny);
        }
        let span = |lo: usize, hi: usize, n: usize| {
            let lo = lo.saturating_sub(margin);
            let hi = (hi + margin).min(n - 1);
            let w = bucket(hi - lo + 1).min(n);
            (lo.min(n - w), w)
        };
        let (x0, wx) = span(x_lo, x_hi, nx);
        let (y0, wy) = span(y_lo, y_hi, ny);
        Window {
            nx,
            ny,
            x0,
            y0,
            wx,
            wy,
        }
    }

    /// Whether the window is the whole grid.
    pub fn is_full(&self) -> bool {
        self.wx == self.nx && self.wy == self.ny
    }

    /// Grid index of window element `j`.
    pub fn to_grid(&self, j: usize) -> usize {
        (self.y0 + j / self.wx) * self.nx + self.x0 + j % self.wx
    }

    /// Copies the window's part of `full` into `out` (cleared first).
    pub fn gather<T: Copy>(&self, full: &[T], out: &mut Vec<T>) {
        out.clear();
        for r in 0..self.wy {
            let s = (self.y0 + r) * self.nx + self.x0;
            out.extend_from_slice(&full[s..s + self.wx]);
        }
    }

    /// Writes window values `win` into `full`, and zero everywhere else.
    pub fn scatter(&self, win: &[f64], full: &mut [f64]) {
        full.fill(0.0);
        for r in 0..self.wy {
            let s = (self.y0 + r) * self.nx + self.x0;
            full[s..s + self.wx].copy_from_slice(&win[r * self.wx..(r + 1) * self.wx]);
        }
    }
}

/// Contact solvers of the windows of one grid keyed by window size, made on first use from
/// the grid's kernel table (computed once).
pub struct SolverPool {
    kernel: KernelTable,
    plans: FftPlans,
    solvers: HashMap<(usize, usize), ContactSolver<FftOperator>>,
}

impl SolverPool {
    /// An empty pool for the windows of an `nx` x `ny` grid of elements of side `dx` (m).
    pub fn new(nx: usize, ny: usize, dx: f64) -> Result<Self> {
        check_positive("element size dx", dx)?;
        Ok(SolverPool {
            kernel: KernelTable::new(nx, ny, dx),
            plans: FftPlans::default(),
            solvers: HashMap::new(),
        })
    }

    /// A new operator for a `wx` x `wy` window from the pool's kernel table and plans.
    pub fn operator(&mut self, wx: usize, wy: usize) -> Result<FftOperator> {
        FftOperator::with_kernel(wx, wy, &self.kernel, &mut self.plans)
    }

    /// The solver for a `wx` x `wy` grid.
    pub fn get(&mut self, wx: usize, wy: usize) -> Result<&mut ContactSolver<FftOperator>> {
        use std::collections::hash_map::Entry;
        Ok(match self.solvers.entry((wx, wy)) {
            Entry::Occupied(e) => e.into_mut(),
            Entry::Vacant(e) => e.insert(ContactSolver::new(FftOperator::with_kernel(
                wx,
                wy,
                &self.kernel,
                &mut self.plans,
            )?)),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn buckets_are_tight_and_coarse() {
        assert_eq!(bucket(7), 7);
        assert_eq!(bucket(17), 18);
        assert_eq!(bucket(100), 104);
        assert_eq!(bucket(257), 288);
        for n in 1..2000 {
            assert!(bucket(n) >= n && bucket(n) as f64 <= 1.125 * n as f64 + 1.0);
        }
    }

    #[test]
    fn window_round_trip() {
        let (nx, ny) = (40, 30);
        let w = Window::around(nx, ny, 2, |i| i == 5 * nx + 7 || i == 12 * nx + 20);
        assert!(w.x0 <= 5 && w.x0 + w.wx > 22 && w.y0 <= 3 && w.y0 + w.wy > 14);
        let full: Vec<f64> = (0..nx * ny).map(|i| i as f64).collect();
        let mut part = vec![];
        w.gather(&full, &mut part);
        assert_eq!(part.len(), w.wx * w.wy);
        for (j, v) in part.iter().enumerate() {
            assert_eq!(*v, w.to_grid(j) as f64);
        }
        let mut back = vec![0.0; nx * ny];
        w.scatter(&part, &mut back);
        assert_eq!(back[w.to_grid(3)], full[w.to_grid(3)]);
    }
}
