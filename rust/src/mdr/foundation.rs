//! The method of dimensionality reduction (Popov & Heß): a 1D foundation of independent
//! elements at spacing dx under a rigid 1D profile g(x).
//!
//! Elastic elements are springs of stiffness 4 G dx, viscous ones dashpots of damping
//! 4 eta dx. For the viscous foundation the element displacement is its impulse over
//! 4 eta dx, so at every output time the depth d solves sum 4 eta dx max(d - g_i, 0) = I(t)
//! (I = integral of F dt), exactly as the elastic foundation solves it for F. The sum is
//! piecewise linear and increasing in d: the root is found exactly on the sorted profile.

use crate::model::contact_law::{ContactLaw, SortedSurface};
use crate::model::loading::{check_output_times, ForceHistory};
use crate::model::settings::ExplicitControl;
use crate::stepping::{Series, Trail};
use crate::support::error::{check_finite, check_positive, Error, Result};
use crate::support::monitor::Monitor;

/// What the 1D elements are (per unit length, the 3D parameter times 4): springs or
/// dashpots.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Elements {
    /// Springs of stiffness 4 G dx (G: shear modulus, Pa).
    Elastic {
        /// Shear modulus (Pa).
        g: f64,
    },
    /// Dashpots of damping 4 eta dx (eta: shear viscosity, Pa s).
    Viscous {
        /// Shear viscosity (Pa s).
        eta: f64,
    },
}

impl Elements {
    fn validate(&self) -> Result<()> {
        match *self {
            Elements::Elastic { g } => check_positive("shear modulus G", g),
            Elements::Viscous { eta } => check_positive("viscosity eta", eta),
        }
    }

    /// The parameter (G or eta) whose 4 dx multiple is the element constant.
    fn modulus(&self) -> f64 {
        match *self {
            Elements::Elastic { g } => g,
            Elements::Viscous { eta } => eta,
        }
    }

    /// What the element displacements balance at time t: the force (elastic) or the impulse
    /// (viscous).
    fn load(&self, history: &ForceHistory, t: f64) -> f64 {
        match self {
            Elements::Elastic { .. } => history.force(t),
            Elements::Viscous { .. } => history.impulse(t),
        }
    }
}

/// A rigid 1D indenter on the foundation: element centres and heights above the tip.
#[derive(Debug, Clone, PartialEq)]
pub struct Foundation {
    dx: f64,
    profile: Vec<f64>,
    surface: SortedSurface,
    law: ContactLaw,
}

impl Foundation {
    /// `profile`: g at the element centres (m, >= 0), spacing `dx` (m), in contact by `law`.
    pub fn new(profile: Vec<f64>, dx: f64, law: ContactLaw) -> Result<Self> {
        check_positive("element spacing dx", dx)?;
        if profile.is_empty() {
            return Err(Error::InvalidInput("the 1D profile has no elements".into()));
        }
        check_finite("1D profile", &profile)?;
        if let Some(v) = profile.iter().find(|&&v| v < 0.0) {
            return Err(Error::InvalidInput(format!(
                "1D profile heights must be >= 0 (measured from the tip), got {v}"
            )));
        }
        Ok(Foundation {
            dx,
            surface: SortedSurface::new(&profile),
            profile,
            law,
        })
    }

    /// Number of elements.
    pub fn element_count(&self) -> usize {
        self.profile.len()
    }

    /// Element spacing (m).
    pub fn dx(&self) -> f64 {
        self.dx
    }

    /// Depth d (m) at which the elements are compressed by `s` (m, >= 0) in all, and the
    /// number that touch (the contact law's root). Exact up to round-off.
    pub fn depth_for(&self, s: f64) -> (f64, usize) {
        self.law.depth_for_compression(&self.surface, s)
    }

    /// The elements' total compression (m) at depth `d` (m) and how many touch: under hard
    /// contact sum max(d - g_i, 0), the load over the element stiffness that holds the
    /// foundation at that depth. Exact up to round-off.
    pub fn compression_at(&self, d: f64) -> (f64, usize) {
        self.law.compression_at(&self.surface, d)
    }

