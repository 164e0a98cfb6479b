//! Array-level bindings: the surface operator, static and viscous contact of any height
//! map, the flat punch, and the inverse MDR transforms. Numpy in; typed reports or arrays
//! out.

use super::convert::{grid_from, history, options, slice1};
use super::monitor::{in_pool, to_pyerr, PyMonitor};
use super::report::PyReport;
use crate::bem::contact::Target;
use crate::bem::static_contact;
use crate::bem::viscous::Fields;
use crate::bem::viscous::{self, ViscousRequest};
use crate::halfspace::operator::{DenseOperator, FftOperator, SurfaceOperator};
use crate::mdr::transforms;
use crate::model::body::Body;
use crate::model::grid::Grid;
use crate::model::settings::ExplicitControl;
use crate::model::settings::DENSE_LIMIT;
use crate::model::{Integrator, Method, RunSettings};
use crate::run::assemble::{bem_report, bem_static_report, report_from, Wanted};
use crate::run::report::FieldSet;
use crate::run::viscous_bem;
use crate::stepping::Series;
use crate::support::error::{check_finite, Error};
use numpy::{
    IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use std::sync::Mutex;
use std::time::Instant;

/// Settings of a BEM run on a given grid (n: its longer side).
fn grid_settings(grid: &Grid, solver: crate::model::settings::SolverOptions) -> RunSettings {
    let mut s = RunSettings::new(Method::Bem, grid.nx.max(grid.ny));
    s.solver = solver;
    s
}

/// Element-centre coordinates (m) of `m` elements of size dx, symmetric about 0.
/// The body of the array API's `periodic` flag.
fn body_of(periodic: bool) -> Body {
    if periodic {
        Body::Periodic
    } else {
        Body::HalfSpace
    }
}

fn centres(m: usize, dx: f64) -> Vec<f64> {
    (0..m)
        .map(|i| (i as f64 - 0.5 * (m as f64 - 1.0)) * dx)
        .collect()
}

/// Implicit (or, with `explicit` = (step, area_change, start), the paper's explicit) viscous
/// BEM run on a height map (m, (ny, nx)) with footprint mask, element size dx (m),
/// viscosity eta (Pa s), output times (s) and force history samples (s, N); fields at the
/// output indices `fields_at`.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, eta, times, force_times, force_values, rates=false, fields_at=vec![], tol=1e-10, max_iter=5000, progress=None, explicit=None, dense_limit=DENSE_LIMIT, depth_bounds=None, active_limit=None, precondition=true))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bem_viscous(
    py: Python<'_>,
    height: PyReadonlyArray2<'_, f64>,
    allowed: PyReadonlyArray2<'_, bool>,
    dx: f64,
    eta: f64,
    times: PyReadonlyArray1<'_, f64>,
    force_times: PyReadonlyArray1<'_, f64>,
    force_values: PyReadonlyArray1<'_, f64>,
    rates: bool,
    fields_at: Vec<usize>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    explicit: Option<(f64, f64, f64)>,
    dense_limit: usize,
    depth_bounds: Option<Vec<f64>>,
    active_limit: Option<usize>,
    precondition: bool,
) -> PyResult<PyReport> {
    let start = Instant::now();
    let grid = grid_from(py, &height, &allowed, dx)?;
    let hist = history(
        py,
        slice1(py, &force_times, "force_times")?,
        slice1(py, &force_values, "force_values")?,
    )?;
    let times = slice1(py, &times, "times")?;
    if let Some(&k) = fields_at.iter().find(|&&k| k >= times.len()) {
        return Err(to_pyerr(
            py,
            Error::InvalidInput(format!(
                "field output index {k} is out of range for {} output times",
                times.len()
            )),
        ));
    }
    let request = ViscousRequest {
        times: times.clone(),
        rates,
        fields_at: fields_at.clone(),
        depth_bounds: depth_bounds.unwrap_or_default(),
    };
    let mut settings = grid_settings(
        &grid,
        options(tol, max_iter, dense_limit, active_limit, precondition),
    );
    if let Some((step, area_change, start)) = explicit {
        settings.integrator = Integrator::Explicit(ExplicitControl {
            step,
            area_change,
            start,
        });
    }
    let s = PyMonitor::new(progress).run(py, |monitor| {
        viscous_bem(&grid, eta, &hist, &request, &settings, monitor)
    })?;
    let all = !fields_at.is_empty();
    let wanted = Wanted {
        velocity: rates,
        stiffness_length: rates,
        pressure: all,
        surface_velocity: all,
        deflection: all,
        ..Wanted::default()
    };
    let fields: Vec<(f64, usize)> = fields_at.iter().map(|&k| (times[k], k)).collect();
    let integrator = settings.integrator.name();
    let mut inner = bem_report(&settings, &grid, integrator, s, wanted, &fields);
    inner.wall_time = start.elapsed().as_secs_f64();
    Ok(PyReport::from(inner))
}

