//! BEM for a viscous half-space (shear viscosity eta, Pa s) under a force history.
//!
//! Written for the impulse P = integral of p dt: the deflection is u = K[P] / eta, so the
//! state at each output time is an elastic contact problem (modulus eta) for the impulse
//! increment dP >= 0 with total dI = integral of F over the step and separation h + u_n.
//! While the contact grows (always, for F >= 0 on a viscous body) this implicit step has no
//! time-discretisation error (Lee–Radok), so a run costs one contact solve per output time.

use crate::bem::contact::{ContactSolver, Target};
use crate::bem::window::SolverPool;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::grid::Grid;
use crate::model::loading::{check_output_times, ForceHistory};
use crate::model::settings::ExplicitControl;
use crate::model::settings::SolverOptions;
use crate::stepping::Series;
use crate::support::error::{check_len, check_positive, Error, Result};
use crate::support::monitor::Monitor;

/// Surface fields at one output time.
#[derive(Debug, Clone, PartialEq)]
pub struct Fields {
    /// Index of the output time.
    pub step: usize,
    /// Contact pressure (Pa) at that instant.
    pub pressure: Vec<f64>,
    /// Surface deflection rate du/dt (m/s).
    pub velocity: Vec<f64>,
    /// Surface deflection u (m).
    pub deflection: Vec<f64>,
}

/// What a viscous BEM run computes besides depth and contact area.
#[derive(Debug, Clone, PartialEq)]
pub struct ViscousRequest {
    /// Output times (s), > 0 and increasing.
    pub times: Vec<f64>,
    /// Compute the instantaneous penetration rate and stiffness-based contact length.
    pub rates: bool,
    /// Output-time indices at which to build pressure and velocity fields.
    pub fields_at: Vec<usize>,
    /// Estimated upper bounds of the depth at the output times (m), e.g. 1.05 times MDR's
    /// (one per output time, non-finite where there is none; empty: none at all). A step's
    /// solve runs on the window the smaller of its bound and the linear extrapolation
    /// implies, and again on a larger window if the depth exceeds it, so the result never
    /// depends on them. Without a bound the first step uses the whole grid.
    pub depth_bounds: Vec<f64>,
}

fn check_request(request: &ViscousRequest, eta: f64) -> Result<()> {
    check_positive("viscosity eta", eta)?;
    check_output_times(&request.times)?;
    if !request.depth_bounds.is_empty() {
        check_len(
            "depth bounds",
            request.depth_bounds.len(),
            request.times.len(),
        )?;
    }
    match request
        .fields_at
        .iter()
        .find(|&&k| k >= request.times.len())
    {
        Some(k) => Err(Error::InvalidInput(format!(
            "field output index {k} is out of range for {} output times",
            request.times.len()
        ))),
        None => Ok(()),
    }
}

/// The flat-punch solution of a contact set: unit pressure (K p = 1 on the set, G = 1) and
/// its stiffness sum(p) dA (m).
struct Punch {
    p_unit: Vec<f64>,
    k_unit: f64,
}

impl Punch {
    /// No set solved yet.
    fn new() -> Self {
        Punch {
            p_unit: Vec::new(),
            k_unit: 0.0,
        }
    }

    /// Solves the unit punch on `set` (started from the current solution when `warm` and
    /// it has the set's length), reusing this punch's buffer; returns (iterations,
    /// residual).
    fn solve<O: SurfaceOperator>(
        &mut self,
        solver: &mut ContactSolver<O>,
        set: &[bool],
        warm: bool,
        opts: &SolverOptions,
        monitor: &mut dyn Monitor,
    ) -> Result<(usize, f64)> {
        let area_el = solver.operator().dx().powi(2);
        let start = (warm && self.p_unit.len() == set.len()).then_some(self.p_unit.as_slice());
        let (its, res) = solver.unit_punch(set, start, opts, monitor)?;
        self.p_unit.clear();
        self.p_unit.extend_from_slice(solver.pressure());
        self.k_unit = self.p_unit.iter().sum::<f64>() * area_el;
        Ok((its, res))
    }

