//! The flat-punch solve: the pressure that moves a fixed contact set rigidly by 1 m, by
//! (preconditioned) conjugate gradients on the set, or by a dense Cholesky solve (faer) for
//! small sets.

use super::ContactSolver;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::settings::SolverOptions;
use crate::support::error::{check_len, Error, Result};
use crate::support::monitor::Monitor;
use crate::support::pool::KeepAwake;
use faer::linalg::solvers::Solve;
use faer::{ColRef, Mat, Side};

impl<O: SurfaceOperator> ContactSolver<O> {
    /// Flat-punch solve on a fixed contact set: the pressure (Pa at G = 1) that moves every
    /// element of `set` by exactly 1 m, left as the solver's pressure (`pressure()`).
    /// Returns (iterations, relative residual). Sets of at most `opts.dense_limit` elements
    /// are factorised densely; larger ones use CG, started from `start` (restricted to the
    /// set) when given, in the solver's buffers.
    pub fn unit_punch(
        &mut self,
        set: &[bool],
        start: Option<&[f64]>,
        opts: &SolverOptions,
        monitor: &mut dyn Monitor,
    ) -> Result<(usize, f64)> {
        // every CG iteration is a few parallel loops of well under a millisecond each
        let _awake = KeepAwake::new();
        let n = self.p.len();
        check_len("contact set", set.len(), n)?;
        opts.validate()?;
        self.tuning.validate()?;
        if let Some(s) = start {
            check_len("starting pressure", s.len(), n)?;
        }
        self.set_idx.clear();
        self.set_idx.extend((0..n).filter(|&i| set[i]));
        let idx = &self.set_idx;
        if idx.is_empty() {
            return Err(Error::InvalidInput("the contact set is empty".into()));
        }
        let x = &mut self.p;
        x.fill(0.0);
        if idx.len() <= opts.dense_limit {
            return unit_punch_dense(self.op.submatrix(idx)?, idx, x);
        }
        // Conjugate gradient on K_SS x = 1 (symmetric positive definite), preconditioned by
        // the inverse-kernel stencil restricted to the set unless turned off.
        if let Some(s) = start {
            for &i in idx {
                x[i] = s[i];
            }
        }
        let (r, d, q, z) = (&mut self.g, &mut self.t, &mut self.r, &mut self.z);
        self.op.apply(x, q);
        for i in 0..n {
            r[i] = if set[i] { 1.0 - q[i] } else { 0.0 };
        }
        // z = M r on the set (M = the stencil or 1); returns r . z over the set
        let apply_m = |op: &mut O, r: &[f64], z: &mut [f64]| {
            if opts.precondition {
                op.precondition(r, z);
            } else {
                z.copy_from_slice(r);
            }
            idx.iter().map(|&i| r[i] * z[i]).sum::<f64>()
        };
        let mut rz = apply_m(&mut self.op, r, z);
        d.fill(0.0);
        for &i in idx {
            d[i] = z[i];
        }
        let bnorm = (idx.len() as f64).sqrt();
        let mut rr: f64 = idx.iter().map(|&i| r[i] * r[i]).sum();
        if rr.sqrt() / bnorm < opts.tol {
            return Ok((0, rr.sqrt() / bnorm));
        }
        for it in 1..=opts.max_iter {
            self.op.apply(d, q);
            let dq: f64 = idx.iter().map(|&i| d[i] * q[i]).sum();
            let alpha = rz / dq;
            for &i in idx {
                x[i] += alpha * d[i];
                r[i] -= alpha * q[i];
            }
            rr = idx.iter().map(|&i| r[i] * r[i]).sum();
            let res = rr.sqrt() / bnorm;
            if res < opts.tol {
                return Ok((it, res));
            }
            let rz_new = apply_m(&mut self.op, r, z);
            let beta = rz_new / rz;
            rz = rz_new;
            for &i in idx {
                d[i] = z[i] + beta * d[i];
            }
            if it % self.tuning.progress_every == 0 {
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

/// Dense Cholesky solve of K_SS x = 1 on the elements `idx` (faer), K_SS = `k` (the
/// operator's matrix among them), written into `x` (zero elsewhere beforehand); returns
/// (1, relative residual).
fn unit_punch_dense(k: Mat<f64>, idx: &[usize], x: &mut [f64]) -> Result<(usize, f64)> {
    let llt = k.llt(Side::Lower).map_err(|e| {
        Error::Domain(format!(
            "influence matrix of the contact set is not positive definite: {e:?}"
        ))
    })?;
    let ones = vec![1.0; idx.len()];
    let sol = llt.solve(ColRef::from_slice(&ones));
    for (j, &i) in idx.iter().enumerate() {
        x[i] = sol[j];
    }
    let resid = (&k * &sol)
        .iter()
        .map(|v| (v - 1.0) * (v - 1.0))
        .sum::<f64>()
        .sqrt()
        / (idx.len() as f64).sqrt();
    Ok((1, resid))
}

#[cfg(test)]
mod tests {
    use crate::bem::contact::tests::{hertz_grid, max_abs_diff};
    use crate::bem::contact::ContactSolver;
    use crate::halfspace::operator::FftOperator;
    use crate::model::settings::SolverOptions;
    use crate::support::monitor::Silent;

    /// The preconditioned and the plain flat-punch CG reach the dense Cholesky solve's
    /// pressure (to the tolerance), the preconditioned one in at most half the iterations.
    #[test]
    fn preconditioning_keeps_the_punch_and_saves_iterations() {
        let n = 96;
        let (h, dx) = hertz_grid(n, 1.0);
        let set: Vec<bool> = h.iter().map(|&v| v < 0.2).collect();
        let punch = |precondition, dense_limit| {
            let opts = SolverOptions {
                precondition,
                dense_limit,
                ..SolverOptions::default()
            };
            let mut solver = ContactSolver::new(FftOperator::new(n, n, dx).unwrap());
            let (its, res) = solver.unit_punch(&set, None, &opts, &mut Silent).unwrap();
            (solver.pressure().to_vec(), its, res)
        };
        let (dense, _, _) = punch(true, usize::MAX);
        let (p_plain, it_plain, _) = punch(false, 0);
        let (p_pre, it_pre, res) = punch(true, 0);
        assert!(res < 1e-10);
        let peak = dense.iter().fold(0.0f64, |m, &v| m.max(v));
        assert!(max_abs_diff(&dense, &p_pre) < 1e-8 * peak);
        assert!(max_abs_diff(&dense, &p_plain) < 1e-8 * peak);
        assert!(
            2 * it_pre <= it_plain,
            "{it_pre} preconditioned vs {it_plain} plain"
        );
    }
}
