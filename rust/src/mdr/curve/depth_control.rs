//! A curve under depth control: with the depth prescribed, each element of the MDR
//! foundation evolves on its own, so the stepping runs element by element through all the
//! steps, its state in registers, and blocks of elements run in parallel; the force of a
//! sample is the sum of the blocks' forces, added in block order (the same result on any
//! number of threads). The derivatives are laid out term by term with the tangents
//! contiguous (padded to a multiple of `LANES`), so that the part of each update common to
//! all tangents is one loop the compiler vectorises; the few tangents that move a term's
//! own coefficients add their terms after it.

use super::steps::{Step, Steps};
use super::{with_shift_tangent, Curve, Evaluation, Forward, StepCoefficients};
use crate::model::medium::rheology::Rheology;
use crate::support::error::Result;
use crate::support::monitor::Stop;
use rayon::prelude::*;

/// Elements per block of the parallel loop.
const BLOCK: usize = 32;

/// The tangents are padded to a multiple of this (zero tangents, whose derivatives stay 0):
/// the f64 lanes of the narrowest x86-64 vectors (SSE2).
const LANES: usize = 2;

/// A step's coefficients laid out for the element loop: 1 / g_eff, d g_eff and d relaxing
/// along every tangent (pp, padded), and per term k the tangents that move its decay or
/// gain, with those derivatives (a tangent of one parameter moves one term or none, so
/// these lists are short; the rest of the update is the same for every tangent).
struct Tangential {
    /// 1 / g_eff (1/Pa), for multiplications in the element loop.
    inv_g_eff: f64,
    d_g_eff: Vec<Lanes>,
    d_relaxing: Vec<Lanes>,
    /// Per term: (tangent, d decay, d gain) where either is nonzero.
    moving: Vec<Vec<(usize, f64, f64)>>,
    /// (d decay, d gain) at each pair of the table's `settled` pattern.
    settled: Vec<(f64, f64)>,
}

/// Values along `LANES` consecutive tangents.
type Lanes = [f64; LANES];

/// `values` (one per tangent) padded with zeros into lanes.
fn lanes(values: &[f64], pp: usize) -> Vec<Lanes> {
    let mut out = vec![[0.0; LANES]; pp / LANES];
    for (j, v) in values.iter().enumerate() {
        out[j / LANES][j % LANES] = *v;
    }
    out
}

impl Tangential {
    fn new(c: &StepCoefficients, p: usize, pp: usize) -> Self {
        let m = c.decay.len();
        let (d_g_eff, d_relaxing) = (lanes(&c.d_g_eff, pp), lanes(&c.d_relaxing, pp));
        let moving = (0..m)
            .map(|k| {
                (0..p)
                    .map(|j| (j, c.d_decay[j * m + k], c.d_gain[j * m + k]))
                    .filter(|&(_, dd, dg)| dd != 0.0 || dg != 0.0)
                    .collect()
            })
            .collect();
        Tangential {
            inv_g_eff: 1.0 / c.g_eff,
            d_g_eff,
            d_relaxing,
            moving,
            settled: vec![],
        }
    }

    /// The derivatives of c's decays and gains at the (term, tangent) pairs `pattern`.
    fn with_settled(mut self, c: &StepCoefficients, pattern: &[(usize, usize)]) -> Self {
        let m = c.decay.len();
        self.settled = pattern
            .iter()
            .map(|&(k, j)| (c.d_decay[j * m + k], c.d_gain[j * m + k]))
            .collect();
        self
    }
}

/// The (term, tangent) pairs whose derivative of a Prony stress can be nonzero while an
/// element has stayed in contact since it first touched: its displacement's derivatives are
/// then the depth's (constant), so a stress's derivative along a tangent grows only from
/// that tangent's derivatives of the term's own coefficients, or from a moving depth.
fn settled_pattern(tangential: &[Tangential], rates: &[f64], m: usize) -> Vec<(usize, usize)> {
    let mut pattern: Vec<(usize, usize)> = tangential
        .iter()
        .flat_map(|t| {
            t.moving
                .iter()
                .enumerate()
                .flat_map(|(k, list)| list.iter().map(move |&(j, _, _)| (k, j)))
        })
        .chain(
            rates
                .iter()
                .enumerate()
                .filter(|(_, r)| **r != 0.0)
                .flat_map(|(j, _)| (0..m).map(move |k| (k, j))),
        )
        .collect();
    pattern.sort_unstable();
    pattern.dedup();
    pattern
}

