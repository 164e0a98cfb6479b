//! pyo3 bindings (cargo feature "python"): numpy in, dicts of numpy arrays out. The GIL is
//! released during computations, which run on a rayon worker (their parallel loops then split
//! without waking the calling thread each time); the calling thread serves Ctrl-C meanwhile,
//! and progress callbacks are served between chunks of work.

use crate::contact::{SolverOptions, Target, DENSE_LIMIT};
use crate::error::check_finite;
use crate::error::Error;
use crate::grid::Grid;
use crate::integrator::ExplicitControl;
use crate::loading::{DepthHistory, ForceHistory, Loading};
use crate::mdr::{self, Foundation, Medium};
use crate::monitor::Monitor;
use crate::operator::{DenseOperator, FftOperator, SurfaceOperator};
use crate::rheology::Rheology;
use crate::static_contact;
use crate::transforms;
use crate::viscoelastic;
use crate::viscous::{self, ViscousRequest};
use numpy::{
    IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{self, RecvTimeoutError};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// Raises the matching exception class of `mdrvisc.errors`.
fn to_pyerr(py: Python<'_>, e: Error) -> PyErr {
    let errors = match py.import("mdrvisc.errors") {
        Ok(m) => m,
        Err(err) => return err,
    };
    let msg = e.to_string();
    let made = match &e {
        Error::InvalidInput(_) => errors
            .getattr("InvalidInputError")
            .and_then(|c| c.call1((msg,))),
        Error::NotConverged {
            iterations,
            residual,
            ..
        } => errors
            .getattr("ConvergenceError")
            .and_then(|c| c.call1((msg, *iterations, *residual))),
        Error::Domain(_) => errors.getattr("DomainError").and_then(|c| c.call1((msg,))),
        Error::Interrupted => return pyo3::exceptions::PyKeyboardInterrupt::new_err(msg),
    };
    match made {
        Ok(obj) => PyErr::from_value(obj),
        Err(err) => err,
    }
}

/// Serves an optional Python callback `progress(stage, done, total)` at most every 200 ms
/// (and at the end of each stage), and stops the computation when the callback raises or
/// the calling thread caught a signal (`run`).
struct PyMonitor {
    callback: Option<Py<PyAny>>,
    last: Instant,
    error: Option<PyErr>,
    cancel: Arc<AtomicBool>,
}

impl PyMonitor {
    fn new(callback: Option<Py<PyAny>>) -> Self {
        PyMonitor {
            callback,
            last: Instant::now(),
            error: None,
            cancel: Arc::new(AtomicBool::new(false)),
        }
    }

    /// Runs `f` with this monitor on a rayon worker, the GIL released, while the calling
    /// thread waits for it and checks for signals (Ctrl-C) every 50 ms; a signal stops `f` at
    /// its next progress report (on a worker already, `f` runs in place). Returns f's result,
    /// or the Python exception that stopped it.
    fn run<T: Send>(
        mut self,
        py: Python<'_>,
        f: impl FnOnce(&mut PyMonitor) -> crate::Result<T> + Send,
    ) -> PyResult<T> {
        if rayon::current_thread_index().is_some() {
            // Called from a worker (a progress callback that runs mdrvisc): run in place, as
            // waiting on this thread for a job of the same pool could deadlock.
            let r = py.detach(|| f(&mut self));
            return self.finish(py, r);
        }
        let cancel = Arc::clone(&self.cancel);
        let monitor = &mut self;
        let (r, signal) = py.detach(|| {
            let (tx, rx) = mpsc::channel();
            let mut signal = None;
            let r = rayon::in_place_scope(|s| {
                s.spawn(move |_| {
                    // The receiver outlives the scope: the send cannot fail.
                    let _ = tx.send(f(monitor));
                });
                loop {
                    match rx.recv_timeout(Duration::from_millis(50)) {
                        Ok(r) => break r,
                        Err(RecvTimeoutError::Timeout) if signal.is_none() => {
                            if let Err(e) = Python::attach(|py| py.check_signals()) {
                                cancel.store(true, Ordering::Relaxed);
                                signal = Some(e);
                            }
                        }
                        Err(RecvTimeoutError::Timeout) => {}
                        // The job panicked: the scope re-raises the panic when it ends.
                        Err(RecvTimeoutError::Disconnected) => break Err(Error::Interrupted),
                    }
                }
            });
            (r, signal)
        });
        match signal {
            Some(e) => Err(e),
            None => self.finish(py, r),
        }
    }

    /// Converts the computation's result, preferring the Python exception that stopped it.
    fn finish<T>(self, py: Python<'_>, r: crate::Result<T>) -> PyResult<T> {
        match (r, self.error) {
            (Err(_), Some(e)) => Err(e),
            (r, _) => r.map_err(|e| to_pyerr(py, e)),
        }
    }
}

impl Monitor for PyMonitor {
    fn progress(&mut self, stage: &str, done: usize, total: usize) -> crate::Result<()> {
        if self.cancel.load(Ordering::Relaxed) {
            return Err(Error::Interrupted);
        }
        if done < total && self.last.elapsed() < Duration::from_millis(200) {
            return Ok(());
        }
        self.last = Instant::now();
        let outcome = Python::attach(|py| -> PyResult<()> {
            py.check_signals()?;
            if let Some(cb) = &self.callback {
                cb.call1(py, (stage, done, total))?;
            }
            Ok(())
        });
        outcome.map_err(|e| {
            self.error = Some(e);
            Error::Interrupted
        })
    }
}

/// Runs `f` on a rayon worker with the GIL released and waits for it: its parallel loops
/// then split among the workers without waking the calling thread each time (for short
/// computations that serve no progress callback; the others use `PyMonitor::run`).
fn in_pool<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> T {
    py.detach(|| rayon::join(f, || ()).0)
}

fn slice1(a: &PyReadonlyArray1<'_, f64>, name: &str) -> PyResult<Vec<f64>> {
    a.as_slice().map(<[f64]>::to_vec).map_err(|_| {
        pyo3::exceptions::PyValueError::new_err(format!(
            "{name} must be a contiguous float64 array"
        ))
    })
}

fn grid_from(
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

/// Explicit-loop controls from (step, area_change, start).
fn explicit_control((step, area_change, start): (f64, f64, f64)) -> ExplicitControl {
    ExplicitControl {
        step,
        area_change,
        start,
    }
}

fn options(
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

fn history(py: Python<'_>, times: Vec<f64>, forces: Vec<f64>) -> PyResult<ForceHistory> {
    ForceHistory::piecewise_linear(times, forces).map_err(|e| to_pyerr(py, e))
}

/// Implicit viscous BEM run on a grid: heights (m, (ny, nx)), footprint mask, element size
/// dx (m), viscosity eta (Pa s), output times (s), force history samples (s, N).
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, eta, times, force_times, force_values, rates=false, fields_at=vec![], tol=1e-10, max_iter=5000, progress=None, explicit=None, dense_limit=DENSE_LIMIT, depth_bounds=None, active_limit=None, precondition=true))]
#[allow(clippy::too_many_arguments)]
fn bem_viscous<'py>(
    py: Python<'py>,
    height: PyReadonlyArray2<'py, f64>,
    allowed: PyReadonlyArray2<'py, bool>,
    dx: f64,
    eta: f64,
    times: PyReadonlyArray1<'py, f64>,
    force_times: PyReadonlyArray1<'py, f64>,
    force_values: PyReadonlyArray1<'py, f64>,
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
) -> PyResult<Bound<'py, PyDict>> {
    let grid = grid_from(py, &height, &allowed, dx)?;
    let hist = history(
        py,
        slice1(&force_times, "force_times")?,
        slice1(&force_values, "force_values")?,
    )?;
    let request = ViscousRequest {
        times: slice1(&times, "times")?,
        rates,
        fields_at,
        depth_bounds: depth_bounds.unwrap_or_default(),
    };
    let opts = options(tol, max_iter, dense_limit, active_limit, precondition);
    let ctrl = explicit.map(explicit_control);
    let s = PyMonitor::new(progress).run(py, |monitor| match &ctrl {
        None => viscous::run_implicit(&grid, eta, &hist, &request, &opts, monitor),
        Some(c) => viscous::run_explicit(&grid, eta, &hist, &request, c, &opts, monitor),
    })?;
    let d = PyDict::new(py);
    d.set_item("steps", s.steps)?;
    d.set_item("t", s.t.into_pyarray(py))?;
    d.set_item("depth", s.depth.into_pyarray(py))?;
    d.set_item("area", s.area.into_pyarray(py))?;
    d.set_item("contact_length", s.contact_length.into_pyarray(py))?;
    d.set_item("velocity", s.velocity.into_pyarray(py))?;
    d.set_item("stiffness_length", s.stiffness_length.into_pyarray(py))?;
    d.set_item("iterations", s.iterations.into_pyarray(py))?;
    d.set_item("residual", s.residual.into_pyarray(py))?;
    d.set_item("at_border", s.at_border.into_pyarray(py))?;
    d.set_item("solves", s.solves)?;
    let shape = [grid.ny, grid.nx];
    let fields = PyDict::new(py);
    for f in s.fields {
        let e = PyDict::new(py);
        e.set_item("pressure", f.pressure.into_pyarray(py).reshape(shape)?)?;
        e.set_item("velocity", f.velocity.into_pyarray(py).reshape(shape)?)?;
        e.set_item("deflection", f.deflection.into_pyarray(py).reshape(shape)?)?;
        fields.set_item(f.step, e)?;
    }
    d.set_item("fields", fields)?;
    Ok(d)
}

