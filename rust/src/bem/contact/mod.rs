//! Frictionless normal contact of a rigid indenter with a half-space: the Polonsky–Keer
//! (1999) constrained conjugate gradient (force- or displacement-controlled), a dense
//! primal-dual active-set solve (faer Cholesky on the contact set) chosen instead while the
//! contact set is small, and the flat-punch solve on a fixed contact set (CG, or a dense
//! Cholesky solve for small sets).
//!
//! Conventions: `h` is the separation before loading (m), `compliance` multiplies the
//! G = 1 operator (1/G for an elastic body, dt/eta or 1/eta for viscous steps), and the gap
//! is g = compliance * K[p] + h - d >= 0 with p >= 0 and p g = 0 on the allowed elements.
//!
//! This module holds the shared types (targets, options, the `Tuning` that holds the
//! algorithms' switch points and limits, the solver) and `ContactSolver::solve`, which picks
//! the algorithm; each algorithm has its own file: `polonsky_keer`, `active_set` and
//! `punch`, with the solver's parallel passes over its work buffers in `passes`.

mod active_set;
mod extension;
mod passes;
mod polonsky_keer;
mod punch;

use crate::halfspace::body::Operator;
use crate::halfspace::operator::SurfaceOperator;
use crate::model::settings::SolverOptions;
use crate::support::error::{check_finite, check_len, check_positive, Error, Result};
use crate::support::monitor::Monitor;
use crate::support::pool::KeepAwake;
use passes::{MAX_SUMS, PASS_CHUNK};

/// What the solve holds fixed: the total force (N, or N s for impulses) or the rigid-body
/// approach d (m).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Target {
    /// Sum of p over the elements times the element area.
    Force(f64),
    /// Rigid-body approach of the indenter (m, positive into the body).
    Depth(f64),
}

/// Switch points, limits and fractions that steer the contact algorithms inside a solve;
/// `Default` holds the values measured or chosen for them. Results repeat bit for bit for
/// the same tuning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Tuning {
    /// Largest automatic active set (elements): caps the dense matrix of the active-set
    /// method (8 m^2 bytes, 128 MB at the default 4000), above the crossovers of grids up to
    /// ~2000^2.
    pub active_cap: usize,
    /// Constant c (dimensionless) of the automatic active-set limit
    /// m = (c n log2(4n))^(1/3) elements on a grid of n elements (`active_crossover`);
    /// default 230, fitted to `benchmarks/bench_active_set.py`.
    pub crossover_constant: f64,
    /// Active-set iterations before the solve falls back to Polonsky–Keer (default 40).
    pub active_max_iter: usize,
    /// Factor on the active-set limit that an iterate may reach in passing (default 2): the
    /// first iterations overshoot, a small start set pressing in deep.
    pub active_overshoot: usize,
    /// Overlaps below this fraction (dimensionless) of the largest |h| over the allowed
    /// elements count as none (default 1e-12): without it, a step whose load is tiny against
    /// the accumulated separation flips edge elements forever.
    pub gap_round_off: f64,
    /// Fraction (dimensionless) of the load that a degenerate Polonsky–Keer step (e.g. a
    /// one-element contact) seeds onto the overlapping elements (default 0.01).
    pub seed_fraction: f64,
    /// Polonsky–Keer recomputes u = K[p] by an operator apply at least every this many
    /// iterations (default 32), bounding the round-off drift of its linear updates.
    pub refresh_every: usize,
    /// Iterations between progress reports (and cancellation checks) of Polonsky–Keer and
    /// the flat-punch CG (default 1: an iteration of a large grid takes a good part of a
    /// second, and a report costs a few nanoseconds).
    pub progress_every: usize,
    /// Where Polonsky–Keer's preconditioner continues the residual onto a band around the
    /// contact set (`extension`); default `ResidualBand::Everywhere`.
    pub residual_band: ResidualBand,
    /// Polonsky–Keer's single-precision applies (`SurfaceOperator::apply_single` of its
    /// search direction, `add_single` of u's correction where the contact set changed;
    /// ASPHER mixes precisions too) leave an error in u = K[p] until it is next refreshed
    /// in double precision, measured at 2-3e-7 of the relative pressure change
    /// (sum |p_k - p_{k-1}| / sum p) summed over the iterations since. An iteration takes
    /// them while that sum, with the last iteration's change, stays within this many times
    /// the tolerance (default 1e5: an error of at most 1/30 of the tolerance; the nested
    /// grids' coarse levels take them throughout), 0 turns them off.
    pub single_precision_drift: f64,
    /// Polonsky–Keer's early iterations, the first of a cold start and each after one that
    /// changed the pressure by more than this (relative, dimensionless, > 0), run every
    /// apply in single precision, u's refreshes included, and the last of them refreshes u
    /// in double precision (default 1e-3: on `benchmarks/bench_rough.py`'s grids the finest
    /// level's double-precision applies fall from 15-44 to 4-7 with the same iterations;
    /// 1e-4 and below took more iterations); infinity turns them off.
    pub single_precision_above: f64,
}

