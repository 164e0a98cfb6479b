//! A spring-controlled curve (an AFM cantilever of stiffness k in series with the indenter,
//! its piezo driving u) by Ting's solution (`hereditary`): at the end of each step the depth
//! d solves the scalar balance k (u - d) = F[d](t), F Ting's force of the depth history so
//! far with d as its newest value.
//!
//! While the contact grows, F = 8 (G_inf A(d) + sum_k Q_k + eta dA/h), the Prony integrals
//! Q_k updated exactly over the step for A linear in time (an O(1) update per term), so the
//! balance is a monotone equation in d (A piecewise quadratic), solved by Newton's method
//! inside a bracket. Once the depth falls with the contact, F is the force of Ting's t1
//! construction: phi(t, t_j) (the force on the element that touched at the rising end j) is
//! linear in d with slope g_eff, the same for every j, so between two rising ends F is
//! linear in d, and the balance is solved by walking to the interval of rising ends that
//! holds t1. Once the contact lets go the indenter follows the drive.
//!
//! A dashpot (eta delta(t) in G(t)) adds eta dA/dt while the contact grows, taken as its
//! mean over the step, eta (A - A_prev) / h (what the elements' dashpots sum to; first
//! order in the step; the rate at the step's end, eta a dd/h, would jump with a as the
//! contact forms, the profile being flat over the first half element, and the balance's
//! root with it), so the balance stays continuous and monotone in d; it adds nothing to
//! the force once t1 lies before the step (it acts at s = t only), and eta dd/h to every
//! phi: on retraction t1 moves back at once, the contact shrinking with the drive's speed.
//!
//! Before contact nothing is stored: the rest state moves along with the drive, and the
//! integrals count from there (the falling steps read their differences since the
//! contact's start only). The integrals sit one row per rising end (`Integrals`), each
//! step's row written in one pass per tangent from the one before.
//!
//! Covered: any medium, a depth that may wander before contact and rises (within
//! round-off) while the contact grows, then a contact that only shrinks (t1 never moves
//! later; the depth itself may rise as the cantilever unbends) until it lets go, and
//! afterwards a drive that stays below its lowest value since, or below the profile:
//! otherwise `None` (the elements are stepped instead).
//!
//! Derivatives: forward mode through the same arithmetic, each step's depth derivative
//! from the implicit-function theorem on the balance, dd = (k du - 8 dF|_d) / (k + 8 dF/dd).

use super::hereditary::{dot, sum, tau_rates, AreaFunction, Integrals, NEGLIGIBLE, WEIGHT};
use super::steps::Steps;
use super::{Curve, Evaluation, Forward};
use crate::model::medium::rheology::Rheology;
use crate::support::error::Result;
use crate::support::monitor::Stop;

/// Depths within this fraction of the largest drive count as unchanged (the depth's
/// monotonicity is tested to it).
const SLACK: f64 = 1e-12;

/// How far t1 may move later between two falling steps (in rising ends: round-off).
const REGROWTH: f64 = 1e-6;

/// The state at the end of a step while the contact grows (a rising end).
struct End {
    time: f64,
    depth: f64,
    area: f64,
    radius: f64,
    /// Index of the coefficients of the step that ends here.
    coefficients: usize,
}

/// Where the falling step's balance was found.
enum Found {
    /// t1 at the rising end `upper` (F independent of d there).
    AtEnd,
    /// t1 between rising ends `upper - 1` and `upper`, at the fraction theta in phi.
    Between,
    /// The contact has let go.
    Released,
}

