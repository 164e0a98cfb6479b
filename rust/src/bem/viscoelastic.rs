//! Linear viscoelastic contact by BEM and MDR under force or depth control, unloading
//! included.
//!
//! Both methods carry a strain-like history variable per point: MDR the element
//! displacement w; BEM the elastic-equivalent pressure x = K^-1[u] at G = 1 (so that
//! u = K[x]). The stress follows the hereditary law s = integral G(t - s) dx(s), advanced by
//! `Rheology`'s exact exponential update: s_{n+1} = G_eff x_{n+1} + r_n. Each step is then
//! an elastic contact problem with modulus G_eff: for MDR with the effective profile
//! g_i - r_i / G_eff (an element touches where the indenter reaches its freely relaxed
//! surface, and leaves when its force would turn tensile); for BEM with compliance 1/G_eff
//! and separation h - K[r] / G_eff. Points out of contact relax freely (s = 0).

use crate::bem::contact::{ContactSolver, Target};
use crate::bem::viscous::Fields;
use crate::halfspace::operator::{FftOperator, SurfaceOperator};
use crate::halfspace::periodic::PeriodicOperator;
use crate::mdr::foundation::{depth_on_sorted, prefix_sums, Fields1D};
use crate::model::grid::Grid;
use crate::model::loading::{check_output_times, Loading};
use crate::model::medium::rheology::Rheology;
use crate::model::settings::check_steps;
use crate::model::settings::SolverOptions;
use crate::support::error::{check_positive, Error, Result};
use crate::support::monitor::Monitor;