/// Flat punch on the footprint mask pressed by `force` (N) into a viscous half-space;
/// with `margin`, the surface velocity on a grid extended by that many elements per side.
#[pyfunction]
#[pyo3(signature = (allowed, dx, eta, force, margin=None, tol=1e-10, max_iter=5000, progress=None, dense_limit=DENSE_LIMIT, precondition=true))]
#[allow(clippy::too_many_arguments)]
fn bem_punch<'py>(
    py: Python<'py>,
    allowed: PyReadonlyArray2<'py, bool>,
    dx: f64,
    eta: f64,
    force: f64,
    margin: Option<usize>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    dense_limit: usize,
    precondition: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let shape = allowed.shape().to_vec();
    let zeros = vec![0.0; shape[0] * shape[1]];
    let grid = Grid::new(
        shape[1],
        shape[0],
        dx,
        zeros,
        allowed.as_array().iter().copied().collect(),
    )
    .map_err(|e| to_pyerr(py, e))?;
    let opts = options(tol, max_iter, dense_limit, None, precondition);
    let r = PyMonitor::new(progress).run(py, |monitor| {
        viscous::run_punch(&grid, eta, force, margin, &opts, monitor)
    })?;
    let d = PyDict::new(py);
    d.set_item("velocity", r.velocity)?;
    d.set_item("damping", r.damping)?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("residual", r.residual)?;
    d.set_item(
        "pressure",
        r.pressure.into_pyarray(py).reshape([grid.ny, grid.nx])?,
    )?;
    if let (Some(v), Some(m)) = (r.surface_velocity, margin) {
        d.set_item(
            "surface_velocity",
            v.into_pyarray(py)
                .reshape([grid.ny + 2 * m, grid.nx + 2 * m])?,
        )?;
    }
    Ok(d)
}

