//! Adhesive contact by BEM with a cohesive-zone law (`ContactLaw::MaugisDugdale`,
//! `ContactLaw::Exponential`): the total pressure is p = p_c + q, with p_c >= 0 the hard
//! contact's compression and q = -t(g) <= 0 the law's traction at the gap g (in contact,
//! g = 0, too), under depth control.
//!
//! The solve is a fixed point on the adhesive traction (as in Bazrafshan, Rey et al. 2017
//! for the Maugis–Dugdale zone): with q frozen, the surface lifted by compliance * K[q]
//! meets the indenter in a hard contact, solved by the hard-contact solver
//! (`ContactSolver`, Polonsky–Keer or the dense active set, warm-started) on the separation
//! h + compliance * K[q]; its gap gives the next traction. Under Maugis–Dugdale the
//! traction is -sigma0 on the zone {g <= h0} and the sweeps end when the zone stops
//! changing, the answer then exact up to the hard solve's tolerance. Under the exponential
//! law each element's traction is updated by one Newton step on its own equation
//! q_i = -t(g_i), its gap following q_i through the self-compliance s:
//! q_i <- q_i - (q_i + t(g_i)) / (1 - s t'(g_i)) (a Jacobi–Newton sweep), and the sweeps
//! end when the traction changes by less than `opts.tol` of t(0).
//!
//! The fixed point follows the loading history: a warm solve starts from the previous
//! traction, so that a retracting indenter keeps the zone it had (the branch a
//! depth-controlled retract follows until it jumps out). The elastic energy of the element
//! scale must stay below the law's: sigma0 dx / (E* h0) (Maugis–Dugdale) or
//! w dx / (E* rho^2) (exponential) well below 1, which is also what resolving the zone takes;
//! `SWEEPS` bounds the sweeps.

use crate::bem::contact::{ContactSolver, Target};
use crate::bem::static_contact::load_to_separation;
use crate::halfspace::influence;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::contact_law::ContactLaw;
use crate::model::grid::Grid;
use crate::model::settings::SolverOptions;
use crate::support::error::{check_len, check_positive, Error, Result};
use crate::support::monitor::Monitor;

/// Most fixed-point sweeps of one cohesive solve.
pub const SWEEPS: usize = 400;

/// Summary of one cohesive solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CohesiveSummary {
    /// Rigid-body approach d (m).
    pub depth: f64,
    /// Total force (N; tensile: negative).
    pub force: f64,
    /// Elements in contact (gap 0, p_c > 0).
    pub contact_count: usize,
    /// Elements out of contact within the law's range (gap <= h0, or <= rho for the
    /// exponential law): the adhesive zone.
    pub zone_count: usize,
    /// Fixed-point sweeps taken.
    pub sweeps: usize,
    /// Hard-contact iterations summed over the sweeps.
    pub iterations: usize,
    /// Final relative residual of the last hard solve.
    pub residual: f64,
}

/// The state of a cohesive solve on one grid (its traction is what a warm solve starts
/// from); the hard-contact solver it drives is passed to each solve.
pub struct CohesiveSolver {
    law: ContactLaw,
    /// Adhesive traction q (Pa, <= 0).
    q: Vec<f64>,
    /// K[q] at G = 1.
    kq: Vec<f64>,
    /// Separation h + compliance K[q] (m).
    lifted: Vec<f64>,
    /// Gap (m).
    gap: Vec<f64>,
    /// Total pressure p_c + q (Pa).
    p: Vec<f64>,
}

impl CohesiveSolver {
    /// A solver for `law` (a cohesive one) on a grid of `n` elements, its traction zero.
    pub fn new(law: ContactLaw, n: usize) -> Result<Self> {
        law.validate()?;
        if !law.is_cohesive() {
            return Err(Error::InvalidInput(format!(
                "the cohesive BEM solve takes contact 'maugis_dugdale' or 'exponential', not '{}'",
                law.name()
            )));
        }
        Ok(CohesiveSolver {
            law,
            q: vec![0.0; n],
            kq: vec![0.0; n],
            lifted: vec![0.0; n],
            gap: vec![0.0; n],
            p: vec![0.0; n],
        })
    }

