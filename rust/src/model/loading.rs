//! Loading histories: the force F(t) applied to the indenter and its impulse.

use crate::support::error::{check_finite, check_magnitude, Error, Result};

/// A force history F(t) (N), piecewise linear between samples, constant after the last
/// sample; time starts at t = 0 (first touch).
#[derive(Debug, Clone, PartialEq)]
pub struct ForceHistory {
    times: Vec<f64>,
    forces: Vec<f64>,
}

impl ForceHistory {
    /// A constant force `f` (N) from t = 0.
    pub fn constant(f: f64) -> Result<Self> {
        Self::piecewise_linear(vec![0.0], vec![f])
    }

    /// Samples (t_i, F_i): times start at 0 and strictly increase. Whether a force may be
    /// negative is the contact law's to say (`ContactLaw::check_force`).
    pub fn piecewise_linear(times: Vec<f64>, forces: Vec<f64>) -> Result<Self> {
        check_samples("force history", &times, &forces)?;
        Ok(ForceHistory { times, forces })
    }

    /// Force (N) at time `t` (s).
    pub fn force(&self, t: f64) -> f64 {
        let k = self.times.partition_point(|&s| s <= t);
        if k == 0 {
            0.0
        } else if k == self.times.len() {
            self.forces[k - 1]
        } else {
            let (t0, t1) = (self.times[k - 1], self.times[k]);
            let (f0, f1) = (self.forces[k - 1], self.forces[k]);
            f0 + (f1 - f0) * (t - t0) / (t1 - t0)
        }
    }

    /// Whether the history is linear on the open interval (`t0`, `t1`) (s): no sample, where
    /// its rate may change, strictly inside.
    pub fn linear_between(&self, t0: f64, t1: f64) -> bool {
        let k = self.times.partition_point(|&s| s <= t0);
        self.times.get(k).is_none_or(|&s| s >= t1)
    }

    /// Impulse (N s): integral of F from 0 to `t`, exact for the piecewise-linear history.
    pub fn impulse(&self, t: f64) -> f64 {
        if t <= 0.0 {
            return 0.0;
        }
        let mut total = 0.0;
        for k in 0..self.times.len() {
            let t0 = self.times[k];
            if t0 >= t {
                break;
            }
            let t1 = self
                .times
                .get(k + 1)
                .copied()
                .unwrap_or(f64::INFINITY)
                .min(t);
            total += 0.5 * (self.force(t0) + self.force(t1)) * (t1 - t0);
        }
        total
    }
}

/// A prescribed depth history d(t) (m), piecewise linear between samples, constant after
/// the last; time starts at t = 0. Negative depths hold the indenter above the surface.
#[derive(Debug, Clone, PartialEq)]
pub struct DepthHistory {
    samples: ForceHistory,
    offset: f64,
}

impl DepthHistory {
    /// Samples (t_i, d_i): times start at 0 and strictly increase, depths finite.
    pub fn piecewise_linear(times: Vec<f64>, depths: Vec<f64>) -> Result<Self> {
        check_samples("depth history", &times, &depths)?;
        // Stored shifted to be >= 0 so that the force-history checks apply unchanged.
        let offset = depths.iter().copied().fold(0.0f64, f64::min);
        let shifted = depths.iter().map(|d| d - offset).collect();
        Ok(DepthHistory {
            samples: ForceHistory::piecewise_linear(times, shifted)?,
            offset,
        })
    }

    /// Depth (m) at time `t` (s).
    pub fn depth(&self, t: f64) -> f64 {
        self.samples.force(t) + self.offset
    }

    /// Whether the history is linear on the open interval (`t0`, `t1`) (s).
    pub fn linear_between(&self, t0: f64, t1: f64) -> bool {
        self.samples.linear_between(t0, t1)
    }
}

/// What drives the indenter.
#[derive(Debug, Clone, PartialEq)]
pub enum Loading {
    /// Prescribed force F(t) (N; >= 0 unless the contact law is adhesive).
    Force(ForceHistory),
    /// Prescribed depth d(t) (m).
    Depth(DepthHistory),
}

