//! MDR on a layer (`crate::mdr::layer`): the layered profile and element weights from the
//! scene, then the weighted hereditary foundation; hard contact, elastic and viscoelastic
//! media, no fields.

use super::assemble::{report_from, Wanted};
use super::report::Report;
use super::sizing::mdr_half_length;
use super::{refuse, step_length, stepped_rheology};
use crate::mdr::layer::{element_weights, layered_profile, run_mdr_layer};
use crate::model::loading::{ForceHistory, Loading};
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
        let force = scene.force.as_ref().expect("validated: force").last();
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
            &Loading::Force(ForceHistory::constant(force)?),
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
