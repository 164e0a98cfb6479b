//! Adhesive MDR contact by Heß's rule (Heß 2011; Popov & Heß 2015, ch. 6): the elements
//! attached to the indenter, settled at each step under a depth or a load.
//!
//! An element attaches when the indenter reaches its free surface (the touch rule: a JKR
//! contact of zero range grows as a hard one) and lets go when its elongation g_i - d
//! exceeds the contact law's detachment elongation at the current contact radius
//! a = (elements attached) dx / 2 — sqrt(2 pi a w / E*) under JKR, which makes the
//! contact's edge a crack in Griffith equilibrium: the JKR solution for any axisymmetric
//! profile. Letting go starts at the outermost element (the largest g), and each release
//! shrinks a and with it the elongation the next element may carry: a pull-off is that
//! cascade running to the last element.
//!
//! A step visits only what changes. The attached elements all move with the indenter
//! (w_i = d - g_i), so their Prony stresses differ from those of one reference point
//! driven by the depth, P_k, by a decaying constant each: q_ik(t) = P_k(t) +
//! exp(-(t - t_i) / tau_k) c_ik, fixed when element i attaches at t_i. Their sums over the
//! attached set (the force, the sum of their free surfaces) are advanced as aggregates,
//! and an element's own state is formed only when it attaches or lets go: O(terms) per step
//! and per change. The elements that have let go relax freely and may touch again: they are
//! stepped one by one (none on an elastic body, where a released element is at rest at
//! once); the untouched ones are at rest and wait in the order of their heights.

use crate::mdr::adhesion_crack::CrackTip;
use crate::mdr::foundation::Fields1D;
use crate::model::contact_law::ContactLaw;
use crate::model::loading::Loading;
use crate::model::medium::rheology::{Rheology, StepRule, StepRules};
use crate::stepping::{jumps_at_start, step_times, Jumps, Request, Series, Trail};
use crate::support::error::Result;
use crate::support::monitor::Monitor;
use std::collections::BTreeSet;

/// Where an element stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum State {
    /// Never touched (at rest, its free surface g_i).
    Untouched,
    Attached,
    /// Let go: relaxing freely, its displacement and Prony stresses stored.
    Released,
}

/// The foundation's elements in adhesive contact, advanced step by step.
#[derive(Debug, Clone)]
pub struct AdhesiveElements {
    law: ContactLaw,
    /// Contact modulus (Pa) of Heß's rule.
    e_star: f64,
    dx: f64,
    g: Vec<f64>,
    /// Relaxation times (s) of the Prony terms.
    taus: Vec<f64>,
    /// Whether a released element is at once at rest (no Prony term, no dashpot).
    elastic: bool,
    state: Vec<State>,
    /// Element indices by height, lowest first, and each element's rank in that order.
    order: Vec<usize>,
    rank: Vec<usize>,
    /// Ranks below this have been touched.
    untouched_from: usize,
    /// Ranks of the attached elements.
    attached: BTreeSet<usize>,
    /// Sum of g over the attached elements (m).
    sum_g: f64,
    /// The reference point's depth (m) and Prony stresses P_k (Pa) at the last step's end.
    depth: f64,
    reference: Vec<f64>,
    /// Sum of the attached elements' Prony stresses (Pa) at the last step's end.
    stress_sum: Vec<f64>,
    /// Time (s) of the last step's end.
    t: f64,
    /// Per element: the displacement w (m) of a released one.
    w: Vec<f64>,
    /// Per element and term: the Prony stresses of a released one, c_ik of an attached one.
    q: Vec<f64>,
    /// Per element: when an attached one attached (s).
    since: Vec<f64>,
    /// The released elements.
    released: Vec<usize>,
    /// The edge's crack when it lets go by its process zone (a JKR law with a zone stress on
    /// a viscoelastic body) instead of Heß's rule with `e_star`.
    crack: Option<CrackTip>,
}

