//! A depth-controlled curve whose depth rises and then falls, on a profile that rises away
//! from its centre: Ting's solution (T. C. T. Ting, J. Appl. Mech. 33, 845–854, 1966),
//! which is the MDR elements' forces integrated over the contact in closed form.
//!
//! While the depth rises, every element within the contact radius a has stayed in contact
//! since it touched, so F(t) = 8 int_0^t G(t - s) dA(d(s)), with A(d) = int_0^a (d - g) dx
//! the area between the indenter at depth d and the half profile g (m^2, dA/dd = a; the
//! factor 8 is E* = 4 G on both halves). When the depth falls, the contact radius shrinks
//! back to a(d(t1)), where the edge element, which touched at t1 <= t_peak, carries no
//! force: phi(t, t1) = int_t1^t G(t - s) dd(s) = 0; then F(t) = 8 int_0^t1 G(t - s) dA(d(s)).
//! Once the whole contact has let go the force stays zero (Ting's assumption: no contact
//! again while the depth falls).
//!
//! Discretisation: the depth and A vary linearly in time over each step (second order in
//! the step, as the elements' stepping), and the Prony integrals are updated exactly for
//! that; a dashpot's force is eta dA/dt at the step's end, exact for that depth; g is interpolated linearly between the element centres (constant over the first
//! and the last half element), so the contact edge falls between them and the elements'
//! first-order contact-edge error is absent. The root t1 lies between two step ends where
//! phi changes sign; t1, the force and the contact radius are interpolated linearly in
//! phi between them. The derivatives follow the same arithmetic in forward mode.

use super::steps::{Step, Steps};
use super::{Curve, Evaluation, Forward, StepCoefficients};
use crate::model::medium::rheology::Rheology;
use crate::support::error::Result;
use crate::support::monitor::Stop;

/// E* = 4 G on the two halves of the even profile: the force is 8 G A.
pub(super) const WEIGHT: f64 = 8.0;

/// Below this an exponential factor is set to zero (no denormal arithmetic).
pub(super) const NEGLIGIBLE: f64 = 1e-250;

/// The area function A(d) of an even profile rising away from its centre.
pub(super) struct AreaFunction {
    /// Nodes: 0, the element centres (i + 1/2) dx, the end n dx (m).
    x: Vec<f64>,
    /// The profile at the nodes (m).
    g: Vec<f64>,
    /// int_0^x g at the nodes (m^2).
    integral: Vec<f64>,
    dx: f64,
    elements: usize,
}

impl AreaFunction {
    /// The area function of the half profile `g` at x_i = (i + 1/2) dx, or None when g
    /// falls anywhere (then the contact need not be one interval).
    pub(super) fn new(g: &[f64], dx: f64) -> Option<Self> {
        if g.windows(2).any(|w| w[1] < w[0]) {
            return None;
        }
        let n = g.len();
        let mut x = vec![0.0];
        x.extend((0..n).map(|i| (i as f64 + 0.5) * dx));
        x.push(n as f64 * dx);
        let mut nodes = vec![g[0]];
        nodes.extend_from_slice(g);
        nodes.push(g[n - 1]);
        let mut integral = vec![0.0; x.len()];
        for j in 1..x.len() {
            integral[j] = integral[j - 1] + 0.5 * (x[j] - x[j - 1]) * (nodes[j] + nodes[j - 1]);
        }
        Some(AreaFunction {
            x,
            g: nodes,
            integral,
            dx,
            elements: n,
        })
    }

    /// (A (m^2), a (m), da/dd) at depth `d` (m); the node search starts from `hint`, its
    /// last answer (updated).
    pub(super) fn at(&self, d: f64, hint: &mut usize) -> (f64, f64, f64) {
        let mut j = (*hint).min(self.g.len());
        while j > 0 && self.g[j - 1] >= d {
            j -= 1;
        }
        while j < self.g.len() && self.g[j] < d {
            j += 1;
        }
        *hint = j;
        if j == 0 {
            return (0.0, 0.0, 0.0);
        }
        let last = self.x.len() - 1;
        if j > last {
            return (d * self.x[last] - self.integral[last], self.x[last], 0.0);
        }
        // g[j - 1] < d <= g[j]
        let i = j - 1;
        let slope = (self.x[j] - self.x[i]) / (self.g[j] - self.g[i]);
        let a = self.x[i] + (d - self.g[i]) * slope;
        let area = d * a - self.integral[i] - 0.5 * (a - self.x[i]) * (self.g[i] + d);
        (area, a, slope)
    }