/// What a block of elements adds to each sample: force (N per unit weight), its derivative
/// along each tangent (row-major, sample by tangent) and the elements in contact.
struct Sums {
    force: Vec<f64>,
    d_force: Vec<f64>,
    contact: Vec<usize>,
}

impl Sums {
    fn zero(samples: usize, p: usize) -> Self {
        Sums {
            force: vec![0.0; samples],
            d_force: vec![0.0; samples * p],
            contact: vec![0; samples],
        }
    }

    fn add(mut self, other: &Sums) -> Self {
        let pairs = [
            (&mut self.force, &other.force),
            (&mut self.d_force, &other.d_force),
        ];
        for (a, b) in pairs {
            a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        }
        self.contact
            .iter_mut()
            .zip(&other.contact)
            .for_each(|(x, y)| *x += y);
        self
    }
}

impl Curve {
    /// `Curve::evaluate` under depth control, with `shift` (m) added to every prescribed
    /// depth; with a shift, the derivative along it is a last tangent (a zero rheology
    /// tangent whose depth moves at unit rate).
    pub(super) fn evaluate_depth_control(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: Option<f64>,
        stop: &Stop,
    ) -> Result<Evaluation> {
        let (all, rates) = with_shift_tangent(r, tangents, shift.is_some());
        let tangents = &all[..];
        let shift = shift.unwrap_or(0.0);
        if self.hereditary {
            if let Some(e) = self.evaluate_hereditary(r, tangents, &rates, shift, stop)? {
                return Ok(e);
            }
        }
        let p = tangents.len();
        let samples = self.times.len();
        let Steps {
            steps,
            coefficients,
        } = self.depth_steps(r, tangents, shift)?;
        // an element never reached by the indenter keeps a zero state
        let deepest = steps
            .iter()
            .map(|s| s.depth)
            .fold(f64::NEG_INFINITY, f64::max);
        let n = self.g.len();
        let pp = p.div_ceil(LANES) * LANES;
        let tangential: Vec<Tangential> = coefficients
            .iter()
            .map(|(_, c)| Tangential::new(c, p, pp))
            .collect();
        let settled = settled_pattern(&tangential, &rates, r.terms.len());
        let tangential: Vec<Tangential> = tangential
            .into_iter()
            .zip(&coefficients)
            .map(|(t, (_, c))| t.with_settled(c, &settled))
            .collect();
        let rates = lanes(&rates, pp);
        let table = Table {
            steps: &steps,
            coefficients: &coefficients,
            tangential: &tangential,
            rates: &rates,
            settled: &settled,
        };
        let blocks: Vec<Sums> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut sums = Sums::zero(samples, pp);
                let mut state = ElementState::new(r.terms.len(), pp);
                for &g in &self.g[b * BLOCK..n.min((b + 1) * BLOCK)] {
                    stop.check()?;
                    if g < deepest {
                        state.run(g, &table, &mut sums);
                    }
                }
                Ok(sums)
            })
            .collect::<Result<_>>()?;
        let total = blocks
            .iter()
            .fold(Sums::zero(samples, pp), |acc, b| acc.add(b));
        // each element stands for itself and its mirror image
        let weight = 8.0 * self.dx;
        Ok(Evaluation {
            values: total.force.iter().map(|f| weight * f).collect(),
            jacobian: total
                .d_force
                .chunks_exact(pp.max(1))
                .flat_map(|row| row[..p].iter().map(|f| weight * f))
                .collect(),
            contact: total.contact,
            forward: Forward::Elements,
        })
    }
}

