//! The steps of a depth-controlled curve: each sample interval cut into the curve's
//! substeps, with one set of step coefficients per distinct step length.

use super::{Curve, StepCoefficients};
use crate::model::medium::rheology::Rheology;
use crate::support::error::Result;
use std::collections::HashMap;

/// Up to this many distinct step lengths they are found by a scan, beyond by a hash.
const SCANNED: usize = 16;

/// One step of the prescribed depth history.
pub(super) struct Step {
    /// Index of the step's coefficients (one set per distinct step length).
    pub coefficients: usize,
    /// Time at the end of the step (s).
    pub time: f64,
    /// Depth at the end of the step (m).
    pub depth: f64,
    /// The depth's derivative with respect to the shift of the prescribed depths (1, or
    /// less inside the first interval, which starts from the unshifted rest).
    pub along: f64,
    /// The sample whose last step this is.
    pub sample: Option<usize>,
}

/// The steps and their coefficients (step length h in s, coefficients along the tangents).
pub(super) struct Steps {
    pub steps: Vec<Step>,
    pub coefficients: Vec<(f64, StepCoefficients)>,
}

impl Curve {
    /// The steps of the prescribed depths plus `shift` (m) for the medium `r` and its
    /// `tangents`.
    pub(super) fn depth_steps(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: f64,
    ) -> Result<Steps> {
        let mut steps = vec![];
        let mut coefficients: Vec<(f64, StepCoefficients)> = vec![];
        let mut index_of: HashMap<u64, usize> = HashMap::new();
        let (mut t_prev, mut value_prev) = (0.0, 0.0);
        for (s, (&t_sample, &v_sample)) in self.times.iter().zip(&self.values).enumerate() {
            let v_sample = v_sample + shift;
            let substeps = self.substeps_to(r, (t_prev, value_prev), (t_sample, v_sample))?;
            let (last, from_rest) = (substeps.len(), s == 0);
            let mut clock = t_prev;
            for (j, (t, depth)) in substeps.into_iter().enumerate() {
                let h = t - clock;
                clock = t;
                // a few step lengths, usually: a scan before a hash
                let scanned = (coefficients.len() <= SCANNED)
                    .then(|| coefficients.iter().position(|(hh, _)| *hh == h))
                    .flatten();
                let index = scanned.unwrap_or_else(|| {
                    *index_of.entry(h.to_bits()).or_insert_with(|| {
                        coefficients.push((h, StepCoefficients::new(r, tangents, h)));
                        coefficients.len() - 1
                    })
                });
                let along = if from_rest && t_sample > 0.0 {
                    (j + 1) as f64 / last as f64
                } else {
                    1.0
                };
                steps.push(Step {
                    coefficients: index,
                    time: t,
                    depth,
                    along,
                    sample: (j + 1 == last).then_some(s),
                });
            }
            t_prev = t_sample;
            value_prev = v_sample;
        }
        Ok(Steps {
            steps,
            coefficients,
        })
    }
}
