//! An indentation curve by MDR viscoelastic stepping, and its derivatives with respect to
//! the medium's parameters by forward-mode differentiation of the same steps: the forward
//! model of fits to measured curves.
//!
//! The stepping is that of `viscoelastic::run_mdr` (exact exponential updates of the Prony
//! stresses for a strain varying linearly over a step; an element touches where the
//! indenter reaches its freely relaxed surface) on the half of the even 1D profile, prepared
//! once: the profile at x_i = (i + 1/2) dx, each element counted twice, and the steps (the
//! sample times, each interval cut into `substeps` equal steps). The derivatives follow the
//! stepping exactly: the contact set is piecewise constant in the parameters, and inside it
//! every update is differentiable. Element count and contact-edge errors are the MDR
//! discretisation's and shared by the derivatives.

use crate::error::{check_finite, check_positive, Error, Result};
use crate::rheology::Rheology;

mod depth_control;
mod hereditary;
mod steps;

/// What the curve prescribes (the other quantity is computed).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Control {
    /// Depth (m) prescribed, force (N) computed.
    Depth,
    /// Force (N) prescribed, depth (m) computed.
    Force,
}

/// A prepared curve: the half profile, the samples and the steps between them.
#[derive(Debug, Clone, PartialEq)]
pub struct Curve {
    g: Vec<f64>,
    dx: f64,
    /// Sample times (s), >= 0, increasing.
    times: Vec<f64>,
    /// Prescribed depth (m) or force (N) at the sample times.
    values: Vec<f64>,
    control: Control,
    substeps: usize,
    /// Whether a depth-controlled curve may be evaluated by Ting's solution.
    hereditary: bool,
}

/// How a curve was evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Forward {
    /// Ting's solution: the MDR elements' forces integrated over the contact in closed
    /// form (depth control, a depth that rises and then falls, a profile rising away from
    /// its centre).
    Hereditary,
    /// The MDR elements stepped one by one (any history).
    Elements,
}

/// The curve's computed quantity at the sample times and its derivatives.
#[derive(Debug, Clone, PartialEq)]
pub struct Evaluation {
    /// Force (N, depth control) or depth (m, force control) at each sample time.
    pub values: Vec<f64>,
    /// d values / d parameter: one row per sample, one column per tangent (row-major).
    pub jacobian: Vec<f64>,
    /// Elements in contact at each sample time (of the half profile).
    pub contact: Vec<usize>,
    /// How the curve was evaluated.
    pub forward: Forward,
}

/// Coefficients of one step of length h and their derivatives along each tangent.
struct StepCoefficients {
    decay: Vec<f64>,
    gain: Vec<f64>,
    g_eff: f64,
    /// g_eff - G_inf: what multiplies the old strain in the history term.
    relaxing: f64,
    /// Per tangent: d decay_k, d gain_k (m each), d g_eff, d relaxing.
    d_decay: Vec<f64>,
    d_gain: Vec<f64>,
    d_g_eff: Vec<f64>,
    d_relaxing: Vec<f64>,
}

impl StepCoefficients {
    fn new(r: &Rheology, tangents: &[Rheology], h: f64) -> Self {
        let m = r.terms.len();
        let mut decay = Vec::with_capacity(m);
        let mut gain = Vec::with_capacity(m);
        // per term: a = (tau / h)(1 - e) and da / dtau
        let mut da = Vec::with_capacity(m);
        let mut de = Vec::with_capacity(m);
        for &(g, tau) in &r.terms {
            let x = h / tau;
            let e = (-x).exp();
            let (a, a_tau) = if x < 1e-8 {
                (1.0 - 0.5 * x, 0.5 * x / tau)
            } else {
                (-(-x).exp_m1() / x, (-(-x).exp_m1() / h - e / tau))
            };
            decay.push(e);
            gain.push(g * a);
            da.push(a_tau);
            de.push(e * x / tau);
        }
        let damping = if r.eta == 0.0 { 0.0 } else { r.eta / h };
        let g_eff = r.g_inf + gain.iter().sum::<f64>() + damping;
        let p = tangents.len();
        let (mut d_decay, mut d_gain) = (vec![0.0; p * m], vec![0.0; p * m]);
        let (mut d_g_eff, mut d_relaxing) = (vec![0.0; p], vec![0.0; p]);
        for (j, t) in tangents.iter().enumerate() {
            let mut sum = if t.eta == 0.0 { 0.0 } else { t.eta / h };
            for k in 0..m {
                let (dg, dtau) = t.terms[k];
                let g = r.terms[k].0;
                d_decay[j * m + k] = de[k] * dtau;
                d_gain[j * m + k] = dg * gain[k] / g + g * da[k] * dtau;
                sum += d_gain[j * m + k];
            }
            d_relaxing[j] = sum;
            d_g_eff[j] = t.g_inf + sum;
        }
        StepCoefficients {
            decay,
            gain,
            g_eff,
            relaxing: g_eff - r.g_inf,
            d_decay,
            d_gain,
            d_g_eff,
            d_relaxing,
        }
    }
}

