//! The detachment criterion of a JKR contact on a viscoelastic body whose edge is a crack
//! with a Dugdale process zone of cohesive stress sigma0 (Schapery 1975; Greenwood &
//! Johnson 1981; Greenwood 2004).
//!
//! The edge of an MDR contact of radius a carrying the line load T (N/m, tensile > 0) on its
//! edge element is a crack of stress intensity K = T / sqrt(pi a) (the MDR transform of a
//! jump T of the line load at x = a). Ahead of a receding edge the stresses are the elastic
//! ones of the current K; the crack faces open by the hereditary integral of their elastic
//! opening with the creep compliance C(t) of the contact modulus (Schapery's extended
//! correspondence for a growing crack). A Dugdale zone of stress sigma0 behind the edge is
//! s = pi K^2 / (8 sigma0^2) long; its elastic opening at a distance rho s from the edge is
//! delta_t f(rho) with f(rho) = sqrt(rho) - (1 - rho) / 2 ln((1 + sqrt rho) / (1 - sqrt rho)),
//! f(1) = 1, f'(rho) = artanh(sqrt rho), and delta_t E* = K^2 / (2 sigma0). A material point
//! crosses the zone in the time dt = s / (da/dt); it left the edge at rho = 0 and its
//! opening at the zone's end, delta_t E* integral_0^1 C(dt (1 - rho)) f'(rho) drho, reaches
//! the range h0 = w / sigma0 when
//!
//! ```text
//! T^2 C_eff(dt) = 2 pi a w,   C_eff(dt) = integral_0^1 C(dt (1 - rho)) artanh(sqrt rho) drho,
//! ```
//!
//! the edge's criterion: Heß's sqrt(2 pi a w / E*) on an elastic body (C = 1 / E*), the
//! relaxed modulus's for a crack slow against the relaxation (C_eff -> 1 / E*_inf), the
//! glassy one's for a fast crack (C_eff -> 1 / E*_0).
//!
//! The time dt is read off the edge's path: the material now at the zone's end, a + s, left
//! the edge when the edge was last at a + s. The path is the edge's radius at the step ends
//! since the contact last grew, linear within a step (so dt = s / (da/dt) for a steady
//! crack whatever the step); where the edge has not receded by s yet (a crack starting
//! from a contact held at its largest radius) the zone's material has been stretched since
//! the edge last carried no tension, and dt is the time since then.

use crate::model::medium::rheology::Rheology;
use std::f64::consts::PI;

/// Time points per decade of the compliance tables.
const PER_DECADE: f64 = 40.0;

/// The zone's effective creep compliance C_eff(dt) (1/Pa) of the contact modulus
/// E*(t) = 4 G(t), tabulated on a geometric grid of dt.
#[derive(Debug, Clone)]
struct ZoneCompliance {
    /// ln of the grid's first time (s) and the grid's step in ln t.
    ln_first: f64,
    step: f64,
    values: Vec<f64>,
}