    /// Element compressions (m) at depth `d` (max(d - g_i, 0) under hard contact).
    pub fn displacements(&self, d: f64) -> Vec<f64> {
        self.profile
            .iter()
            .map(|&g| self.law.compression(d, g))
            .collect()
    }
}

/// 1D fields at one output time.
#[derive(Debug, Clone, PartialEq)]
pub struct Fields1D {
    /// Index of the output time.
    pub step: usize,
    /// Element displacements w_i (m).
    pub displacement: Vec<f64>,
    /// Line load q_i (N/m): 4 G w_i (elastic) or 4 eta dw_i/dt (viscous).
    pub line_load: Vec<f64>,
    /// Element velocities dw_i/dt (m/s); zero for the elastic medium under a held force.
    pub velocity: Vec<f64>,
}

impl Fields1D {
    /// The fields of output `step` of a stepped foundation at time `t` (s): displacements
    /// `w` (m), line loads 4 `g_eff` (`depth` - `surface`_i) (N/m) on the elements where
    /// `loaded(i)` and zero elsewhere, velocities from `trail` (m/s; zero without one).
    #[allow(clippy::too_many_arguments)]
    pub fn of_step(
        step: usize,
        t: f64,
        depth: f64,
        g_eff: f64,
        surface: &[f64],
        loaded: impl Fn(usize) -> bool,
        w: &[f64],
        trail: Option<&Trail>,
    ) -> Self {
        let line_load = (0..w.len())
            .map(|i| {
                if loaded(i) {
                    4.0 * g_eff * (depth - surface[i])
                } else {
                    0.0
                }
            })
            .collect();
        let mut velocity = vec![0.0; w.len()];
        if let Some(trail) = trail {
            trail.rate(t, w, &mut velocity);
        }
        Fields1D {
            step,
            displacement: w.to_vec(),
            line_load,
            velocity,
        }
    }
}

/// Runs the MDR foundation under the force `history` (N over s), with output at `times`
/// (s) and 1D fields at the output indices `fields_at`: depths (m), contact lengths (m) and
/// penetration rates (m/s).
pub fn run(
    foundation: &Foundation,
    medium: Elements,
    history: &ForceHistory,
    times: &[f64],
    fields_at: &[usize],
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    medium.validate()?;
    check_output_times(times)?;
    if let Some(&k) = fields_at.iter().find(|&&k| k >= times.len()) {
        return Err(Error::InvalidInput(format!(
            "field output index {k} is out of range for {} output times",
            times.len()
        )));
    }
    let c = 4.0 * medium.modulus() * foundation.dx;
    let n = foundation.element_count();
    let mut out = Series::default();
    for (k, &t) in times.iter().enumerate() {
        let (d, count) = foundation.depth_for(medium.load(history, t) / c);
        let rate = match medium {
            Elements::Viscous { .. } if count > 0 => history.force(t) / (c * count as f64),
            Elements::Viscous { .. } => 0.0,
            Elements::Elastic { .. } => f64::NAN,
        };
        out.t.push(t);
        out.depth.push(d);
        out.force.push(history.force(t));
        out.contact_length.push(count as f64 * foundation.dx);
        // F / (4 eta dd/dt) is the contact's element count times dx, exactly
        out.stiffness_length.push(count as f64 * foundation.dx);
        out.velocity.push(rate);
        out.saturated.push(count == n);
        if fields_at.contains(&k) {
            let displacement = foundation.displacements(d);
            let velocity: Vec<f64> = displacement
                .iter()
                .map(|&w| {
                    if w > 0.0 && rate.is_finite() {
                        rate
                    } else {
                        0.0
                    }
                })
                .collect();
            let line_load = match medium {
                Elements::Elastic { g } => displacement.iter().map(|w| 4.0 * g * w).collect(),
                Elements::Viscous { eta } => velocity.iter().map(|v| 4.0 * eta * v).collect(),
            };
            out.fields.push(Fields1D {
                step: k,
                displacement,
                line_load,
                velocity,
            });
        }
        monitor.progress("time steps", k + 1, times.len())?;
    }
    out.steps = times.len();
    out.solves = times.len();
    Ok(out)
}

