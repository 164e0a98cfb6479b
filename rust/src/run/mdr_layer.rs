//! MDR on a layer (`crate::mdr::layer`): the layered profile and element weights from the
//! scene, then the weighted hereditary foundation; hard contact, elastic and viscoelastic
//! media, no fields. Also the layer's contact radius at a depth, which sizes the grids of
//! depth-controlled scenes on a layer (`radius_at_depth`).

use super::assemble::{report_from, Wanted};
use super::report::Report;
use super::sizing::mdr_half_length;
use super::{refuse, step_length, stepped_rheology};
use crate::halfspace::layer::gauss_legendre;
use crate::mdr::layer::{
    depth_at_radius, element_weights, layered_profile, run_mdr_layer, CHI_MAX,
};
use crate::model::body::{Base, Layer};
use crate::model::indenter::{bisect_radius, Footprint, Reach};
use crate::model::medium::rheology::Rheology;
use crate::model::settings::RunSettings;
use crate::model::{Medium, Output, Scene};
use crate::stepping::Request;
use crate::support::error::{Error, Result};
use crate::support::monitor::Monitor;

/// A scene with a layer by MDR: fails for an adhesive contact law, a viscous medium and
/// field outputs (their inverse transforms are the half-space's).
pub(super) fn run(
    scene: &Scene,
    settings: &RunSettings,
    monitor: &mut dyn Monitor,
) -> Result<Report> {
    let layer = scene.layer.expect("called for a scene with a layer");
    if !scene.contact.is_hard() {
        return Err(Error::InvalidInput(format!(
            "MDR on a layer solves hard contact only, got contact '{}'",
            scene.contact.name()
        )));
    }
    let why = "by MDR on a layer (its inverse transforms are the half-space's): solve by BEM (method \"bem\")";
    refuse(
        scene,
        &[
            Output::Pressure,
            Output::SurfaceVelocity,
            Output::Deflection,
            Output::Gap,
            Output::StiffnessLength,
        ],
        why,
    )?;
    let (g1, dx) = scene
        .indenter
        .mdr_profile(settings.n, mdr_half_length(scene)?)?;
    let indenter = &scene.indenter;
    let profile = |x: f64| indenter.profile_1d(x);
    let nu = scene.medium.nu();
    let g = layered_profile(&profile, g1.len(), dx, layer, nu)?;
    let weights = element_weights(g.len(), dx, layer, nu)?;
    let wanted = Wanted::of(scene);
    if scene.is_static() {
        refuse(scene, &[Output::Velocity], "for an elastic medium")?;
        let shear = match scene.medium.incompressible_equivalent()? {
            Medium::Elastic { g, .. } => g,
            _ => unreachable!("a static scene has an elastic medium"),
        };
        let loading = scene.held_loading()?;
        let request = Request {
            times: &[1.0],
            dt: 1.0,
            fields_at: &[],
            field_rates: false,
        };
        let mut s = run_mdr_layer(
            &g,
            dx,
            &weights,
            &Rheology::new(shear, vec![], 0.0)?,
            &loading,
            &request,
            monitor,
        )?;
        // one solve and no time step; the report is at t = 0
        s.steps = 0;
        s.t = vec![0.0];
        return Ok(report_from(settings, dx, "static", &mut s, wanted));
    }
    if matches!(scene.medium, Medium::Viscous { .. }) {
        return Err(Error::InvalidInput(
            "MDR on a layer takes elastic and viscoelastic media; a purely viscous one is solved by BEM (method \"bem\")".into(),
        ));
    }
    let loading = scene.loading()?;
    let times = scene.solved_times();
    let dt = step_length(scene, settings).expect("validated: a duration");
    let rheology = stepped_rheology(scene, dt)?;
    let request = Request {
        times: &times,
        dt,
        fields_at: &[],
        field_rates: false,
    };
    let mut s = run_mdr_layer(&g, dx, &weights, &rheology, &loading, &request, monitor)?;
    Ok(report_from(settings, dx, "viscoelastic", &mut s, wanted))
}

/// Relative distance inside a disc footprint's rim at which [`radius_at_depth`] ends its
/// search: a sphere's MDR profile is defined on the open disc and diverges (logarithmically)
/// at the rim.
const INSIDE_RIM: f64 = 1e-9;

/// The contact radius (m) of the scene's axisymmetric indenter on `layer` at depth `depth`
/// (m): the radius whose edge pressure is regular at that depth (`depth_at_radius`, exact
/// for an elastic layer, and for a viscoelastic one under a depth history, whose contact
/// is the elastic one's at each depth while it grows and recedes while the depth falls),
/// by bisection up to `CHI_MAX` thicknesses. A layer's contact is wider than the
/// half-space's at the same depth. Beyond `CHI_MAX` thicknesses, its thin-layer limit:
/// on a bonded base the squeeze film's (an incompressible layer,
/// (h^3 / 3 G) laplacian p = f(r) - d, whose pressure leaves the contact with zero slope
/// where the profile's mean over the contact disc, (2 / a^2) integral_0^a r f(r) dr, is the
/// depth: a = 2 sqrt(R d) for a paraboloid, sqrt 2 times the intersection with the undeformed
/// surface; a compressible bonded layer lies between it and the Winkler foundation's
/// intersection); on a frictionless base (a Winkler foundation at every nu) the radius
/// where the indenter's height is the depth, widened by the contact's excess over that
/// radius at `CHI_MAX` thicknesses. An indenter whose footprint is a disc narrower than
/// `CHI_MAX` thicknesses (a sphere's, at its radius) is searched within the disc, and a
/// depth beyond the disc's takes the whole disc. None for an indenter without an MDR
/// profile (a height map).
pub(super) fn radius_at_depth(scene: &Scene, layer: Layer, depth: f64) -> Result<Option<f64>> {
    let indenter = &scene.indenter;
    let nu = scene.medium.nu();
    let profile = |x: f64| indenter.profile_1d(x);
    let depth_at = |a: f64| depth_at_radius(&profile, a, layer, nu);
    let disc = match indenter.footprint() {
        Footprint::Disc { radius, .. } if radius < CHI_MAX * layer.thickness => Some(radius),
        _ => None,
    };
    // a disc is searched up to just inside its rim, where the MDR profile is defined
    let top = disc.map_or(CHI_MAX * layer.thickness, |r| r * (1.0 - INSIDE_RIM));
    let (Ok(deepest), true) = (depth_at(top), depth > 0.0) else {
        return Ok(None);
    };
    if deepest < depth && disc.is_some() {
        return Ok(disc);
    }
    if deepest >= depth {
        let disc = Reach::Disc {
            radius: top,
            fills: true,
        };
        return bisect_radius(disc, depth_at, depth, "depth").map(Some);
    }
    let beyond = Reach::Beyond {
        start: top,
        doublings: 60,
    };
    let height = |r: f64| indenter.height(r);
    let radius = match layer.base {
        Base::Bonded => {
            let points = gauss_legendre(32);
            let mean = |a: f64| {
                points.iter().try_fold(0.0, |sum, &(x, w)| {
                    let r = a * (x + 0.5);
                    Ok(sum + 2.0 * w * (r / a) * height(r)?)
                })
            };
            bisect_radius(beyond, mean, depth, "depth")
        }
        Base::Frictionless => bisect_radius(beyond, height, depth, "depth").and_then(|at| {
            let at_top = bisect_radius(beyond, height, deepest, "depth")?;
            Ok(at + (top - at_top).max(0.0))
        }),
    };
    Ok(radius.ok())
}
