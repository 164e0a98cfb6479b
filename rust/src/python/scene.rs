//! Scenes across the boundary: the scene model built from its parts (what the Python
//! `Scene` sends: the model's numbers as JSON, its arrays as numpy arrays), scene files, and
//! `run_scene`, which solves one.

use super::convert::{self, samples_array};
use super::monitor::{to_pyerr, PyMonitor};
use super::report::PyReport;
use crate::model::settings::ExplicitControl;
use crate::model::settings::SolverOptions;
use crate::model::{
    file, History, Indenter, Integrator, Method, RunSettings, Scene, SceneArrays, SceneFile,
};
use crate::support::error::Error;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// A validated scene of the crate's scene model.
#[pyclass(name = "Scene", module = "mdrvisc._core", frozen)]
pub(crate) struct PyScene {
    pub(crate) inner: Scene,
}

fn parse_method(py: Python<'_>, name: &str) -> PyResult<Method> {
    match name {
        "bem" => Ok(Method::Bem),
        "mdr" => Ok(Method::Mdr),
        other => Err(to_pyerr(
            py,
            Error::InvalidInput(format!("method must be 'bem' or 'mdr', got {other:?}")),
        )),
    }
}

/// The integrator named `name` ("implicit" or "explicit", the latter with `control`).
fn parse_integrator(py: Python<'_>, name: &str, control: ExplicitControl) -> PyResult<Integrator> {
    match name {
        "implicit" => Ok(Integrator::Implicit),
        "explicit" => Ok(Integrator::Explicit(control)),
        other => Err(to_pyerr(
            py,
            Error::InvalidInput(format!(
                "integrator must be 'implicit' or 'explicit', got {other:?}"
            )),
        )),
    }
}

/// (scene, method, n) of a parsed scene file.
fn unpack(f: SceneFile) -> (PyScene, &'static str, usize) {
    (
        PyScene { inner: f.scene },
        f.settings.method.name(),
        f.settings.n,
    )
}

/// The model text of `build` and `with_values` as JSON, or InvalidInputError.
fn parse_json(py: Python<'_>, what: &str, text: &str) -> PyResult<serde_json::Value> {
    serde_json::from_str(text)
        .map_err(|e| to_pyerr(py, Error::InvalidInput(format!("scene: {what}: {e}"))))
}

/// The numpy arrays of `arrays` by the names of `build`'s arguments, in its order.
type ArraysOut<'py> = (
    Option<Bound<'py, PyArray2<f64>>>,
    Option<Bound<'py, PyArray1<f64>>>,
    Option<Bound<'py, PyArray1<f64>>>,
    Option<Bound<'py, PyArray1<f64>>>,
    Option<Bound<'py, PyArray2<f64>>>,
    Option<Bound<'py, PyArray2<f64>>>,
);

