//! The element grid of a BEM run: square elements over the indenter's footprint, with the
//! indenter's height above its tip at each element centre.

use crate::model::body::Body;
use crate::support::error::{check_finite, check_len, check_positive, Error, Result};

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
    /// The body the grid lies on (a periodic body: the grid is one cell, its opposite edges
    /// meet).
    pub body: Body,
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
            body: Body::HalfSpace,
        })
    }

    /// Number of contact patches of `set`: its connected components, elements joined
    /// through their edges (4-connectivity), across opposite edges where the grid has none.
    pub fn patches(&self, set: &[bool]) -> usize {
        count_patches(self.nx, self.ny, set, !self.body.has_edge())
    }

    /// Whether a contact of `area` (m^2) covers the whole footprint.
    pub fn covers(&self, area: f64) -> bool {
        let footprint = self.allowed.iter().filter(|&&a| a).count() as f64 * self.dx * self.dx;
        area >= footprint * (1.0 - 1e-12)
    }

    /// Whether any element of `set` lies on the outermost ring of the grid.
    pub fn touches_edge(&self, set: &[bool]) -> bool {
        let (nx, ny) = (self.nx, self.ny);
        let rows = [0, ny.saturating_sub(1)];
        let columns = [0, nx.saturating_sub(1)];
        rows.iter()
            .any(|&iy| set[iy * nx..(iy + 1) * nx].contains(&true))
            || (0..ny).any(|iy| columns.iter().any(|&ix| set[iy * nx + ix]))
    }
}

/// Connected components of `set` on an `nx` x `ny` grid (row-major), elements joined
/// through their edges (4-connectivity); with `wrap` the grid is a periodic cell and
/// elements on opposite edges are neighbours.
pub fn count_patches(nx: usize, ny: usize, set: &[bool], wrap: bool) -> usize {
    let mut seen = vec![false; nx * ny];
    let mut stack = vec![];
    let mut patches = 0;
    for start in 0..nx * ny {
        if !set[start] || seen[start] {
            continue;
        }
        patches += 1;
        seen[start] = true;
        stack.push(start);
        while let Some(i) = stack.pop() {
            let (ix, iy) = (i % nx, i / nx);
            let step = |v: usize, n: usize, up: bool| -> Option<usize> {
                match (up, wrap) {
                    (true, _) if v + 1 < n => Some(v + 1),
                    (true, true) => Some(0),
                    (false, _) if v > 0 => Some(v - 1),
                    (false, true) => Some(n - 1),
                    _ => None,
                }
            };
            let neighbours = [
                step(ix, nx, true).map(|x| iy * nx + x),
                step(ix, nx, false).map(|x| iy * nx + x),
                step(iy, ny, true).map(|y| y * nx + ix),
                step(iy, ny, false).map(|y| y * nx + ix),
            ];
            for j in neighbours.into_iter().flatten() {
                if set[j] && !seen[j] {
                    seen[j] = true;
                    stack.push(j);
                }
            }
        }
    }
    patches
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A set touches the edge exactly when one of its elements is on the outermost ring:
    /// every single element of wide, tall, square and one-element grids.
    #[test]
    fn a_set_touches_the_edge_where_an_element_is_on_the_ring() {
        for (nx, ny) in [(5, 3), (3, 5), (4, 4), (1, 6), (6, 1), (1, 1)] {
            let grid = Grid::new(nx, ny, 1.0, vec![0.0; nx * ny], vec![true; nx * ny]).unwrap();
            assert!(!grid.touches_edge(&vec![false; nx * ny]));
            for i in 0..nx * ny {
                let mut set = vec![false; nx * ny];
                set[i] = true;
                let (ix, iy) = (i % nx, i / nx);
                let ring = ix == 0 || iy == 0 || ix + 1 == nx || iy + 1 == ny;
                assert_eq!(grid.touches_edge(&set), ring, "{nx} x {ny}, ({ix}, {iy})");
            }
        }
    }

    /// Patches of a drawn set: diagonal neighbours stay apart; on a periodic cell the
    /// patches touching opposite edges join.
    #[test]
    fn patches_join_through_edges_and_wrap_on_a_cell() {
        let rows = ["#..#", "....", "#.#.", ".#.#"];
        let set: Vec<bool> = rows
            .iter()
            .flat_map(|r| r.chars().map(|c| c == '#'))
            .collect();
        assert_eq!(count_patches(4, 4, &set, false), 6);
        // wrapped: (0, 0), (3, 0) and (3, 3) join across both edges; the other three stay
        assert_eq!(count_patches(4, 4, &set, true), 4);
        assert_eq!(count_patches(4, 4, &[false; 16], true), 0);
        assert_eq!(count_patches(4, 4, &[true; 16], false), 1);
    }
}
