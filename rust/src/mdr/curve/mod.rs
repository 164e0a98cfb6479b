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

use crate::model::medium::rheology::Rheology;
use crate::model::settings::MAX_STEPS;
use crate::support::error::{check_finite, check_positive, Error, Result};
use crate::support::monitor::Stop;

pub use adhesive::{AdhesiveEvaluation, Approach};

mod adhesive;
mod balance;
mod depth_control;
mod hereditary;
mod spring_hereditary;
mod steps;

/// What the curve prescribes (the other quantity is computed).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Depth (m) prescribed, force (N) computed.
    Depth,
    /// Force (N) prescribed, depth (m) computed.
    Force,
    /// A drive u (m) prescribed that pushes the indenter through a spring of this stiffness
    /// (N/m), the force k (u - depth) computed: an AFM cantilever on its piezo (u is the
    /// piezo's travel past the contact point, k the cantilever's spring constant).
    Spring(f64),
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
    /// Whether a depth- or spring-controlled curve may be evaluated by Ting's solution.
    hereditary: bool,
}

/// How a curve was evaluated.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Forward {
    /// Ting's solution: the MDR elements' forces integrated over the contact in closed
    /// form (depth control, or spring control with the depth balancing the spring at each
    /// step; a depth that rises and then falls, a profile rising away from its centre).
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
        crate::support::error::check_len("prescribed values", values.len(), times.len())?;
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
        // the step list is allocated before stepping: refuse what would outgrow memory
        let steps = times.len() as f64 * substeps as f64;
        if steps > MAX_STEPS {
            return Err(Error::InvalidInput(format!(
                "substeps = {substeps} over {} samples is {steps:.3e} steps, more than {MAX_STEPS:.0e}",
                times.len()
            )));
        }
        if let Control::Spring(k) = control {
            check_positive("spring stiffness", k)?;
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
            let driven = matches!(self.control, Control::Depth | Control::Spring(_));
            if v_sample == 0.0 || (driven && v_sample < 0.0) {
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
            if let Control::Spring(_) = self.control {
                return Err(Error::InvalidInput(
                    "a drive already past the contact at t = 0 would press a medium with a dashpot by a jump: start the samples before contact or after t = 0".into(),
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
        self.evaluate_until(r, tangents, None, &Stop::default())
    }

    /// `evaluate` of a depth- or spring-controlled curve with `shift` (m) added to every
    /// prescribed depth or drive (a value <= 0 at t = 0 is no contact), with the derivatives
    /// along the shift (N/m) as a last Jacobian column after those of the tangents: the
    /// forward model of a raw AFM curve, whose contact point offsets the depths.
    pub fn evaluate_shifted(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: f64,
    ) -> Result<Evaluation> {
        self.evaluate_until(r, tangents, Some(shift), &Stop::default())
    }

    /// `evaluate` (no `shift`) or `evaluate_shifted`, stopping with `Error::Interrupted`
    /// soon after `stop` is requested (the loops over steps and elements poll it).
    pub fn evaluate_until(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: Option<f64>,
        stop: &Stop,
    ) -> Result<Evaluation> {
        if let Some(shift) = shift {
            check_finite("depth shift", &[shift])?;
        }
        check_tangents(r, tangents)?;
        match (self.control, shift) {
            (Control::Depth, _) => self.evaluate_depth_control(r, tangents, shift, stop),
            (Control::Spring(_), _) | (Control::Force, None) => {
                self.evaluate_balance(r, tangents, shift, stop)
            }
            (Control::Force, Some(_)) => Err(Error::InvalidInput(
                "a shift of the prescribed values needs a depth- or spring-controlled curve".into(),
            )),
        }
    }
}

/// The tangents and the prescribed values' derivative along each (0), with, when `shift`,
/// a last tangent for the shift of the prescribed values: a zero rheology whose values move
/// at unit rate.
fn with_shift_tangent(
    r: &Rheology,
    tangents: &[Rheology],
    shift: bool,
) -> (Vec<Rheology>, Vec<f64>) {
    let mut all = tangents.to_vec();
    let mut rates = vec![0.0; tangents.len()];
    if shift {
        all.push(Rheology {
            g_inf: 0.0,
            terms: vec![(0.0, 0.0); r.terms.len()],
            eta: 0.0,
        });
        rates.push(1.0);
    }
    (all, rates)
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

#[cfg(test)]
mod hereditary_tests;
#[cfg(test)]
mod spring_hereditary_tests;
#[cfg(test)]
mod spring_tests;
#[cfg(test)]
mod tests;