    /// Pressure (Pa) and surface velocity (m/s) under `force` (N) on a body of viscosity eta.
    fn fields<O: SurfaceOperator>(
        &self,
        solver: &mut ContactSolver<O>,
        force: f64,
        eta: f64,
    ) -> (Vec<f64>, Vec<f64>) {
        let pressure: Vec<f64> = self
            .p_unit
            .iter()
            .map(|v| v * force / self.k_unit)
            .collect();
        let mut velocity = vec![0.0; pressure.len()];
        solver.operator().apply(&pressure, &mut velocity);
        velocity.iter_mut().for_each(|v| *v /= eta);
        (pressure, velocity)
    }
}

impl Series<Fields> {
    /// Appends one output time (`force` in N, `deflection` in m on the grid).
    #[allow(clippy::too_many_arguments)]
    fn record(
        &mut self,
        grid: &Grid,
        t: f64,
        force: f64,
        depth: f64,
        contact: &[bool],
        deflection: &[f64],
        rate: Option<(f64, f64)>,
        iterations: usize,
        residual: f64,
    ) {
        let area = contact.iter().filter(|&&c| c).count() as f64 * grid.dx * grid.dx;
        self.t.push(t);
        self.depth.push(depth);
        self.force.push(force);
        self.area.push(area);
        self.saturated.push(grid.covers(area));
        self.contact_length
            .push(2.0 * (area / std::f64::consts::PI).sqrt());
        self.velocity.push(rate.map_or(f64::NAN, |r| r.0));
        self.stiffness_length.push(rate.map_or(f64::NAN, |r| r.1));
        self.iterations.push(iterations);
        self.residual.push(residual);
        self.at_edge.push(grid.touches_edge(contact));
        self.patches.push(grid.patches(contact));
        self.mean_deflection
            .push(deflection.iter().sum::<f64>() / deflection.len() as f64);
    }
}

/// The memory (bytes) a viscous BEM run of an `nx` x `ny` grid on `body` reaches, the grid
/// itself aside: the whole grid's operator (`Body::operator_bytes`) and contact solver
/// (`ContactSolver::BYTES_PER_ELEMENT`), 48 per element of state (separation, accumulated
/// and incremental deflection, pressure step, contact, a window's copies) and 24 per field
/// (pressure, velocity, deflection) of the `fields` asked for; `pooled` (the implicit
/// stepping's `SolverPool`) adds the windows' kernel table (8 per element) and the solvers
/// of its smaller windows, which hold at most half the whole grid's operator and solver
/// (windows of other padded sizes than the whole grid's). The check before a run and the
/// measured peak (`tests/test_memory.py`) use it.
pub fn run_bytes(
    body: crate::model::body::Body,
    nx: usize,
    ny: usize,
    fields: usize,
    pooled: bool,
) -> f64 {
    let elements = (nx * ny) as f64;
    let whole = body.operator_bytes(nx, ny)
        + ContactSolver::<crate::halfspace::body::Operator>::BYTES_PER_ELEMENT * elements;
    let pool = if pooled && body.windows() {
        0.5 * whole + 8.0 * elements
    } else {
        0.0
    };
    whole + pool + (48.0 + 24.0 * fields as f64) * elements
}