    /// Elements whose centre lies inside the contact radius `a` (m).
    pub(super) fn elements_within(&self, a: f64) -> usize {
        ((a / self.dx - 0.5).ceil().max(0.0) as usize).min(self.elements)
    }
}

/// The state at the end of a rising step, kept for the roots t1 of the falling ones.
struct Rising {
    time: f64,
    depth: f64,
    /// The depth's derivative along the shift.
    along: f64,
    area: f64,
    radius: f64,
    /// Index of the coefficients of the step that ends here.
    coefficients: usize,
}

/// Per-term integrals at the ends of the rising steps and their derivatives: Q_k =
/// G_k int exp(-(t - s) / tau_k) dA(s) and P_k = the same of the depth, one row per end,
/// [Q | P | dQ along each tangent | dP along each tangent], m values each.
pub(super) struct Integrals {
    m: usize,
    p: usize,
    rows: Vec<f64>,
}

/// Rows of the integrals kept for the next evaluation on the same thread are at most this
/// long (f64 values): reusing them spares the pages' faults and zeroing.
const SPARE_LIMIT: usize = 1 << 23;

thread_local! {
    /// The last evaluation's rows, for the next one on this thread.
    static SPARE: std::cell::Cell<Vec<f64>> = const { std::cell::Cell::new(Vec::new()) };
}

impl Integrals {
    /// The rest state before the first step, with room for `ends` more.
    pub(super) fn new(m: usize, p: usize, ends: usize) -> Self {
        let stride = m * (2 + 2 * p);
        let mut rows = SPARE.with(|spare| spare.take());
        rows.clear();
        rows.reserve(stride * (ends + 1));
        rows.resize(stride, 0.0);
        Integrals { m, p, rows }
    }

    fn stride(&self) -> usize {
        self.m * (2 + 2 * self.p)
    }

    /// Appends the state after a step of coefficients `c` that changes A and d by `delta` =
    /// (dA, dd). Their derivatives along tangent j are `known[j]` plus what `rest(j, s_j)`
    /// returns, s_j = sum_k dQ_k with `known[j]` alone (both as (d dA, d dd)): a depth that
    /// balances a load finds its own derivatives from s_j.
    pub(super) fn push(
        &mut self,
        c: &StepCoefficients,
        delta: (f64, f64),
        known: &[(f64, f64)],
        mut rest: impl FnMut(usize, f64) -> (f64, f64),
    ) {
        let (m, stride) = (self.m, self.stride());
        let at = self.rows.len();
        self.rows.resize(at + stride, 0.0);
        let (old, new) = self.rows.split_at_mut(at);
        let old = &old[at - stride..];
        let (q_old, rest_old) = old.split_at(m);
        let (p_old, rest_old) = rest_old.split_at(m);
        let (dq_old, dp_old) = rest_old.split_at(m * self.p);
        let (q_new, rest_new) = new.split_at_mut(m);
        let (p_new, rest_new) = rest_new.split_at_mut(m);
        let (dq_new, dp_new) = rest_new.split_at_mut(m * self.p);
        let (decay, gain) = (&c.decay[..m], &c.gain[..m]);
        let (q_old, p_old) = (&q_old[..m], &p_old[..m]);
        for (j, &(da, dd)) in known.iter().enumerate() {
            // the slices cut to one length: the loops run without bounds checks
            let row = j * m..(j + 1) * m;
            let (dq, dp) = (&mut dq_new[row.clone()], &mut dp_new[row.clone()]);
            let (dq0, dp0) = (&dq_old[row.clone()], &dp_old[row.clone()]);
            let (d_decay, d_gain) = (&c.d_decay[row.clone()], &c.d_gain[row]);
            for k in 0..m {
                dq[k] =
                    d_decay[k] * q_old[k] + decay[k] * dq0[k] + d_gain[k] * delta.0 + gain[k] * da;
            }
            let (da_rest, dd_rest) = rest(j, sum(dq));
            if da_rest != 0.0 {
                for (y, &g) in dq.iter_mut().zip(gain) {
                    *y += g * da_rest;
                }
            }
            let dd = dd + dd_rest;
            for k in 0..m {
                dp[k] =
                    d_decay[k] * p_old[k] + decay[k] * dp0[k] + d_gain[k] * delta.1 + gain[k] * dd;
            }
        }
        let (q_new, p_new) = (&mut q_new[..m], &mut p_new[..m]);
        for k in 0..m {
            q_new[k] = decay[k] * q_old[k] + gain[k] * delta.0;
            p_new[k] = decay[k] * p_old[k] + gain[k] * delta.1;
        }
    }

