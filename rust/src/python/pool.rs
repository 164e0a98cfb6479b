//! The thread pool from Python: `set_num_threads` and `num_threads`.

use super::monitor::to_pyerr;
use pyo3::prelude::*;

/// Sets the worker threads of computations started from now on (an integer from 1 to a few
/// times the cores), or rayon's default with None (`RAYON_NUM_THREADS`, else the available
/// cores).
#[pyfunction]
#[pyo3(signature = (n=None))]
pub(crate) fn set_num_threads(py: Python<'_>, n: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
    let count = match n {
        None => None,
        Some(v) => Some(thread_count(v).map_err(|e| to_pyerr(py, e))?),
    };
    crate::support::pool::set_num_threads(count).map_err(|e| to_pyerr(py, e))
}

/// A thread count from a Python integer (not a bool, a float or a string); negative and
/// huge ones are refused with the bounds.
fn thread_count(v: &Bound<'_, PyAny>) -> crate::Result<usize> {
    let refuse = |what: String| {
        crate::Error::InvalidInput(format!(
            "the number of threads must be an integer from 1 to {}, got {what}",
            crate::support::pool::max_threads()
        ))
    };
    let shown = || v.repr().map_or_else(|_| "?".into(), |r| r.to_string());
    if v.is_instance_of::<pyo3::types::PyBool>() || !v.is_instance_of::<pyo3::types::PyInt>() {
        return Err(refuse(shown()));
    }
    match v.extract::<i64>() {
        Ok(k) if k >= 1 => usize::try_from(k).map_err(|_| refuse(shown())),
        _ => Err(refuse(shown())),
    }
}

/// The worker threads computations run on.
#[pyfunction]
pub(crate) fn num_threads(py: Python<'_>) -> PyResult<usize> {
    crate::support::pool::num_threads().map_err(|e| to_pyerr(py, e))
}
