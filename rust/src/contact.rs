//! Frictionless normal contact of a rigid indenter with a half-space: the Polonsky–Keer
//! (1999) constrained conjugate gradient (force- or displacement-controlled), and the
//! flat-punch solve on a fixed contact set (CG, or a dense Cholesky solve for small sets).
//!
//! Conventions: `h` is the separation before loading (m), `compliance` multiplies the
//! G = 1 operator (1/G for an elastic body, dt/eta or 1/eta for viscous steps), and the gap
//! is g = compliance * K[p] + h - d >= 0 with p >= 0 and p g = 0 on the allowed elements.

use crate::error::{check_finite, check_len, check_positive, Error, Result};
use crate::influence;
use crate::monitor::Monitor;
use crate::operator::{DenseOperator, SurfaceOperator};
use faer::linalg::solvers::Solve;
use faer::{ColRef, Side};

/// What the solve holds fixed: the total force (N, or N s for impulses) or the rigid-body
/// approach d (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// Sum of p over the elements times the element area.
    Force(f64),
    /// Rigid-body approach of the indenter (m, positive into the body).
    Depth(f64),
}

/// Tolerances of the iterative solvers.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Relative tolerance: sum |p_k - p_{k-1}| / sum p for Polonsky–Keer, |r| / |b| for CG.
    pub tol: f64,
    /// Iteration limit; reaching it is an error.
    pub max_iter: usize,
    /// Fixed contact sets of at most this many elements are solved densely (faer).
    pub dense_limit: usize,
}

impl Default for SolverOptions {
    fn default() -> Self {
        SolverOptions {
            tol: 1e-10,
            max_iter: 5000,
            dense_limit: 128,
        }
    }
}

impl SolverOptions {
    /// Fails unless the tolerance is in (0, 1) and the iteration limit is >= 1.
    pub fn validate(&self) -> Result<()> {
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return Err(Error::InvalidInput(format!(
                "tolerance must lie in (0, 1), got {}",
                self.tol
            )));
        }
        if self.max_iter == 0 {
            return Err(Error::InvalidInput("max_iter must be >= 1".into()));
        }
        Ok(())
    }
}

/// Summary of one contact solve; the fields live in the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSummary {
    /// Rigid-body approach d (m).
    pub depth: f64,
    /// Total force (sum p dA).
    pub force: f64,
    /// Iterations taken.
    pub iterations: usize,
    /// Final relative residual (see `SolverOptions::tol`).
    pub residual: f64,
    /// Elements with p > 0.
    pub contact_count: usize,
}

/// Polonsky–Keer solver owning its operator and work buffers (allocated once).
pub struct ContactSolver<O: SurfaceOperator> {
    op: O,
    p: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
    p_old: Vec<f64>,
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// Wraps `op`; buffers are sized to its grid.
    pub fn new(op: O) -> Self {
        let n = op.nx() * op.ny();
        ContactSolver {
            op,
            p: vec![0.0; n],
            u: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            r: vec![0.0; n],
            p_old: vec![0.0; n],
        }
    }

    /// The operator.
    pub fn operator(&mut self) -> &mut O {
        &mut self.op
    }

    /// Pressure of the last solve (Pa, or Pa s for impulse densities).
    pub fn pressure(&self) -> &[f64] {
        &self.p
    }

    /// Deflection compliance * K[p] of the last solve (m).
    pub fn deflection(&self) -> &[f64] {
        &self.u
    }

    /// Sets the pressure to zero everywhere (the indenter has left the surface).
    pub fn clear_pressure(&mut self) {
        self.p.fill(0.0);
    }

    /// Sets the starting pressure for a warm-started solve.
    pub fn set_pressure(&mut self, p: &[f64]) -> Result<()> {
        check_len("starting pressure", p.len(), self.p.len())?;
        check_finite("starting pressure", p)?;
        self.p.copy_from_slice(p);
        Ok(())
    }

