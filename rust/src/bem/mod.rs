//! The boundary element method on a grid: the static contact solvers (`contact`:
//! Polonsky–Keer, the dense active set, the flat punch), the windows of the elements that
//! can touch (`window`), static contact (`static_contact`), and time stepping of viscous
//! (`viscous`) and viscoelastic (`viscoelastic`) bodies; adhesive contact with a cohesive-zone
//! law (`cohesive`).

pub mod cohesive;
pub mod contact;
pub mod nested;
pub mod static_contact;
pub mod viscoelastic;
pub mod viscous;
pub mod window;
