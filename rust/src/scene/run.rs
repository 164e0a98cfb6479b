//! Runs a scene: grid sizing, dispatch to the solvers (static elastic contact, the exact
//! viscous impulse engine, the paper's explicit loop, viscoelastic stepping) and the report.

use super::report::{FieldSet, Report};
use super::{Output, Scene, MAX_STEPS};
use crate::contact::{SolverOptions, Target};
use crate::error::{check_positive, Error, Result};
use crate::grid::Grid;
use crate::integrator::ExplicitControl;
use crate::loading::{ForceHistory, Loading};
use crate::mdr::{self, Foundation};
use crate::monitor::Monitor;
use crate::static_contact;
use crate::transforms;
use crate::viscoelastic;
use crate::viscous::{self, ViscousRequest, ViscousSeries};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::time::Instant;

/// The solution method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Boundary elements on an n x n grid over the footprint.
    Bem,
    /// Method of dimensionality reduction with n elements.
    Mdr,
}

impl Method {
    /// "bem" or "mdr".
    pub fn name(self) -> &'static str {
        match self {
            Method::Bem => "bem",
            Method::Mdr => "mdr",
        }
    }
}

/// Time integration of a viscous medium under a force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// One exact impulse step per output time (no time-discretisation error while the
    /// contact grows).
    Implicit,
    /// The paper's explicit loop (its Fig. 1b).
    Explicit(ExplicitControl),
}

/// Largest BEM grid side (elements).
pub const MAX_BEM_N: usize = 4096;
/// Largest MDR element count.
pub const MAX_MDR_N: usize = 1 << 26;
/// An unbounded indenter's grid reaches this factor times its largest contact radius.
pub const UNBOUNDED_MARGIN: f64 = 1.2;
/// Depth bounds that size the BEM windows: this factor times MDR's depth.
const DEPTH_BOUND_FACTOR: f64 = 1.05;
/// Radii of an MDR radial field: this many points from 0 to twice the contact radius.
const RADIAL_POINTS: usize = 401;
/// Viscoelastic steps per duration when neither the scene nor the settings give dt.
const DEFAULT_STEPS: f64 = 500.0;

/// How to solve a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// BEM or MDR.
    pub method: Method,
    /// BEM: elements across the footprint (n x n grid); MDR: elements of the 1D indenter.
    pub n: usize,
    /// Contact-solver tolerances and choices (BEM).
    pub solver: SolverOptions,
    /// Time integration of a viscous medium under a force.
    pub integrator: Integrator,
    /// Longest viscoelastic time step (s), overriding the scene's.
    pub dt: Option<f64>,
}

impl RunSettings {
    /// Default settings for `method` at resolution `n`.
    pub fn new(method: Method, n: usize) -> Self {
        RunSettings {
            method,
            n,
            solver: SolverOptions::default(),
            integrator: Integrator::Implicit,
            dt: None,
        }
    }

    /// Fails on resolutions out of range or bad tolerances.
    pub fn validate(&self) -> Result<()> {
        let limit = match self.method {
            Method::Bem => MAX_BEM_N,
            Method::Mdr => MAX_MDR_N,
        };
        if self.n == 0 || self.n > limit {
            return Err(Error::InvalidInput(format!(
                "{} resolution n must be in 1..={limit}, got {}",
                self.method.name().to_uppercase(),
                self.n
            )));
        }
        check_positive("tol", self.solver.tol)?;
        if self.solver.max_iter == 0 {
            return Err(Error::InvalidInput("max_iter must be >= 1".into()));
        }
        if let Integrator::Explicit(c) = &self.integrator {
            c.validate()?;
        }
        if let Some(dt) = self.dt {
            check_positive("dt", dt)?;
        }
        Ok(())
    }
}

/// Solves `scene` as `settings` say, reporting progress to `monitor`.
pub fn run(scene: &Scene, settings: &RunSettings, monitor: &mut dyn Monitor) -> Result<Report> {
    let start = Instant::now();
    scene.validate()?;
    settings.validate()?;
    let viscous_force =
        matches!(scene.medium, super::Medium::Viscous { .. }) && scene.force.is_some();
    if matches!(settings.integrator, Integrator::Explicit(_))
        && !viscous_force
        && !scene.indenter.is_flat()
    {
        return Err(Error::InvalidInput(
            "the explicit integrator needs a viscous medium under a force".into(),
        ));
    }
    let mut report = if scene.medium.is_elastic() {
        run_static(scene, settings, monitor)?
    } else if viscous_force {
        run_viscous(scene, settings, monitor)?
    } else {
        run_viscoelastic(scene, settings, monitor)?
    };
    report.check_resolution();
    report.wall_time = start.elapsed().as_secs_f64();
    Ok(report)
}

