//! Built-in scenes for the Rust-only binary: indenter geometry, scene files (TOML) and a
//! runner that returns one JSON-serialisable report per scene. The Python package has
//! its own, richer geometry layer; this one covers the paper's indenters.

use crate::contact::SolverOptions;
use crate::error::{check_positive, Error, Result};
use crate::grid::Grid;
use crate::loading::{DepthHistory, ForceHistory, Loading};
use crate::mdr::{self, Foundation, Medium};
use crate::monitor::Monitor;
use crate::rheology::Rheology;
use crate::viscoelastic;
use crate::viscous::{self, ViscousRequest};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;
use std::time::Instant;

/// An axisymmetric rigid indenter; `edge` bounds a square footprint (m), None = unbounded.
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum Indenter {
    /// Flat cylindrical punch of radius `radius` (m).
    Rod {
        /// Radius (m).
        radius: f64,
    },
    /// h = c r^2 (c in 1/m).
    Paraboloid {
        /// Curvature parameter c (1/m); R = 1 / (2c).
        c: f64,
        /// Edge of the square footprint (m).
        edge: Option<f64>,
    },
    /// h = slope r.
    Cone {
        /// Slope (dimensionless).
        slope: f64,
        /// Edge of the square footprint (m).
        edge: Option<f64>,
    },
}

impl Indenter {
    /// Fails on non-finite or non-positive parameters.
    pub fn validate(&self) -> Result<()> {
        let edge = match *self {
            Indenter::Rod { radius } => return check_positive("rod radius", radius),
            Indenter::Paraboloid { c, edge } => {
                check_positive("paraboloid c", c)?;
                edge
            }
            Indenter::Cone { slope, edge } => {
                check_positive("cone slope", slope)?;
                edge
            }
        };
        edge.map_or(Ok(()), |e| check_positive("footprint edge", e))
    }

    /// Height above the tip (m) at radius `r` (m).
    pub fn height(&self, r: f64) -> f64 {
        match *self {
            Indenter::Rod { .. } => 0.0,
            Indenter::Paraboloid { c, .. } => c * r * r,
            Indenter::Cone { slope, .. } => slope * r,
        }
    }

    /// MDR profile g(x) (m) at |x| (m).
    pub fn profile_1d(&self, x: f64) -> f64 {
        match *self {
            Indenter::Rod { .. } => 0.0,
            Indenter::Paraboloid { c, .. } => 2.0 * c * x * x,
            Indenter::Cone { slope, .. } => 0.5 * PI * slope * x.abs(),
        }
    }

    /// Half-width of the square footprint, if bounded (m).
    pub fn half_width(&self) -> Option<f64> {
        match *self {
            Indenter::Rod { radius } => Some(radius),
            Indenter::Paraboloid { edge, .. } | Indenter::Cone { edge, .. } => {
                edge.map(|e| 0.5 * e)
            }
        }
    }

    /// Half-length of the 1D MDR indenter (equal area for a square footprint), if bounded.
    pub fn half_length_1d(&self) -> Option<f64> {
        match *self {
            Indenter::Rod { radius } => Some(radius),
            Indenter::Paraboloid { edge, .. } | Indenter::Cone { edge, .. } => {
                edge.map(|e| e / PI.sqrt())
            }
        }
    }

    /// Final contact radius (m) of an unbounded indenter on a viscous half-space after the
    /// impulse `impulse` (N s): a = x with 4 eta integral_{-a}^{a} (g(a) - g(x)) dx = I.
    fn contact_radius(&self, impulse: f64, eta: f64) -> f64 {
        let s = impulse / (4.0 * eta);
        match *self {
            Indenter::Rod { radius } => radius,
            // 2 (g(a) a - integral_0^a g) = 2 (2c a^3 - 2c a^3 / 3) = 8 c a^3 / 3
            Indenter::Paraboloid { c, .. } => (3.0 * s / (8.0 * c)).cbrt(),
            // 2 (k a^2 - k a^2 / 2) = k a^2, k = pi slope / 2
            Indenter::Cone { slope, .. } => (s / (0.5 * PI * slope)).sqrt(),
        }
    }

    /// Half-width of the BEM grid (m): the footprint, or for unbounded indenters 1.2 times
    /// the final contact radius.
    fn grid_half_width(&self, impulse: f64, eta: f64) -> f64 {
        self.half_width()
            .unwrap_or_else(|| 1.2 * self.contact_radius(impulse, eta))
    }