impl Curve {
    /// `evaluate_balance` under spring control (`stiffness` k, N/m) by Ting's solution with
    /// the spring in series: None when the profile falls somewhere or the depth leaves the
    /// covered history. `tangents` include the shift's, `rates` the drives' derivatives
    /// along them per unit shift.
    pub(super) fn evaluate_spring_hereditary(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        rates: &[f64],
        shift: f64,
        stiffness: f64,
        stop: &Stop,
    ) -> Result<Option<Evaluation>> {
        let Some(area) = AreaFunction::new(&self.g, self.dx) else {
            return Ok(None);
        };
        let Steps {
            steps,
            coefficients,
        } = self.depth_steps(r, tangents, shift)?;
        let (m, p) = (r.terms.len(), tangents.len());
        let samples = self.times.len();
        let mut e = Evaluation {
            values: vec![0.0; samples],
            jacobian: vec![0.0; samples * p],
            contact: vec![0; samples],
            forward: Forward::Hereditary,
        };
        let widest = steps.iter().fold(0.0f64, |a, s| a.max(s.depth.abs()));
        let tol = SLACK * widest.max(self.dx);
        // the balance is solved far below the monotonicity's slack (a stiff spring
        // multiplies the depth's error)
        let precision = 1e-6 * tol;
        // the balance per unit weight: kw (u - d) = F / WEIGHT
        let kw = stiffness / WEIGHT;
        let lowest_g = self.g[0];
        let mut ends = vec![End {
            time: 0.0,
            depth: 0.0,
            area: 0.0,
            radius: 0.0,
            coefficients: 0,
        }];
        // the depth's derivatives at the rising ends, p per end
        let mut ends_d = vec![0.0; p];
        let mut integrals = Integrals::new(m, p, steps.len());
        let (mut d_prev, mut dd_prev) = (0.0, vec![0.0; p]);
        let mut node = 0;
        let mut scratch = vec![0.0; p];
        let mut d_now = vec![0.0; p];
        let mut d_delta = vec![(0.0, 0.0); p];
        let mut at = 0;
        // rising: the contact grows (or has not formed)
        while at < steps.len() {
            stop.check()?;
            let step = &steps[at];
            let (h, c) = (
                coefficients[step.coefficients].0,
                &coefficients[step.coefficients].1,
            );
            let last = ends.len() - 1;
            let (a_prev, radius_prev) = (ends[last].area, ends[last].radius);
            let damping = damping_of(r.eta, h);
            let gains = sum(&c.gain);
            let decayed = dot(&c.decay, integrals.q(last));
            // the dashpot's eta dA/dt as the step's mean, eta (A - A_prev) / h: continuous in
            // d as the contact forms (a jumps there, the profile flat over the first half
            // element)
            let force = |d: f64, node: &mut usize| {
                let (a, radius, _) = area.at(d, node);
                (
                    r.g_inf * a + decayed + (gains + damping) * (a - a_prev),
                    (r.g_inf + gains + damping) * radius,
                )
            };
            let u = step.depth;
            let d = balance(kw, u, d_prev, precision, |d| force(d, &mut node));
            if a_prev > 0.0 && d < d_prev - tol {
                break;
            }
            let (a_new, radius, _) = area.at(d, &mut node);
            let (f_new, slope_f) = force(d, &mut node);
            let dd = d - d_prev;
            if a_new == 0.0 && a_prev == 0.0 {
                // before contact the indenter follows the drive, and nothing is stored: the
                // rest state moves along (Ting's integrals counted from there; the falling
                // steps read only their differences since the contact's start)
                for (x, &rate) in d_now.iter_mut().zip(rates) {
                    *x = rate * step.along;
                }
                ends[0] = End {
                    time: step.time,
                    depth: d,
                    area: 0.0,
                    radius: 0.0,
                    coefficients: step.coefficients,
                };
                ends_d.copy_from_slice(&d_now);
                put(
                    &mut e,
                    step.sample,
                    0.0,
                    stiffness,
                    rates,
                    step.along,
                    &d_now,
                    || 0,
                );
                d_prev = d;
                dd_prev.copy_from_slice(&d_now);
                at += 1;
                continue;
            }
            for (known, &before) in d_delta.iter_mut().zip(&dd_prev) {
                *known = (-radius_prev * before, -before);
            }
            let along = step.along;
            integrals.push(c, (a_new - a_prev, dd), &d_delta, |j, s| {
                let t = &tangents[j];
                let x = t.g_inf * a_new + damping_of(t.eta, h) * (a_new - a_prev)
                    - damping * radius_prev * dd_prev[j]
                    + s;
                let now = (kw * rates[j] * along - x) / (kw + slope_f);
                d_now[j] = now;
                (radius * now, now)
            });
            put(
                &mut e,
                step.sample,
                WEIGHT * f_new,
                stiffness,
                rates,
                step.along,
                &d_now,
                || area.elements_within(radius),
            );
            ends.push(End {
                time: step.time,
                depth: d,
                area: a_new,
                radius,
                coefficients: step.coefficients,
            });
            ends_d.extend_from_slice(&d_now);
            d_prev = d;
            dd_prev.copy_from_slice(&d_now);
            at += 1;
        }
        if at == steps.len() {
            return Ok(finite(e));
        }
        let falling = Falling {
            r,
            tangents,
            ends: &ends,
            ends_d: &ends_d,
            integrals: &integrals,
            tau_rates: tau_rates(r, tangents),
        };
        let last = ends.len() - 1;
        let first = ends.iter().rposition(|s| s.area == 0.0).unwrap_or(0);
        let mut p_now = integrals.p(last).to_vec();
        let mut dp_now: Vec<f64> = (0..p)
            .flat_map(|j| integrals.dp(last, j).to_vec())
            .collect();
        let mut dp_new = vec![0.0; m * p];
        let mut upper = last;
        let mut decay_upper = vec![1.0; m];
        let mut decay_lower = vec![0.0; m];
        let mut released: Option<f64> = None;
        let mut t1_before = last as f64;
        let mut d_force = vec![0.0; p];
        let (mut lo_dphi, mut lo_df, mut hi_dphi) = (vec![0.0; p], vec![0.0; p], vec![0.0; p]);
        let mut sum_dp = vec![0.0; p];
        for step in &steps[at..] {
            stop.check()?;
            let (h, c) = (
                coefficients[step.coefficients].0,
                &coefficients[step.coefficients].1,
            );
            let u = step.depth;
            for (e_k, decay) in decay_upper.iter_mut().zip(&c.decay) {
                let next = *e_k * decay;
                *e_k = if next < NEGLIGIBLE { 0.0 } else { next };
            }
            let damping = damping_of(r.eta, h);
            // sum_k P_k at d = d_prev (it moves by gains (d - d_prev))
            let p_ref = dot(&c.decay, &p_now);
            // Between: phi at d = d_prev and the force were t1 at the bracket's two ends
            // (lower, upper)
            let mut bracket = (0.0, 0.0, 0.0, 0.0);
            let (d, found, theta, force) = if let Some(lowest) = released {
                if u > lowest_g && u > lowest + tol {
                    return Ok(None);
                }
                released = Some(lowest.min(u));
                (u, Found::Released, 0.0, 0.0)
            } else {
                let phi_ref = |j: usize, decay: &[f64]| {
                    p_ref - dot(decay, integrals.p(j)) + r.g_inf * (d_prev - ends[j].depth)
                };
                let force_at =
                    |j: usize, decay: &[f64]| dot(decay, integrals.q(j)) + r.g_inf * ends[j].area;
                let mut direction = 0i8;
                let mut tries = 0;
                loop {
                    tries += 1;
                    if tries > 2 * ends.len() + 4 {
                        return Ok(None);
                    }
                    let hi_phi = phi_ref(upper, &decay_upper);
                    let hi_force = force_at(upper, &decay_upper);
                    let at_end = u - hi_force / kw;
                    if upper == last && hi_phi + c.g_eff * (at_end - d_prev) > 0.0 {
                        break (at_end, Found::AtEnd, 1.0, hi_force);
                    }
                    if upper <= first {
                        released = Some(u);
                        break (u, Found::Released, 0.0, 0.0);
                    }
                    let into = &coefficients[ends[upper].coefficients].1;
                    for ((lower, e_k), decay) in
                        decay_lower.iter_mut().zip(&decay_upper).zip(&into.decay)
                    {
                        *lower = e_k * decay;
                    }
                    let lo_phi = phi_ref(upper - 1, &decay_lower);
                    let span = lo_phi - hi_phi;
                    // theta: where t1 falls between the two ends (1 above, <= 0 below)
                    let (d, theta, lo_force, w) = if span > 0.0 {
                        let lo_force = force_at(upper - 1, &decay_lower);
                        let jump = hi_force - lo_force;
                        let shape = Shape::new(&ends[upper - 1], &ends[upper]);
                        let depth_at = |theta: f64| d_prev + (theta * span - lo_phi) / c.g_eff;
                        // the balance's excess at t1's fraction theta, and its derivative
                        let mut excess = |theta: f64| {
                            let (w, dw) = shape.weight(theta, &area, &mut node);
                            (
                                kw * (u - depth_at(theta)) - lo_force - w * jump,
                                -kw * span / c.g_eff - dw * jump,
                                w,
                            )
                        };
                        if excess(1.0).0 > 0.0 {
                            (depth_at(1.0), 2.0, lo_force, 1.0)
                        } else if excess(0.0).0 < 0.0 {
                            (depth_at(0.0), -1.0, lo_force, 0.0)
                        } else {
                            let theta = root_in_unit(&mut excess);
                            (depth_at(theta), theta, lo_force, excess(theta).2)
                        }
                    } else if direction > 0 {
                        // the depth did not move between the two ends: t1 above them
                        (at_end, 2.0, hi_force, 1.0)
                    } else {
                        (at_end, 0.0, hi_force, 0.0)
                    };
                    if theta > 1.0 && direction >= 0 && upper < last {
                        direction = 1;
                        upper += 1;
                        let age = step.time - ends[upper].time;
                        for (e_k, &(_, tau)) in decay_upper.iter_mut().zip(&r.terms) {
                            let next = (-age / tau).exp();
                            *e_k = if next < NEGLIGIBLE { 0.0 } else { next };
                        }
                        continue;
                    }
                    if theta > 1.0 && (span <= 0.0 || span.is_nan()) {
                        break (at_end, Found::AtEnd, 1.0, hi_force);
                    }
                    if theta <= 0.0 && direction <= 0 {
                        direction = -1;
                        upper -= 1;
                        std::mem::swap(&mut decay_upper, &mut decay_lower);
                        continue;
                    }
                    let theta = theta.clamp(0.0, 1.0);
                    bracket = (lo_phi, hi_phi, lo_force, hi_force);
                    break (
                        d,
                        Found::Between,
                        theta,
                        lo_force + w.clamp(0.0, 1.0) * (hi_force - lo_force),
                    );
                }
            };
            // t1 (in rising ends) must not move later: the contact shrinks, or Ting's
            // construction does not hold
            let t1 = match found {
                Found::Released => f64::NEG_INFINITY,
                Found::AtEnd => upper as f64,
                Found::Between => (upper - 1) as f64 + theta,
            };
            if t1 > t1_before + REGROWTH {
                return Ok(None);
            }
            t1_before = t1;
            let dd = d - d_prev;
            // P_k's derivatives at this step with the depth's own derivative left out
            let (decay, gain, p_old) = (&c.decay[..m], &c.gain[..m], &p_now[..m]);
            for (j, total) in sum_dp.iter_mut().enumerate() {
                // the slices cut to one length: the loop runs without bounds checks
                let row = j * m..(j + 1) * m;
                let (out, old) = (&mut dp_new[row.clone()], &dp_now[row.clone()]);
                let (d_decay, d_gain) = (&c.d_decay[row.clone()], &c.d_gain[row]);
                let before = dd_prev[j];
                for k in 0..m {
                    out[k] = d_decay[k] * p_old[k] + decay[k] * old[k] + d_gain[k] * dd
                        - gain[k] * before;
                }
                *total = sum(out);
            }
            let now = Now {
                time: step.time,
                depth: d,
                dd,
                damping,
                h,
                dd_prev: &dd_prev,
                sum_dp: &sum_dp,
            };
            let radius = match found {
                Found::Released => {
                    for (x, &rate) in d_now.iter_mut().zip(rates) {
                        *x = rate * step.along;
                    }
                    0.0
                }
                Found::AtEnd => {
                    falling.force_derivatives(
                        &now,
                        upper,
                        &decay_upper,
                        &mut scratch,
                        &mut d_force,
                    );
                    for j in 0..p {
                        d_now[j] = (kw * rates[j] * step.along - d_force[j]) / kw;
                    }
                    ends[upper].radius
                }
                Found::Between => {
                    falling.force_derivatives(
                        &now,
                        upper,
                        &decay_upper,
                        &mut hi_dphi,
                        &mut d_force,
                    );
                    falling.force_derivatives(
                        &now,
                        upper - 1,
                        &decay_lower,
                        &mut lo_dphi,
                        &mut lo_df,
                    );
                    // phi at the step's depth: it moves by g_eff (d - d_prev)
                    let (lo_phi, hi_phi, lo_force, hi_force) = bracket;
                    let (lo_phi, hi_phi) = (lo_phi + c.g_eff * dd, hi_phi + c.g_eff * dd);
                    let span = lo_phi - hi_phi;
                    let jump = hi_force - lo_force;
                    let (lo, hi) = (&ends[upper - 1], &ends[upper]);
                    let shape = Shape::new(lo, hi);
                    let (w, dw) = shape.weight(theta, &area, &mut node);
                    let d1 = lo.depth + theta * (hi.depth - lo.depth);
                    let (_, radius, _) = area.at(d1, &mut node);
                    let slope = c.g_eff * jump * dw / span;
                    for j in 0..p {
                        let d_theta = (lo_phi * hi_dphi[j] - hi_phi * lo_dphi[j]) / (span * span);
                        let (d_lo, d_hi) = (ends_d[(upper - 1) * p + j], ends_d[upper * p + j]);
                        let d_w = if shape.area > 0.0 {
                            let d_d1 =
                                d_lo + theta * (d_hi - d_lo) + d_theta * (hi.depth - lo.depth);
                            (radius * d_d1 - lo.radius * d_lo * (1.0 - w) - hi.radius * d_hi * w)
                                / shape.area
                        } else {
                            d_theta
                        };
                        let x = (1.0 - w) * lo_df[j] + w * d_force[j] + d_w * jump;
                        d_now[j] = (kw * rates[j] * step.along - x) / (kw + slope);
                    }
                    radius
                }
            };
            for ((now, new), &step_d) in dp_now
                .chunks_exact_mut(m.max(1))
                .zip(dp_new.chunks_exact(m.max(1)))
                .zip(&d_now)
            {
                for ((x, &y), &g) in now.iter_mut().zip(new).zip(&c.gain) {
                    *x = y + g * step_d;
                }
            }
            for (pk, (decay, gain)) in p_now.iter_mut().zip(c.decay.iter().zip(&c.gain)) {
                *pk = decay * *pk + gain * dd;
            }
            put(
                &mut e,
                step.sample,
                WEIGHT * force,
                stiffness,
                rates,
                step.along,
                &d_now,
                || area.elements_within(radius),
            );
            d_prev = d;
            dd_prev.copy_from_slice(&d_now);
        }
        Ok(finite(e))
    }
}

