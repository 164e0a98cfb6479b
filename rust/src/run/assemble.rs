//! Report assembly: the one place where the engines' series (`Series`) become a `Report`
//! (`report_from`), with the fields and grid numbers each method adds (`bem_report`,
//! `mdr_report`), for the scene runs and for the array-level bindings alike.

use super::report::{FieldSet, Report};
use crate::bem::static_contact;
use crate::bem::viscous::Fields;
use crate::mdr::foundation::Fields1D;
use crate::mdr::transforms;
use crate::model::grid::Grid;
use crate::model::RunSettings;
use crate::model::{Output, Scene};
use crate::stepping::Series;
use crate::support::error::Result;
use std::f64::consts::PI;

/// Radii of an MDR radial field inside the contact (this many, from 0 towards the contact
/// radius a) and outside it (one more, from just beyond a out to 2a).
pub const RADIAL_POINTS: usize = 200;

/// Radii (m) of an MDR radial field of contact radius `a` (m): graded towards r = a from
/// both sides, where the pressure of a sharp-edged contact has its inverse-square-root
/// singularity, so that the trapezoid rule over the samples integrates the force; r = a
/// itself is not sampled. Without contact, uniform radii out to twice the element size
/// `dx` (m).
pub fn radial_points(a: f64, dx: f64) -> Vec<f64> {
    let m = RADIAL_POINTS as f64;
    if a <= 0.0 {
        return (0..=2 * RADIAL_POINTS)
            .map(|j| 2.0 * dx * j as f64 / (2.0 * m))
            .collect();
    }
    let inside = (0..RADIAL_POINTS).map(|j| a * (1.0 - (1.0 - j as f64 / m).powi(4)));
    let outside = (1..=RADIAL_POINTS + 1).map(|j| a * (1.0 + (j as f64 / (m + 1.0)).powi(4)));
    inside.chain(outside).collect()
}

/// Element-centre coordinates (m) of `m` elements of size dx, symmetric about 0.
pub fn centres(m: usize, dx: f64) -> Vec<f64> {
    (0..m)
        .map(|i| (i as f64 - 0.5 * (m as f64 - 1.0)) * dx)
        .collect()
}

/// A report with the run's identity and output times `t`, the rest empty.
fn report(settings: &RunSettings, dx: f64, integrator: &str, t: Vec<f64>) -> Report {
    Report {
        method: settings.method,
        n: settings.n,
        dx,
        grid_shape: None,
        integrator: integrator.into(),
        depth: vec![],
        contact_length: vec![],
        area: None,
        zone_area: None,
        zone_length: None,
        force: vec![],
        velocity: None,
        stiffness_length: None,
        central_pressure: None,
        contact_fraction: None,
        patches: None,
        mean_gap: None,
        saturated: None,
        at_edge: None,
        fields: vec![],
        pull_off_force: None,
        pull_off_depth: None,
        pull_off_time: None,
        jump_in: None,
        jump_out: None,
        steps: 0,
        solves: 0,
        iterations: 0,
        solver: None,
        window: None,
        level_iterations: None,
        residual: 0.0,
        wall_time: 0.0,
        warnings: vec![],
        t,
    }
}