    /// Total pressure p_c + q of the last solve (Pa; tensile: negative).
    pub fn pressure(&self) -> &[f64] {
        &self.p
    }

    /// Gap of the last solve (m, >= 0).
    pub fn gap(&self) -> &[f64] {
        &self.gap
    }

    /// Zeroes the traction (the next solve starts cold).
    pub fn clear(&mut self) {
        self.q.fill(0.0);
    }

    /// Solves the adhesive contact for the approach `depth` (m) on the separation `h` (m)
    /// at `compliance` (multiplying the G = 1 operator of `hard`), on the elements
    /// `allowed`. With `warm`, starts from the last traction and hard pressure, else from
    /// the traction at the rigid gap max(h - d, 0) and no pressure. A body whose
    /// depth-controlled cold start goes through force control (`loads_depth_by_force`,
    /// a periodic cell) passes `by_force`.
    #[allow(clippy::too_many_arguments)]
    pub fn solve<O: SurfaceOperator>(
        &mut self,
        hard: &mut ContactSolver<O>,
        h: &[f64],
        allowed: &[bool],
        compliance: f64,
        depth: f64,
        warm: bool,
        by_force: bool,
        opts: &SolverOptions,
        monitor: &mut dyn Monitor,
    ) -> Result<CohesiveSummary> {
        let n = self.q.len();
        check_len("separation h", h.len(), n)?;
        check_len("allowed mask", allowed.len(), n)?;
        check_positive("compliance", compliance)?;
        if !depth.is_finite() {
            return Err(Error::InvalidInput(format!(
                "depth must be finite, got {depth}"
            )));
        }
        let law = self.law;
        let dx = hard.operator().dx();
        let area = dx * dx;
        let self_compliance = compliance * influence::coefficient(0, 0, dx);
        let t0 = law.traction(0.0);
        if !warm {
            for i in 0..n {
                self.q[i] = if allowed[i] {
                    -law.traction((h[i] - depth).max(0.0))
                } else {
                    0.0
                };
            }
            hard.clear_pressure();
        }
        let (mut iterations, mut residual) = (0, 0.0);
        let mut started = warm;
        for sweep in 1..=SWEEPS {
            hard.operator().apply(&self.q, &mut self.kq);
            for i in 0..n {
                self.lifted[i] = h[i] + compliance * self.kq[i];
            }
            if !started && by_force {
                let mean_sep = self.lifted.iter().sum::<f64>() / n as f64 - depth;
                if mean_sep > 0.0 && self.lifted.iter().any(|&v| v < depth) {
                    iterations += load_to_separation(
                        hard,
                        &self.lifted,
                        allowed,
                        dx,
                        compliance,
                        mean_sep,
                        opts,
                        monitor,
                    )?;
                    started = true;
                }
            }
            let r = hard.solve(
                &self.lifted,
                allowed,
                compliance,
                Target::Depth(depth),
                started,
                0.0,
                opts,
                monitor,
            )?;
            started = r.contact_count > 0;
            iterations += r.iterations;
            residual = r.residual;
            let (pc, u) = (hard.pressure(), hard.deflection());
            let (mut changed, mut change) = (0usize, 0.0f64);
            for i in 0..n {
                if !allowed[i] {
                    self.gap[i] = 0.0;
                    continue;
                }
                let g = if pc[i] > 0.0 {
                    0.0
                } else {
                    (u[i] + self.lifted[i] - depth).max(0.0)
                };
                self.gap[i] = g;
                let next = match law {
                    ContactLaw::MaugisDugdale { .. } => -law.traction(g),
                    _ if pc[i] > 0.0 => -t0,
                    _ => {
                        // one Newton step on q + t(g(q)) = 0, g moving by s per unit q
                        let t = law.traction(g);
                        let slope = 1.0 - self_compliance * t / law.range();
                        let step = (self.q[i] + t) / slope.max(0.5);
                        self.q[i] - step
                    }
                };
                if next != self.q[i] {
                    changed += 1;
                    change = change.max((next - self.q[i]).abs());
                }
                self.q[i] = next;
            }
            monitor.progress("cohesive sweeps", sweep, SWEEPS)?;
            let done = match law {
                ContactLaw::MaugisDugdale { .. } => changed == 0,
                _ => change <= opts.tol * t0,
            };
            if done {
                let mut force = 0.0;
                let (mut contact_count, mut zone_count) = (0, 0);
                let range = law.range();
                for i in 0..n {
                    self.p[i] = pc[i] + self.q[i];
                    force += self.p[i];
                    if pc[i] > 0.0 {
                        contact_count += 1;
                    } else if allowed[i] && self.gap[i] <= range {
                        zone_count += 1;
                    }
                }
                return Ok(CohesiveSummary {
                    depth,
                    force: force * area,
                    contact_count,
                    zone_count,
                    sweeps: sweep,
                    iterations,
                    residual,
                });
            }
        }
        Err(Error::NotConverged {
            what: format!("cohesive ({}) contact sweeps", law.name()),
            iterations: SWEEPS,
            residual,
        })
    }
}