/// MDR run: 1D profile g (m) at element centres spaced dx (m); medium "viscous" (param =
/// eta, Pa s) or "elastic" (param = G, Pa); output times (s); force history samples.
#[pyfunction]
#[pyo3(signature = (profile, dx, medium, param, times, force_times, force_values, fields_at=vec![], progress=None, explicit=None))]
#[allow(clippy::too_many_arguments)]
fn mdr_run<'py>(
    py: Python<'py>,
    profile: PyReadonlyArray1<'py, f64>,
    dx: f64,
    medium: &str,
    param: f64,
    times: PyReadonlyArray1<'py, f64>,
    force_times: PyReadonlyArray1<'py, f64>,
    force_values: PyReadonlyArray1<'py, f64>,
    fields_at: Vec<usize>,
    progress: Option<Py<PyAny>>,
    explicit: Option<(f64, f64, f64)>,
) -> PyResult<Bound<'py, PyDict>> {
    let medium = match medium {
        "viscous" => Medium::Viscous { eta: param },
        "elastic" => Medium::Elastic { g: param },
        other => {
            return Err(to_pyerr(
                py,
                Error::InvalidInput(format!(
                    "medium must be 'viscous' or 'elastic', got {other:?}"
                )),
            ))
        }
    };
    let f = Foundation::new(slice1(&profile, "profile")?, dx).map_err(|e| to_pyerr(py, e))?;
    let hist = history(
        py,
        slice1(&force_times, "force_times")?,
        slice1(&force_values, "force_values")?,
    )?;
    let times = slice1(&times, "times")?;
    let r = PyMonitor::new(progress).run(py, |monitor| match (explicit, medium) {
        (None, _) => {
            mdr::run(&f, medium, &hist, &times, &fields_at, monitor).map(|s| (s, times.len()))
        }
        (Some(c), Medium::Viscous { eta }) => {
            mdr::run_explicit(&f, eta, &hist, &times, &explicit_control(c), monitor)
        }
        (Some(_), Medium::Elastic { .. }) => Err(Error::InvalidInput(
            "the explicit integrator applies to the viscous medium only".into(),
        )),
    });
    let (s, steps) = r?;
    let d = PyDict::new(py);
    d.set_item("steps", steps)?;
    d.set_item("t", s.t.into_pyarray(py))?;
    d.set_item("depth", s.depth.into_pyarray(py))?;
    d.set_item("contact_length", s.contact_length.into_pyarray(py))?;
    d.set_item("velocity", s.velocity.into_pyarray(py))?;
    d.set_item("saturated", s.saturated.into_pyarray(py))?;
    let fields = PyDict::new(py);
    for fl in s.fields {
        let e = PyDict::new(py);
        e.set_item("displacement", fl.displacement.into_pyarray(py))?;
        e.set_item("line_load", fl.line_load.into_pyarray(py))?;
        e.set_item("velocity", fl.velocity.into_pyarray(py))?;
        fields.set_item(fl.step, e)?;
    }
    d.set_item("fields", fields)?;
    Ok(d)
}

