//! The scene model's indenters and media as Python objects: the Python classes hold one and
//! delegate their geometry (height maps, footprints, MDR profiles, contact radii, Lee–Radok
//! depths) and rheology (relaxation modulus, creep compliance, series, parameter names) to
//! it. Arrays of any shape go in and come back in that shape.

use super::monitor::{in_pool, to_pyerr};
use crate::model::indenter::profile::ProfileTable;
use crate::model::indenter::pyramid;
use crate::model::indenter::{MdrProfile, Reach};
use crate::model::medium::{self, KINDS};
use crate::model::{Footprint, Indenter, Medium, Profile};
use crate::support::error::Error;
use numpy::ndarray::{ArrayD, IxDyn};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArrayDyn, PyArrayMethods, PyReadonlyArray1,
    PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::prelude::*;
use rayon::prelude::*;
use std::cell::RefCell;

/// What an `Indenter` holds: one of the crate's indenters, or an axisymmetric profile known
/// only to Python (its height f(r) and MDR profile g(x) as vectorised callables) on a
/// footprint.
enum Shape {
    Crate(Indenter),
    Functions {
        height: Py<PyAny>,
        profile: Py<PyAny>,
        footprint: Footprint,
        reach: Reach,
    },
}

/// A validated indenter of the scene model, or an axisymmetric profile given by Python
/// functions, with the crate's geometry and MDR relations.
#[pyclass(name = "Indenter", module = "mdrvisc._core", frozen)]
pub(crate) struct PyIndenter {
    shape: Shape,
}

/// `values` mapped by `f` into an array of their shape.
fn map_array<'py>(
    py: Python<'py>,
    values: &PyReadonlyArrayDyn<'py, f64>,
    f: impl Fn(f64) -> crate::Result<f64>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let shape = values.shape().to_vec();
    let out: crate::Result<Vec<f64>> = values.as_array().iter().map(|&v| f(v)).collect();
    let out = out.map_err(|e| to_pyerr(py, e))?;
    let array = ArrayD::from_shape_vec(IxDyn(&shape), out)
        .map_err(|e| to_pyerr(py, Error::InvalidInput(e.to_string())))?;
    Ok(array.into_pyarray(py))
}

/// A Python callable of a 1D float64 array as a function of the crate's: its errors are kept
/// in `error` (the crate sees a placeholder) and its values must be finite.
fn call_profile<'a>(
    py: Python<'a>,
    f: &'a Py<PyAny>,
    error: &'a RefCell<Option<PyErr>>,
) -> impl Fn(&[f64]) -> crate::Result<Vec<f64>> + 'a {
    move |x: &[f64]| {
        let values = f
            .bind(py)
            .call1((x.to_vec().into_pyarray(py),))
            .and_then(|v| v.extract::<Vec<f64>>());
        match values {
            Ok(v) if v.len() == x.len() => Ok(v),
            Ok(v) => Err(Error::InvalidInput(format!(
                "the profile gave {} values for {} points",
                v.len(),
                x.len()
            ))),
            Err(e) => {
                error.borrow_mut().replace(e);
                Err(Error::InvalidInput("the profile failed".into()))
            }
        }
    }
}

impl PyIndenter {
    fn footprint(&self) -> Footprint {
        match &self.shape {
            Shape::Crate(i) => i.footprint(),
            Shape::Functions { footprint, .. } => *footprint,
        }
    }

    /// Runs `f` on the crate's indenter with the GIL released, or on the MDR relations of
    /// the Python profile; a Python error raised by the profile comes back as itself.
    fn with<T: Send>(
        &self,
        py: Python<'_>,
        crate_side: impl FnOnce(&Indenter) -> crate::Result<T> + Send,
        function_side: impl FnOnce(&MdrProfile<'_>) -> crate::Result<T>,
    ) -> PyResult<T> {
        match &self.shape {
            Shape::Crate(i) => py.detach(|| crate_side(i)).map_err(|e| to_pyerr(py, e)),
            Shape::Functions {
                profile,
                footprint,
                reach,
                ..
            } => {
                let error = RefCell::new(None);
                let g = call_profile(py, profile, &error);
                let mdr = MdrProfile {
                    profile: &g,
                    footprint: *footprint,
                    reach: *reach,
                };
                let out = function_side(&mdr);
                match error.take() {
                    Some(e) => Err(e),
                    None => out.map_err(|e| to_pyerr(py, e)),
                }
            }
        }
    }

    fn from_indenter(py: Python<'_>, inner: Indenter) -> PyResult<Self> {
        inner.validate().map_err(|e| to_pyerr(py, e))?;
        Ok(PyIndenter {
            shape: Shape::Crate(inner),
        })
    }
}

#[pymethods]
impl PyIndenter {
    /// Parses and validates an indenter from JSON text (a scene file's `[indenter]` table).
    #[staticmethod]
    fn from_json(py: Python<'_>, text: &str) -> PyResult<Self> {
        let inner: Indenter = serde_json::from_str(text)
            .map_err(|e| to_pyerr(py, Error::InvalidInput(format!("indenter: {e}"))))?;
        Self::from_indenter(py, inner)
    }

