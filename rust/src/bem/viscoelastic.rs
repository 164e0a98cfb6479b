//! Linear viscoelastic contact by BEM under force or depth control, unloading included.
//!
//! Each element carries the elastic-equivalent pressure x = K^-1[u] at G = 1 (so that
//! u = K[x]). The stress follows the hereditary law s = integral G(t - s) dx(s), advanced by
//! `Rheology`'s exact exponential update for x quadratic through the step's end and the two
//! states before it (`Rheology::step_after`: linear on the first step, after a jump, after a
//! much shorter step and where a sample of the loading history, at which its rate may
//! change, lies between the three): s_{n+1} = G_eff x_{n+1} + r_n. Each step is then
//! an elastic contact problem with compliance 1/G_eff and separation h - K[r] / G_eff, on
//! the body's operator. Points out of contact relax freely (s = 0), or, under a
//! cohesive-zone law (`run_bem_with`), carry the law's traction at their gap: each step is
//! then the elastic cohesive solve (`crate::bem::cohesive`) at compliance 1/G_eff.

use crate::bem::cohesive::CohesiveStepper;
use crate::bem::contact::{ContactSolver, Target};
use crate::bem::static_contact::load_to_separation;
use crate::bem::viscous::Fields;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::contact_law::ContactLaw;
use crate::model::grid::Grid;
use crate::model::loading::Loading;
use crate::model::medium::rheology::Rheology;
use crate::model::settings::SolverOptions;
use crate::stepping::{jumps_at_start, step_times, Request, Series, Trail};
use crate::support::error::{Error, Result};
use crate::support::monitor::Monitor;

