//! The fit's forward model: a prepared indentation curve (`crate::mdr::curve::Curve`) evaluated
//! for media given as the scene model's JSON, with derivatives in the logarithms of the
//! named parameters; the media of one call run in parallel with the GIL released, stopped
//! by Ctrl-C.

use super::convert::slice1;
use super::monitor::{to_pyerr, PyMonitor};
use crate::mdr::curve::{AdhesiveEvaluation, Approach, Control, Curve, Forward};
use crate::model::medium::rheology::Rheology;
use crate::model::Medium;
use crate::support::error::Error;
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1};
use pyo3::prelude::*;
use rayon::prelude::*;

/// One evaluation: the computed values at the samples, their derivatives (samples x
/// parameters), the elements in contact, and how the curve was evaluated.
type Evaluated<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<u64>>,
    &'static str,
);

/// An adhesive evaluation: force, contact radius and depth at the samples, and the elements
/// in contact.
type AdhesiveEvaluated<'py> = (
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<u64>>,
);

/// An indentation curve prepared once: the half MDR profile (m, at x = (i + 1/2) dx), the
/// samples (s) and the prescribed depth (m, control "depth"), force (N, "force") or drive
/// through a spring of `stiffness` (m and N/m, "spring": an AFM cantilever on its piezo).
#[pyclass(name = "Curve", module = "mdrvisc._core", frozen)]
pub(crate) struct PyCurve {
    inner: Curve,
}