/// One step's view of the elements: the rule, and the free surfaces of the attached set.
struct Settling<'a> {
    rule: &'a StepRule,
    /// The step's end time (s) and its number of attached elements at the start.
    t: f64,
    start_count: usize,
    /// Whether the edge carries tension after the last check of `release`.
    tensile: bool,
    /// Number of attached elements and the sum (m) of their free surfaces.
    count: usize,
    sum: f64,
    /// Elements attached during this step's settling, attached ones let go, and elements
    /// attached and let go again.
    joined: Vec<usize>,
    left: Vec<usize>,
    returned: Vec<usize>,
    /// The lowest untouched rank not yet attached in this step.
    next_untouched: usize,
    /// The released elements by free surface, lowest first: (surface, element).
    candidates: Vec<(f64, usize)>,
    next_candidate: usize,
}

impl AdhesiveElements {
    /// No element attached, on the profile `g` (m, spacing `dx` m) of a body of contact
    /// modulus `e_star` (Pa, Heß's rule) and relaxation modulus `medium`, in contact by `law`.
    pub fn new(g: &[f64], dx: f64, law: ContactLaw, e_star: f64, medium: &Rheology) -> Self {
        let n = g.len();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| g[i].total_cmp(&g[j]));
        let mut rank = vec![0; n];
        for (r, &i) in order.iter().enumerate() {
            rank[i] = r;
        }
        let m = medium.internal();
        let crack = match law {
            ContactLaw::Jkr {
                work_of_adhesion,
                stress: Some(stress),
            } if m > 0 || medium.eta > 0.0 => Some(CrackTip::new(work_of_adhesion, stress, medium)),
            _ => None,
        };
        AdhesiveElements {
            law,
            e_star,
            dx,
            g: g.to_vec(),
            taus: medium.terms.iter().map(|&(_, tau)| tau).collect(),
            elastic: m == 0 && medium.eta == 0.0,
            state: vec![State::Untouched; n],
            order,
            rank,
            untouched_from: 0,
            attached: BTreeSet::new(),
            sum_g: 0.0,
            depth: 0.0,
            reference: vec![0.0; m],
            stress_sum: vec![0.0; m],
            t: 0.0,
            w: vec![0.0; n],
            q: vec![0.0; n * m],
            since: vec![0.0; n],
            released: Vec::new(),
            crack,
        }
    }

    /// Whether element `i` is attached.
    pub fn is_attached(&self, i: usize) -> bool {
        self.state[i] == State::Attached
    }

    /// Number of attached elements.
    pub fn count(&self) -> usize {
        self.attached.len()
    }

    /// The Prony stresses (Pa) of element `i` at the last step's end.
    fn stresses(&self, i: usize) -> Vec<f64> {
        let m = self.taus.len();
        let own = &self.q[i * m..(i + 1) * m];
        match self.state[i] {
            State::Attached => (0..m)
                .map(|k| {
                    self.reference[k] + (-(self.t - self.since[i]) / self.taus[k]).exp() * own[k]
                })
                .collect(),
            _ => own.to_vec(),
        }
    }

    /// Displacement (m) of element `i` at the last step's end.
    fn displacement(&self, i: usize) -> f64 {
        match self.state[i] {
            State::Attached => self.depth - self.g[i],
            State::Released => self.w[i],
            State::Untouched => 0.0,
        }
    }

    /// Free surface (m) of element `i` in a step by `rule`: where the indenter meets it.
    fn surface(&self, rule: &StepRule, i: usize) -> f64 {
        if self.state[i] == State::Untouched {
            return self.g[i];
        }
        self.g[i] - rule.history(self.displacement(i), &self.stresses(i)) / rule.g_eff
    }

    /// The free surfaces (m) of all elements in a step by `rule` (for field output).
    pub fn surfaces(&self, rule: &StepRule) -> Vec<f64> {
        (0..self.g.len()).map(|i| self.surface(rule, i)).collect()
    }

    /// Displacements w (m) of all elements at the last step's end.
    pub fn displacements(&self) -> Vec<f64> {
        (0..self.g.len()).map(|i| self.displacement(i)).collect()
    }

    /// Starts a step by `rule`: the attached set's sum of free surfaces, the released
    /// elements' surfaces in order.
    fn begin<'a>(&self, rule: &'a StepRule, t: f64) -> Settling<'a> {
        let count = self.count();
        let w_sum = count as f64 * self.depth - self.sum_g;
        let r_sum = if count > 0 {
            rule.history(w_sum, &self.stress_sum)
        } else {
            0.0
        };
        let mut candidates: Vec<(f64, usize)> = self
            .released
            .iter()
            .map(|&i| (self.surface(rule, i), i))
            .collect();
        candidates.sort_by(|a, b| a.0.total_cmp(&b.0));
        Settling {
            rule,
            t,
            start_count: count,
            tensile: false,
            count,
            sum: self.sum_g - r_sum / rule.g_eff,
            joined: Vec::new(),
            left: Vec::new(),
            returned: Vec::new(),
            next_untouched: self.untouched_from,
            candidates,
            next_candidate: 0,
        }
    }

    /// The lowest free surface not yet attached in this step: (surface, element).
    fn next_touch(&self, s: &Settling) -> Option<(f64, usize)> {
        let untouched = self.order.get(s.next_untouched).map(|&i| (self.g[i], i));
        let released = s.candidates.get(s.next_candidate).copied();
        match (untouched, released) {
            (Some(u), Some(r)) => Some(if r.0 < u.0 { r } else { u }),
            (u, r) => u.or(r),
        }
    }

    fn attach(&mut self, s: &mut Settling, (surface, i): (f64, usize)) {
        if self.state[i] == State::Untouched {
            s.next_untouched += 1;
        } else {
            s.next_candidate += 1;
        }
        s.joined.push(i);
        self.attached.insert(self.rank[i]);
        s.count += 1;
        s.sum += surface;
    }

    /// Lets go the elements whose elongation exceeds the detachment elongation, from the
    /// outside in, at the depth `depth(count, sum)` (m) the attached set gives; whether any
    /// let go.
    fn release(&mut self, s: &mut Settling, depth: impl Fn(usize, f64) -> f64) -> bool {
        let mut released = false;
        while let Some(&top) = self.attached.last() {
            let i = self.order[top];
            let d = depth(s.count, s.sum);
            let a = 0.5 * s.count as f64 * self.dx;
            // its state is still the step's start: its surface is that of this step
            let surface = self.surface(s.rule, i);
            let holds = match &self.crack {
                Some(crack) => {
                    let tension = 4.0 * s.rule.g_eff * (surface - d);
                    s.tensile = tension > 0.0;
                    let a0 = 0.5 * s.start_count as f64 * self.dx;
                    !crack.lets_go(tension, a, a0, self.t, s.t)
                }
                None => self.g[i] - d <= self.law.detachment_elongation(a, self.e_star),
            };
            if holds {
                break;
            }
            self.attached.remove(&top);
            if let Some(k) = s.joined.iter().position(|&j| j == i) {
                s.joined.swap_remove(k);
                s.returned.push(i);
            } else {
                s.left.push(i);
            }
            s.count -= 1;
            s.sum -= surface;
            released = true;
        }
        released
    }

    /// Settles the attached set under an indenter at depth `d` (m) in a step by `rule`:
    /// every touched element attaches, then elements let go from the outside in; the
    /// compression sum_i (d - surface_i) (m) of the attached ones (negative when they pull).
    pub fn at_depth(&mut self, rule: &StepRule, t: f64, d: f64) -> f64 {
        let mut s = self.begin(rule, t);
        while let Some(next) = self.next_touch(&s) {
            if next.0 >= d {
                break;
            }
            self.attach(&mut s, next);
        }
        self.release(&mut s, |_, _| d);
        let compression = if s.count > 0 {
            s.count as f64 * d - s.sum
        } else {
            0.0
        };
        self.finish(s, t, d);
        compression
    }

    /// Settles the attached set under the load `load` (m: the force over the element
    /// stiffness) in a step by `rule` and returns the depth (m) that carries it; None when no
    /// element stays attached under a tensile load (the indenter has come off). A zero load
    /// without contact touches the lowest free surface.
    pub fn under_load(&mut self, rule: &StepRule, t: f64, load: f64) -> Option<f64> {
        let mut s = self.begin(rule, t);
        let depth = |count: usize, sum: f64| (load + sum) / count as f64;
        let result = loop {
            while let Some(next) = self.next_touch(&s) {
                let reaches = if s.count == 0 {
                    load > 0.0
                } else {
                    next.0 < depth(s.count, s.sum)
                };
                if !reaches {
                    break;
                }
                self.attach(&mut s, next);
            }
            // settled unless elements let go and some stay (then more may touch)
            let released = s.count > 0 && self.release(&mut s, depth);
            if !released || s.count == 0 {
                break if s.count > 0 {
                    Some(depth(s.count, s.sum))
                } else if load >= 0.0 {
                    Some(self.lowest_surface(&s))
                } else {
                    None
                };
            }
        };
        self.finish(s, t, result.unwrap_or(f64::NAN));
        result
    }

    /// The lowest free surface (m) of all elements, none attached.
    fn lowest_surface(&self, s: &Settling) -> f64 {
        let untouched = self.order[self.untouched_from.min(self.order.len() - 1)];
        let mut lowest = self.surface(s.rule, untouched);
        for &(surface, _) in &s.candidates {
            lowest = lowest.min(surface);
        }
        for &i in &s.left {
            lowest = lowest.min(self.surface(s.rule, i));
        }
        lowest
    }

    /// Ends the step at time `t` (s) and depth `d` (m; NaN without contact): the elements
    /// that let go relax from their state, the attached ones follow the depth, the released
    /// ones relax freely.
    fn finish(&mut self, s: Settling, t: f64, d: f64) {
        let rule = s.rule;
        let m = self.taus.len();
        // the released elements relax freely: zero stress, w = surface - g
        let relax = |me: &mut Self, i: usize, surface: f64| {
            let w_old = me.displacement(i);
            let mut q = me.stresses(i);
            let w_new = surface - me.g[i];
            rule.advance(w_old, w_new, &mut q);
            me.w[i] = w_new;
            me.q[i * m..(i + 1) * m].copy_from_slice(&q);
        };
        for &(surface, i) in &s.candidates {
            if !s.joined.contains(&i) {
                relax(self, i, surface);
            }
        }
        let mut at_rest = Vec::new();
        for &i in &s.left {
            let surface = self.surface(rule, i);
            let q = self.stresses(i);
            for (sum, qk) in self.stress_sum.iter_mut().zip(&q) {
                *sum -= qk;
            }
            self.sum_g -= self.g[i];
            relax(self, i, surface);
            self.state[i] = State::Released;
            if self.elastic {
                at_rest.push(i);
            } else {
                self.released.push(i);
            }
        }
        // the attached set that stays follows the depth, as the reference point does
        let staying = s.count - s.joined.len();
        if staying > 0 {
            let step = d - self.depth;
            rule.advance(0.0, staying as f64 * step, &mut self.stress_sum);
            rule.advance(0.0, step, &mut self.reference);
        } else {
            // none attached: the sums are exactly empty (not their round-off)
            self.stress_sum.iter_mut().for_each(|v| *v = 0.0);
            self.reference.iter_mut().for_each(|v| *v = 0.0);
            self.sum_g = 0.0;
        }
        for &i in &s.joined {
            let w_old = self.displacement(i);
            let mut q = self.stresses(i);
            rule.advance(w_old, d - self.g[i], &mut q);
            let own = &mut self.q[i * m..(i + 1) * m];
            for (k, qk) in q.iter().enumerate() {
                self.stress_sum[k] += qk;
                own[k] = qk - self.reference[k];
            }
            self.sum_g += self.g[i];
            self.since[i] = t;
            self.state[i] = State::Attached;
        }
        self.released.retain(|&i| self.state[i] == State::Released);
        // untouched elements attached and let go within the step are untouched again, and on
        // an elastic body so is every element that lets go (it is at rest at once): they are
        // the highest of the attached set, which then holds the lowest elements
        self.untouched_from = s.next_untouched;
        let back: Vec<usize> = s
            .returned
            .iter()
            .copied()
            .filter(|&i| self.state[i] == State::Untouched)
            .collect();
        for i in back.into_iter().chain(at_rest) {
            self.state[i] = State::Untouched;
            self.w[i] = 0.0;
            self.untouched_from = self.untouched_from.min(self.rank[i]);
        }
        if let Some(crack) = &mut self.crack {
            let a = |count: usize| 0.5 * count as f64 * self.dx;
            crack.record(self.t, a(s.start_count), t, a(s.count), s.tensile);
        }
        if s.count > 0 {
            self.depth = d;
        }
        self.t = t;
    }
}