/// The largest contact radius (m) the scene reaches, by MDR (closed forms where they
/// exist): elastic at its force; viscous at its last impulse; viscoelastic at its largest
/// force with the modulus 1 / J(duration), or at its largest depth.
fn sizing_radius(scene: &Scene) -> Result<f64> {
    let ind = &scene.indenter;
    if let Some(d) = &scene.depth {
        return ind.radius_at_depth(d.max());
    }
    let force = scene.force.as_ref().expect("validated: force or depth");
    match scene.medium {
        super::Medium::Elastic { g } => ind.radius_at_load(force.last() / (4.0 * g)),
        super::Medium::Viscous { eta } => {
            let t_end = *scene
                .output_times()
                .last()
                .expect("validated: output times");
            ind.radius_at_load(force.force()?.impulse(t_end) / (4.0 * eta))
        }
        _ => {
            let duration = scene.duration.expect("validated: a duration");
            let compliance = scene.medium.creep_compliance(duration)?;
            ind.radius_at_load(force.max() * compliance / 4.0)
        }
    }
}

/// Half-width (m) of the square the BEM grid covers: the footprint, or for an unbounded
/// indenter `UNBOUNDED_MARGIN` times its largest contact radius.
pub fn bem_half_width(scene: &Scene) -> Result<f64> {
    match scene.indenter.half_width() {
        Some(h) => Ok(h),
        None => Ok(UNBOUNDED_MARGIN * sizing_radius(scene)?),
    }
}

/// Half-length (m) of the MDR foundation: the 1D indenter, or for an unbounded indenter
/// `UNBOUNDED_MARGIN` times its largest contact radius.
pub fn mdr_half_length(scene: &Scene) -> Result<f64> {
    match scene.indenter.half_length_1d() {
        Some(h) => Ok(h),
        None => Ok(UNBOUNDED_MARGIN * sizing_radius(scene)?),
    }
}

/// Upper bounds of the depth (m) at each output time of a viscous scene under a force,
/// which size the BEM steps' windows: `DEPTH_BOUND_FACTOR` times MDR's depth, NaN where the
/// contact would leave the footprint (the solver then extrapolates; it checks every bound
/// and widens a window that was too small).
pub fn depth_bounds(scene: &Scene) -> Result<Vec<f64>> {
    let eta = match scene.medium {
        super::Medium::Viscous { eta } => eta,
        _ => {
            return Err(Error::InvalidInput(
                "depth bounds need a viscous medium".into(),
            ))
        }
    };
    let history = match &scene.force {
        Some(f) => f.force()?,
        None => {
            return Err(Error::InvalidInput(
                "depth bounds need a force history".into(),
            ))
        }
    };
    Ok(scene
        .output_times()
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
    scene.indenter.bem_grid(n, bem_half_width(scene)?)
}

/// The MDR foundation of `scene` with n elements.
pub fn mdr_foundation(scene: &Scene, n: usize) -> Result<Foundation> {
    let (g, dx) = scene.indenter.mdr_profile(n, mdr_half_length(scene)?)?;
    Foundation::new(g, dx)
}

/// Element-centre coordinates (m) of `m` elements of size dx, symmetric about 0.
fn centres(m: usize, dx: f64) -> Vec<f64> {
    (0..m)
        .map(|i| (i as f64 - 0.5 * (m as f64 - 1.0)) * dx)
        .collect()
}

/// A report with the run's identity and output times `t`, the rest empty.
pub fn report(settings: &RunSettings, dx: f64, integrator: &str, t: Vec<f64>) -> Report {
    Report {
        method: settings.method,
        n: settings.n,
        dx,
        grid_shape: None,
        integrator: integrator.into(),
        depth: vec![],
        contact_length: vec![],
        area: None,
        force: vec![],
        velocity: None,
        stiffness_length: None,
        central_pressure: None,
        saturated: None,
        at_edge: None,
        fields: vec![],
        steps: 0,
        solves: 0,
        iterations: 0,
        solver: None,
        window: None,
        residual: 0.0,
        wall_time: 0.0,
        warnings: vec![],
        t,
    }
}

/// Which optional outputs a run builds.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Wanted {
    /// Penetration rate series.
    pub velocity: bool,
    /// F / (4 eta dd/dt) series.
    pub stiffness_length: bool,
    /// Pressure fields.
    pub pressure: bool,
    /// Surface-velocity fields.
    pub surface_velocity: bool,
    /// Deflection fields.
    pub deflection: bool,
}

