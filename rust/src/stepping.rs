//! Time stepping shared by the engines of both methods: what a viscoelastic run computes
//! (`Request`), the time series every engine returns (`Series`), its step times (`step_times`, at most
//! `MAX_STEPS` of them) and the backward-difference rates of its states (`Trail`).

use crate::model::loading::{check_output_times, Loading};
use crate::model::medium::rheology::Rheology;
use crate::model::settings::check_steps;
use crate::support::error::{Error, Result};

/// The time series every engine returns, one entry per output time, with its fields of
/// type `F` (BEM surface fields, or MDR 1D fields). A series an engine does not compute
/// stays empty; `crate::run::assemble::report_from` is the one place that turns it into a
/// `Report`.
#[derive(Debug, Clone, PartialEq)]
pub struct Series<F> {
    /// Output times (s).
    pub t: Vec<f64>,
    /// Indentation depth (m); under force control with zero force, the depth at which the
    /// indenter just touches the relaxing surface.
    pub depth: Vec<f64>,
    /// Total force (N).
    pub force: Vec<f64>,
    /// Contact length: BEM 2 sqrt(A / pi), MDR elements in contact times dx (m).
    pub contact_length: Vec<f64>,
    /// Contact area (m^2) (BEM).
    pub area: Vec<f64>,
    /// Area (m^2) of the contact and the adhesive zone around it: the elements within a
    /// cohesive law's range (BEM under a cohesive-zone law).
    pub zone_area: Vec<f64>,
    /// Penetration rate dd/dt (m/s): exact for a viscous medium, the second-order backward
    /// difference of the depth over the last three step times for the others (first order
    /// on the first two steps, where the state at t = 0 may precede a jump of the load);
    /// NaN where a run computes none.
    pub velocity: Vec<f64>,
    /// Contact length from the stiffness, F / (4 eta dd/dt) (m) (viscous BEM, when asked).
    pub stiffness_length: Vec<f64>,
    /// Whether the contact covers the indenter's whole footprint (saturation).
    pub saturated: Vec<bool>,
    /// Whether the contact reached the outermost ring of the grid (BEM).
    pub at_edge: Vec<bool>,
    /// Contact patches, 4-connected components of the contact (BEM).
    pub patches: Vec<usize>,
    /// Mean surface deflection over the grid (m) (BEM).
    pub mean_deflection: Vec<f64>,
    /// Solver iterations per output interval (BEM).
    pub iterations: Vec<usize>,
    /// Largest final relative residual of the contact solves per output interval (BEM).
    pub residual: Vec<f64>,
    /// Fields at the requested output indices.
    pub fields: Vec<F>,
    /// Time steps taken.
    pub steps: usize,
    /// Contact solves run.
    pub solves: usize,
    /// The jumps of an adhesive contact (None under hard contact).
    pub jumps: Option<Jumps>,
}

/// The jumps of an adhesive contact over a run, found at every time step.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Jumps {
    /// Times (s) of the steps at which a contact formed already carrying tension.
    pub jump_in: Vec<f64>,
    /// Times (s) of the steps at which a contact that carried tension let go.
    pub jump_out: Vec<f64>,
    /// The last state in contact before the first jump-out: time (s), depth (m) and the
    /// force (N, negative: tensile) the contact carried.
    pub pull_off: Option<[f64; 3]>,
}

impl Jumps {
    /// Records the step from `before` to `now`, each (time s, depth m, force N, elements
    /// in contact).
    pub fn record(&mut self, before: (f64, f64, f64, usize), now: (f64, f64, f64, usize)) {
        let (t0, d0, f0, k0) = before;
        let (t1, _, f1, k1) = now;
        if k0 > 0 && k1 == 0 && f0 < 0.0 {
            self.jump_out.push(t1);
            self.pull_off.get_or_insert([t0, d0, f0]);
        } else if k0 == 0 && k1 > 0 && f1 < 0.0 {
            self.jump_in.push(t1);
        }
    }
}

impl<F> Default for Series<F> {
    fn default() -> Self {
        Series {
            t: vec![],
            depth: vec![],
            force: vec![],
            contact_length: vec![],
            area: vec![],
            zone_area: vec![],
            velocity: vec![],
            stiffness_length: vec![],
            saturated: vec![],
            at_edge: vec![],
            patches: vec![],
            mean_deflection: vec![],
            iterations: vec![],
            residual: vec![],
            fields: vec![],
            steps: 0,
            solves: 0,
            jumps: None,
        }
    }
}

