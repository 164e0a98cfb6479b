//! Conversions of Python inputs (numpy arrays, numbers) into the crate's types; errors name
//! the argument.

use super::monitor::to_pyerr;
use crate::model::contact_law::ContactLaw;
use crate::model::grid::Grid;
use crate::model::loading::ForceHistory;
use crate::model::settings::SolverOptions;
use crate::model::SceneArrays;
use crate::support::error::Error;
use numpy::ndarray::Dimension;
use numpy::{
    IntoPyArray, PyArray2, PyArrayMethods, PyReadonlyArray, PyReadonlyArray1, PyReadonlyArray2,
    PyUntypedArrayMethods,
};
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

/// The values of a float64 array in row-major order, copied once (any memory layout).
fn values<D: Dimension>(a: &PyReadonlyArray<'_, f64, D>) -> Vec<f64> {
    let mut out = Vec::with_capacity(a.len());
    huge_pages(&mut out);
    match a.as_slice() {
        Ok(s) => out.extend_from_slice(s),
        Err(_) => out.extend(a.as_array().iter().copied()),
    }
    out
}

/// Asks Linux to back the spare capacity of `v` with transparent huge pages, as numpy does
/// for its arrays: a height map of 4096^2 values is then written in 64 faults of 2 MiB, not
/// 32768 of 4 KiB (where the system's setting is "madvise"). Small buffers are left alone.
#[cfg(target_os = "linux")]
fn huge_pages(v: &mut Vec<f64>) {
    const PAGE: usize = 4096;
    const HUGE: usize = 2 << 20;
    const MADV_HUGEPAGE: std::ffi::c_int = 14;
    extern "C" {
        fn madvise(
            addr: *mut std::ffi::c_void,
            len: usize,
            advice: std::ffi::c_int,
        ) -> std::ffi::c_int;
    }
    let bytes = v.capacity() * std::mem::size_of::<f64>();
    if bytes < 4 * HUGE {
        return;
    }
    let start = v.as_mut_ptr() as usize;
    let aligned = start.next_multiple_of(PAGE);
    let len = (start + bytes - aligned) / PAGE * PAGE;
    // SAFETY: [aligned, aligned + len) lies inside the allocation of `v`, page-aligned; the
    // advice changes how its pages are backed, not their contents; failure is harmless.
    unsafe {
        madvise(aligned as *mut std::ffi::c_void, len, MADV_HUGEPAGE);
    }
}

/// Huge pages are a Linux hint; elsewhere nothing to do.
#[cfg(not(target_os = "linux"))]
fn huge_pages(_v: &mut Vec<f64>) {}

/// The [t, value] rows of a (k, 2) array of history samples, or InvalidInputError naming it.
fn samples(py: Python<'_>, a: &PyReadonlyArray2<'_, f64>, name: &str) -> PyResult<Vec<[f64; 2]>> {
    let shape = a.shape();
    if shape[1] != 2 {
        return Err(to_pyerr(
            py,
            Error::InvalidInput(format!(
                "scene: {name} samples must be a (k, 2) array of [t, value] rows, got shape {shape:?}"
            )),
        ));
    }
    Ok(values(a).chunks_exact(2).map(|s| [s[0], s[1]]).collect())
}

/// History samples ([t, value] rows) as a (k, 2) numpy array.
pub(crate) fn samples_array(
    py: Python<'_>,
    s: Vec<[f64; 2]>,
) -> PyResult<Bound<'_, PyArray2<f64>>> {
    let k = s.len();
    let flat: Vec<f64> = s.into_iter().flatten().collect();
    flat.into_pyarray(py).reshape([k, 2])
}

/// The arrays of a scene from the bindings' arguments (see `Scene.build`), each copied once.
pub(crate) fn scene_arrays(
    py: Python<'_>,
    heights: Option<PyReadonlyArray2<'_, f64>>,
    r: Option<PyReadonlyArray1<'_, f64>>,
    h: Option<PyReadonlyArray1<'_, f64>>,
    slope: Option<PyReadonlyArray1<'_, f64>>,
    force: Option<PyReadonlyArray2<'_, f64>>,
    depth: Option<PyReadonlyArray2<'_, f64>>,
) -> PyResult<SceneArrays> {
    let line = |a: Option<PyReadonlyArray1<'_, f64>>| a.map(|a| values(&a));
    Ok(SceneArrays {
        heights: heights.map(|a| {
            let shape = a.shape();
            ([shape[0], shape[1]], values(&a))
        }),
        r: line(r),
        h: line(h),
        slope: line(slope),
        force: force.map(|a| samples(py, &a, "force")).transpose()?,
        depth: depth.map(|a| samples(py, &a, "depth")).transpose()?,
    })
}
