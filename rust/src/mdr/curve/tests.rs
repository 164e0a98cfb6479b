//! The prepared curve against `run_mdr`, and its derivatives against differences.

use super::*;
use crate::mdr::viscoelastic::run_mdr;
use crate::model::contact_law::ContactLaw;
use crate::model::loading::{DepthHistory, ForceHistory, Loading};
use crate::stepping::Request;
use crate::support::monitor::Silent;

fn half_parabola(n: usize, c: f64, half: f64) -> (Vec<f64>, Vec<f64>, f64) {
    let dx = half / n as f64;
    let g: Vec<f64> = (0..n)
        .map(|i| {
            let x = (i as f64 + 0.5) * dx;
            2.0 * c * x * x
        })
        .collect();
    let mut full: Vec<f64> = g.iter().rev().copied().collect();
    full.extend_from_slice(&g);
    (g, full, dx)
}

fn standard_solid(g_inf: f64, g1: f64, tau: f64) -> Rheology {
    Rheology::new(g_inf, vec![(g1, tau)], 0.0).unwrap()
}

/// The derivatives of a standard solid's coefficients in ln G_inf, ln G1 and ln tau1.
pub(super) fn standard_solid_tangents(r: &Rheology) -> Vec<Rheology> {
    let zero = Rheology {
        g_inf: 0.0,
        terms: vec![(0.0, 0.0)],
        eta: 0.0,
    };
    let mut t = vec![zero.clone(), zero.clone(), zero];
    t[0].g_inf = r.g_inf;
    t[1].terms[0].0 = r.terms[0].0;
    t[2].terms[0].1 = r.terms[0].1;
    t
}

/// The curve's elements equal `run_mdr` on the full profile with the same steps, under
/// depth and under force control (the same stepping, halved by symmetry): agreement to
/// round-off.
#[test]
fn curve_equals_the_full_profile_stepping() {
    let (half, full, dx) = half_parabola(500, 1.0, 1.0);
    let r = standard_solid(1.0, 2.0, 0.3);
    let times: Vec<f64> = (1..=40).map(|k| 0.05 * k as f64).collect();
    let depth: Vec<f64> = times.iter().map(|&t| 0.2 * t.min(2.0 - t + 0.0)).collect();
    let force: Vec<f64> = times
        .iter()
        .map(|&t| 0.3 * (t * 2.0).sin().max(0.0))
        .collect();
    for (control, values) in [(Control::Depth, &depth), (Control::Force, &force)] {
        let curve = Curve::new(half.clone(), dx, times.clone(), values.clone(), control, 1)
            .unwrap()
            .elements_only();
        let e = curve.evaluate(&r, &[]).unwrap();
        assert_eq!(e.forward, Forward::Elements);
        let mut t_all = vec![0.0];
        t_all.extend_from_slice(&times);
        let mut v_all = vec![0.0];
        v_all.extend_from_slice(values);
        let loading = match control {
            Control::Depth => Loading::Depth(DepthHistory::piecewise_linear(t_all, v_all).unwrap()),
            Control::Force => Loading::Force(ForceHistory::piecewise_linear(t_all, v_all).unwrap()),
            Control::Spring(_) => unreachable!("run_mdr has no spring"),
        };
        let request = Request {
            times: &times,
            dt: 1.0,
            fields_at: &[],
            field_rates: false,
        };
        let s = run_mdr(
            &full,
            dx,
            &r,
            ContactLaw::Hard,
            &loading,
            &request,
            &mut Silent,
        )
        .unwrap();
        let reference = match control {
            Control::Depth => &s.force,
            Control::Force => &s.depth,
            Control::Spring(_) => unreachable!("run_mdr has no spring"),
        };
        let scale = reference.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        for (a, b) in e.values.iter().zip(reference) {
            assert!((a - b).abs() <= 1e-12 * scale, "{control:?}: {a} vs {b}");
        }
    }
}

