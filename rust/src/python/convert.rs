//! Conversions of Python inputs (numpy arrays, numbers) into the crate's types; errors name
//! the argument.

use super::monitor::to_pyerr;
use crate::model::contact_law::ContactLaw;
use crate::model::grid::Grid;
use crate::model::loading::ForceHistory;
use crate::model::settings::SolverOptions;
use crate::support::error::Error;
use numpy::{PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;

/// A contiguous float64 array as a Vec, or InvalidInputError naming it.
pub(crate) fn slice1(
    py: Python<'_>,
    a: &PyReadonlyArray1<'_, f64>,
    name: &str,
) -> PyResult<Vec<f64>> {
    a.as_slice().map(<[f64]>::to_vec).map_err(|_| {
        to_pyerr(
            py,
            Error::InvalidInput(format!("{name} must be a contiguous float64 array")),
        )
    })
}

/// The grid of a height map (m, (ny, nx)) with its footprint mask and element size (m).
pub(crate) fn grid_from(
    py: Python<'_>,
    height: &PyReadonlyArray2<'_, f64>,
    allowed: &PyReadonlyArray2<'_, bool>,
    dx: f64,
) -> PyResult<Grid> {
    let shape = height.shape();
    let (ny, nx) = (shape[0], shape[1]);
    if allowed.shape() != shape {
        return Err(to_pyerr(
            py,
            Error::InvalidInput(format!(
                "footprint mask shape {:?} differs from height map shape {:?}",
                allowed.shape(),
                shape
            )),
        ));
    }
    let h = height.as_array().iter().copied().collect();
    let a = allowed.as_array().iter().copied().collect();
    Grid::new(nx, ny, dx, h, a).map_err(|e| to_pyerr(py, e))
}

/// Contact-solver options from the binding's keyword arguments.
pub(crate) fn options(
    tol: f64,
    max_iter: usize,
    dense_limit: usize,
    active_limit: Option<usize>,
    precondition: bool,
) -> SolverOptions {
    SolverOptions {
        tol,
        max_iter,
        dense_limit,
        active_limit,
        precondition,
    }
}

/// A force history from samples (s, N).
pub(crate) fn history(py: Python<'_>, times: Vec<f64>, forces: Vec<f64>) -> PyResult<ForceHistory> {
    // the array-level solvers press with hard contact
    forces
        .iter()
        .try_for_each(|&f| ContactLaw::Hard.check_force(f))
        .and_then(|()| ForceHistory::piecewise_linear(times, forces))
        .map_err(|e| to_pyerr(py, e))
}