/// Runs the implicit impulse stepping of a viscous half-space (viscosity `eta`, Pa s) under
/// the force `history` (N over s); depths (m), areas (m^2) and rates (m/s) per output time.
///
/// Each step solves on a window that holds every element that can touch: the contact lies
/// where the separation h + u_n plus the step's own deflection is at most the new depth, so
/// a window covering {h + u_n + u_low <= d_bound} is exact whenever the solve returns
/// d <= d_bound (checked; otherwise the step is repeated on a larger window), u_low being a
/// lower bound of the step's deflection (`Window::around_contact`). d_bound is the smaller
/// of the request's depth bound for the step and the depth extrapolated linearly in the
/// impulse (an upper bound while the contact grows); a first step without a bound uses the
/// whole grid. On a body without windows (a periodic cell, `grid` one period) every step
/// solves the whole cell, the force is the total on the cell (N), and depths are approaches
/// from the deflected surface's mean plane (mean separation mean(h) - depth).
pub fn run_implicit(
    grid: &Grid,
    eta: f64,
    history: &ForceHistory,
    request: &ViscousRequest,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields>> {
    check_request(request, eta)?;
    crate::support::memory::check(
        &format!("a {} x {} viscous BEM run", grid.nx, grid.ny),
        run_bytes(grid.body, grid.nx, grid.ny, request.fields_at.len(), true),
    )?;
    let mut pool = SolverPool::new(grid.body, grid.nx, grid.ny, grid.dx)?;
    let n = grid.nx * grid.ny;
    let mut full = ContactSolver::new(pool.whole()?);
    let mut sep = grid.height.clone();
    let mut u_acc = vec![0.0; n];
    let mut u_inc = vec![0.0; n];
    let mut d_p = vec![0.0; n];
    let mut contact = vec![false; n];
    let (mut sep_w, mut allowed_w, mut start_w) = (vec![], vec![], vec![]);
    let mut punch = Punch::new();
    let mut out = Series::default();
    let (mut t_prev, mut depth, mut depth_prev) = (0.0, 0.0, 0.0);
    let mut impulse_prev = 0.0;
    let total = request.times.len();
    for (k, &t) in request.times.iter().enumerate() {
        let impulse = history.impulse(t) - history.impulse(t_prev);
        let (mut iterations, mut residual) = (0, 0.0);
        if impulse > 0.0 {
            let warm = contact.iter().any(|&c| c);
            let extrapolated = if warm {
                depth + 1.05 * (depth - depth_prev) * impulse / impulse_prev
            } else {
                f64::INFINITY
            };
            let estimate = request.depth_bounds.get(k).copied().unwrap_or(f64::NAN);
            let mut bound = if estimate.is_finite() {
                estimate.min(extrapolated)
            } else {
                extrapolated
            };
            let (window, s) = loop {
                let win = pool.contact_window(&sep, &grid.allowed, bound, impulse / eta);
                win.gather(&sep, &mut sep_w);
                win.gather(&grid.allowed, &mut allowed_w);
                let solver = pool.get(win.wx, win.wy)?;
                if warm {
                    win.gather(&d_p, &mut start_w);
                    solver.set_pressure(&start_w)?;
                }
                let s = solver.solve(
                    &sep_w,
                    &allowed_w,
                    1.0 / eta,
                    Target::Force(impulse),
                    warm,
                    history.impulse(t),
                    opts,
                    monitor,
                )?;
                iterations += s.iterations;
                residual = s.residual;
                out.solves += 1;
                if s.depth <= bound || win.is_full() {
                    break (win, s);
                }
                bound = s.depth + (s.depth - depth);
            };
            depth_prev = depth;
            depth = s.depth;
            impulse_prev = impulse;
            window.scatter(pool.get(window.wx, window.wy)?.pressure(), &mut d_p);
            full.operator().apply(&d_p, &mut u_inc);
            for i in 0..n {
                u_acc[i] += u_inc[i] / eta;
                sep[i] = grid.height[i] + u_acc[i];
                contact[i] = d_p[i] > 0.0;
            }
        }
        let want_fields = request.fields_at.contains(&k);
        let force = history.force(t);
        let mut rate = None;
        if (request.rates || want_fields) && contact.iter().any(|&c| c) {
            let win = pool.set_window(&contact);
            win.gather(&contact, &mut allowed_w);
            let (its, res) =
                punch.solve(pool.get(win.wx, win.wy)?, &allowed_w, false, opts, monitor)?;
            out.solves += 1;
            iterations += its;
            residual = f64::max(residual, res);
            rate = Some((force / (eta * punch.k_unit), punch.k_unit / 4.0));
            if want_fields {
                let mut p_unit = vec![0.0; n];
                win.scatter(&punch.p_unit, &mut p_unit);
                let full_punch = Punch {
                    p_unit,
                    k_unit: punch.k_unit,
                };
                let (pressure, velocity) = full_punch.fields(&mut full, force, eta);
                out.fields.push(Fields {
                    step: k,
                    pressure,
                    velocity,
                    deflection: u_acc.clone(),
                });
            }
        }
        out.record(
            grid,
            t,
            history.force(t),
            depth,
            &contact,
            &u_acc,
            rate,
            iterations,
            residual,
        );
        out.steps += 1;
        t_prev = t;
        monitor.progress("time steps", k + 1, total)?;
    }
    Ok(out)
}

/// Runs the paper's explicit loop on a viscous half-space (`eta` in Pa s, `history` in N
/// over s): the surface velocity of the current contact set (a flat-punch solve), an
/// explicit Euler step of depth and deflection, contact growth where the gap closed; the
/// flat punch is re-solved only when the contact area grew by more than `ctrl.area_change`.
/// Its error is first order in the step and carries the singular start.
pub fn run_explicit(
    grid: &Grid,
    eta: f64,
    history: &ForceHistory,
    request: &ViscousRequest,
    ctrl: &ExplicitControl,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields>> {
    check_request(request, eta)?;
    ctrl.validate()?;
    crate::support::memory::check(
        &format!("a {} x {} viscous BEM run", grid.nx, grid.ny),
        run_bytes(grid.body, grid.nx, grid.ny, request.fields_at.len(), false),
    )?;
    let n = grid.nx * grid.ny;
    let mut solver = ContactSolver::new(grid.body.operator(grid.nx, grid.ny, grid.dx)?);
    let hmin = (0..n)
        .filter(|&i| grid.allowed[i])
        .map(|i| grid.height[i])
        .fold(f64::INFINITY, f64::min);
    let mut contact: Vec<bool> = (0..n)
        .map(|i| grid.allowed[i] && grid.height[i] <= hmin)
        .collect();
    let mut count = contact.iter().filter(|&&c| c).count();
    let mut punch = Punch::new();
    let (mut iterations, mut residual) =
        punch.solve(&mut solver, &contact, false, opts, monitor)?;
    let mut v_unit = vec![0.0; n];
    solver.operator().apply(&punch.p_unit, &mut v_unit);
    let mut solved_count = count;
    let mut out = Series {
        solves: 1,
        ..Series::default()
    };
    let (mut t, mut depth) = (0.0, hmin);
    let mut u = vec![0.0; n];
    let t_first = ctrl.start * request.times.last().copied().unwrap_or(1.0);
    let mut steps = 0usize;
    for (k, &target) in request.times.iter().enumerate() {
        while t < target {
            let rate = history.force(t) / (eta * punch.k_unit);
            let (dt, next) = ctrl.next_step(t, t_first, target);
            t = next;
            depth += rate * dt;
            for i in 0..n {
                u[i] += rate * dt * v_unit[i];
                if grid.allowed[i] && !contact[i] && u[i] - depth + grid.height[i] <= 0.0 {
                    contact[i] = true;
                    count += 1;
                }
            }
            steps += 1;
            if count as f64 > solved_count as f64 * (1.0 + ctrl.area_change) {
                let (its, res) = punch.solve(&mut solver, &contact, true, opts, monitor)?;
                solver.operator().apply(&punch.p_unit, &mut v_unit);
                solved_count = count;
                out.solves += 1;
                iterations += its;
                residual = residual.max(res);
            }
            if steps % 256 == 0 {
                monitor.progress("time steps", k, request.times.len())?;
            }
        }
        let force = history.force(t);
        if request.fields_at.contains(&k) {
            let (pressure, velocity) = punch.fields(&mut solver, force, eta);
            out.fields.push(Fields {
                step: k,
                pressure,
                velocity,
                deflection: u.clone(),
            });
        }
        let rate = (force / (eta * punch.k_unit), punch.k_unit / 4.0);
        out.record(
            grid,
            t,
            history.force(t),
            depth,
            &contact,
            &u,
            Some(rate),
            iterations,
            residual,
        );
        (iterations, residual) = (0, 0.0);
        monitor.progress("time steps", k + 1, request.times.len())?;
    }
    out.steps = steps;
    Ok(out)
}

/// Result of a flat-punch (rod) solve: its contact never changes, so one solve suffices.
#[derive(Debug, Clone, PartialEq)]
pub struct PunchResult {
    /// Penetration rate dd/dt (m/s).
    pub velocity: f64,
    /// Pressure of the elements (Pa), on the footprint grid.
    pub pressure: Vec<f64>,
    /// Contact stiffness rate F / (dd/dt) (N s/m).
    pub damping: f64,
    /// Iterations (1 for a dense solve).
    pub iterations: usize,
    /// Final relative residual.
    pub residual: f64,
    /// Surface velocity (m/s) on a grid extended by `margin` elements on each side, when
    /// asked for (row-major, (nx + 2 margin) x (ny + 2 margin)).
    pub surface_velocity: Option<Vec<f64>>,
}

/// Solves a flat punch covering `grid.allowed` (heights ignored) pressed by `force` (N)
/// into a viscous half-space. With `margin = Some(m)` also returns the surface velocity on
/// a grid extended by m elements on every side.
pub fn run_punch(
    grid: &Grid,
    eta: f64,
    force: f64,
    margin: Option<usize>,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<PunchResult> {
    check_positive("viscosity eta", eta)?;
    check_positive("force", force)?;
    let area_el = grid.dx * grid.dx;
    let mut solver = ContactSolver::new(grid.body.operator(grid.nx, grid.ny, grid.dx)?);
    let (iterations, residual) = solver.unit_punch(&grid.allowed, None, opts, monitor)?;
    let p_unit = solver.pressure();
    let k_unit: f64 = p_unit.iter().sum::<f64>() * area_el;
    let pressure: Vec<f64> = p_unit.iter().map(|v| v * force / k_unit).collect();
    let surface_velocity = match margin {
        None => None,
        Some(m) => {
            let (ex, ey) = (grid.nx + 2 * m, grid.ny + 2 * m);
            let mut big = vec![0.0; ex * ey];
            for iy in 0..grid.ny {
                let row = (iy + m) * ex + m;
                big[row..row + grid.nx]
                    .copy_from_slice(&pressure[iy * grid.nx..(iy + 1) * grid.nx]);
            }
            let mut v = vec![0.0; ex * ey];
            grid.body.operator(ex, ey, grid.dx)?.apply(&big, &mut v);
            v.iter_mut().for_each(|x| *x /= eta);
            Some(v)
        }
    };
    Ok(PunchResult {
        velocity: force / (eta * k_unit),
        pressure,
        damping: eta * k_unit,
        iterations,
        residual,
        surface_velocity,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::support::monitor::Silent;

    fn paraboloid_grid(n: usize, c: f64, edge: f64) -> Grid {
        let dx = edge / n as f64;
        let x = |i: usize| (i as f64 - 0.5 * (n as f64 - 1.0)) * dx;
        let h = (0..n * n)
            .map(|i| c * (x(i % n).powi(2) + x(i / n).powi(2)))
            .collect();
        Grid::new(n, n, dx, h, vec![true; n * n]).unwrap()
    }

    #[test]
    fn sharp_indenter_grows_from_a_one_element_contact() {
        let grid = paraboloid_grid(257, 1000.0, 2.56);
        let times: Vec<f64> = (0..8)
            .map(|k| 1e-3 * (5e3f64).powf(k as f64 / 7.0))
            .collect();
        let req = ViscousRequest {
            times: times.clone(),
            rates: false,
            fields_at: vec![],
            // far too small for the first step: it is solved again on a larger window
            depth_bounds: [1e-3].into_iter().chain([f64::NAN; 7]).collect(),
        };
        let h = ForceHistory::constant(1.0).unwrap();
        let s = run_implicit(&grid, 1.0, &h, &req, &SolverOptions::default(), &mut Silent).unwrap();
        let c = 1000.0f64;
        let exact = (3.0 * 5.0 * (2.0 * c).sqrt() / 16.0).powf(2.0 / 3.0);
        assert!((s.depth[7] / exact - 1.0).abs() < 0.01);
    }
}