/// The static adhesive contact of `grid` (compliance in m/Pa per unit kernel, 1/G for an
/// elastic half-space) at each approach of `depths` (m) in turn, each solve warm-started
/// from the last: a depth-controlled load curve, approach and retract, that follows its
/// history. The whole grid is solved on its body's operator (free or periodic).
pub fn depth_curve(
    grid: &Grid,
    compliance: f64,
    law: ContactLaw,
    depths: &[f64],
    opts: &SolverOptions,
    monitor: &mut dyn Monitor,
) -> Result<Vec<CohesiveSummary>> {
    let (nx, ny) = (grid.nx, grid.ny);
    check_len("height", grid.height.len(), nx * ny)?;
    let mut hard = ContactSolver::new(grid.body.operator(nx, ny, grid.dx)?);
    let mut solver = CohesiveSolver::new(law, nx * ny)?;
    let mean_height = grid.height.iter().sum::<f64>() / (nx * ny) as f64;
    let by_force = grid.body.loads_depth_by_force();
    let mut out = Vec::with_capacity(depths.len());
    for (k, &d) in depths.iter().enumerate() {
        grid.body.check_depth(mean_height, d)?;
        let s = solver.solve(
            &mut hard,
            &grid.height,
            &grid.allowed,
            compliance,
            d,
            k > 0,
            by_force,
            opts,
            monitor,
        )?;
        out.push(s);
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::support::monitor::Silent;
    use std::f64::consts::PI;

    /// Maugis's (1992) parametric solution in Johnson & Greenwood's (1997) reduced variables
    /// A = a (4 E* / (3 pi w R^2))^(1/3), P = F / (pi w R): for a contact radius A, the ratio
    /// m = c / a of zone to contact radius solves
    /// lambda A^2 / 2 [sqrt(m^2-1) + (m^2-2) atan sqrt(m^2-1)]
    ///   + 4 lambda^2 A / 3 [sqrt(m^2-1) atan sqrt(m^2-1) - m + 1] = 1,
    /// and P = A^3 - lambda A^2 [sqrt(m^2-1) + m^2 atan sqrt(m^2-1)].
    /// Returns P at A (bisection on m; the left side grows with m).
    fn maugis_force(lambda: f64, a: f64) -> f64 {
        let lhs = |m: f64| {
            let s = (m * m - 1.0).sqrt();
            let t = s.atan();
            lambda * a * a / 2.0 * (s + (m * m - 2.0) * t)
                + 4.0 * lambda * lambda * a / 3.0 * (s * t - m + 1.0)
        };
        let (mut lo, mut hi) = (1.0, 2.0);
        while lhs(hi) < 1.0 {
            lo = hi;
            hi *= 2.0;
        }
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if lhs(mid) < 1.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        let m = 0.5 * (lo + hi);
        let s = (m * m - 1.0).sqrt();
        a * a * a - lambda * a * a * (s + m * m * s.atan())
    }

    /// Maugis's pull-off force in units of pi w R: the least P over contact radii A > 0
    /// (a fine scan refined by golden sections).
    fn maugis_pull_off(lambda: f64) -> f64 {
        let f = |a: f64| maugis_force(lambda, a);
        let grid: Vec<f64> = (1..=400).map(|k| k as f64 * 0.005).collect();
        let best = grid
            .iter()
            .copied()
            .min_by(|x, y| f(*x).total_cmp(&f(*y)))
            .unwrap();
        let (mut lo, mut hi) = ((best - 0.005).max(1e-6), best + 0.005);
        let r = 0.5 * (5f64.sqrt() - 1.0);
        for _ in 0..100 {
            let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
            if f(x1) < f(x2) {
                hi = x2;
            } else {
                lo = x1;
            }
        }
        -f(0.5 * (lo + hi))
    }

    /// The reduced pull-off tends to JKR's 3/2 at large lambda and DMT's 2 at small lambda
    /// (Maugis 1992, Johnson & Greenwood 1997 fig. 3): the reference of the BEM tests.
    #[test]
    fn maugis_reference_has_its_limits() {
        assert!((maugis_pull_off(20.0) - 1.5).abs() < 0.02);
        assert!((maugis_pull_off(0.02) - 2.0).abs() < 0.02);
        let mut last = 2.1;
        for lambda in [0.1, 0.3, 0.5, 1.0, 2.0, 5.0] {
            let p = maugis_pull_off(lambda);
            assert!(p < last && p > 1.5, "{lambda}: {p}");
            last = p;
        }
    }

    /// A sphere R = 1 m (paraboloid) on an elastic half-space of E* = 4 Pa (G = 1 Pa, the
    /// compliance 1), with work of adhesion w and sigma0 set by lambda:
    /// lambda = 2 sigma0 (R / (pi w E*^2))^(1/3). The grid of n x n elements spans `side`.
    fn md_sphere(n: usize, side: f64) -> Grid {
        let dx = side / n as f64;
        let c = (n as f64 - 1.0) / 2.0;
        let h = (0..n * n)
            .map(|i| {
                let (x, y) = (((i % n) as f64 - c) * dx, ((i / n) as f64 - c) * dx);
                (x * x + y * y) / 2.0
            })
            .collect();
        Grid::new(n, n, dx, h, vec![true; n * n]).unwrap()
    }

    /// The Maugis–Dugdale law with work of adhesion `w` at transition parameter `lambda`
    /// (R = 1 m, E* = 4 Pa).
    fn md_law(w: f64, lambda: f64) -> ContactLaw {
        let stress = lambda / 2.0 * (PI * w * 16.0).cbrt();
        ContactLaw::MaugisDugdale {
            work_of_adhesion: w,
            stress,
        }
    }

    /// Approach to `d_max`, then retract in `steps` steps until the contact and zone are
    /// gone; the least force over the retract (N).
    fn pull_off(grid: &Grid, law: ContactLaw, d_max: f64, d_min: f64, steps: usize) -> f64 {
        let depths: Vec<f64> = (0..=steps)
            .map(|k| d_max - (d_max - d_min) * k as f64 / steps as f64)
            .collect();
        let curve = depth_curve(grid, 1.0, law, &depths, &SolverOptions::default(), &mut Silent)
            .unwrap();
        let sweeps: usize = curve.iter().map(|s| s.sweeps).sum();
        let its: usize = curve.iter().map(|s| s.iterations).sum();
        eprintln!("sweeps {sweeps} iterations {its}");
        curve.iter().map(|s| s.force).fold(f64::INFINITY, f64::min)
    }

    /// Maugis–Dugdale at lambda = 1: the BEM pull-off converges to Maugis's under mesh
    /// refinement.
    #[test]
    fn maugis_dugdale_pull_off_converges() {
        let w = 0.01;
        let lambda = 1.0;
        let reference = maugis_pull_off(lambda) * PI * w;
        let law = md_law(w, lambda);
        for n in [32, 64, 128] {
            let grid = md_sphere(n, 1.2);
            let f = pull_off(&grid, law, 0.02, -0.08, 50);
            eprintln!("n = {n}: {f} vs {}", -reference);
        }
    }
}
