//! One static contact solve on the smallest window that holds the contact.
//!
//! Deflections under positive pressures are positive, so no element whose height exceeds
//! the depth can touch: under depth control the window around {h <= d} holds the whole
//! contact, and under force control so does the window around {h + u_low <= bound} for any
//! bound above the depth (e.g. from MDR), u_low a lower bound of the deflection under the
//! force (`Window::around_contact`). The windowed solution is then the full grid's, exactly.
//! A bound the solve exceeds is widened and the solve repeated. On a free layer the surface
//! may rise around the contact, by at most F / dx^2 times the body's least coefficient
//! (`Body::least_coefficient`): the windows widen to {h - rise <= bound}; under depth control
//! the force is known after the solve, and a window that did not hold {h - rise(F) <= d} is
//! widened and the solve repeated.
//!
//! A body without windows (a periodic cell, `Body::windows`) is solved whole by
//! [`solve_whole`]. Either is started from the solution on the grid coarsened twice and again
//! (nested grids) when the grid is large and no start or depth bound is given.

use crate::bem::contact::{ContactSolver, ContactSummary, Target};
use crate::bem::nested::{averaged, coarsened, prolonged, NESTED_COARSEST, NESTED_TOL};
use crate::bem::window::Window;
use crate::halfspace::influence::KernelTable;
use crate::halfspace::operator::{FftPlans, SurfaceOperator};
use crate::halfspace::periodic;
use crate::model::body::Body;
use crate::model::grid::Grid;
use crate::model::settings::SolverOptions;
use crate::support::error::{check_len, Error, Result};
use crate::support::monitor::Monitor;

/// The result of [`solve`] on the whole grid.
pub struct StaticContact {
    /// The last solve's summary (iterations are summed over all solves).
    pub summary: ContactSummary,
    /// Pressure (Pa), row-major on the whole grid (zero outside the window).
    pub pressure: Vec<f64>,
    /// Surface deflection (m) on the whole grid, when asked for.
    pub deflection: Option<Vec<f64>>,
    /// The window of the last solve.
    pub window: Window,
    /// Solves run (more than one when a depth bound was exceeded).
    pub solves: usize,
    /// Iterations of each level of a nested solve, coarsest first, the finest level's last
    /// (a level's repeated window solves summed into its entry; a periodic cell's loading to
    /// a separation into its level's); one entry without coarse levels. They sum to the
    /// summary's iterations.
    pub level_iterations: Vec<usize>,
}

/// One static solve's request: what to reach, the windows' depth bound, whether the
/// deflection is returned, and where to start.
#[derive(Clone, Copy)]
pub struct StaticRequest<'a> {
    /// The force (N) or depth (m) to reach.
    pub target: Target,
    /// Under force control, a depth bound (m) that sizes the windows (None: the whole grid).
    pub depth_bound: Option<f64>,
    /// Whether the deflection (m) on the whole grid is returned.
    pub deflection: bool,
    /// A starting pressure (Pa, row-major on the whole grid, rescaled to the target force),
    /// e.g. the solution at a neighbouring load (None: a cold or nested start).
    pub start: Option<&'a [f64]>,
}

impl StaticRequest<'_> {
    /// A request for `target` on the whole grid, without a start or the deflection.
    pub fn to(target: Target) -> Self {
        StaticRequest {
            target,
            depth_bound: None,
            deflection: false,
            start: None,
        }
    }
}

/// Solves the static contact of `grid` (compliance in m/Pa per unit kernel, 1/G for an
/// elastic half-space) for `req.target` on the window that can touch: under depth control
/// the elements with h <= d, under force control those with h + u_low <= `req.depth_bound`
/// (m; the whole grid without one). Windows get a margin of 2 elements. When the solved
/// depth exceeds the bound, the bound grows by the excess and the solve repeats.
/// `req.deflection` asks for the deflection on the whole grid, one extra whole-grid operator
/// when the window is smaller. A body without windows (`Body::windows`) is solved whole by
/// `solve_whole`; a depth bound, which sizes windows, is refused there.
///
/// A start (`req.start`, a load curve's warm start) gives the same solution as a cold
/// start's, to the solver's tolerance. A periodic cell with nested coarse levels starts its
/// coarsest level from it (averaged over 2 x 2 elements per level). Without a start, a grid
/// whose halves are at least `NESTED_COARSEST` elements (under a depth bound: the window of
/// the elements with h <= bound at least twice that each way) is started from its solution
/// on the grid coarsened by two (`coarsened`, solved the same way, with the same depth bound,
/// at tolerance max(tol, `NESTED_TOL`)), carried over to each element's four children
/// (`nested::prolonged`); `solves` and the iterations count every level.
pub fn solve(
    grid: &Grid,
    compliance: f64,
    req: StaticRequest,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    solve_sharing(grid, compliance, req, None, opts, monitor)
}

