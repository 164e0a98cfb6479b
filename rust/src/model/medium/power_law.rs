//! The power-law relaxation modulus G(t) = G0 (t / t0)^-beta (0 < beta < 1) as a Prony
//! series with a long-time modulus and a dashpot, over a time range [t_lo, t_hi].
//!
//! t^-beta = 1 / Gamma(beta) * integral exp(beta u - e^u t) du over the real line (u = ln(1/tau)).
//! The trapezoid rule in u with step `NODE_SPACING` is spectrally accurate for this integrand
//! (analytic in a strip of half-width pi / 2). Each node is a Prony term G_k exp(-t / tau_k)
//! with G_k = G0 t0^beta h e^(beta u_k) / Gamma(beta), tau_k = e^-u_k. Nodes far below
//! 1 / t_hi (tau_k > t_hi e^LOW_MARGIN) barely relax within t_hi: one slow term carries
//! them, with their sums of G_k and of G_k / tau_k (their modulus and its initial rate of
//! relaxation), so that its error is of second order in t / tau_k. Nodes far above 1 / t_lo (tau_k < t_lo e^-HIGH_MARGIN) relax
//! within any step of t_lo or longer, where only their integral sum G_k tau_k matters: one
//! last term, one spacing further, carries that sum (a dashpot would do the same for steps,
//! but could not take a jump of the load at t = 0).
//! Measured (tests below) for beta in [0.01, 0.99] over three to eight decades: the relative
//! error of G(t) on [t_lo, t_hi] is below 4e-6 and that of integral_0^t G ds below 1e-6;
//! `RELATIVE_ERROR` states the bound.

use crate::model::medium::rheology::Rheology;
use crate::support::error::{check_positive, Error, Result};

/// Spacing of the nodes in u = ln(1 / tau) (about 3.5 terms per decade of time).
pub const NODE_SPACING: f64 = 0.65;

/// Nodes reach e^LOW_MARGIN beyond t_hi before the rest are lumped into one slow term.
pub const LOW_MARGIN: f64 = 5.0;

/// Nodes reach e^HIGH_MARGIN below t_lo before the rest are lumped into a dashpot.
pub const HIGH_MARGIN: f64 = 3.0;

/// The stated bound on the relative error of the series' G(t) for t in [t_lo, t_hi].
pub const RELATIVE_ERROR: f64 = 1e-5;

/// A power-law medium G0 (t / t0)^-beta as a Prony series over a time range, and the
/// derivatives of the series' coefficients with respect to ln G0, beta and ln t0.
#[derive(Debug, Clone, PartialEq)]
pub struct PronyOfPowerLaw {
    /// The series (G_inf, terms, eta).
    pub rheology: Rheology,
    /// The node positions u_k = ln(1 / tau_k).
    nodes: Vec<f64>,
    /// u at which the slow term's geometric sums start (one spacing below the first node).
    low: f64,
    /// u of the last term, which carries the geometric sum of G_k tau_k above it.
    high: f64,
    beta: f64,
    t0: f64,
}