/// Inverse MDR transform: 3D pressure (Pa) at radii r (m) from the line load q (N/m).
#[pyfunction]
fn mdr_pressure<'py>(
    py: Python<'py>,
    q: PyReadonlyArray1<'py, f64>,
    dx: f64,
    r: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    radial(py, transforms::pressure_from_line_load, &q, "q", dx, &r)
}

/// An inverse MDR transform: (1D data, dx, radii) -> 3D values at the radii.
type RadialTransform = fn(&[f64], f64, &[f64]) -> crate::Result<Vec<f64>>;

/// Applies an inverse transform `f` of 1D data `values` at radii `r` and returns numpy.
fn radial<'py>(
    py: Python<'py>,
    f: RadialTransform,
    values: &PyReadonlyArray1<'py, f64>,
    name: &str,
    dx: f64,
    r: &PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    let out = f(&slice1(values, name)?, dx, &slice1(r, "r")?).map_err(|e| to_pyerr(py, e))?;
    Ok(out.into_pyarray(py))
}

/// Inverse MDR transform: 3D surface deflection (or rate) at radii r (m) outside the
/// contact from 1D displacements (or velocities) w.
#[pyfunction]
fn mdr_deflection<'py>(
    py: Python<'py>,
    w: PyReadonlyArray1<'py, f64>,
    dx: f64,
    r: PyReadonlyArray1<'py, f64>,
) -> PyResult<Bound<'py, numpy::PyArray1<f64>>> {
    radial(py, transforms::deflection_outside, &w, "w", dx, &r)
}

/// Surface deflection (m) of a half-space with G = 1 Pa under element pressures p (Pa),
/// (ny, nx), by the DC-FFT operator or (`dense=True`) the dense faer matrix.
#[pyfunction]
#[pyo3(signature = (p, dx, dense=false))]
fn surface_deflection<'py>(
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
    });
    let u = r.map_err(|e| to_pyerr(py, e))?;
    u.into_pyarray(py).reshape(shape)
}

/// The DC-FFT surface operator of an `nx` x `ny` grid of square elements of side `dx` (m),
/// built once (Love kernel spectrum, FFT plans, buffers) and applied many times:
/// `apply(p)` maps element pressures (Pa, shape (ny, nx)) to element-centre deflections (m)
/// of an incompressible half-space with G = 1 Pa (divide by G, or by eta for rates).
#[pyclass(name = "SurfaceOperator", module = "mdrvisc._core")]
struct PySurfaceOperator {
    op: FftOperator,
}

#[pymethods]
impl PySurfaceOperator {
    #[new]
    fn new(py: Python<'_>, nx: usize, ny: usize, dx: f64) -> PyResult<Self> {
        let op = py
            .detach(|| FftOperator::new(nx, ny, dx))
            .map_err(|e| to_pyerr(py, e))?;
        Ok(PySurfaceOperator { op })
    }

