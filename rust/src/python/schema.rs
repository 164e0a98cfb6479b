//! The crate's schema, for the Python package to build its own lists from: the outputs a
//! scene may ask for, the quantities of a report with their units, the solver's defaults
//! and the default and largest resolutions.

use crate::model::quantities::QUANTITIES;
use crate::model::settings::ExplicitControl;
use crate::model::settings::SolverOptions;
use crate::model::settings::{default_n, max_n};
use crate::model::{Integrator, Method, Output};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

/// Adds `OUTPUTS`, `QUANTITIES`, `SOLVER_DEFAULTS` and `DEFAULT_N` to the module `m`.
pub(crate) fn add(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    let outputs = Output::ALL.map(|o| {
        (
            o.name(),
            o.unit(),
            o.kind().name(),
            o.is_default(),
            o.is_height_map(),
        )
    });
    // (name, unit, kind, default, height map only) of each output
    m.add("OUTPUTS", PyTuple::new(py, outputs)?)?;
    let quantities = QUANTITIES.map(|(name, unit, kind)| (name, unit, kind.name()));
    // (name, unit, kind) of each quantity of a report
    m.add("QUANTITIES", PyTuple::new(py, quantities)?)?;
    let solver = SolverOptions::default();
    let explicit = ExplicitControl::default();
    let defaults = PyDict::new(py);
    defaults.set_item("tol", solver.tol)?;
    defaults.set_item("max_iter", solver.max_iter)?;
    defaults.set_item("integrator", Integrator::Implicit.name())?;
    defaults.set_item("step", explicit.step)?;
    defaults.set_item("area_change", explicit.area_change)?;
    defaults.set_item("dt", None::<f64>)?;
    defaults.set_item("precondition", solver.precondition)?;
    defaults.set_item("dense_limit", solver.dense_limit)?;
    defaults.set_item("active_limit", solver.active_limit)?;
    m.add("SOLVER_DEFAULTS", defaults)?;
    let resolutions = PyDict::new(py);
    for method in [Method::Bem, Method::Mdr] {
        resolutions.set_item(method.name(), default_n(method))?;
    }
    m.add("DEFAULT_N", resolutions)?;
    let limits = PyDict::new(py);
    for method in [Method::Bem, Method::Mdr] {
        limits.set_item(method.name(), max_n(method))?;
    }
    m.add("MAX_N", limits)?;
    Ok(())
}