/// Flat punch on the footprint mask pressed by `force` (N) into a viscous half-space of
/// viscosity eta (Pa s): velocity, stiffness length, central pressure, and the pressure
/// field (with `margin`, the surface velocity on a grid extended by that many elements).
#[pyfunction]
#[pyo3(signature = (allowed, dx, eta, force, margin=None, tol=1e-10, max_iter=5000, progress=None, dense_limit=DENSE_LIMIT, precondition=true))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn bem_punch(
    py: Python<'_>,
    allowed: PyReadonlyArray2<'_, bool>,
    dx: f64,
    eta: f64,
    force: f64,
    margin: Option<usize>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    dense_limit: usize,
    precondition: bool,
) -> PyResult<PyReport> {
    let start = Instant::now();
    let shape = allowed.shape().to_vec();
    let zeros = vec![0.0; shape[0] * shape[1]];
    let mask = allowed.as_array().iter().copied().collect();
    let grid = Grid::new(shape[1], shape[0], dx, zeros, mask).map_err(|e| to_pyerr(py, e))?;
    let settings = grid_settings(
        &grid,
        options(tol, max_iter, dense_limit, None, precondition),
    );
    let r = PyMonitor::new(progress).run(py, |monitor| {
        viscous::run_punch(&grid, eta, force, margin, &settings.solver, monitor)
    })?;
    let area = grid.allowed.iter().filter(|&&a| a).count() as f64 * dx * dx;
    let mut s: Series<Fields> = Series {
        t: vec![0.0],
        depth: vec![0.0],
        force: vec![force],
        contact_length: vec![2.0 * (area / std::f64::consts::PI).sqrt()],
        area: vec![area],
        velocity: vec![r.velocity],
        stiffness_length: vec![r.damping / (4.0 * eta)],
        iterations: vec![r.iterations],
        residual: vec![r.residual],
        solves: 1,
        ..Series::default()
    };
    let rates = Wanted {
        velocity: true,
        stiffness_length: true,
        ..Wanted::default()
    };
    let mut out = report_from(&settings, dx, "one solve", &mut s, rates);
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.fields.push(FieldSet {
        t: 0.0,
        x: Some(centres(grid.nx, dx)),
        y: Some(centres(grid.ny, dx)),
        pressure: Some(r.pressure),
        x_extended: margin.map(|m| centres(grid.nx + 2 * m, dx)),
        surface_velocity: r.surface_velocity,
        ..FieldSet::default()
    });
    out.wall_time = start.elapsed().as_secs_f64();
    Ok(PyReport::from(out))
}

/// An inverse MDR transform: (1D data, dx, radii) -> 3D values at the radii.
type RadialTransform = fn(&[f64], f64, &[f64]) -> crate::Result<Vec<f64>>;

/// Applies the inverse transform `f` to the named 1D data at radii `r`, numpy out.
fn radial<'py>(
    py: Python<'py>,
    f: RadialTransform,
    (values, name): (&PyReadonlyArray1<'py, f64>, &str),
    dx: f64,
    r: &PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    let out =
        f(&slice1(py, values, name)?, dx, &slice1(py, r, "r")?).map_err(|e| to_pyerr(py, e))?;
    Ok(out.into_pyarray(py))
}

/// Inverse MDR transform: 3D pressure (Pa) at radii r (m) from the line load q (N/m) of
/// elements spaced dx (m).
#[pyfunction]
pub(crate) fn mdr_pressure<'py>(
    py: Python<'py>,
    q: PyReadonlyArray1<'py, f64>,
    dx: f64,
    r: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    radial(py, transforms::pressure_from_line_load, (&q, "q"), dx, &r)
}

/// Inverse MDR transform: 3D surface deflection (or rate) at radii r (m) outside the
/// contact from 1D displacements (or velocities) w of elements spaced dx (m).
#[pyfunction]
pub(crate) fn mdr_deflection<'py>(
    py: Python<'py>,
    w: PyReadonlyArray1<'py, f64>,
    dx: f64,
    r: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    radial(py, transforms::deflection_outside, (&w, "w"), dx, &r)
}