/// [`solve`], its windows' kernel tables taken from `shared` (a finer level's) where it
/// holds them (`KernelTable::part`): a nested solve evaluates Love's coefficients once, for
/// its finest level's first window, and its coarse levels take them scaled.
fn solve_sharing(
    grid: &Grid,
    compliance: f64,
    req: StaticRequest,
    shared: Option<&KernelTable>,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    let StaticRequest {
        target,
        depth_bound,
        deflection,
        start,
    } = req;
    if let Some(p) = start {
        check_len("starting pressure", p.len(), grid.nx * grid.ny)?;
    }
    crate::support::memory::check(
        &format!("a {} x {} contact solve", grid.nx, grid.ny),
        solve_bytes(grid.body, grid.nx, grid.ny, opts.precondition),
    )?;
    if !grid.body.windows() {
        if depth_bound.is_some() {
            return Err(Error::InvalidInput(format!(
                "depth_bound sizes windows, which a {} body does not have",
                grid.body.name()
            )));
        }
        return solve_whole_from(grid, compliance, target, deflection, start, opts, monitor);
    }
    let (nx, ny, n) = (grid.nx, grid.ny, grid.nx * grid.ny);
    check_len("height", grid.height.len(), n)?;
    if let Some(b) = depth_bound.filter(|b| !b.is_finite()) {
        return Err(Error::InvalidInput(format!(
            "depth bound must be finite, got {b}"
        )));
    }
    // nested grids: a large grid without a start starts from its solution on the grid
    // coarsened by two (recursively), under a depth bound when the elements that bound lets
    // touch span at least twice `NESTED_COARSEST` each way (a small contact's window is
    // solved faster alone); the coarse levels take the same bound, and widen it as the
    // finest level does where their solve exceeds it
    let spans_levels = |b: f64| {
        let w = Window::around(nx, ny, 2, |i| grid.allowed[i] && grid.height[i] <= b);
        w.wx.min(w.wy) >= 2 * NESTED_COARSEST
    };
    let nest = start.is_none() && opts.precondition && depth_bound.is_none_or(spans_levels);
    let mut bound = match target {
        Target::Depth(d) => Some(d),
        Target::Force(_) => depth_bound,
    };
    let (h, allowed) = (&grid.height, &grid.allowed);
    // the most the surface can rise under a force (m; 0 on a half-space), and under depth
    // control the rise the window allows for, checked against the solved force
    let least = grid.body.least_coefficient(grid.dx);
    let rise = |force: f64| -compliance * force * least / (grid.dx * grid.dx);
    let mut allowance = match target {
        Target::Force(f) => rise(f),
        Target::Depth(_) => 0.0,
    };
    // the window around the elements that can touch under `bound` with the surface raised
    // by `allowance` (None: the whole grid)
    let outer = |bound: Option<f64>, allowance: f64| {
        let can = |i: usize, b: f64| allowed[i] && h[i] - allowance <= b;
        bound
            .filter(|&b| (0..n).any(|i| can(i, b)))
            .map(|b| Window::around(nx, ny, 2, |i| can(i, b)))
    };
    // the first window's table, made before the coarse levels, which take parts of it
    let extent = |w: Option<Window>| w.map_or((nx, ny), |w| (w.wx, w.wy));
    let (wx, wy) = extent(outer(bound, allowance));
    let mut table = window_table(grid, wx, wy, shared)?;
    let coarse = match coarsened(grid).filter(|_| nest) {
        Some(coarse) => {
            let loose = SolverOptions {
                tol: opts.tol.max(NESTED_TOL),
                ..*opts
            };
            let below = StaticRequest {
                deflection: false,
                start: None,
                ..req
            };
            let solved = solve_sharing(&coarse, compliance, below, Some(&table), &loose, monitor)?;
            Some((
                prolonged(&solved.pressure, grid, compliance),
                solved.summary.iterations,
                solved.solves,
                solved.level_iterations,
            ))
        }
        None => None,
    };
    let start = start.or(coarse.as_ref().map(|c| c.0.as_slice()));
    let (mut iterations, mut solves) = coarse.as_ref().map_or((0, 0), |c| (c.1, c.2));
    let coarse_iterations = iterations;
    let (mut h_w, mut allowed_w) = (vec![], vec![]);
    let mut plans = FftPlans::default();
    loop {
        let around = outer(bound, allowance);
        let (wx, wy) = extent(around);
        table = window_table(grid, wx, wy, Some(&table))?;
        let window = match (around, bound, target) {
            (Some(_), Some(b), Target::Force(f)) => {
                Window::around_contact(nx, ny, h, allowed, b, compliance * f, &table, least)
            }
            (Some(o), _, _) => o,
            (None, _, _) => Window::full(nx, ny),
        };
        window.gather(h, &mut h_w);
        window.gather(allowed, &mut allowed_w);
        let op = grid
            .body
            .window_operator(&table, window.wx, window.wy, &mut plans)?;
        let mut solver = ContactSolver::new(op);
        let warm = match start {
            Some(p) => {
                // a whole grid's window is the grid: its start is not copied
                let mut p_w = vec![];
                let p_w = if window.is_full() {
                    p
                } else {
                    window.gather(p, &mut p_w);
                    &p_w
                };
                let loaded = p_w.iter().zip(&allowed_w).any(|(&p, &a)| a && p > 0.0);
                if loaded {
                    solver.set_pressure(p_w)?;
                }
                loaded
            }
            None => false,
        };
        let mut summary = solver.solve(
            &h_w, &allowed_w, compliance, target, warm, 0.0, opts, monitor,
        )?;
        solves += 1;
        iterations += summary.iterations;
        match (bound, target) {
            (Some(b), Target::Force(_)) if !window.is_full() && summary.depth > b => {
                bound = Some(summary.depth + (summary.depth - b));
                continue;
            }
            // under depth control the force is known only now: the elements that its rise
            // could bring into contact must lie inside the window
            (Some(d), Target::Depth(_)) if !window.is_full() && rise(summary.force) > allowance => {
                let needed = rise(summary.force);
                if !window.contains(&Window::around(nx, ny, 2, |i| {
                    allowed[i] && h[i] - needed <= d
                })) {
                    allowance = RISE_ALLOWANCE * needed;
                    continue;
                }
            }
            _ => {}
        }
        summary.iterations = iterations;
        let mut level_iterations = coarse.as_ref().map_or(vec![], |c| c.3.clone());
        level_iterations.push(iterations - coarse_iterations);
        let mut pressure = vec![0.0; n];
        window.scatter(solver.pressure(), &mut pressure);
        let deflection = match (deflection, window.is_full()) {
            (false, _) => None,
            (true, true) => Some(solver.deflection().to_vec()),
            (true, false) => {
                let mut u = vec![0.0; n];
                grid.body
                    .operator(nx, ny, grid.dx)?
                    .apply(&pressure, &mut u);
                u.iter_mut().for_each(|v| *v *= compliance);
                Some(u)
            }
        };
        return Ok(StaticContact {
            summary,
            pressure,
            deflection,
            window,
            solves,
            level_iterations,
        });
    }
}