    /// BEM grid of n x n elements over the footprint. For the rod, n = diameter / dx and the
    /// grid is centred on an element ((n + 1) x (n + 1) for even n), so n = 200 puts the
    /// paper's 31417 elements inside the disc.
    pub fn bem_grid(&self, n: usize, impulse: f64, eta: f64) -> Result<Grid> {
        self.bem_grid_over(n, self.grid_half_width(impulse, eta))
    }

    /// BEM grid of n x n elements over a square of half-width `half` (m).
    fn bem_grid_over(&self, n: usize, half: f64) -> Result<Grid> {
        self.validate()?;
        if n == 0 {
            return Err(Error::InvalidInput("grid size n must be >= 1".into()));
        }
        let dx = 2.0 * half / n as f64;
        let (m, offset) = match self {
            Indenter::Rod { .. } => (2 * (n / 2) + 1, (n / 2) as f64),
            _ => (n, 0.5 * (n as f64 - 1.0)),
        };
        let centre = |i: usize| (i as f64 - offset) * dx;
        let mut height = Vec::with_capacity(m * m);
        let mut allowed = Vec::with_capacity(m * m);
        for iy in 0..m {
            for ix in 0..m {
                let r = centre(ix).hypot(centre(iy));
                let inside = match self {
                    Indenter::Rod { radius } => r <= *radius * (1.0 + 1e-12),
                    _ => true,
                };
                allowed.push(inside);
                height.push(if inside { self.height(r) } else { 0.0 });
            }
        }
        Grid::new(m, m, dx, height, allowed)
    }

    /// MDR foundation of n elements over the 1D indenter (unbounded: 1.2 times the final
    /// contact radius on each side).
    pub fn foundation(&self, n: usize, impulse: f64, eta: f64) -> Result<Foundation> {
        let (profile, dx) = self.profile_over(n, || 1.2 * self.contact_radius(impulse, eta))?;
        Foundation::new(profile, dx)
    }

    /// The 1D profile (m) of n elements and their spacing (m) over the 1D indenter, or over
    /// `unbounded()` on each side of an unbounded one.
    fn profile_over(&self, n: usize, unbounded: impl FnOnce() -> f64) -> Result<(Vec<f64>, f64)> {
        self.validate()?;
        if n == 0 {
            return Err(Error::InvalidInput("element count n must be >= 1".into()));
        }
        let half = self.half_length_1d().unwrap_or_else(unbounded);
        let dx = 2.0 * half / n as f64;
        Ok((
            (0..n)
                .map(|i| self.profile_1d((i as f64 + 0.5) * dx - half))
                .collect(),
            dx,
        ))
    }

    /// Contact radius (m) at depth `d` (m) of an unbounded indenter (MDR: g(a) = d).
    fn radius_at_depth(&self, d: f64) -> f64 {
        match *self {
            Indenter::Rod { radius } => radius,
            Indenter::Paraboloid { c, .. } => (d.max(0.0) / (2.0 * c)).sqrt(),
            Indenter::Cone { slope, .. } => 2.0 * d.max(0.0) / (PI * slope),
        }
    }
}

/// Solution method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Boundary elements on an n x n grid.
    Bem,
    /// Method of dimensionality reduction with n elements.
    Mdr,
}

/// The medium of a scene file.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MediumSpec {
    /// Newtonian viscous half-space.
    Viscous {
        /// Shear viscosity (Pa s).
        eta: f64,
    },
    /// Spring G (Pa) parallel to a dashpot eta (Pa s).
    KelvinVoigt {
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Viscosity (Pa s).
        eta: f64,
    },
    /// Spring G (Pa) in series with a dashpot eta (Pa s).
    Maxwell {
        /// Shear modulus (Pa).
        #[serde(rename = "G")]
        g: f64,
        /// Viscosity (Pa s).
        eta: f64,
    },
    /// G(t) = G_inf + G1 exp(-t / tau1).
    StandardSolid {
        /// Long-time modulus (Pa).
        #[serde(rename = "G_inf")]
        g_inf: f64,
        /// Relaxing modulus (Pa).
        #[serde(rename = "G1")]
        g1: f64,
        /// Relaxation time (s).
        tau1: f64,
    },
    /// G(t) = G_inf + sum G_k exp(-t / tau_k).
    Prony {
        /// Long-time modulus (Pa).
        #[serde(rename = "G_inf")]
        g_inf: f64,
        /// Terms [G_k (Pa), tau_k (s)].
        terms: Vec<[f64; 2]>,
    },
}