fn arrays_out(py: Python<'_>, arrays: SceneArrays) -> PyResult<ArraysOut<'_>> {
    let SceneArrays {
        heights,
        r,
        h,
        slope,
        force,
        depth,
    } = arrays;
    let heights = heights
        .map(|(shape, values)| values.into_pyarray(py).reshape(shape))
        .transpose()?;
    let line = |v: Option<Vec<f64>>| v.map(|v| v.into_pyarray(py));
    Ok((
        heights,
        line(r),
        line(h),
        line(slope),
        force.map(|s| samples_array(py, s)).transpose()?,
        depth.map(|s| samples_array(py, s)).transpose()?,
    ))
}

#[pymethods]
impl PyScene {
    /// Parses and validates a scene from JSON text (the scene-file keys, without method
    /// and n).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        Scene::from_json(text)
            .map(|inner| PyScene { inner })
            .map_err(|e| to_pyerr(py, e))
    }

    /// Builds and validates a scene from its model without the arrays (JSON text: the keys
    /// of a scene file but method and n) and its arrays, each copied once: a height map's
    /// `heights` (m, (ny, nx)), a tabulated profile's `r`, `h` (m) and `slope`, sampled
    /// `force` (N) or `depth` (m) histories as (k, 2) arrays of [t (s), value] rows. An
    /// array's key is left out of the model.
    #[staticmethod]
    #[pyo3(signature = (model, heights=None, r=None, h=None, slope=None, force=None, depth=None))]
    #[allow(clippy::too_many_arguments)]
    fn build(
        py: Python<'_>,
        model: &str,
        heights: Option<PyReadonlyArray2<'_, f64>>,
        r: Option<PyReadonlyArray1<'_, f64>>,
        h: Option<PyReadonlyArray1<'_, f64>>,
        slope: Option<PyReadonlyArray1<'_, f64>>,
        force: Option<PyReadonlyArray2<'_, f64>>,
        depth: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Self> {
        let model = parse_json(py, "model", model)?;
        let arrays = convert::scene_arrays(py, heights, r, h, slope, force, depth)?;
        Scene::from_parts(model, arrays)
            .map(|inner| PyScene { inner })
            .map_err(|e| to_pyerr(py, e))
    }

    /// The scene with the values of `changes` (JSON text: a list of [dotted model key,
    /// value], applied in order) and the arrays given (as in `build`) in place of its own,
    /// validated. A change at an array's key replaces the array; the other arrays are copied
    /// as they are, not read again.
    #[pyo3(signature = (changes, heights=None, r=None, h=None, slope=None, force=None, depth=None))]
    #[allow(clippy::too_many_arguments)]
    fn with_values(
        &self,
        py: Python<'_>,
        changes: &str,
        heights: Option<PyReadonlyArray2<'_, f64>>,
        r: Option<PyReadonlyArray1<'_, f64>>,
        h: Option<PyReadonlyArray1<'_, f64>>,
        slope: Option<PyReadonlyArray1<'_, f64>>,
        force: Option<PyReadonlyArray2<'_, f64>>,
        depth: Option<PyReadonlyArray2<'_, f64>>,
    ) -> PyResult<Self> {
        let changes: Vec<(String, serde_json::Value)> =
            serde_json::from_value(parse_json(py, "changes", changes)?).map_err(|e| {
                to_pyerr(
                    py,
                    Error::InvalidInput(format!("scene: changes must be [key, value] pairs: {e}")),
                )
            })?;
        let arrays = convert::scene_arrays(py, heights, r, h, slope, force, depth)?;
        self.inner
            .with_values(changes, arrays)
            .map(|inner| PyScene { inner })
            .map_err(|e| to_pyerr(py, e))
    }

    /// The model without the arrays (JSON text, the keys in a scene file's order): the
    /// `model` of `build`.
    fn model(&self) -> String {
        self.inner.model()
    }

    /// The arrays of the scene (copies) by the names of `build`'s arguments; only those the
    /// scene holds.
    fn arrays<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let (heights, r, h, slope, force, depth) = arrays_out(py, self.inner.arrays())?;
        let out = PyDict::new(py);
        let names = ["heights", "r", "h", "slope", "force", "depth"];
        let values = [
            heights.map(Bound::into_any),
            r.map(Bound::into_any),
            h.map(Bound::into_any),
            slope.map(Bound::into_any),
            force.map(Bound::into_any),
            depth.map(Bound::into_any),
        ];
        for (name, value) in names.into_iter().zip(values) {
            if let Some(value) = value {
                out.set_item(name, value)?;
            }
        }
        Ok(out)
    }

    /// "force" or "depth": what the loading prescribes.
    fn controlled_by(&self) -> &'static str {
        if self.inner.force.is_some() {
            "force"
        } else {
            "depth"
        }
    }

    /// (times (s), values) of the force (N) or depth (m) history; a constant is one sample
    /// at t = 0.
    fn history<'py>(
        &self,
        py: Python<'py>,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let history = self.inner.force.as_ref().or(self.inner.depth.as_ref());
        let (t, v) = history.map_or((vec![], vec![]), History::samples);
        (t.into_pyarray(py), v.into_pyarray(py))
    }

    /// Scenes are equal when their models and arrays are.
    fn __eq__(&self, other: &Self) -> bool {
        self.inner == other.inner
    }

    /// Pickles as `build`'s arguments: the model's text and the arrays as numpy arrays.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let scene = &slf.get().inner;
        let (heights, r, h, slope, force, depth) = arrays_out(py, scene.arrays())?;
        let args = (scene.model(), heights, r, h, slope, force, depth).into_pyobject(py)?;
        Ok((slf.get_type().getattr("build")?, args))
    }

    /// The scene as JSON text.
    fn to_json(&self) -> String {
        self.inner.to_json()
    }

    /// The scene as scene-file TOML, with `method` and `n` when given (a height map's `n` is
    /// its own); with `path`, also written there (a height map's heights to a `.npy` file
    /// beside it).
    #[pyo3(signature = (method=None, n=None, path=None))]
    fn to_toml(
        &self,
        py: Python<'_>,
        method: Option<&str>,
        n: Option<usize>,
        path: Option<std::path::PathBuf>,
    ) -> PyResult<String> {
        let map = match &self.inner.indenter {
            Indenter::HeightMap(map) => Some(map),
            _ => None,
        };
        let n = n.or(map.filter(|_| method.is_some()).map(|m| m.n()));
        let run = match (method, n) {
            (Some(m), Some(n)) => Some((parse_method(py, m)?, n)),
            (None, None) => None,
            _ => {
                return Err(to_pyerr(
                    py,
                    Error::InvalidInput("give both method and n, or neither".into()),
                ))
            }
        };
        if let Some((method, n)) = run {
            // a file the scene files' reader refuses is never written (n = 0, n past the limit)
            RunSettings::new(method, n)
                .validate()
                .map_err(|e| to_pyerr(py, e))?;
            if let Some(map) = map {
                map.check_run(method, n).map_err(|e| to_pyerr(py, e))?;
            }
        }
        match path {
            Some(path) => file::write(&self.inner, run, &path).map_err(|e| to_pyerr(py, e)),
            None => Ok(file::to_toml(&self.inner, run)),
        }
    }

    /// Output times (s): the requested ones and the field times, sorted.
    fn output_times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.output_times().into_pyarray(py)
    }

    /// Field times (s); empty when no field is asked for.
    fn field_times<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        self.inner.field_times().into_pyarray(py)
    }

    /// (x, dx, height, mask) of the BEM grid with n elements across: element centres (m),
    /// element size (m), heights above the tip (m, (ny, nx)) and footprint mask.
    #[allow(clippy::type_complexity)]
    fn bem_grid<'py>(
        &self,
        py: Python<'py>,
        n: usize,
    ) -> PyResult<(
        Bound<'py, PyArray1<f64>>,
        f64,
        Bound<'py, PyArray2<f64>>,
        Bound<'py, PyArray2<bool>>,
    )> {
        let grid = crate::run::sizing::bem_grid(&self.inner, n).map_err(|e| to_pyerr(py, e))?;
        let x: Vec<f64> = (0..grid.nx)
            .map(|i| (i as f64 - 0.5 * (grid.nx as f64 - 1.0)) * grid.dx)
            .collect();
        let shape = [grid.ny, grid.nx];
        Ok((
            x.into_pyarray(py),
            grid.dx,
            grid.height.into_pyarray(py).reshape(shape)?,
            grid.allowed.into_pyarray(py).reshape(shape)?,
        ))
    }

    /// (x, dx, g) of the MDR foundation with n elements: centres (m), spacing (m), 1D
    /// profile (m).
    #[allow(clippy::type_complexity)]
    fn mdr_grid<'py>(
        &self,
        py: Python<'py>,
        n: usize,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, f64, Bound<'py, PyArray1<f64>>)> {
        let half = crate::run::sizing::mdr_half_length(&self.inner).map_err(|e| to_pyerr(py, e))?;
        let (g, dx) = self
            .inner
            .indenter
            .mdr_profile(n, half)
            .map_err(|e| to_pyerr(py, e))?;
        let x: Vec<f64> = (0..n)
            .map(|i| (i as f64 - 0.5 * (n as f64 - 1.0)) * dx)
            .collect();
        Ok((x.into_pyarray(py), dx, g.into_pyarray(py)))
    }

    /// Upper bounds of the depth (m) at the output times that size the BEM windows of a
    /// viscous scene under a force (NaN where none applies).
    fn depth_bounds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let b = crate::run::sizing::depth_bounds(&self.inner).map_err(|e| to_pyerr(py, e))?;
        Ok(b.into_pyarray(py))
    }

    /// The largest radius (m) at which a solve evaluates the indenter.
    fn extent_needed(&self, py: Python<'_>) -> PyResult<f64> {
        crate::run::sizing::extent_needed(&self.inner).map_err(|e| to_pyerr(py, e))
    }
}