impl Curve {
    /// A curve of the even MDR profile `g` (m) sampled at x_i = (i + 1/2) dx (the half
    /// x >= 0), prescribed `values` (depth in m or force in N, per `control`) at `times`
    /// (s, >= 0, strictly increasing), each interval (and the first, from t = 0 at rest)
    /// stepped in `substeps` equal steps.
    pub fn new(
        g: Vec<f64>,
        dx: f64,
        times: Vec<f64>,
        values: Vec<f64>,
        control: Control,
        substeps: usize,
    ) -> Result<Self> {
        check_positive("element spacing dx", dx)?;
        if g.is_empty() {
            return Err(Error::InvalidInput("the 1D profile has no elements".into()));
        }
        check_finite("1D profile", &g)?;
        check_finite("times", &times)?;
        check_finite("prescribed values", &values)?;
        crate::error::check_len("prescribed values", values.len(), times.len())?;
        if times.is_empty() {
            return Err(Error::InvalidInput("the curve has no samples".into()));
        }
        if times[0] < 0.0 {
            return Err(Error::InvalidInput(format!(
                "times must be >= 0, got {}",
                times[0]
            )));
        }
        if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(Error::InvalidInput(format!(
                "times must increase strictly: t[{}] = {} is followed by t[{}] = {}",
                k,
                times[k],
                k + 1,
                times[k + 1]
            )));
        }
        if substeps == 0 {
            return Err(Error::InvalidInput("substeps must be >= 1".into()));
        }
        Ok(Curve {
            g,
            dx,
            times,
            values,
            control,
            substeps,
            hereditary: true,
        })
    }

    /// The same curve, always evaluated by stepping the elements.
    pub fn elements_only(mut self) -> Self {
        self.hereditary = false;
        self
    }

    /// The shortest and the longest step time (s): the range over which a medium's series
    /// must hold (`Medium::rheology_over`).
    pub fn time_range(&self) -> (f64, f64) {
        let mut prev = 0.0;
        let mut shortest = f64::INFINITY;
        for &t in &self.times {
            if t > prev {
                shortest = shortest.min((t - prev) / self.substeps as f64);
            }
            prev = t;
        }
        (shortest.min(prev), prev)
    }

    /// Number of sample times.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether the curve has no samples (never: `new` refuses that).
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// The steps (end time in s, prescribed value at it) from the sample `from` to the
    /// sample `to`, both (time, value): `substeps` equal steps, or at t = 0 one step of
    /// length zero to a value already there (none for a medium with a dashpot under force
    /// control, which takes a step force without moving; an error under depth control),
    /// and none to a depth <= 0 (no contact).
    fn substeps_to(
        &self,
        r: &Rheology,
        from: (f64, f64),
        to: (f64, f64),
    ) -> Result<Vec<(f64, f64)>> {
        let ((t_prev, value_prev), (t_sample, v_sample)) = (from, to);
        if t_sample == 0.0 {
            // at rest, no contact: nothing to step (a depth <= 0 touches no element)
            if v_sample == 0.0 || (self.control == Control::Depth && v_sample < 0.0) {
                return Ok(vec![]);
            }
            if r.eta == 0.0 {
                return Ok(vec![(0.0, v_sample)]);
            }
            if self.control == Control::Depth {
                return Err(Error::InvalidInput(
                    "a depth already there at t = 0 needs an infinite force on a medium with a dashpot: start the samples from depth 0 or after t = 0".into(),
                ));
            }
            return Ok(vec![]);
        }
        Ok((1..=self.substeps)
            .map(|j| {
                let f = j as f64 / self.substeps as f64;
                let t = if j == self.substeps {
                    t_sample
                } else {
                    t_prev + f * (t_sample - t_prev)
                };
                (t, value_prev + f * (v_sample - value_prev))
            })
            .collect())
    }

    /// The computed quantity at the sample times for the medium `r`, and its derivatives
    /// along each of `tangents` (derivatives of r's coefficients, same shape as r).
    pub fn evaluate(&self, r: &Rheology, tangents: &[Rheology]) -> Result<Evaluation> {
        check_tangents(r, tangents)?;
        match self.control {
            Control::Depth => self.evaluate_depth_control(r, tangents, None),
            Control::Force => self.evaluate_force_control(r, tangents),
        }
    }

    /// `evaluate` of a depth-controlled curve with `shift` (m) added to every prescribed
    /// depth (a depth <= 0 at t = 0 is no contact), with the derivatives along the shift
    /// (N/m) as a last Jacobian column after those of the tangents: the forward model of a
    /// raw AFM curve, whose contact point offsets the depths.
    pub fn evaluate_shifted(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: f64,
    ) -> Result<Evaluation> {
        if self.control != Control::Depth {
            return Err(Error::InvalidInput(
                "a shift of the prescribed values needs a depth-controlled curve".into(),
            ));
        }
        check_finite("depth shift", &[shift])?;
        check_tangents(r, tangents)?;
        self.evaluate_depth_control(r, tangents, Some(shift))
    }

    /// `evaluate` under force control: the depth of each step balances the prescribed force
    /// over all elements, so the elements are stepped together, one step at a time.
    fn evaluate_force_control(&self, r: &Rheology, tangents: &[Rheology]) -> Result<Evaluation> {
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
            let substeps = self.substeps_to(r, (t_prev, value_prev), (t_sample, v_sample))?;
            let mut count = 0;
            let mut value = self.g.iter().copied().fold(f64::INFINITY, f64::min);
            d_value.iter_mut().for_each(|v| *v = 0.0);
            let mut clock = t_prev;
            for (t, prescribed) in substeps {
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
                // the depth that balances the force, and its derivatives
                let target = prescribed / (weight * c.g_eff);
                loop {
                    depth = depth_for(&relaxed[..reach], target, depth);
                    if reach == n || lowest_from[reach] >= depth {
                        break;
                    }
                    while reach < n && lowest_from[reach] < depth {
                        reach += 1;
                    }
                }
                in_contact.clear();
                in_contact.extend((0..reach).filter(|&i| relaxed[i] < depth));
                if in_contact.is_empty() {
                    // the indenter rests on the lowest relaxed point
                    let i = argmin(&relaxed[..reach]);
                    for j in 0..p {
                        d_depth[j] = -(d_history[i * p + j] * c.g_eff - history[i] * c.d_g_eff[j])
                            / (c.g_eff * c.g_eff);
                    }
                } else {
                    for (j, dd) in d_depth.iter_mut().enumerate() {
                        let sum: f64 = in_contact
                            .iter()
                            .map(|&i| c.d_g_eff[j] * (depth - self.g[i]) + d_history[i * p + j])
                            .sum();
                        *dd = -sum / (c.g_eff * in_contact.len() as f64);
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
                value = depth;
                d_value.copy_from_slice(&d_depth);
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

/// Refuses tangents whose Prony terms do not match the medium's.
fn check_tangents(r: &Rheology, tangents: &[Rheology]) -> Result<()> {
    let m = r.terms.len();
    match tangents.iter().find(|t| t.terms.len() != m) {
        Some(t) => Err(Error::InvalidInput(format!(
            "a tangent has {} Prony terms, the medium {m}",
            t.terms.len()
        ))),
        None => Ok(()),
    }
}

/// Index of the smallest entry.
fn argmin(v: &[f64]) -> usize {
    v.iter()
        .enumerate()
        .min_by(|a, b| a.1.total_cmp(b.1))
        .map_or(0, |(i, _)| i)
}

/// Depth d with sum max(d - s_i, 0) = `target` (m): the lowest s when target <= 0; else
/// Newton's method on the convex piecewise-linear sum from `guess`, which ends in finitely
/// many steps (from above it descends monotonically; from below the first step lands
/// above), and the sorted exact root should it not within 100 steps.
fn depth_for(relaxed: &[f64], target: f64, guess: f64) -> f64 {
    let lowest = relaxed.iter().copied().fold(f64::INFINITY, f64::min);
    if target <= 0.0 {
        return lowest;
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
        d = (target + sum) / count as f64;
    }
    let mut sorted = relaxed.to_vec();
    sorted.sort_unstable_by(f64::total_cmp);
    let mut prefix = Vec::with_capacity(sorted.len() + 1);
    crate::mdr::prefix_sums(&sorted, &mut prefix);
    crate::mdr::depth_on_sorted(&sorted, &prefix, target).0
}

#[cfg(test)]
mod hereditary_tests;
#[cfg(test)]
mod tests;
