//! The typed results of the bindings: `Report` (series and the run's numbers) and
//! `FieldSet` (fields at one time), numpy arrays out.

use crate::run::report::{FieldSet, Report};
use numpy::{IntoPyArray, PyArray1, PyArrayMethods};
use pyo3::prelude::*;
use std::sync::Arc;

/// What a run computed and how (see `mdrvisc.Result`, which wraps it).
#[pyclass(name = "Report", module = "mdrvisc._core", frozen)]
pub(crate) struct PyReport {
    /// The report, its fields moved to `fields`.
    inner: Report,
    /// The report's fields, shared with the `FieldSet`s handed out (a field map is as large
    /// as the grid: handing it out copies it once, into its array).
    fields: Vec<Arc<FieldSet>>,
}

impl From<Report> for PyReport {
    fn from(mut inner: Report) -> Self {
        let fields = std::mem::take(&mut inner.fields)
            .into_iter()
            .map(Arc::new)
            .collect();
        PyReport { inner, fields }
    }
}

fn array<'py>(py: Python<'py>, v: &[f64]) -> Bound<'py, PyArray1<f64>> {
    v.to_vec().into_pyarray(py)
}

fn optional<'py>(py: Python<'py>, v: &Option<Vec<f64>>) -> Option<Bound<'py, PyArray1<f64>>> {
    v.as_deref().map(|v| array(py, v))
}

fn flags<'py>(py: Python<'py>, v: &Option<Vec<bool>>) -> Option<Bound<'py, PyArray1<bool>>> {
    v.as_ref().map(|v| v.clone().into_pyarray(py))
}

#[pymethods]
impl PyReport {
    /// "bem" or "mdr".
    #[getter]
    fn method(&self) -> &'static str {
        self.inner.method.name()
    }
    /// Resolution asked for (BEM elements across the footprint, MDR elements).
    #[getter]
    fn n(&self) -> usize {
        self.inner.n
    }
    /// Element size (m).
    #[getter]
    fn dx(&self) -> f64 {
        self.inner.dx
    }
    /// BEM grid (ny, nx), or None.
    #[getter]
    fn grid_shape(&self) -> Option<(usize, usize)> {
        self.inner.grid_shape.map(|[a, b]| (a, b))
    }
    /// "implicit", "explicit", "one solve", "static" or "viscoelastic".
    #[getter]
    fn integrator(&self) -> &str {
        &self.inner.integrator
    }
    /// Output times (s).
    #[getter]
    fn t<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.t)
    }
    /// Tip depth (m).
    #[getter]
    fn depth<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.depth)
    }
    /// Contact length (m).
    #[getter]
    fn contact_length<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.contact_length)
    }
    /// Contact area (m^2), BEM.
    #[getter]
    fn area<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.area)
    }
    /// Area of the contact and the adhesive zone around it (m^2), BEM under a cohesive law.
    #[getter]
    fn zone_area<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.zone_area)
    }
    /// Outer diameter of the adhesive zone, 2 sqrt(zone_area / pi) (m).
    #[getter]
    fn zone_length<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.zone_length)
    }
    /// Force on the indenter (N).
    #[getter]
    fn force<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        array(py, &self.inner.force)
    }
    /// Penetration rate (m/s).
    #[getter]
    fn velocity<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.velocity)
    }
    /// F / (4 eta dd/dt) (m).
    #[getter]
    fn stiffness_length<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.stiffness_length)
    }
    /// Central pressure of a flat punch (Pa).
    #[getter]
    fn central_pressure<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.central_pressure)
    }
    /// Real contact area over the area of a height map.
    #[getter]
    fn contact_fraction<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.contact_fraction)
    }
    /// Number of contact patches of a height map.
    #[getter]
    fn patches<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<usize>>> {
        self.inner.patches.clone().map(|v| v.into_pyarray(py))
    }
    /// Mean gap (m) between a height map and the deformed surface.
    #[getter]
    fn mean_gap<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.mean_gap)
    }
    /// Whether the contact covers the whole indenter.
    #[getter]
    fn saturated<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<bool>>> {
        flags(py, &self.inner.saturated)
    }
    /// Whether the contact reached the outermost ring of the BEM grid.
    #[getter]
    fn at_edge<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<bool>>> {
        flags(py, &self.inner.at_edge)
    }
    /// Fields at the field times.
    #[getter]
    fn fields(&self) -> Vec<PyFieldSet> {
        self.fields
            .iter()
            .map(|f| PyFieldSet {
                inner: Arc::clone(f),
            })
            .collect()
    }
    /// Time steps taken.
    #[getter]
    fn steps(&self) -> usize {
        self.inner.steps
    }
    /// Contact solves.
    #[getter]
    fn solves(&self) -> usize {
        self.inner.solves
    }
    /// Solver iterations in all.
    #[getter]
    fn iterations(&self) -> usize {
        self.inner.iterations
    }
    /// Largest final relative residual.
    #[getter]
    fn residual(&self) -> f64 {
        self.inner.residual
    }
    /// Static contact solver used, or None.
    #[getter]
    fn solver(&self) -> Option<&str> {
        self.inner.solver.as_deref()
    }
    /// Window (y0, x0, rows, columns) of the last static solve, or None.
    #[getter]
    fn window(&self) -> Option<(usize, usize, usize, usize)> {
        self.inner.window.map(|[a, b, c, d]| (a, b, c, d))
    }
    /// Iterations of each grid level of a static BEM solve (coarsest first, the solved grid
    /// last), or None.
    #[getter]
    fn level_iterations(&self) -> Option<Vec<usize>> {
        self.inner.level_iterations.clone()
    }
    /// Pull-off force (N, tensile: negative) of an adhesive contact, or None.
    #[getter]
    fn pull_off_force(&self) -> Option<f64> {
        self.inner.pull_off_force
    }
    /// Depth (m) of the pull-off, or None.
    #[getter]
    fn pull_off_depth(&self) -> Option<f64> {
        self.inner.pull_off_depth
    }
    /// Time (s) of the pull-off, or None.
    #[getter]
    fn pull_off_time(&self) -> Option<f64> {
        self.inner.pull_off_time
    }
    /// Times (s) an adhesive contact jumped in, or None under hard contact.
    #[getter]
    fn jump_in<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.jump_in)
    }
    /// Times (s) an adhesive contact jumped out, or None under hard contact.
    #[getter]
    fn jump_out<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.jump_out)
    }
    /// Wall time (s).
    #[getter]
    fn wall_time(&self) -> f64 {
        self.inner.wall_time
    }
    /// Warnings about the result's accuracy.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.inner.warnings.clone()
    }
    /// Units of the quantities, {name: unit}.
    #[staticmethod]
    fn units() -> Vec<(&'static str, &'static str)> {
        crate::run::report::UNITS.to_vec()
    }
    /// One line: method, resolution, steps, solves, iterations, residual, wall time.
    fn summary(&self) -> String {
        self.inner.summary()
    }
    /// The text table the command line prints, headed by `name`.
    fn table(&self, name: &str) -> String {
        self.inner.table(name)
    }
    /// The JSON document the command line prints for this run of `scene`, named `name`.
    fn document(&self, name: &str, scene: &super::scene::PyScene) -> String {
        self.inner.document(name, &scene.inner).to_string()
    }
}

