//! Scenes across the boundary: the scene model built from JSON (what the Python `Scene`
//! sends), scene files, and `run_scene`, which solves one.

use super::monitor::{to_pyerr, PyMonitor};
use super::report::PyReport;
use crate::contact::DENSE_LIMIT;
use crate::error::Error;
use crate::integrator::ExplicitControl;
use crate::scene::{self, file, Indenter, Integrator, Method, RunSettings, Scene, SceneFile};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArrayMethods, PyReadonlyArray1};
use pyo3::prelude::*;

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

/// (scene, method, n) of a parsed scene file.
fn unpack(f: SceneFile) -> (PyScene, &'static str, usize) {
    (
        PyScene { inner: f.scene },
        f.settings.method.name(),
        f.settings.n,
    )
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
        if let (Some(map), Some((method, n))) = (map, run) {
            map.check_run(method, n).map_err(|e| to_pyerr(py, e))?;
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
        let grid = scene::sizing::bem_grid(&self.inner, n).map_err(|e| to_pyerr(py, e))?;
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
        let half = scene::sizing::mdr_half_length(&self.inner).map_err(|e| to_pyerr(py, e))?;
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
        let b = scene::sizing::depth_bounds(&self.inner).map_err(|e| to_pyerr(py, e))?;
        Ok(b.into_pyarray(py))
    }

    /// The largest radius (m) at which a solve evaluates the indenter.
    fn extent_needed(&self, py: Python<'_>) -> PyResult<f64> {
        scene::sizing::extent_needed(&self.inner).map_err(|e| to_pyerr(py, e))
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

/// Solves `scene` by `method` ("bem" or "mdr") at resolution `n`; see `mdrvisc.solve`.
#[pyfunction]
#[pyo3(signature = (scene, method, n, tol=1e-10, max_iter=5000, integrator="implicit", step=0.01, area_change=0.01, dt=None, progress=None, precondition=true, dense_limit=DENSE_LIMIT, active_limit=None))]
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
    let integrator = match integrator {
        "implicit" => Integrator::Implicit,
        "explicit" => Integrator::Explicit(ExplicitControl {
            step,
            area_change,
            ..ExplicitControl::default()
        }),
        other => {
            return Err(to_pyerr(
                py,
                Error::InvalidInput(format!(
                    "integrator must be 'implicit' or 'explicit', got {other:?}"
                )),
            ))
        }
    };
    let settings = RunSettings {
        method: parse_method(py, method)?,
        n,
        solver: super::convert::options(tol, max_iter, dense_limit, active_limit, precondition),
        integrator,
        dt,
    };
    let scene = scene.inner.clone();
    let report =
        PyMonitor::new(progress).run(py, |monitor| scene::run(&scene, &settings, monitor))?;
    Ok(PyReport { inner: report })
}

/// A validated indenter of the scene model, evaluated where the Python layer needs the
/// crate's own numbers (a tabulated profile's interpolant).
#[pyclass(name = "Indenter", module = "mdrvisc._core", frozen)]
pub(crate) struct PyIndenter {
    inner: Indenter,
}

impl PyIndenter {
    fn map<'py>(
        &self,
        py: Python<'py>,
        values: PyReadonlyArray1<'py, f64>,
        f: impl Fn(&Indenter, f64) -> crate::Result<f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let out: crate::Result<Vec<f64>> = values
            .as_array()
            .iter()
            .map(|&v| f(&self.inner, v))
            .collect();
        Ok(out.map_err(|e| to_pyerr(py, e))?.into_pyarray(py))
    }
}

#[pymethods]
impl PyIndenter {
    /// Parses and validates an indenter from JSON text (a scene file's `[indenter]` table).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        let inner: Indenter = serde_json::from_str(text)
            .map_err(|e| to_pyerr(py, Error::InvalidInput(format!("indenter: {e}"))))?;
        inner.validate().map_err(|e| to_pyerr(py, e))?;
        Ok(PyIndenter { inner })
    }

    /// Heights above the tip (m) at radii `r` (m).
    fn height<'py>(
        &self,
        py: Python<'py>,
        r: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map(py, r, Indenter::height)
    }

    /// MDR profile g (m) at 1D coordinates `x` (m).
    fn profile_1d<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<Bound<'py, PyArray1<f64>>> {
        self.map(py, x, Indenter::profile_1d)
    }

    /// Contact radius (m) at tip depth `d` (m).
    fn radius_at_depth(&self, py: Python<'_>, d: f64) -> PyResult<f64> {
        self.inner.radius_at_depth(d).map_err(|e| to_pyerr(py, e))
    }
}
