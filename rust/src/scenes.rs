//! Built-in scenes for the Rust-only binary: indenter geometry, scene files (TOML) and a
//! runner that returns one JSON-serialisable report per scene. The Python package has
//! its own, richer geometry layer; this one covers the paper's indenters.

use crate::contact::SolverOptions;
use crate::error::{check_positive, Error, Result};
use crate::loading::ForceHistory;
use crate::mdr::{self, Foundation, Medium};
use crate::monitor::Monitor;
use crate::viscous::{self, Grid, ViscousRequest};
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
        self.validate()?;
        if n == 0 {
            return Err(Error::InvalidInput("grid size n must be >= 1".into()));
        }
        let half = self.grid_half_width(impulse, eta);
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
        self.validate()?;
        if n == 0 {
            return Err(Error::InvalidInput("element count n must be >= 1".into()));
        }
        let half = self
            .half_length_1d()
            .unwrap_or_else(|| 1.2 * self.contact_radius(impulse, eta));
        let dx = 2.0 * half / n as f64;
        let profile = (0..n)
            .map(|i| self.profile_1d((i as f64 + 0.5) * dx - half))
            .collect();
        Foundation::new(profile, dx)
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
#[derive(Debug, Clone, Copy, PartialEq, Deserialize, Serialize)]
#[serde(tag = "type", rename_all = "lowercase", deny_unknown_fields)]
pub enum MediumSpec {
    /// Newtonian viscous half-space.
    Viscous {
        /// Shear viscosity (Pa s).
        eta: f64,
    },
}

/// A scene: indenter, medium, constant force, duration, method and resolution.
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// The indenter.
    pub indenter: Indenter,
    /// The half-space.
    pub medium: MediumSpec,
    /// Constant force from first touch (N).
    pub force: f64,
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
    /// Penetration rate (m/s).
    pub velocity: Vec<f64>,
    /// Central pressure (Pa): rods only.
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
        check_positive("force", s.force)?;
        check_positive("duration", s.duration)?;
        Ok(s)
    }

    fn output_times(&self) -> Vec<f64> {
        self.times
            .clone()
            .unwrap_or_else(|| (1..=5).map(|k| self.duration * k as f64 / 5.0).collect())
    }

    /// Runs the scene.
    pub fn run(&self, opts: &SolverOptions, monitor: &mut dyn Monitor) -> Result<Report> {
        let MediumSpec::Viscous { eta } = self.medium;
        check_positive("viscosity eta", eta)?;
        let start = Instant::now();
        let history = ForceHistory::constant(self.force)?;
        let times = self.output_times();
        let impulse = history.impulse(*times.last().unwrap_or(&self.duration));
        match (self.method, self.indenter) {
            (Method::Bem, Indenter::Rod { .. }) => {
                let grid = self.indenter.bem_grid(self.n, impulse, eta)?;
                let r = viscous::run_punch(&grid, eta, self.force, None, opts, monitor)?;
                Ok(Report {
                    method: Method::Bem,
                    n: self.n,
                    dx: grid.dx,
                    t: times.clone(),
                    depth: times.iter().map(|t| r.velocity * t).collect(),
                    contact_length: vec![
                        2.0 * (grid.allowed.iter().filter(|&&a| a).count() as f64
                            * grid.dx
                            * grid.dx
                            / PI)
                            .sqrt();
                        times.len()
                    ],
                    velocity: vec![r.velocity; times.len()],
                    central_pressure: Some(central_value(&r.pressure, grid.nx, grid.ny)),
                    iterations: r.iterations,
                    residual: r.residual,
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
            (Method::Bem, _) => {
                let grid = self.indenter.bem_grid(self.n, impulse, eta)?;
                let req = ViscousRequest {
                    times,
                    rates: true,
                    fields_at: vec![],
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
                    central_pressure: None,
                    iterations: s.iterations.iter().sum(),
                    residual: s.residual.iter().fold(0.0, |a: f64, &b| a.max(b)),
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
            (Method::Mdr, _) => {
                let f = self.indenter.foundation(self.n, impulse, eta)?;
                let fields: &[usize] = if matches!(self.indenter, Indenter::Rod { .. }) {
                    &[0]
                } else {
                    &[]
                };
                let s = mdr::run(
                    &f,
                    Medium::Viscous { eta },
                    &history,
                    &times,
                    fields,
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
                    central_pressure,
                    iterations: 0,
                    residual: 0.0,
                    wall_time: start.elapsed().as_secs_f64(),
                })
            }
        }
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