/// Surface deflection (m) of a half-space with G = 1 Pa under element pressures p (Pa),
/// (ny, nx), by the DC-FFT operator or (`dense=True`) the dense faer matrix.
#[pyfunction]
#[pyo3(signature = (p, dx, dense=false))]
pub(crate) fn surface_deflection<'py>(
    py: Python<'py>,
    p: PyReadonlyArray2<'py, f64>,
    dx: f64,
    dense: bool,
) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
    let shape = [p.shape()[0], p.shape()[1]];
    let pv: Vec<f64> = p.as_array().iter().copied().collect();
    let r = in_pool(py, || -> crate::Result<Vec<f64>> {
        let mut u = vec![0.0; pv.len()];
        if dense {
            DenseOperator::new(shape[1], shape[0], dx)?.apply(&pv, &mut u);
        } else {
            FftOperator::new(shape[1], shape[0], dx)?.apply(&pv, &mut u);
        }
        Ok(u)
    })?;
    let u = r.map_err(|e| to_pyerr(py, e))?;
    u.into_pyarray(py).reshape(shape)
}

/// The surface operator of an `nx` x `ny` grid of square elements of side `dx` (m), built
/// once (kernel spectrum, FFT plans, buffers) and applied many times: `apply(p)` maps
/// element pressures (Pa, shape (ny, nx)) to element-centre deflections (m) of an
/// incompressible half-space with G = 1 Pa (divide by G, or by eta for rates). Non-periodic:
/// Love's coefficients by DC-FFT; `periodic`: the periodic cell's spectral kernel
/// (`PeriodicOperator`, zero-mean deflections).
///
/// One operator may be used from several threads: its buffers are behind a lock, so calls
/// from different threads run one after the other.
#[pyclass(name = "SurfaceOperator", module = "mdrvisc._core", frozen)]
pub(crate) struct PySurfaceOperator {
    op: Mutex<Box<dyn SurfaceOperator + Send>>,
    /// (ny, nx) of the grid.
    shape: [usize; 2],
    /// Element side (m).
    dx: f64,
    /// FFT sizes (y, x): zero-padded, or the grid's own for a periodic cell.
    padded: (usize, usize),
    /// Whether the grid is a periodic cell.
    periodic: bool,
}

impl PySurfaceOperator {
    /// Applies the operator on the crate's pool, the GIL released. The lock is taken on the
    /// calling thread before the pool is entered: a worker waiting for the lock could
    /// otherwise be the one the holder's parallel loop needs. A poisoned lock still holds
    /// valid buffers (each apply overwrites them).
    fn apply_locked(&self, py: Python<'_>, p: &[f64], u: &mut [f64]) -> PyResult<()> {
        py.detach(|| {
            let mut guard = self.op.lock().unwrap_or_else(|e| e.into_inner());
            let op: &mut (dyn SurfaceOperator + Send) = &mut **guard;
            crate::support::pool::run(|| op.apply(p, u))?;
            // pressures and element sizes near the range of physical inputs can overflow
            crate::support::error::check_finite("deflection K[p] (overflows double precision)", u)
        })
        .map_err(|e| to_pyerr(py, e))
    }
}

#[pymethods]
impl PySurfaceOperator {
    #[new]
    #[pyo3(signature = (nx, ny, dx, periodic=false))]
    fn new(py: Python<'_>, nx: usize, ny: usize, dx: f64, periodic: bool) -> PyResult<Self> {
        let built = py.detach(|| -> crate::Result<(Box<dyn SurfaceOperator + Send>, _)> {
            let op = body_of(periodic).operator(nx, ny, dx)?;
            let (mx, my) = op.fft_size();
            Ok((Box::new(op), (my, mx)))
        });
        let (op, padded) = built.map_err(|e| to_pyerr(py, e))?;
        Ok(PySurfaceOperator {
            shape: [op.ny(), op.nx()],
            dx: op.dx(),
            padded,
            periodic,
            op: Mutex::new(op),
        })
    }

