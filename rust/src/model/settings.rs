//! How a scene is solved, below the model and the engines: the method and its resolution
//! limits, the contact solvers' tolerances, the time integrator (the implicit impulse step,
//! exact in time while the contact grows, or the paper's explicit loop, kept so that the
//! cost of that choice can be measured) and the step limits of every time-stepping engine.

use crate::support::error::{check_finite_positive, check_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// Tolerances of the iterative solvers and the choice between dense and iterative solves.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolverOptions {
    /// Relative tolerance: sum |p_k - p_{k-1}| / sum p for Polonsky–Keer, |r| / |b| for CG.
    pub tol: f64,
    /// Iteration limit; reaching it is an error.
    pub max_iter: usize,
    /// Fixed contact sets of at most this many elements are solved densely (faer).
    pub dense_limit: usize,
    /// Largest contact set (elements) of the dense active-set method, which replaces
    /// Polonsky–Keer while the estimated and iterated set stays within it; None picks the
    /// faster automatically (`Tuning::active_crossover` of the grid, at most
    /// `Tuning::active_cap`), 0 turns it off.
    pub active_limit: Option<usize>,
    /// Precondition the conjugate gradients (Polonsky–Keer and the flat punch) with the
    /// truncated inverse-kernel stencil of `precondition`: 2.5–3x fewer iterations for one
    /// stencil pass each.
    pub precondition: bool,
}

/// Default `SolverOptions::dense_limit` (elements): a fixed set alone on its window is
/// solved faster by faer's Cholesky up to 144 elements and by the preconditioned CG from 169
/// (`benchmarks/bench_dense_crossover.py`).
pub const DENSE_LIMIT: usize = 144;

impl Default for SolverOptions {
    /// Tolerance 1e-10, 5000 iterations, `DENSE_LIMIT`, automatic active set,
    /// preconditioned.
    fn default() -> Self {
        SolverOptions {
            tol: 1e-10,
            max_iter: 5000,
            dense_limit: DENSE_LIMIT,
            active_limit: None,
            precondition: true,
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

/// Most time steps a run may take, so that no step list outgrows memory (16 bytes a step).
pub const MAX_STEPS: f64 = 1e7;

/// Fails when `steps`, the time steps of `dt` (s) over `span` (s), exceed `MAX_STEPS`; the
/// message gives the count even where it overflows a double (dt = 1e-308 over 2 s is
/// 2.0e308 steps).
pub fn check_steps(dt: f64, span: f64, steps: f64) -> Result<()> {
    if steps <= MAX_STEPS {
        return Ok(());
    }
    let count = if steps.is_finite() {
        format!("{steps:.3e}")
    } else {
        let decades = span.log10() - dt.log10();
        format!("{:.1}e{}", 10f64.powf(decades.fract()), decades.trunc())
    };
    Err(Error::InvalidInput(format!(
        "dt = {dt:e} s over {span} s is {count} steps, more than {MAX_STEPS:.0e}"
    )))
}

/// The solution method.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Method {
    /// Boundary elements on an n x n grid over the footprint.
    Bem,
    /// Method of dimensionality reduction with n elements.
    Mdr,
}

impl Method {
    /// "bem" or "mdr".
    pub fn name(self) -> &'static str {
        match self {
            Method::Bem => "bem",
            Method::Mdr => "mdr",
        }
    }
}

/// Time integration of a viscous medium under a force.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Integrator {
    /// One exact impulse step per output time (no time-discretisation error while the
    /// contact grows).
    Implicit,
    /// The paper's explicit loop (its Fig. 1b).
    Explicit(ExplicitControl),
}

impl Integrator {
    /// "implicit" or "explicit".
    pub fn name(&self) -> &'static str {
        match self {
            Integrator::Implicit => "implicit",
            Integrator::Explicit(_) => "explicit",
        }
    }
}

/// Largest BEM grid side (elements).
pub const MAX_BEM_N: usize = 8192;

/// Largest MDR element count.
pub const MAX_MDR_N: usize = 1 << 26;

/// Viscoelastic steps per duration when neither the scene nor the settings give dt.
pub const DEFAULT_STEPS: f64 = 500.0;

/// Largest resolution of a method: `MAX_BEM_N` elements across a BEM footprint, `MAX_MDR_N`
/// MDR elements.
pub fn max_n(method: Method) -> usize {
    match method {
        Method::Bem => MAX_BEM_N,
        Method::Mdr => MAX_MDR_N,
    }
}

/// Resolution of a run that names none: the paper's, 257 x 257 BEM elements over the
/// footprint or 66049 MDR elements.
pub fn default_n(method: Method) -> usize {
    match method {
        Method::Bem => 257,
        Method::Mdr => 66049,
    }
}

/// How to solve a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RunSettings {
    /// BEM or MDR.
    pub method: Method,
    /// BEM: elements across the footprint (n x n grid); MDR: elements of the 1D indenter.
    pub n: usize,
    /// Contact-solver tolerances and choices (BEM).
    pub solver: SolverOptions,
    /// Time integration of a viscous medium under a force.
    pub integrator: Integrator,
    /// Longest viscoelastic time step (s), overriding the scene's.
    pub dt: Option<f64>,
}

impl RunSettings {
    /// Default settings for `method` at resolution `n`.
    pub fn new(method: Method, n: usize) -> Self {
        RunSettings {
            method,
            n,
            solver: SolverOptions::default(),
            integrator: Integrator::Implicit,
            dt: None,
        }
    }