impl Wanted {
    /// What `scene` asks for.
    pub fn of(scene: &Scene) -> Self {
        Wanted {
            velocity: scene.wants(Output::Velocity),
            stiffness_length: scene.wants(Output::StiffnessLength),
            pressure: scene.wants(Output::Pressure),
            surface_velocity: scene.wants(Output::SurfaceVelocity),
            deflection: scene.wants(Output::Deflection),
        }
    }

    /// Whether any field is asked for.
    pub fn fields(&self) -> bool {
        self.pressure || self.surface_velocity || self.deflection
    }
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

fn run_static(scene: &Scene, settings: &RunSettings, monitor: &mut dyn Monitor) -> Result<Report> {
    refuse(
        scene,
        &[
            Output::Velocity,
            Output::StiffnessLength,
            Output::SurfaceVelocity,
        ],
        "for an elastic medium",
    )?;
    let g = match scene.medium {
        super::Medium::Elastic { g } => g,
        _ => unreachable!("run_static is called for elastic media"),
    };
    let force = scene.force.as_ref().expect("validated: force").last();
    let n = settings.n;
    match settings.method {
        Method::Bem => {
            let grid = bem_grid(scene, n)?;
            let bound = scene
                .indenter
                .depth_at_load(force / (4.0 * g))
                .ok()
                .flatten()
                .map(|d| DEPTH_BOUND_FACTOR * d);
            let r = static_contact::solve(
                &grid,
                1.0 / g,
                Target::Force(force),
                bound,
                scene.wants(Output::Deflection),
                &settings.solver,
                monitor,
            )?;
            Ok(bem_static_report(
                settings,
                &grid,
                force,
                r,
                Wanted::of(scene),
            ))
        }
        Method::Mdr => {
            let f = mdr_foundation(scene, n)?;
            let fields_at: Vec<usize> = if scene.wants_fields() {
                vec![0]
            } else {
                vec![]
            };
            let s = mdr::run(
                &f,
                mdr::Medium::Elastic { g },
                &ForceHistory::constant(force)?,
                &[1.0],
                &fields_at,
                monitor,
            )?;
            let mut out = report(settings, f.dx(), "static", vec![0.0]);
            out.depth = s.depth.clone();
            out.contact_length = s.contact_length.clone();
            out.force = vec![force];
            out.saturated = Some(s.saturated.clone());
            out.solves = 1;
            out.fields = mdr_fields(scene, &f, &s, &[0.0], &fields_at)?;
            Ok(out)
        }
    }
}

/// The report of a static BEM contact on `grid` under `force` (N), with pressure and
/// deflection fields as `wanted` says (the deflection only where the solve computed it).
pub fn bem_static_report(
    settings: &RunSettings,
    grid: &Grid,
    force: f64,
    r: static_contact::StaticContact,
    wanted: Wanted,
) -> Report {
    let area = r.summary.contact_count as f64 * grid.dx * grid.dx;
    let contact: Vec<bool> = r.pressure.iter().map(|&p| p > 0.0).collect();
    let mut out = report(settings, grid.dx, "static", vec![0.0]);
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.depth = vec![r.summary.depth];
    out.contact_length = vec![2.0 * (area / PI).sqrt()];
    out.area = Some(vec![area]);
    out.force = vec![force];
    out.saturated = Some(vec![covers(grid, area)]);
    out.at_edge = Some(vec![grid.touches_border(&contact)]);
    out.solves = r.solves;
    out.iterations = r.summary.iterations;
    out.residual = r.summary.residual;
    out.solver = Some(static_solver_name(r.summary.dense).into());
    out.window = Some([r.window.y0, r.window.x0, r.window.wy, r.window.wx]);
    if wanted.fields() {
        out.fields.push(FieldSet {
            t: 0.0,
            x: Some(centres(grid.nx, grid.dx)),
            y: Some(centres(grid.ny, grid.dx)),
            pressure: wanted.pressure.then_some(r.pressure),
            deflection: r.deflection.filter(|_| wanted.deflection),
            ..FieldSet::default()
        });
    }
    out
}

/// The name of the static contact solver: the dense active set or Polonsky–Keer.
pub fn static_solver_name(dense: bool) -> &'static str {
    if dense {
        "active-set"
    } else {
        "polonsky-keer"
    }
}

