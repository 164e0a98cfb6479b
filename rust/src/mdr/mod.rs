//! The method of dimensionality reduction: the 1D foundation of independent elements and
//! its elastic and viscous stepping (`foundation`), viscoelastic stepping (`viscoelastic`),
//! the inverse transforms back to 3D fields (`transforms`) and the fits' prepared curve with
//! its parameter derivatives (`curve`).

pub mod adhesion;
pub mod adhesion_crack;
pub mod curve;
pub mod foundation;
pub mod layer;
pub mod transforms;
pub mod viscoelastic;