/// The evaluation, or None (the elements instead) should anything in it not be finite.
fn finite(e: Evaluation) -> Option<Evaluation> {
    let all = |v: &[f64]| v.iter().all(|x| x.is_finite());
    (all(&e.values) && all(&e.jacobian)).then_some(e)
}

/// The shape of the force between two rising ends as t1 moves from one to the other: the
/// area's share of its change, (A(d1) - A_lo) / (A_hi - A_lo) at the depth d1 linear in
/// t1's fraction theta (exact for an elastic medium; the force near the release falls
/// smoothly to zero as A does, rather than linearly), theta itself where the area does not
/// change.
struct Shape {
    lo: (f64, f64),
    hi_depth: f64,
    /// A_hi - A_lo (m^2).
    area: f64,
}

impl Shape {
    fn new(lo: &End, hi: &End) -> Self {
        Shape {
            lo: (lo.depth, lo.area),
            hi_depth: hi.depth,
            area: hi.area - lo.area,
        }
    }

    /// (w, dw / dtheta) at theta in [0, 1].
    fn weight(&self, theta: f64, area: &AreaFunction, node: &mut usize) -> (f64, f64) {
        if self.area <= 0.0 || self.area.is_nan() {
            return (theta, 1.0);
        }
        let rise = self.hi_depth - self.lo.0;
        let (a1, radius, _) = area.at(self.lo.0 + theta * rise, node);
        ((a1 - self.lo.1) / self.area, radius * rise / self.area)
    }
}