impl MediumSpec {
    /// The medium as a relaxation modulus.
    pub fn rheology(&self) -> Result<Rheology> {
        match self {
            MediumSpec::Viscous { eta } => Rheology::new(0.0, vec![], *eta),
            MediumSpec::KelvinVoigt { g, eta } => {
                check_positive("G", *g)?;
                check_positive("eta", *eta)?;
                Rheology::new(*g, vec![], *eta)
            }
            MediumSpec::Maxwell { g, eta } => {
                check_positive("G", *g)?;
                check_positive("eta", *eta)?;
                Rheology::new(0.0, vec![(*g, eta / g)], 0.0)
            }
            MediumSpec::StandardSolid { g_inf, g1, tau1 } => {
                check_positive("G_inf", *g_inf)?;
                Rheology::new(*g_inf, vec![(*g1, *tau1)], 0.0)
            }
            MediumSpec::Prony { g_inf, terms } => {
                Rheology::new(*g_inf, terms.iter().map(|t| (t[0], t[1])).collect(), 0.0)
            }
        }
    }
}

/// The force on the indenter in a scene file: a constant (N) from first touch, or samples
/// [t (s), F (N)], piecewise linear from t = 0 and held after the last sample.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(untagged, expecting = "a number or a list of [t, F] pairs")]
pub enum ForceSpec {
    /// Constant force (N).
    Constant(f64),
    /// History samples [t (s), F (N)].
    Samples(Vec<[f64; 2]>),
}

impl ForceSpec {
    /// The validated force history.
    pub fn history(&self) -> Result<ForceHistory> {
        match self {
            ForceSpec::Constant(f) => {
                check_positive("force", *f)?;
                ForceHistory::constant(*f)
            }
            ForceSpec::Samples(samples) => {
                let (t, f): (Vec<f64>, Vec<f64>) = samples.iter().map(|p| (p[0], p[1])).unzip();
                ForceHistory::piecewise_linear(t, f)
            }
        }
    }

    /// Largest force of the history (N).
    pub fn max(&self) -> f64 {
        match self {
            ForceSpec::Constant(f) => *f,
            ForceSpec::Samples(samples) => samples.iter().map(|p| p[1]).fold(0.0, f64::max),
        }
    }
}

/// A scene: indenter, medium, force or depth history, duration, method and resolution.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The indenter.
    pub indenter: Indenter,
    /// The half-space.
    pub medium: MediumSpec,
    /// Force: constant from first touch, or a history; or give `depth`.
    #[serde(default)]
    pub force: Option<ForceSpec>,
    /// Depth history samples [t (s), d (m)], piecewise linear from t = 0.
    #[serde(default)]
    pub depth: Option<Vec<[f64; 2]>>,
    /// Longest time step (s) of the viscoelastic stepping; default duration / 500.
    #[serde(default)]
    pub dt: Option<f64>,
    /// Outputs the Python interface computes; the binary reports depth, force, contact
    /// length and rates whatever is named here.
    #[serde(default)]
    pub outputs: Option<Vec<String>>,
    /// Simulated time (s).
    pub duration: f64,
    /// BEM or MDR.
    pub method: Method,
    /// Grid size (BEM: n x n) or element count (MDR).
    pub n: usize,
    /// Output times (s); default: 5 equal steps up to the duration.
    #[serde(default)]
    pub times: Option<Vec<f64>>,
}

/// What a scene run reports (SI units), ready for printing or JSON.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Report {
    /// "bem" or "mdr".
    pub method: Method,
    /// Grid size or element count.
    pub n: usize,
    /// Element size (m).
    pub dx: f64,
    /// Output times (s).
    pub t: Vec<f64>,
    /// Depth (m).
    pub depth: Vec<f64>,
    /// Contact length from the contact area (BEM) or element count (MDR) (m).
    pub contact_length: Vec<f64>,
    /// Penetration rate (m/s); empty for viscoelastic runs.
    pub velocity: Vec<f64>,
    /// Total force (N) at each output time: viscoelastic runs only.
    pub force: Option<Vec<f64>>,
    /// Central pressure (Pa) at the last output time: rods only.
    pub central_pressure: Option<f64>,
    /// Solver iterations in total.
    pub iterations: usize,
    /// Largest final residual.
    pub residual: f64,
    /// Wall time (s).
    pub wall_time: f64,
}