    /// Flat cylindrical punch of radius `radius` (m).
    #[staticmethod]
    fn rod(py: Python<'_>, radius: f64) -> PyResult<Self> {
        Self::from_indenter(py, Indenter::Rod { radius })
    }

    /// Paraboloid h = c r^2 (c in 1/m) on a square footprint of side `edge` (m) or unbounded.
    #[staticmethod]
    #[pyo3(signature = (c, edge=None))]
    fn paraboloid(py: Python<'_>, c: f64, edge: Option<f64>) -> PyResult<Self> {
        Self::from_indenter(py, Indenter::Paraboloid { c, edge })
    }

    /// Cone h = slope r on a square footprint of side `edge` (m) or unbounded.
    #[staticmethod]
    #[pyo3(signature = (slope, edge=None))]
    fn cone(py: Python<'_>, slope: f64, edge: Option<f64>) -> PyResult<Self> {
        Self::from_indenter(py, Indenter::Cone { slope, edge })
    }

    /// Exact spherical cap of radius `radius` (m).
    #[staticmethod]
    fn sphere(py: Python<'_>, radius: f64) -> PyResult<Self> {
        Self::from_indenter(py, Indenter::Sphere { radius })
    }

    /// Four-sided pyramid of face half-angle `half_angle` (radians, in (0, pi/2)) on a square
    /// base of side `edge` (m) or unbounded.
    #[staticmethod]
    #[pyo3(signature = (half_angle, edge=None))]
    fn pyramid(py: Python<'_>, half_angle: f64, edge: Option<f64>) -> PyResult<Self> {
        Self::from_indenter(py, Indenter::Pyramid { half_angle, edge })
    }

    /// A tabulated profile: radii `r` (m) from 0, heights `h` (m), optional slopes, and a
    /// square (`edge`, m) or disc (`radius`, m) footprint or none.
    #[staticmethod]
    #[pyo3(signature = (r, h, slope=None, edge=None, radius=None))]
    fn profile(
        py: Python<'_>,
        r: PyReadonlyArray1<'_, f64>,
        h: PyReadonlyArray1<'_, f64>,
        slope: Option<PyReadonlyArray1<'_, f64>>,
        edge: Option<f64>,
        radius: Option<f64>,
    ) -> PyResult<Self> {
        let table = ProfileTable {
            r: r.as_array().to_vec(),
            h: h.as_array().to_vec(),
            slope: slope.map(|s| s.as_array().to_vec()),
            edge,
            radius,
        };
        let profile = Profile::try_from(table).map_err(|e| to_pyerr(py, e))?;
        Self::from_indenter(py, Indenter::Profile(Box::new(profile)))
    }

