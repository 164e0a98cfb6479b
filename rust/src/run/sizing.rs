//! Grid sizing: how far the BEM grid and the MDR foundation reach for an unbounded
//! indenter (the largest contact radius, by MDR's closed forms or quadrature), and the depth
//! bounds that size the BEM steps' windows.

use crate::mdr::foundation::Foundation;
use crate::model::grid::Grid;
use crate::model::{Medium, Scene};
use crate::support::error::{Error, Result};

/// An unbounded indenter's grid reaches this factor times its largest contact radius.
pub const UNBOUNDED_MARGIN: f64 = 1.2;

/// Depth bounds that size the BEM windows: this factor times MDR's depth.
pub const DEPTH_BOUND_FACTOR: f64 = 1.05;

/// The largest contact radius (m) the scene reaches, by MDR (closed forms where they
/// exist): elastic at its force; viscous at its last impulse; viscoelastic at its largest
/// force with the modulus 1 / J(duration), or at its largest depth (on a layer the larger
/// of the half-space's and the layer's, `mdr_layer::radius_at_depth`).
pub fn sizing_radius(scene: &Scene) -> Result<f64> {
    let ind = &scene.indenter;
    if let Some(d) = &scene.depth {
        // a cohesive zone reaches gaps of a few times its range
        let depth = d.max() + 3.0 * scene.contact.range();
        let half = ind.radius_at_depth(depth)?;
        // a layer's contact is wider than the half-space's at the same depth
        let layer = match scene.layer {
            Some(layer) => super::mdr_layer::radius_at_depth(scene, layer, depth)?,
            None => None,
        };
        return Ok(layer.map_or(half, |a| a.max(half)));
    }
    let force = scene.force.as_ref().expect("validated: force or depth");
    // MDR loads F / (4 G) of the incompressible medium with the same contact modulus; an
    // adhesive contact is widest at its largest force (DMT: plus its attraction)
    let medium = scene.medium.incompressible_equivalent()?;
    let attraction = scene.contact.attraction(ind.tip_radius())?;
    match medium {
        Medium::Elastic { g, .. } if scene.contact.is_adhesive() => {
            ind.radius_at_load((force.max() + attraction) / (4.0 * g))
        }
        Medium::Elastic { g, .. } => ind.radius_at_load(force.last() / (4.0 * g)),
        Medium::Viscous { eta, .. } => {
            let t_end = *scene
                .solved_times()
                .last()
                .expect("validated: output times");
            let impulse = force.force(scene.contact)?.impulse(t_end) + attraction * t_end;
            ind.radius_at_load(impulse / (4.0 * eta))
        }
        _ => {
            let duration = scene.duration.expect("validated: a duration");
            let compliance = medium.creep_compliance(duration)?;
            ind.radius_at_load((force.max() + attraction) * compliance / 4.0)
        }
    }
}

/// Half-width (m) of the square the BEM grid covers: the footprint, or for an unbounded
/// indenter `UNBOUNDED_MARGIN` times its largest contact radius.
pub fn bem_half_width(scene: &Scene) -> Result<f64> {
    match scene.indenter.half_width() {
        Some(h) => Ok(h),
        None => unbounded_extent(scene),
    }
}

/// `UNBOUNDED_MARGIN` times the largest contact radius of a scene whose indenter has no
/// edge; an error when that radius is zero (no load at any time: nothing sizes the grid).
fn unbounded_extent(scene: &Scene) -> Result<f64> {
    let radius = sizing_radius(scene)?;
    if radius > 0.0 {
        Ok(UNBOUNDED_MARGIN * radius)
    } else {
        Err(Error::InvalidInput(
            "the indenter is unbounded and the load is zero throughout: no contact sizes the grid; give the indenter an edge or a load".into(),
        ))
    }
}

/// Half-length (m) of the MDR foundation: the 1D indenter, or for an unbounded indenter
/// `UNBOUNDED_MARGIN` times its largest contact radius.
pub fn mdr_half_length(scene: &Scene) -> Result<f64> {
    match scene.indenter.half_length_1d() {
        Some(h) => Ok(h),
        None => unbounded_extent(scene),
    }
}

/// Upper bounds of the depth (m) at each output time of a viscous scene under a force,
/// which size the BEM steps' windows: `DEPTH_BOUND_FACTOR` times MDR's depth, NaN where the
/// contact would leave the footprint (the solver then extrapolates; it checks every bound
/// and widens a window that was too small).
pub fn depth_bounds(scene: &Scene) -> Result<Vec<f64>> {
    let eta = match scene.medium.incompressible_equivalent()? {
        Medium::Viscous { eta, .. } => eta,
        _ => {
            return Err(Error::InvalidInput(
                "depth bounds need a viscous medium".into(),
            ))
        }
    };
    let history = match &scene.force {
        Some(f) => f.force(scene.contact)?,
        None => {
            return Err(Error::InvalidInput(
                "depth bounds need a force history".into(),
            ))
        }
    };
    Ok(scene
        .solved_times()
        .iter()
        .map(|&t| {
            match scene
                .indenter
                .depth_at_load(history.impulse(t) / (4.0 * eta))
            {
                Ok(Some(d)) => DEPTH_BOUND_FACTOR * d,
                _ => f64::NAN,
            }
        })
        .collect())
}

/// The largest radius (m) at which a solve of the scene evaluates the indenter: the BEM
/// grid's corner.
pub fn extent_needed(scene: &Scene) -> Result<f64> {
    Ok(bem_half_width(scene)?.max(mdr_half_length(scene)?) * 2f64.sqrt())
}

/// The BEM grid of `scene` with n elements across (see `Indenter::bem_grid`).
pub fn bem_grid(scene: &Scene, n: usize) -> Result<Grid> {
    let mut grid = scene.indenter.bem_grid(n, bem_half_width(scene)?)?;
    grid.body = scene.body();
    Ok(grid)
}

/// The MDR foundation of `scene` with n elements.
pub fn mdr_foundation(scene: &Scene, n: usize) -> Result<Foundation> {
    let (g, dx) = scene.indenter.mdr_profile(n, mdr_half_length(scene)?)?;
    Foundation::new(g, dx, scene.contact)
}