/// Scene files: `load(path)`, `parse(text, source)` (TOML) and `parse_json(text, source)`,
/// each giving (scene, method, n).
#[pyfunction]
pub(crate) fn load_scene_file(
    py: Python<'_>,
    path: &str,
) -> PyResult<(PyScene, &'static str, usize)> {
    SceneFile::load(path)
        .map(unpack)
        .map_err(|e| to_pyerr(py, e))
}

/// The scene of the scene file at `path`, whose `method` and `n` may be absent
/// (`SceneFile::load_scene`).
#[pyfunction]
pub(crate) fn read_scene_file(py: Python<'_>, path: &str) -> PyResult<PyScene> {
    SceneFile::load_scene(path)
        .map(|inner| PyScene { inner })
        .map_err(|e| to_pyerr(py, e))
}

/// A scene file's TOML text parsed and validated; `source` names it in errors.
#[pyfunction]
pub(crate) fn parse_scene_file(
    py: Python<'_>,
    text: &str,
    source: &str,
) -> PyResult<(PyScene, &'static str, usize)> {
    SceneFile::parse(text, source)
        .map(unpack)
        .map_err(|e| to_pyerr(py, e))
}

/// A scene file's table given as JSON text, parsed and validated like TOML.
#[pyfunction]
pub(crate) fn parse_scene_table(
    py: Python<'_>,
    text: &str,
    source: &str,
) -> PyResult<(PyScene, &'static str, usize)> {
    SceneFile::parse_json(text, source)
        .map(unpack)
        .map_err(|e| to_pyerr(py, e))
}

