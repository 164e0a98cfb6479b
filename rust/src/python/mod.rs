//! pyo3 bindings (cargo feature "python"): numpy in, typed objects out (`Scene`, `Report`,
//! `FieldSet`, `SurfaceOperator`). Computations run on a rayon worker with the GIL released
//! (`monitor`); inputs are converted in `convert`; scenes in `scene`, indenters and media in
//! `model`, arrays in `arrays`, random surfaces in `surfaces`; the schema Python builds its
//! lists from (outputs, report quantities, defaults) in `schema`.

mod arrays;
mod cohesive;
mod convert;
mod curve;
mod model;
mod monitor;
mod pool;
mod report;
mod scene;
mod schema;
mod surfaces;

/// The compiled core of mdrvisc.
#[pyo3::pymodule(name = "_core")]
mod core_module {
    #[pymodule_export]
    use super::arrays::{
        bem_punch, bem_viscous, contact_solve, mdr_deflection, mdr_pressure, surface_deflection,
        PySurfaceOperator,
    };
    #[pymodule_export]
    use super::cohesive::{cohesive_curve, cohesive_pull_off};
    #[pymodule_export]
    use super::curve::PyCurve;
    #[pymodule_export]
    use super::pool::{num_threads, set_num_threads};
    #[pymodule_export]
    use super::surfaces::self_affine;
    /// Largest magnitude of a physical input (and inverse of the smallest nonzero one).
    #[pymodule_export]
    const MAGNITUDE: f64 = crate::support::error::MAGNITUDE;
    /// Largest input file (bytes) the command lines read: scene, sweep and curve files.
    #[pymodule_export]
    const MAX_FILE_BYTES: u64 = crate::model::file::MAX_FILE_BYTES;
    /// tan(psi) / tan(alpha) of the cone MDR solves in place of a four-sided pyramid.
    #[pymodule_export]
    const EQUIVALENT_CONE_FACTOR: f64 = crate::model::indenter::pyramid::EQUIVALENT_CONE_FACTOR;
    #[pymodule_export]
    use super::model::{PyIndenter, PyMedium};
    #[pymodule_export]
    use super::report::{PyFieldSet, PyReport};
    #[pymodule_export]
    use super::scene::{
        load_scene_file, parse_scene_file, parse_scene_table, read_scene_file, run_loads,
        run_memory, run_scene, PyScene,
    };

    /// Imports NumPy's C API and adds the schema: `OUTPUTS`, `QUANTITIES`,
    /// `SOLVER_DEFAULTS`, `DEFAULT_N`.
    #[pymodule_init]
    fn init(m: &pyo3::Bound<'_, pyo3::types::PyModule>) -> pyo3::PyResult<()> {
        // NumPy's C API is imported here, where an exception (a Ctrl-C while its Python
        // code runs) propagates from the import; imported lazily by the first array a call
        // returns, it would be a panic. The first array then finds it imported and runs no
        // Python code.
        numpy::get_array_module(m.py())?;
        numpy::PyArray1::<f64>::zeros(m.py(), 0, false);
        super::schema::add(m)
    }
}
