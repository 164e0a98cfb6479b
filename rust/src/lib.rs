//! mdrvisc: normal contact of rigid indenters with elastic, viscous and viscoelastic bodies,
//! by the boundary element method (BEM) and the method of dimensionality reduction (MDR).
//!
//! Units are SI throughout (m, s, N, Pa, Pa s). Depths and deflections are positive into
//! the body.
//!
//! Layers, from the bottom: `support` (errors, progress, memory, threads, files); `model`
//! (the scene: indenter, medium, body, contact law, loading, outputs, settings); `halfspace`
//! (pressure to deflection: influence coefficients, free and periodic operators,
//! preconditioners); the engines `bem` and `mdr`; and `run`, which sizes a scene's grid,
//! dispatches it to the engines and builds its `Report`. The Python bindings (`python`) and
//! the binary sit on top. No module imports one above it.

pub mod bem;
pub mod halfspace;
pub mod mdr;
pub mod model;
#[cfg(feature = "python")]
mod python;
pub mod run;
pub mod stepping;
pub mod support;

pub use support::error::{Error, Result};