/// The kernel table of a `wx` x `wy` window of `grid`: a part of `shared` (a finer level's or
/// an earlier window's table) where it holds it (`KernelTable::part`), else the body's own
/// (`Body::window_kernel`).
fn window_table(
    grid: &Grid,
    wx: usize,
    wy: usize,
    shared: Option<&KernelTable>,
) -> Result<KernelTable> {
    match shared.and_then(|t| t.part(wx, wy, grid.dx)) {
        Some(part) => Ok(part),
        None => Ok(grid
            .body
            .window_kernel(wx, wy, grid.dx)?
            .expect("a body with windows has a window kernel")),
    }
}

/// Factor on the rise of a free layer's surface under the solved force by which a
/// depth-controlled window that was too narrow is widened (the force grows with the window).
const RISE_ALLOWANCE: f64 = 1.25;

/// Bytes per element a solve holds besides the operator: the contact solver's buffers
/// (`ContactSolver::BYTES_PER_ELEMENT`), the pressure returned (8), with `precondition` the
/// nested levels' start (8), and on a body with windows the window's heights and mask (9)
/// and the windows' kernel table (8).
fn solve_bytes_per_element(body: Body, precondition: bool) -> f64 {
    let windows = if body.windows() { 17.0 } else { 0.0 };
    let start = if precondition { 8.0 } else { 0.0 };
    ContactSolver::<crate::halfspace::body::Operator>::BYTES_PER_ELEMENT + 8.0 + start + windows
}

/// The memory (bytes) a solve of an `nx` x `ny` grid on `body` reaches at its peak, the
/// grid itself aside: the whole grid's operator (`Body::operator_bytes`; on a body with
/// windows without its spectral preconditioner unless `precondition`) and
/// `solve_bytes_per_element`; coarse levels are freed before the finest starts. The check
/// before a solve and the measured peak (`tests/test_memory.py`) use it.
pub fn solve_bytes(body: Body, nx: usize, ny: usize, precondition: bool) -> f64 {
    let unused = if body.windows() && !precondition {
        crate::halfspace::operator::inverse_bytes(nx, ny)
    } else {
        0.0
    };
    body.operator_bytes(nx, ny) - unused
        + solve_bytes_per_element(body, precondition) * (nx * ny) as f64
}

/// Solves the static contact of a body without windows, a periodic cell: `grid` is one
/// period (its heights the separation h before loading, m; the whole cell is solved,
/// `allowed` still masks elements out), `compliance` multiplies the body's G = 1 operator
/// (`Body::operator`; 1/G for an elastic body, m/Pa). `Target::Force` is the total force on the cell (N: mean
/// pressure times the cell area nx ny dx^2); `Target::Depth(d)` is the rigid-body approach
/// from the mean plane of the deflected surface, so that the mean separation is
/// mean(h) - d (`periodic::depth_at_mean_separation` converts a mean separation; it must
/// be > 0, since full contact takes an unbounded force in depth control). The summary's
/// depth is that approach; the window is the whole cell. Polonsky–Keer runs on the whole
/// cell; the dense active set applies as for a non-periodic grid (with the periodic
/// operator's matrix), and declines full contact, where that matrix is singular.
///
/// Nested grids: with `opts.precondition`, a cell of even sides whose halves are at least
/// `NESTED_COARSEST` elements is first solved on the cell coarsened by two (heights averaged
/// over 2 x 2 elements, an element allowed where all four are), at tolerance
/// max(tol, `NESTED_TOL`) and recursively, and its pressure, carried over to each element's
/// four children (`nested::prolonged`), starts the solve (rescaled to the force under force
/// control). `solves`
/// counts the levels and the summary's iterations are summed over them. Under depth
/// control, a cell without a coarse level starts from `load_to_separation`.
pub fn solve_whole(
    grid: &Grid,
    compliance: f64,
    target: Target,
    deflection: bool,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    solve_whole_from(grid, compliance, target, deflection, None, opts, monitor)
}