    pub(super) fn q(&self, i: usize) -> &[f64] {
        let at = i * self.stride();
        &self.rows[at..at + self.m]
    }

    pub(super) fn p(&self, i: usize) -> &[f64] {
        let at = i * self.stride() + self.m;
        &self.rows[at..at + self.m]
    }

    pub(super) fn dq(&self, i: usize, j: usize) -> &[f64] {
        let at = i * self.stride() + (2 + j) * self.m;
        &self.rows[at..at + self.m]
    }

    pub(super) fn dp(&self, i: usize, j: usize) -> &[f64] {
        let at = i * self.stride() + (2 + self.p + j) * self.m;
        &self.rows[at..at + self.m]
    }
}

impl Drop for Integrals {
    fn drop(&mut self) {
        let rows = std::mem::take(&mut self.rows);
        if rows.capacity() <= SPARE_LIMIT {
            SPARE.with(|spare| spare.set(rows));
        }
    }
}

/// The evaluation, filled sample by sample.
struct Output {
    e: Evaluation,
    p: usize,
}

impl Output {
    /// Sets the sample that `step` ends, if any: the force and its derivatives (per unit
    /// weight, Pa m^2: the force over `WEIGHT`) and the elements in contact (`contact`).
    fn put(&mut self, step: &Step, force: f64, d_force: &[f64], contact: impl FnOnce() -> usize) {
        if let Some(s) = step.sample {
            self.e.values[s] = WEIGHT * force;
            for (out, d) in self.e.jacobian[s * self.p..(s + 1) * self.p]
                .iter_mut()
                .zip(d_force)
            {
                *out = WEIGHT * d;
            }
            self.e.contact[s] = contact();
        }
    }

    /// Sets the sample that `step` ends, if any, to no contact.
    fn released(&mut self, step: &Step) {
        if let Some(s) = step.sample {
            self.e.values[s] = 0.0;
            self.e.jacobian[s * self.p..(s + 1) * self.p].fill(0.0);
            self.e.contact[s] = 0;
        }
    }
}