/// What the elements' stepping reads: the steps, their coefficients (as computed and with
/// the tangents contiguous) and the depth's derivative along each tangent.
struct Table<'a> {
    steps: &'a [Step],
    coefficients: &'a [(f64, StepCoefficients)],
    tangential: &'a [Tangential],
    rates: &'a [Lanes],
    /// `settled_pattern`: the derivatives of the stresses that can be nonzero while an
    /// element has not left contact.
    settled: &'a [(usize, usize)],
}

/// The state of one element (displacement w, Prony stresses q) and its derivatives along
/// each of the padded tangents (in lanes; dq term by term), with the history term's
/// derivatives of the current step and the change of dw in it; and a copy of the state
/// where the element last left contact.
struct ElementState {
    m: usize,
    chunks: usize,
    q: Vec<f64>,
    dw: Vec<Lanes>,
    dq: Vec<Lanes>,
    dh: Vec<Lanes>,
    d_dw: Vec<Lanes>,
    saved_q: Vec<f64>,
    saved_dw: Vec<Lanes>,
    saved_dq: Vec<Lanes>,
}

/// Where an element's stepping stands.
#[derive(Clone, Copy)]
enum Phase {
    /// In contact at every step since it first touched: only the table's `settled`
    /// stress derivatives are nonzero.
    Settled,
    /// Out of contact since step `since` (index into the steps), displacement `w` before
    /// it: its derivatives do not reach the force until it touches again, so only its
    /// own state is stepped (the state before `since` is saved, to replay from).
    Free { since: usize, w: f64 },
    /// Every derivative stepped.
    Full,
}

/// One step's scalar quantities of an element: the history term, whether it touches, its
/// new displacement.
struct Scalar {
    hist: f64,
    touching: bool,
    w_new: f64,
}

impl ElementState {
    fn new(m: usize, pp: usize) -> Self {
        let chunks = pp / LANES;
        ElementState {
            m,
            chunks,
            q: vec![0.0; m],
            dw: vec![[0.0; LANES]; chunks],
            dq: vec![[0.0; LANES]; m * chunks],
            dh: vec![[0.0; LANES]; chunks],
            d_dw: vec![[0.0; LANES]; chunks],
            saved_q: vec![0.0; m],
            saved_dw: vec![[0.0; LANES]; chunks],
            saved_dq: vec![[0.0; LANES]; m * chunks],
        }
    }

