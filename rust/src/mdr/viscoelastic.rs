//! Linear viscoelastic contact by MDR under force or depth control, unloading included.
//!
//! Each element carries its displacement w; its stress follows the hereditary law
//! s = integral G(t - s) dw(s), advanced by `Rheology`'s exact exponential update:
//! s_{n+1} = G_eff w_{n+1} + r_n. Each step is then an elastic contact problem with modulus
//! G_eff and the effective profile g_i - r_i / G_eff: an element touches where the indenter
//! reaches its freely relaxed surface and leaves where the contact law says so (hard
//! contact: when its force would turn tensile). Elements out of contact relax freely.

use crate::mdr::adhesion::run_jkr;
use crate::mdr::foundation::Fields1D;
use crate::model::contact_law::{ContactLaw, SortedSurface};
use crate::model::loading::Loading;
use crate::model::medium::rheology::{Rheology, StepRules};
use crate::stepping::{jumps_at_start, step_times, Jumps, Request, Series, Trail};
use crate::support::error::{check_positive, Error, Result};
use crate::support::monitor::Monitor;

/// MDR: a viscoelastic foundation (elements 4 dx times the medium) under a 1D profile `g`
/// (m, spacing dx m) in contact by `law`, output as `request` says; also the 1D fields at its field indices:
/// displacements w (m), line load 4 s (N/m, s the element stress) and dw/dt (m/s, zero
/// unless field rates are asked for). A DMT law's attraction is that of `run_mdr_adhesive`'s
/// `attraction`, here none.
pub fn run_mdr(
    g: &[f64],
    dx: f64,
    medium: &Rheology,
    law: ContactLaw,
    loading: &Loading,
    request: &Request,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    run_mdr_adhesive(g, dx, medium, law, 0.0, loading, request, monitor)
}

/// `run_mdr` with the attraction (N) that acts while the surfaces touch (DMT's 2 pi w R;
/// `ContactLaw::attraction`). An adhesive law reports its jumps and pull-off (`Series::jumps`);
/// under force control the depth is NaN while a tensile force finds no contact (after a
/// pull-off). JKR lets its elements go by Heß's rule with the relaxed contact modulus
/// 4 G_inf (a critical opening of the contact's edge: the relaxed JKR solution when the body
/// relaxes faster than it is pulled, up to G_0 / G_inf times JKR's work of adhesion when it
/// is pulled too fast to relax), or, with the law's zone stress, by the crack's process zone
/// (`mdr::adhesion_crack`: the relaxed JKR solution for slow cracks, the glassy one for fast
/// ones). A medium without a relaxed modulus (G_inf = 0) never lets go under either and is
/// refused.
#[allow(clippy::too_many_arguments)]
pub fn run_mdr_adhesive(
    g: &[f64],
    dx: f64,
    medium: &Rheology,
    law: ContactLaw,
    attraction: f64,
    loading: &Loading,
    request: &Request,
    monitor: &mut dyn Monitor,
) -> Result<Series<Fields1D>> {
    check_positive("element spacing dx", dx)?;
    let n = g.len();
    if n == 0 {
        return Err(Error::InvalidInput("the 1D profile has no elements".into()));
    }
    request.check()?;
    law.validate()?;
    match law {
        ContactLaw::Jkr { .. } if medium.g_inf > 0.0 => {
            return run_jkr(g, dx, medium, law, loading, request, monitor)
        }
        ContactLaw::Jkr { .. } => {
            return Err(Error::InvalidInput(
                "contact 'jkr' needs a medium with a relaxed modulus (G_inf > 0): Heß's rule lets an element go at the elongation sqrt(2 pi a w / E*_inf), which has no bound without one".into(),
            ))
        }
        _ => {}
    }
    let steps = step_times(request.times, request.dt, jumps_at_start(loading, medium))?;
    let start = match loading {
        Loading::Depth(_) => 0.0,
        Loading::Force(_) => g.iter().copied().fold(f64::INFINITY, f64::min),
    };
    let mut depths = Trail::new(vec![start]);
    let field_rates = request.field_rates && !request.fields_at.is_empty();
    let mut displacements = field_rates.then(|| Trail::new(vec![0.0; n]));
    let m = medium.internal();
    let (mut w, mut q) = (vec![0.0; n], vec![0.0; n * m]);
    let mut surface = vec![0.0; n];
    let mut sorted = SortedSurface::default();
    let mut out = Series::default();
    let mut jumps = law.is_adhesive().then(Jumps::default);
    let mut before = (0.0, start, 0.0, 0usize);
    let mut t_prev = 0.0;
    let mut rules = StepRules::new(medium);
    for (s, &(t, output)) in steps.iter().enumerate() {
        let h = t - t_prev;
        let rule = rules.at(h);
        let c = 4.0 * dx * rule.g_eff;
        for i in 0..n {
            // where the indenter meets the element's freely relaxed surface
            surface[i] = g[i] - rule.history(w[i], &q[i * m..(i + 1) * m]) / rule.g_eff;
        }
        let (depth, force) = match loading {
            Loading::Depth(hist) => {
                let d = hist.depth(t);
                sorted.refill(&surface);
                let (compression, k) = law.compression_at(&sorted, d);
                let pull = if k > 0 { attraction } else { 0.0 };
                (d, c * compression - pull)
            }
            Loading::Force(hist) => {
                let f = hist.force(t);
                sorted.refill(&surface);
                let load = f + attraction;
                let d = if load < 0.0 {
                    f64::NAN
                } else {
                    law.depth_for_compression(&sorted, load / c).0
                };
                (d, f)
            }
        };
        let touches = |i: usize| law.compression(depth, surface[i]) > 0.0;
        let mut count = 0;
        for i in 0..n {
            let w_new = if touches(i) {
                count += 1;
                depth - g[i]
            } else {
                surface[i] - g[i]
            };
            rule.advance(w[i], w_new, &mut q[i * m..(i + 1) * m]);
            w[i] = w_new;
        }
        if let Some(j) = &mut jumps {
            j.record(before, (t, depth, force, count));
        }
        before = (t, depth, force, count);
        if h == 0.0 {
            // the jump at t = 0: rates start from the state just after it
            depths = Trail::new(vec![depth]);
            displacements = displacements.map(|_| Trail::new(w.clone()));
        }
        let mut rate = [0.0];
        depths.rate(t, &[depth], &mut rate);
        if output {
            let k = out.t.len();
            out.t.push(t);
            out.depth.push(depth);
            out.force.push(force);
            out.contact_length.push(count as f64 * dx);
            out.saturated.push(count == n);
            out.velocity.push(rate[0]);
            out.iterations.push(0);
            if request.fields_at.contains(&k) {
                out.fields.push(Fields1D::of_step(
                    k,
                    t,
                    depth,
                    rule.g_eff,
                    &surface,
                    touches,
                    &w,
                    displacements.as_ref(),
                ));
            }
        }
        if h > 0.0 {
            depths.push(t, &[depth]);
            if let Some(trail) = &mut displacements {
                trail.push(t, &w);
            }
        }
        out.steps = s + 1;
        monitor.progress("time steps", s + 1, steps.len())?;
        t_prev = t;
    }
    out.jumps = jumps;
    Ok(out)
}