/// Time series of a viscoelastic run, one entry per output time.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
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
    /// Contact patches, 4-connected components of the contact (BEM).
    pub patches: Vec<usize>,
    /// Mean surface deflection over the grid (m) (BEM).
    pub mean_deflection: Vec<f64>,
    /// Penetration rate dd/dt (m/s): the second-order backward difference of the depth over
    /// the last three step times (first order on the first two steps, where the state at
    /// t = 0 may precede a jump of the load).
    pub velocity: Vec<f64>,
    /// Solver iterations per output interval (BEM).
    pub iterations: Vec<usize>,
    /// Largest final relative residual of the contact solves per output interval (BEM).
    pub residual: Vec<f64>,
    /// Whether the contact reached the outermost ring of the grid (BEM).
    pub at_edge: Vec<bool>,
    /// Time steps taken.
    pub steps: usize,
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
    fn check(&self) -> Result<()> {
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
struct Trail {
    t: [f64; 2],
    v: [Vec<f64>; 2],
    known: usize,
}

impl Trail {
    /// A trail that starts from `start` at t = 0.
    fn new(start: Vec<f64>) -> Self {
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
    fn rate(&self, t: f64, now: &[f64], rate: &mut [f64]) {
        let [c0, c1, c2] = self.weights(t);
        for (i, r) in rate.iter_mut().enumerate() {
            *r = c0 * now[i] + c1 * self.v[0][i] + c2 * self.v[1][i];
        }
    }

    /// Records the new state `now` at `t`.
    fn push(&mut self, t: f64, now: &[f64]) {
        self.v.swap(0, 1);
        self.v[0].copy_from_slice(now);
        self.t = [t, self.t[0]];
        self.known += 1;
    }
}

/// Whether the loading jumps at t = 0 (a force or a depth already there at t = 0+) on a
/// medium without a dashpot, which then answers at once with its instantaneous modulus.
fn jumps_at_start(loading: &Loading, medium: &Rheology) -> bool {
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
fn step_times(times: &[f64], dt: f64, jump: bool) -> Result<Vec<(f64, bool)>> {
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

/// MDR: a viscoelastic foundation (elements 4 dx times the medium) under a 1D profile `g`
/// (m, spacing dx m), output as `request` says; also the 1D fields at its field indices:
/// displacements w (m), line load 4 s (N/m, s the element stress) and dw/dt (m/s, zero
/// unless field rates are asked for).
pub fn run_mdr(
    g: &[f64],
    dx: f64,
    medium: &Rheology,
    loading: &Loading,
    request: &Request,
    monitor: &mut dyn Monitor,
) -> Result<(Series, Vec<Fields1D>)> {
    check_positive("element spacing dx", dx)?;
    let n = g.len();
    if n == 0 {
        return Err(Error::InvalidInput("the 1D profile has no elements".into()));
    }
    request.check()?;
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => g.iter().copied().fold(f64::INFINITY, f64::min),
    };
    let mut depths = Trail::new(vec![start]);
    let field_rates = request.field_rates && !request.fields_at.is_empty();
    let mut displacements = field_rates.then(|| Trail::new(vec![0.0; n]));
    let mut fields = vec![];
    let m = medium.internal();
    let (mut w, mut q) = (vec![0.0; n], vec![0.0; n * m]);
    let mut surface = vec![0.0; n];
    let mut sorted = vec![0.0; n];
    let mut prefix = Vec::with_capacity(n + 1);
    let mut out = Series::default();
    let mut t_prev = 0.0;
    let mut rule = medium.step(1.0);
    let mut rule_dt = f64::NAN;
    for (s, &(t, output)) in steps.iter().enumerate() {
        let h = t - t_prev;
        if h != rule_dt {
            rule = medium.step(h);
            rule_dt = h;
        }
        let c = 4.0 * dx * rule.g_eff;
        for i in 0..n {
            // where the indenter meets the element's freely relaxed surface
            surface[i] = g[i] - rule.history(w[i], &q[i * m..(i + 1) * m]) / rule.g_eff;
        }
        sorted.copy_from_slice(&surface);
        sorted.sort_unstable_by(f64::total_cmp);
        prefix_sums(&sorted, &mut prefix);
        let (depth, force) = match loading {
            Loading::Depth(hist) => {
                let d = hist.depth(t);
                let k = sorted.partition_point(|&v| v < d);
                (d, c * (k as f64 * d - prefix[k]))
            }
            Loading::Force(hist) => {
                let f = hist.force(t);
                (depth_on_sorted(&sorted, &prefix, f / c).0, f)
            }
        };
        let mut count = 0;
        for i in 0..n {
            let w_new = if depth > surface[i] {
                count += 1;
                depth - g[i]
            } else {
                surface[i] - g[i]
            };
            rule.advance(w[i], w_new, &mut q[i * m..(i + 1) * m]);
            w[i] = w_new;
        }
        if h == 0.0 {
            // the jump at t = 0: rates start from the state just after it
            depths = Trail::new(vec![depth]);
            displacements = displacements.map(|_| Trail::new(w.clone()));
        }
        let mut rate = [0.0];
        depths.rate(t, &[depth], &mut rate);
        if output {
            let k = out.t.len();
            out.t.push(t);
            out.depth.push(depth);
            out.force.push(force);
            out.contact_length.push(count as f64 * dx);
            out.velocity.push(rate[0]);
            out.iterations.push(0);
            if request.fields_at.contains(&k) {
                let line_load = (0..n)
                    .map(|i| 4.0 * rule.g_eff * (depth - surface[i]).max(0.0))
                    .collect();
                let mut velocity = vec![0.0; n];
                if let Some(trail) = &displacements {
                    trail.rate(t, &w, &mut velocity);
                }
                fields.push(Fields1D {
                    step: k,
                    displacement: w.clone(),
                    line_load,
                    velocity,
                });
            }
        }
        if h > 0.0 {
            depths.push(t, &[depth]);
            if let Some(trail) = &mut displacements {
                trail.push(t, &w);
            }
        }
        out.steps = s + 1;
        monitor.progress("time steps", s + 1, steps.len())?;
        t_prev = t;
    }
    Ok((out, fields))
}

/// BEM: a viscoelastic half-space under an indenter on `grid`, output as `request` says;
/// also the fields at its field indices: pressure (Pa), deflection u = K[x] (m) and its
/// rate (m/s, zero unless field rates are asked for). A periodic cell (`grid.periodic`)
/// runs on the periodic operator (`run_bem_on`).
pub fn run_bem(
    grid: &Grid,
    medium: &Rheology,
    loading: &Loading,
    request: &Request,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<(Series, Vec<Fields>)> {
    if grid.periodic {
        let op = PeriodicOperator::new(grid.nx, grid.ny, grid.dx)?;
        return run_bem_on(op, grid, medium, loading, request, opts, monitor);
    }
    let op = FftOperator::new(grid.nx, grid.ny, grid.dx)?;
    run_bem_on(op, grid, medium, loading, request, opts, monitor)
}

/// `run_bem` with the surface operator `op` of `grid` (same size and element side): the
/// non-periodic `FftOperator`, or a `PeriodicOperator` for a periodic cell, where the depth
/// is the approach from the deflected surface's mean plane (mean separation
/// mean(h) - depth, `periodic::mean_separation`) and a force is the total on the cell.
pub fn run_bem_on<O: SurfaceOperator>(
    op: O,
    grid: &Grid,
    medium: &Rheology,
    loading: &Loading,
    request: &Request,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<(Series, Vec<Fields>)> {
    if (op.nx(), op.ny()) != (grid.nx, grid.ny) || op.dx() != grid.dx {
        return Err(Error::InvalidInput(format!(
            "the operator's {} x {} grid of side {} m differs from the {} x {} grid of side {} m",
            op.nx(),
            op.ny(),
            op.dx(),
            grid.nx,
            grid.ny,
            grid.dx
        )));
    }
    request.check()?;
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let n = grid.nx * grid.ny;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => (0..n)
            .filter(|&i| grid.allowed[i])
            .map(|i| grid.height[i])
            .fold(f64::INFINITY, f64::min),
    };
    let mut depths = Trail::new(vec![start]);
    let field_rates = request.field_rates && !request.fields_at.is_empty();
    let mut strains = field_rates.then(|| Trail::new(vec![0.0; n]));
    let mut fields = vec![];
    let m = medium.internal();
    let mut solver = ContactSolver::new(op);
    let (mut x, mut q) = (vec![0.0; n], vec![0.0; n * m]);
    let (mut hist, mut k_hist, mut sep) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut out = Series::default();
    let (mut t_prev, mut iterations, mut residual) = (0.0, 0usize, 0.0f64);
    let mut warm = false;
    let (mut extrapolate, mut h_prev) = (false, 1.0);
    let (mut p_prev, mut guess) = (vec![0.0; n], vec![0.0; n]);
    for (s, &(t, output)) in steps.iter().enumerate() {
        let rule = medium.step(t - t_prev);
        for i in 0..n {
            hist[i] = rule.history(x[i], &q[i * m..(i + 1) * m]);
        }
        solver.operator().apply(&hist, &mut k_hist);
        for i in 0..n {
            sep[i] = grid.height[i] - k_hist[i] / rule.g_eff;
        }
        let target = match loading {
            Loading::Depth(h) => Target::Depth(h.depth(t)),
            Loading::Force(h) => Target::Force(h.force(t)),
        };
        let (depth, force) = match target {
            Target::Force(f) if f <= 0.0 => {
                // separated: the indenter rests where it touches the relaxed surface
                let lowest = (0..n)
                    .filter(|&i| grid.allowed[i])
                    .map(|i| sep[i])
                    .fold(f64::INFINITY, f64::min);
                solver.clear_pressure();
                (warm, extrapolate) = (false, false);
                (lowest, 0.0)
            }
            _ => {
                if warm {
                    // start from the pressure extrapolated linearly over the step (an
                    // O(dt^2) start once two steps are known)
                    let ratio = if extrapolate {
                        (t - t_prev) / h_prev
                    } else {
                        0.0
                    };
                    let p = solver.pressure();
                    for i in 0..n {
                        guess[i] = (p[i] + ratio * (p[i] - p_prev[i])).max(0.0);
                    }
                    p_prev.copy_from_slice(p);
                    solver.set_pressure(&guess)?;
                }
                let r = solver.solve(
                    &sep,
                    &grid.allowed,
                    1.0 / rule.g_eff,
                    target,
                    warm,
                    0.0,
                    opts,
                    monitor,
                )?;
                iterations += r.iterations;
                residual = residual.max(r.residual);
                extrapolate = warm && t > t_prev;
                warm = r.contact_count > 0;
                h_prev = t - t_prev;
                (r.depth, r.force)
            }
        };
        let p = solver.pressure();
        let mut count = 0;
        for i in 0..n {
            let x_new = (p[i] - hist[i]) / rule.g_eff;
            rule.advance(x[i], x_new, &mut q[i * m..(i + 1) * m]);
            x[i] = x_new;
            count += usize::from(p[i] > 0.0);
        }
        if t == t_prev {
            // the jump at t = 0: rates start from the state just after it
            depths = Trail::new(vec![depth]);
            strains = strains.map(|_| Trail::new(x.clone()));
        }
        let mut rate = [0.0];
        depths.rate(t, &[depth], &mut rate);
        if output {
            let k = out.t.len();
            let area = count as f64 * grid.dx * grid.dx;
            out.t.push(t);
            out.depth.push(depth);
            out.force.push(force);
            out.contact_length
                .push(2.0 * (area / std::f64::consts::PI).sqrt());
            out.velocity.push(rate[0]);
            out.iterations.push(iterations);
            out.residual.push(residual);
            let contact: Vec<bool> = p.iter().map(|&v| v > 0.0).collect();
            out.at_edge.push(grid.touches_edge(&contact));
            out.area.push(area);
            out.patches.push(grid.patches(&contact));
            (iterations, residual) = (0, 0.0);
            if request.fields_at.contains(&k) {
                let pressure = p.to_vec();
                let mut deflection = vec![0.0; n];
                solver.operator().apply(&x, &mut deflection);
                let mut velocity = vec![0.0; n];
                if let Some(trail) = &strains {
                    trail.rate(t, &x, &mut hist);
                    solver.operator().apply(&hist, &mut velocity);
                }
                fields.push(Fields {
                    step: k,
                    pressure,
                    velocity,
                    deflection,
                });
            }
            solver.operator().apply(&x, &mut k_hist);
            out.mean_deflection
                .push(k_hist.iter().sum::<f64>() / n as f64);
        }
        if t > t_prev {
            depths.push(t, &[depth]);
            if let Some(trail) = &mut strains {
                trail.push(t, &x);
            }
        }
        out.steps = s + 1;
        monitor.progress("time steps", s + 1, steps.len())?;
        t_prev = t;
    }
    Ok((out, fields))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::loading::{DepthHistory, ForceHistory};
    use crate::support::monitor::Silent;

    fn parabola(n: usize, c: f64, half: f64) -> (Vec<f64>, f64) {
        let dx = 2.0 * half / n as f64;
        (
            (0..n)
                .map(|i| {
                    let x = (i as f64 + 0.5) * dx - half;
                    2.0 * c * x * x
                })
                .collect(),
            dx,
        )
    }

    /// Creep of a paraboloid under a step force on a standard solid (Lee–Radok):
    /// d^(3/2) = 3 F J(t) / (16 sqrt R), J(t) = 1/G_inf + (1/G0 - 1/G_inf) exp(-G_inf t / (G0 tau)).
    #[test]
    fn mdr_creep_of_a_standard_solid_follows_lee_radok() {
        let (g_inf, g1, tau, c, f) = (1.0, 3.0, 0.5, 1.0, 1.0);
        let medium = Rheology::new(g_inf, vec![(g1, tau)], 0.0).unwrap();
        let (g, dx) = parabola(8001, c, 1.5);
        let times: Vec<f64> = (0..40)
            .map(|k| 1e-7 * (5e7f64).powf(k as f64 / 39.0))
            .collect();
        let loading = Loading::Force(ForceHistory::constant(f).unwrap());
        let request = Request {
            times: &times,
            dt: 1e-2,
            fields_at: &[],
            field_rates: false,
        };
        let (s, _) = run_mdr(&g, dx, &medium, &loading, &request, &mut Silent).unwrap();
        let g0 = g_inf + g1;
        let r = 1.0 / (2.0 * c);
        for (t, d) in s.t.iter().zip(&s.depth) {
            let j = 1.0 / g_inf + (1.0 / g0 - 1.0 / g_inf) * (-g_inf * t / (g0 * tau)).exp();
            let exact = (3.0 * f * j / (16.0 * r.sqrt())).powf(2.0 / 3.0);
            assert!((d / exact - 1.0).abs() < 2e-4, "t={t}: {d} vs {exact}");
        }
    }

    /// Depth held after a ramp on a Maxwell body: the force relaxes as exp(-t / tau) while
    /// the contact stays (Lee–Radok with fixed contact).
    #[test]
    fn mdr_force_relaxes_under_a_held_depth() {
        let (g, tau) = (2.0, 0.3);
        let medium = Rheology::new(0.0, vec![(g, tau)], 0.0).unwrap();
        let (prof, dx) = parabola(4001, 1.0, 1.0);
        let hist = DepthHistory::piecewise_linear(vec![0.0, 1e-6], vec![0.0, 0.2]).unwrap();
        let times = [1e-6, 0.1, 0.5, 1.0];
        let request = Request {
            times: &times,
            dt: 1e-3,
            fields_at: &[],
            field_rates: false,
        };
        let (s, _) = run_mdr(
            &prof,
            dx,
            &medium,
            &Loading::Depth(hist),
            &request,
            &mut Silent,
        )
        .unwrap();
        for (t, f) in s.t.iter().zip(&s.force).skip(1) {
            let expected = s.force[0] * (-(t - 1e-6) / tau).exp();
            assert!((f / expected - 1.0).abs() < 1e-6, "t={t}");
        }
    }
}