impl ZoneCompliance {
    /// The table of `medium` (G_inf > 0) from 1e-6 of its shortest time scale to 1e6 of its
    /// longest (the relaxation times and eta / G_inf): C(t) by the exact exponential update
    /// of a unit contact stress held from t = 0, then C_eff by the weight artanh(sqrt rho)
    /// in ln t on the same grid (C before the grid's first time as at it).
    fn new(medium: &Rheology) -> Self {
        let mut scales: Vec<f64> = medium.terms.iter().map(|&(_, tau)| tau).collect();
        if medium.eta > 0.0 {
            scales.push(medium.eta / medium.g_inf);
        }
        if scales.is_empty() {
            return ZoneCompliance {
                ln_first: 0.0,
                step: 1.0,
                values: vec![1.0 / (4.0 * medium.g_inf)],
            };
        }
        let lo = 1e-6 * scales.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = 1e6 * scales.iter().copied().fold(0.0, f64::max);
        let step = std::f64::consts::LN_10 / PER_DECADE;
        let n = ((hi / lo).ln() / step).ceil() as usize + 1;
        let times: Vec<f64> = (0..n).map(|k| lo * (k as f64 * step).exp()).collect();
        // creep of the shear modulus under a unit stress: x = J(t), Prony stresses q
        let g0 = medium.g_inf + medium.terms.iter().map(|&(g, _)| g).sum::<f64>();
        let mut x = if medium.eta > 0.0 { 0.0 } else { 1.0 / g0 };
        let mut q: Vec<f64> = medium.terms.iter().map(|&(g, _)| g * x).collect();
        let mut creep = Vec::with_capacity(n);
        let mut t = 0.0;
        const SUBSTEPS: usize = 8;
        for &next in &times {
            let ratio = if t > 0.0 { next / t } else { 1.0 };
            for j in 1..=SUBSTEPS {
                let end = if t > 0.0 {
                    t * ratio.powf(j as f64 / SUBSTEPS as f64)
                } else {
                    next * j as f64 / SUBSTEPS as f64
                };
                let start = if j == 1 {
                    t
                } else if t > 0.0 {
                    t * ratio.powf((j - 1) as f64 / SUBSTEPS as f64)
                } else {
                    next * (j - 1) as f64 / SUBSTEPS as f64
                };
                let rule = medium.step(end - start);
                let x_new = (1.0 - rule.history(x, &q)) / rule.g_eff;
                rule.advance(x, x_new, &mut q);
                x = x_new;
            }
            t = next;
            creep.push(x / 4.0);
        }
        // C_eff(t_k) = integral over y = ln u < 0 of C(t_k e^y) artanh(sqrt(1 - e^y)) e^y dy
        // (u = 1 - rho), C linear in y between the grid's points: each point's weight is
        // the integral of the weight function times its hat, by midpoints within each cell
        // (in y = -step v^2 in the first, where the weight grows as sqrt(-y)), normalised to
        // the exact total 1
        let weight = |y: f64| {
            let u = y.exp();
            let r = (1.0 - u).sqrt();
            // artanh(r) = ln((1 + r) / (1 - r)) / 2 with 1 - r = u / (1 + r)
            0.5 * ((1.0 + r) * (1.0 + r) / u).ln() * u
        };
        const FINE: usize = 64;
        let cells = (35.0 / step).ceil() as usize;
        let mut weights = vec![0.0; cells + 1];
        for j in 0..cells {
            for i in 0..FINE {
                let v = (i as f64 + 0.5) / FINE as f64;
                // theta in (0, 1) across the cell from y_j = -j step, and d theta / dv
                let (theta, jac) = if j == 0 { (v * v, 2.0 * v) } else { (v, 1.0) };
                let part = weight(-(j as f64 + theta) * step) * jac / FINE as f64;
                weights[j] += (1.0 - theta) * part;
                weights[j + 1] += theta * part;
            }
        }
        let total: f64 = weights.iter().sum();
        let values = (0..n)
            .map(|k| {
                let sum: f64 = weights
                    .iter()
                    .enumerate()
                    .map(|(j, w)| w * creep[k.saturating_sub(j)])
                    .sum();
                sum / total
            })
            .collect();
        ZoneCompliance {
            ln_first: lo.ln(),
            step,
            values,
        }
    }

    /// C_eff (1/Pa) of a zone crossed in `dt` (s): linear in ln dt between the grid's
    /// points, its ends beyond.
    fn at(&self, dt: f64) -> f64 {
        let last = self.values.len() - 1;
        if dt <= 0.0 {
            return self.values[0];
        }
        let s = (dt.ln() - self.ln_first) / self.step;
        if s <= 0.0 {
            return self.values[0];
        }
        let k = s.floor() as usize;
        if k >= last {
            return self.values[last];
        }
        let f = s - k as f64;
        self.values[k] * (1.0 - f) + self.values[k + 1] * f
    }
}

/// The crack at a viscoelastic JKR contact's edge: its process zone and its path.
#[derive(Debug, Clone)]
pub struct CrackTip {
    /// Work of adhesion w (J/m^2) and the zone's cohesive stress sigma0 (Pa).
    work: f64,
    stress: f64,
    compliance: ZoneCompliance,
    /// The edge's path since the contact last grew: (time s, radius m), radius falling.
    path: Vec<(f64, f64)>,
    /// The last step end (s) at which the edge carried no tension.
    slack_at: f64,
}

impl CrackTip {
    /// The crack of work of adhesion `work` (J/m^2) and zone stress `stress` (Pa) on
    /// `medium` (G_inf > 0).
    pub fn new(work: f64, stress: f64, medium: &Rheology) -> Self {
        CrackTip {
            work,
            stress,
            compliance: ZoneCompliance::new(medium),
            path: Vec::new(),
            slack_at: 0.0,
        }
    }