impl Curve {
    /// `evaluate_depth_control` by Ting's solution: None when it does not apply (the
    /// profile falls somewhere, or the shifted depth does not rise and then fall), and the
    /// elements are stepped instead. `rates` are the depths' derivatives along the tangents
    /// per unit shift (m per unit).
    pub(super) fn evaluate_hereditary(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        rates: &[f64],
        shift: f64,
        stop: &Stop,
    ) -> Result<Option<Evaluation>> {
        let Some(area) = AreaFunction::new(&self.g, self.dx) else {
            return Ok(None);
        };
        let Steps {
            steps,
            coefficients,
        } = self.depth_steps(r, tangents, shift)?;
        let peak = steps
            .windows(2)
            .position(|w| w[1].depth < w[0].depth)
            .map_or(steps.len(), |i| i + 1);
        if steps[peak..].windows(2).any(|w| w[1].depth > w[0].depth) {
            return Ok(None);
        }
        let (m, p) = (r.terms.len(), tangents.len());
        let mut out = Output {
            e: Evaluation {
                values: vec![0.0; self.times.len()],
                jacobian: vec![0.0; self.times.len() * p],
                contact: vec![0; self.times.len()],
                forward: Forward::Hereditary,
            },
            p,
        };
        // rising: the integrals at every step end (index 0: the rest before the first step)
        let mut rising = vec![Rising {
            time: 0.0,
            depth: 0.0,
            along: 0.0,
            area: 0.0,
            radius: 0.0,
            coefficients: 0,
        }];
        let mut integrals = Integrals::new(m, p, peak);
        let mut node = 0;
        let mut d_delta = vec![(0.0, 0.0); p];
        let mut d_force = vec![0.0; p];
        for (i, step) in steps[..peak].iter().enumerate() {
            stop.check()?;
            let (h, c) = (
                coefficients[step.coefficients].0,
                &coefficients[step.coefficients].1,
            );
            let before = &rising[i];
            let (a_new, radius, slope) = area.at(step.depth, &mut node);
            let delta = (a_new - before.area, step.depth - before.depth);
            for (dd, &rate) in d_delta.iter_mut().zip(rates) {
                *dd = (
                    rate * (radius * step.along - before.radius * before.along),
                    rate * (step.along - before.along),
                );
            }
            integrals.push(c, delta, &d_delta, |_, _| (0.0, 0.0));
            // the dashpot's force: eta dA/dt at the step's end, exact for a depth linear in t
            let damping = if r.eta == 0.0 { 0.0 } else { r.eta / h };
            let q = integrals.q(i + 1);
            let force = r.g_inf * a_new + sum(q) + damping * radius * delta.1;
            for (j, (df, t)) in d_force.iter_mut().zip(tangents).enumerate() {
                let d_damping = if t.eta == 0.0 { 0.0 } else { t.eta / h };
                let d_radius = slope * rates[j] * step.along;
                *df = t.g_inf * a_new
                    + r.g_inf * rates[j] * radius * step.along
                    + sum(integrals.dq(i + 1, j))
                    + d_damping * radius * delta.1
                    + damping * (d_radius * delta.1 + radius * d_delta[j].1);
            }
            out.put(step, force, &d_force, || area.elements_within(radius));
            rising.push(Rising {
                time: step.time,
                depth: step.depth,
                along: step.along,
                area: a_new,
                radius,
                coefficients: step.coefficients,
            });
        }
        if peak < steps.len() {
            let falling = Falling {
                r,
                tangents,
                rates,
                rising: &rising,
                integrals: &integrals,
                area: &area,
                tau_rates: tau_rates(r, tangents),
            };
            falling.run(&steps[peak..], &coefficients, &mut out, stop)?;
        }
        Ok(Some(out.e))
    }
}

/// The falling part of the curve: what it reads.
struct Falling<'a> {
    r: &'a Rheology,
    tangents: &'a [Rheology],
    rates: &'a [f64],
    rising: &'a [Rising],
    integrals: &'a Integrals,
    area: &'a AreaFunction,
    /// Per tangent, (k, d tau_k / tau_k^2 in 1/s) of the terms whose tau moves.
    tau_rates: Vec<Vec<(usize, f64)>>,
}

/// The current falling step: its end, length (s), change of depth (m) and its derivatives,
/// and P_k there with its derivatives (tangent-major).
struct Now<'a> {
    step: &'a Step,
    h: f64,
    dd: f64,
    d_dd: &'a [f64],
    /// sum_k P_k and its derivatives along each tangent.
    sum_p: f64,
    sum_dp: &'a [f64],
}

/// At a rising step end j: the force phi (per unit weight) on the element that touched
/// there, and the curve's force if t1 were there, with their derivatives.
struct AtEnd {
    phi: f64,
    d_phi: Vec<f64>,
    force: f64,
    d_force: Vec<f64>,
}

impl AtEnd {
    fn new(p: usize) -> Self {
        AtEnd {
            phi: 0.0,
            d_phi: vec![0.0; p],
            force: 0.0,
            d_force: vec![0.0; p],
        }
    }
}

