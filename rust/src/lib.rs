//! mdrvisc: normal contact of rigid indenters with viscous half-spaces, by the boundary
//! element method (BEM) and the method of dimensionality reduction (MDR).
//!
//! Units are SI throughout (m, s, N, Pa, Pa s). Depths and deflections are positive into
//! the body.

//!
//! Layers, from the bottom: the half-space's influence coefficients (`influence`) and
//! surface operators (`operator`, `periodic`, `precondition`); contact solvers (`contact`,
//! `static_contact`, `window`, `grid`); time stepping (`viscous`, `viscoelastic`, `mdr`,
//! `rheology`, `integrator`, `loading`, `transforms`); the scene model (`scene`), which
//! sizes grids, dispatches to the solvers and reports; and its applications (the
//! binary, the Python bindings in `python`); random rough surfaces (`surfaces`).

pub mod contact;
pub mod curve;
pub mod error;
pub mod grid;
pub mod influence;
pub mod integrator;
pub mod loading;
pub mod mdr;
pub mod memory;
pub mod monitor;
pub mod npy;
pub mod operator;
pub mod periodic;
pub mod pool;
pub mod power_law;
pub mod precondition;
#[cfg(feature = "python")]
mod python;
pub mod rheology;
pub mod scene;
pub mod static_contact;
pub mod surfaces;
pub mod transforms;
pub mod viscoelastic;
pub mod viscous;
pub mod window;

pub use error::{Error, Result};
