//! Linear viscoelastic media (incompressible, E* = 4 G) as a relaxation modulus
//! G(t) = G_inf + sum_k G_k exp(-t / tau_k) + eta delta(t): elastic (G_inf only), Maxwell,
//! standard linear solid and Prony series (generalised Maxwell), Kelvin–Voigt (G_inf and
//! eta) and the Newtonian fluid (eta only). A medium of Poisson ratio nu enters as its
//! incompressible equivalent (`crate::model::Medium::incompressible_equivalent`).
//!
//! A material point is advanced by the exact exponential update of each Prony term for a
//! strain-like variable that varies linearly over the step (`Rheology::step`), or, where the
//! stepping keeps the previous increment, quadratically through the last three states for
//! the terms whose relaxation time is at least the step (`Rheology::step_after`), so any
//! ratio of relaxation time to step is stable: the step stress is s_{n+1} = G_eff x_{n+1} +
//! r_n, with the effective modulus G_eff and a history term r_n.

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

/// The longest step, as a multiple of the step before it, that [`Rheology::step_after`]
/// interpolates quadratically through both (a longer step is linear): the interpolant's
/// weights stay bounded, and a step far longer than the last would extrapolate its curvature.
pub const QUADRATIC_STEP_RATIO: f64 = 2.0;

/// Coefficients of one time step of length dt. Each Prony stress gains
/// `gain_k` (x_{n+1} - x_n) - `lag_k` (x_n - x_{n-1}) over the step: the exact integral of
/// G_k exp(-(t_{n+1} - s) / tau_k) x'(s) for x linear over the step (lag 0) or quadratic
/// through x_{n-1}, x_n, x_{n+1}. The dashpot's stress is eta (x_{n+1} - x_n) / dt.
#[derive(Debug, Clone, PartialEq)]
pub struct StepRule {
    /// Effective modulus G_inf + sum_k gain_k + eta / dt (Pa).
    pub g_eff: f64,
    /// exp(-dt / tau_k).
    decay: Vec<f64>,
    /// Weight (Pa) of the step's increment x_{n+1} - x_n in the gain of Prony stress k.
    gain: Vec<f64>,
    /// Weight (Pa) of the previous step's increment x_n - x_{n-1} in that gain (0 when linear).
    lag: Vec<f64>,
    /// eta / dt (Pa).
    damping: f64,
    /// sum_k gain_k + damping (Pa): the history term's weight of x_n, summed once per step.
    rate_weight: f64,
    /// sum_k lag_k (Pa): the history term's weight of the previous increment.
    lag_weight: f64,
}

/// The step rule of the last step length asked for, recomputed only when the length
/// changes (stepping loops whose steps are mostly of one length).
pub struct StepRules<'a> {
    medium: &'a Rheology,
    dt: f64,
    rule: StepRule,
}

/// integral_0^dt exp(-u / tau) du and integral_0^dt exp(-u / tau) (dt - 2 u) du (s), the
/// weights of a linear strain's rate and of its quadratic correction (the second by its
/// series for dt < tau, where the closed form's terms cancel).
fn moments(dt: f64, tau: f64) -> (f64, f64) {
    let eps = dt / tau;
    let e = (-eps).exp();
    let first = if eps < 1e-8 {
        dt * (1.0 - 0.5 * eps)
    } else {
        tau * (1.0 - e)
    };
    let second = if eps < 1.0 {
        // dt^2 sum_j (-eps)^j / j! (-j) / ((j + 1)(j + 2)), to round-off by j = 20
        let (mut sum, mut power) = (0.0, 1.0);
        for j in 1..=20 {
            power *= -eps / j as f64;
            let jf = j as f64;
            sum -= power * jf / ((jf + 1.0) * (jf + 2.0));
        }
        dt * dt * sum
    } else {
        dt * first - 2.0 * tau * first + 2.0 * tau * dt * e
    };
    (first, second)
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

    /// Coefficients of a step of length `dt` (s), the strain linear over it (second order
    /// in dt; exact for a strain linear in time).
    pub fn step(&self, dt: f64) -> StepRule {
        self.step_after(dt, 0.0)
    }

    /// Coefficients of a step of length `dt` (s) after one of length `dt_prev` (s): for the
    /// Prony terms with tau_k >= `dt`, the strain quadratic through the three states (the
    /// error of a smooth history third order in dt) when `dt_prev` > 0 and `dt` <=
    /// `QUADRATIC_STEP_RATIO` `dt_prev`; linear over the step otherwise (`dt_prev` = 0: no
    /// state before the step's start that the history reaches smoothly, as at the start or
    /// after a jump). Faster terms and the dashpot stay linear: their stress follows the
    /// strain's rate at the step's end, which a quadratic through a kink of the history (a
    /// load reversed at a step) would miss by the kink's whole change of rate.
    pub fn step_after(&self, dt: f64, dt_prev: f64) -> StepRule {
        let quadratic = dt > 0.0 && dt_prev > 0.0 && dt <= QUADRATIC_STEP_RATIO * dt_prev;
        let span = dt + dt_prev;
        let mut rule = StepRule {
            g_eff: self.g_inf,
            decay: Vec::with_capacity(self.terms.len()),
            gain: Vec::with_capacity(self.terms.len()),
            lag: Vec::with_capacity(self.terms.len()),
            damping: 0.0,
            rate_weight: 0.0,
            lag_weight: 0.0,
        };
        for &(g, tau) in &self.terms {
            rule.decay.push((-dt / tau).exp());
            if dt == 0.0 {
                // a step of zero length (a jump of the load): the glassy modulus
                rule.gain.push(g);
                rule.lag.push(0.0);
                continue;
            }
            let (first, second) = moments(dt, tau);
            if quadratic && dt <= tau {
                rule.gain.push(g * (first + second / span) / dt);
                rule.lag.push(g * second / (span * dt_prev));
            } else {
                rule.gain.push(g * first / dt);
                rule.lag.push(0.0);
            }
        }
        // a step of zero length (a jump of the load) meets no dashpot when there is none
        if self.eta != 0.0 {
            rule.damping = self.eta / dt;
        }
        rule.rate_weight = rule.gain.iter().sum::<f64>() + rule.damping;
        rule.lag_weight = rule.lag.iter().sum::<f64>();
        rule.g_eff += rule.rate_weight;
        rule
    }

    /// Number of internal variables per material point.
    pub fn internal(&self) -> usize {
        self.terms.len()
    }
}