#[pymethods]
impl PyCurve {
    #[new]
    #[pyo3(signature = (profile, dx, times, values, control, substeps=1, stiffness=None))]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        profile: PyReadonlyArray1<'_, f64>,
        dx: f64,
        times: PyReadonlyArray1<'_, f64>,
        values: PyReadonlyArray1<'_, f64>,
        control: &str,
        substeps: usize,
        stiffness: Option<f64>,
    ) -> PyResult<Self> {
        let control = match (control, stiffness) {
            ("depth", None) => Control::Depth,
            ("force", None) => Control::Force,
            ("spring", Some(k)) => Control::Spring(k),
            (other, k) => {
                return Err(to_pyerr(
                    py,
                    Error::InvalidInput(format!(
                        "control must be \"depth\" or \"force\", or \"spring\" with a stiffness (N/m); got {other:?} with stiffness {k:?}"
                    )),
                ))
            }
        };
        let inner = Curve::new(
            slice1(py, &profile, "profile")?,
            dx,
            slice1(py, &times, "times")?,
            slice1(py, &values, "values")?,
            control,
            substeps,
        )
        .map_err(|e| to_pyerr(py, e))?;
        Ok(PyCurve { inner })
    }

    /// The same curve, always evaluated by stepping the elements (Ting's solution off: for
    /// comparisons).
    fn elements_only(&self) -> Self {
        PyCurve {
            inner: self.inner.clone().elements_only(),
        }
    }

    /// The shortest step and the last sample time (s): the range a power law's series holds.
    fn time_range(&self) -> (f64, f64) {
        self.inner.time_range()
    }

    /// For each medium (JSON of a scene's medium table): the force (N, depth and spring
    /// control) or depth (m, force control) at the samples, its derivatives with respect to the natural
    /// logarithms of the parameters named in `free` (samples x parameters), and the
    /// elements of the half profile in contact, and the forward model that ran
    /// ("hereditary": Ting's solution; "elements": the elements stepped). With `shift` (m; depth and spring control)
    /// every prescribed depth or drive is moved by it and the derivative along it (N/m) is a last column.
    #[pyo3(signature = (media, free, shift=None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        media: Vec<String>,
        free: Vec<String>,
        shift: Option<f64>,
    ) -> PyResult<Vec<Evaluated<'py>>> {
        let (t_lo, t_hi) = self.inner.time_range();
        let parsed = media
            .iter()
            .map(|text| {
                let m: Medium = serde_json::from_str(text)
                    .map_err(|e| Error::InvalidInput(format!("medium: {e}")))?;
                m.validate()?;
                m.rheology_tangents_of(&free, t_lo, t_hi)
            })
            .collect::<crate::Result<Vec<_>>>()
            .map_err(|e| to_pyerr(py, e))?;
        let curve = &self.inner;
        // served like a solve: Ctrl-C stops the evaluation within a step or an element
        let results = PyMonitor::new(None).run(py, |monitor| {
            let stop = monitor.stop();
            parsed
                .par_iter()
                .map(|(r, tangents)| curve.evaluate_until(r, tangents, shift, &stop))
                .collect::<crate::Result<Vec<_>>>()
        })?;
        let (k, p) = (curve.len(), free.len() + usize::from(shift.is_some()));
        results
            .into_iter()
            .map(|e| {
                let jacobian = numpy::ndarray::Array2::from_shape_vec((k, p), e.jacobian)
                    .map_err(|err| to_pyerr(py, Error::InvalidInput(err.to_string())))?;
                let contact: Vec<u64> = e.contact.iter().map(|&c| c as u64).collect();
                let forward = match e.forward {
                    Forward::Hereditary => "hereditary",
                    Forward::Elements => "elements",
                };
                Ok((
                    e.values.into_pyarray(py),
                    jacobian.into_pyarray(py),
                    contact.into_pyarray(py),
                    forward,
                ))
            })
            .collect()
    }
    /// JKR contact (work of adhesion `work_of_adhesion`, J/m^2) of an elastic medium (JSON of a
    /// scene's medium table) by MDR with a continuous contact edge, depth or spring control:
    /// the force (N), contact radius (m), depth (m) and elements of the half profile in
    /// contact at the samples, every prescribed depth or drive moved by `shift` (m); the edge
    /// advances on the approach by `approach`: "touch" (a hard contact's growth) or
    /// "equilibrium" (the JKR branch, jumping in at the touch). A viscoelastic medium (a
    /// relaxed modulus, no dashpot; depth control, touch approach) lets go by the relaxed
    /// modulus, each element carrying its hereditary integral since it attached.
    #[pyo3(signature = (medium, work_of_adhesion, shift=0.0, approach="touch"))]
    fn evaluate_jkr<'py>(
        &self,
        py: Python<'py>,
        medium: String,
        work_of_adhesion: f64,
        shift: f64,
        approach: &str,
    ) -> PyResult<AdhesiveEvaluated<'py>> {
        let approach = match approach {
            "touch" => Approach::Touch,
            "equilibrium" => Approach::Equilibrium,
            other => {
                return Err(to_pyerr(
                    py,
                    Error::InvalidInput(format!(
                        "approach must be \"touch\" or \"equilibrium\", got {other:?}"
                    )),
                ))
            }
        };
        let e = self
            .rheology(&medium)
            .and_then(|r| {
                if r.terms.is_empty() && r.eta == 0.0 {
                    self.inner
                        .evaluate_jkr(4.0 * r.g_inf, work_of_adhesion, shift, approach)
                } else if approach == Approach::Touch {
                    self.inner
                        .evaluate_jkr_viscoelastic(&r, work_of_adhesion, shift)
                } else {
                    Err(Error::InvalidInput(
                        "a viscoelastic adhesive curve grows its contact by the touch rule".into(),
                    ))
                }
            })
            .map_err(|e| to_pyerr(py, e))?;
        Ok(adhesive_arrays(py, e))
    }

    /// `evaluate_jkr` for DMT: hard contact plus the `attraction` (N, 2 pi w R) while the
    /// surfaces touch.
    #[pyo3(signature = (medium, attraction, shift=0.0))]
    fn evaluate_dmt<'py>(
        &self,
        py: Python<'py>,
        medium: String,
        attraction: f64,
        shift: f64,
    ) -> PyResult<AdhesiveEvaluated<'py>> {
        let e = self
            .contact_modulus(&medium)
            .and_then(|e_star| self.inner.evaluate_dmt(e_star, attraction, shift))
            .map_err(|e| to_pyerr(py, e))?;
        Ok(adhesive_arrays(py, e))
    }
}

impl PyCurve {
    /// The relaxation modulus of a medium (JSON of a scene's medium table) over the curve's
    /// times.
    fn rheology(&self, medium: &str) -> crate::Result<Rheology> {
        let (t_lo, t_hi) = self.inner.time_range();
        let m: Medium = serde_json::from_str(medium)
            .map_err(|e| Error::InvalidInput(format!("medium: {e}")))?;
        m.validate()?;
        Ok(m.rheology_tangents_of(&[], t_lo, t_hi)?.0)
    }

    /// The contact modulus E* (Pa) of an elastic medium (JSON of a scene's medium table).
    fn contact_modulus(&self, medium: &str) -> crate::Result<f64> {
        let r = self.rheology(medium)?;
        if !r.terms.is_empty() || r.eta != 0.0 {
            return Err(Error::InvalidInput(
                "an adhesive curve is computed for an elastic medium".into(),
            ));
        }
        Ok(4.0 * r.g_inf)
    }
}

/// The arrays of an adhesive evaluation.
fn adhesive_arrays(py: Python<'_>, e: AdhesiveEvaluation) -> AdhesiveEvaluated<'_> {
    let contact: Vec<u64> = e.contact.iter().map(|&c| c as u64).collect();
    (
        e.values.into_pyarray(py),
        e.contact_radius.into_pyarray(py),
        e.depth.into_pyarray(py),
        contact.into_pyarray(py),
    )
}