    /// An axisymmetric indenter known only to Python: `height(r)` (m) and its MDR profile
    /// `profile(x)` (m), vectorised callables of 1D float64 arrays (m), on a square (`edge`,
    /// m) or disc (`radius`, m) footprint or none. `fills`: whether the contact can fill
    /// the disc (false for a profile that diverges at its rim).
    #[staticmethod]
    #[pyo3(signature = (height, profile, edge=None, radius=None, fills=true))]
    fn from_functions(
        py: Python<'_>,
        height: Py<PyAny>,
        profile: Py<PyAny>,
        edge: Option<f64>,
        radius: Option<f64>,
        fills: bool,
    ) -> PyResult<Self> {
        let (footprint, reach) = match (edge, radius) {
            (Some(_), Some(_)) => {
                return Err(to_pyerr(
                    py,
                    Error::InvalidInput("give edge or radius, not both".into()),
                ))
            }
            (None, Some(radius)) => (
                Footprint::Disc { radius, rim: true },
                Reach::Disc { radius, fills },
            ),
            (Some(edge), None) => (
                Footprint::Square { edge },
                Reach::Beyond {
                    start: 0.5 * edge,
                    doublings: 20,
                },
            ),
            (None, None) => (
                Footprint::Unbounded,
                Reach::Beyond {
                    start: 1.0,
                    doublings: 20,
                },
            ),
        };
        for v in edge.iter().chain(radius.iter()) {
            crate::support::error::check_positive("footprint size", *v)
                .map_err(|e| to_pyerr(py, e))?;
        }
        Ok(PyIndenter {
            shape: Shape::Functions {
                height,
                profile,
                footprint,
                reach,
            },
        })
    }