/// The report of a run from the series `s` its engine returned: output times, depth,
/// contact length, force, area, velocity and stiffness length as `wanted` says, saturation,
/// edge contact, an adhesive contact's pull-off and jumps, steps, solves, iterations summed and the largest residual. The series'
/// fields, patches and mean deflections stay in `s` for the caller (`bem_report`,
/// `mdr_report`).
pub fn report_from<F>(
    settings: &RunSettings,
    dx: f64,
    integrator: &str,
    s: &mut Series<F>,
    wanted: Wanted,
) -> Report {
    let some = |v: Vec<f64>| (!v.is_empty()).then_some(v);
    let mut out = report(settings, dx, integrator, std::mem::take(&mut s.t));
    out.depth = std::mem::take(&mut s.depth);
    out.contact_length = std::mem::take(&mut s.contact_length);
    out.force = std::mem::take(&mut s.force);
    out.area = some(std::mem::take(&mut s.area));
    out.zone_area = some(std::mem::take(&mut s.zone_area));
    out.zone_length = out
        .zone_area
        .as_ref()
        .map(|a| a.iter().map(|&a| 2.0 * (a / PI).sqrt()).collect());
    out.velocity = wanted.velocity.then(|| std::mem::take(&mut s.velocity));
    out.stiffness_length = wanted
        .stiffness_length
        .then(|| std::mem::take(&mut s.stiffness_length));
    out.saturated = (!s.saturated.is_empty()).then(|| std::mem::take(&mut s.saturated));
    out.at_edge = (!s.at_edge.is_empty()).then(|| std::mem::take(&mut s.at_edge));
    if let Some(jumps) = s.jumps.take() {
        if let Some([t, d, f]) = jumps.pull_off {
            (out.pull_off_time, out.pull_off_depth, out.pull_off_force) =
                (Some(t), Some(d), Some(f));
        }
        out.jump_in = Some(jumps.jump_in);
        out.jump_out = Some(jumps.jump_out);
    }
    out.steps = s.steps;
    out.solves = s.solves;
    out.iterations = s.iterations.iter().sum();
    out.residual = s.residual.iter().fold(0.0, |a: f64, &b| a.max(b));
    out
}

/// The report of a BEM run on `grid` from its series (`report_from`), with the grid's shape,
/// the fields at (time, output index) `at` and, for a height map, its series.
pub fn bem_report(
    settings: &RunSettings,
    grid: &Grid,
    integrator: &str,
    mut s: Series<Fields>,
    wanted: Wanted,
    at: &[(f64, usize)],
) -> Report {
    let mut out = report_from(settings, grid.dx, integrator, &mut s, wanted);
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.fields = bem_fields(grid, &s.fields, wanted, at, &out.depth);
    if wanted.height_map {
        let area = out.area.clone().unwrap_or_default();
        height_map_series(&mut out, grid, &area, s.patches, &s.mean_deflection);
    }
    out
}

/// The report of an MDR run of `scene` (element spacing `dx`, m) from its series
/// (`report_from`), with the radial fields at (time, output index) `at`.
pub fn mdr_report(
    scene: &Scene,
    settings: &RunSettings,
    dx: f64,
    integrator: &str,
    mut s: Series<Fields1D>,
    wanted: Wanted,
    at: &[(f64, usize)],
) -> Result<Report> {
    let (field_times, steps): (Vec<f64>, Vec<usize>) = at.iter().copied().unzip();
    let fields = mdr_fields(scene, dx, &s, &field_times, &steps)?;
    let mut out = report_from(settings, dx, integrator, &mut s, wanted);
    out.fields = fields;
    Ok(out)
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
    /// Gap fields (height maps).
    pub gap: bool,
    /// The height-map series: contact fraction, patches, mean gap.
    pub height_map: bool,
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
            gap: scene.wants(Output::Gap),
            height_map: matches!(scene.indenter, crate::model::Indenter::HeightMap(_)),
        }
    }

    /// Whether any field is asked for.
    pub fn fields(&self) -> bool {
        self.pressure || self.surface_velocity || self.deflection || self.gap
    }
}

/// Fills the height-map series of `out` at each output time from the contact areas (m^2),
/// patch counts, depths (m) and mean deflections over the grid (m): the contact fraction
/// A / (nx ny dx^2) and the mean gap, mean height below the highest point plus mean
/// deflection minus depth (the gap is h + u - d everywhere, zero in contact).
pub fn height_map_series(
    out: &mut Report,
    grid: &Grid,
    area: &[f64],
    patches: Vec<usize>,
    mean_deflection: &[f64],
) {
    let elements = (grid.nx * grid.ny) as f64;
    let map_area = elements * grid.dx * grid.dx;
    let mean_height = grid.height.iter().sum::<f64>() / elements;
    out.contact_fraction = Some(area.iter().map(|a| a / map_area).collect());
    out.patches = Some(patches);
    out.mean_gap = Some(
        out.depth
            .iter()
            .zip(mean_deflection)
            .map(|(d, u)| mean_height + u - d)
            .collect(),
    );
}

/// The gap field (m) of `grid` under the deflection `u` (m) at depth `d` (m): h + u - d.
pub fn gap(grid: &Grid, u: &[f64], d: f64) -> Vec<f64> {
    grid.height.iter().zip(u).map(|(h, u)| h + u - d).collect()
}