/// Whether a contact of `area` (m^2) covers the whole footprint of `grid`.
fn covers(grid: &Grid, area: f64) -> bool {
    let footprint = grid.allowed.iter().filter(|&&a| a).count() as f64 * grid.dx * grid.dx;
    area >= footprint * (1.0 - 1e-12)
}

fn run_viscous(scene: &Scene, settings: &RunSettings, monitor: &mut dyn Monitor) -> Result<Report> {
    let eta = match scene.medium {
        super::Medium::Viscous { eta } => eta,
        _ => unreachable!("run_viscous is called for viscous media"),
    };
    let history = scene.force.as_ref().expect("validated: force").force()?;
    if scene.indenter.is_flat() {
        return match settings.method {
            Method::Bem => bem_punch(scene, settings, eta, &history, monitor),
            Method::Mdr => mdr_punch(scene, settings, eta, &history, monitor),
        };
    }
    let times = scene.output_times();
    let steps = scene.field_steps();
    let (label, forces) = (
        match settings.integrator {
            Integrator::Implicit => "implicit",
            Integrator::Explicit(_) => "explicit",
        },
        times
            .iter()
            .map(|&t| history.force(t))
            .collect::<Vec<f64>>(),
    );
    match settings.method {
        Method::Bem => {
            let grid = bem_grid(scene, settings.n)?;
            let depth_bounds = depth_bounds(scene)?;
            let request = ViscousRequest {
                times: times.clone(),
                rates: scene.wants(Output::Velocity) || scene.wants(Output::StiffnessLength),
                fields_at: steps.clone(),
                depth_bounds,
            };
            let s = match &settings.integrator {
                Integrator::Implicit => viscous::run_implicit(
                    &grid,
                    eta,
                    &history,
                    &request,
                    &settings.solver,
                    monitor,
                )?,
                Integrator::Explicit(c) => viscous::run_explicit(
                    &grid,
                    eta,
                    &history,
                    &request,
                    c,
                    &settings.solver,
                    monitor,
                )?,
            };
            if scene.indenter.half_width().is_none() {
                if let Some(k) = s.at_border.iter().position(|&b| b) {
                    return Err(Error::Domain(format!(
                        "BEM: the contact reached the edge of the grid of an unbounded indenter at t = {} s; the grid is too small",
                        s.t[k]
                    )));
                }
            }
            let fields: Vec<(f64, usize)> = scene.field_times().into_iter().zip(steps).collect();
            Ok(bem_viscous_report(
                settings,
                &grid,
                label,
                forces,
                s,
                Wanted::of(scene),
                &fields,
            ))
        }
        Method::Mdr => {
            let f = mdr_foundation(scene, settings.n)?;
            let (s, taken) = match &settings.integrator {
                Integrator::Implicit => (
                    mdr::run(
                        &f,
                        mdr::Medium::Viscous { eta },
                        &history,
                        &times,
                        &steps,
                        monitor,
                    )?,
                    times.len(),
                ),
                Integrator::Explicit(c) => {
                    mdr::run_explicit(&f, eta, &history, &times, c, monitor)?
                }
            };
            let mut out = report(settings, f.dx(), label, s.t.clone());
            out.depth = s.depth.clone();
            out.contact_length = s.contact_length.clone();
            out.force = forces;
            out.velocity = scene.wants(Output::Velocity).then(|| s.velocity.clone());
            // F / (4 eta dd/dt) is the contact's element count times dx, exactly
            out.stiffness_length = scene
                .wants(Output::StiffnessLength)
                .then(|| s.contact_length.clone());
            out.saturated = Some(s.saturated.clone());
            out.steps = taken;
            out.solves = times.len();
            if scene.wants_fields() && s.fields.is_empty() {
                out.warnings
                    .push("the explicit MDR integrator computes no fields".into());
            }
            let field_times = scene.field_times();
            out.fields = mdr_fields(scene, &f, &s, &field_times, &steps)?;
            Ok(out)
        }
    }
}