    /// K[p] (m) for pressures `p` (Pa, (ny, nx) float64), with the GIL released; written
    /// into `out` (a C-contiguous (ny, nx) float64 array) when given, else a new array.
    #[pyo3(signature = (p, out=None))]
    fn apply<'py>(
        &mut self,
        py: Python<'py>,
        p: PyReadonlyArray2<'py, f64>,
        out: Option<Bound<'py, numpy::PyArray2<f64>>>,
    ) -> PyResult<Bound<'py, numpy::PyArray2<f64>>> {
        let shape = [self.op.ny(), self.op.nx()];
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
        let op = &mut self.op;
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
                    let mut rw = out.readwrite();
                    let u = rw.as_slice_mut().map_err(|_| {
                        to_pyerr(
                            py,
                            Error::InvalidInput("out must be C-contiguous and writable".into()),
                        )
                    })?;
                    in_pool(py, || op.apply(pv, u));
                }
                Ok(out)
            }
            None => {
                let mut u = vec![0.0; pv.len()];
                in_pool(py, || op.apply(pv, &mut u));
                u.into_pyarray(py).reshape(shape)
            }
        }
    }

    /// Grid shape (ny, nx).
    #[getter]
    fn shape(&self) -> (usize, usize) {
        (self.op.ny(), self.op.nx())
    }

    /// Element side (m).
    #[getter]
    fn dx(&self) -> f64 {
        self.op.dx()
    }

    /// Zero-padded FFT sizes (y, x).
    #[getter]
    fn padded(&self) -> (usize, usize) {
        let (mx, my) = self.op.padded();
        (my, mx)
    }
}

/// Static contact solve: separation h (m), footprint mask, element size dx (m), compliance
/// (1/G, 1/Pa), and either `force` (N) or `depth` (m). The solve runs on the window that can
/// touch (`static_contact::solve`): the elements with h <= depth, or under force control
/// those with h plus a lower bound of the deflection <= `depth_bound` (m; the whole grid
/// without one). `deflection=False` leaves the
/// deflection out (None), which spares a whole-grid operator when the window is smaller.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, compliance, force=None, depth=None, tol=1e-10, max_iter=5000, progress=None, dense_limit=DENSE_LIMIT, active_limit=None, precondition=true, depth_bound=None, deflection=true))]
#[allow(clippy::too_many_arguments)]
fn contact_solve<'py>(
    py: Python<'py>,
    height: PyReadonlyArray2<'py, f64>,
    allowed: PyReadonlyArray2<'py, bool>,
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
) -> PyResult<Bound<'py, PyDict>> {
    let grid = grid_from(py, &height, &allowed, dx)?;
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
    let opts = options(tol, max_iter, dense_limit, active_limit, precondition);
    let r = PyMonitor::new(progress).run(py, |monitor| {
        static_contact::solve(
            &grid,
            compliance,
            target,
            depth_bound,
            deflection,
            &opts,
            monitor,
        )
    })?;
    let s = &r.summary;
    let shape = [grid.ny, grid.nx];
    let d = PyDict::new(py);
    d.set_item("depth", s.depth)?;
    d.set_item("force", s.force)?;
    d.set_item("iterations", s.iterations)?;
    d.set_item("residual", s.residual)?;
    d.set_item("contact_count", s.contact_count)?;
    d.set_item(
        "method",
        if s.dense {
            "active-set"
        } else {
            "polonsky-keer"
        },
    )?;
    d.set_item("solves", r.solves)?;
    let w = r.window;
    d.set_item("window", (w.y0, w.x0, w.wy, w.wx))?;
    d.set_item("pressure", r.pressure.into_pyarray(py).reshape(shape)?)?;
    match r.deflection {
        Some(u) => d.set_item("deflection", u.into_pyarray(py).reshape(shape)?)?,
        None => d.set_item("deflection", py.None())?,
    }
    Ok(d)
}

fn loading(py: Python<'_>, kind: &str, times: Vec<f64>, values: Vec<f64>) -> PyResult<Loading> {
    let r = match kind {
        "force" => ForceHistory::piecewise_linear(times, values).map(Loading::Force),
        "depth" => DepthHistory::piecewise_linear(times, values).map(Loading::Depth),
        other => Err(Error::InvalidInput(format!(
            "loading must be 'force' or 'depth', got {other:?}"
        ))),
    };
    r.map_err(|e| to_pyerr(py, e))
}

