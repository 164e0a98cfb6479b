//! The four-sided pyramid (an AFM cantilever's tip): h(x, y) = max(|x|, |y|) / tan(alpha),
//! alpha the face half-angle (between the axis and a face, radians), faces normal to the x
//! and y axes, edges along the diagonals.
//!
//! The BEM solves this shape exactly. MDR needs an axisymmetric indenter and solves an
//! equivalent cone instead, tan(psi) = `EQUIVALENT_CONE_FACTOR` tan(alpha), psi the cone's
//! half-opening angle; its contact radius is that of the disc of the contact's area, as the
//! BEM reports it.

use super::Indenter;
use crate::support::error::{check_positive, Error, Result};
use std::f64::consts::FRAC_PI_2;

/// tan(psi) / tan(alpha) of the cone MDR solves in place of a pyramid of face half-angle
/// alpha: Bilodeau's (1992) force F = 0.7453 E / (1 - nu^2) tan(alpha) d^2 equals Sneddon's
/// cone, F = (2 / pi) E / (1 - nu^2) tan(psi) d^2, for tan(psi) = 0.7453 (pi / 2) tan(alpha).
/// The BEM of the exact pyramid, extrapolated in the element size, carries 1.04 % less force
/// at a given depth (tan(psi) = 1.15865 tan(alpha)); the cone of the same projected area at
/// every depth (tan(psi) = 2 tan(alpha) / sqrt(pi)) 2.6 % less than the BEM.
pub const EQUIVALENT_CONE_FACTOR: f64 = 0.7453 * FRAC_PI_2;

/// Fails unless `half_angle` (radians) is finite and in (0, pi/2).
pub fn check_half_angle(half_angle: f64) -> Result<()> {
    check_positive("pyramid half_angle", half_angle)?;
    if half_angle < FRAC_PI_2 {
        Ok(())
    } else {
        Err(Error::InvalidInput(format!(
            "pyramid half_angle must be an angle in (0, pi/2) radians, got {half_angle}"
        )))
    }
}

/// The cone MDR solves in place of a pyramid of face half-angle `half_angle` (radians) and
/// base `edge` (m, or unbounded): slope cot(psi) = 1 / (`EQUIVALENT_CONE_FACTOR`
/// tan(alpha)), the same footprint.
pub fn equivalent_cone(half_angle: f64, edge: Option<f64>) -> Indenter {
    Indenter::Cone {
        slope: 1.0 / (EQUIVALENT_CONE_FACTOR * half_angle.tan()),
        edge,
    }
}

/// Height (m) above the tip of a pyramid of face half-angle `half_angle` (radians) at
/// (`x`, `y`) (m).
pub fn height(half_angle: f64, x: f64, y: f64) -> f64 {
    x.abs().max(y.abs()) / half_angle.tan()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Angles outside (0, pi/2) and NaN are refused, naming the parameter.
    #[test]
    fn half_angles_outside_the_quadrant_are_refused() {
        for bad in [0.0, -0.1, FRAC_PI_2, 2.0, 35.0, f64::NAN, f64::INFINITY] {
            let e = check_half_angle(bad).unwrap_err().to_string();
            assert!(e.contains("pyramid half_angle"), "{e}");
        }
        assert!(check_half_angle(0.3).is_ok() && check_half_angle(1.5).is_ok());
    }

    /// The level set at height h is the square of half-side h tan(alpha).
    #[test]
    fn level_sets_are_squares() {
        let alpha: f64 = 0.6;
        let half_side = 2.0 * alpha.tan();
        for (x, y) in [(half_side, 0.0), (half_side, -half_side), (-0.3, half_side)] {
            assert!((height(alpha, x, y) - 2.0).abs() < 1e-15);
        }
    }
}