    /// Steps the element at profile height `g` (m) from rest through the table's steps,
    /// adding its force at each sample to `sums`; the table's `rates` are the derivatives
    /// of the depth along each tangent (constant over the history). Until the depth first
    /// passes g the element's state stays zero and its steps are skipped. While the element
    /// has stayed in contact since it first touched, only the stress derivatives of the
    /// table's `settled` pattern are updated; once it leaves contact, only its own state,
    /// until it touches again, when its derivatives are stepped from where it left (the
    /// same operations as if they had been stepped all along).
    fn run(&mut self, g: f64, table: &Table<'_>, sums: &mut Sums) {
        let pp = self.chunks * LANES;
        self.q.iter_mut().for_each(|x| *x = 0.0);
        self.dw.iter_mut().for_each(|x| *x = [0.0; LANES]);
        self.dq.iter_mut().for_each(|x| *x = [0.0; LANES]);
        let Some(first) = table.steps.iter().position(|s| s.depth > g) else {
            return;
        };
        let mut w = 0.0;
        let mut phase = Phase::Settled;
        for (i, step) in table.steps.iter().enumerate().skip(first) {
            let c = &table.coefficients[step.coefficients].1;
            let t = &table.tangential[step.coefficients];
            let depth = step.depth;
            let mut now = self.scalar(c, t, g, depth, w);
            match phase {
                Phase::Settled if now.touching => self.settled_step(c, t, table, w, now.w_new - w),
                Phase::Settled | Phase::Full if !now.touching => {
                    self.saved_q.copy_from_slice(&self.q);
                    self.saved_dw.copy_from_slice(&self.dw);
                    self.saved_dq.copy_from_slice(&self.dq);
                    phase = Phase::Free { since: i, w };
                }
                Phase::Free { .. } if !now.touching => {}
                Phase::Free { since, w: w_then } => {
                    // touching again: replay the free steps with the derivatives
                    self.q.copy_from_slice(&self.saved_q);
                    self.dw.copy_from_slice(&self.saved_dw);
                    self.dq.copy_from_slice(&self.saved_dq);
                    let mut w_replay = w_then;
                    for past in &table.steps[since..i] {
                        let c = &table.coefficients[past.coefficients].1;
                        let t = &table.tangential[past.coefficients];
                        let then = self.scalar(c, t, g, past.depth, w_replay);
                        self.full_step(c, t, table.rates, w_replay, &then, None);
                        self.advance(c, then.w_new - w_replay);
                        w_replay = then.w_new;
                    }
                    now = self.scalar(c, t, g, depth, w);
                    phase = Phase::Full;
                    let row = step.sample.map(|s| &mut sums.d_force[s * pp..(s + 1) * pp]);
                    self.full_step(c, t, table.rates, w, &now, row.map(|r| (r, depth - g)));
                }
                Phase::Settled | Phase::Full => {
                    let row = step.sample.map(|s| &mut sums.d_force[s * pp..(s + 1) * pp]);
                    self.full_step(c, t, table.rates, w, &now, row.map(|r| (r, depth - g)));
                }
            }
            if let (true, Some(s)) = (now.touching, step.sample) {
                sums.force[s] += c.g_eff * (depth - g) + now.hist;
                sums.contact[s] += 1;
                if let Phase::Settled = phase {
                    let row = sums.d_force[s * pp..(s + 1) * pp].chunks_exact_mut(LANES);
                    add_derivatives(row, c, t, table.rates, &self.dh, depth - g);
                }
            }
            self.advance(c, now.w_new - w);
            w = now.w_new;
        }
    }

    /// The step's history term, contact and new displacement from displacement `w`.
    #[inline]
    fn scalar(&self, c: &StepCoefficients, t: &Tangential, g: f64, depth: f64, w: f64) -> Scalar {
        let mut hist = -c.relaxing * w;
        for (e, q) in c.decay.iter().zip(&self.q) {
            hist += e * q;
        }
        let relaxed = g - hist * t.inv_g_eff;
        let touching = relaxed < depth;
        let w_new = if touching { depth - g } else { relaxed - g };
        Scalar {
            hist,
            touching,
            w_new,
        }
    }

    /// The stresses after a step that changes the displacement by `dw_step` (m).
    #[inline]
    fn advance(&mut self, c: &StepCoefficients, dw_step: f64) {
        for k in 0..self.m {
            self.q[k] = c.decay[k] * self.q[k] + c.gain[k] * dw_step;
        }
    }

    /// The derivatives through a step in contact of a settled element (the stresses not
    /// yet advanced): dh, then dw (the depth's), then the settled stress derivatives.
    fn settled_step(
        &mut self,
        c: &StepCoefficients,
        t: &Tangential,
        table: &Table<'_>,
        w: f64,
        dw_step: f64,
    ) {
        let chunks = self.chunks;
        for ((dh, dr), dw) in self.dh.iter_mut().zip(&t.d_relaxing).zip(&self.dw) {
            for l in 0..LANES {
                dh[l] = -dr[l] * w - c.relaxing * dw[l];
            }
        }
        for (&(k, j), &(dd, _)) in table.settled.iter().zip(&t.settled) {
            let dq = self.dq[k * chunks + j / LANES][j % LANES];
            self.dh[j / LANES][j % LANES] += c.decay[k] * dq + dd * self.q[k];
        }
        for ((d_dw, dw), rate) in self.d_dw.iter_mut().zip(&mut self.dw).zip(table.rates) {
            for l in 0..LANES {
                d_dw[l] = rate[l] - dw[l];
                dw[l] = rate[l];
            }
        }
        for (&(k, j), &(dd, dg)) in table.settled.iter().zip(&t.settled) {
            let d_dw = self.d_dw[j / LANES][j % LANES];
            let dq = &mut self.dq[k * chunks + j / LANES][j % LANES];
            *dq = dd * self.q[k] + c.decay[k] * *dq + dg * dw_step + c.gain[k] * d_dw;
        }
    }