    /// Solves the contact problem for separation `h` on the elements where `allowed` is
    /// true. With `warm`, starts from the current pressure (rescaled to the target force),
    /// else from a uniform pressure. The residual is measured against the larger of this
    /// solve's load and `reference` (N): a time step passes the load accumulated so far, so
    /// that a small increment is converged relative to the state it changes, not to itself
    /// (below that, round-off of the accumulated separation dominates).
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        h: &[f64],
        allowed: &[bool],
        compliance: f64,
        target: Target,
        warm: bool,
        reference: f64,
        opts: &SolverOptions,
        monitor: &mut dyn Monitor,
    ) -> Result<ContactSummary> {
        let n = self.p.len();
        check_len("separation h", h.len(), n)?;
        check_len("allowed mask", allowed.len(), n)?;
        check_finite("separation h", h)?;
        check_positive("compliance", compliance)?;
        opts.validate()?;
        let n_allowed = allowed.iter().filter(|&&a| a).count();
        if n_allowed == 0 {
            return Err(Error::InvalidInput(
                "the indenter's footprint holds no element of the grid".into(),
            ));
        }
        let area = self.op.dx() * self.op.dx();
        let force = match target {
            Target::Force(w) => {
                check_positive("force", w)?;
                Some(w)
            }
            Target::Depth(d) => {
                if !d.is_finite() {
                    return Err(Error::InvalidInput(format!(
                        "depth must be finite, got {d}"
                    )));
                }
                None
            }
        };
        let warm = warm && self.p.iter().zip(allowed).any(|(&p, &a)| a && p > 0.0);
        let self_influence = influence::coefficient(0, 0, self.op.dx());
        if !warm {
            match target {
                Target::Force(w) => {
                    let start = w / (n_allowed as f64 * area);
                    for (p, &a) in self.p.iter_mut().zip(allowed) {
                        *p = if a { start } else { 0.0 };
                    }
                }
                // Each overlapping element alone: the pressure that closes its own gap.
                Target::Depth(d) => {
                    for i in 0..n {
                        self.p[i] = if allowed[i] {
                            (d - h[i]).max(0.0) / (compliance * self_influence)
                        } else {
                            0.0
                        };
                    }
                }
            }
        }
        for (p, &a) in self.p.iter_mut().zip(allowed) {
            if !a || *p < 0.0 {
                *p = 0.0;
            }
        }
        if let Some(w) = force {
            let sum: f64 = self.p.iter().sum();
            self.p.iter_mut().for_each(|v| *v *= w / area / sum);
        }
        if let Target::Depth(d) = target {
            if h.iter().zip(allowed).all(|(&h, &a)| !a || h >= d) {
                self.p.fill(0.0);
                self.u.fill(0.0);
                return Ok(ContactSummary {
                    depth: d,
                    force: 0.0,
                    iterations: 0,
                    residual: 0.0,
                    contact_count: 0,
                });
            }
        }
        // Overlaps below round-off of the separation are no overlaps: without this, a step
        // whose load is tiny against the accumulated separation flips edge elements forever.
        let gap_tol = 1e-12
            * h.iter()
                .zip(allowed)
                .filter(|(_, &a)| a)
                .fold(0.0f64, |m, (h, _)| m.max(h.abs()));
        let mut delta = 0.0;
        let mut g_old = 1.0;
        let mut residual = f64::INFINITY;
        // u = K[p] is refreshed by an operator apply when the active set changed and every
        // 32 iterations (bounding round-off drift); otherwise it follows p by the same linear
        // update, so most iterations cost one apply.
        self.op.apply(&self.p, &mut self.u);
        for it in 1..=opts.max_iter {
            let shift = match target {
                Target::Force(_) => mean_on_contact(&self.p, allowed, &self.u, h, compliance),
                Target::Depth(d) => d,
            };
            let mut gsum = 0.0;
            for i in 0..n {
                self.g[i] = if allowed[i] {
                    compliance * self.u[i] + h[i] - shift
                } else {
                    0.0
                };
                if self.p[i] > 0.0 {
                    gsum += self.g[i] * self.g[i];
                }
            }
            let beta = if delta > 0.0 && g_old > 0.0 {
                gsum / g_old
            } else {
                0.0
            };
            g_old = gsum;
            for i in 0..n {
                self.t[i] = if self.p[i] > 0.0 {
                    self.g[i] + beta * self.t[i]
                } else {
                    0.0
                };
            }
            self.op.apply(&self.t, &mut self.r);
            let rbar = match target {
                Target::Force(_) => {
                    let (s, c) = self
                        .r
                        .iter()
                        .zip(&self.p)
                        .filter(|(_, &p)| p > 0.0)
                        .fold((0.0, 0usize), |(s, c), (r, _)| (s + r, c + 1));
                    compliance * s / c.max(1) as f64
                }
                Target::Depth(_) => 0.0,
            };
            let (mut num, mut den) = (0.0, 0.0);
            for i in 0..n {
                if self.p[i] > 0.0 {
                    num += self.g[i] * self.t[i];
                    den += (compliance * self.r[i] - rbar) * self.t[i];
                }
            }
            let tau = if den > 0.0 { num / den } else { 0.0 };
            // A degenerate CG step (e.g. a one-element contact, where g = 0 on the set) would
            // never admit the overlapping elements: seed them with pressures proportional to
            // their overlap, carrying 1 % of the load, and let the iteration grow them.
            let tau_overlap = if tau > 0.0 {
                tau
            } else {
                let (load, deficit) =
                    (0..n)
                        .filter(|&i| allowed[i])
                        .fold((0.0, 0.0), |(l, d), i| {
                            (
                                l + self.p[i],
                                if self.p[i] <= 0.0 && self.g[i] < -gap_tol {
                                    d - self.g[i]
                                } else {
                                    d
                                },
                            )
                        });
                if deficit > 0.0 {
                    0.01 * load / deficit
                } else {
                    0.0
                }
            };
            self.p_old.copy_from_slice(&self.p);
            let (mut overlap, mut clamped) = (false, false);
            for i in (0..n).filter(|&i| allowed[i]) {
                if self.p[i] > 0.0 {
                    let v = self.p[i] - tau * self.t[i];
                    clamped |= v <= 0.0;
                    self.p[i] = v.max(0.0);
                } else if self.g[i] < -gap_tol {
                    self.p[i] = -tau_overlap * self.g[i];
                    overlap = true;
                }
            }

            delta = if overlap { 0.0 } else { 1.0 };
            let mut factor = 1.0;
            let sum: f64 = self.p.iter().sum();
            match force {
                Some(w) if sum > 0.0 => {
                    factor = w / area / sum;
                    self.p.iter_mut().for_each(|v| *v *= factor);
                }
                Some(w) => {
                    let imin = argmin_gap(&self.g, allowed);
                    self.p[imin] = w / area;
                    clamped = true;
                }
                // Everything released while elements still overlap: restart from the
                // pressures that close each overlap alone.
                None if sum == 0.0 && (0..n).any(|i| allowed[i] && self.g[i] < -gap_tol) => {
                    for i in (0..n).filter(|&i| allowed[i]) {
                        self.p[i] = (-self.g[i]).max(0.0) / (compliance * self_influence);
                    }
                    clamped = true;
                }
                None => {}
            }
            if overlap || clamped || it % 32 == 0 {
                self.op.apply(&self.p, &mut self.u);
            } else {
                for i in 0..n {
                    self.u[i] = factor * (self.u[i] - tau * self.r[i]);
                }
            }
            let total: f64 = self.p.iter().sum();
            let change: f64 = self
                .p
                .iter()
                .zip(&self.p_old)
                .map(|(a, b)| (a - b).abs())
                .sum();
            residual = if total > 0.0 {
                change / total.max(reference / area)
            } else {
                0.0
            };
            if it % 16 == 0 {
                monitor.progress("contact iterations", it, opts.max_iter)?;
            }
            if residual < opts.tol {
                self.op.apply(&self.p, &mut self.u);
                self.u.iter_mut().for_each(|v| *v *= compliance);
                let depth = match target {
                    Target::Force(_) => {
                        let (s, c) = self
                            .u
                            .iter()
                            .zip(h)
                            .zip(&self.p)
                            .filter(|(_, &p)| p > 0.0)
                            .fold((0.0, 0usize), |(s, c), ((u, h), _)| (s + u + h, c + 1));
                        s / c.max(1) as f64
                    }
                    Target::Depth(d) => d,
                };
                return Ok(ContactSummary {
                    depth,
                    force: total * area,
                    iterations: it,
                    residual,
                    contact_count: self.p.iter().filter(|&&p| p > 0.0).count(),
                });
            }
        }
        Err(Error::NotConverged {
            what: "Polonsky-Keer contact solve".into(),
            iterations: opts.max_iter,
            residual,
        })
    }

    /// Flat-punch solve on a fixed contact set: the pressure (Pa at G = 1) that moves every
    /// element of `set` by exactly 1 m. Returns (pressure, iterations, relative residual).
    /// Sets of at most `opts.dense_limit` elements are factorised densely; larger ones use
    /// CG, started from `start` (restricted to the set) when given.
    pub fn unit_punch(
        &mut self,
        set: &[bool],
        start: Option<&[f64]>,
        opts: &SolverOptions,
        monitor: &mut dyn Monitor,
    ) -> Result<(Vec<f64>, usize, f64)> {
        let n = self.p.len();
        check_len("contact set", set.len(), n)?;
        opts.validate()?;
        let idx: Vec<usize> = (0..n).filter(|&i| set[i]).collect();
        if idx.is_empty() {
            return Err(Error::InvalidInput("the contact set is empty".into()));
        }
        if idx.len() <= opts.dense_limit {
            return unit_punch_dense(self.op.nx(), self.op.dx(), &idx, n);
        }
        // Conjugate gradient on K_SS x = 1 (symmetric positive definite).
        let mut x = vec![0.0; n];
        if let Some(s) = start {
            check_len("starting pressure", s.len(), n)?;
            for &i in &idx {
                x[i] = s[i];
            }
        }
        let (r, d, q) = (&mut self.g, &mut self.t, &mut self.r);
        self.op.apply(&x, q);
        for i in 0..n {
            r[i] = if set[i] { 1.0 - q[i] } else { 0.0 };
            d[i] = r[i];
        }
        let bnorm = (idx.len() as f64).sqrt();
        let mut rr: f64 = idx.iter().map(|&i| r[i] * r[i]).sum();
        if rr.sqrt() / bnorm < opts.tol {
            return Ok((x, 0, rr.sqrt() / bnorm));
        }
        for it in 1..=opts.max_iter {
            self.op.apply(d, q);
            let dq: f64 = idx.iter().map(|&i| d[i] * q[i]).sum();
            let alpha = rr / dq;
            for &i in &idx {
                x[i] += alpha * d[i];
                r[i] -= alpha * q[i];
            }
            let rr_new: f64 = idx.iter().map(|&i| r[i] * r[i]).sum();
            let res = rr_new.sqrt() / bnorm;
            if res < opts.tol {
                return Ok((x, it, res));
            }
            let beta = rr_new / rr;
            rr = rr_new;
            for &i in &idx {
                d[i] = r[i] + beta * d[i];
            }
            if it % 16 == 0 {
                monitor.progress("flat-punch CG iterations", it, opts.max_iter)?;
            }
        }
        Err(Error::NotConverged {
            what: "flat-punch conjugate gradient".into(),
            iterations: opts.max_iter,
            residual: (rr.sqrt() / bnorm),
        })
    }
}