/// What a viscoelastic run computes: output times, step length, and fields.
#[derive(Debug, Clone, PartialEq)]
pub struct Request<'a> {
    /// Output times (s), > 0 and increasing.
    pub times: &'a [f64],
    /// Longest time step (s).
    pub dt: f64,
    /// Output-time indices at which to build fields.
    pub fields_at: &'a [usize],
    /// Whether those fields include surface-velocity rates (which keep two earlier states).
    pub field_rates: bool,
}

impl Request<'_> {
    /// Fails on a field index beyond the output times.
    pub fn check(&self) -> Result<()> {
        if let Some(&k) = self.fields_at.iter().find(|&&k| k >= self.times.len()) {
            return Err(Error::InvalidInput(format!(
                "field output index {k} is out of range for {} output times",
                self.times.len()
            )));
        }
        Ok(())
    }
}

/// The last two states of a quantity (a scalar or one value per point) and their times,
/// for the backward-difference rate at a new state.
pub struct Trail {
    t: [f64; 2],
    v: [Vec<f64>; 2],
    known: usize,
}

impl Trail {
    /// A trail that starts from `start` at t = 0.
    pub fn new(start: Vec<f64>) -> Self {
        Trail {
            t: [0.0, 0.0],
            v: [start.clone(), start],
            known: 1,
        }
    }

    /// Weights of the new state and the last two in the rate at `t`: BDF2 on the
    /// nonuniform steps once two states after the start are known, first order before.
    fn weights(&self, t: f64) -> [f64; 3] {
        let h1 = t - self.t[0];
        if self.known < 3 {
            return [1.0 / h1, -1.0 / h1, 0.0];
        }
        let h2 = self.t[0] - self.t[1];
        [
            (2.0 * h1 + h2) / (h1 * (h1 + h2)),
            -(h1 + h2) / (h1 * h2),
            h1 / (h2 * (h1 + h2)),
        ]
    }

    /// Rate (per s) at `t` of the new state `now`, written to `rate`.
    pub fn rate(&self, t: f64, now: &[f64], rate: &mut [f64]) {
        let [c0, c1, c2] = self.weights(t);
        for (i, r) in rate.iter_mut().enumerate() {
            *r = c0 * now[i] + c1 * self.v[0][i] + c2 * self.v[1][i];
        }
    }

    /// Records the new state `now` at `t`.
    pub fn push(&mut self, t: f64, now: &[f64]) {
        self.v.swap(0, 1);
        self.v[0].copy_from_slice(now);
        self.t = [t, self.t[0]];
        self.known += 1;
    }
}

/// Whether the loading jumps at t = 0 (a force or a depth already there at t = 0+) on a
/// medium without a dashpot, which then answers at once with its instantaneous modulus.
pub fn jumps_at_start(loading: &Loading, medium: &Rheology) -> bool {
    medium.eta == 0.0
        && match loading {
            Loading::Force(h) => h.force(0.0) > 0.0,
            Loading::Depth(h) => h.depth(0.0) != 0.0,
        }
}

/// Step times: a zero-length step at t = 0 when `jump` (the exponential update assumes the
/// strain varies linearly over a step, so a jump spread over the first step would leave the
/// relaxation high by dt / (2 tau) ever after), then the output times, each interval cut
/// into equal steps no longer than `dt`; the flag marks output times. More than
/// `MAX_STEPS` steps is an error, before anything is allocated.
pub fn step_times(times: &[f64], dt: f64, jump: bool) -> Result<Vec<(f64, bool)>> {
    check_output_times(times)?;
    crate::support::error::check_finite_positive("time step dt", dt)?;
    let mut total = 0.0;
    let mut t0 = 0.0;
    for &t1 in times {
        total += ((t1 - t0) / dt).ceil().max(1.0);
        t0 = t1;
    }
    check_steps(dt, t0, total)?;
    let mut out = Vec::with_capacity(total as usize + 1);
    if jump {
        out.push((0.0, false));
    }
    let mut t0 = 0.0;
    for &t1 in times {
        let m = ((t1 - t0) / dt).ceil().max(1.0) as usize;
        for j in 1..=m {
            let t = if j == m {
                t1
            } else {
                t0 + (t1 - t0) * j as f64 / m as f64
            };
            out.push((t, j == m));
        }
        t0 = t1;
    }
    Ok(out)
}