/// The report of a viscous BEM run on `grid`: series, and the fields at (time, output
/// index) `fields` as `wanted` says.
pub fn bem_viscous_report(
    settings: &RunSettings,
    grid: &Grid,
    label: &str,
    forces: Vec<f64>,
    s: ViscousSeries,
    wanted: Wanted,
    fields: &[(f64, usize)],
) -> Report {
    let mut out = report(settings, grid.dx, label, s.t);
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.depth = s.depth;
    out.contact_length = s.contact_length;
    out.saturated = Some(s.area.iter().map(|&a| covers(grid, a)).collect());
    out.area = Some(s.area);
    out.force = forces;
    out.velocity = wanted.velocity.then_some(s.velocity);
    out.stiffness_length = wanted.stiffness_length.then_some(s.stiffness_length);
    out.at_edge = Some(s.at_border);
    out.steps = s.steps;
    out.solves = s.solves;
    out.iterations = s.iterations.iter().sum();
    out.residual = s.residual.iter().fold(0.0, |a: f64, &b| a.max(b));
    for &(t, k) in fields {
        if let Some(f) = s.fields.iter().find(|f| f.step == k) {
            out.fields.push(FieldSet {
                t,
                x: Some(centres(grid.nx, grid.dx)),
                y: Some(centres(grid.ny, grid.dx)),
                pressure: wanted.pressure.then(|| f.pressure.clone()),
                surface_velocity: wanted.surface_velocity.then(|| f.velocity.clone()),
                deflection: wanted.deflection.then(|| f.deflection.clone()),
                ..FieldSet::default()
            });
        }
    }
    out
}

/// Value at the grid centre: the centre element (odd sizes) or the mean of the 2 or 4
/// elements around it (even sizes).
fn central_value(field: &[f64], nx: usize, ny: usize) -> f64 {
    let around = |n: usize| {
        if n % 2 == 1 {
            vec![n / 2]
        } else {
            vec![n / 2 - 1, n / 2]
        }
    };
    let (xs, ys) = (around(nx), around(ny));
    let vals: Vec<f64> = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| field[y * nx + x]))
        .collect();
    vals.iter().sum::<f64>() / vals.len() as f64
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
    let times = scene.output_times();
    let area = grid.allowed.iter().filter(|&&a| a).count() as f64 * grid.dx * grid.dx;
    let p0 = central_value(&r.pressure, grid.nx, grid.ny);
    let mut out = report(settings, grid.dx, "one solve", times.clone());
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.depth = times
        .iter()
        .map(|&t| r.velocity * history.impulse(t))
        .collect();
    out.contact_length = vec![2.0 * (area / PI).sqrt(); times.len()];
    out.area = Some(vec![area; times.len()]);
    out.force = times.iter().map(|&t| history.force(t)).collect();
    out.velocity = Some(
        times
            .iter()
            .map(|&t| r.velocity * history.force(t))
            .collect(),
    );
    out.stiffness_length = Some(vec![r.damping / (4.0 * eta); times.len()]);
    out.central_pressure = Some(times.iter().map(|&t| p0 * history.force(t)).collect());
    out.saturated = Some(vec![true; times.len()]);
    out.at_edge = Some(vec![false; times.len()]);
    out.solves = 1;
    out.iterations = r.iterations;
    out.residual = r.residual;
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
    let times = scene.output_times();
    let steps = scene.field_steps();
    let medium = mdr::Medium::Viscous { eta };
    let s = mdr::run(&f, medium, history, &times, &steps, monitor)?;
    let unit = mdr::run(
        &f,
        medium,
        &ForceHistory::constant(1.0)?,
        &[1.0],
        &[0],
        monitor,
    )?;
    let p0 = transforms::pressure_from_line_load(&unit.fields[0].line_load, f.dx(), &[0.0])?[0];
    let mut out = report(settings, f.dx(), "one solve", s.t.clone());
    out.depth = s.depth.clone();
    out.contact_length = s.contact_length.clone();
    out.force = times.iter().map(|&t| history.force(t)).collect();
    out.velocity = Some(s.velocity.clone());
    out.stiffness_length = Some(s.contact_length.clone());
    out.central_pressure = Some(out.force.iter().map(|&force| p0 * force).collect());
    out.saturated = Some(s.saturated.clone());
    out.steps = times.len();
    out.solves = 1;
    out.fields = mdr_fields(scene, &f, &s, &scene.field_times(), &steps)?;
    Ok(out)
}