/// The grids on which Polonsky–Keer preconditions by E^T S E, the residual continued onto a
/// band around the contact set (`extension`), rather than by S alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ResidualBand {
    /// Nowhere.
    Off,
    /// Grids that are not periodic cells only.
    Free,
    /// Every grid: 10-25 % fewer iterations on `benchmarks/bench_rough.py`'s 512^2 rough
    /// surfaces (2-20 % contact), and 1.0-1.25x less wall time on its periodic cells, where
    /// an apply is one unpadded FFT pair and the band's search and passes weigh most.
    Everywhere,
}

impl Default for Tuning {
    /// The values each field's doc names.
    fn default() -> Self {
        Tuning {
            active_cap: 4000,
            crossover_constant: 230.0,
            active_max_iter: 40,
            active_overshoot: 2,
            gap_round_off: 1e-12,
            seed_fraction: 0.01,
            refresh_every: 32,
            progress_every: 1,
            residual_band: ResidualBand::Everywhere,
            single_precision_drift: 1e5,
            single_precision_above: 1e-3,
        }
    }
}

impl Tuning {
    /// Fails unless the periods are >= 1, the fractions and factors finite and >= 0, and
    /// `single_precision_above` > 0 (infinity allowed).
    pub fn validate(&self) -> Result<()> {
        if self.refresh_every == 0 || self.progress_every == 0 {
            return Err(Error::InvalidInput(
                "refresh_every and progress_every must be >= 1".into(),
            ));
        }
        for (name, v) in [
            ("crossover_constant", self.crossover_constant),
            ("gap_round_off", self.gap_round_off),
            ("seed_fraction", self.seed_fraction),
            ("single_precision_drift", self.single_precision_drift),
        ] {
            if !(v.is_finite() && v >= 0.0) {
                return Err(Error::InvalidInput(format!(
                    "{name} must be finite and >= 0, got {v}"
                )));
            }
        }
        let above = self.single_precision_above;
        if above.is_nan() || above <= 0.0 {
            return Err(Error::InvalidInput(format!(
                "single_precision_above must be > 0 (infinity turns it off), got {above}"
            )));
        }
        Ok(())
    }

    /// Contact-set size (elements) below which the dense active-set solve beats
    /// Polonsky–Keer on a grid of `n` elements: a Cholesky factorisation (m^3/3) per
    /// active-set iteration against one FFT apply (~ n log n) per Polonsky–Keer iteration,
    /// m = (c n log2(4n))^(1/3) with c = `crossover_constant` (~400 elements at 128^2, ~650
    /// at 256^2, 2 cores).
    pub fn active_crossover(&self, n: usize) -> usize {
        let n = n.max(1) as f64;
        (self.crossover_constant * n * (4.0 * n).log2()).cbrt() as usize
    }
}

/// Summary of one contact solve; the fields live in the solver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ContactSummary {
    /// Rigid-body approach d (m).
    pub depth: f64,
    /// Total force (sum p dA: N, or N s for impulses).
    pub force: f64,
    /// Iterations taken.
    pub iterations: usize,
    /// Final relative residual (see `SolverOptions::tol`).
    pub residual: f64,
    /// Elements with p > 0.
    pub contact_count: usize,
    /// Solved by the dense active-set method (else Polonsky–Keer).
    pub dense: bool,
}

