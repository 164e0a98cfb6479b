//! The element grid of a BEM run: square elements over the indenter's footprint, with the
//! indenter's height above its tip at each element centre.

use crate::error::{check_finite, check_len, check_positive, Error, Result};

/// A square-element grid over the indenter's footprint.
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    /// Elements along x.
    pub nx: usize,
    /// Elements along y.
    pub ny: usize,
    /// Element side (m).
    pub dx: f64,
    /// Indenter height above its tip at element centres (m), row-major (iy * nx + ix).
    pub height: Vec<f64>,
    /// Elements the indenter covers (where contact is possible).
    pub allowed: Vec<bool>,
}

impl Grid {
    /// An `nx` x `ny` grid of elements of side `dx` (m) with indenter heights `height` (m)
    /// and the footprint `allowed`, validated: sizes match, heights finite and >= 0 where
    /// allowed, and at least one element allowed.
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        height: Vec<f64>,
        allowed: Vec<bool>,
    ) -> Result<Self> {
        if nx == 0 || ny == 0 {
            return Err(Error::InvalidInput(format!(
                "grid size must be at least 1 x 1, got {nx} x {ny}"
            )));
        }
        check_positive("element size dx", dx)?;
        check_len("height map", height.len(), nx * ny)?;
        check_len("footprint mask", allowed.len(), nx * ny)?;
        check_finite("height map", &height)?;
        if let Some(i) = (0..nx * ny).find(|&i| allowed[i] && height[i] < 0.0) {
            return Err(Error::InvalidInput(format!(
                "heights must be >= 0 (measured from the indenter's tip), got {} at element ({}, {})",
                height[i],
                i % nx,
                i / nx
            )));
        }
        if !allowed.iter().any(|&a| a) {
            return Err(Error::InvalidInput(
                "the indenter's footprint holds no element of the grid".into(),
            ));
        }
        Ok(Grid {
            nx,
            ny,
            dx,
            height,
            allowed,
        })
    }

    /// Whether any element of `set` lies on the outermost ring of the grid.
    pub fn touches_edge(&self, set: &[bool]) -> bool {
        let (nx, ny) = (self.nx, self.ny);
        (0..nx * ny).any(|i| {
            let (ix, iy) = (i % nx, i / nx);
            set[i] && (ix == 0 || iy == 0 || ix + 1 == nx || iy + 1 == ny)
        })
    }
}
