//! Runs a scene: grid sizing, dispatch to the solvers (static elastic contact, the exact
//! viscous impulse engine, the paper's explicit loop, viscoelastic stepping) and the report.

pub mod assemble;
mod mdr_layer;
pub mod report;
pub mod sizing;

use crate::bem::contact::Target;
use crate::bem::static_contact;
use crate::bem::viscoelastic;
use crate::bem::viscous::{self, Fields, ViscousRequest};
use crate::mdr::foundation;
use crate::mdr::transforms;
use crate::model::grid::Grid;
use crate::model::loading::{ForceHistory, Loading};
use crate::model::settings::{check_steps, Integrator, Method, RunSettings, DEFAULT_STEPS};
use crate::model::{History, Indenter, Medium, Output, Scene};
use crate::stepping::Series;
use crate::support::error::{Error, Result};
use crate::support::monitor::Monitor;
use assemble::{
    bem_report, bem_static_report, central_value, centres, mdr_report, report_from, Wanted,
};
use report::{FieldSet, Report};
use sizing::{bem_grid, depth_bounds, mdr_foundation, mdr_half_length, DEPTH_BOUND_FACTOR};
use std::f64::consts::PI;
use std::time::Instant;

/// Runs a viscous BEM request on `grid` (a periodic cell: the implicit stepping only) with
/// the integrator and solver options of `settings` (eta in Pa s, the force history in N
/// over s).
pub fn viscous_bem(
    grid: &Grid,
    eta: f64,
    history: &ForceHistory,
    request: &ViscousRequest,
    settings: &RunSettings,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields>> {
    match &settings.integrator {
        Integrator::Implicit => {
            viscous::run_implicit(grid, eta, history, request, &settings.solver, monitor)
        }
        Integrator::Explicit(c) if grid.body.has_edge() => {
            viscous::run_explicit(grid, eta, history, request, c, &settings.solver, monitor)
        }
        Integrator::Explicit(_) => Err(Error::InvalidInput(
            "the explicit integrator runs on non-periodic grids; a periodic cell steps implicitly"
                .into(),
        )),
    }
}

/// Solves `scene` as `settings` say, reporting progress to `monitor`.
pub fn run(scene: &Scene, settings: &RunSettings, monitor: &mut dyn Monitor) -> Result<Report> {
    run_from(scene, settings, None, false, monitor).map(|(report, _)| report)
}

/// A load curve: the static scene `scene` (an elastic medium) solved under each of `forces`
/// (N) in turn, each BEM solve started from the pressure of the one before (rescaled to its
/// force), which saves iterations where neighbouring loads' contacts are alike (rough
/// surfaces above all). One report per force, each the same as `run` gives for the scene
/// under that force, to the solver's tolerance.
pub fn run_loads(
    scene: &Scene,
    forces: &[f64],
    settings: &RunSettings,
    monitor: &mut dyn Monitor,
) -> Result<Vec<Report>> {
    if !scene.is_static() {
        return Err(Error::InvalidInput(
            "a load curve solves static scenes: the medium must be elastic and the contact hard"
                .into(),
        ));
    }
    if forces.is_empty() {
        return Err(Error::InvalidInput(
            "a load curve needs at least one force".into(),
        ));
    }
    let mut reports = Vec::with_capacity(forces.len());
    let mut pressure: Option<Vec<f64>> = None;
    for &force in forces {
        let mut at = scene.clone();
        at.force = Some(History::Constant(force));
        at.depth = None;
        let (report, solved) = run_from(&at, settings, pressure.as_deref(), true, monitor)?;
        pressure = solved;
        reports.push(report);
    }
    Ok(reports)
}

/// [`run`], a static BEM solve started from the pressure `start` (Pa, on the scene's grid)
/// when given; also returns, with `keep`, that solve's pressure on the grid (None for other
/// runs, and without `keep`: a copy of the grid's size).
fn run_from(
    scene: &Scene,
    settings: &RunSettings,
    start_pressure: Option<&[f64]>,
    keep: bool,
    monitor: &mut dyn Monitor,
) -> Result<(Report, Option<Vec<f64>>)> {
    let start = Instant::now();
    scene.validate()?;
    settings.validate()?;
    if let (Some(duration), Some(dt)) = (scene.duration, settings.dt) {
        check_steps(dt, duration, duration / dt)?;
    }
    if let Indenter::HeightMap(map) = &scene.indenter {
        map.check_run(settings.method, settings.n)?;
    } else {
        let only_maps: Vec<Output> = scene
            .outputs()
            .into_iter()
            .filter(|o| o.is_height_map())
            .collect();
        refuse(
            scene,
            &only_maps,
            "for an axisymmetric indenter, only for a height map",
        )?;
    }
    crate::support::memory::check(
        &format!(
            "{} n = {}",
            settings.method.name().to_uppercase(),
            settings.n
        ),
        memory_needed(scene, settings),
    )?;
    let viscous_force = runs_viscous(scene);
    if matches!(settings.integrator, Integrator::Explicit(_))
        && !viscous_force
        && !scene.indenter.is_flat()
    {
        return Err(Error::InvalidInput(
            "the explicit integrator needs a viscous medium under a force".into(),
        ));
    }
    let (mut report, pressure) = if scene.layer.is_some() && settings.method == Method::Mdr {
        (mdr_layer::run(scene, settings, monitor)?, None)
    } else if scene.is_static() {
        run_static(scene, settings, start_pressure, keep, monitor)?
    } else if viscous_force {
        (run_viscous(scene, settings, monitor)?, None)
    } else {
        (run_viscoelastic(scene, settings, monitor)?, None)
    };
    beyond_the_equator(scene, &report)?;
    within_the_grid(scene, &report)?;
    if !scene.body().has_edge() {
        report.at_edge = None;
    }
    let from = scene.solved_from();
    if from.len() != report.t.len() {
        report.expand(scene.output_times(), &from);
    }
    report.check_resolution();
    if let Integrator::Explicit(c) = &settings.integrator {
        report.warnings.extend(c.warning());
    }
    report.wall_time = start.elapsed().as_secs_f64();
    Ok((report, pressure))
}

/// Whether a time-stepped scene runs on the viscous engine (`bem::viscous`,
/// `mdr::foundation`'s viscous runs): a viscous medium under a force, without adhesion; every
/// other stepped scene runs on the viscoelastic one.
fn runs_viscous(scene: &Scene) -> bool {
    matches!(scene.medium, Medium::Viscous { .. })
        && scene.force.is_some()
        && !scene.contact.is_adhesive()
}

/// Bytes per MDR element of a run, before the internal variables and the fields.
const MDR_BYTES_PER_ELEMENT: f64 = 64.0;

/// Bytes per element of a BEM grid: heights and mask.
const GRID_BYTES_PER_ELEMENT: f64 = 9.0;

/// The memory (bytes) a run of `scene` as `settings` say reaches at its peak, checked before
/// it allocates. BEM: the grid and the larger of what its solver holds while it runs (a
/// static solve's `static_contact::solve_bytes` with a whole-grid deflection where one is
/// asked for, a viscous run's `viscous::run_bytes`, a viscoelastic one's
/// `viscoelastic::run_bytes`; each with the fields it keeps) and the fields it hands on (its
/// own, those of the report and their copies for the caller, 8 bytes per element each).
/// MDR: per element its buffers, 8 bytes per internal variable of the medium and per field
/// array. Both add 16 bytes per viscoelastic time step.
pub fn memory_needed(scene: &Scene, settings: &RunSettings) -> f64 {
    let internal = step_length(scene, settings)
        .map_or_else(|| scene.medium.rheology(), |dt| stepped_rheology(scene, dt))
        .map_or(0, |r| r.internal());
    let wanted = [
        Output::Pressure,
        Output::SurfaceVelocity,
        Output::Deflection,
        Output::Gap,
    ]
    .iter()
    .filter(|&&o| scene.wants(o))
    .count() as f64;
    let field_times = scene.field_times().len();
    let steps = match (scene.duration, settings.dt.or(scene.dt)) {
        (Some(duration), Some(dt)) => duration / dt,
        (Some(_), None) => DEFAULT_STEPS,
        _ => 0.0,
    };
    let per_step = 16.0 * steps;
    let n = settings.n;
    if settings.method == Method::Mdr {
        let fields = wanted * field_times as f64;
        return n as f64 * (MDR_BYTES_PER_ELEMENT + 8.0 * (internal as f64 + fields)) + per_step;
    }
    let (nx, ny) = scene.indenter.bem_shape(n);
    let elements = nx as f64 * ny as f64;
    let body = scene.body();
    // the fields asked for, in the report and again in the caller's arrays
    let handed_on = 2.0 * 8.0 * wanted * field_times as f64 * elements;
    let (running, kept) = if scene.is_static() {
        let deflection = scene.wants(Output::Deflection) || Wanted::of(scene).height_map;
        let extra = if deflection { 8.0 * elements } else { 0.0 };
        // the pressure kept for a load curve's warm start
        (
            static_contact::solve_bytes(body, nx, ny, settings.solver.precondition) + extra,
            8.0 * elements,
        )
    } else {
        // a stepping run's own fields: pressure, velocity and deflection
        let kept = 24.0 * field_times as f64 * elements;
        let running = if runs_viscous(scene) {
            let implicit = matches!(settings.integrator, Integrator::Implicit);
            let pooled = implicit && !scene.indenter.is_flat();
            viscous::run_bytes(body, nx, ny, field_times, pooled)
        } else {
            viscoelastic::run_bytes(
                body,
                nx,
                ny,
                internal,
                field_times,
                scene.wants(Output::SurfaceVelocity),
                scene.contact.is_cohesive(),
            )
        };
        (running, kept)
    };
    GRID_BYTES_PER_ELEMENT * elements + running.max(kept + handed_on) + per_step
}

/// The longest viscoelastic time step (s) of a run: the settings', the scene's, or the
/// duration over `DEFAULT_STEPS`; None without a duration.
fn step_length(scene: &Scene, settings: &RunSettings) -> Option<f64> {
    let duration = scene.duration?;
    Some(settings.dt.or(scene.dt).unwrap_or(duration / DEFAULT_STEPS))
}

/// The medium's series over the run's time range: from its shortest step (half the longest
/// step `dt`, or a shorter gap between output times) to the last output time.
fn stepped_rheology(scene: &Scene, dt: f64) -> Result<crate::model::medium::rheology::Rheology> {
    let times = scene.solved_times();
    let (mut t_lo, mut prev) = (0.5 * dt, 0.0);
    for &t in &times {
        if t > prev {
            t_lo = t_lo.min(t - prev);
        }
        prev = t;
    }
    scene.medium.rheology_over(t_lo, prev.max(t_lo))
}

/// Fails when the contact of a sphere covers its whole footprint (its equator): beyond
/// that the indenter the solvers see is a sphere on a cylinder, not a sphere.
fn beyond_the_equator(scene: &Scene, report: &Report) -> Result<()> {
    let Indenter::Sphere { radius } = scene.indenter else {
        return Ok(());
    };
    match report.saturated.iter().flatten().position(|&s| s) {
        Some(k) => Err(Error::Domain(format!(
            "the contact of the sphere (radius {radius} m) reached its equator at t = {} s (depth {:.4e} m); past it the solvers' indenter is no longer a sphere: lower the load or enlarge the radius",
            report.t[k], report.depth[k]
        ))),
        None => Ok(()),
    }
}

/// Fails when the BEM contact reached the edge of a grid that is a window onto the
/// indenter (`at_edge` at an output time): an unbounded indenter's grid, or a sphere's
/// narrower than its footprint, both sized by MDR's contact radius (`sizing`). The contact
/// beyond the window was cut off, so the result would be wrong. A grid over the whole
/// footprint (a height map's, a punch's) holds every contact the indenter makes.
fn within_the_grid(scene: &Scene, report: &Report) -> Result<()> {
    if report.method != Method::Bem || !scene.body().has_edge() {
        return Ok(());
    }
    let Some(k) = report.at_edge.iter().flatten().position(|&e| e) else {
        return Ok(());
    };
    let half_width = sizing::bem_half_width(scene)?;
    let footprint = scene.indenter.half_width();
    if footprint.is_some_and(|w| half_width >= w * (1.0 - 1e-12)) {
        return Ok(());
    }
    Err(Error::Domain(format!(
        "BEM: the contact reached the edge of the grid at t = {} s; the grid (half-width {half_width:.4e} m) is a window onto the indenter, sized by MDR's largest contact radius, and this contact grew beyond it, so the result would be cut off at the window's edge",
        report.t[k]
    )))
}

/// Refuses outputs the scene's medium does not have.
fn refuse(scene: &Scene, outputs: &[Output], why: &str) -> Result<()> {
    match outputs.iter().find(|o| scene.wants(**o)) {
        Some(o) => Err(Error::InvalidInput(format!(
            "output {:?} is not available {why}",
            serde_json::to_value(o).expect("outputs serialise")
        ))),
        None => Ok(()),
    }
}

/// A static solve (elastic medium) under the scene's final force or depth, by BEM started
/// from the pressure `start` (Pa, on the grid) when given; the report, and by BEM with
/// `keep` the solution's pressure on the grid.
fn run_static(
    scene: &Scene,
    settings: &RunSettings,
    start: Option<&[f64]>,
    keep: bool,
    monitor: &mut dyn Monitor,
) -> Result<(Report, Option<Vec<f64>>)> {
    refuse(
        scene,
        &[
            Output::Velocity,
            Output::StiffnessLength,
            Output::SurfaceVelocity,
        ],
        "for an elastic medium",
    )?;
    // the solvers' G: that of the incompressible medium with the same contact modulus
    let shear = match scene.medium.incompressible_equivalent()? {
        Medium::Elastic { g, .. } => g,
        _ => unreachable!("run_static is called for elastic media"),
    };
    let target = match scene.held_loading()? {
        Loading::Force(f) => Target::Force(f.force(0.0)),
        Loading::Depth(d) => Target::Depth(d.depth(0.0)),
    };
    let n = settings.n;
    let wanted = Wanted::of(scene);
    match settings.method {
        Method::Bem => {
            let grid = bem_grid(scene, n)?;
            let bound = match target {
                Target::Force(force) => scene
                    .indenter
                    .depth_at_load(force / (4.0 * shear))
                    .ok()
                    .flatten()
                    .map(|d| DEPTH_BOUND_FACTOR * d),
                Target::Depth(d) => Some(d),
            };
            let deflection = wanted.deflection || wanted.height_map;
            let req = static_contact::StaticRequest {
                target,
                depth_bound: bound.filter(|_| grid.body.windows()),
                deflection,
                start,
            };
            let r = static_contact::solve(&grid, 1.0 / shear, req, &settings.solver, monitor)?;
            let pressure = keep.then(|| r.pressure.clone());
            let force = match target {
                Target::Force(force) => force,
                Target::Depth(_) => r.summary.force,
            };
            Ok((
                bem_static_report(settings, &grid, force, r, wanted),
                pressure,
            ))
        }
        Method::Mdr => {
            let f = mdr_foundation(scene, n)?;
            let fields_at: Vec<usize> = if scene.wants_fields() {
                vec![0]
            } else {
                vec![]
            };
            // under depth control, the force of the springs (4 G dx each) compressed at it
            let force = match target {
                Target::Force(force) => force,
                Target::Depth(d) => 4.0 * shear * f.dx() * f.compression_at(d).0,
            };
            let mut s = foundation::run(
                &f,
                foundation::Elements::Elastic { g: shear },
                &ForceHistory::constant(force)?,
                &[1.0],
                &fields_at,
                monitor,
            )?;
            // one solve and no time step; the report is at t = 0, at the depth held (the
            // root of its force is that depth to round-off where the indenter touches)
            s.steps = 0;
            s.t = vec![0.0];
            if let Target::Depth(d) = target {
                s.depth = vec![d];
            }
            let at: Vec<(f64, usize)> = fields_at.iter().map(|&k| (0.0, k)).collect();
            Ok((
                mdr_report(scene, settings, f.dx(), "static", s, wanted, &at)?,
                None,
            ))
        }
    }
}

fn run_viscous(scene: &Scene, settings: &RunSettings, monitor: &mut dyn Monitor) -> Result<Report> {
    // the solvers' eta: that of the incompressible medium with the same contact modulus
    let eta = match scene.medium.incompressible_equivalent()? {
        Medium::Viscous { eta, .. } => eta,
        _ => unreachable!("run_viscous is called for viscous media"),
    };
    let history = scene
        .force
        .as_ref()
        .expect("validated: force")
        .force(scene.contact)?;
    if scene.indenter.is_flat() {
        return match settings.method {
            Method::Bem => bem_punch(scene, settings, eta, &history, monitor),
            Method::Mdr => mdr_punch(scene, settings, eta, &history, monitor),
        };
    }
    let times = scene.solved_times();
    let steps = scene.field_steps();
    let at = scene.field_points();
    let wanted = Wanted::of(scene);
    let integrator = settings.integrator.name();
    match settings.method {
        Method::Bem => {
            let grid = bem_grid(scene, settings.n)?;
            let request = ViscousRequest {
                times,
                rates: wanted.velocity || wanted.stiffness_length,
                fields_at: steps.clone(),
                depth_bounds: depth_bounds(scene)?,
            };
            let s = viscous_bem(&grid, eta, &history, &request, settings, monitor)?;
            Ok(bem_report(settings, &grid, integrator, s, wanted, &at))
        }
        Method::Mdr => {
            let f = mdr_foundation(scene, settings.n)?;
            let s = match &settings.integrator {
                Integrator::Implicit => foundation::run(
                    &f,
                    foundation::Elements::Viscous { eta },
                    &history,
                    &times,
                    &steps,
                    monitor,
                )?,
                Integrator::Explicit(c) => {
                    foundation::run_explicit(&f, eta, &history, &times, c, monitor)?
                }
            };
            let no_fields = scene.wants_fields() && s.fields.is_empty();
            let mut out = mdr_report(scene, settings, f.dx(), integrator, s, wanted, &at)?;
            if no_fields {
                out.warnings
                    .push("the explicit MDR integrator computes no fields".into());
            }
            Ok(out)
        }
    }
}

/// What a flat punch reports whatever the scene asks: its rate and stiffness length are
/// exact and come with its one solve.
fn punch_wanted(scene: &Scene) -> Wanted {
    Wanted {
        velocity: true,
        stiffness_length: true,
        ..Wanted::of(scene)
    }
}

/// A flat punch by BEM: its contact never changes, so one solve at unit force gives every
/// output time (rates and pressures scale with F(t), depths and deflections with the
/// impulse).
fn bem_punch(
    scene: &Scene,
    settings: &RunSettings,
    eta: f64,
    history: &ForceHistory,
    monitor: &mut dyn Monitor,
) -> Result<Report> {
    let grid = bem_grid(scene, settings.n)?;
    let extended = scene.wants(Output::SurfaceVelocity) || scene.wants(Output::Deflection);
    let margin = extended.then_some(grid.nx / 2);
    let r = viscous::run_punch(&grid, eta, 1.0, margin, &settings.solver, monitor)?;
    let times = scene.solved_times();
    let area = grid.allowed.iter().filter(|&&a| a).count() as f64 * grid.dx * grid.dx;
    let p0 = central_value(&r.pressure, grid.nx, grid.ny);
    let count = times.len();
    let mut s: Series<Fields> = Series {
        depth: times
            .iter()
            .map(|&t| r.velocity * history.impulse(t))
            .collect(),
        force: times.iter().map(|&t| history.force(t)).collect(),
        contact_length: vec![2.0 * (area / PI).sqrt(); count],
        area: vec![area; count],
        velocity: times
            .iter()
            .map(|&t| r.velocity * history.force(t))
            .collect(),
        stiffness_length: vec![r.damping / (4.0 * eta); count],
        saturated: vec![true; count],
        at_edge: vec![false; count],
        iterations: vec![r.iterations],
        residual: vec![r.residual],
        solves: 1,
        t: times,
        ..Series::default()
    };
    let mut out = report_from(settings, grid.dx, "one solve", &mut s, punch_wanted(scene));
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.central_pressure = Some(out.force.iter().map(|&f| p0 * f).collect());
    for &t in &scene.field_times() {
        let scaled = |v: &[f64], by: f64| v.iter().map(|x| x * by).collect::<Vec<f64>>();
        let sv = r.surface_velocity.as_deref();
        out.fields.push(FieldSet {
            t,
            x: Some(centres(grid.nx, grid.dx)),
            y: Some(centres(grid.ny, grid.dx)),
            pressure: scene
                .wants(Output::Pressure)
                .then(|| scaled(&r.pressure, history.force(t))),
            surface_velocity: sv
                .filter(|_| scene.wants(Output::SurfaceVelocity))
                .map(|v| scaled(v, history.force(t))),
            deflection: sv
                .filter(|_| scene.wants(Output::Deflection))
                .map(|v| scaled(v, history.impulse(t))),
            x_extended: margin.map(|m| centres(grid.nx + 2 * m, grid.dx)),
            ..FieldSet::default()
        });
    }
    Ok(out)
}

/// A flat punch by MDR: exact for any n; its central pressure by the inverse transform of
/// the line load at unit force, scaled with F(t).
fn mdr_punch(
    scene: &Scene,
    settings: &RunSettings,
    eta: f64,
    history: &ForceHistory,
    monitor: &mut dyn Monitor,
) -> Result<Report> {
    let f = mdr_foundation(scene, settings.n)?;
    let times = scene.solved_times();
    let steps = scene.field_steps();
    let medium = foundation::Elements::Viscous { eta };
    let mut s = foundation::run(&f, medium, history, &times, &steps, monitor)?;
    let unit = foundation::run(
        &f,
        medium,
        &ForceHistory::constant(1.0)?,
        &[1.0],
        &[0],
        monitor,
    )?;
    let p0 = transforms::pressure_from_line_load(&unit.fields[0].line_load, f.dx(), &[0.0])?[0];
    // the contact never changes: one solve serves every output time
    s.solves = 1;
    let at = scene.field_points();
    let mut out = mdr_report(
        scene,
        settings,
        f.dx(),
        "one solve",
        s,
        punch_wanted(scene),
        &at,
    )?;
    out.central_pressure = Some(out.force.iter().map(|&force| p0 * force).collect());
    Ok(out)
}

/// A viscoelastic scene by exact exponential steps, with the penetration rate and fields
/// as asked for; `stiffness_length` (F / (4 eta dd/dt)) has no meaning without a single
/// viscosity and is refused.
fn run_viscoelastic(
    scene: &Scene,
    settings: &RunSettings,
    monitor: &mut dyn Monitor,
) -> Result<Report> {
    refuse(
        scene,
        &[Output::StiffnessLength],
        "for a viscoelastic medium: F / (4 eta dd/dt) needs a purely viscous one",
    )?;
    let loading: Loading = scene.loading()?;
    let times = scene.solved_times();
    let steps = scene.field_steps();
    let at = scene.field_points();
    let dt = step_length(scene, settings).expect("validated: a duration");
    let rheology = stepped_rheology(scene, dt)?;
    let request = crate::stepping::Request {
        times: &times,
        dt,
        fields_at: &steps,
        field_rates: scene.wants(Output::SurfaceVelocity),
    };
    let wanted = Wanted::of(scene);
    match settings.method {
        Method::Mdr if scene.contact.is_cohesive() => Err(Error::InvalidInput(format!(
            "MDR solves hard, JKR and DMT contact; the cohesive law '{}' is solved by BEM (method \"bem\")",
            scene.contact.name()
        ))),
        Method::Mdr => {
            let (profile, dx) = scene
                .indenter
                .mdr_profile(settings.n, mdr_half_length(scene)?)?;
            let attraction = scene.contact.attraction(scene.indenter.tip_radius())?;
            let s = crate::mdr::viscoelastic::run_mdr_adhesive(
                &profile,
                dx,
                &rheology,
                scene.contact,
                attraction,
                &loading,
                &request,
                monitor,
            )?;
            mdr_report(scene, settings, dx, "viscoelastic", s, wanted, &at)
        }
        Method::Bem => {
            let grid = bem_grid(scene, settings.n)?;
            let s = viscoelastic::run_bem_with(
                &grid,
                &rheology,
                scene.contact,
                &loading,
                &request,
                &settings.solver,
                monitor,
            )?;
            Ok(bem_report(settings, &grid, "viscoelastic", s, wanted, &at))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::contact_law::ContactLaw;
    use crate::model::indenter::heightmap::HeightMap;
    use crate::model::medium::INCOMPRESSIBLE;
    use crate::model::{History, Indenter, Medium};
    use crate::support::monitor::Silent;

    fn scene(indenter: Indenter, medium: Medium, force: History) -> Scene {
        Scene {
            indenter,
            layer: None,
            contact: ContactLaw::Hard,
            medium,
            force: Some(force),
            depth: None,
            duration: Some(2.0),
            times: Some(vec![0.5, 1.0, 2.0]),
            outputs: None,
            field_times: None,
            dt: None,
        }
    }

    fn solve(s: &Scene, method: Method, n: usize) -> Report {
        run(s, &RunSettings::new(method, n), &mut Silent).unwrap()
    }

    /// An unbounded paraboloid on a Maxwell body under a force: the grid is sized by the
    /// compliance at the end, J = 1/G + t/eta, and holds the contact at every output;
    /// MDR's depth is the elastic one at that compliance, 4/3 sqrt(R) d^1.5 / J = F.
    #[test]
    fn maxwell_under_a_force_on_an_unbounded_indenter() {
        let s = scene(
            Indenter::Paraboloid { c: 0.5, edge: None },
            Medium::Maxwell {
                g: 1.0,
                eta: 2.0,
                nu: INCOMPRESSIBLE,
            },
            History::Constant(0.3),
        );
        let mdr = solve(&s, Method::Mdr, 4001);
        let half = mdr.dx * 4001.0 / 2.0;
        for k in 0..3 {
            let t = mdr.t[k];
            let j = 1.0 / 1.0 + t / 2.0;
            let exact = (3.0 * 0.3 * j / (16.0 * 1.0f64.sqrt())).powf(2.0 / 3.0);
            assert!(
                (mdr.depth[k] / exact - 1.0).abs() < 2e-3,
                "{k}: {} {exact}",
                mdr.depth[k]
            );
            assert!(0.5 * mdr.contact_length[k] < half / 1.1);
        }
        let bem = solve(&s, Method::Bem, 33);
        assert!(
            bem.residual > 0.0 && bem.residual <= 1e-10,
            "{}",
            bem.residual
        );
        assert!(bem.at_edge.as_ref().unwrap().iter().all(|&e| !e));
        for k in 0..3 {
            assert!(
                (bem.depth[k] / mdr.depth[k] - 1.0).abs() < 2e-2,
                "{k}: {}",
                bem.depth[k]
            );
        }
    }

    /// A flat punch under a force history needs one solve: its rate follows F(t), its depth
    /// the impulse, its central pressure F(t) / (2 pi a^2) (MDR: exactly).
    #[test]
    fn punch_under_a_force_history() {
        let history = History::Samples(vec![[0.0, 0.0], [1.0, 2.0], [2.0, 1.0]]);
        let s = scene(
            Indenter::Rod { radius: 1.0 },
            Medium::Viscous {
                eta: 1.0,
                nu: INCOMPRESSIBLE,
            },
            history,
        );
        let forces = [1.0, 2.0, 1.0];
        let impulses = [0.25, 1.0, 2.5];
        for method in [Method::Bem, Method::Mdr] {
            let r = solve(&s, method, 40);
            assert_eq!(r.solves, 1);
            let v = r.velocity.as_ref().unwrap();
            let p0 = r.central_pressure.as_ref().unwrap();
            for k in 0..3 {
                assert!((r.force[k] - forces[k]).abs() < 1e-15);
                assert!((v[k] / forces[k] - v[1] / 2.0).abs() < 1e-12 * v[1]);
                assert!((r.depth[k] - v[1] / 2.0 * impulses[k]).abs() < 1e-12 * r.depth[2]);
                let exact = forces[k] / (2.0 * PI);
                let tol = if method == Method::Mdr { 1e-9 } else { 0.05 };
                assert!(
                    (p0[k] / exact - 1.0).abs() < tol,
                    "{method:?} {k}: {}",
                    p0[k]
                );
            }
        }
    }

    /// An elastic sphere by MDR: Hertz's depth a^2 / R and force 16/3 G sqrt(R) d^1.5 for a
    /// contact small against R.
    #[test]
    fn elastic_sphere_follows_hertz() {
        let mut s = scene(
            Indenter::Sphere { radius: 10.0 },
            Medium::Elastic {
                g: 2.0,
                nu: INCOMPRESSIBLE,
            },
            History::Constant(0.05),
        );
        s.duration = None;
        s.times = None;
        let r = solve(&s, Method::Mdr, 200001);
        let d = (3.0 * 0.05 / (16.0 * 2.0 * 10f64.sqrt())).powf(2.0 / 3.0);
        assert!((r.depth[0] / d - 1.0).abs() < 1e-3, "{} {d}", r.depth[0]);
        assert_eq!(r.integrator, "static");
    }

    /// An elastic scene held at a depth: a paraboloid carries Hertz's force 16/3 G sqrt(R)
    /// d^1.5 by MDR (to 1e-6) and BEM (to 1e-3 on 97^2), and held at that force comes back to
    /// the depth (MDR to round-off, BEM to 1e-6); a sphere on a bonded layer, whose contact
    /// is wider than the half-space's at the same depth, keeps it inside the BEM grid and
    /// carries MDR's force (to 1e-3).
    #[test]
    fn elastic_scene_held_at_a_depth() {
        let (g, r, d) = (2.0, 10.0, 0.05);
        let mut s = scene(
            Indenter::Paraboloid {
                c: 0.5 / r,
                edge: None,
            },
            Medium::Elastic {
                g,
                nu: INCOMPRESSIBLE,
            },
            History::Constant(1.0),
        );
        (s.duration, s.times, s.force) = (None, None, None);
        s.depth = Some(History::Constant(d));
        s.validate().unwrap();
        let hertz = 16.0 / 3.0 * g * r.sqrt() * d.powf(1.5);
        for (method, n, tol, back) in [
            (Method::Mdr, 20001, 1e-6, 1e-12),
            (Method::Bem, 97, 1e-3, 1e-6),
        ] {
            let held = solve(&s, method, n);
            assert_eq!(held.integrator, "static");
            assert_eq!(held.depth, vec![d]);
            let f = held.force[0];
            assert!((f / hertz - 1.0).abs() < tol, "{method:?}: {f} {hertz}");
            let mut loaded = s.clone();
            (loaded.depth, loaded.force) = (None, Some(History::Constant(f)));
            let back_depth = solve(&loaded, method, n).depth[0];
            assert!(
                (back_depth / d - 1.0).abs() < back,
                "{method:?}: {back_depth} {d}"
            );
        }
        s.indenter = Indenter::Sphere { radius: 5.0 };
        s.layer = Some(crate::model::body::Layer {
            thickness: 2.0,
            base: crate::model::body::Base::Bonded,
        });
        s.depth = Some(History::Constant(1.0));
        let bem = solve(&s, Method::Bem, 97);
        let mdr = solve(&s, Method::Mdr, 2001);
        assert_eq!(bem.at_edge, Some(vec![false]));
        assert!(
            (bem.force[0] / mdr.force[0] - 1.0).abs() < 1e-3,
            "{} {}",
            bem.force[0],
            mdr.force[0]
        );
    }

    /// A load curve gives, at each force, the static solve of the scene under that force:
    /// the same depth to the solver's tolerance (BEM, warm-started after the first load) or
    /// bit for bit (MDR); the warm starts take fewer iterations than cold solves; a
    /// time-dependent medium and an empty curve are refused.
    #[test]
    fn load_curve_matches_static_solves() {
        let mut s = scene(
            Indenter::Paraboloid {
                c: 0.5,
                edge: Some(2.56),
            },
            Medium::Elastic {
                g: 1.0,
                nu: INCOMPRESSIBLE,
            },
            History::Constant(0.1),
        );
        s.duration = None;
        s.times = None;
        let forces = [0.1, 0.15, 0.2, 0.3];
        for (method, n) in [(Method::Bem, 65), (Method::Mdr, 4001)] {
            let settings = RunSettings::new(method, n);
            let curve = run_loads(&s, &forces, &settings, &mut Silent).unwrap();
            let (mut warm, mut cold) = (0, 0);
            for (k, (&force, r)) in forces.iter().zip(&curve).enumerate() {
                let mut at = s.clone();
                at.force = Some(History::Constant(force));
                let one = solve(&at, method, n);
                assert_eq!(r.force, one.force);
                if method == Method::Mdr {
                    assert_eq!(r.depth, one.depth);
                } else {
                    assert!((r.depth[0] / one.depth[0] - 1.0).abs() < 1e-8);
                }
                if k > 0 {
                    warm += r.iterations;
                    cold += one.iterations;
                }
            }
            if method == Method::Bem {
                assert!(warm < cold, "{warm} warm iterations, {cold} cold");
            }
        }
        assert!(run_loads(&s, &[], &RunSettings::new(Method::Bem, 65), &mut Silent).is_err());
        let viscous = scene(
            Indenter::Paraboloid { c: 0.5, edge: None },
            Medium::Viscous {
                eta: 1.0,
                nu: INCOMPRESSIBLE,
            },
            History::Constant(0.1),
        );
        assert!(run_loads(
            &viscous,
            &[0.1],
            &RunSettings::new(Method::Mdr, 401),
            &mut Silent
        )
        .is_err());
    }

    /// An adhesive scene file (DMT, pi w R = 1 N) runs on an elastic medium along its
    /// force history: it lets go at -2 pi w R and reports the pull-off; BEM refuses it.
    #[test]
    fn adhesive_scene_file_runs() {
        let text = r#"
method = "mdr"
n = 501
duration = 2.0
dt = 0.001
force = [[0.0, 0.0], [1.0, 5.0], [2.0, -3.0]]
contact = { type = "dmt", work_of_adhesion = 0.3183098861837907 }
[indenter]
type = "paraboloid"
c = 0.5
[medium]
type = "elastic"
G = 0.25
"#;
        let file = crate::model::file::SceneFile::parse(text, "dmt.toml").unwrap();
        let r = run(&file.scene, &file.settings, &mut Silent).unwrap();
        // steps of 1 ms, 8 mN each: the last state in contact lies within one of -2 pi w R
        let f = r.pull_off_force.unwrap();
        assert!((-2.0..-2.0 + 0.008 * (1.0 + 1e-9)).contains(&f), "{f}");
        assert_eq!(r.jump_out.as_ref().unwrap().len(), 1);
        assert!(r.table("dmt").contains("pull-off force"));
        let bem = RunSettings::new(Method::Bem, 17);
        assert!(run(&file.scene, &bem, &mut Silent).is_err());
        let bad = text.replace("type = \"dmt\", ", "type = \"dmt\", w = 1, ");
        assert!(crate::model::file::SceneFile::parse(&bad, "bad.toml").is_err());
    }

    /// A contact at the edge of a window onto the indenter is an error; at the edge of a grid
    /// over the whole footprint it is not (a height map's contact may touch its border).
    #[test]
    fn contact_at_the_edge_of_a_window_is_an_error() {
        let elastic = Medium::Elastic {
            g: 1.0,
            nu: INCOMPRESSIBLE,
        };
        let mut sphere = scene(
            Indenter::Sphere { radius: 1.0 },
            elastic.clone(),
            History::Constant(1e-3),
        );
        (sphere.duration, sphere.times) = (None, None);
        let mut report = solve(&sphere, Method::Bem, 33);
        assert_eq!(report.at_edge, Some(vec![false]));
        assert!(sizing::bem_half_width(&sphere).unwrap() < 0.5);
        within_the_grid(&sphere, &report).unwrap();
        report.at_edge = Some(vec![true]);
        let err = within_the_grid(&sphere, &report).unwrap_err().to_string();
        assert!(err.contains("window onto the indenter"), "{err}");

        let heights: Vec<f64> = (0..16 * 16)
            .map(|i| ((i % 16) as f64 - 7.5).powi(2) + ((i / 16) as f64 - 7.5).powi(2))
            .collect();
        let map = HeightMap::new(16, 16, heights, 0.1, false).unwrap();
        let mut mapped = scene(
            Indenter::HeightMap(Box::new(map)),
            elastic,
            History::Constant(1e-3),
        );
        (mapped.duration, mapped.times) = (None, None);
        within_the_grid(&mapped, &report).unwrap();
    }
}
