//! The thread pool from Python: `set_num_threads` and `num_threads`.

use super::monitor::to_pyerr;
use pyo3::prelude::*;

/// Sets the worker threads of computations started from now on (n >= 1), or rayon's default
/// with None (`RAYON_NUM_THREADS`, else the available cores).
#[pyfunction]
#[pyo3(signature = (n=None))]
pub(crate) fn set_num_threads(py: Python<'_>, n: Option<usize>) -> PyResult<()> {
    crate::support::pool::set_num_threads(n).map_err(|e| to_pyerr(py, e))
}

/// The worker threads computations run on.
#[pyfunction]
pub(crate) fn num_threads(py: Python<'_>) -> PyResult<usize> {
    crate::support::pool::num_threads().map_err(|e| to_pyerr(py, e))
}