/// The root in [0, 1] of a decreasing `excess` (value, derivative, w) that is >= 0 at 0 and
/// <= 0 at 1: Newton's method kept in the bracket, a bisection where it would leave it.
fn root_in_unit(excess: &mut impl FnMut(f64) -> (f64, f64, f64)) -> f64 {
    let (mut lo, mut hi) = (0.0, 1.0);
    let mut theta = 0.5;
    for _ in 0..100 {
        let (g, slope, _) = excess(theta);
        if g == 0.0 {
            return theta;
        }
        if g > 0.0 {
            lo = theta;
        } else {
            hi = theta;
        }
        let mut next = if slope < 0.0 {
            theta - g / slope
        } else {
            f64::NAN
        };
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        if (next - theta).abs() <= 1e-15 || hi - lo <= 1e-15 {
            return next;
        }
        theta = next;
    }
    theta
}

/// eta / h, 0 without a dashpot.
fn damping_of(eta: f64, h: f64) -> f64 {
    if eta == 0.0 {
        0.0
    } else {
        eta / h
    }
}

/// Sets `sample` (if any): the `force` (N) and its derivatives k (rate du/dshift - dd)
/// along each tangent (`stiffness` k in N/m), and the elements in contact.
#[allow(clippy::too_many_arguments)]
fn put(
    e: &mut Evaluation,
    sample: Option<usize>,
    force: f64,
    stiffness: f64,
    rates: &[f64],
    along: f64,
    d_depth: &[f64],
    contact: impl FnOnce() -> usize,
) {
    if let Some(s) = sample {
        let p = rates.len();
        e.values[s] = force;
        for ((out, &rate), dd) in e.jacobian[s * p..(s + 1) * p]
            .iter_mut()
            .zip(rates)
            .zip(d_depth)
        {
            *out = stiffness * (rate * along - dd);
        }
        e.contact[s] = contact();
    }
}

