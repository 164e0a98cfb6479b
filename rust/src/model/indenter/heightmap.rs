//! Height maps: a rigid surface given by its heights on a grid of square elements, a rough
//! surface measured or generated, or any shape sampled. The map fixes the BEM grid; it has
//! no axis and no MDR profile.
//!
//! Heights are the rigid surface's (m, any sign, row-major (ny, nx)): the highest point
//! touches first, and depths are measured from there. Element centres lie symmetric about
//! the origin, x_i = (i - (nx - 1) / 2) dx.
//!
//! A periodic map is one cell of a periodic surface, solved with the periodic half-space
//! (`periodic.rs`): a force is the total on the cell (mean pressure times the cell area),
//! deflections have zero mean over the cell, and the depth is the approach of the highest
//! point from the deflected surface's mean plane, so that the mean gap (the mean
//! separation) is the mean height below the highest point minus the depth.

use crate::model::body::Body;
use crate::model::grid::Grid;
use crate::model::settings::Method;
use crate::support::error::{check_finite, check_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// A height map's scene-model table: heights as rows (each of nx values, ny rows), element
/// side `dx` (m), and whether the map is one cell of a periodic surface.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct HeightMapTable {
    /// Heights (m), ny rows of nx values.
    pub heights: Vec<Vec<f64>>,
    /// Element side (m).
    pub dx: f64,
    /// Whether the map is one cell of a periodic surface.
    #[serde(default)]
    pub periodic: bool,
}

/// A validated height map.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    nx: usize,
    ny: usize,
    dx: f64,
    heights: Vec<f64>,
    periodic: bool,
}

impl TryFrom<HeightMapTable> for HeightMap {
    type Error = Error;

    fn try_from(t: HeightMapTable) -> Result<Self> {
        let ny = t.heights.len();
        let nx = t.heights.first().map_or(0, Vec::len);
        if let Some(k) = t.heights.iter().position(|row| row.len() != nx) {
            return Err(Error::InvalidInput(format!(
                "height map: every row needs the first row's {nx} values, row {k} has {}",
                t.heights[k].len()
            )));
        }
        HeightMap::new(ny, nx, t.heights.concat(), t.dx, t.periodic)
    }
}

impl HeightMap {
    /// A map of `ny` rows and `nx` columns of heights (m, row-major) on elements of side
    /// `dx` (m), validated: not empty, every height finite, dx > 0.
    pub fn new(ny: usize, nx: usize, heights: Vec<f64>, dx: f64, periodic: bool) -> Result<Self> {
        if nx == 0 || ny == 0 {
            return Err(Error::InvalidInput(format!(
                "height map: the heights are empty (shape ({ny}, {nx})); give a 2-D array of at least one value"
            )));
        }
        if heights.len() != nx * ny {
            return Err(Error::InvalidInput(format!(
                "height map: shape ({ny}, {nx}) needs {} heights, got {}",
                nx * ny,
                heights.len()
            )));
        }
        check_positive("height map dx", dx)?;
        check_finite("height map heights", &heights)?;
        Ok(HeightMap {
            nx,
            ny,
            dx,
            heights,
            periodic,
        })
    }

    /// The map's table (heights as rows).
    pub fn table(&self) -> HeightMapTable {
        HeightMapTable {
            heights: self.heights.chunks(self.nx).map(<[f64]>::to_vec).collect(),
            dx: self.dx,
            periodic: self.periodic,
        }
    }

    /// Shape (ny, nx).
    pub fn shape(&self) -> [usize; 2] {
        [self.ny, self.nx]
    }

    /// Element side (m).
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// Heights (m), row-major (ny, nx).
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }

    /// Whether the map is one cell of a periodic surface.
    pub fn periodic(&self) -> bool {
        self.periodic
    }

    /// The body the map presses into: a periodic cell for a periodic map, a free half-space
    /// otherwise.
    pub fn body(&self) -> Body {
        if self.periodic {
            Body::Periodic
        } else {
            Body::HalfSpace
        }
    }

    /// The resolution `n` of a run on the map: its longer side, in elements.
    pub fn n(&self) -> usize {
        self.nx.max(self.ny)
    }

    /// Side lengths (m) along x and y.
    pub fn sides(&self) -> (f64, f64) {
        (self.nx as f64 * self.dx, self.ny as f64 * self.dx)
    }

    /// Fails unless a run by `method` at resolution `n` can solve the map: BEM, with n the
    /// map's own (the map fixes the grid).
    pub fn check_run(&self, method: Method, n: usize) -> Result<()> {
        if method == Method::Mdr {
            return Err(Error::InvalidInput(
                "MDR needs an axisymmetric indenter; a height map is solved by BEM (method \"bem\")"
                    .into(),
            ));
        }
        if n != self.n() {
            return Err(Error::InvalidInput(format!(
                "a height map fixes the BEM grid ({} x {} elements, n = {}): give n = {} or none, got n = {n}",
                self.ny,
                self.nx,
                self.n(),
                self.n()
            )));
        }
        Ok(())
    }

    /// The BEM grid: the map's elements, every one allowed to touch, with heights measured
    /// down from the highest point (m, >= 0); a periodic cell for a periodic map.
    pub fn grid(&self) -> Result<Grid> {
        let top = self.top();
        let mut grid = Grid::new(
            self.nx,
            self.ny,
            self.dx,
            self.heights.iter().map(|h| top - h).collect(),
            vec![true; self.nx * self.ny],
        )?;
        grid.body = self.body();
        Ok(grid)
    }

    /// The highest height (m).
    pub fn top(&self) -> f64 {
        self.heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The error of an axisymmetric quantity (`what`) asked of a height map.
pub fn not_axisymmetric(what: &str) -> Error {
    Error::InvalidInput(format!(
        "a height map is not axisymmetric: it has no {what}; solve it by BEM"
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(heights: Vec<Vec<f64>>) -> HeightMapTable {
        HeightMapTable {
            heights,
            dx: 0.5,
            periodic: false,
        }
    }

    /// The grid measures heights down from the highest point; the table round-trips.
    #[test]
    fn grid_heights_fall_from_the_highest_point() {
        let map =
            HeightMap::try_from(table(vec![vec![1.0, -2.0, 0.5], vec![3.0, 0.0, 1.0]])).unwrap();
        assert_eq!((map.shape(), map.n()), ([2, 3], 3));
        let g = map.grid().unwrap();
        assert_eq!((g.nx, g.ny), (3, 2));
        assert_eq!(g.height, vec![2.0, 5.0, 2.5, 0.0, 3.0, 2.0]);
        assert_eq!(HeightMap::try_from(map.table()).unwrap(), map);
    }

    #[test]
    fn bad_maps_and_runs_are_refused_naming_what() {
        let refused = |t: HeightMapTable, word: &str| {
            let e = HeightMap::try_from(t).unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        };
        refused(table(vec![]), "empty");
        refused(table(vec![vec![]]), "empty");
        refused(table(vec![vec![1.0, 2.0], vec![1.0]]), "row 1");
        refused(table(vec![vec![1.0, f64::NAN]]), "finite");
        let mut t = table(vec![vec![1.0]]);
        t.dx = 0.0;
        refused(t, "dx");
        let map = HeightMap::try_from(table(vec![vec![0.0; 4]; 2])).unwrap();
        assert!(map.check_run(Method::Bem, 4).is_ok());
        let e = map.check_run(Method::Bem, 8).unwrap_err().to_string();
        assert!(e.contains("n = 4"), "{e}");
        let e = map.check_run(Method::Mdr, 4).unwrap_err().to_string();
        assert!(e.contains("MDR"), "{e}");
    }
}