/// Dense Cholesky solve of K_SS x = 1 on the elements `idx` (faer).
fn unit_punch_dense(nx: usize, dx: f64, idx: &[usize], n: usize) -> Result<(Vec<f64>, usize, f64)> {
    let k = DenseOperator::subset_matrix(nx, dx, idx)?;
    let llt = k.llt(Side::Lower).map_err(|e| {
        Error::Domain(format!(
            "influence matrix of the contact set is not positive definite: {e:?}"
        ))
    })?;
    let ones = vec![1.0; idx.len()];
    let sol = llt.solve(ColRef::from_slice(&ones));
    let mut x = vec![0.0; n];
    for (j, &i) in idx.iter().enumerate() {
        x[i] = sol[j];
    }
    let resid = (&k * &sol)
        .iter()
        .map(|v| (v - 1.0) * (v - 1.0))
        .sum::<f64>()
        .sqrt()
        / (idx.len() as f64).sqrt();
    Ok((x, 1, resid))
}

/// Mean of compliance * u + h over the contact set {p > 0}: the rigid-body approach that
/// makes the mean gap there vanish.
fn mean_on_contact(p: &[f64], allowed: &[bool], u: &[f64], h: &[f64], c: f64) -> f64 {
    let (mut s, mut k) = (0.0, 0usize);
    for i in 0..p.len() {
        if allowed[i] && p[i] > 0.0 {
            s += c * u[i] + h[i];
            k += 1;
        }
    }
    if k == 0 {
        0.0
    } else {
        s / k as f64
    }
}

/// Index of the allowed element with the smallest gap.
fn argmin_gap(g: &[f64], allowed: &[bool]) -> usize {
    (0..g.len())
        .filter(|&i| allowed[i])
        .min_by(|&a, &b| g[a].total_cmp(&g[b]))
        .unwrap_or(0)
}
