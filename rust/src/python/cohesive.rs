//! Bindings of the static cohesive-zone BEM (`crate::bem::cohesive`): a depth-controlled load
//! curve and the pull-off of a retract, on a height array (free or a periodic cell).

use super::convert::{grid_from, options, slice1};
use super::monitor::{to_pyerr, PyMonitor};
use crate::bem::cohesive;
use crate::model::body::Body;
use crate::model::contact_law::ContactLaw;
use crate::model::grid::Grid;
use crate::model::settings::DENSE_LIMIT;
use crate::support::error::Error;
use numpy::{PyArray1, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::PyDict;

/// The cohesive law of a scene model's `contact` table in JSON, and the grid of the height
/// array `height` (m) with its footprint mask, element size `dx` (m), one period of a
/// periodic cell when `periodic`.
fn problem_from(
    py: Python<'_>,
    contact: &str,
    height: &PyReadonlyArray2<'_, f64>,
    allowed: &PyReadonlyArray2<'_, bool>,
    dx: f64,
    periodic: bool,
) -> PyResult<(ContactLaw, Grid)> {
    let law: ContactLaw = serde_json::from_str(contact).map_err(|e| {
        to_pyerr(
            py,
            Error::InvalidInput(format!("contact law {contact}: {e}")),
        )
    })?;
    let mut grid = grid_from(py, height, allowed, dx)?;
    if periodic {
        grid.body = Body::Periodic;
    }
    Ok((law, grid))
}

/// Depth-controlled static adhesive contact under the cohesive law `contact` (the scene
/// model's table as JSON): separation h (m), footprint mask, element size dx (m),
/// compliance (1/G, 1/Pa), the approaches `depths` (m) solved in turn, each warm-started
/// from the last (`cohesive::depth_curve`). With `periodic`, the grid is one period of a
/// periodic cell and a depth is the approach from the deflected surface's mean plane.
/// Returns a dict of arrays: depth (m), force (N), contact and zone (elements), energy (J),
/// sweeps and iterations.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, compliance, contact, depths, tol=1e-10, max_iter=5000, progress=None, periodic=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn cohesive_curve<'py>(
    py: Python<'py>,
    height: PyReadonlyArray2<'_, f64>,
    allowed: PyReadonlyArray2<'_, bool>,
    dx: f64,
    compliance: f64,
    contact: &str,
    depths: PyReadonlyArray1<'_, f64>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    periodic: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (law, grid) = problem_from(py, contact, &height, &allowed, dx, periodic)?;
    let depths = slice1(py, &depths, "depths")?;
    let opts = options(tol, max_iter, DENSE_LIMIT, None, true);
    let curve = PyMonitor::new(progress).run(py, |monitor| {
        cohesive::depth_curve(&grid, compliance, law, &depths, &opts, monitor)
    })?;
    let out = PyDict::new(py);
    let column = |f: &dyn Fn(&cohesive::CohesiveSummary) -> f64| -> Vec<f64> {
        curve.iter().map(f).collect()
    };
    out.set_item("depth", PyArray1::from_vec(py, column(&|s| s.depth)))?;
    out.set_item("force", PyArray1::from_vec(py, column(&|s| s.force)))?;
    out.set_item(
        "contact",
        PyArray1::from_vec(py, column(&|s| s.contact_count as f64)),
    )?;
    out.set_item(
        "zone",
        PyArray1::from_vec(py, column(&|s| s.zone_count as f64)),
    )?;
    out.set_item("energy", PyArray1::from_vec(py, column(&|s| s.energy)))?;
    out.set_item(
        "sweeps",
        PyArray1::from_vec(py, column(&|s| s.sweeps as f64)),
    )?;
    out.set_item(
        "iterations",
        PyArray1::from_vec(py, column(&|s| s.iterations as f64)),
    )?;
    Ok(out)
}

/// The pull-off of a depth-controlled approach to `d_max` and retract to `d_min` (m) in
/// `steps` steps each under the cohesive law `contact` (JSON), refined around the least
/// force (`cohesive::pull_off`); arguments as `cohesive_curve`. Returns a dict: force (N,
/// tensile: negative), depth (m), contact and zone (elements there), solves.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, compliance, contact, d_max, d_min, steps=30, tol=1e-10, max_iter=5000, progress=None, periodic=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn cohesive_pull_off<'py>(
    py: Python<'py>,
    height: PyReadonlyArray2<'_, f64>,
    allowed: PyReadonlyArray2<'_, bool>,
    dx: f64,
    compliance: f64,
    contact: &str,
    d_max: f64,
    d_min: f64,
    steps: usize,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    periodic: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let (law, grid) = problem_from(py, contact, &height, &allowed, dx, periodic)?;
    let opts = options(tol, max_iter, DENSE_LIMIT, None, true);
    let r = PyMonitor::new(progress).run(py, |monitor| {
        cohesive::pull_off(&grid, compliance, law, d_max, d_min, steps, &opts, monitor)
    })?;
    let out = PyDict::new(py);
    out.set_item("force", r.force)?;
    out.set_item("depth", r.depth)?;
    out.set_item("contact", r.at.contact_count)?;
    out.set_item("zone", r.at.zone_count)?;
    out.set_item("solves", r.solves)?;
    Ok(out)
}