/// The depth d with kw (u - d) = F(d), F non-decreasing (`force` gives F and dF/dd, per
/// unit weight): Newton's method from `guess` (each step towards the root; the root
/// bracketed by the iterates, a bisection where a step would leave the bracket), to `tol`
/// (m). F is convex where the contact grows (A(d) is), so Newton's steps settle from above.
fn balance(kw: f64, u: f64, guess: f64, tol: f64, mut force: impl FnMut(f64) -> (f64, f64)) -> f64 {
    let (mut lo, mut hi) = (f64::NEG_INFINITY, f64::INFINITY);
    let mut d = guess;
    for _ in 0..200 {
        let (f, slope) = force(d);
        let excess = kw * (u - d) - f;
        // zero to the round-off of its terms
        if excess.abs() <= 8.0 * f64::EPSILON * (kw * (u.abs() + d.abs()) + f.abs()) {
            return d;
        }
        if excess > 0.0 {
            lo = d;
        } else {
            hi = d;
        }
        let mut next = d + excess / (kw + slope.max(0.0));
        if !(next > lo && next < hi) {
            if !(lo.is_finite() && hi.is_finite()) {
                // a step that does not move d: the root to round-off
                return d;
            }
            next = 0.5 * (lo + hi);
        }
        if (next - d).abs() <= tol.max(4.0 * f64::EPSILON * d.abs()) || hi - lo <= tol {
            return next;
        }
        d = next;
    }
    d
}

