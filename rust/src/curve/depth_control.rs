//! A curve under depth control: with the depth prescribed, each element of the MDR
//! foundation evolves on its own, so the stepping runs element by element through all the
//! steps, its state in registers, and blocks of elements run in parallel; the force of a
//! sample is the sum of the blocks' forces, added in block order (the same result on any
//! number of threads).

use super::{Curve, Evaluation, StepCoefficients};
use crate::error::Result;
use crate::rheology::Rheology;
use rayon::prelude::*;

/// Elements per block of the parallel loop.
const BLOCK: usize = 32;

/// One step of the prescribed depth history.
struct Step {
    /// Index of the step's coefficients (one set per distinct step length).
    coefficients: usize,
    /// Depth at the end of the step (m).
    depth: f64,
    /// The sample whose last step this is.
    sample: Option<usize>,
}

/// What a block of elements adds to each sample: force (N per unit weight), its derivative
/// along each tangent (row-major, sample by tangent) and the elements in contact.
struct Sums {
    force: Vec<f64>,
    d_force: Vec<f64>,
    contact: Vec<usize>,
}

impl Sums {
    fn zero(samples: usize, p: usize) -> Self {
        Sums {
            force: vec![0.0; samples],
            d_force: vec![0.0; samples * p],
            contact: vec![0; samples],
        }
    }

    fn add(mut self, other: &Sums) -> Self {
        let pairs = [
            (&mut self.force, &other.force),
            (&mut self.d_force, &other.d_force),
        ];
        for (a, b) in pairs {
            a.iter_mut().zip(b).for_each(|(x, y)| *x += y);
        }
        self.contact
            .iter_mut()
            .zip(&other.contact)
            .for_each(|(x, y)| *x += y);
        self
    }
}

impl Curve {
    /// `Curve::evaluate` under depth control, with `shift` (m) added to every prescribed
    /// depth; with a shift, the derivative along it is a last tangent (a zero rheology
    /// tangent whose depth moves at unit rate).
    pub(super) fn evaluate_depth_control(
        &self,
        r: &Rheology,
        tangents: &[Rheology],
        shift: Option<f64>,
    ) -> Result<Evaluation> {
        let mut all = tangents.to_vec();
        let mut rates = vec![0.0; tangents.len()];
        if shift.is_some() {
            all.push(Rheology {
                g_inf: 0.0,
                terms: vec![(0.0, 0.0); r.terms.len()],
                eta: 0.0,
            });
            rates.push(1.0);
        }
        let tangents = &all[..];
        let shift = shift.unwrap_or(0.0);
        let p = tangents.len();
        let samples = self.times.len();
        let mut steps = vec![];
        let mut coefficients: Vec<(f64, StepCoefficients)> = vec![];
        let (mut t_prev, mut value_prev) = (0.0, 0.0);
        for (s, (&t_sample, &v_sample)) in self.times.iter().zip(&self.values).enumerate() {
            let v_sample = v_sample + shift;
            let substeps = self.substeps_to(r, (t_prev, value_prev), (t_sample, v_sample))?;
            let last = substeps.len();
            let mut clock = t_prev;
            for (j, (t, depth)) in substeps.into_iter().enumerate() {
                let h = t - clock;
                clock = t;
                let index = match coefficients.iter().position(|(hh, _)| *hh == h) {
                    Some(index) => index,
                    None => {
                        coefficients.push((h, StepCoefficients::new(r, tangents, h)));
                        coefficients.len() - 1
                    }
                };
                steps.push(Step {
                    coefficients: index,
                    depth,
                    sample: (j + 1 == last).then_some(s),
                });
            }
            t_prev = t_sample;
            value_prev = v_sample;
        }
        // an element never reached by the indenter keeps a zero state
        let deepest = steps
            .iter()
            .map(|s| s.depth)
            .fold(f64::NEG_INFINITY, f64::max);
        let n = self.g.len();
        let blocks: Vec<Sums> = (0..n.div_ceil(BLOCK))
            .into_par_iter()
            .map(|b| {
                let mut sums = Sums::zero(samples, p);
                let mut state = ElementState::new(r.terms.len(), p);
                for &g in &self.g[b * BLOCK..n.min((b + 1) * BLOCK)] {
                    if g < deepest {
                        state.run(g, &steps, &coefficients, &rates, &mut sums);
                    }
                }
                sums
            })
            .collect();
        let total = blocks
            .iter()
            .fold(Sums::zero(samples, p), |acc, b| acc.add(b));
        // each element stands for itself and its mirror image
        let weight = 8.0 * self.dx;
        Ok(Evaluation {
            values: total.force.iter().map(|f| weight * f).collect(),
            jacobian: total.d_force.iter().map(|f| weight * f).collect(),
            contact: total.contact,
        })
    }
}