/// BEM: a viscoelastic body under an indenter on `grid`, output as `request` says; also
/// the fields at its field indices: pressure (Pa), deflection u = K[x] (m) and its rate
/// (m/s, zero unless field rates are asked for). The steps solve on the operator of the
/// grid's body; on a periodic cell the depth is the approach from the deflected surface's
/// mean plane (mean separation mean(h) - depth, `periodic::mean_separation`) and a force is
/// the total on the cell.
pub fn run_bem(
    grid: &Grid,
    medium: &Rheology,
    loading: &Loading,
    request: &Request,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields>> {
    run_bem_with(
        grid,
        medium,
        ContactLaw::Hard,
        loading,
        request,
        opts,
        monitor,
    )
}

/// [`run_bem`] under the contact law `law`: hard, or a cohesive zone (Maugis–Dugdale,
/// exponential) under depth or force control, whose steps are those of a
/// `CohesiveStepper` (the zone follows the history; under force control the contact lets
/// go where the tension passes its branch's least force), whose pressure field includes the
/// tension, whose contact counts the elements at zero gap, and which reports the adhesive
/// zone's area (`Series::zone_area`), its jumps and pull-off (`Series::jumps`). Other laws
/// are refused.
pub fn run_bem_with(
    grid: &Grid,
    medium: &Rheology,
    law: ContactLaw,
    loading: &Loading,
    request: &Request,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields>> {
    request.check()?;
    crate::support::memory::check(
        &format!("a {} x {} viscoelastic BEM run", grid.nx, grid.ny),
        run_bytes(
            grid.body,
            grid.nx,
            grid.ny,
            medium.internal(),
            request.fields_at.len(),
            request.field_rates,
            law.is_cohesive(),
        ),
    )?;
    let mut cohesive = match law {
        ContactLaw::Hard => None,
        _ if law.is_cohesive() => Some(CohesiveStepper::new(law, grid.nx * grid.ny)?),
        _ => {
            return Err(Error::InvalidInput(format!(
                "BEM solves hard contact only, or a cohesive law ('maugis_dugdale', 'exponential'); contact '{}' is solved by MDR (method \"mdr\")",
                law.name()
            )))
        }
    };
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let n = grid.nx * grid.ny;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => (0..n)
            .filter(|&i| grid.allowed[i])
            .map(|i| grid.height[i])
            .fold(f64::INFINITY, f64::min),
    };
    let mean_height = grid.height.iter().sum::<f64>() / n as f64;
    let mut depths = Trail::new(vec![start]);
    let field_rates = request.field_rates && !request.fields_at.is_empty();
    let mut strains = field_rates.then(|| Trail::new(vec![0.0; n]));
    let m = medium.internal();
    let mut solver = ContactSolver::new(grid.body.operator(grid.nx, grid.ny, grid.dx)?);
    // x, its increment over the last step and the Prony stresses of every element
    let (mut x, mut rise, mut q) = (vec![0.0; n], vec![0.0; n], vec![0.0; n * m]);
    let mut dt_prev = 0.0;
    let (mut hist, mut k_hist, mut sep) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let mut out = Series::default();
    let (mut t_prev, mut iterations, mut residual) = (0.0, 0usize, 0.0f64);
    let mut warm = false;
    // the pressures of the last two warm solves before the current one, `known` of them
    // usable (after the steps h_prev, h_prev2 of positive length, s)
    let (mut known, mut h_prev, mut h_prev2) = (0usize, 1.0, 1.0);
    let mut contact_count = 0;
    let (mut p_prev, mut p_prev2, mut guess) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    for (s, &(t, output)) in steps.iter().enumerate() {
        // the strain is quadratic through the last three states only where the load is
        // smooth over them: a rate that changes at a sample of the history (a load reversed)
        // kinks every element's history there
        let smooth = loading.linear_between(t_prev - dt_prev, t);
        let rule = medium.step_after(t - t_prev, if smooth { dt_prev } else { 0.0 });
        for i in 0..n {
            hist[i] = rule.history_after(x[i], rise[i], &q[i * m..(i + 1) * m]);
        }
        solver.operator().apply(&hist, &mut k_hist);
        for i in 0..n {
            sep[i] = grid.height[i] - k_hist[i] / rule.g_eff;
        }
        let target = match loading {
            Loading::Depth(h) => {
                grid.body.check_depth(mean_height, h.depth(t))?;
                Target::Depth(h.depth(t))
            }
            Loading::Force(h) => Target::Force(h.force(t)),
        };
        let mut zone = 0;
        let (depth, force) = match target {
            _ if cohesive.is_some() => {
                let c = cohesive.as_mut().expect("matched: a cohesive law");
                let r = c.step(
                    &mut solver,
                    &sep,
                    &grid.allowed,
                    1.0 / rule.g_eff,
                    t,
                    target,
                    grid.body.loads_depth_by_force(),
                    opts,
                    monitor,
                )?;
                iterations += r.iterations;
                residual = residual.max(r.residual);
                zone = r.contact_count + r.zone_count;
                (r.depth, r.force)
            }
            Target::Force(f) if f <= 0.0 => {
                // separated: the indenter rests where it touches the relaxed surface
                let lowest = (0..n)
                    .filter(|&i| grid.allowed[i])
                    .map(|i| sep[i])
                    .fold(f64::INFINITY, f64::min);
                solver.clear_pressure();
                (warm, known) = (false, 0);
                (lowest, 0.0)
            }
            _ => {
                if warm {
                    // start from the pressure extrapolated over the step (Lagrange) through
                    // the last solves: quadratic once three are known, an O(dt^3) start on
                    // a smooth path
                    let [w0, w1, w2] = extrapolation(t - t_prev, h_prev, h_prev2, known);
                    let p = solver.pressure();
                    for i in 0..n {
                        guess[i] = (w0 * p[i] + w1 * p_prev[i] + w2 * p_prev2[i]).max(0.0);
                    }
                    std::mem::swap(&mut p_prev, &mut p_prev2);
                    p_prev.copy_from_slice(p);
                    solver.set_pressure(&guess)?;
                }
                let mut started = warm;
                if let (false, Target::Depth(d), true) =
                    (warm, target, grid.body.loads_depth_by_force())
                {
                    let mean_sep = sep.iter().sum::<f64>() / n as f64;
                    iterations += load_to_separation(
                        &mut solver,
                        &sep,
                        &grid.allowed,
                        grid.dx,
                        1.0 / rule.g_eff,
                        mean_sep - d,
                        opts,
                        monitor,
                    )?;
                    started = true;
                }
                let r = solver.solve(
                    &sep,
                    &grid.allowed,
                    1.0 / rule.g_eff,
                    target,
                    started,
                    0.0,
                    opts,
                    monitor,
                )?;
                iterations += r.iterations;
                residual = residual.max(r.residual);
                known = if warm && t > t_prev {
                    (known + 1).min(2)
                } else {
                    0
                };
                // a shrinking contact's pressure drops to zero at a receding edge, where a
                // parabola through three solves overshoots: a line then
                if r.contact_count < contact_count {
                    known = known.min(1);
                }
                contact_count = r.contact_count;
                warm = r.contact_count > 0;
                (h_prev, h_prev2) = (t - t_prev, h_prev);
                (r.depth, r.force)
            }
        };
        let compression = solver.pressure();
        let p = match &cohesive {
            Some(c) => c.pressure(),
            None => compression,
        };
        let mut count = 0;
        for i in 0..n {
            let x_new = (p[i] - hist[i]) / rule.g_eff;
            rule.advance_after(x[i], x_new, rise[i], &mut q[i * m..(i + 1) * m]);
            rise[i] = x_new - x[i];
            x[i] = x_new;
            count += usize::from(compression[i] > 0.0);
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
            let length = 2.0 * (area / std::f64::consts::PI).sqrt();
            out.contact_length.push(length);
            out.velocity.push(rate[0]);
            out.iterations.push(iterations);
            out.residual.push(residual);
            let contact: Vec<bool> = compression.iter().map(|&v| v > 0.0).collect();
            // a cohesive zone cut by the grid's edge is as wrong as a cut contact
            let reach: Vec<bool> = match &cohesive {
                Some(c) => contact
                    .iter()
                    .zip(c.gap())
                    .map(|(&k, &g)| k || g <= law.range())
                    .collect(),
                None => contact.clone(),
            };
            out.at_edge.push(grid.touches_edge(&reach));
            out.area.push(area);
            if cohesive.is_some() {
                out.zone_area.push(zone as f64 * grid.dx * grid.dx);
            }
            out.saturated
                .push(grid.covers(0.25 * std::f64::consts::PI * length * length));
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
                out.fields.push(Fields {
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
        // a zero-length step (the jump at t = 0) leaves no smooth history before it
        dt_prev = t - t_prev;
        t_prev = t;
    }
    out.solves = out.steps;
    out.jumps = cohesive.map(|c| c.jumps().clone());
    Ok(out)
}

/// The memory (bytes) [`run_bem_with`] reaches on an `nx` x `ny` grid on `body`, the grid
/// itself aside: the whole grid's operator (`Body::operator_bytes`) and contact solver
/// (`ContactSolver::BYTES_PER_ELEMENT`); per element the state x and the medium's
/// `internal` variables (8 each), its last increment, the history, its deflection and the
/// separation, the last two pressures and the guess (56), with `field_rates` the trail of
/// two earlier states (16), a cohesive zone's buffers (`cohesive`, 40) and 24 per field
/// (pressure, velocity, deflection) of the `fields` asked for. The check before a run and
/// the measured peak (`tests/test_memory.py`) use it.
pub fn run_bytes(
    body: crate::model::body::Body,
    nx: usize,
    ny: usize,
    internal: usize,
    fields: usize,
    field_rates: bool,
    cohesive: bool,
) -> f64 {
    let solver = ContactSolver::<crate::halfspace::body::Operator>::BYTES_PER_ELEMENT;
    let rates = if field_rates { 16.0 } else { 0.0 };
    let zone = if cohesive { 40.0 } else { 0.0 };
    let per_element =
        solver + 8.0 * (1 + internal) as f64 + 56.0 + rates + zone + 24.0 * fields as f64;
    body.operator_bytes(nx, ny) + per_element * (nx * ny) as f64
}

/// Weights (w0, w1, w2) of the pressures at the last three solves (times t_k, t_k - h1,
/// t_k - h1 - h2; s) in the start of a step of length `step` (s) from t_k: the Lagrange
/// polynomial through the last `known` + 1 of them (0: the last solve's pressure; 1: the
/// line through two; 2: the parabola through three, an O(step^3) start on a smooth path).
fn extrapolation(step: f64, h1: f64, h2: f64, known: usize) -> [f64; 3] {
    match known {
        0 => [1.0, 0.0, 0.0],
        1 => [1.0 + step / h1, -step / h1, 0.0],
        _ => {
            let (a, b) = (step + h1, step + h1 + h2);
            [
                a * b / (h1 * (h1 + h2)),
                -step * b / (h1 * h2),
                step * a / (h2 * (h1 + h2)),
            ]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The weights reproduce every polynomial of degree `known` through the solves' times
    /// exactly at the next step, on uneven steps too (and sum to 1).
    #[test]
    fn extrapolation_is_exact_on_polynomials_of_its_degree() {
        let f = |t: f64, degree: usize| match degree {
            0 => 2.5,
            1 => 2.5 - 1.5 * t,
            _ => 2.5 - 1.5 * t + 0.75 * t * t,
        };
        for (step, h1, h2) in [(0.1, 0.1, 0.1), (0.3, 0.1, 0.05), (0.02, 0.4, 1.3)] {
            let tk = 1.7;
            for known in 0..=2 {
                let w = extrapolation(step, h1, h2, known);
                let at = [tk, tk - h1, tk - h1 - h2];
                let guess: f64 = (0..3).map(|k| w[k] * f(at[k], known)).sum();
                let exact = f(tk + step, known);
                assert!((guess - exact).abs() < 1e-12, "{known} {step} {h1} {h2}");
                assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
            }
        }
    }
}