    /// The derivatives through any step (the stresses not yet advanced), adding the force's
    /// derivatives to `row` (with the depth minus g) when given and in contact.
    fn full_step(
        &mut self,
        c: &StepCoefficients,
        t: &Tangential,
        rates: &[Lanes],
        w: f64,
        now: &Scalar,
        row: Option<(&mut [f64], f64)>,
    ) {
        let (m, chunks) = (self.m, self.chunks);
        let dw_step = now.w_new - w;
        // dh = -d_relaxing w - relaxing dw + sum_k (d_decay_k q_k + decay_k dq_k)
        for ((dh, dr), dw) in self.dh.iter_mut().zip(&t.d_relaxing).zip(&self.dw) {
            for l in 0..LANES {
                dh[l] = -dr[l] * w - c.relaxing * dw[l];
            }
        }
        for k in 0..m {
            let ek = c.decay[k];
            for (dh, dq) in self
                .dh
                .iter_mut()
                .zip(&self.dq[k * chunks..(k + 1) * chunks])
            {
                for l in 0..LANES {
                    dh[l] += ek * dq[l];
                }
            }
            for &(j, dd, _) in &t.moving[k] {
                self.dh[j / LANES][j % LANES] += dd * self.q[k];
            }
        }
        if let (true, Some((row, pressed))) = (now.touching, row) {
            add_derivatives(row.chunks_exact_mut(LANES), c, t, rates, &self.dh, pressed);
        }
        // a touching element's displacement follows the prescribed depth (which depends
        // on the shift only); a free one's follows its relaxed surface
        if now.touching {
            for ((d_dw, dw), rate) in self.d_dw.iter_mut().zip(&mut self.dw).zip(rates) {
                for l in 0..LANES {
                    d_dw[l] = rate[l] - dw[l];
                    dw[l] = rate[l];
                }
            }
        } else {
            let (hist, inv) = (now.hist, t.inv_g_eff);
            let iter = self.d_dw.iter_mut().zip(&mut self.dw);
            for (((d_dw, dw), dg), dh) in iter.zip(&t.d_g_eff).zip(&self.dh) {
                for l in 0..LANES {
                    let new = (hist * dg[l] * inv - dh[l]) * inv;
                    d_dw[l] = new - dw[l];
                    dw[l] = new;
                }
            }
        }
        for k in 0..m {
            let (qk, ek, gk) = (self.q[k], c.decay[k], c.gain[k]);
            let dq = &mut self.dq[k * chunks..(k + 1) * chunks];
            for (dq, d_dw) in dq.iter_mut().zip(&self.d_dw) {
                for l in 0..LANES {
                    dq[l] = ek * dq[l] + gk * d_dw[l];
                }
            }
            for &(j, dd, dg) in &t.moving[k] {
                dq[j / LANES][j % LANES] += dd * qk + dg * dw_step;
            }
        }
    }
}

/// Adds an element's force derivatives d(g_eff (depth - g) + hist) to a sample's row:
/// `pressed` = depth - g (m), `dh` the history term's derivatives.
fn add_derivatives<'a>(
    row: impl Iterator<Item = &'a mut [f64]>,
    c: &StepCoefficients,
    t: &Tangential,
    rates: &[Lanes],
    dh: &[Lanes],
    pressed: f64,
) {
    for (((f, dg), rate), dh) in row.zip(&t.d_g_eff).zip(rates).zip(dh) {
        for l in 0..LANES {
            f[l] += dg[l] * pressed + c.g_eff * rate[l] + dh[l];
        }
    }
}