/// The state of one element (displacement w, Prony stresses q) and its derivatives along
/// each tangent, with the history term's derivatives of the current step.
struct ElementState {
    m: usize,
    p: usize,
    q: Vec<f64>,
    dw: Vec<f64>,
    dq: Vec<f64>,
    dh: Vec<f64>,
}

impl ElementState {
    fn new(m: usize, p: usize) -> Self {
        ElementState {
            m,
            p,
            q: vec![0.0; m],
            dw: vec![0.0; p],
            dq: vec![0.0; p * m],
            dh: vec![0.0; p],
        }
    }

    /// Steps the element at profile height `g` (m) from rest through `steps`, adding its
    /// force at each sample to `sums`; `rates` are the derivatives of the depth along each
    /// tangent (constant over the history). Until the depth first passes g the element's
    /// state stays zero and its steps are skipped.
    fn run(
        &mut self,
        g: f64,
        steps: &[Step],
        coefficients: &[(f64, StepCoefficients)],
        rates: &[f64],
        sums: &mut Sums,
    ) {
        let (m, p) = (self.m, self.p);
        self.q.iter_mut().for_each(|x| *x = 0.0);
        self.dw.iter_mut().for_each(|x| *x = 0.0);
        self.dq.iter_mut().for_each(|x| *x = 0.0);
        let Some(first) = steps.iter().position(|s| s.depth > g) else {
            return;
        };
        let mut w = 0.0;
        for step in &steps[first..] {
            let c = &coefficients[step.coefficients].1;
            let depth = step.depth;
            let mut hist = -c.relaxing * w;
            for k in 0..m {
                hist += c.decay[k] * self.q[k];
            }
            for j in 0..p {
                let mut dh = -c.d_relaxing[j] * w - c.relaxing * self.dw[j];
                for k in 0..m {
                    dh += c.d_decay[j * m + k] * self.q[k] + c.decay[k] * self.dq[j * m + k];
                }
                self.dh[j] = dh;
            }
            let relaxed = g - hist / c.g_eff;
            let touching = relaxed < depth;
            let w_new = if touching { depth - g } else { relaxed - g };
            if let (true, Some(s)) = (touching, step.sample) {
                sums.force[s] += c.g_eff * (depth - g) + hist;
                sums.contact[s] += 1;
                for j in 0..p {
                    sums.d_force[s * p + j] +=
                        c.d_g_eff[j] * (depth - g) + c.g_eff * rates[j] + self.dh[j];
                }
            }
            let dw_step = w_new - w;
            let inv = 1.0 / c.g_eff;
            for j in 0..p {
                // a touching element's displacement follows the prescribed depth (which
                // depends on the shift only); a free one's follows its relaxed surface
                let dw_new = if touching {
                    rates[j]
                } else {
                    (hist * c.d_g_eff[j] * inv - self.dh[j]) * inv
                };
                let d_dw = dw_new - self.dw[j];
                for k in 0..m {
                    let dq = &mut self.dq[j * m + k];
                    *dq = c.d_decay[j * m + k] * self.q[k]
                        + c.decay[k] * *dq
                        + c.d_gain[j * m + k] * dw_step
                        + c.gain[k] * d_dw;
                }
                self.dw[j] = dw_new;
            }
            for k in 0..m {
                self.q[k] = c.decay[k] * self.q[k] + c.gain[k] * dw_step;
            }
            w = w_new;
        }
    }
}