/// Forward-mode derivatives against central differences of the curve itself in each
/// log-parameter (step 1e-6: truncation and round-off ~1e-9 relative to the largest
/// derivative), under depth control (Ting's solution and the elements) and force control,
/// standard solid and Kelvin-Voigt.
#[test]
fn derivatives_match_central_differences() {
    let (half, _, dx) = half_parabola(400, 1.0, 1.0);
    let times: Vec<f64> = (1..=30).map(|k| 0.05 * k as f64).collect();
    let depth: Vec<f64> = times.iter().map(|&t| 0.2 * t.min(1.5 - t)).collect();
    let force: Vec<f64> = times
        .iter()
        .map(|&t| 0.4 * t.min(1.2 - t).max(0.0))
        .collect();
    type Build = fn(&[f64]) -> Rheology;
    // the media of log-parameters, and their derivatives in each
    let sls: Build = |p| standard_solid(p[0].exp(), p[1].exp(), p[2].exp());
    let kv: Build = |p| Rheology::new(p[0].exp(), vec![], p[1].exp()).unwrap();
    let kv_tangents = |r: &Rheology| {
        let zero = Rheology {
            g_inf: 0.0,
            terms: vec![],
            eta: 0.0,
        };
        let mut t = vec![zero.clone(), zero];
        t[0].g_inf = r.g_inf;
        t[1].eta = r.eta;
        t
    };
    type Tangents<'a> = &'a dyn Fn(&Rheology) -> Vec<Rheology>;
    let cases: [(Build, Vec<f64>, Tangents); 2] = [
        (sls, vec![0.0, 0.7, -1.2], &standard_solid_tangents),
        (kv, vec![0.3, -2.0], &kv_tangents),
    ];
    let runs = [
        (Control::Depth, &depth, Forward::Hereditary),
        (Control::Depth, &depth, Forward::Elements),
        (Control::Force, &force, Forward::Elements),
    ];
    for (build, params, tangents_of) in cases {
        for (control, values, forward) in runs {
            let curve =
                Curve::new(half.clone(), dx, times.clone(), values.clone(), control, 2).unwrap();
            let curve = match forward {
                Forward::Hereditary => curve,
                Forward::Elements => curve.elements_only(),
            };
            let r = build(&params);
            let e = curve.evaluate(&r, &tangents_of(&r)).unwrap();
            assert_eq!(e.forward, forward);
            let p = params.len();
            let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
            for j in 0..p {
                let h = 1e-6;
                let (mut up, mut down) = (params.clone(), params.clone());
                up[j] += h;
                down[j] -= h;
                let fu = curve.evaluate(&build(&up), &[]).unwrap().values;
                let fd = curve.evaluate(&build(&down), &[]).unwrap().values;
                for k in 0..times.len() {
                    let numeric = (fu[k] - fd[k]) / (2.0 * h);
                    let analytic = e.jacobian[k * p + j];
                    assert!(
                        (numeric - analytic).abs() <= 1e-6 * biggest,
                        "{control:?} param {j} sample {k}: {analytic} vs {numeric}"
                    );
                }
            }
        }
    }
}

/// The derivative along a depth shift against central differences of the shifted curve
/// (step 1e-7 of a 0.3 peak depth: truncation and round-off ~1e-8 relative to the largest
/// derivative), on a raw-curve-like history that starts out of contact (depths < 0 from
/// t = 0) and separates on retraction; the rheology columns beside it against the unshifted
/// curve of the shifted depths; by Ting's solution and by the elements.
#[test]
fn shift_derivative_matches_central_differences() {
    for forward in [Forward::Hereditary, Forward::Elements] {
        shift_derivative_by(forward);
    }
}

