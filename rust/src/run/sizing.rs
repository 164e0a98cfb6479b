//! Grid sizing: how far the BEM grid and the MDR foundation reach for an unbounded
//! indenter (the largest contact radius, by MDR's closed forms or quadrature), and the depth
//! bounds that size the BEM steps' windows.

use crate::mdr::foundation::Foundation;
use crate::model::grid::Grid;
use crate::model::indenter::Footprint;
use crate::model::{Medium, Scene};
use crate::support::error::{Error, Result};
use std::f64::consts::PI;

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
    let law = scene.contact;
    // a cohesive zone pulls the contact in beyond the hard contact's (MDR's JKR grows by
    // touch, as a hard contact, and DMT's attraction is a load)
    if law.is_cohesive() {
        if let Some(e_star) = relaxed_contact_modulus(scene, &medium)? {
            return adhesive_radius_at_force(scene, force.max(), e_star);
        }
    }
    match medium {
        Medium::Elastic { g, .. } if law.is_adhesive() => {
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

/// The contact modulus (Pa) that bounds a force-controlled scene's contact: 4 G of an
/// elastic medium, 4 / J(duration) of a viscoelastic one; None for a viscous medium (sized
/// by its impulse).
fn relaxed_contact_modulus(scene: &Scene, medium: &Medium) -> Result<Option<f64>> {
    Ok(match medium {
        Medium::Elastic { g, .. } => Some(4.0 * g),
        Medium::Viscous { .. } => None,
        _ => {
            let duration = scene.duration.expect("validated: a duration");
            Some(4.0 / medium.creep_compliance(duration)?)
        }
    })
}

/// A bound (m) of the radius a cohesive-zone contact reaches at the force `force` (N) on a
/// body of contact modulus `e_star` (Pa): the largest radius a at which JKR's equilibrium
/// force E* s(a) - sqrt(8 pi w E* a^3) (s the MDR load of the profile, Hess's rule) is at most
/// the force - JKR's contact is the widest of the adhesive limits at a given force - taken
/// three ranges deeper, where the zone's traction still acts (as under depth control).
fn adhesive_radius_at_force(scene: &Scene, force: f64, e_star: f64) -> Result<f64> {
    let ind = &scene.indenter;
    let w = scene.contact.work_of_adhesion();
    let excess = |a: f64| -> Result<f64> {
        Ok(e_star * ind.load_at_radius(a)? - (8.0 * PI * w * e_star * a.powi(3)).sqrt() - force)
    };
    let mut lo = ind.radius_at_load(force.max(0.0) / e_star)?;
    let mut hi = if lo > 0.0 {
        2.0 * lo
    } else {
        // JKR's zero-load radius of a paraboloid of unit radius sets the scale
        (4.5 * PI * w / e_star).cbrt()
    };
    let mut doublings = 0;
    while excess(hi)? <= 0.0 {
        lo = hi;
        hi *= 2.0;
        doublings += 1;
        if doublings > 200 {
            return Err(Error::InvalidInput(
                "the adhesive contact grows without bound under this force: no grid holds it"
                    .into(),
            ));
        }
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if excess(mid)? <= 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    ind.radius_at_depth(ind.profile_1d(hi)? + 3.0 * scene.contact.range())
}

/// Half-width (m) of the square the BEM grid covers: the footprint, or for an unbounded
/// indenter `UNBOUNDED_MARGIN` times its largest contact radius; a sphere's grid takes the
/// smaller of the two (its contact grows with depth inside the footprint, and a grid over
/// the whole footprint would spend its elements where nothing touches).
pub fn bem_half_width(scene: &Scene) -> Result<f64> {
    match scene.indenter.footprint() {
        Footprint::Unbounded => unbounded_extent(scene),
        Footprint::Disc { radius, rim: false } => Ok(match sizing_radius(scene) {
            // no contact radius below the footprint's (a contact that reaches the rim, or
            // no load): the footprint holds every contact the sphere makes
            Ok(a) if a > 0.0 => (UNBOUNDED_MARGIN * a).min(radius),
            _ => radius,
        }),
        _ => Ok(scene
            .indenter
            .half_width()
            .expect("a bounded footprint has a half-width")),
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
