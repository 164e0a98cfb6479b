//! The dense primal-dual active-set solve (Hintermüller et al. 2002) for small contact
//! sets: faer's Cholesky factorisation of the influence matrix on the set, iterated over
//! the set until it repeats.

use super::{ContactSolver, ContactSummary, Problem, Target};
use crate::halfspace::influence;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::contact_law::{ContactLaw, SortedSurface};
use crate::model::settings::SolverOptions;
use crate::support::error::Result;
use crate::support::monitor::Monitor;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};

/// Where a dense active-set solve starts (`ContactSolver::active_start`): the start set and
/// the largest set the solve may reach (elements).
pub(super) struct ActiveStart {
    set: Vec<usize>,
    limit: usize,
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// The start set of the dense active-set solve on `pb`: the elements with pressure
    /// (`warm`), else those of a Winkler foundation with the self-influence coefficient
    /// (force control) or those that overlap (depth control); None when it is empty or
    /// exceeds the limit (`opts.active_limit`, or automatic), so that a solve the dense
    /// method declines copies nothing. A warm set is counted only up to the limit.
    pub(super) fn active_start(
        &self,
        pb: &Problem,
        warm: bool,
        opts: &SolverOptions,
    ) -> Option<ActiveStart> {
        let n = self.p.len();
        let (dx, c) = (self.op.dx(), pb.compliance);
        let limit = self.active_limit(n, opts);
        let start = if warm {
            let in_set = |i: &usize| pb.allowed[*i] && self.p[*i] > 0.0;
            (0..n)
                .filter(in_set)
                .nth(limit)
                .is_none()
                .then(|| (0..n).filter(in_set).collect())
        } else {
            match pb.target {
                Target::Depth(d) => overlap_set(pb.h, pb.allowed, d - pb.gap_tol, limit),
                Target::Force(w) => {
                    let stiffness = 1.0 / (c * influence::coefficient(0, 0, dx));
                    winkler_set(pb.h, pb.allowed, w / (dx * dx * stiffness), limit)
                }
            }
        };
        start
            .filter(|s: &Vec<usize>| !s.is_empty())
            .map(|set| ActiveStart { set, limit })
    }

    /// The largest set of the dense active-set solve on a grid of `n` elements:
    /// `opts.active_limit`, else the tuning's crossover capped at `active_cap`.
    fn active_limit(&self, n: usize, opts: &SolverOptions) -> usize {
        let tuning = self.tuning;
        opts.active_limit
            .unwrap_or_else(|| tuning.active_crossover(n).min(tuning.active_cap))
    }

    /// Dense primal-dual active-set solve (Hintermüller et al. 2002) from `start`
    /// (`active_start`: the start set and the limit): on the set S solve compliance
    /// K_SS p_S = d - h_S (with sum p_S dA = W under force control) by faer's Cholesky,
    /// then drop elements with p <= 0 and add those that overlap (one operator apply for
    /// the gaps), until the set repeats; the solution is then exact up to round-off. None
    /// when an iterate exceeds `active_overshoot` times the limit, the iteration takes more
    /// than `active_max_iter` iterations or cycles, or K_SS is not positive definite: the
    /// caller falls back to Polonsky–Keer.
    pub(super) fn solve_active_set(
        &mut self,
        pb: &Problem,
        start: ActiveStart,
        monitor: &mut dyn Monitor,
    ) -> Result<Option<ContactSummary>> {
        let n = self.p.len();
        let (dx, c) = (self.op.dx(), pb.compliance);
        let area = dx * dx;
        let tuning = self.tuning;
        let ActiveStart { mut set, limit } = start;
        let mut member = vec![false; n];
        for it in 1..=tuning.active_max_iter {
            let m = set.len();
            let k = self.op.submatrix(&set)?;
            let Ok(llt) = k.llt(Side::Lower) else {
                return Ok(None);
            };
            let rhs = Mat::from_fn(m, 2, |j, col| if col == 0 { 1.0 } else { pb.h[set[j]] });
            let sol = llt.solve(&rhs);
            let ones: f64 = (0..m).map(|j| sol[(j, 0)]).sum();
            let heights: f64 = (0..m).map(|j| sol[(j, 1)]).sum();
            let d = match pb.target {
                Target::Force(w) => (w * c / area + heights) / ones,
                Target::Depth(d) => d,
            };
            self.p.fill(0.0);
            for (j, &i) in set.iter().enumerate() {
                self.p[i] = (d * sol[(j, 0)] - sol[(j, 1)]) / c;
                member[i] = true;
            }
            self.op.apply(&self.p, &mut self.u);
            let next: Vec<usize> = (0..n)
                .filter(|&i| {
                    pb.allowed[i]
                        && if member[i] {
                            self.p[i] > 0.0
                        } else {
                            c * self.u[i] + pb.h[i] - d < -pb.gap_tol
                        }
                })
                .collect();
            set.iter().for_each(|&i| member[i] = false);
            monitor.progress("active-set iterations", it, tuning.active_max_iter)?;
            if next == set {
                self.u.iter_mut().for_each(|v| *v *= c);
                let (mut misfit, mut scale) = (0.0, 0.0);
                for &i in &set {
                    misfit += (self.u[i] + pb.h[i] - d).abs();
                    scale += (d - pb.h[i]).abs();
                }
                return Ok(Some(ContactSummary {
                    depth: d,
                    force: self.p.iter().sum::<f64>() * area,
                    iterations: it,
                    residual: if scale > 0.0 { misfit / scale } else { 0.0 },
                    contact_count: m,
                    dense: true,
                }));
            }
            // the first iterations overshoot (a small start set presses in deep): allow
            // `active_overshoot` times the limit in passing
            if next.is_empty() || next.len() > tuning.active_overshoot * limit {
                return Ok(None);
            }
            set = next;
        }
        Ok(None)
    }
}