fn shift_derivative_by(forward: Forward) {
    let (half, _, dx) = half_parabola(400, 1.0, 1.0);
    let times: Vec<f64> = (0..=60).map(|k| 0.05 * k as f64).collect();
    let depth: Vec<f64> = times
        .iter()
        .map(|&t| 0.3 * (t - 0.6).min(2.4 - t))
        .collect();
    let only = |c: Curve| match forward {
        Forward::Hereditary => c,
        Forward::Elements => c.elements_only(),
    };
    let curve = only(
        Curve::new(
            half.clone(),
            dx,
            times.clone(),
            depth.clone(),
            Control::Depth,
            2,
        )
        .unwrap(),
    );
    let r = standard_solid(1.0, 2.0, 0.3);
    let tangent = Rheology {
        g_inf: r.g_inf,
        terms: vec![(0.0, 0.0)],
        eta: 0.0,
    };
    for shift in [0.0, 0.05, -0.07] {
        let e = curve
            .evaluate_shifted(&r, std::slice::from_ref(&tangent), shift)
            .unwrap();
        let moved: Vec<f64> = depth.iter().map(|d| d + shift).collect();
        let plain =
            only(Curve::new(half.clone(), dx, times.clone(), moved, Control::Depth, 2).unwrap())
                .evaluate(&r, std::slice::from_ref(&tangent))
                .unwrap();
        assert_eq!((e.forward, plain.forward), (forward, forward));
        let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let h = 1e-7;
        let up = curve.evaluate_shifted(&r, &[], shift + h).unwrap().values;
        let down = curve.evaluate_shifted(&r, &[], shift - h).unwrap().values;
        for k in 0..times.len() {
            assert!((e.values[k] - plain.values[k]).abs() <= 1e-12 * biggest);
            assert!((e.jacobian[2 * k] - plain.jacobian[k]).abs() <= 1e-12 * biggest);
            let numeric = (up[k] - down[k]) / (2.0 * h);
            let analytic = e.jacobian[2 * k + 1];
            assert!(
                (numeric - analytic).abs() <= 1e-6 * biggest,
                "shift {shift} sample {k}: {analytic} vs {numeric}"
            );
        }
        assert_eq!(e.values[0], 0.0);
        assert!(e.jacobian.iter().any(|&d| d > 0.0));
    }
    let force = Curve::new(half, dx, times, depth, Control::Force, 1).unwrap();
    assert!(force.evaluate_shifted(&r, &[], 0.0).is_err());
}

/// Elements that leave contact and touch again (press, partly retract, press deeper; no
/// case for Ting's solution, so the elements are stepped): the derivatives stepped from
/// where each left contact against central differences (step 1e-6, as above), with the
/// values equal to the full profile's stepping.
#[test]
fn derivatives_through_a_second_contact() {
    let (half, full, dx) = half_parabola(400, 1.0, 1.0);
    let times: Vec<f64> = (1..=60).map(|k| 0.025 * k as f64).collect();
    let depth: Vec<f64> = times
        .iter()
        .map(|&t| {
            if t <= 0.5 {
                0.3 * t
            } else if t <= 0.9 {
                0.15 - 0.3 * (t - 0.5)
            } else {
                0.03 + 0.4 * (t - 0.9)
            }
        })
        .collect();
    let build = |p: &[f64]| standard_solid(p[0].exp(), p[1].exp(), p[2].exp());
    let params = [0.0, 0.7, -1.2];
    let r = build(&params);
    let tangents = standard_solid_tangents(&r);
    let curve = Curve::new(half, dx, times.clone(), depth.clone(), Control::Depth, 1).unwrap();
    let e = curve.evaluate_shifted(&r, &tangents, 0.0).unwrap();
    assert_eq!(e.forward, Forward::Elements);
    let mut t_all = vec![0.0];
    t_all.extend_from_slice(&times);
    let mut v_all = vec![0.0];
    v_all.extend_from_slice(&depth);
    let loading = Loading::Depth(DepthHistory::piecewise_linear(t_all, v_all).unwrap());
    let request = Request {
        times: &times,
        dt: 1.0,
        fields_at: &[],
        field_rates: false,
    };
    let s = run_mdr(
        &full,
        dx,
        &r,
        ContactLaw::Hard,
        &loading,
        &request,
        &mut Silent,
    )
    .unwrap();
    let scale = s.force.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    for (a, b) in e.values.iter().zip(&s.force) {
        assert!((a - b).abs() <= 1e-12 * scale, "{a} vs {b}");
    }
    let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let p = 4;
    let h = 1e-6;
    for j in 0..p {
        let (up, down) = if j < 3 {
            let (mut u, mut d) = (params, params);
            u[j] += h;
            d[j] -= h;
            (
                curve.evaluate(&build(&u), &[]).unwrap().values,
                curve.evaluate(&build(&d), &[]).unwrap().values,
            )
        } else {
            (
                curve.evaluate_shifted(&r, &[], h).unwrap().values,
                curve.evaluate_shifted(&r, &[], -h).unwrap().values,
            )
        };
        for k in 0..times.len() {
            let numeric = (up[k] - down[k]) / (2.0 * h);
            let analytic = e.jacobian[k * p + j];
            assert!(
                (numeric - analytic).abs() <= 1e-6 * biggest,
                "param {j} sample {k}: {analytic} vs {numeric}"
            );
        }
    }
}
