//! mdrvisc: normal contact of rigid indenters with viscous half-spaces, by the boundary
//! element method (BEM) and the method of dimensionality reduction (MDR).
//!
//! Units are SI throughout (m, s, N, Pa, Pa s). Depths and deflections are positive into
//! the body.

pub mod error;
pub mod influence;
pub mod monitor;
pub mod operator;
pub mod precondition;
pub mod rheology;

pub use error::{Error, Result};
pub mod contact;
pub mod grid;
pub mod integrator;
pub mod loading;
pub mod mdr;
#[cfg(feature = "python")]
mod python;
pub mod scenes;
pub mod static_contact;
pub mod transforms;
pub mod viscoelastic;
pub mod viscous;
pub mod window;