/// [`solve_whole`] started from the pressure `start` (Pa, on the whole cell) when given:
/// the coarsest nested level from it averaged, or without coarse levels the cell itself
/// (no loading to a separation then).
fn solve_whole_from(
    grid: &Grid,
    compliance: f64,
    target: Target,
    deflection: bool,
    start: Option<&[f64]>,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    let (nx, ny) = (grid.nx, grid.ny);
    check_len("height", grid.height.len(), nx * ny)?;
    if let Target::Depth(d) = target {
        grid.body
            .check_depth(periodic::mean_separation(&grid.height, 0.0), d)?;
    }
    let mut solver = ContactSolver::new(grid.body.operator(nx, ny, grid.dx)?);
    let start = start.filter(|p| grid.allowed.iter().zip(*p).any(|(&a, &p)| a && p > 0.0));
    // a warm start goes to the coarsest level, whose solution starts the finer ones
    let coarse = match coarsened(grid) {
        Some(coarse) if opts.precondition => {
            let loose = SolverOptions {
                tol: opts.tol.max(NESTED_TOL),
                ..*opts
            };
            let below = start.map(|p| averaged(p, nx));
            let solved = solve_whole_from(
                &coarse,
                compliance,
                target,
                false,
                below.as_deref(),
                &loose,
                monitor,
            )?;
            solver.set_pressure(&prolonged(&solved.pressure, grid, compliance))?;
            Some(solved)
        }
        _ => None,
    };
    let started = match (&coarse, start) {
        (None, Some(p)) => {
            solver.set_pressure(p)?;
            true
        }
        _ => false,
    };
    let loading = match (&coarse, target) {
        (None, Target::Depth(d)) if !started => {
            let separation = periodic::mean_separation(&grid.height, d);
            load_to_separation(
                &mut solver,
                &grid.height,
                &grid.allowed,
                grid.dx,
                compliance,
                separation,
                opts,
                monitor,
            )?
        }
        _ => 0,
    };
    let mut summary = solver.solve(
        &grid.height,
        &grid.allowed,
        compliance,
        target,
        started || coarse.is_some() || loading > 0,
        0.0,
        opts,
        monitor,
    )?;
    let mut level_iterations = coarse
        .as_ref()
        .map_or(vec![], |c| c.level_iterations.clone());
    level_iterations.push(summary.iterations + loading);
    summary.iterations += loading + coarse.as_ref().map_or(0, |c| c.summary.iterations);
    Ok(StaticContact {
        summary,
        pressure: solver.pressure().to_vec(),
        deflection: deflection.then(|| solver.deflection().to_vec()),
        window: Window::full(nx, ny),
        solves: 1 + coarse.map_or(0, |c| c.solves),
        level_iterations,
    })
}

/// Relative error of the mean separation at which `load_to_separation` stops.
const LOADING_TOL: f64 = 1e-3;