impl Loading {
    /// Whether the prescribed force or depth is linear on the open interval (`t0`, `t1`)
    /// (s): no sample of its history, where its rate may change, strictly inside.
    pub fn linear_between(&self, t0: f64, t1: f64) -> bool {
        match self {
            Loading::Force(h) => h.linear_between(t0, t1),
            Loading::Depth(h) => h.linear_between(t0, t1),
        }
    }
}

/// Fails unless `times` are finite, > 0 and strictly increasing.
pub fn check_output_times(times: &[f64]) -> Result<()> {
    if times.is_empty() {
        return Err(Error::InvalidInput("no output times given".into()));
    }
    check_finite("output times", times)?;
    if times[0] <= 0.0 {
        return Err(Error::InvalidInput(format!(
            "output times must be > 0 (t = 0 is first touch), got {}",
            times[0]
        )));
    }
    check_increasing("output times", times)
}

/// Fails unless a history `what` has as many finite `values` as finite `times`, at least
/// one, with times starting at 0 and strictly increasing.
fn check_samples(what: &str, times: &[f64], values: &[f64]) -> Result<()> {
    if times.is_empty() || times.len() != values.len() {
        return Err(Error::InvalidInput(format!(
            "{what} needs equally many times and values (>= 1), got {} and {}",
            times.len(),
            values.len()
        )));
    }
    check_finite(&format!("{what} times"), times)?;
    check_finite(&format!("{what} values"), values)?;
    for (t, v) in times.iter().zip(values) {
        check_magnitude(&format!("{what} time"), *t)?;
        check_magnitude(&format!("{what} value"), *v)?;
    }
    if times[0] != 0.0 {
        return Err(Error::InvalidInput(format!(
            "{what} must start at t = 0, got {}",
            times[0]
        )));
    }
    check_increasing(&format!("{what} times"), times)
}

/// Fails unless `times` (named `what`) strictly increase.
fn check_increasing(what: &str, times: &[f64]) -> Result<()> {
    match times.windows(2).find(|w| w[1] <= w[0]) {
        Some(w) => Err(Error::InvalidInput(format!(
            "{what} must increase, got {} then {}",
            w[0], w[1]
        ))),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn impulse_of_ramp_and_hold() {
        let h = ForceHistory::piecewise_linear(vec![0.0, 2.0], vec![0.0, 4.0]).unwrap();
        assert_eq!(h.force(1.0), 2.0);
        assert_eq!(h.force(3.0), 4.0);
        assert!((h.impulse(2.0) - 4.0).abs() < 1e-15);
        assert!((h.impulse(3.0) - 8.0).abs() < 1e-15);
        assert!((ForceHistory::constant(1.5).unwrap().impulse(2.0) - 3.0).abs() < 1e-15);
    }

    /// A history is linear between two times unless a sample lies strictly between them.
    #[test]
    fn linear_between_samples() {
        let h = ForceHistory::piecewise_linear(vec![0.0, 1.0, 2.0], vec![0.0, 1.0, 0.0]).unwrap();
        assert!(h.linear_between(0.0, 1.0) && h.linear_between(1.0, 2.0));
        assert!(h.linear_between(2.0, 9.0) && h.linear_between(0.2, 0.8));
        assert!(!h.linear_between(0.9, 1.1) && !h.linear_between(0.5, 2.5));
        let d = Loading::Depth(
            DepthHistory::piecewise_linear(vec![0.0, 1.0], vec![0.0, -1.0]).unwrap(),
        );
        assert!(d.linear_between(1.0, 3.0) && !d.linear_between(0.5, 1.5));
    }

    #[test]
    fn rejects_bad_histories() {
        assert!(ForceHistory::piecewise_linear(vec![0.0, 0.0], vec![1.0, 1.0]).is_err());
        assert!(ForceHistory::piecewise_linear(vec![1.0], vec![1.0]).is_err());
        assert!(check_output_times(&[1.0, 0.5]).is_err());
        assert!(check_output_times(&[f64::NAN]).is_err());
        let e = DepthHistory::piecewise_linear(vec![0.0, 1.0, 0.5], vec![0.0; 3]).unwrap_err();
        assert!(
            e.to_string().contains("depth history times must increase"),
            "{e}"
        );
    }
}