/// Fields at one time: BEM maps (ny, nx) over `x`, `y`, or MDR radial profiles over `r`.
#[pyclass(name = "FieldSet", module = "mdrvisc._core", frozen)]
pub(crate) struct PyFieldSet {
    inner: Arc<FieldSet>,
}

impl PyFieldSet {
    /// `v` as an array: (ny, nx) over x, y; (m, m) over x_extended (`extended`); 1-D over r.
    fn shaped<'py>(
        &self,
        py: Python<'py>,
        v: &Option<Vec<f64>>,
        extended: bool,
    ) -> PyResult<Option<Bound<'py, PyAny>>> {
        let Some(v) = v else { return Ok(None) };
        let a = array(py, v);
        let f = &self.inner;
        let shape = match (&f.x_extended, &f.x, &f.y) {
            (Some(xe), _, _) if extended => Some([xe.len(), xe.len()]),
            (_, Some(x), Some(y)) => Some([y.len(), x.len()]),
            _ => None,
        };
        Ok(Some(match shape {
            Some(s) => a.reshape(s)?.into_any(),
            None => a.into_any(),
        }))
    }
}

#[pymethods]
impl PyFieldSet {
    /// Time (s).
    #[getter]
    fn t(&self) -> f64 {
        self.inner.t
    }
    /// Element-centre x (m) of BEM maps.
    #[getter]
    fn x<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.x)
    }
    /// Element-centre y (m) of BEM maps.
    #[getter]
    fn y<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.y)
    }
    /// Radii (m) of MDR profiles.
    #[getter]
    fn r<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.r)
    }
    /// Element centres (m) of the grid extended around a BEM flat punch.
    #[getter]
    fn x_extended<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyArray1<f64>>> {
        optional(py, &self.inner.x_extended)
    }
    /// Pressure (Pa).
    #[getter]
    fn pressure<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.shaped(py, &self.inner.pressure, false)
    }
    /// Surface velocity (m/s).
    #[getter]
    fn surface_velocity<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.shaped(py, &self.inner.surface_velocity, true)
    }
    /// Surface deflection (m).
    #[getter]
    fn deflection<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.shaped(py, &self.inner.deflection, true)
    }
    /// Gap (m) between a height map and the deformed surface.
    #[getter]
    fn gap<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyAny>>> {
        self.shaped(py, &self.inner.gap, false)
    }
}