impl Scene {
    /// Parses a scene from TOML text; unknown keys are errors.
    pub fn from_toml(text: &str) -> Result<Self> {
        let s: Scene =
            toml::from_str(text).map_err(|e| Error::InvalidInput(format!("scene file: {e}")))?;
        s.indenter.validate()?;
        match (&s.force, &s.depth) {
            (Some(f), None) => {
                f.history()?;
            }
            (None, Some(_)) => {}
            (None, None) => {
                return Err(Error::InvalidInput(
                    "scene file: missing key force (or depth)".into(),
                ))
            }
            (Some(_), Some(_)) => {
                return Err(Error::InvalidInput(
                    "scene file: give only one of force and depth".into(),
                ))
            }
        }
        check_positive("duration", s.duration)?;
        s.medium.rheology()?;
        Ok(s)
    }

    fn output_times(&self) -> Vec<f64> {
        self.times
            .clone()
            .unwrap_or_else(|| (1..=5).map(|k| self.duration * k as f64 / 5.0).collect())
    }

    /// Runs the scene: the exact viscous engine for a viscous medium under a force, the
    /// viscoelastic stepping otherwise.
    pub fn run(&self, opts: &SolverOptions, monitor: &mut dyn Monitor) -> Result<Report> {
        let (eta, history) = match (&self.medium, &self.force) {
            (MediumSpec::Viscous { eta }, Some(f)) => (*eta, f.history()?),
            _ => return self.run_viscoelastic(opts, monitor),
        };
        check_positive("viscosity eta", eta)?;
        let start = Instant::now();
        let times = self.output_times();
        let t_end = *times.last().unwrap_or(&self.duration);
        let impulse = history.impulse(t_end);
        match (self.method, self.indenter) {
            (Method::Bem, Indenter::Rod { .. }) => {
                let grid = self.indenter.bem_grid(self.n, impulse, eta)?;
                // the rod's rate is proportional to the force: one solve at unit force
                let r = viscous::run_punch(&grid, eta, 1.0, None, opts, monitor)?;
                Ok(Report {
                    method: Method::Bem,
                    n: self.n,
                    dx: grid.dx,
                    t: times.clone(),
                    depth: times
                        .iter()
                        .map(|&t| r.velocity * history.impulse(t))
                        .collect(),
                    contact_length: vec![
                        2.0 * (grid.allowed.iter().filter(|&&a| a).count() as f64
                            * grid.dx
                            * grid.dx
                            / PI)
                            .sqrt();
                        times.len()
                    ],
                    velocity: times
                        .iter()
                        .map(|&t| r.velocity * history.force(t))
                        .collect(),
                    force: None,
                    central_pressure: Some(
                        central_value(&r.pressure, grid.nx, grid.ny) * history.force(t_end),
                    ),
                    iterations: r.iterations,
                    residual: r.residual,
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
            (Method::Bem, _) => {
                let grid = self.indenter.bem_grid(self.n, impulse, eta)?;
                // MDR's depths size the steps' windows while the contact fits the footprint
                let half = self.indenter.half_width().unwrap_or(f64::INFINITY);
                let depth_bounds = times
                    .iter()
                    .map(|&t| {
                        let a = self.indenter.contact_radius(history.impulse(t), eta);
                        if a < half {
                            1.05 * self.indenter.profile_1d(a)
                        } else {
                            f64::NAN
                        }
                    })
                    .collect();
                let req = ViscousRequest {
                    times,
                    rates: true,
                    fields_at: vec![],
                    depth_bounds,
                };
                let s = viscous::run_implicit(&grid, eta, &history, &req, opts, monitor)?;
                if self.indenter.half_width().is_none() && s.at_border.iter().any(|&b| b) {
                    return Err(Error::Domain(
                        "the contact reached the edge of the BEM grid of an unbounded indenter"
                            .into(),
                    ));
                }
                Ok(Report {
                    method: Method::Bem,
                    n: self.n,
                    dx: grid.dx,
                    t: s.t,
                    depth: s.depth,
                    contact_length: s.contact_length,
                    velocity: s.velocity,
                    force: None,
                    central_pressure: None,
                    iterations: s.iterations.iter().sum(),
                    residual: s.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
            (Method::Mdr, _) => {
                let f = self.indenter.foundation(self.n, impulse, eta)?;
                let fields = if matches!(self.indenter, Indenter::Rod { .. }) {
                    vec![times.len() - 1]
                } else {
                    vec![]
                };
                let s = mdr::run(
                    &f,
                    Medium::Viscous { eta },
                    &history,
                    &times,
                    &fields,
                    monitor,
                )?;
                let central_pressure = s
                    .fields
                    .first()
                    .map(|fl| {
                        crate::transforms::pressure_from_line_load(&fl.line_load, f.dx(), &[0.0])
                            .map(|p| p[0])
                    })
                    .transpose()?;
                Ok(Report {
                    method: Method::Mdr,
                    n: self.n,
                    dx: f.dx(),
                    t: s.t,
                    depth: s.depth,
                    contact_length: s.contact_length,
                    velocity: s.velocity,
                    force: None,
                    central_pressure,
                    iterations: 0,
                    residual: 0.0,
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
        }
    }
}

impl Scene {
    fn run_viscoelastic(&self, opts: &SolverOptions, monitor: &mut dyn Monitor) -> Result<Report> {
        let start = Instant::now();
        let medium = self.medium.rheology()?;
        let times = self.output_times();
        let dt = self.dt.unwrap_or(self.duration / 500.0);
        let (loading, radius) = match (&self.force, &self.depth) {
            (Some(spec), _) => {
                if medium.g_inf <= 0.0 && self.indenter.half_width().is_none() {
                    return Err(Error::InvalidInput(
                        "an unbounded indenter under a force needs a medium with long-time stiffness (G_inf > 0), or an edge".into(),
                    ));
                }
                let r = 1.2
                    * self
                        .indenter
                        .contact_radius(spec.max(), medium.g_inf.max(f64::MIN_POSITIVE));
                (Loading::Force(spec.history()?), r)
            }
            (None, Some(samples)) => {
                let (t, d): (Vec<f64>, Vec<f64>) = samples.iter().map(|p| (p[0], p[1])).unzip();
                let d_max = d.iter().copied().fold(0.0, f64::max);
                (
                    Loading::Depth(DepthHistory::piecewise_linear(t, d)?),
                    1.2 * self.indenter.radius_at_depth(d_max),
                )
            }
            (None, None) => {
                return Err(Error::InvalidInput(
                    "scene: missing force (or depth)".into(),
                ))
            }
        };
        let (s, dx) = match self.method {
            Method::Mdr => {
                let (g, dx) = self.indenter.profile_over(self.n, || radius)?;
                (
                    viscoelastic::run_mdr(&g, dx, &medium, &loading, &times, dt, monitor)?,
                    dx,
                )
            }
            Method::Bem => {
                let half = self.indenter.half_width().unwrap_or(radius);
                let grid = self.indenter.bem_grid_over(self.n, half)?;
                (
                    viscoelastic::run_bem(&grid, &medium, &loading, &times, dt, opts, monitor)?,
                    grid.dx,
                )
            }
        };
        Ok(Report {
            method: self.method,
            n: self.n,
            dx,
            t: s.t,
            depth: s.depth,
            contact_length: s.contact_length,
            velocity: vec![],
            force: Some(s.force),
            central_pressure: None,
            iterations: s.iterations.iter().sum(),
            residual: 0.0,
            wall_time: start.elapsed().as_secs_f64(),
        })
    }
}

/// Value at the grid centre: the centre element (odd sizes) or the mean of the 2 or 4
/// elements around it (even sizes).
pub fn central_value(field: &[f64], nx: usize, ny: usize) -> f64 {
    let xs: Vec<usize> = if nx % 2 == 1 {
        vec![nx / 2]
    } else {
        vec![nx / 2 - 1, nx / 2]
    };
    let ys: Vec<usize> = if ny % 2 == 1 {
        vec![ny / 2]
    } else {
        vec![ny / 2 - 1, ny / 2]
    };
    let vals: Vec<f64> = ys
        .iter()
        .flat_map(|&y| xs.iter().map(move |&x| field[y * nx + x]))
        .collect();
    vals.iter().sum::<f64>() / vals.len() as f64
}