    /// Heights above the tip (m) at radii `r` (m) of the axisymmetric indenter MDR solves.
    fn height<'py>(
        &self,
        py: Python<'py>,
        r: PyReadonlyArrayDyn<'py, f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        match &self.shape {
            Shape::Crate(i) => map_array(py, &r, |v| i.height(v)),
            Shape::Functions { height, .. } => Ok(height
                .bind(py)
                .call1((r.as_array().to_owned().into_pyarray(py),))?
                .extract()?),
        }
    }

    /// MDR profile g (m) at 1D coordinates `x` (m).
    fn profile_1d<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArrayDyn<'py, f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        match &self.shape {
            Shape::Crate(i) => map_array(py, &x, |v| i.profile_1d(v)),
            Shape::Functions { profile, .. } => Ok(profile
                .bind(py)
                .call1((x.as_array().to_owned().into_pyarray(py),))?
                .extract()?),
        }
    }

    /// The half MDR profile (m) of n elements on a layer of `thickness` (m) on `base`
    /// ("bonded" or "frictionless") for Poisson ratio `nu`, reaching `half` (m), as a
    /// half-space's, and its element spacing (m): `crate::mdr::layer::half_space_equivalent`.
    fn layer_profile_1d<'py>(
        &self,
        py: Python<'py>,
        half: f64,
        n: usize,
        thickness: f64,
        base: &str,
        nu: f64,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, f64)> {
        use crate::model::body::{Base, Layer};
        let base = match base {
            "bonded" => Base::Bonded,
            "frictionless" => Base::Frictionless,
            other => {
                return Err(to_pyerr(
                    py,
                    Error::InvalidInput(format!(
                        "base must be \"bonded\" or \"frictionless\", got {other:?}"
                    )),
                ))
            }
        };
        let layer = Layer { thickness, base };
        layer.validate().map_err(|e| to_pyerr(py, e))?;
        let Shape::Crate(indenter) = &self.shape else {
            return Err(to_pyerr(
                py,
                Error::InvalidInput(
                    "a layer needs an indenter of the crate's shapes (a profile given by Python functions has none)".into(),
                ),
            ));
        };
        let profile = |x: f64| indenter.profile_1d(x);
        let (g, dx) = py
            .detach(|| crate::mdr::layer::half_space_equivalent(&profile, n, half, layer, nu))
            .map_err(|e| to_pyerr(py, e))?;
        Ok((g.into_pyarray(py), dx))
    }

    /// (h, mask) over the element centres `x` (nx) by `y` (ny) (m): heights above the tip
    /// (m, (ny, nx), the true shape, 0 outside the footprint) and whether each centre lies
    /// in the footprint.
    #[allow(clippy::type_complexity)]
    fn height_map<'py>(
        &self,
        py: Python<'py>,
        x: PyReadonlyArray1<'py, f64>,
        y: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray2<f64>>, Bound<'py, PyArray2<bool>>)> {
        let (x, y) = (x.as_array().to_vec(), y.as_array().to_vec());
        let shape = [y.len(), x.len()];
        let (height, mask) = match &self.shape {
            Shape::Crate(i) => py
                .detach(|| i.height_map(&x, &y))
                .map_err(|e| to_pyerr(py, e))?,
            Shape::Functions {
                height, footprint, ..
            } => {
                let mask: Vec<bool> = y
                    .iter()
                    .flat_map(|&yi| x.iter().map(move |&xi| footprint.covers(xi, yi)))
                    .collect();
                let r: Vec<f64> = y
                    .iter()
                    .flat_map(|&yi| x.iter().map(move |&xi| xi.hypot(yi)))
                    .zip(&mask)
                    .filter_map(|(r, &m)| m.then_some(r))
                    .collect();
                let inside: Vec<f64> = height.bind(py).call1((r.into_pyarray(py),))?.extract()?;
                let mut values = inside.into_iter();
                let h = mask
                    .iter()
                    .map(|&m| if m { values.next().unwrap_or(0.0) } else { 0.0 })
                    .collect();
                (h, mask)
            }
        };
        Ok((
            height.into_pyarray(py).reshape(shape)?,
            mask.into_pyarray(py).reshape(shape)?,
        ))
    }

    /// Half the side of the smallest centred square holding the footprint (m); None when
    /// unbounded.
    #[getter]
    fn half_width(&self) -> Option<f64> {
        match &self.shape {
            Shape::Crate(i) => i.half_width(),
            Shape::Functions { footprint, .. } => match *footprint {
                Footprint::Disc { radius, .. } => Some(radius),
                Footprint::Square { edge } => Some(0.5 * edge),
                _ => None,
            },
        }
    }

    /// Half-length of the 1D MDR indenter (m): a disc's radius, L / sqrt(pi) for a square of
    /// side L (equal area); None when unbounded.
    #[getter]
    fn half_length_1d(&self) -> Option<f64> {
        match &self.shape {
            Shape::Crate(i) => i.half_length_1d(),
            Shape::Functions { footprint, .. } => match *footprint {
                Footprint::Disc { radius, .. } => Some(radius),
                Footprint::Square { edge } => Some(edge / std::f64::consts::PI.sqrt()),
                _ => None,
            },
        }
    }

    /// Whether the face is flat (the rod): its contact is the whole face at every depth.
    #[getter]
    fn is_flat(&self) -> bool {
        matches!(&self.shape, Shape::Crate(i) if i.is_flat())
    }

    /// Slope of the cone MDR solves in place of a pyramid (its equivalent cone); None for
    /// other indenters.
    #[getter]
    fn equivalent_cone_slope(&self) -> Option<f64> {
        match &self.shape {
            Shape::Crate(Indenter::Pyramid { half_angle, edge }) => {
                match pyramid::equivalent_cone(*half_angle, *edge) {
                    Indenter::Cone { slope, .. } => Some(slope),
                    _ => None,
                }
            }
            _ => None,
        }
    }

    /// Whether points exactly on the rim of a disc footprint belong to it (None without a
    /// disc).
    #[getter]
    fn rim_inside(&self) -> Option<bool> {
        match self.footprint() {
            Footprint::Disc { rim, .. } => Some(rim),
            _ => None,
        }
    }

    /// Contact radius (m) at tip depth `d` (m): g(a) = d; a disc footprint caps it.
    fn radius_at_depth(&self, py: Python<'_>, d: f64) -> PyResult<f64> {
        self.with(py, |i| i.radius_at_depth(d), |m| m.radius_at_depth(d))
    }

    /// Contact radius (m) under the MDR load `s` = F / (4 G) or I / (4 eta) (m^2).
    fn radius_at_load(&self, py: Python<'_>, s: f64) -> PyResult<f64> {
        self.with(py, |i| i.radius_at_load(s), |m| m.radius_at_load(s))
    }

    /// Lee–Radok depths (m) under the MDR loads `s` (m^2, any shape): NaN where the contact
    /// circle has outgrown a square footprint.
    fn depth_under_load<'py>(
        &self,
        py: Python<'py>,
        s: PyReadonlyArrayDyn<'py, f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let shape = s.shape().to_vec();
        let loads = s.as_array().iter().copied().collect::<Vec<f64>>();
        let depth = |d: Option<f64>| d.unwrap_or(f64::NAN);
        let out = self.with(
            py,
            |i| {
                loads
                    .iter()
                    .map(|&v| i.depth_under_load(v).map(depth))
                    .collect::<crate::Result<Vec<f64>>>()
            },
            |m| {
                loads
                    .iter()
                    .map(|&v| m.depth_under_load(v).map(depth))
                    .collect::<crate::Result<Vec<f64>>>()
            },
        )?;
        let array = ArrayD::from_shape_vec(IxDyn(&shape), out)
            .map_err(|e| to_pyerr(py, Error::InvalidInput(e.to_string())))?;
        Ok(array.into_pyarray(py))
    }
}

