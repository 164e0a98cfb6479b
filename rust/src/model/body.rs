//! The body a scene presses into: which solid it is, decided once per scene
//! (`Scene::body`) and carried by its BEM grid. The body's operators, kernel tables and
//! preconditioners are built in `crate::halfspace::body`, the only place that builds them;
//! the engines ask the body what it can do (`windows`, `has_edge`) instead of what it is.
//! A finite-thickness layer on a rigid base (`Layer`) is a body of its own, free or
//! periodic.

use crate::support::error::{check_finite_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// How a layer is joined to its rigid base.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Base {
    /// Bonded: the layer's bottom does not move (no slip).
    #[default]
    Bonded,
    /// Frictionless: the bottom stays on the base (no normal displacement) and slides
    /// freely along it (no shear traction).
    Frictionless,
}

impl Base {
    /// The base's name in scene files ("bonded", "frictionless").
    pub fn name(self) -> &'static str {
        match self {
            Base::Bonded => "bonded",
            Base::Frictionless => "frictionless",
        }
    }
}

/// A layer of the scene's medium, of uniform thickness, on a rigid flat base: the scene
/// key `layer` (absent: a half-space).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Layer {
    /// Thickness (m), > 0.
    pub thickness: f64,
    /// How the layer is joined to its base (default bonded).
    #[serde(default)]
    pub base: Base,
}

impl Layer {
    /// Fails unless the thickness is finite and > 0.
    pub fn validate(&self) -> Result<()> {
        check_finite_positive("layer.thickness", self.thickness)
    }
}

/// Mean separations below this fraction of the mean height count as full contact on a
/// periodic cell (round-off of the mean over a large cell stays far below it).
pub const FULL_CONTACT: f64 = 1e-9;

/// The solid under the indenter, of the scene's medium.
#[derive(Debug, Clone, Copy, PartialEq, Default, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Body {
    /// A half-space with a free surface: pressure far from the contact is zero and the
    /// surface is at rest at infinity.
    #[default]
    HalfSpace,
    /// A half-space whose surface repeats with the periods of its grid (one cell of a
    /// periodic height map): depths are approaches from the deflected surface's mean plane
    /// and forces are totals on the cell.
    Periodic,
    /// A layer on a rigid base (`Layer`) of Poisson ratio `nu` (the medium's), with a free
    /// surface, or with `periodic` one cell of a periodic one (depths and forces as on a
    /// periodic half-space).
    Layer {
        /// Thickness and base.
        layer: Layer,
        /// Poisson ratio of the layer, -1 < nu <= 0.5.
        nu: f64,
        /// Whether the surface repeats with the periods of its grid.
        periodic: bool,
    },
}

impl Body {
    /// The body's name ("halfspace", "periodic", "layer", "periodic layer").
    pub fn name(self) -> &'static str {
        match self {
            Body::HalfSpace => "halfspace",
            Body::Periodic => "periodic",
            Body::Layer {
                periodic: false, ..
            } => "layer",
            Body::Layer { periodic: true, .. } => "periodic layer",
        }
    }

    /// Whether the body's surface repeats with the periods of its grid.
    pub fn is_periodic(self) -> bool {
        match self {
            Body::HalfSpace => false,
            Body::Periodic => true,
            Body::Layer { periodic, .. } => periodic,
        }
    }

    /// The layer of a layered body; None for a half-space.
    pub fn layer(self) -> Option<Layer> {
        match self {
            Body::Layer { layer, .. } => Some(layer),
            Body::HalfSpace | Body::Periodic => None,
        }
    }

    /// Whether a contact on the body can be solved on a window of its grid that holds the
    /// contact, the elements outside carrying no pressure (a free surface's deflection
    /// inside depends only on the pressure inside); otherwise (a periodic cell) every solve
    /// takes the whole grid. A free layer's surface may rise around a contact (an
    /// incompressible layer bulges): its windows widen by the most it can rise
    /// (`Body::least_coefficient`).
    pub fn windows(self) -> bool {
        !self.is_periodic()
    }

    /// Whether the grid has an edge a contact can reach (a periodic cell has none: its
    /// opposite edges meet).
    pub fn has_edge(self) -> bool {
        !self.is_periodic()
    }

    /// Whether a cold depth-controlled solve is reached by force-controlled solves first: on
    /// a periodic cell a cold depth-controlled start overloads the cell, whose zero-mean
    /// deflection lifts the rest of its surface into contact, and Polonsky–Keer can end
    /// released there (`crate::bem::static_contact::load_to_separation`).
    pub fn loads_depth_by_force(self) -> bool {
        self.is_periodic()
    }

    /// Fails on a depth `depth` (m) the body cannot be pressed to by depth control, its
    /// separation before loading having the mean `mean_height` (m). A periodic cell's depth
    /// is the approach from its deflected surface's mean plane, so its mean separation is
    /// mean_height - depth; at zero the cell is in full contact under any force above the
    /// one that closes it (depth control leaves the force undetermined), and below zero no
    /// force reaches it: a mean separation within `FULL_CONTACT` of the mean height of zero,
    /// or below, is refused. A free surface takes any depth.
    pub fn check_depth(self, mean_height: f64, depth: f64) -> Result<()> {
        match self.is_periodic() {
            false => Ok(()),
            true => {
                let separation = mean_height - depth;
                if separation > FULL_CONTACT * mean_height.abs() {
                    Ok(())
                } else {
                    Err(Error::InvalidInput(format!(
                        "the mean separation of a periodic cell must be > 0 m, got {separation:e} m \
                         (depth {depth:e} m; full contact at depth {mean_height:e} m)"
                    )))
                }
            }
        }
    }
}