/// Force-controlled solves bringing a cold periodic cell (separation `h` before loading, m,
/// on the elements `allowed` of side `dx`, m) near the mean `separation` (m): returns their
/// iterations, the pressure left in `solver`. A cold depth-controlled start
/// (each overlapping element's own closing pressure) overloads a cell, whose zero-mean
/// deflection then lifts the rest of the surface into contact; in full contact a uniform
/// pressure change deflects nothing, Polonsky–Keer's line search along it is unbounded, and
/// the iteration can end released. Force control projects that mode out. The force starts
/// at the cold start's and moves by factors of 4 until the separation is bracketed, then by
/// secant steps in ln F (the separation falls about linearly in ln F), each solve at
/// tolerance max(tol, `NESTED_TOL`) and warm-started from the last, until the separation is
/// within `LOADING_TOL`.
#[allow(clippy::too_many_arguments)]
pub fn load_to_separation<O: SurfaceOperator>(
    solver: &mut ContactSolver<O>,
    h: &[f64],
    allowed: &[bool],
    dx: f64,
    compliance: f64,
    separation: f64,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<usize> {
    let depth = periodic::depth_at_mean_separation(h, separation);
    let closing = compliance * crate::halfspace::influence::coefficient(0, 0, dx);
    let mut force = dx * dx / closing
        * h.iter()
            .zip(allowed)
            .filter(|(_, &a)| a)
            .map(|(&h, _)| (depth - h).max(0.0))
            .sum::<f64>();
    let loose = SolverOptions {
        tol: opts.tol.max(NESTED_TOL),
        ..*opts
    };
    // (ln F, separation) with the separation above (shallow) and below (deep) the target
    let (mut shallow, mut deep) = (None::<(f64, f64)>, None::<(f64, f64)>);
    let (mut iterations, mut error) = (0, f64::INFINITY);
    for solve in 0..60 {
        let summary = solver.solve(
            h,
            allowed,
            compliance,
            Target::Force(force),
            solve > 0,
            0.0,
            &loose,
            monitor,
        )?;
        iterations += summary.iterations;
        let s = periodic::mean_separation(h, summary.depth);
        error = (s / separation - 1.0).abs();
        if error <= LOADING_TOL {
            return Ok(iterations);
        }
        let point = (force.ln(), s);
        if s > separation {
            shallow = Some(point);
        } else {
            deep = Some(point);
        }
        force = match (shallow, deep) {
            (Some((a, sa)), Some((b, sb))) => {
                let x = a + (separation - sa) * (b - a) / (sb - sa);
                // bisection where a secant step leaves the bracket's inner 90 %
                let (lo, hi) = (a.min(b), a.max(b));
                if x > lo + 0.05 * (hi - lo) && x < hi - 0.05 * (hi - lo) {
                    x.exp()
                } else {
                    (0.5 * (a + b)).exp()
                }
            }
            (Some(_), None) => 4.0 * force,
            _ => 0.25 * force,
        };
    }
    Err(Error::NotConverged {
        what: "the force loading a periodic cell to its mean separation".into(),
        iterations,
        residual: error,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::support::monitor::Silent;

    /// A paraboloid (R = 10 m) on a 96 x 96 grid of side 2.56 m.
    fn hertz() -> Grid {
        let n = 96;
        let dx = 2.56 / n as f64;
        let c = (n as f64 - 1.0) / 2.0;
        let h = (0..n * n)
            .map(|i| {
                let (x, y) = (((i % n) as f64 - c) * dx, ((i / n) as f64 - c) * dx);
                (x * x + y * y) / 20.0
            })
            .collect();
        Grid::new(n, n, dx, h, vec![true; n * n]).unwrap()
    }

    /// The windowed solution equals the whole grid's: under depth control always, under
    /// force control with a tight bound, and with a bound below the depth after a retry.
    #[test]
    fn windowed_solves_match_the_whole_grid() {
        let grid = hertz();
        let opts = SolverOptions {
            tol: 1e-12,
            active_limit: Some(0),
            ..SolverOptions::default()
        };
        let run = |target, bound| {
            let req = StaticRequest {
                depth_bound: bound,
                deflection: true,
                ..StaticRequest::to(target)
            };
            solve(&grid, 1.0, req, &opts, &mut Silent).unwrap()
        };
        let full = run(Target::Force(0.02), None);
        assert!(full.window.is_full() && full.solves == 1);
        let d = full.summary.depth;
        let peak = full.pressure.iter().fold(0.0f64, |m, &p| m.max(p));
        let umax = full
            .deflection
            .as_ref()
            .unwrap()
            .iter()
            .fold(0.0f64, |m, &u| m.max(u));
        for (target, bound, solves) in [
            (Target::Force(0.02), Some(1.05 * d), 1),
            (Target::Force(0.02), Some(0.8 * d), 2),
            (Target::Depth(d), None, 1),
        ] {
            let w = run(target, bound);
            assert!(!w.window.is_full(), "{:?}", w.window);
            assert!(w.window.wx < grid.nx * 3 / 4, "{:?}", w.window);
            assert_eq!(w.solves, solves);
            assert!((w.summary.depth - d).abs() < 1e-9 * d);
            assert!((w.summary.force - 0.02).abs() < 1e-9 * 0.02);
            for (a, b) in w.pressure.iter().zip(&full.pressure) {
                assert!((a - b).abs() < 1e-8 * peak);
            }
            let u = w.deflection.unwrap();
            for (a, b) in u.iter().zip(full.deflection.as_ref().unwrap()) {
                assert!((a - b).abs() < 1e-9 * umax);
            }
        }
    }

    /// Under force control with a depth bound, a rough grid whose touching part spans two
    /// levels is nested (the coarse level under the same bound), and its solution equals
    /// the single-level solve's (started from a uniform pressure, which skips the coarse
    /// level) to the tolerance.
    #[test]
    fn nested_solves_under_a_depth_bound_match_one_level() {
        use crate::model::surfaces::{self_affine, Roughness, SelfAffine};
        let n = 256;
        let surface = SelfAffine {
            nx: n,
            ny: n,
            dx: 1.0 / n as f64,
            hurst: 0.8,
            rolloff: Some(0.25),
            short_cutoff: None,
            roughness: Roughness::RmsSlope(0.1),
        };
        let h = self_affine(&surface, 7, &Default::default()).unwrap();
        let low = h.iter().fold(f64::INFINITY, |m, &v| m.min(v));
        let h = h.iter().map(|v| v - low).collect();
        let grid = Grid::new(n, n, surface.dx, h, vec![true; n * n]).unwrap();
        let opts = SolverOptions {
            tol: 1e-11,
            ..SolverOptions::default()
        };
        let force = Target::Force(0.01);
        let free = solve(&grid, 1.0, StaticRequest::to(force), &opts, &mut Silent).unwrap();
        let d = free.summary.depth;
        let uniform = vec![1.0; n * n];
        {
            let bound = 1.5 * d;
            let bounded = StaticRequest {
                depth_bound: Some(bound),
                ..StaticRequest::to(force)
            };
            let nested = solve(&grid, 1.0, bounded, &opts, &mut Silent).unwrap();
            let started = StaticRequest {
                start: Some(&uniform),
                ..bounded
            };
            let single = solve(&grid, 1.0, started, &opts, &mut Silent).unwrap();
            assert_eq!((single.solves, nested.solves), (1, 2));
            let total: f64 = single.pressure.iter().sum();
            let diff: f64 = nested
                .pressure
                .iter()
                .zip(&single.pressure)
                .map(|(a, b)| (a - b).abs())
                .sum();
            assert!(diff < 1e-8 * total, "{diff} of {total}");
            assert!((nested.summary.depth - single.summary.depth).abs() < 1e-9 * d);
        }
    }

    /// A non-finite bound is refused.
    #[test]
    fn a_nan_bound_is_refused() {
        let grid = hertz();
        let r = solve(
            &grid,
            1.0,
            StaticRequest {
                depth_bound: Some(f64::NAN),
                ..StaticRequest::to(Target::Force(0.02))
            },
            &SolverOptions::default(),
            &mut Silent,
        );
        assert!(matches!(r, Err(Error::InvalidInput(_))));
    }
}

#[cfg(test)]
mod periodic_tests {
    //! Periodic cells against closed forms: Westergaard's wavy surface (plane strain, on a
    //! 2D grid uniform in y) and an isolated Hertz contact, periodic and not.

    use super::*;
    use crate::model::body::Body;
    use crate::support::monitor::Silent;
    use std::f64::consts::PI;

    /// The static elastic (G = 1 Pa) solve of `grid` as a periodic cell for `target`, no
    /// deflection.
    fn cell(grid: &Grid, target: Target, opts: &SolverOptions) -> StaticContact {
        let cell = Grid {
            body: Body::Periodic,
            ..grid.clone()
        };
        solve(&cell, 1.0, StaticRequest::to(target), opts, &mut Silent).unwrap()
    }

    /// Westergaard's wavy surface h(x) = g (1 - cos(2 pi x / lambda)) on an n x ny cell of
    /// one wavelength, element centres at (i - n/2 + 1/2) dx (the crest between the two
    /// middle elements); shear modulus 1 Pa, so E* = 4 Pa and p* = pi E* g / lambda.
    struct Wavy {
        n: usize,
        ny: usize,
        dx: f64,
        lambda: f64,
        g: f64,
    }

    impl Wavy {
        fn new(n: usize) -> Self {
            Wavy {
                n,
                ny: 4,
                dx: 1.0 / n as f64,
                lambda: 1.0,
                g: 0.01,
            }
        }
        fn x(&self, i: usize) -> f64 {
            ((i % self.n) as f64 - (self.n / 2) as f64 + 0.5) * self.dx
        }
        fn grid(&self) -> Grid {
            let h = (0..self.n * self.ny)
                .map(|i| self.g * (1.0 - (2.0 * PI * self.x(i) / self.lambda).cos()))
                .collect();
            Grid {
                body: Body::Periodic,
                ..Grid::new(self.n, self.ny, self.dx, h, vec![true; self.n * self.ny]).unwrap()
            }
        }
        fn p_star(&self) -> f64 {
            PI * 4.0 * self.g / self.lambda
        }
        /// Total force on the cell at mean pressure `pbar`.
        fn force(&self, pbar: f64) -> f64 {
            pbar * self.lambda * self.ny as f64 * self.dx
        }
        /// Westergaard's pressure at x for mean pressure pbar = p* sin^2(pi a / lambda).
        fn pressure(&self, pbar: f64, x: f64) -> f64 {
            let s2 = pbar / self.p_star();
            let s = (PI * x / self.lambda).sin();
            if s * s < s2 {
                2.0 * pbar * (PI * x / self.lambda).cos() / s2 * (s2 - s * s).sqrt()
            } else {
                0.0
            }
        }
    }

    fn tight() -> SolverOptions {
        SolverOptions {
            tol: 1e-12,
            ..SolverOptions::default()
        }
    }

    /// Partial contact at p = p* sin^2(3 pi / 16), so that the contact half-width a =
    /// 3 lambda / 16 falls on an element boundary at every refinement: the contact holds
    /// exactly 2a / dx elements per row, and the pressure error falls under refinement, in
    /// the mean as dx^1.5 and at worst (the elements at the square-root edge) as dx^0.5.
    /// Measured (relative L1 error, max error / peak), n = 64 .. 2048:
    /// 2.19e-3, 7.74e-4, 2.73e-4, 9.66e-5, 3.41e-5, 1.21e-5 (ratio 2.83 = 2^1.5);
    /// 1.62e-2, 1.13e-2, 7.96e-3, 5.62e-3, 3.97e-3, 2.80e-3 (ratio 1.41 = 2^0.5).
    #[test]
    fn westergaard_partial_contact_converges() {
        let mut last: Option<(f64, f64)> = None;
        for n in [64, 128, 256, 512, 1024, 2048] {
            let w = Wavy::new(n);
            let s2 = (3.0 * PI / 16.0).sin().powi(2);
            let pbar = s2 * w.p_star();
            let r = solve_whole(
                &w.grid(),
                1.0,
                Target::Force(w.force(pbar)),
                false,
                &tight(),
                &mut Silent,
            )
            .unwrap();
            let peak = 2.0 * pbar / s2.sqrt();
            let (mut l1, mut norm, mut worst) = (0.0, 0.0, 0.0f64);
            for (i, &p) in r.pressure.iter().enumerate() {
                let exact = w.pressure(pbar, w.x(i));
                l1 += (p - exact).abs();
                norm += exact;
                worst = worst.max((p - exact).abs() / peak);
            }
            let l1 = l1 / norm;
            assert_eq!(r.summary.contact_count, w.ny * 3 * n / 8, "n = {n}");
            assert!((r.summary.force / w.force(pbar) - 1.0).abs() < 1e-12);
            if let Some((l1_prev, worst_prev)) = last {
                assert!(l1_prev / l1 > 2.6, "n = {n}: L1 {l1_prev:e} -> {l1:e}");
                assert!(
                    worst_prev / worst > 1.3,
                    "n = {n}: max {worst_prev:e} -> {worst:e}"
                );
            }
            last = Some((l1, worst));
        }
        let (l1, worst) = last.unwrap();
        assert!(l1 < 4e-5 && worst < 1e-2, "{l1:e} {worst:e}");
    }

    /// The mean separation under force control and the force under mean-separation control
    /// follow Westergaard's g_bar = g (1 - P (1 - ln P)), P = p / p*: the mean separation of
    /// a force-controlled solve (measured relative errors at n = 512: 5.6e-6, 7.5e-6, 2.9e-6
    /// for P = 0.1, 0.31, 0.7), and the force of a solve at that closed-form mean separation
    /// (depth control).
    #[test]
    fn westergaard_mean_separation_under_force_and_depth_control() {
        let w = Wavy::new(512);
        let grid = w.grid();
        for ratio in [0.1, 0.3086582838174551, 0.7] {
            let pbar = ratio * w.p_star();
            let closed = w.g * (1.0 - ratio * (1.0 - f64::ln(ratio)));
            let by_force = cell(&grid, Target::Force(w.force(pbar)), &tight());
            let sep = periodic::mean_separation(&grid.height, by_force.summary.depth);
            assert!(
                (sep / closed - 1.0).abs() < 3e-5,
                "{ratio}: {sep} vs {closed}"
            );
            let depth = periodic::depth_at_mean_separation(&grid.height, closed);
            let by_depth = cell(&grid, Target::Depth(depth), &tight());
            let f = by_depth.summary.force / w.force(pbar);
            // measured 1.6e-5, 6.8e-6, 5.9e-7
            assert!((f - 1.0).abs() < 1e-4, "{ratio}: force ratio {f}");
            // the plain method too (a cold depth-controlled start once ended released)
            let plain = SolverOptions {
                precondition: false,
                ..tight()
            };
            let by_plain = cell(&grid, Target::Depth(depth), &plain);
            let f = by_plain.summary.force / w.force(pbar);
            assert!((f - 1.0).abs() < 1e-4, "{ratio}: plain force ratio {f}");
        }
    }

    /// A 256 x 256 grid of side 1 m of many asperities: a sum of 40 random cosines up to
    /// wavenumber 12 per side, the highest point at h = 0 (a half-space body).
    fn asperities() -> Grid {
        let (n, dx) = (256, 1.0 / 256.0);
        let mut seed = 7u64;
        let mut next = || {
            seed = seed
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (seed >> 11) as f64 / (1u64 << 53) as f64
        };
        let waves: Vec<[f64; 4]> = (0..40)
            .map(|_| {
                let (kx, ky) = ((next() * 25.0) as i64 - 12, (next() * 13.0) as i64);
                let k = (kx * kx + ky * ky).max(1) as f64;
                [kx as f64, ky as f64, next() * 2.0 * PI, 1e-3 / k]
            })
            .collect();
        let z: Vec<f64> = (0..n * n)
            .map(|i| {
                let (x, y) = ((i % n) as f64 * dx, (i / n) as f64 * dx);
                waves
                    .iter()
                    .map(|[kx, ky, ph, a]| a * (2.0 * PI * (kx * x + ky * y) + ph).cos())
                    .sum::<f64>()
            })
            .collect();
        let top = z.iter().fold(f64::MIN, |m, &v| m.max(v));
        let h: Vec<f64> = z.iter().map(|v| top - v).collect();
        Grid::new(n, n, dx, h, vec![true; n * n]).unwrap()
    }

    /// A 256 x 256 cell of many asperities (a sum of 40 random cosines up to wavenumber 12
    /// per cell, 13.5 % contact) solved on nested grids (256 from 128) and on the cell
    /// alone (the plain method, which has no coarse level) under force and depth control:
    /// the same pressure to the tolerance (measured 9.7e-10 and 6.7e-10 of the
    /// peak at tol 1e-10; 34 and 97 iterations in all against the plain method's 86 and 333).
    #[test]
    fn nested_solves_match_the_single_level() {
        let n = 256;
        let grid = asperities();
        let opts = SolverOptions {
            tol: 1e-10,
            active_limit: Some(0),
            ..SolverOptions::default()
        };
        let force = 2e-3;
        let nested = cell(&grid, Target::Force(force), &opts);
        let depth = nested.summary.depth;
        let plain = SolverOptions {
            precondition: false,
            ..opts
        };
        for target in [Target::Force(force), Target::Depth(depth)] {
            let nested = cell(&grid, target, &opts);
            let single = cell(&grid, target, &plain);
            let fraction = nested.summary.contact_count as f64 / (n * n) as f64;
            assert!(
                (0.1..0.2).contains(&fraction),
                "contact fraction {fraction}"
            );
            assert_eq!((nested.solves, single.solves), (2, 1));
            assert_eq!(nested.level_iterations.len(), 2);
            assert_eq!(
                nested.level_iterations.iter().sum::<usize>(),
                nested.summary.iterations
            );
            assert_eq!(single.level_iterations, vec![single.summary.iterations]);
            let peak = nested.pressure.iter().fold(0.0f64, |m, &v| m.max(v));
            let diff = nested
                .pressure
                .iter()
                .zip(&single.pressure)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff < 5e-9 * peak, "{target:?}: {diff:e} of {peak:e}");
        }
    }

    /// The same asperities on a free half-space (Love's kernel, spectral preconditioner):
    /// solved on nested grids (256 from 128) and on the whole grid alone (started cold,
    /// which takes the single level), under force and depth control: the same pressure to
    /// the tolerance (tol 1e-10).
    #[test]
    fn free_nested_solves_match_the_single_level() {
        let grid = asperities();
        let n = grid.nx;
        let opts = SolverOptions {
            tol: 1e-10,
            active_limit: Some(0),
            ..SolverOptions::default()
        };
        let force = 2e-3;
        let run =
            |target| solve(&grid, 1.0, StaticRequest::to(target), &opts, &mut Silent).unwrap();
        let depth = run(Target::Force(force)).summary.depth;
        for target in [Target::Force(force), Target::Depth(depth)] {
            let nested = run(target);
            // a start (here a cold one) skips the coarse level
            let cold = vec![0.0; n * n];
            let started = StaticRequest {
                start: Some(&cold),
                ..StaticRequest::to(target)
            };
            let single = solve(&grid, 1.0, started, &opts, &mut Silent).unwrap();
            let fraction = nested.summary.contact_count as f64 / (n * n) as f64;
            assert!(
                (0.05..0.3).contains(&fraction),
                "contact fraction {fraction}"
            );
            assert_eq!((nested.solves, single.solves), (2, 1));
            assert_eq!(nested.level_iterations.len(), 2);
            assert_eq!(
                nested.level_iterations.iter().sum::<usize>(),
                nested.summary.iterations
            );
            assert_eq!(single.level_iterations, vec![single.summary.iterations]);
            assert!(single.window.is_full());
            let peak = nested.pressure.iter().fold(0.0f64, |m, &v| m.max(v));
            let diff = nested
                .pressure
                .iter()
                .zip(&single.pressure)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(diff < 5e-9 * peak, "{target:?}: {diff:e} of {peak:e}");
        }
    }

    /// Full contact (p > p*): p = p + p* cos(2 pi x / lambda) everywhere, answered to the
    /// solver's tolerance by the spectral kernel at any resolution (measured 9e-12 of p* at
    /// tolerance 1e-12);
    /// a mean separation <= 0 is refused.
    #[test]
    fn westergaard_full_contact_is_exact() {
        let w = Wavy::new(96);
        let grid = w.grid();
        let pbar = 1.5 * w.p_star();
        let r = solve_whole(
            &grid,
            1.0,
            Target::Force(w.force(pbar)),
            true,
            &tight(),
            &mut Silent,
        )
        .unwrap();
        assert_eq!(r.summary.contact_count, w.n * w.ny);
        for (i, &p) in r.pressure.iter().enumerate() {
            let exact = pbar + w.p_star() * (2.0 * PI * w.x(i) / w.lambda).cos();
            assert!(
                (p - exact).abs() < 5e-11 * w.p_star(),
                "{i}: {p} vs {exact}"
            );
        }
        let mean = grid.height.iter().sum::<f64>() / grid.height.len() as f64;
        let refused = solve_whole(
            &grid,
            1.0,
            Target::Depth(mean),
            false,
            &tight(),
            &mut Silent,
        );
        assert!(matches!(refused, Err(Error::InvalidInput(_))));
    }

    /// An isolated Hertz contact (radius a = 16 dx = L / 16) is the same periodic and
    /// non-periodic: the same contact elements, pressures within 6.2e-3 of p0 at worst
    /// (measured; the two kernels differ at the edge elements, each 2.5-2.9e-2 from Hertz
    /// there) and 1.6e-3 apart in the L1 norm; and the depths differ by the periodic images'
    /// mean-plane offset F C / (4 pi G L), C = 3.900265 (the square lattice's Madelung
    /// constant of 1/r, -4 zeta(1/2) beta(1/2)): measured 0.9961 of it.
    #[test]
    fn isolated_hertz_contact_is_the_same_periodic_and_not() {
        let (n, dx, radius, a) = (256, 1.0 / 128.0, 1.0, 0.125f64);
        let c = n as f64 / 2.0 - 0.5;
        let r = |i: usize| (((i % n) as f64 - c) * dx).hypot(((i / n) as f64 - c) * dx);
        let h = (0..n * n).map(|i| r(i).powi(2) / (2.0 * radius)).collect();
        let grid = Grid::new(n, n, dx, h, vec![true; n * n]).unwrap();
        // Hertz: a^3 = 3 F R / (4 E*), E* = 4 G = 4 Pa
        let force = 16.0 * a.powi(3) / (3.0 * radius);
        let p0 = 3.0 * force / (2.0 * PI * a * a);
        let target = Target::Force(force);
        let per = cell(&grid, target, &tight());
        let free = solve(&grid, 1.0, StaticRequest::to(target), &tight(), &mut Silent).unwrap();
        assert_eq!(per.summary.contact_count, free.summary.contact_count);
        let (mut worst, mut l1, mut norm) = (0.0f64, 0.0, 0.0);
        for (i, (x, y)) in per.pressure.iter().zip(&free.pressure).enumerate() {
            assert_eq!(*x > 0.0, *y > 0.0, "element {i}");
            worst = worst.max((x - y).abs() / p0);
            l1 += (x - y).abs();
            norm += y;
        }
        assert!(
            worst < 2e-2 && l1 / norm < 5e-3,
            "{worst:e} {:e}",
            l1 / norm
        );
        let lattice = 3.900_264_920;
        let offset = force * lattice / (4.0 * PI * n as f64 * dx);
        let ratio = (free.summary.depth - per.summary.depth) / offset;
        assert!((ratio - 1.0).abs() < 1.5e-2, "offset ratio {ratio}");
    }

    /// The dense active set runs on the periodic operator's matrix and agrees with
    /// Polonsky–Keer on a small contact (96 elements: 4 active-set iterations against 26
    /// and 37 of Polonsky–Keer), under force and mean-separation control.
    #[test]
    fn active_set_and_polonsky_keer_agree_on_a_periodic_cell() {
        let w = Wavy::new(256);
        let grid = w.grid();
        let pbar = 0.02 * w.p_star();
        let depth = cell(&grid, Target::Force(w.force(pbar)), &tight())
            .summary
            .depth;
        for target in [Target::Force(w.force(pbar)), Target::Depth(depth)] {
            let run = |active_limit| {
                let opts = SolverOptions {
                    active_limit,
                    ..tight()
                };
                cell(&grid, target, &opts)
            };
            let (dense, pk) = (run(Some(2000)), run(Some(0)));
            assert!(dense.summary.dense && !pk.summary.dense, "{target:?}");
            assert_eq!(dense.summary.contact_count, pk.summary.contact_count);
            let peak = pk.pressure.iter().fold(0.0f64, |m, &v| m.max(v));
            for (a, b) in dense.pressure.iter().zip(&pk.pressure) {
                assert!((a - b).abs() < 1e-8 * peak, "{target:?}");
            }
            assert!((dense.summary.depth - pk.summary.depth).abs() < 1e-9 * depth.abs());
        }
    }
}
