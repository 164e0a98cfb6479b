//! Curves whose depth balances a load over all the elements: a prescribed force, or the
//! force of a spring pressed by a prescribed drive (an AFM cantilever on its piezo). Spring
//! control goes by Ting's solution (`spring_hereditary`) where it covers the history; else
//! the elements are stepped together, one step at a time; the derivatives follow the
//! stepping (the contact set piecewise constant in the parameters).

use super::{with_shift_tangent, Control, Curve, Evaluation, Forward, StepCoefficients};
use crate::model::contact_law::{ContactLaw, SortedSurface};
use crate::model::medium::rheology::Rheology;
use crate::support::error::Result;
use crate::support::monitor::Stop;

impl Curve {
    /// `evaluate` under force or spring control, with `shift` (m) added to every drive
    /// (spring control; its derivative a last column): the depth of each step balances
    /// the prescribed force, or the spring's k (u - depth), over all elements, so the
    /// elements are stepped together, one step at a time.
    pub(super) fn evaluate_balance(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: Option<f64>,
        stop: &Stop,
    ) -> Result<Evaluation> {
        let stiffness = match self.control {
            Control::Spring(k) => k,
            _ => 0.0,
        };
        let (all, rates) = with_shift_tangent(r, tangents, shift.is_some());
        let tangents = &all[..];
        let shift = shift.unwrap_or(0.0);
        if self.hereditary && stiffness > 0.0 {
            if let Some(e) =
                self.evaluate_spring_hereditary(r, tangents, &rates, shift, stiffness, stop)?
            {
                return Ok(e);
            }
        }
        let (n, m, p) = (self.g.len(), r.terms.len(), tangents.len());
        let k_out = self.times.len();
        let mut out = Evaluation {
            values: Vec::with_capacity(k_out),
            jacobian: Vec::with_capacity(k_out * p),
            contact: Vec::with_capacity(k_out),
            forward: Forward::Elements,
        };
        let (mut w, mut q) = (vec![0.0; n], vec![0.0; n * m]);
        let (mut dw, mut dq) = (vec![0.0; n * p], vec![0.0; n * m * p]);
        // elements from `reach` on have never touched: their state is zero and their relaxed
        // surface the profile, lowest_from[i] = min_{j >= i} g_j tells when one may touch
        let (mut relaxed, mut history) = (self.g.clone(), vec![0.0; n]);
        let mut lowest_from = vec![f64::INFINITY; n + 1];
        for i in (0..n).rev() {
            lowest_from[i] = lowest_from[i + 1].min(self.g[i]);
        }
        let mut reach = 1;
        let mut d_history = vec![0.0; n * p];
        let mut d_value = vec![0.0; p];
        let mut d_depth = vec![0.0; p];
        let mut in_contact = Vec::with_capacity(n);
        // each element stands for itself and its mirror image
        let weight = 8.0 * self.dx;
        let mut depth = 0.0;
        let mut t_prev = 0.0;
        let mut value_prev = 0.0;
        let mut coefficients: Option<(f64, StepCoefficients)> = None;
        for (&t_sample, &v_sample) in self.times.iter().zip(&self.values) {
            let v_sample = v_sample + shift;
            let substeps = self.substeps_to(r, (t_prev, value_prev), (t_sample, v_sample))?;
            let mut count = 0;
            // a sample without steps (at rest at t = 0): no force; the depth of the lowest point
            let mut value = if stiffness > 0.0 {
                0.0
            } else {
                self.g.iter().copied().fold(f64::INFINITY, f64::min)
            };
            d_value.iter_mut().for_each(|v| *v = 0.0);
            let mut clock = t_prev;
            for (t, prescribed) in substeps {
                stop.check()?;
                let h = t - clock;
                clock = t;
                let fresh = !matches!(&coefficients, Some((hh, _)) if *hh == h);
                if fresh {
                    coefficients = Some((h, StepCoefficients::new(r, tangents, h)));
                }
                let c = &coefficients.as_ref().expect("set above").1;
                for i in 0..reach {
                    let qi = &q[i * m..(i + 1) * m];
                    let mut hist = -c.relaxing * w[i];
                    for (e, qk) in c.decay.iter().zip(qi) {
                        hist += e * qk;
                    }
                    history[i] = hist;
                    relaxed[i] = self.g[i] - hist / c.g_eff;
                    for j in 0..p {
                        let dqi = &dq[(i * p + j) * m..(i * p + j + 1) * m];
                        let mut dh = -c.d_relaxing[j] * w[i] - c.relaxing * dw[i * p + j];
                        for k in 0..m {
                            dh += c.d_decay[j * m + k] * qi[k] + c.decay[k] * dqi[k];
                        }
                        d_history[i * p + j] = dh;
                    }
                }
                // the depth that balances the force, and its derivatives: sum over the
                // contact of (depth - relaxed) = target - kappa depth
                let kappa = stiffness / (weight * c.g_eff);
                let target = if stiffness > 0.0 {
                    kappa * prescribed
                } else {
                    prescribed / (weight * c.g_eff)
                };
                loop {
                    depth = depth_for(&relaxed[..reach], target, kappa, depth);
                    if reach == n || lowest_from[reach] >= depth {
                        break;
                    }
                    while reach < n && lowest_from[reach] < depth {
                        reach += 1;
                    }
                }
                in_contact.clear();
                in_contact.extend((0..reach).filter(|&i| relaxed[i] < depth));
                if in_contact.is_empty() && stiffness > 0.0 {
                    // the spring is slack: the indenter follows the drive
                    d_depth.copy_from_slice(&rates);
                } else if in_contact.is_empty() {
                    // the indenter rests on the lowest relaxed point
                    let i = argmin(&relaxed[..reach]);
                    for j in 0..p {
                        d_depth[j] = -(d_history[i * p + j] * c.g_eff - history[i] * c.d_g_eff[j])
                            / (c.g_eff * c.g_eff);
                    }
                } else {
                    // w sum (d g_eff (d - g_i) + d hist_i + g_eff dd) = k (rate - dd)
                    let count = in_contact.len() as f64;
                    for (j, dd) in d_depth.iter_mut().enumerate() {
                        let sum: f64 = in_contact
                            .iter()
                            .map(|&i| c.d_g_eff[j] * (depth - self.g[i]) + d_history[i * p + j])
                            .sum();
                        *dd = (kappa * c.g_eff * rates[j] - sum) / (c.g_eff * (count + kappa));
                    }
                }
                count = 0;
                for i in 0..reach {
                    let touching = relaxed[i] < depth;
                    let w_new = if touching {
                        count += 1;
                        depth - self.g[i]
                    } else {
                        relaxed[i] - self.g[i]
                    };
                    let dw_step = w_new - w[i];
                    for j in 0..p {
                        let dw_new = if touching {
                            d_depth[j]
                        } else {
                            -(d_history[i * p + j] * c.g_eff - history[i] * c.d_g_eff[j])
                                / (c.g_eff * c.g_eff)
                        };
                        let d_dw = dw_new - dw[i * p + j];
                        let dqi = &mut dq[(i * p + j) * m..(i * p + j + 1) * m];
                        let qi = &q[i * m..(i + 1) * m];
                        for k in 0..m {
                            dqi[k] = c.d_decay[j * m + k] * qi[k]
                                + c.decay[k] * dqi[k]
                                + c.d_gain[j * m + k] * dw_step
                                + c.gain[k] * d_dw;
                        }
                        dw[i * p + j] = dw_new;
                    }
                    let qi = &mut q[i * m..(i + 1) * m];
                    for ((qk, e), gain) in qi.iter_mut().zip(&c.decay).zip(&c.gain) {
                        *qk = e * *qk + gain * dw_step;
                    }
                    w[i] = w_new;
                }
                if stiffness > 0.0 {
                    value = stiffness * (prescribed - depth);
                    for ((v, dd), rate) in d_value.iter_mut().zip(&d_depth).zip(&rates) {
                        *v = stiffness * (rate - dd);
                    }
                } else {
                    value = depth;
                    d_value.copy_from_slice(&d_depth);
                }
            }
            out.values.push(value);
            out.jacobian.extend_from_slice(&d_value);
            out.contact.push(count);
            t_prev = t_sample;
            value_prev = v_sample;
        }
        Ok(out)
    }
}