impl Falling<'_> {
    /// Steps through the falling steps, handing each sample to `put`; stops with
    /// `Error::Interrupted` once `stop` is requested.
    fn run(
        &self,
        steps: &[Step],
        coefficients: &[(f64, StepCoefficients)],
        out: &mut Output,
        stop: &Stop,
    ) -> Result<()> {
        let (m, p) = (self.r.terms.len(), self.tangents.len());
        let last = self.rising.len() - 1;
        // the last rising end before contact: t1 lies after it
        let first = self.rising.iter().rposition(|s| s.area == 0.0).unwrap_or(0);
        let mut p_now = self.integrals.p(last).to_vec();
        let mut dp_now: Vec<f64> = (0..p)
            .flat_map(|j| self.integrals.dp(last, j).to_vec())
            .collect();
        let mut previous = (self.rising[last].depth, self.rising[last].along);
        // the bracket's upper end and exp(-(t - t_upper) / tau_k)
        let mut upper = last;
        let mut decay_upper = vec![1.0; m];
        let mut decay_lower = vec![0.0; m];
        let (mut hi, mut lo) = (AtEnd::new(p), AtEnd::new(p));
        let mut d_force = vec![0.0; p];
        let mut sum_dp = vec![0.0; p];
        let mut node = self.area.g.len();
        let mut released = false;
        let mut d_dd = vec![0.0; p];
        for step in steps {
            stop.check()?;
            let (h, c) = (
                coefficients[step.coefficients].0,
                &coefficients[step.coefficients].1,
            );
            let dd = step.depth - previous.0;
            for (x, &rate) in d_dd.iter_mut().zip(self.rates) {
                *x = rate * (step.along - previous.1);
            }
            previous = (step.depth, step.along);
            let rows = dp_now
                .chunks_exact_mut(m.max(1))
                .zip(c.d_decay.chunks_exact(m.max(1)))
                .zip(c.d_gain.chunks_exact(m.max(1)));
            for (((row, d_decay), d_gain), &d_dd) in rows.zip(&d_dd) {
                for k in 0..row.len() {
                    row[k] = d_decay[k] * p_now[k]
                        + c.decay[k] * row[k]
                        + d_gain[k] * dd
                        + c.gain[k] * d_dd;
                }
            }
            for ((pk, e), (decay, gain)) in p_now
                .iter_mut()
                .zip(decay_upper.iter_mut())
                .zip(c.decay.iter().zip(&c.gain))
            {
                *pk = decay * *pk + gain * dd;
                let next = *e * decay;
                *e = if next < NEGLIGIBLE { 0.0 } else { next };
            }
            if released {
                out.released(step);
                continue;
            }
            for (total, row) in sum_dp.iter_mut().zip(dp_now.chunks_exact(m.max(1))) {
                *total = sum(row);
            }
            let now = Now {
                step,
                h,
                dd,
                d_dd: &d_dd,
                sum_p: sum(&p_now),
                sum_dp: &sum_dp,
            };
            self.at_end(&now, upper, &decay_upper, &mut hi);
            while hi.phi > 0.0 && upper < last {
                upper += 1;
                let age = step.time - self.rising[upper].time;
                for (e, &(_, tau)) in decay_upper.iter_mut().zip(&self.r.terms) {
                    *e = (-age / tau).exp();
                }
                self.at_end(&now, upper, &decay_upper, &mut hi);
            }
            if hi.phi > 0.0 {
                // the contact radius is still the largest
                let radius = self.rising[upper].radius;
                out.put(step, hi.force, &hi.d_force, || {
                    self.area.elements_within(radius)
                });
                continue;
            }
            loop {
                if upper <= first {
                    released = true;
                    out.released(step);
                    break;
                }
                let into = &coefficients[self.rising[upper].coefficients].1;
                for ((lower, e), d) in decay_lower.iter_mut().zip(&decay_upper).zip(&into.decay) {
                    *lower = e * d;
                }
                self.at_end(&now, upper - 1, &decay_lower, &mut lo);
                if lo.phi > 0.0 {
                    self.interpolated(&lo, &hi, &mut d_force);
                    let theta = lo.phi / (lo.phi - hi.phi);
                    let (a, b) = (&self.rising[upper - 1], &self.rising[upper]);
                    let force = lo.force + theta * (hi.force - lo.force);
                    out.put(step, force, &d_force, || {
                        let (_, radius, _) = self
                            .area
                            .at(a.depth + theta * (b.depth - a.depth), &mut node);
                        self.area.elements_within(radius)
                    });
                    break;
                }
                upper -= 1;
                std::mem::swap(&mut decay_upper, &mut decay_lower);
                std::mem::swap(&mut hi, &mut lo);
            }
        }
        Ok(())
    }

    /// phi and the force at rising end `j` for the step `now`, with `decay` the factors
    /// exp(-(t - t_j) / tau_k).
    fn at_end(&self, now: &Now<'_>, j: usize, decay: &[f64], out: &mut AtEnd) {
        let (r, end) = (self.r, &self.rising[j]);
        let (pj, qj) = (self.integrals.p(j), self.integrals.q(j));
        let damping = if r.eta == 0.0 { 0.0 } else { r.eta / now.h };
        let rise = now.step.depth - end.depth;
        out.phi = now.sum_p - dot(decay, pj) + r.g_inf * rise + damping * now.dd;
        out.force = dot(decay, qj) + r.g_inf * end.area;
        let age = now.step.time - end.time;
        for (i, t) in self.tangents.iter().enumerate() {
            let rate = self.rates[i];
            let d_damping = if t.eta == 0.0 { 0.0 } else { t.eta / now.h };
            let (dpj, dqj) = (self.integrals.dp(j, i), self.integrals.dq(j, i));
            let mut dp = t.g_inf * rise
                + r.g_inf * rate * (now.step.along - end.along)
                + d_damping * now.dd
                + damping * now.d_dd[i]
                + now.sum_dp[i]
                - dot(decay, dpj);
            let mut df =
                t.g_inf * end.area + r.g_inf * rate * end.radius * end.along + dot(decay, dqj);
            // d exp(-age / tau_k) = exp(-age / tau_k) age d tau_k / tau_k^2
            for &(k, tau_rate) in &self.tau_rates[i] {
                let d_decay = decay[k] * age * tau_rate;
                dp -= d_decay * pj[k];
                df += d_decay * qj[k];
            }
            out.d_phi[i] = dp;
            out.d_force[i] = df;
        }
    }

    /// The derivatives of the force (per unit weight) with t1 between two rising ends,
    /// `lo` (phi > 0) and `hi` (phi <= 0), interpolated linearly in phi, into `d_force`.
    fn interpolated(&self, lo: &AtEnd, hi: &AtEnd, d_force: &mut [f64]) {
        let span = lo.phi - hi.phi;
        let theta = lo.phi / span;
        let jump = hi.force - lo.force;
        for (i, df) in d_force.iter_mut().enumerate() {
            let d_theta = (lo.phi * hi.d_phi[i] - hi.phi * lo.d_phi[i]) / (span * span);
            *df = (1.0 - theta) * lo.d_force[i] + theta * hi.d_force[i] + d_theta * jump;
        }
    }
}