#[cfg(test)]
#[path = "adhesion_tests.rs"]
mod adhesion_tests;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::loading::{DepthHistory, ForceHistory};
    use crate::support::monitor::Silent;

    fn parabola(n: usize, c: f64, half: f64) -> (Vec<f64>, f64) {
        let dx = 2.0 * half / n as f64;
        (
            (0..n)
                .map(|i| {
                    let x = (i as f64 + 0.5) * dx - half;
                    2.0 * c * x * x
                })
                .collect(),
            dx,
        )
    }

    /// Creep of a paraboloid under a step force on a standard solid (Lee–Radok):
    /// d^(3/2) = 3 F J(t) / (16 sqrt R), J(t) = 1/G_inf + (1/G0 - 1/G_inf) exp(-G_inf t / (G0 tau)).
    #[test]
    fn mdr_creep_of_a_standard_solid_follows_lee_radok() {
        let (g_inf, g1, tau, c, f) = (1.0, 3.0, 0.5, 1.0, 1.0);
        let medium = Rheology::new(g_inf, vec![(g1, tau)], 0.0).unwrap();
        let (g, dx) = parabola(8001, c, 1.5);
        let times: Vec<f64> = (0..40)
            .map(|k| 1e-7 * (5e7f64).powf(k as f64 / 39.0))
            .collect();
        let loading = Loading::Force(ForceHistory::constant(f).unwrap());
        let request = Request {
            times: &times,
            dt: 1e-2,
            fields_at: &[],
            field_rates: false,
        };
        let s = run_mdr(
            &g,
            dx,
            &medium,
            ContactLaw::Hard,
            &loading,
            &request,
            &mut Silent,
        )
        .unwrap();
        let g0 = g_inf + g1;
        let r = 1.0 / (2.0 * c);
        for (t, d) in s.t.iter().zip(&s.depth) {
            let j = 1.0 / g_inf + (1.0 / g0 - 1.0 / g_inf) * (-g_inf * t / (g0 * tau)).exp();
            let exact = (3.0 * f * j / (16.0 * r.sqrt())).powf(2.0 / 3.0);
            assert!((d / exact - 1.0).abs() < 2e-4, "t={t}: {d} vs {exact}");
        }
    }

    /// Depth held after a ramp on a Maxwell body: the force relaxes as exp(-t / tau) while
    /// the contact stays (Lee–Radok with fixed contact).
    #[test]
    fn mdr_force_relaxes_under_a_held_depth() {
        let (g, tau) = (2.0, 0.3);
        let medium = Rheology::new(0.0, vec![(g, tau)], 0.0).unwrap();
        let (prof, dx) = parabola(4001, 1.0, 1.0);
        let hist = DepthHistory::piecewise_linear(vec![0.0, 1e-6], vec![0.0, 0.2]).unwrap();
        let times = [1e-6, 0.1, 0.5, 1.0];
        let request = Request {
            times: &times,
            dt: 1e-3,
            fields_at: &[],
            field_rates: false,
        };
        let s = run_mdr(
            &prof,
            dx,
            &medium,
            ContactLaw::Hard,
            &Loading::Depth(hist),
            &request,
            &mut Silent,
        )
        .unwrap();
        for (t, f) in s.t.iter().zip(&s.force).skip(1) {
            let expected = s.force[0] * (-(t - 1e-6) / tau).exp();
            assert!((f / expected - 1.0).abs() < 1e-6, "t={t}");
        }
    }
}