/// 3D radial fields at the field times from the 1D solution, by the inverse MDR transforms,
/// at `RADIAL_POINTS` radii from 0 to twice the contact radius.
fn mdr_fields(
    scene: &Scene,
    f: &Foundation,
    s: &mdr::MdrSeries,
    field_times: &[f64],
    steps: &[usize],
) -> Result<Vec<FieldSet>> {
    let dx = f.dx();
    let mut out = vec![];
    for (&t, &k) in field_times.iter().zip(steps) {
        let Some(fl) = s.fields.iter().find(|fl| fl.step == k) else {
            continue;
        };
        let a = 0.5 * s.contact_length[k];
        let span = 2.0 * a.max(dx);
        let r: Vec<f64> = (0..RADIAL_POINTS)
            .map(|i| span * i as f64 / (RADIAL_POINTS - 1) as f64)
            .collect();
        let inside = |v: &mut Vec<f64>, value: &dyn Fn(f64) -> Result<f64>| -> Result<()> {
            for (i, &ri) in r.iter().enumerate() {
                if ri < a {
                    v[i] = value(ri)?;
                }
            }
            Ok(())
        };
        let pressure = if scene.wants(Output::Pressure) {
            Some(transforms::pressure_from_line_load(&fl.line_load, dx, &r)?)
        } else {
            None
        };
        let surface_velocity = if scene.wants(Output::SurfaceVelocity) {
            let mut v = transforms::deflection_outside(&fl.velocity, dx, &r)?;
            inside(&mut v, &|_| Ok(s.velocity[k]))?;
            Some(v)
        } else {
            None
        };
        let deflection = if scene.wants(Output::Deflection) {
            let mut u = transforms::deflection_outside(&fl.displacement, dx, &r)?;
            inside(&mut u, &|ri| Ok(s.depth[k] - scene.indenter.height(ri)?))?;
            Some(u)
        } else {
            None
        };
        out.push(FieldSet {
            t,
            r: Some(r),
            pressure,
            surface_velocity,
            deflection,
            ..FieldSet::default()
        });
    }
    Ok(out)
}

fn run_viscoelastic(
    scene: &Scene,
    settings: &RunSettings,
    monitor: &mut dyn Monitor,
) -> Result<Report> {
    refuse(
        scene,
        &[
            Output::Velocity,
            Output::StiffnessLength,
            Output::Pressure,
            Output::SurfaceVelocity,
            Output::Deflection,
        ],
        "from the viscoelastic stepping (depth, contact length and force are)",
    )?;
    let rheology = scene.medium.rheology()?;
    let loading: Loading = scene.loading()?;
    let times = scene.output_times();
    let duration = scene.duration.expect("validated: a duration");
    let dt = settings.dt.or(scene.dt).unwrap_or(duration / DEFAULT_STEPS);
    if duration / dt > MAX_STEPS {
        return Err(Error::InvalidInput(format!(
            "dt = {dt} s over {duration} s is {:.3e} steps, more than {MAX_STEPS:.0e}",
            duration / dt
        )));
    }
    let (s, dx, shape) = match settings.method {
        Method::Mdr => {
            let (g, dx) = scene
                .indenter
                .mdr_profile(settings.n, mdr_half_length(scene)?)?;
            let s = viscoelastic::run_mdr(&g, dx, &rheology, &loading, &times, dt, monitor)?;
            (s, dx, None)
        }
        Method::Bem => {
            let grid = bem_grid(scene, settings.n)?;
            let s = viscoelastic::run_bem(
                &grid,
                &rheology,
                &loading,
                &times,
                dt,
                &settings.solver,
                monitor,
            )?;
            (s, grid.dx, Some([grid.ny, grid.nx]))
        }
    };
    let mut out = report(settings, dx, "viscoelastic", s.t);
    out.grid_shape = shape;
    out.depth = s.depth;
    out.contact_length = s.contact_length;
    out.force = s.force;
    out.steps = s.steps;
    out.solves = if settings.method == Method::Bem {
        s.steps
    } else {
        0
    };
    out.iterations = s.iterations.iter().sum();
    Ok(out)
}