    /// Whether the edge at radius `a` (m) carrying the tensile line load `tension` (N/m) at
    /// time `t` (s) lets go, the edge having receded from `a0` (m) at the step's start `t0`
    /// (s) to `a` in this step.
    pub fn lets_go(&self, tension: f64, a: f64, a0: f64, t0: f64, t: f64) -> bool {
        if tension <= 0.0 || a <= 0.0 {
            return false;
        }
        // the zone's length s = pi K^2 / (8 sigma0^2), K = T / sqrt(pi a)
        let zone = tension * tension / (8.0 * a * self.stress * self.stress);
        let dt = t - self.left_edge(a + zone, a, a0, t0, t);
        tension * tension * self.compliance.at(dt) >= 2.0 * PI * a * self.work
    }

    /// The time (s) the material at radius `r` > `a` (m) left the edge: when the edge was
    /// last at r on its path (this step's part linear from `a0` at `t0` to `a` at `t`),
    /// and not before the edge last carried no tension.
    fn left_edge(&self, r: f64, a: f64, a0: f64, t0: f64, t: f64) -> f64 {
        let passed = if r <= a0 && a < a0 {
            t0 + (t - t0) * (a0 - r) / (a0 - a)
        } else {
            // the path's radii fall: the last point at or beyond r, then its next
            let k = self.path.partition_point(|&(_, radius)| radius >= r);
            match (k.checked_sub(1).map(|j| self.path[j]), self.path.get(k)) {
                (Some((t1, r1)), Some(&(t2, r2))) => t1 + (t2 - t1) * (r1 - r) / (r1 - r2),
                (Some(_), None) => t0,
                (None, _) => f64::NEG_INFINITY,
            }
        };
        passed.max(self.slack_at)
    }

    /// Records a step from `t0` (s) to `t` in which the edge went from radius `a0` (m) to
    /// `a` (0: no contact), carrying tension at the end when `tensile`.
    pub fn record(&mut self, t0: f64, a0: f64, t: f64, a: f64, tensile: bool) {
        if a > a0 || a == 0.0 {
            self.path.clear();
        }
        if !tensile || a == 0.0 {
            self.slack_at = t;
        }
        if a > 0.0 && a < a0 {
            if self.path.last().is_none_or(|&(_, r)| r != a0) {
                self.path.push((t0, a0));
            }
            self.path.push((t, a));
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The table's compliance: 1/E* on an elastic body; on a standard solid the glassy and
    /// relaxed ones at its ends (the table's), and between them the weighted mean of the closed-form
    /// creep compliance J(t) / 4 = 1/E*_inf + (1/E*_0 - 1/E*_inf) exp(-t G_inf / (G_0 tau)),
    /// integral_0^1 exp(-dt (1 - rho) / lambda) artanh(sqrt rho) drho by fine quadrature.
    #[test]
    fn zone_compliance_of_a_standard_solid() {
        let elastic = ZoneCompliance::new(&Rheology::new(2.0, vec![], 0.0).unwrap());
        assert_eq!(elastic.at(3.0), 1.0 / 8.0);
        let (g_inf, g1, tau) = (2.0, 6.0, 0.01);
        let sls = ZoneCompliance::new(&Rheology::new(g_inf, vec![(g1, tau)], 0.0).unwrap());
        let (c0, c_inf) = (1.0 / (4.0 * (g_inf + g1)), 1.0 / (4.0 * g_inf));
        assert!((sls.at(0.0) / c0 - 1.0).abs() < 1e-5);
        // the glassy tail near the zone's end fades as (lambda / dt) ln(dt / lambda) only
        assert!((sls.at(1e9) / c_inf - 1.0).abs() < 1e-4);
        let lambda = tau * (g_inf + g1) / g_inf;
        for dt in [1e-3, 1e-2, 0.04, 0.3, 3.0] {
            // midpoint rule in u = 1 - rho, refined towards u = 0 by u = v^4
            let m = 200_000;
            let mean: f64 = (0..m)
                .map(|i| {
                    let v = (i as f64 + 0.5) / m as f64;
                    let u = v.powi(4);
                    let r = (1.0 - u).sqrt();
                    let artanh = 0.5 * ((1.0 + r) * (1.0 + r) / u).ln();
                    (-dt * u / lambda).exp() * artanh * 4.0 * v.powi(3) / m as f64
                })
                .sum();
            let exact = c_inf + (c0 - c_inf) * mean;
            assert!(
                (sls.at(dt) / exact - 1.0).abs() < 2e-4,
                "dt {dt}: {} against {exact}",
                sls.at(dt)
            );
        }
    }
}