/// Index of the smallest entry.
fn argmin(v: &[f64]) -> usize {
    v.iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i)
}

/// Depth d with sum max(d - s_i, 0) + kappa d = `target` (m; kappa >= 0, the spring's
/// stiffness over the medium's): with kappa = 0 the lowest s when target <= 0, with a
/// positive kappa target / kappa when that is at or below the lowest s (no contact); else Newton's
/// method on the convex piecewise-linear sum from `guess`, which ends in finitely many
/// steps (from above it descends monotonically; from below the first step lands above),
/// and the sorted exact root should it not within 100 steps.
fn depth_for(relaxed: &[f64], target: f64, kappa: f64, guess: f64) -> f64 {
    let lowest = relaxed.iter().copied().fold(f64::INFINITY, f64::min);
    if kappa == 0.0 && target <= 0.0 {
        return lowest;
    }
    if kappa > 0.0 && target <= kappa * lowest {
        return target / kappa;
    }
    let mut d = guess.max(lowest);
    let mut last = (usize::MAX, f64::NAN);
    for _ in 0..100 {
        let (mut count, mut sum) = (0usize, 0.0);
        for &s in relaxed {
            if s <= d {
                count += 1;
                sum += s;
            }
        }
        if (count, sum) == last {
            return d;
        }
        last = (count, sum);
        d = (target + sum) / (count as f64 + kappa);
    }
    if kappa == 0.0 {
        let surface = SortedSurface::new(relaxed);
        return ContactLaw::Hard.depth_for_compression(&surface, target).0;
    }
    let mut sorted = relaxed.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    // the first count whose root lies below the next relaxed height
    let mut sum = 0.0;
    for (count, s) in sorted.iter().enumerate() {
        sum += s;
        let d = (target + sum) / (count as f64 + 1.0 + kappa);
        if sorted.get(count + 1).is_none_or(|&next| d <= next) {
            return d;
        }
    }
    target / kappa
}