fn series_dict<'py>(py: Python<'py>, s: viscoelastic::Series) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("t", s.t.into_pyarray(py))?;
    d.set_item("depth", s.depth.into_pyarray(py))?;
    d.set_item("force", s.force.into_pyarray(py))?;
    d.set_item("contact_length", s.contact_length.into_pyarray(py))?;
    d.set_item("iterations", s.iterations.into_pyarray(py))?;
    d.set_item("steps", s.steps)?;
    Ok(d)
}

/// The validated medium (G_inf, Prony terms, eta) and loading history of a viscoelastic run.
fn medium_and_loading(
    py: Python<'_>,
    (g_inf, terms, eta): (f64, Vec<(f64, f64)>, f64),
    kind: &str,
    load_times: &PyReadonlyArray1<'_, f64>,
    load_values: &PyReadonlyArray1<'_, f64>,
) -> PyResult<(Rheology, Loading)> {
    let medium = Rheology::new(g_inf, terms, eta).map_err(|e| to_pyerr(py, e))?;
    let load = loading(
        py,
        kind,
        slice1(load_times, "load_times")?,
        slice1(load_values, "load_values")?,
    )?;
    Ok((medium, load))
}

/// Viscoelastic MDR run: 1D profile (m) spaced dx (m); medium G(t) = g_inf + sum G_k
/// exp(-t/tau_k) + eta delta(t); loading "force" (N) or "depth" (m) samples; output times
/// (s); steps no longer than dt (s).
#[pyfunction]
#[pyo3(signature = (profile, dx, g_inf, terms, eta, kind, load_times, load_values, times, dt, progress=None))]
#[allow(clippy::too_many_arguments)]
fn viscoelastic_mdr<'py>(
    py: Python<'py>,
    profile: PyReadonlyArray1<'py, f64>,
    dx: f64,
    g_inf: f64,
    terms: Vec<(f64, f64)>,
    eta: f64,
    kind: &str,
    load_times: PyReadonlyArray1<'py, f64>,
    load_values: PyReadonlyArray1<'py, f64>,
    times: PyReadonlyArray1<'py, f64>,
    dt: f64,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let (medium, load) =
        medium_and_loading(py, (g_inf, terms, eta), kind, &load_times, &load_values)?;
    let (g, times) = (slice1(&profile, "profile")?, slice1(&times, "times")?);
    check_finite("1D profile", &g).map_err(|e| to_pyerr(py, e))?;
    let s = PyMonitor::new(progress).run(py, |monitor| {
        viscoelastic::run_mdr(&g, dx, &medium, &load, &times, dt, monitor)
    })?;
    series_dict(py, s)
}

/// Viscoelastic BEM run on a height map (m, (ny, nx)) with footprint mask; medium, loading,
/// output times and step as for `viscoelastic_mdr`.
#[pyfunction]
#[pyo3(signature = (height, allowed, dx, g_inf, terms, eta, kind, load_times, load_values, times, dt, tol=1e-10, max_iter=5000, progress=None))]
#[allow(clippy::too_many_arguments)]
fn viscoelastic_bem<'py>(
    py: Python<'py>,
    height: PyReadonlyArray2<'py, f64>,
    allowed: PyReadonlyArray2<'py, bool>,
    dx: f64,
    g_inf: f64,
    terms: Vec<(f64, f64)>,
    eta: f64,
    kind: &str,
    load_times: PyReadonlyArray1<'py, f64>,
    load_values: PyReadonlyArray1<'py, f64>,
    times: PyReadonlyArray1<'py, f64>,
    dt: f64,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let grid = grid_from(py, &height, &allowed, dx)?;
    let (medium, load) =
        medium_and_loading(py, (g_inf, terms, eta), kind, &load_times, &load_values)?;
    let times = slice1(&times, "times")?;
    let opts = options(tol, max_iter, DENSE_LIMIT, None, true);
    let s = PyMonitor::new(progress).run(py, |monitor| {
        viscoelastic::run_bem(&grid, &medium, &load, &times, dt, &opts, monitor)
    })?;
    series_dict(py, s)
}

/// The compiled core of mdrvisc.
#[pymodule(name = "_core")]
mod core_module {
    #[pymodule_export]
    use super::{
        bem_punch, bem_viscous, contact_solve, mdr_deflection, mdr_pressure, mdr_run,
        surface_deflection, viscoelastic_bem, viscoelastic_mdr, PySurfaceOperator,
    };
}