/// The paper's explicit loop on the viscous foundation (`eta` in Pa s, `history` in N over
/// s, output at `times` in s), with the steps it took: penetration rate of the
/// current contact, an explicit Euler step, contact growth; the rate uses the element count
/// of the last update, refreshed when the count grew by more than `ctrl.area_change`.
pub fn run_explicit(
    foundation: &Foundation,
    eta: f64,
    history: &ForceHistory,
    times: &[f64],
    ctrl: &ExplicitControl,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    check_positive("viscosity eta", eta)?;
    check_output_times(times)?;
    ctrl.validate()?;
    let c = 4.0 * eta * foundation.dx;
    let n = foundation.element_count();
    let in_contact = |d: f64| foundation.surface.sorted().partition_point(|&g| g <= d);
    let mut depth = foundation.surface.sorted()[0];
    let mut count = in_contact(depth);
    let mut used = count;
    let t_first = ctrl.start * times.last().copied().unwrap_or(1.0);
    let (mut t, mut steps) = (0.0, 0usize);
    let mut out = Series::default();
    for (k, &target) in times.iter().enumerate() {
        while t < target {
            let rate = history.force(t) / (c * used as f64);
            let (dt, next) = ctrl.next_step(t, t_first, target);
            t = next;
            depth += rate * dt;
            count = in_contact(depth);
            if count as f64 > used as f64 * (1.0 + ctrl.area_change) {
                used = count;
            }
            steps += 1;
            if steps % 4096 == 0 {
                monitor.progress("time steps", k, times.len())?;
            }
        }
        out.t.push(t);
        out.depth.push(depth);
        out.force.push(history.force(t));
        out.contact_length.push(count as f64 * foundation.dx);
        out.stiffness_length.push(count as f64 * foundation.dx);
        out.velocity.push(history.force(t) / (c * used as f64));
        out.saturated.push(count == n);
        monitor.progress("time steps", k + 1, times.len())?;
    }
    out.steps = steps;
    out.solves = times.len();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::support::monitor::Silent;

    #[test]
    fn depth_root_is_exact() {
        let f = Foundation::new(vec![3.0, 0.0, 1.0, 2.0], 1.0, ContactLaw::Hard).unwrap();
        // d = 1.5: (1.5 - 0) + (1.5 - 1) = 2
        let (d, k) = f.depth_for(2.0);
        assert!((d - 1.5).abs() < 1e-15);
        assert_eq!(k, 2);
        // beyond all elements: 4 d - 6 = 10 -> d = 4
        let (d, k) = f.depth_for(10.0);
        assert!((d - 4.0).abs() < 1e-15);
        assert_eq!(k, 4);
    }

    #[test]
    fn viscous_rod_rate_is_exact() {
        let n = 1000;
        let a = 1.0;
        let f = Foundation::new(vec![0.0; n], 2.0 * a / n as f64, ContactLaw::Hard).unwrap();
        let h = ForceHistory::constant(1.0).unwrap();
        let s = run(
            &f,
            Elements::Viscous { eta: 1.0 },
            &h,
            &[1.0],
            &[],
            &mut Silent,
        )
        .unwrap();
        assert!((s.velocity[0] / 0.125 - 1.0).abs() < 1e-14);
        assert!((s.depth[0] / 0.125 - 1.0).abs() < 1e-14);
    }

    #[test]
    fn viscous_paraboloid_follows_lee_radok() {
        let (n, c, half) = (20001usize, 1.0, 1.5);
        let dx = 2.0 * half / n as f64;
        let g: Vec<f64> = (0..n)
            .map(|i| {
                let x = -half + (i as f64 + 0.5) * dx;
                2.0 * c * x * x
            })
            .collect();
        let f = Foundation::new(g, dx, ContactLaw::Hard).unwrap();
        let h = ForceHistory::constant(1.0).unwrap();
        let s = run(
            &f,
            Elements::Viscous { eta: 1.0 },
            &h,
            &[1.0, 5.0],
            &[],
            &mut Silent,
        )
        .unwrap();
        for (t, d) in s.t.iter().zip(&s.depth) {
            let exact = (3.0 * t * (2.0 * c).sqrt() / 16.0).powf(2.0 / 3.0);
            assert!((d / exact - 1.0).abs() < 1e-6, "t={t}: {d} vs {exact}");
        }
    }
}