impl PronyOfPowerLaw {
    /// The series of G0 (t / t0)^-beta (Pa, s; 0 < beta < 1) over [t_lo, t_hi] (s).
    pub fn new(g0: f64, beta: f64, t0: f64, t_lo: f64, t_hi: f64) -> Result<Self> {
        check_positive("power-law G0", g0)?;
        check_positive("power-law t0", t0)?;
        check_exponent(beta)?;
        check_positive("power-law time range start", t_lo)?;
        check_positive("power-law time range end", t_hi)?;
        if t_lo > t_hi {
            return Err(Error::InvalidInput(format!(
                "power-law time range: start {t_lo} s is after its end {t_hi} s"
            )));
        }
        let h = NODE_SPACING;
        let u_lo = -t_hi.ln() - LOW_MARGIN;
        let u_hi = -t_lo.ln() + HIGH_MARGIN;
        let count = ((u_hi - u_lo) / h).ceil() as usize + 1;
        let nodes: Vec<f64> = (0..count).map(|k| u_lo + h * k as f64).collect();
        // G0 t0^beta h / Gamma(beta), in logs so that no factor overflows
        let scale = g0.ln() + beta * t0.ln() + h.ln() - ln_gamma(beta);
        let mut terms: Vec<(f64, f64)> = nodes
            .iter()
            .map(|&u| ((scale + beta * u).exp(), (-u).exp()))
            .collect();
        let (low, high) = (u_lo - h, nodes[count - 1] + h);
        // sum_{j>=0} exp((beta - 1)(high + j h)): G_k tau_k of the nodes from `high` on,
        // carried by a term at `high`
        let tail = (scale + (beta - 1.0) * high).exp() / -((beta - 1.0) * h).exp_m1();
        terms.push((tail * high.exp(), (-high).exp()));
        // sum_{j>=0} G_k and G_k / tau_k over the nodes low - j h: exp(b (low - j h)) with
        // b = beta and beta + 1
        let slow = (scale + beta * low).exp() / -(-beta * h).exp_m1();
        let slow_rate = (scale + (beta + 1.0) * low).exp() / -(-(beta + 1.0) * h).exp_m1();
        terms.push((slow, slow / slow_rate));
        Ok(PronyOfPowerLaw {
            rheology: Rheology::new(0.0, terms, 0.0)?,
            nodes,
            low,
            high,
            beta,
            t0,
        })
    }

    /// d(series)/d(beta): the derivatives of G_inf, of each (G_k, tau_k) and of eta.
    pub fn d_beta(&self) -> Rheology {
        let h = NODE_SPACING;
        let (b, r) = (self.beta, &self.rheology);
        let common = self.t0.ln() - digamma(b);
        // d/dbeta of -ln(1 - e^(-c h)) (c = beta, beta + 1) and of -ln(1 - e^((beta - 1) h))
        let geometric_low = |c: f64| -h * (-c * h).exp() / -(-c * h).exp_m1();
        let geometric_high = h * ((b - 1.0) * h).exp() / -((b - 1.0) * h).exp_m1();
        let tail = r.terms[self.nodes.len()].0;
        let (slow, tau_slow) = r.terms[self.nodes.len() + 1];
        let mut terms: Vec<(f64, f64)> = r
            .terms
            .iter()
            .zip(&self.nodes)
            .map(|(&(g, _), &u)| (g * (common + u), 0.0))
            .collect();
        terms.push((tail * (common + self.high + geometric_high), 0.0));
        // the slow term's modulus and its time: tau = sum G_k / sum (G_k / tau_k)
        terms.push((
            slow * (common + self.low + geometric_low(b)),
            tau_slow * (geometric_low(b) - geometric_low(b + 1.0)),
        ));
        Rheology {
            g_inf: 0.0,
            terms,
            eta: 0.0,
        }
    }
}

/// Fails unless 0 < beta < 1.
pub fn check_exponent(beta: f64) -> Result<()> {
    if beta.is_finite() && beta > 0.0 && beta < 1.0 {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "power-law exponent beta must lie in (0, 1), got {beta}"
        )))
    }
}

