//! One static contact solve on the smallest window that holds the contact.
//!
//! Deflections under positive pressures are positive, so no element whose height exceeds
//! the depth can touch: under depth control the window around {h <= d} holds the whole
//! contact, and under force control so does the window around {h + u_low <= bound} for any
//! bound above the depth (e.g. from MDR), u_low a lower bound of the deflection under the
//! force (`Window::around_contact`). The windowed solution is then the full grid's, exactly.
//! A bound the solve exceeds is widened and the solve repeated.
//!
//! A periodic cell has no window: [`solve_periodic`] solves the whole cell.

use crate::contact::{ContactSolver, ContactSummary, SolverOptions, Target};
use crate::error::{check_len, Error, Result};
use crate::grid::Grid;
use crate::influence::KernelTable;
use crate::monitor::Monitor;
use crate::operator::{FftOperator, FftPlans, SurfaceOperator};
use crate::periodic::{self, PeriodicOperator};
use crate::window::Window;

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
}

/// Solves the static contact of `grid` (compliance in m/Pa per unit kernel, 1/G for an
/// elastic half-space) for `target` on the window that can touch: under depth control the
/// elements with h <= d, under force control those with h + u_low <= `depth_bound` (m; the
/// whole grid without one). Windows get a margin of 2 elements. When the solved depth exceeds the
/// bound, the bound grows by the excess and the solve repeats. `deflection` asks for the
/// deflection on the whole grid, one extra whole-grid operator when the window is smaller.
pub fn solve(
    grid: &Grid,
    compliance: f64,
    target: Target,
    depth_bound: Option<f64>,
    deflection: bool,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    let (nx, ny, n) = (grid.nx, grid.ny, grid.nx * grid.ny);
    check_len("height", grid.height.len(), n)?;
    let mut bound = match target {
        Target::Depth(d) => Some(d),
        Target::Force(_) => match depth_bound {
            Some(b) if !b.is_finite() => {
                return Err(Error::InvalidInput(format!(
                    "depth bound must be finite, got {b}"
                )))
            }
            b => b,
        },
    };
    let (h, allowed) = (&grid.height, &grid.allowed);
    let (mut h_w, mut allowed_w) = (vec![], vec![]);
    let mut plans = FftPlans::default();
    let (mut iterations, mut solves) = (0, 0);
    loop {
        let (window, table) = match bound {
            Some(b) if (0..n).any(|i| allowed[i] && h[i] <= b) => {
                let outer = Window::around(nx, ny, 2, |i| allowed[i] && h[i] <= b);
                let table = KernelTable::new(outer.wx, outer.wy, grid.dx);
                let window = match target {
                    Target::Force(f) => {
                        Window::around_contact(nx, ny, h, allowed, b, compliance * f, &table)
                    }
                    Target::Depth(_) => outer,
                };
                (window, table)
            }
            _ => (Window::full(nx, ny), KernelTable::new(nx, ny, grid.dx)),
        };
        window.gather(h, &mut h_w);
        window.gather(allowed, &mut allowed_w);
        let op = FftOperator::with_kernel(window.wx, window.wy, &table, &mut plans)?;
        let mut solver = ContactSolver::new(op);
        let mut summary = solver.solve(
            &h_w, &allowed_w, compliance, target, false, 0.0, opts, monitor,
        )?;
        solves += 1;
        iterations += summary.iterations;
        match bound {
            Some(b) if !window.is_full() && summary.depth > b => {
                bound = Some(summary.depth + (summary.depth - b));
                continue;
            }
            _ => {}
        }
        summary.iterations = iterations;
        let mut pressure = vec![0.0; n];
        window.scatter(solver.pressure(), &mut pressure);
        let deflection = match (deflection, window.is_full()) {
            (false, _) => None,
            (true, true) => Some(solver.deflection().to_vec()),
            (true, false) => {
                let mut u = vec![0.0; n];
                FftOperator::new(nx, ny, grid.dx)?.apply(&pressure, &mut u);
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
        });
    }
}

/// Solves the static contact of a periodic cell: `grid` is one period (its heights the
/// separation h before loading, m; the whole cell is solved, `allowed` still masks elements
/// out), `compliance` multiplies the G = 1 periodic operator (`PeriodicOperator`; 1/G for
/// an elastic body, m/Pa). `Target::Force` is the total force on the cell (N: mean
/// pressure times the cell area nx ny dx^2); `Target::Depth(d)` is the rigid-body approach
/// from the mean plane of the deflected surface, so that the mean separation is
/// mean(h) - d (`periodic::depth_at_mean_separation` converts a mean separation; it must
/// be > 0, since full contact takes an unbounded force in depth control). The summary's
/// depth is that approach; the window is the whole cell and `solves` 1. Polonsky–Keer runs
/// on the whole cell; the dense active set applies as for a non-periodic grid (with the
/// periodic operator's matrix), and declines full contact, where that matrix is singular.
pub fn solve_periodic(
    grid: &Grid,
    compliance: f64,
    target: Target,
    deflection: bool,
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<StaticContact> {
    let (nx, ny) = (grid.nx, grid.ny);
    check_len("height", grid.height.len(), nx * ny)?;
    if let Target::Depth(d) = target {
        let separation = periodic::mean_separation(&grid.height, d);
        if separation.is_nan() || separation <= 0.0 {
            return Err(Error::InvalidInput(format!(
                "the mean separation of a periodic cell must be > 0 m, got {separation:e} m \
                 (depth {d:e} m)"
            )));
        }
    }
    let mut solver = ContactSolver::new(PeriodicOperator::new(nx, ny, grid.dx)?);
    let summary = solver.solve(
        &grid.height,
        &grid.allowed,
        compliance,
        target,
        false,
        0.0,
        opts,
        monitor,
    )?;
    Ok(StaticContact {
        summary,
        pressure: solver.pressure().to_vec(),
        deflection: deflection.then(|| solver.deflection().to_vec()),
        window: Window::full(nx, ny),
        solves: 1,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::monitor::Silent;

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
        let run =
            |target, bound| solve(&grid, 1.0, target, bound, true, &opts, &mut Silent).unwrap();
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

    /// A non-finite bound is refused.
    #[test]
    fn a_nan_bound_is_refused() {
        let grid = hertz();
        let r = solve(
            &grid,
            1.0,
            Target::Force(0.02),
            Some(f64::NAN),
            false,
            &SolverOptions::default(),
            &mut Silent,
        );
        assert!(matches!(r, Err(Error::InvalidInput(_))));
    }
}