/// Mean of `values` over the grid.
pub fn mean(values: &[f64]) -> f64 {
    values.iter().sum::<f64>() / values.len() as f64
}

/// The report of a static BEM contact on `grid` under `force` (N), with pressure, deflection
/// and gap fields and the height-map series as `wanted` says (the deflection, the gap and
/// the mean gap only where the solve computed the deflection).
pub fn bem_static_report(
    settings: &RunSettings,
    grid: &Grid,
    force: f64,
    r: static_contact::StaticContact,
    wanted: Wanted,
) -> Report {
    let area = r.summary.contact_count as f64 * grid.dx * grid.dx;
    let contact: Vec<bool> = r.pressure.iter().map(|&p| p > 0.0).collect();
    let mut s: Series<Fields> = Series {
        t: vec![0.0],
        depth: vec![r.summary.depth],
        force: vec![force],
        contact_length: vec![2.0 * (area / PI).sqrt()],
        area: vec![area],
        saturated: vec![grid.covers(area)],
        at_edge: vec![grid.touches_edge(&contact)],
        iterations: vec![r.summary.iterations],
        residual: vec![r.summary.residual],
        solves: r.solves,
        ..Series::default()
    };
    let mut out = report_from(settings, grid.dx, "static", &mut s, wanted);
    out.grid_shape = Some([grid.ny, grid.nx]);
    out.solver = Some(static_solver_name(r.summary.dense).into());
    out.window = Some([r.window.y0, r.window.x0, r.window.wy, r.window.wx]);
    out.level_iterations = Some(r.level_iterations.clone());
    let u = r.deflection.as_deref();
    if wanted.height_map {
        let mean_u = u.map_or(f64::NAN, mean);
        height_map_series(
            &mut out,
            grid,
            &[area],
            vec![grid.patches(&contact)],
            &[mean_u],
        );
    }
    if wanted.fields() {
        out.fields.push(FieldSet {
            t: 0.0,
            x: Some(centres(grid.nx, grid.dx)),
            y: Some(centres(grid.ny, grid.dx)),
            gap: u
                .filter(|_| wanted.gap)
                .map(|u| gap(grid, u, r.summary.depth)),
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

/// BEM field sets on `grid` at (time, output index) `at`, from the solver's fields, as
/// `wanted` says; the gap from the depths (m) at the output indices.
pub fn bem_fields(
    grid: &Grid,
    solved: &[Fields],
    wanted: Wanted,
    at: &[(f64, usize)],
    depth: &[f64],
) -> Vec<FieldSet> {
    at.iter()
        .filter_map(|&(t, k)| {
            let f = solved.iter().find(|f| f.step == k)?;
            Some(FieldSet {
                t,
                x: Some(centres(grid.nx, grid.dx)),
                y: Some(centres(grid.ny, grid.dx)),
                pressure: wanted.pressure.then(|| f.pressure.clone()),
                surface_velocity: wanted.surface_velocity.then(|| f.velocity.clone()),
                deflection: wanted.deflection.then(|| f.deflection.clone()),
                gap: wanted.gap.then(|| gap(grid, &f.deflection, depth[k])),
                ..FieldSet::default()
            })
        })
        .collect()
}

/// Value at the grid centre: the centre element (odd sizes) or the mean of the 2 or 4
/// elements around it (even sizes).
pub fn central_value(field: &[f64], nx: usize, ny: usize) -> f64 {
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

/// 3D radial fields at the field times from the 1D solution (element spacing `dx`, m), by
/// the inverse MDR transforms, at the `radial_points` of each time's contact radius.
pub fn mdr_fields(
    scene: &Scene,
    dx: f64,
    s: &Series<Fields1D>,
    field_times: &[f64],
    steps: &[usize],
) -> Result<Vec<FieldSet>> {
    let mut out = vec![];
    for (&t, &k) in field_times.iter().zip(steps) {
        let Some(fl) = s.fields.iter().find(|fl| fl.step == k) else {
            continue;
        };
        let a = 0.5 * s.contact_length[k];
        let r = radial_points(a, dx);
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