/// The memory (bytes) `run_scene` with these arguments reaches at its peak, as checked
/// before it allocates (`crate::run::memory_needed`).
#[pyfunction]
#[pyo3(signature = (
    scene,
    method,
    n,
    integrator = Integrator::Implicit.name(),
    dt = None,
    precondition = SolverOptions::default().precondition,
))]
pub(crate) fn run_memory(
    py: Python<'_>,
    scene: &PyScene,
    method: &str,
    n: usize,
    integrator: &str,
    dt: Option<f64>,
    precondition: bool,
) -> PyResult<f64> {
    let integrator = parse_integrator(py, integrator, ExplicitControl::default())?;
    let settings = RunSettings {
        method: parse_method(py, method)?,
        n,
        solver: SolverOptions {
            precondition,
            ..SolverOptions::default()
        },
        integrator,
        dt,
    };
    Ok(crate::run::memory_needed(&scene.inner, &settings))
}

/// Solves `scene` by `method` ("bem" or "mdr") at resolution `n`; see `mdrvisc.solve`.
/// The defaults are `SolverOptions::default()`'s and `ExplicitControl::default()`'s
/// (`SOLVER_DEFAULTS`).
#[pyfunction]
#[pyo3(signature = (
    scene,
    method,
    n,
    tol = SolverOptions::default().tol,
    max_iter = SolverOptions::default().max_iter,
    integrator = Integrator::Implicit.name(),
    step = ExplicitControl::default().step,
    area_change = ExplicitControl::default().area_change,
    dt = None,
    progress = None,
    precondition = SolverOptions::default().precondition,
    dense_limit = SolverOptions::default().dense_limit,
    active_limit = SolverOptions::default().active_limit,
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_scene(
    py: Python<'_>,
    scene: &PyScene,
    method: &str,
    n: usize,
    tol: f64,
    max_iter: usize,
    integrator: &str,
    step: f64,
    area_change: f64,
    dt: Option<f64>,
    progress: Option<Py<PyAny>>,
    precondition: bool,
    dense_limit: usize,
    active_limit: Option<usize>,
) -> PyResult<PyReport> {
    let control = ExplicitControl {
        step,
        area_change,
        ..ExplicitControl::default()
    };
    let integrator = parse_integrator(py, integrator, control)?;
    let settings = RunSettings {
        method: parse_method(py, method)?,
        n,
        solver: super::convert::options(tol, max_iter, dense_limit, active_limit, precondition),
        integrator,
        dt,
    };
    // borrowed, not copied: a height map's heights are as large as the run's grid
    let scene = &scene.inner;
    let report =
        PyMonitor::new(progress).run(py, |monitor| crate::run::run(scene, &settings, monitor))?;
    Ok(PyReport::from(report))
}

/// Solves the static scene `scene` under each of `forces` (N) in turn, each BEM solve
/// started from the one before (`run::run_loads`); see `mdrvisc.load_curve`.
#[pyfunction]
#[pyo3(signature = (
    scene,
    method,
    n,
    forces,
    tol = SolverOptions::default().tol,
    max_iter = SolverOptions::default().max_iter,
    progress = None,
    precondition = SolverOptions::default().precondition,
    dense_limit = SolverOptions::default().dense_limit,
    active_limit = SolverOptions::default().active_limit,
))]
#[allow(clippy::too_many_arguments)]
pub(crate) fn run_loads(
    py: Python<'_>,
    scene: &PyScene,
    method: &str,
    n: usize,
    forces: Vec<f64>,
    tol: f64,
    max_iter: usize,
    progress: Option<Py<PyAny>>,
    precondition: bool,
    dense_limit: usize,
    active_limit: Option<usize>,
) -> PyResult<Vec<PyReport>> {
    let settings = RunSettings {
        method: parse_method(py, method)?,
        n,
        solver: super::convert::options(tol, max_iter, dense_limit, active_limit, precondition),
        integrator: Integrator::Implicit,
        dt: None,
    };
    let scene = &scene.inner;
    let reports = PyMonitor::new(progress).run(py, |monitor| {
        crate::run::run_loads(scene, &forces, &settings, monitor)
    })?;
    Ok(reports.into_iter().map(PyReport::from).collect())
}