/// sum_k a_k b_k, in four partial sums (a dependency chain a quarter as long).
pub(super) fn dot(a: &[f64], b: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let (ca, cb) = (a.chunks_exact(4), b.chunks_exact(4));
    let tail: f64 = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for l in 0..4 {
            acc[l] += x[l] * y[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// sum_k a_k, in four partial sums.
pub(super) fn sum(a: &[f64]) -> f64 {
    let mut acc = [0.0; 4];
    let chunks = a.chunks_exact(4);
    let tail: f64 = chunks.remainder().iter().sum();
    for x in chunks {
        for l in 0..4 {
            acc[l] += x[l];
        }
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) + tail
}

/// Per tangent, the terms whose relaxation time it moves and d(1/tau_k) = d tau_k / tau_k^2
/// (1/s per unit of the tangent's parameter), as (term index, rate) pairs.
pub(super) fn tau_rates(r: &Rheology, tangents: &[Rheology]) -> Vec<Vec<(usize, f64)>> {
    tangents
        .iter()
        .map(|t| {
            t.terms
                .iter()
                .zip(&r.terms)
                .enumerate()
                .filter(|(_, (&(_, d_tau), _))| d_tau != 0.0)
                .map(|(k, (&(_, d_tau), &(_, tau)))| (k, d_tau / (tau * tau)))
                .collect()
        })
        .collect()
}