impl StepRule {
    /// History term r_n = sum_k e_k q_k - (sum_k gain_k + damping) x_n of one point whose
    /// strain-like variable is `x` and Prony stresses `q`, stepped linearly.
    pub fn history(&self, x: f64, q: &[f64]) -> f64 {
        self.history_after(x, 0.0, q)
    }

    /// History term of a point whose previous step's increment x_n - x_{n-1} was `rise`:
    /// r_n = sum_k (e_k q_k - lag_k rise) - (sum_k gain_k + damping) x_n.
    pub fn history_after(&self, x: f64, rise: f64, q: &[f64]) -> f64 {
        let mut r = -self.rate_weight * x - self.lag_weight * rise;
        for (k, &qk) in q.iter().enumerate() {
            r += self.decay[k] * qk;
        }
        r
    }

    /// Advances the Prony stresses `q` of a point from `x_old` to `x_new`, stepped linearly.
    pub fn advance(&self, x_old: f64, x_new: f64, q: &mut [f64]) {
        self.advance_after(x_old, x_new, 0.0, q)
    }

    /// Advances the Prony stresses `q` of a point from `x_old` to `x_new` whose previous
    /// step's increment was `rise`.
    pub fn advance_after(&self, x_old: f64, x_new: f64, rise: f64, q: &mut [f64]) {
        for (k, qk) in q.iter_mut().enumerate() {
            *qk = self.decay[k] * *qk + self.gain[k] * (x_new - x_old) - self.lag[k] * rise;
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

    /// Stress (Pa) at `t` under the strain x(s) = s^2 of a medium with terms (G_k, tau_k)
    /// and no dashpot: G_inf t^2 + sum_k 2 G_k tau_k (t - tau_k (1 - exp(-t / tau_k))).
    fn stress_of_square(m: &Rheology, t: f64) -> f64 {
        m.g_inf * t * t
            + m.terms
                .iter()
                .map(|&term| prony_of_square(term, t))
                .sum::<f64>()
    }

    /// The stress (Pa) of one Prony term (G_k, tau_k) under x(s) = s^2 at `t`.
    fn prony_of_square((g, tau): (f64, f64), t: f64) -> f64 {
        2.0 * g * tau * (t + tau * (-t / tau).exp_m1())
    }

    /// The quadratic rule is exact for a quadratic strain on uneven steps (ratios up to
    /// `QUADRATIC_STEP_RATIO`, dt / tau from 1e-5 to 1), the first step's stresses given
    /// exactly; a longer step falls back to the linear rule, which is not, and so do a term
    /// faster than the step and a dashpot.
    #[test]
    fn quadratic_rule_is_exact_for_a_quadratic_strain() {
        let m = Rheology::new(1.5, vec![(2.0, 0.5), (1.1, 0.2), (0.7, 1e4)], 0.0).unwrap();
        let t1 = 0.1;
        let mut q: Vec<f64> = m
            .terms
            .iter()
            .map(|&term| prony_of_square(term, t1))
            .collect();
        let (mut t, mut x, mut rise, mut dt_prev) = (t1, t1 * t1, t1 * t1, t1);
        for dt in [0.2, 0.13, 0.02, 0.04, 0.08, 0.1] {
            let rule = m.step_after(dt, dt_prev);
            let x_new = (t + dt) * (t + dt);
            let s = rule.g_eff * x_new + rule.history_after(x, rise, &q);
            let exact = stress_of_square(&m, t + dt);
            assert!((s / exact - 1.0).abs() < 1e-12, "{dt}: {s} vs {exact}");
            rule.advance_after(x, x_new, rise, &mut q);
            (t, rise, x, dt_prev) = (t + dt, x_new - x, x_new, dt);
        }
        let rule = m.step_after(0.5, 0.1);
        let x_new = (t + 0.5) * (t + 0.5);
        let s = rule.g_eff * x_new + rule.history_after(x, rise, &q);
        assert!((s / stress_of_square(&m, t + 0.5) - 1.0).abs() > 1e-6);
        assert_eq!(rule, m.step(0.5));
        let fast = Rheology::new(1.5, vec![(3.0, 0.05)], 0.3).unwrap();
        assert_eq!(fast.step_after(0.1, 0.1), fast.step(0.1));
    }

    /// Under a smooth strain (x = sin t) the stress's error falls by about 8 per halving of
    /// the step with the quadratic rule (third order; its first step is linear) and by
    /// about 4 with the linear rule.
    #[test]
    fn quadratic_rule_is_third_order_on_a_smooth_strain() {
        let m = Rheology::new(1.0, vec![(4.0, 1.0)], 0.0).unwrap();
        let t_end: f64 = 2.0;
        // s(t) = G_inf sin t + G1 integral_0^t exp(-(t - s) / tau) cos s ds
        let exact = {
            let (g, tau) = m.terms[0];
            let w = 1.0 / tau;
            m.g_inf * t_end.sin()
                + g * (w * t_end.cos() + t_end.sin() - w * (-w * t_end).exp()) / (1.0 + w * w)
        };
        let error = |steps: usize, quadratic: bool| {
            let dt = t_end / steps as f64;
            let (mut x, mut rise, mut q, mut s) = (0.0f64, 0.0, vec![0.0], 0.0);
            for k in 0..steps {
                let dt_prev = if quadratic && k > 0 { dt } else { 0.0 };
                let rule = m.step_after(dt, dt_prev);
                let x_new = ((k + 1) as f64 * dt).sin();
                s = rule.g_eff * x_new + rule.history_after(x, rise, &q);
                rule.advance_after(x, x_new, rise, &mut q);
                (rise, x) = (x_new - x, x_new);
            }
            (s - exact).abs()
        };
        for (quadratic, low, high) in [(true, 6.5, 9.5), (false, 3.5, 4.5)] {
            let ratio = error(40, quadratic) / error(80, quadratic);
            assert!(ratio > low && ratio < high, "{quadratic}: {ratio}");
        }
        assert!(error(40, true) < 0.1 * error(40, false));
    }

    /// Creep under a unit stress held from t = 0 (a jump: one zero-length step first) on
    /// steps whose lengths alternate by the largest ratio the quadratic rule takes, both
    /// ways: the strain rises monotonically, as every creep compliance does (no
    /// oscillation), to within 1e-3 of 1 / G_inf after 60 s, for a standard solid whose term
    /// relaxes over the longer step and for a stiffer Prony series; the standard solid's
    /// strain after
    /// t = 0.5 s is within a third of the linear rule's largest error of its exact creep
    /// compliance.
    #[test]
    fn quadratic_rule_is_stable_on_uneven_steps() {
        let solid = Rheology::new(1.0, vec![(2.0, 0.1)], 0.0).unwrap();
        let series = Rheology::new(1.0, vec![(50.0, 0.1), (2.0, 0.5), (1.0, 1.0)], 0.0).unwrap();
        // the standard solid's J(t): 1 / 3 at once, retarded to 1 / G_inf over
        // tau (G_inf + G1) / G_inf = 0.3 s
        let exact = |t: f64| 1.0 - 2.0 / 3.0 * (-t / 0.3).exp();
        // (t, x) after each step, the quadratic rule where it applies or linear throughout
        let creep = |m: &Rheology, quadratic: bool| {
            let (mut t, mut x, mut rise, mut q) = (0.0, 0.0, 0.0, vec![0.0; m.internal()]);
            let (mut dt_prev, mut path) = (0.0, vec![]);
            for k in 0..800 {
                let dt = match k {
                    0 => 0.0,
                    _ if k % 2 == 0 => 0.1,
                    _ => 0.05,
                };
                let rule = m.step_after(dt, if quadratic { dt_prev } else { 0.0 });
                let x_new = (1.0 - rule.history_after(x, rise, &q)) / rule.g_eff;
                rule.advance_after(x, x_new, rise, &mut q);
                (t, rise, x, dt_prev) = (t + dt, x_new - x, x_new, dt);
                path.push((t, x));
            }
            path
        };
        for m in [&solid, &series] {
            let path = creep(m, true);
            for w in path.windows(2) {
                assert!(w[1].1 >= w[0].1 - 1e-12, "{m:?}: {:?}", w);
            }
            let (t, x) = path[path.len() - 1];
            assert!(x <= 1.0 && x > 0.999, "{m:?}: {x} at {t} s");
        }
        let worst = |path: Vec<(f64, f64)>| {
            path.iter()
                .filter(|&&(t, _)| t > 0.5)
                .map(|&(t, x)| (x - exact(t)).abs())
                .fold(0.0, f64::max)
        };
        let (quadratic, linear) = (worst(creep(&solid, true)), worst(creep(&solid, false)));
        assert!(quadratic < linear / 3.0, "{quadratic} vs {linear}");
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