/// A validated medium of the scene model: its shear relaxation modulus, creep compliance,
/// series and parameters.
#[pyclass(name = "Medium", module = "mdrvisc._core", frozen)]
pub(crate) struct PyMedium {
    pub(crate) inner: Medium,
}

#[pymethods]
impl PyMedium {
    /// The medium of kind `kind` (a scene file's `type`) with the named parameters (Pa, s,
    /// Pa s; a Prony series's G_inf, G1, tau1, ...) and Poisson ratio `nu`; validated.
    #[new]
    fn new(py: Python<'_>, kind: &str, parameters: Vec<(String, f64)>, nu: f64) -> PyResult<Self> {
        Medium::from_parameters(kind, &parameters, nu)
            .map(|inner| PyMedium { inner })
            .map_err(|e| to_pyerr(py, e))
    }

    /// The medium of kind `kind` from its parameter values in the order of `parameters` (a
    /// Prony series: G_inf, G1, tau1, G2, ...) and Poisson ratio `nu`; validated.
    #[staticmethod]
    fn from_values(py: Python<'_>, kind: &str, values: Vec<f64>, nu: f64) -> PyResult<Self> {
        Medium::from_values(kind, &values, nu)
            .map(|inner| PyMedium { inner })
            .map_err(|e| to_pyerr(py, e))
    }

    /// The kinds of media, as scene files name them.
    #[staticmethod]
    fn kinds() -> Vec<&'static str> {
        KINDS.to_vec()
    }

    /// The parameter names of a medium of kind `kind` with `terms` Prony terms.
    #[staticmethod]
    #[pyo3(signature = (kind, terms=0))]
    fn parameter_names(py: Python<'_>, kind: &str, terms: usize) -> PyResult<Vec<String>> {
        medium::parameter_names(kind, terms).map_err(|e| to_pyerr(py, e))
    }

    /// The medium's kind.
    #[getter]
    fn kind(&self) -> &'static str {
        self.inner.kind()
    }

    /// The Poisson ratio.
    #[getter]
    fn nu(&self) -> f64 {
        self.inner.nu()
    }

    /// The parameters (name, value) in the crate's order; nu is not one.
    fn parameters(&self) -> Vec<(String, f64)> {
        self.inner.parameters()
    }

    /// (G_inf, [(G_k, tau_k), ...], eta): the shear relaxation modulus as a Prony series with
    /// a dashpot (Pa, s, Pa s), unscaled by nu; the power law is refused.
    #[allow(clippy::type_complexity)]
    fn rheology(&self, py: Python<'_>) -> PyResult<(f64, Vec<(f64, f64)>, f64)> {
        let r = self.inner.series().map_err(|e| to_pyerr(py, e))?;
        Ok((r.g_inf, r.terms, r.eta))
    }

    /// Shear relaxation modulus G(t) (Pa) at times `t` (s, any shape).
    fn relaxation_modulus<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArrayDyn<'py, f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        map_array(py, &t, |v| self.inner.relaxation_modulus(v))
    }

    /// Shear creep compliance J(t) (1/Pa) at times `t` (s, any shape).
    fn creep_compliance<'py>(
        &self,
        py: Python<'py>,
        t: PyReadonlyArrayDyn<'py, f64>,
    ) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
        let shape = t.shape().to_vec();
        let times = t.as_array().iter().copied().collect::<Vec<f64>>();
        let m = &self.inner;
        // a Prony series steps each time on its own grid: in parallel
        let out = in_pool(py, || {
            times
                .par_iter()
                .map(|&v| m.creep_compliance(v))
                .collect::<crate::Result<Vec<f64>>>()
        })?
        .map_err(|e| to_pyerr(py, e))?;
        let array = ArrayD::from_shape_vec(IxDyn(&shape), out)
            .map_err(|e| to_pyerr(py, Error::InvalidInput(e.to_string())))?;
        Ok(array.into_pyarray(py))
    }
}