    /// Fails on resolutions out of range or bad tolerances.
    pub fn validate(&self) -> Result<()> {
        let limit = max_n(self.method);
        if self.n == 0 || self.n > limit {
            return Err(Error::InvalidInput(format!(
                "{} resolution n must be in 1..={limit}, got {}",
                self.method.name().to_uppercase(),
                self.n
            )));
        }
        check_positive("tol", self.solver.tol)?;
        if self.solver.max_iter == 0 {
            return Err(Error::InvalidInput("max_iter must be >= 1".into()));
        }
        if let Integrator::Explicit(c) = &self.integrator {
            c.validate()?;
        }
        if let Some(dt) = self.dt {
            check_finite_positive("dt", dt)?;
        }
        Ok(())
    }
}

/// Controls of the paper's explicit loop (its Fig. 1b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExplicitControl {
    /// Relative time step: dt = step * max(t, start * t_end).
    pub step: f64,
    /// Re-solve the contact when its area grew by more than this fraction (paper: 0.01).
    pub area_change: f64,
    /// First step length as a fraction of the final output time.
    pub start: f64,
}

impl Default for ExplicitControl {
    fn default() -> Self {
        ExplicitControl {
            step: 0.01,
            area_change: 0.01,
            start: 1e-6,
        }
    }
}

/// Largest relative step of the explicit loop: dt = step * t beyond 1 jumps past the time
/// it steps from (depths 41 % high at 100 and 650 times at 1e6 on the paper's paraboloid).
pub const MAX_EXPLICIT_STEP: f64 = 1.0;

/// Relative steps of the explicit loop above this are solved with a warning: its error is
/// first order in the step (below 1 % at 0.1 on the paper's paraboloid by BEM at n = 65).
pub const EXPLICIT_WARN_STEP: f64 = 0.1;

impl ExplicitControl {
    /// Fails unless step and start are positive, step at most `MAX_EXPLICIT_STEP`, and
    /// area_change >= 0.
    pub fn validate(&self) -> Result<()> {
        check_finite_positive("explicit step", self.step)?;
        if self.step > MAX_EXPLICIT_STEP {
            return Err(Error::InvalidInput(format!(
                "explicit step = {} is more than {MAX_EXPLICIT_STEP}: the loop's steps dt = step * t would jump past the time they step from (its error is first order in the step); use a smaller step or the implicit integrator",
                self.step
            )));
        }
        check_positive("explicit start fraction", self.start)?;
        // dt = step * t_first up to t_first, then growing by (1 + step) a step
        let steps = 1.0 / self.step + (1.0 / self.start).ln() / self.step.ln_1p();
        if steps > crate::model::settings::MAX_STEPS {
            return Err(Error::InvalidInput(format!(
                "explicit step = {} takes about {steps:.3e} steps, more than {:.0e}",
                self.step,
                crate::model::settings::MAX_STEPS
            )));
        }
        if !(self.area_change >= 0.0 && self.area_change.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "area_change must be finite and >= 0, got {}",
                self.area_change
            )));
        }
        Ok(())
    }

    /// A warning for a step above `EXPLICIT_WARN_STEP`, whose first-order error shows.
    pub fn warning(&self) -> Option<String> {
        (self.step > EXPLICIT_WARN_STEP).then(|| {
            format!(
                "explicit step = {} > {EXPLICIT_WARN_STEP}: the loop's error is first order in the step (several percent near 1); lower it or use the implicit integrator",
                self.step
            )
        })
    }

    /// The step (dt, t + dt) from `t`, with first step `t_first` (s), clipped to land exactly
    /// on `target`.
    pub fn next_step(&self, t: f64, t_first: f64, target: f64) -> (f64, f64) {
        let remaining = target - t;
        let dt = (self.step * t.max(t_first)).min(remaining);
        (dt, if dt == remaining { target } else { t + dt })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps grow geometrically by (1 + step) after the first, land exactly on the target, and
    /// their count is the estimate `validate` bounds, to within the clipped last steps.
    #[test]
    fn steps_grow_geometrically_and_land_on_the_target() {
        let c = ExplicitControl::default();
        let (t_end, t_first) = (5.0, 5.0 * c.start);
        let (mut t, mut count, mut last) = (0.0, 0usize, (0.0, 0.0));
        while t < t_end {
            let (dt, next) = c.next_step(t, t_first, t_end);
            // once the previous step started at or past t_first, each is (1 + step) longer
            if last.0 >= t_first && next < t_end {
                assert!((dt / last.1 - (1.0 + c.step)).abs() < 1e-9, "t = {t}");
            }
            (last, t, count) = ((t, dt), next, count + 1);
        }
        assert_eq!(t, t_end);
        let bound = 1.0 / c.step + (1.0 / c.start).ln() / c.step.ln_1p();
        assert!((count as f64 - bound).abs() <= 2.0, "{count} vs {bound}");
    }

    #[test]
    fn bad_controls_are_refused_by_name() {
        let bad = |c: ExplicitControl, word: &str| {
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        };
        let base = ExplicitControl::default();
        bad(ExplicitControl { step: 0.0, ..base }, "explicit step");
        bad(ExplicitControl { step: 1e-9, ..base }, "steps, more than");
        bad(
            ExplicitControl {
                start: -1.0,
                ..base
            },
            "start fraction",
        );
        bad(
            ExplicitControl {
                area_change: -0.1,
                ..base
            },
            "area_change",
        );
        assert!(ExplicitControl {
            area_change: 0.0,
            ..base
        }
        .validate()
        .is_ok());
    }
}
