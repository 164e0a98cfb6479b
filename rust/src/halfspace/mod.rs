//! Pressure to surface deflection of an elastic half-space of unit shear modulus: Love's
//! influence coefficients of a uniformly loaded square (`influence`), the free surface's
//! DC-FFT and dense operators with the truncated inverse-kernel stencil that preconditions
//! them (`operator`), the periodic cell's spectral operator (`periodic`), and a layer's spectral compliance
//! on a rigid base (`layer`). Engines reach these only through `crate::model::body::Body`.

pub mod body;
pub mod influence;
pub mod layer;
pub mod operator;
pub mod periodic;
