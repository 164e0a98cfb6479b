//! Time-integrator controls shared by BEM and MDR.
//!
//! The default engine of both methods is the implicit impulse step, exact in time while the
//! contact grows. The paper's explicit loop is kept as a selectable integrator so that the
//! cost of that choice can be measured.

use crate::error::{check_positive, Error, Result};

/// Controls of the paper's explicit loop (its Fig. 1b).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExplicitControl {
    /// Relative time step: dt = step * max(t, start * t_end).
    pub step: f64,
    /// Re-solve the contact when its area grew by more than this fraction (paper: 0.01).
    pub area_change: f64,
    /// First step length as a fraction of the final output time.
    pub start: f64,
}

impl Default for ExplicitControl {
    fn default() -> Self {
        ExplicitControl {
            step: 0.01,
            area_change: 0.01,
            start: 1e-6,
        }
    }
}

impl ExplicitControl {
    /// Fails unless step and start are positive and area_change >= 0.
    pub fn validate(&self) -> Result<()> {
        crate::error::check_finite_positive("explicit step", self.step)?;
        check_positive("explicit start fraction", self.start)?;
        // dt = step * t_first up to t_first, then growing by (1 + step) a step
        let steps = 1.0 / self.step + (1.0 / self.start).ln() / self.step.ln_1p();
        if steps > crate::viscoelastic::MAX_STEPS {
            return Err(Error::InvalidInput(format!(
                "explicit step = {} takes about {steps:.3e} steps, more than {:.0e}",
                self.step,
                crate::viscoelastic::MAX_STEPS
            )));
        }
        if !(self.area_change >= 0.0 && self.area_change.is_finite()) {
            return Err(Error::InvalidInput(format!(
                "area_change must be finite and >= 0, got {}",
                self.area_change
            )));
        }
        Ok(())
    }

    /// The step (dt, t + dt) from `t`, with first step `t_first` (s), clipped to land exactly
    /// on `target`.
    pub fn next_step(&self, t: f64, t_first: f64, target: f64) -> (f64, f64) {
        let remaining = target - t;
        let dt = (self.step * t.max(t_first)).min(remaining);
        (dt, if dt == remaining { target } else { t + dt })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Steps grow geometrically by (1 + step) after the first, land exactly on the target, and
    /// their count is the estimate `validate` bounds, to within the clipped last steps.
    #[test]
    fn steps_grow_geometrically_and_land_on_the_target() {
        let c = ExplicitControl::default();
        let (t_end, t_first) = (5.0, 5.0 * c.start);
        let (mut t, mut count, mut last) = (0.0, 0usize, (0.0, 0.0));
        while t < t_end {
            let (dt, next) = c.next_step(t, t_first, t_end);
            // once the previous step started at or past t_first, each is (1 + step) longer
            if last.0 >= t_first && next < t_end {
                assert!((dt / last.1 - (1.0 + c.step)).abs() < 1e-9, "t = {t}");
            }
            (last, t, count) = ((t, dt), next, count + 1);
        }
        assert_eq!(t, t_end);
        let bound = 1.0 / c.step + (1.0 / c.start).ln() / c.step.ln_1p();
        assert!((count as f64 - bound).abs() <= 2.0, "{count} vs {bound}");
    }

    #[test]
    fn bad_controls_are_refused_by_name() {
        let bad = |c: ExplicitControl, word: &str| {
            let e = c.validate().unwrap_err().to_string();
            assert!(e.contains(word), "{e}");
        };
        let base = ExplicitControl::default();
        bad(ExplicitControl { step: 0.0, ..base }, "explicit step");
        bad(ExplicitControl { step: 1e-9, ..base }, "steps, more than");
        bad(
            ExplicitControl {
                start: -1.0,
                ..base
            },
            "start fraction",
        );
        bad(
            ExplicitControl {
                area_change: -0.1,
                ..base
            },
            "area_change",
        );
        assert!(ExplicitControl {
            area_change: 0.0,
            ..base
        }
        .validate()
        .is_ok());
    }
}
