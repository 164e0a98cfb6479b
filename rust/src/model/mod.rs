//! The scene model: what a run computes, decided once. The indenter, the medium, the
//! loading history, the outputs and their times (`scene`), the BEM grid an indenter is
//! sampled onto (`grid`), scene files (`file`), random rough surfaces to indent with
//! (`surfaces`) and how a scene is solved (`settings`). Nothing here imports an engine.

pub mod body;
pub mod contact_law;
pub mod file;
pub mod grid;
pub mod indenter;
pub mod loading;
pub mod medium;
pub mod parts;
pub mod quantities;
pub mod scene;
pub mod settings;
pub mod surfaces;

pub use body::Body;
pub use contact_law::ContactLaw;
pub use file::SceneFile;
pub use indenter::heightmap::{HeightMap, HeightMapTable};
pub use indenter::profile::{Profile, ProfileTable};
pub use indenter::{Footprint, Indenter};
pub use medium::Medium;
pub use parts::SceneArrays;
pub use scene::{History, Output, Scene, COINCIDENT_TIMES, DEFAULT_OUTPUTS, EARLIEST_TIME};
pub use settings::{Integrator, Method, RunSettings};
