//! Pressure to surface deflection of an elastic half-space of unit shear modulus: Love's
//! influence coefficients of a uniformly loaded square (`influence`), the free surface's
//! DC-FFT and dense operators (`operator`), the periodic cell's spectral operator
//! (`periodic`) and the truncated inverse-kernel stencil that preconditions the free one
//! (`precondition`). Engines reach these only through `crate::model::body::Body`.

pub mod influence;
pub mod operator;
pub mod periodic;
pub mod precondition;