    /// K[p] (m) for pressures `p` (Pa, (ny, nx) float64), with the GIL released; written
    /// into `out` (a C-contiguous (ny, nx) float64 array) when given, else a new array.
    #[pyo3(signature = (p, out=None))]
    fn apply<'py>(
        &self,
        py: Python<'py>,
        p: PyReadonlyArray2<'py, f64>,
        out: Option<Bound<'py, numpy::PyArray2<f64>>>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let shape = self.shape;
        let bad_shape = |what: &str, got: &[usize]| {
            to_pyerr(
                py,
                Error::InvalidInput(format!(
                    "{what} must have shape {shape:?} (ny, nx), got {got:?}"
                )),
            )
        };
        if p.shape() != shape {
            return Err(bad_shape("pressure", p.shape()));
        }
        let copied;
        let pv = match p.as_slice() {
            Ok(s) if p.is_c_contiguous() => s,
            _ => {
                copied = p.as_array().iter().copied().collect::<Vec<f64>>();
                &copied
            }
        };
        check_finite("pressure", pv).map_err(|e| to_pyerr(py, e))?;
        match out {
            Some(out) => {
                if out.shape() != shape {
                    return Err(bad_shape("out", out.shape()));
                }
                if !out.is_c_contiguous() {
                    return Err(to_pyerr(
                        py,
                        Error::InvalidInput("out must be C-contiguous and writable".into()),
                    ));
                }
                {
                    // fails (instead of panicking) on a read-only array and on one that is
                    // also the pressure
                    let mut rw = out.try_readwrite().map_err(|_| {
                        to_pyerr(
                            py,
                            Error::InvalidInput(
                                "out must be writable and must not be the pressure array".into(),
                            ),
                        )
                    })?;
                    let u = rw.as_slice_mut().map_err(|_| {
                        to_pyerr(
                            py,
                            Error::InvalidInput("out must be C-contiguous and writable".into()),
                        )
                    })?;
                    self.apply_locked(py, pv, u)?;
                }
                Ok(out)
            }
            None => {
                let mut u = vec![0.0; pv.len()];
                self.apply_locked(py, pv, &mut u)?;
                u.into_pyarray(py).reshape(shape)
            }
        }
    }

    /// Grid shape (ny, nx).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.shape[0], self.shape[1])
    }

    /// Element side (m).
    #[getter]
    fn dx(&self) -> f64 {
        self.dx
    }

    /// FFT sizes (y, x): zero-padded, or the grid's own for a periodic cell.
    #[getter]
    fn padded(&self) -> (usize, usize) {
        self.padded
    }

    /// Whether the grid is a periodic cell.
    #[getter]
    fn periodic(&self) -> bool {
        self.periodic
    }
}

/// Static contact solve: separation h (m), footprint mask, element size dx (m), compliance
/// (1/G, 1/Pa), and either `force` (N) or `depth` (m). The solve runs on the window that can
/// touch (`static_contact::solve`): the elements with h <= depth, or under force control
/// those with h plus a lower bound of the deflection <= `depth_bound` (m; the whole grid
/// without one). `deflection=False` leaves the deflection field out, which spares a
/// whole-grid operator when the window is smaller. With `periodic`, the grid is one period
/// of a periodic cell, solved whole (`static_contact::solve_periodic`): `force` is the total
/// on the cell, `depth` the approach from the deflected surface's mean plane (mean
/// separation mean(h) - depth, > 0), and `depth_bound` is refused.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, compliance, force=None, depth=None, tol=1e-10, max_iter=5000, progress=None, dense_limit=DENSE_LIMIT, active_limit=None, precondition=true, depth_bound=None, deflection=true, periodic=false))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn contact_solve(
    py: Python<'_>,
    height: PyReadonlyArray2<'_, f64>,
    allowed: PyReadonlyArray2<'_, bool>,
    dx: f64,
    compliance: f64,
    force: Option<f64>,
    depth: Option<f64>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    dense_limit: usize,
    active_limit: Option<usize>,
    precondition: bool,
    depth_bound: Option<f64>,
    deflection: bool,
    periodic: bool,
) -> PyResult<PyReport> {
    let start = Instant::now();
    let mut grid = grid_from(py, &height, &allowed, dx)?;
    grid.body = body_of(periodic);
    let target = match (force, depth) {
        (Some(f), None) => Target::Force(f),
        (None, Some(d)) => Target::Depth(d),
        _ => {
            return Err(to_pyerr(
                py,
                Error::InvalidInput("give exactly one of force and depth".into()),
            ))
        }
    };
    let settings = grid_settings(
        &grid,
        options(tol, max_iter, dense_limit, active_limit, precondition),
    );
    let r = PyMonitor::new(progress).run(py, |monitor| {
        let req = static_contact::StaticRequest {
            depth_bound,
            deflection,
            ..static_contact::StaticRequest::to(target)
        };
        static_contact::solve(&grid, compliance, req, &settings.solver, monitor)
    })?;
    let force = r.summary.force;
    let wanted = Wanted {
        pressure: true,
        deflection,
        ..Wanted::default()
    };
    let mut inner = bem_static_report(&settings, &grid, force, r, wanted);
    if periodic {
        // a periodic cell has no edge
        inner.at_edge = Some(vec![false]);
    }
    inner.wall_time = start.elapsed().as_secs_f64();
    Ok(PyReport::from(inner))
}
