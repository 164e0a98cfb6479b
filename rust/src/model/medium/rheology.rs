//! Linear viscoelastic media (incompressible, E* = 4 G) as a relaxation modulus
//! G(t) = G_inf + sum_k G_k exp(-t / tau_k) + eta delta(t): elastic (G_inf only), Maxwell,
//! standard linear solid and Prony series (generalised Maxwell), Kelvin–Voigt (G_inf and
//! eta) and the Newtonian fluid (eta only). A medium of Poisson ratio nu enters as its
//! incompressible equivalent (`crate::model::Medium::incompressible_equivalent`).
//!
//! A material point is advanced by the exact exponential update of each Prony term for a
//! strain-like variable that varies linearly over the step, so any ratio of relaxation time
//! to step is stable: the step stress is s_{n+1} = G_eff x_{n+1} + r_n, with the effective
//! modulus G_eff and a history term r_n.

use crate::support::error::{check_magnitude, check_positive, Error, Result};

/// The relaxation modulus of a medium (shear moduli in Pa, times in s, eta in Pa s).
#[derive(Debug, Clone, PartialEq)]
pub struct Rheology {
    /// Long-time modulus G_inf (Pa), >= 0.
    pub g_inf: f64,
    /// Prony terms (G_k in Pa, tau_k in s), G_k > 0, tau_k > 0.
    pub terms: Vec<(f64, f64)>,
    /// Dashpot in parallel (Pa s), >= 0.
    pub eta: f64,
}

/// Coefficients of one time step of length dt.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRule {
    /// Effective modulus G_inf + sum G_k a_k + eta / dt (Pa s^0).
    pub g_eff: f64,
    /// exp(-dt / tau_k).
    decay: Vec<f64>,
    /// G_k a_k with a_k = (tau_k / dt)(1 - exp(-dt / tau_k)).
    gain: Vec<f64>,
    /// eta / dt.
    damping: f64,
}

/// The step rule of the last step length asked for, recomputed only when the length
/// changes (stepping loops whose steps are mostly of one length).
pub struct StepRules<'a> {
    medium: &'a Rheology,
    dt: f64,
    rule: StepRule,
}

impl<'a> StepRules<'a> {
    /// The rules of `medium`, none computed for a step length yet.
    pub fn new(medium: &'a Rheology) -> Self {
        StepRules {
            medium,
            dt: f64::NAN,
            rule: medium.step(1.0),
        }
    }

    /// The rule of a step of length `dt` (s).
    pub fn at(&mut self, dt: f64) -> &StepRule {
        if dt != self.dt {
            self.rule = self.medium.step(dt);
            self.dt = dt;
        }
        &self.rule
    }
}

impl Rheology {
    /// Validates the parameters: finite, non-negative, and a positive instantaneous response.
    pub fn new(g_inf: f64, terms: Vec<(f64, f64)>, eta: f64) -> Result<Self> {
        let nonneg = |name: &str, v: f64| {
            if v.is_finite() && v >= 0.0 {
                check_magnitude(name, v)
            } else {
                Err(Error::InvalidInput(format!(
                    "{name} must be finite and >= 0, got {v}"
                )))
            }
        };
        nonneg("G_inf", g_inf)?;
        nonneg("eta", eta)?;
        for &(g, tau) in &terms {
            check_positive("Prony modulus G_k", g)?;
            check_positive("Prony relaxation time tau_k", tau)?;
        }
        if g_inf == 0.0 && eta == 0.0 && terms.is_empty() {
            return Err(Error::InvalidInput(
                "the medium has no stiffness: give G_inf, a Prony term or eta".into(),
            ));
        }
        Ok(Rheology { g_inf, terms, eta })
    }

    /// Coefficients of a step of length `dt` (s).
    pub fn step(&self, dt: f64) -> StepRule {
        let decay: Vec<f64> = self
            .terms
            .iter()
            .map(|&(_, tau)| (-dt / tau).exp())
            .collect();
        let gain: Vec<f64> = self
            .terms
            .iter()
            .zip(&decay)
            .map(|(&(g, tau), &e)| {
                g * if dt / tau < 1e-8 {
                    1.0 - 0.5 * dt / tau
                } else {
                    tau / dt * (1.0 - e)
                }
            })
            .collect();
        // a step of zero length (a jump of the load) meets no dashpot when there is none
        let damping = if self.eta == 0.0 { 0.0 } else { self.eta / dt };
        StepRule {
            g_eff: self.g_inf + gain.iter().sum::<f64>() + damping,
            decay,
            gain,
            damping,
        }
    }

    /// Number of internal variables per material point.
    pub fn internal(&self) -> usize {
        self.terms.len()
    }
}

impl StepRule {
    /// History term r_n = sum_k e_k q_k - (sum_k G_k a_k + eta / dt) x_n of one point whose
    /// strain-like variable is `x` and Prony stresses `q`.
    pub fn history(&self, x: f64, q: &[f64]) -> f64 {
        let mut r = -(self.gain.iter().sum::<f64>() + self.damping) * x;
        for (k, &qk) in q.iter().enumerate() {
            r += self.decay[k] * qk;
        }
        r
    }

    /// Advances the Prony stresses `q` of a point from `x_old` to `x_new`.
    pub fn advance(&self, x_old: f64, x_new: f64, q: &mut [f64]) {
        for (k, qk) in q.iter_mut().enumerate() {
            *qk = self.decay[k] * *qk + self.gain[k] * (x_new - x_old);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Stress of a standard solid under a constant strain rate, stepped with big and small
    /// steps: the exponential update is exact for piecewise-linear strain.
    #[test]
    fn ramp_relaxation_is_exact_for_any_step() {
        let m = Rheology::new(1.0, vec![(2.0, 0.5)], 0.0).unwrap();
        let (rate, t_end) = (0.3, 2.0);
        let exact = rate * (1.0 * t_end + 2.0 * 0.5 * (1.0 - (-t_end / 0.5f64).exp()));
        for steps in [1usize, 7, 1000] {
            let dt = t_end / steps as f64;
            let rule = m.step(dt);
            let (mut x, mut q, mut s) = (0.0, vec![0.0], 0.0);
            for _ in 0..steps {
                let x_new = x + rate * dt;
                s = rule.g_eff * x_new + rule.history(x, &q);
                rule.advance(x, x_new, &mut q);
                x = x_new;
            }
            assert!(
                (s / exact - 1.0).abs() < 1e-12,
                "{steps} steps: {s} vs {exact}"
            );
        }
    }

    #[test]
    fn stiff_terms_stay_bounded() {
        let m = Rheology::new(1.0, vec![(1e6, 1e-12), (1.0, 1e12)], 0.0).unwrap();
        let r = m.step(1.0);
        assert!(r.g_eff.is_finite() && r.g_eff > 1.0 && r.g_eff < 3.0);
        assert!(Rheology::new(0.0, vec![], 0.0).is_err());
        assert!(Rheology::new(1.0, vec![(1.0, -1.0)], 0.0).is_err());
    }
}