/// Allowed elements with h < `level`; None when more than `limit`.
fn overlap_set(h: &[f64], allowed: &[bool], level: f64, limit: usize) -> Option<Vec<usize>> {
    let mut set = vec![];
    for i in (0..h.len()).filter(|&i| allowed[i] && h[i] < level) {
        if set.len() == limit {
            return None;
        }
        set.push(i);
    }
    Some(set)
}

/// Contact set of a Winkler foundation pressed into `h` until sum max(d - h_i, 0) =
/// `excess` (m) over the allowed elements; None when it holds more than `limit` elements.
/// Only the `limit + 1` lowest elements are sorted.
fn winkler_set(h: &[f64], allowed: &[bool], excess: f64, limit: usize) -> Option<Vec<usize>> {
    let mut low: Vec<(f64, usize)> = (0..h.len())
        .filter(|&i| allowed[i])
        .map(|i| (h[i], i))
        .collect();
    let by_height = |a: &(f64, usize), b: &(f64, usize)| a.0.total_cmp(&b.0);
    if low.len() > limit + 1 {
        low.select_nth_unstable_by(limit, by_height);
        low.truncate(limit + 1);
    }
    low.sort_unstable_by(by_height);
    let heights: Vec<f64> = low.iter().map(|v| v.0).collect();
    // the Winkler foundation's contact: the hard law's MDR root on the lowest heights
    let (_, k) = ContactLaw::Hard.depth_for_compression(&SortedSurface::new(&heights), excess);
    (k <= limit).then(|| low[..k.max(1)].iter().map(|v| v.1).collect())
}

#[cfg(test)]
mod tests {
    use crate::bem::contact::tests::{hertz_grid, max_abs_diff, solve_with};
    use crate::bem::contact::{ContactSummary, Target, Tuning};
    use crate::model::settings::SolverOptions;

    /// Solves `h` with the default options but `active_limit`.
    fn solve(
        h: &[f64],
        n: usize,
        dx: f64,
        target: Target,
        active_limit: Option<usize>,
    ) -> (ContactSummary, Vec<f64>) {
        let opts = SolverOptions {
            active_limit,
            ..SolverOptions::default()
        };
        solve_with(h, n, dx, target, &opts)
    }

    /// The dense active-set solve and Polonsky–Keer give the same contact (to PK's
    /// tolerance) under force and depth control; the automatic choice takes the dense solve
    /// for a small contact and Polonsky–Keer for a large one.
    #[test]
    fn active_set_and_polonsky_keer_agree() {
        let n = 64;
        let (h, dx) = hertz_grid(n, 10.0);
        for target in [Target::Force(1e-3), Target::Depth(2e-3)] {
            let (dense, p_dense) = solve(&h, n, dx, target, None);
            let (pk, p_pk) = solve(&h, n, dx, target, Some(0));
            assert!(dense.dense && !pk.dense, "{target:?}");
            assert!(dense.contact_count > 20 && dense.contact_count < 236);
            assert_eq!(dense.contact_count, pk.contact_count);
            assert!(dense.residual < 1e-12);
            let peak = p_pk.iter().fold(0.0f64, |m, &v| m.max(v));
            let diff = max_abs_diff(&p_dense, &p_pk);
            assert!(diff < 1e-8 * peak, "{target:?}: {diff} vs {peak}");
            assert!((dense.depth - pk.depth).abs() < 1e-9 * pk.depth);
            assert!((dense.force - pk.force).abs() < 1e-9 * pk.force);
        }
        let (large, _) = solve(&h, n, dx, Target::Depth(0.02), None);
        assert!(!large.dense && large.contact_count > Tuning::default().active_crossover(n * n));
    }
}