/// ln Gamma(x) for x > 0 (Lanczos, g = 7, 9 terms; relative error ~1e-15).
pub fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // reflection: Gamma(x) Gamma(1 - x) = pi / sin(pi x)
        let pi = std::f64::consts::PI;
        return (pi / (pi * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + 7.5;
    let sum = C[1..]
        .iter()
        .enumerate()
        .fold(C[0], |s, (i, c)| s + c / (x + 1.0 + i as f64));
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// The digamma function psi(x) = d ln Gamma / dx for x > 0 (recurrence to x >= 8, then
/// the asymptotic series to z^-10; absolute error 3e-13, its next term's size).
pub fn digamma(mut x: f64) -> f64 {
    let mut shift = 0.0;
    while x < 8.0 {
        shift -= 1.0 / x;
        x += 1.0;
    }
    let z = 1.0 / (x * x);
    shift + x.ln()
        - 0.5 / x
        - z * (1.0 / 12.0 - z * (1.0 / 120.0 - z * (1.0 / 252.0 - z * (1.0 / 240.0 - z / 132.0))))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn series_modulus(r: &Rheology, t: f64) -> f64 {
        r.g_inf
            + r.terms
                .iter()
                .map(|&(g, tau)| g * (-t / tau).exp())
                .sum::<f64>()
    }

    fn series_integral(r: &Rheology, t: f64) -> f64 {
        r.eta
            + r.g_inf * t
            + r.terms
                .iter()
                .map(|&(g, tau)| g * tau * -(-t / tau).exp_m1())
                .sum::<f64>()
    }

    /// G(t) and integral_0^t G ds of the series against the power law on dense grids over
    /// several ranges and exponents: measured worst 3.9e-6 and 7.8e-8.
    #[test]
    fn series_follows_the_power_law_within_its_bound() {
        let (mut worst, mut worst_integral) = (0.0f64, 0.0f64);
        for (t_lo, t_hi) in [(1e-3, 1.0), (1e-5, 1e3), (2e-4, 3e-2)] {
            for beta in [0.01, 0.05, 0.1, 0.3, 0.5, 0.7, 0.9, 0.99] {
                let (g0, t0) = (2.5e3, 0.7);
                let p = PronyOfPowerLaw::new(g0, beta, t0, t_lo, t_hi).unwrap();
                for k in 0..=400 {
                    let t = t_lo * (t_hi / t_lo).powf(k as f64 / 400.0);
                    let exact = g0 * (t / t0).powf(-beta);
                    worst = worst.max((series_modulus(&p.rheology, t) / exact - 1.0).abs());
                    let integral = g0 * t0.powf(beta) * t.powf(1.0 - beta) / (1.0 - beta);
                    worst_integral = worst_integral
                        .max((series_integral(&p.rheology, t) / integral - 1.0).abs());
                }
            }
        }
        assert!(worst < RELATIVE_ERROR, "G(t): {worst:e}");
        assert!(worst_integral < 2e-6, "integral: {worst_integral:e}");
    }

    /// The beta-derivative of the coefficients against a central difference (step 1e-5:
    /// truncation ~1e-10 relative).
    #[test]
    fn beta_derivative_matches_a_central_difference() {
        let (beta, db) = (0.3, 1e-5);
        let p = PronyOfPowerLaw::new(1.0, beta, 2.0, 1e-3, 1.0).unwrap();
        let plus = PronyOfPowerLaw::new(1.0, beta + db, 2.0, 1e-3, 1.0).unwrap();
        let minus = PronyOfPowerLaw::new(1.0, beta - db, 2.0, 1e-3, 1.0).unwrap();
        let d = p.d_beta();
        let close = |a: f64, b: f64| (a - b).abs() <= 1e-7 * b.abs().max(a.abs());
        let diff = |a: f64, b: f64| (a - b) / (2.0 * db);
        assert_eq!((d.g_inf, p.rheology.g_inf), (0.0, 0.0));
        for k in 0..d.terms.len() {
            let (plus, minus) = (plus.rheology.terms[k], minus.rheology.terms[k]);
            assert!(close(d.terms[k].0, diff(plus.0, minus.0)), "G {k}");
            assert!(close(d.terms[k].1, diff(plus.1, minus.1)), "tau {k}");
        }
    }

    #[test]
    fn gamma_and_digamma_match_known_values() {
        assert!((ln_gamma(0.5) - std::f64::consts::PI.sqrt().ln()).abs() < 1e-14);
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13);
        // psi(1) = -Euler's gamma, psi(1/2) = -gamma - 2 ln 2 (measured 2.9e-13, 1.4e-13)
        let euler = 0.577_215_664_901_532_9;
        assert!((digamma(1.0) + euler).abs() < 1e-12);
        assert!((digamma(0.5) + euler + 2.0 * 2f64.ln()).abs() < 1e-12);
    }

    #[test]
    fn exponents_outside_the_unit_interval_are_refused() {
        for beta in [0.0, 1.0, -0.1, f64::NAN] {
            assert!(PronyOfPowerLaw::new(1.0, beta, 1.0, 1e-3, 1.0).is_err());
        }
    }
}