/// Contact solver owning its operator, its tuning and its work buffers (allocated once).
pub struct ContactSolver<O: SurfaceOperator> {
    op: O,
    tuning: Tuning,
    p: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
    z: Vec<f64>,
    p_old: Vec<f64>,
    /// Per-chunk sums of the parallel passes (`pass_sums`).
    partials: Vec<[f64; MAX_SUMS]>,
    /// Per-chunk index lists of the parallel passes (`passes::Chunk::set`), each chunk's in
    /// its own elements' slots.
    set_list: Vec<u16>,
    /// Room for the next per-chunk index lists (`passes::Chunk::next`).
    set_next: Vec<u16>,
    /// Lengths of the per-chunk index lists.
    set_len: Vec<usize>,
    /// Elements of the flat punch's set (`unit_punch`).
    set_idx: Vec<usize>,
    /// The band around the contact set onto which Polonsky–Keer's preconditioner continues
    /// the residual (`extension`).
    extension: extension::Extension,
}

/// The data of one contact problem, as `ContactSolver::solve` receives it.
#[derive(Clone, Copy)]
struct Problem<'a> {
    /// Separation before loading (m).
    h: &'a [f64],
    /// Elements where contact is possible.
    allowed: &'a [bool],
    /// Number of allowed elements.
    n_allowed: usize,
    /// Factor on the G = 1 operator.
    compliance: f64,
    /// What the solve holds fixed.
    target: Target,
    /// Load (N) the residual is measured against at least.
    reference: f64,
    /// Largest |h| (m) over the allowed elements.
    height_scale: f64,
    /// Overlaps below this (m) count as none (`Tuning::gap_round_off` times `height_scale`).
    gap_tol: f64,
}

impl ContactSolver<Operator> {
    /// Makes this the solver of an `nx` x `ny` window with the same padded FFT sizes
    /// (`Operator::resize`), keeping operator and buffers; the pressure is zeroed.
    pub fn resize(&mut self, nx: usize, ny: usize) -> Result<()> {
        self.op.resize(nx, ny)?;
        let n = nx * ny;
        for b in [
            &mut self.p,
            &mut self.u,
            &mut self.g,
            &mut self.t,
            &mut self.r,
            &mut self.z,
            &mut self.p_old,
        ] {
            b.clear();
            b.resize(n, 0.0);
        }
        self.partials
            .resize(n.div_ceil(PASS_CHUNK), [0.0; MAX_SUMS]);
        self.set_list.resize(n, 0);
        self.set_next.resize(n, 0);
        self.set_len.clear();
        self.set_len.resize(n.div_ceil(PASS_CHUNK), 0);
        Ok(())
    }
}

impl<O: SurfaceOperator> ContactSolver<O> {
    /// Memory of the solver's work buffers per element (bytes): seven of f64, the flat
    /// punch's index capacity, the passes' two index lists (u16) and the preconditioner's
    /// band around the contact set (`extension`, at most).
    pub const BYTES_PER_ELEMENT: f64 = 68.0 + extension::Extension::BYTES_PER_ELEMENT;

    /// Wraps `op` with the default `Tuning`; buffers are sized to its grid.
    pub fn new(op: O) -> Self {
        Self::with_tuning(op, Tuning::default())
    }

    /// Wraps `op` with `tuning` (checked by each solve); buffers are sized to its grid.
    pub fn with_tuning(op: O, tuning: Tuning) -> Self {
        let n = op.nx() * op.ny();
        ContactSolver {
            op,
            tuning,
            p: vec![0.0; n],
            u: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            r: vec![0.0; n],
            z: vec![0.0; n],
            p_old: vec![0.0; n],
            partials: vec![[0.0; MAX_SUMS]; n.div_ceil(PASS_CHUNK)],
            set_list: vec![0; n],
            set_next: vec![0; n],
            set_len: vec![0; n.div_ceil(PASS_CHUNK)],
            set_idx: Vec::with_capacity(n),
            extension: extension::Extension::default(),
        }
    }