/// The falling steps' reading of the rising ends.
struct Falling<'a> {
    r: &'a Rheology,
    tangents: &'a [Rheology],
    ends: &'a [End],
    ends_d: &'a [f64],
    integrals: &'a Integrals,
    /// Per tangent, (k, d tau_k / tau_k^2 in 1/s) of the terms whose tau moves.
    tau_rates: Vec<Vec<(usize, f64)>>,
}

/// The falling step: its end, depth (m), change of depth, the dashpot's eta / h, the step
/// h (s), the previous depth's derivatives and sum_k dP_k without this step's depth's.
struct Now<'a> {
    time: f64,
    depth: f64,
    dd: f64,
    damping: f64,
    h: f64,
    dd_prev: &'a [f64],
    sum_dp: &'a [f64],
}

impl Falling<'_> {
    /// phi at the rising end `j` and the force were t1 there: their derivatives along each
    /// tangent with the step's depth held (the depth's own derivative left out), into
    /// `d_phi` and `d_force`.
    fn force_derivatives(
        &self,
        now: &Now<'_>,
        j: usize,
        decay: &[f64],
        d_phi: &mut [f64],
        d_force: &mut [f64],
    ) {
        let (r, end) = (self.r, &self.ends[j]);
        let p = self.tangents.len();
        let (pj, qj) = (self.integrals.p(j), self.integrals.q(j));
        let rise = now.depth - end.depth;
        let age = now.time - end.time;
        for (i, t) in self.tangents.iter().enumerate() {
            let d_end = self.ends_d[j * p + i];
            let (dpj, dqj) = (self.integrals.dp(j, i), self.integrals.dq(j, i));
            let mut dp = t.g_inf * rise - r.g_inf * d_end + damping_of(t.eta, now.h) * now.dd
                - now.damping * now.dd_prev[i]
                + now.sum_dp[i]
                - dot(decay, dpj);
            let mut df = t.g_inf * end.area + r.g_inf * end.radius * d_end + dot(decay, dqj);
            for &(k, tau_rate) in &self.tau_rates[i] {
                let d_decay = decay[k] * age * tau_rate;
                dp -= d_decay * pj[k];
                df += d_decay * qj[k];
            }
            d_phi[i] = dp;
            d_force[i] = df;
        }
    }
}