/// JKR by MDR on a viscoelastic foundation (elements 4 dx times `medium`, G_inf > 0) under
/// the 1D profile `g` (m, spacing `dx` m): `viscoelastic::run_mdr_adhesive` for
/// `ContactLaw::Jkr` (its arguments checked there), each step visiting the contact's edge,
/// the released elements and the elements that change only.
pub fn run_jkr(
    g: &[f64],
    dx: f64,
    medium: &Rheology,
    law: ContactLaw,
    loading: &Loading,
    request: &Request,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    let n = g.len();
    let mut elements = AdhesiveElements::new(g, dx, law, 4.0 * medium.g_inf, medium);
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => g.iter().copied().fold(f64::INFINITY, f64::min),
    };
    let mut depths = Trail::new(vec![start]);
    let field_rates = request.field_rates && !request.fields_at.is_empty();
    let mut displacements = field_rates.then(|| Trail::new(vec![0.0; n]));
    let mut out = Series::default();
    let mut jumps = Jumps::default();
    let mut before = (0.0, start, 0.0, 0usize);
    let mut t_prev = 0.0;
    let mut rules = StepRules::new(medium);
    for (s, &(t, output)) in steps.iter().enumerate() {
        let h = t - t_prev;
        let rule = rules.at(h);
        let c = 4.0 * dx * rule.g_eff;
        let fields = output && request.fields_at.contains(&out.t.len());
        // the free surfaces of the step, for the line load of the fields
        let surfaces = fields.then(|| elements.surfaces(rule));
        let (depth, force) = match loading {
            Loading::Depth(hist) => {
                let d = hist.depth(t);
                (d, c * elements.at_depth(rule, t, d))
            }
            Loading::Force(hist) => {
                let f = hist.force(t);
                (elements.under_load(rule, t, f / c).unwrap_or(f64::NAN), f)
            }
        };
        let count = elements.count();
        jumps.record(before, (t, depth, force, count));
        before = (t, depth, force, count);
        if h == 0.0 {
            // the jump at t = 0: rates start from the state just after it
            depths = Trail::new(vec![depth]);
            displacements = displacements.map(|_| Trail::new(elements.displacements()));
        }
        let mut rate = [0.0];
        depths.rate(t, &[depth], &mut rate);
        let w = (fields || field_rates).then(|| elements.displacements());
        if output {
            let k = out.t.len();
            out.t.push(t);
            out.depth.push(depth);
            out.force.push(force);
            out.contact_length.push(count as f64 * dx);
            out.saturated.push(count == n);
            out.velocity.push(rate[0]);
            out.iterations.push(0);
            if let (Some(surface), Some(w)) = (&surfaces, &w) {
                out.fields.push(Fields1D::of_step(
                    k,
                    t,
                    depth,
                    rule.g_eff,
                    surface,
                    |i| elements.is_attached(i),
                    w,
                    displacements.as_ref(),
                ));
            }
        }
        if h > 0.0 {
            depths.push(t, &[depth]);
            if let (Some(trail), Some(w)) = (&mut displacements, &w) {
                trail.push(t, w);
            }
        }
        out.steps = s + 1;
        monitor.progress("time steps", s + 1, steps.len())?;
        t_prev = t;
    }
    out.jumps = Some(jumps);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A flat punch lets go all at once when its elongation reaches sqrt(2 pi a w / E*),
    /// and holds any smaller one.
    #[test]
    fn a_flat_punch_lets_go_at_once() {
        let (n, a, w, e) = (10, 1.0, 0.5, 2.0);
        let g = vec![0.0; n];
        let dx = 2.0 * a / n as f64;
        let law = ContactLaw::Jkr {
            work_of_adhesion: w,
            stress: None,
        };
        let medium = Rheology::new(e / 4.0, vec![], 0.0).unwrap();
        let rule = medium.step(1.0);
        let mut at = AdhesiveElements::new(&g, dx, law, e, &medium);
        at.at_depth(&rule, 1.0, 1e-3);
        assert_eq!(at.count(), n);
        let limit = (2.0 * std::f64::consts::PI * a * w / e).sqrt();
        at.at_depth(&rule, 2.0, -0.999 * limit);
        assert_eq!(at.count(), n);
        at.at_depth(&rule, 3.0, -1.001 * limit);
        assert_eq!(at.count(), 0);
    }
}