    /// The operator.
    pub fn operator(&mut self) -> &mut O {
        &mut self.op
    }

    /// Pressure of the last solve (Pa, or Pa s for impulse densities; for `unit_punch`, Pa at
    /// G = 1 per metre of punch displacement).
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

    /// Sets the starting pressure (Pa, or Pa s) for a warm-started solve.
    pub fn set_pressure(&mut self, p: &[f64]) -> Result<()> {
        check_len("starting pressure", p.len(), self.p.len())?;
        check_finite("starting pressure", p)?;
        self.p.copy_from_slice(p);
        Ok(())
    }

    /// Solves the contact problem for separation `h` (m) on the elements where `allowed` is
    /// true. With `warm`, starts from the current pressure (rescaled to the target force),
    /// else from a uniform pressure. The residual is measured against the larger of this
    /// solve's load and `reference` (N): a time step passes the load accumulated so far, so
    /// that a small increment is converged relative to the state it changes, not to itself
    /// (below that, round-off of the accumulated separation dominates). Tries the dense
    /// active-set solve first unless `opts.active_limit` is 0, and runs Polonsky–Keer when
    /// that declines.
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
        // every iteration is a dozen parallel loops of well under a millisecond each
        let _awake = KeepAwake::new();
        let n = self.p.len();
        check_len("separation h", h.len(), n)?;
        check_len("allowed mask", allowed.len(), n)?;
        check_finite("separation h", h)?;
        check_positive("compliance", compliance)?;
        opts.validate()?;
        self.tuning.validate()?;
        let n_allowed = allowed.iter().filter(|&&a| a).count();
        if n_allowed == 0 {
            return Err(Error::InvalidInput(
                "the indenter's footprint holds no element of the grid".into(),
            ));
        }
        match target {
            Target::Force(w) => check_positive("force", w)?,
            Target::Depth(d) => {
                if !d.is_finite() {
                    return Err(Error::InvalidInput(format!(
                        "depth must be finite, got {d}"
                    )));
                }
            }
        }
        let warm = warm && self.p.iter().zip(allowed).any(|(&p, &a)| a && p > 0.0);
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
                    dense: false,
                });
            }
        }
        let height_scale = h
            .iter()
            .zip(allowed)
            .filter(|(_, &a)| a)
            .fold(0.0f64, |m, (h, _)| m.max(h.abs()));
        let gap_tol = self.tuning.gap_round_off * height_scale;
        let problem = Problem {
            h,
            allowed,
            n_allowed,
            compliance,
            target,
            reference,
            height_scale,
            gap_tol,
        };
        let start = (opts.active_limit != Some(0))
            .then(|| self.active_start(&problem, warm, opts))
            .flatten();
        if let Some(start) = start {
            self.p_old.copy_from_slice(&self.p);
            if let Some(summary) = self.solve_active_set(&problem, start, monitor)? {
                return Ok(summary);
            }
            self.p.copy_from_slice(&self.p_old);
        }
        self.solve_polonsky_keer(&problem, warm, opts, monitor)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    //! Test problems shared by the algorithms' tests, and the test of `Tuning`.

    use super::*;
    use crate::halfspace::operator::FftOperator;
    use crate::support::monitor::Silent;

    /// A paraboloid h = r^2 / (2 R) on an n x n grid of side 2.56 m, and dx.
    pub(super) fn hertz_grid(n: usize, radius: f64) -> (Vec<f64>, f64) {
        let dx = 2.56 / n as f64;
        let c = (n as f64 - 1.0) / 2.0;
        let h = (0..n * n)
            .map(|i| {
                let (x, y) = (((i % n) as f64 - c) * dx, ((i / n) as f64 - c) * dx);
                (x * x + y * y) / (2.0 * radius)
            })
            .collect();
        (h, dx)
    }

    /// Solves `h` on the whole n x n grid (compliance 1, cold start); the summary and the
    /// pressure.
    pub(super) fn solve_with(
        h: &[f64],
        n: usize,
        dx: f64,
        target: Target,
        opts: &SolverOptions,
    ) -> (ContactSummary, Vec<f64>) {
        let solver = ContactSolver::new(FftOperator::new(n, n, dx).unwrap());
        solved(solver, h, target, opts)
    }

    /// The solve of `h` (the whole grid allowed, compliance 1, cold start) by `solver`: its
    /// summary and pressure.
    pub(super) fn solved<O: SurfaceOperator>(
        mut solver: ContactSolver<O>,
        h: &[f64],
        target: Target,
        opts: &SolverOptions,
    ) -> (ContactSummary, Vec<f64>) {
        let allowed = vec![true; h.len()];
        let s = solver
            .solve(h, &allowed, 1.0, target, false, 0.0, opts, &mut Silent)
            .unwrap();
        (s, solver.pressure().to_vec())
    }

    /// The separation (m) before loading of a self-affine n x n surface (rms slope 0.1,
    /// wavelengths down to 4 elements) of Hurst exponent `hurst` from `seed`, its top at 0.
    pub(crate) fn rough_separation(n: usize, dx: f64, hurst: f64, seed: u64) -> Vec<f64> {
        use crate::model::surfaces::{self_affine, Roughness, SelfAffine};
        let surface = SelfAffine {
            nx: n,
            ny: n,
            dx,
            hurst,
            rolloff: None,
            short_cutoff: Some(4.0 * dx),
            roughness: Roughness::RmsSlope(0.1),
        };
        let z = self_affine(&surface, seed, &crate::support::monitor::Stop::default()).unwrap();
        let top = z.iter().fold(f64::MIN, |m, &v| m.max(v));
        z.iter().map(|v| top - v).collect()
    }

    /// Options that keep the solve on Polonsky–Keer (no active set), at tol 1e-10.
    pub(super) fn polonsky_keer_only() -> SolverOptions {
        SolverOptions {
            tol: 1e-10,
            active_limit: Some(0),
            ..Default::default()
        }
    }

    /// Largest |a_i - b_i|.
    pub(super) fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
        a.iter()
            .zip(b)
            .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
    }

    /// A solver built with its own tuning: refreshing u = K[p] on every Polonsky–Keer
    /// iteration reaches the default tuning's contact (to the tolerance), and a zero refresh
    /// period is refused, as is a threshold of early single-precision iterations that would
    /// never end (0, negative, NaN), where infinity, none, is taken.
    #[test]
    fn tuning_is_the_solvers_own() {
        let n = 64;
        let (h, dx) = hertz_grid(n, 10.0);
        let allowed = vec![true; n * n];
        let opts = SolverOptions {
            active_limit: Some(0),
            ..SolverOptions::default()
        };
        let (default, p_default) = solve_with(&h, n, dx, Target::Depth(0.02), &opts);
        let run = |refresh_every| {
            let tuning = Tuning {
                refresh_every,
                ..Tuning::default()
            };
            let op = FftOperator::new(n, n, dx).unwrap();
            let mut solver = ContactSolver::with_tuning(op, tuning);
            let target = Target::Depth(0.02);
            solver
                .solve(&h, &allowed, 1.0, target, false, 0.0, &opts, &mut Silent)
                .map(|s| (s, solver.pressure().to_vec()))
        };
        let (each, p_each) = run(1).unwrap();
        assert_eq!(each.contact_count, default.contact_count);
        let peak = p_default.iter().fold(0.0f64, |m, &v| m.max(v));
        assert!(max_abs_diff(&p_default, &p_each) < 1e-8 * peak);
        assert!(matches!(run(0), Err(Error::InvalidInput(_))));
        let above = |single_precision_above| {
            Tuning {
                single_precision_above,
                ..Tuning::default()
            }
            .validate()
        };
        for v in [0.0, -1.0, f64::NAN] {
            assert!(matches!(above(v), Err(Error::InvalidInput(_))), "{v}");
        }
        assert!(above(f64::INFINITY).is_ok());
    }
}
