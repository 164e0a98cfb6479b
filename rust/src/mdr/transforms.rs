//! Inverse MDR transforms: 3D axisymmetric fields from a 1D solution.
//!
//! Both work on 1D data with one value per element, centres at x_i = (i - (n - 1) / 2) dx,
//! symmetric about 0:
//! * pressure p(r) = -(1/pi) integral_r^inf q'(x) / sqrt(x^2 - r^2) dx, for the line load
//!   interpolated between element centres (linearly; quadratically, with zero slope, across
//!   the centre x = 0) and ending in a jump at the outer edge of the last element (a punch's
//!   rim). A piecewise-constant q would put an inverse-square-root spike at every element
//!   edge; the interpolated one keeps the pressure of a smooth line load smooth and leaves
//!   a constant one (the flat punch) exact;
//! * surface deflection (or its rate) outside the contact,
//!   u(r) = (2/pi) integral_0^a w(x) / sqrt(r^2 - x^2) dx, exact for piecewise-constant w.

use crate::support::error::{check_finite, check_positive, Error, Result};
use std::f64::consts::PI;

/// Right half of the 1D data: (left edge, right edge, value) of each element with x > 0.
fn right_half(values: &[f64], dx: f64) -> Vec<(f64, f64, f64)> {
    let n = values.len();
    let centre = (n as f64 - 1.0) / 2.0;
    values
        .iter()
        .enumerate()
        .filter_map(|(i, &v)| {
            let x = (i as f64 - centre) * dx;
            let (l, r) = (x - 0.5 * dx, x + 0.5 * dx);
            (r > 0.0).then_some((l.max(0.0), r, v))
        })
        .collect()
}

fn check(values: &[f64], dx: f64, r: &[f64], what: &str) -> Result<()> {
    check_positive("element spacing dx", dx)?;
    if values.is_empty() {
        return Err(Error::InvalidInput(format!("{what} has no elements")));
    }
    check_finite(what, values)?;
    check_finite("radii", r)?;
    if let Some(v) = r.iter().find(|&&v| v < 0.0) {
        return Err(Error::InvalidInput(format!("radii must be >= 0, got {v}")));
    }
    Ok(())
}

/// integral from x0 to x1 of dx / sqrt(x^2 - r^2) for r <= x0 <= x1 (r >= 0).
fn inverse_root_integral(x0: f64, x1: f64, r: f64) -> f64 {
    let term = |x: f64| x + ((x - r) * (x + r)).max(0.0).sqrt();
    (term(x1) / term(x0)).ln()
}

/// 3D pressure p(r) (Pa) at radii `r` (m) from the 1D line load `q` (N/m).
pub fn pressure_from_line_load(q: &[f64], dx: f64, r: &[f64]) -> Result<Vec<f64>> {
    check(q, dx, r, "line load")?;
    let n = q.len();
    // values at the centres with x >= 0, outwards
    let first = n / 2;
    let nodes: Vec<(f64, f64)> = (first..n)
        .map(|i| ((i as f64 - 0.5 * (n as f64 - 1.0)) * dx, q[i]))
        .collect();
    let (last_x, last_q) = nodes[nodes.len() - 1];
    let rim = last_x + 0.5 * dx;
    Ok(r.iter()
        .map(|&r| {
            let mut integral = 0.0;
            for w in nodes.windows(2) {
                let ((x0, q0), (x1, q1)) = (w[0], w[1]);
                if x1 <= r || q1 == q0 {
                    continue;
                }
                integral += if x0 == 0.0 {
                    // q0 + (q1 - q0)(x / x1)^2 across the centre: q' = 2 (q1 - q0) x / x1^2
                    2.0 * (q1 - q0) / (x1 * x1) * ((x1 - r) * (x1 + r)).sqrt()
                } else {
                    (q1 - q0) / dx * inverse_root_integral(x0.max(r), x1, r)
                };
            }
            if rim > r {
                integral -= last_q / ((rim - r) * (rim + r)).sqrt();
            }
            -integral / PI
        })
        .collect())
}

/// 3D surface deflection (m, or m/s from velocities) at radii `r` (m) outside the contact,
/// from the 1D displacements `w` (m, or m/s). Valid for r at or beyond the contact radius.
pub fn deflection_outside(w: &[f64], dx: f64, r: &[f64]) -> Result<Vec<f64>> {
    check(w, dx, r, "1D displacement")?;
    let half = right_half(w, dx);
    Ok(r.iter()
        .map(|&r| {
            if r == 0.0 {
                return half.first().map_or(0.0, |e| e.2);
            }
            half.iter()
                .filter(|e| e.0 < r && e.2 != 0.0)
                .map(|&(l, rr, v)| v * ((rr.min(r) / r).asin() - (l / r).asin()))
                .sum::<f64>()
                * 2.0
                / PI
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rod_fields_are_exact() {
        // Flat line of 2000 elements over [-1, 1] with q = 4 eta ddot, ddot = F/(8 a eta).
        let (n, a, f) = (2000usize, 1.0, 1.0);
        let dx = 2.0 * a / n as f64;
        let rate = f / (8.0 * a);
        let q = vec![4.0 * rate; n];
        let radii = [0.0, 0.3, 0.9];
        let p = pressure_from_line_load(&q, dx, &radii).unwrap();
        for (r, p) in radii.iter().zip(&p) {
            let exact = f / (2.0 * PI * a * a) / (1.0 - r * r / (a * a)).sqrt();
            assert!((p / exact - 1.0).abs() < 1e-12, "r={r}");
        }
        let v = deflection_outside(&vec![rate; n], dx, &[1.0, 1.5, 2.0]).unwrap();
        for (r, v) in [1.0f64, 1.5, 2.0].iter().zip(&v) {
            let exact = 2.0 / PI * rate * (a / r).asin();
            assert!((v / exact - 1.0).abs() < 1e-12, "r={r}");
        }
    }
}
