//! Ting's solution (`hereditary`) against the elements' stepping, which it is the limit of,
//! and against closed forms.

use super::*;

/// The half profile 2 c x^2 of the paraboloid z = c r^2 (MDR) at x = (i + 1/2) dx.
fn half_parabola(n: usize, c: f64, half: f64) -> (Vec<f64>, f64) {
    let dx = half / n as f64;
    let g = (0..n)
        .map(|i| 2.0 * c * ((i as f64 + 0.5) * dx).powi(2))
        .collect();
    (g, dx)
}

/// Approach to 0.2 at t = 1, a hold to t = 1.3, retraction to 0 at t = 2.3.
fn ramp_hold_retract(samples: usize) -> (Vec<f64>, Vec<f64>) {
    let times: Vec<f64> = (1..=samples)
        .map(|k| 2.3 * k as f64 / samples as f64)
        .collect();
    let depth = times
        .iter()
        .map(|&t| 0.2 * t.min(1.0).min(2.3 - t).max(0.0))
        .collect();
    (times, depth)
}

/// Media with the bound on the finest elements' deviation from Ting's solution below
/// (measured 1.4e-7, 2.1e-7, 3.6e-8; the dashpot's 5.9e-4, its elements' force following
/// the contact's growth with a first-order error in the step).
fn media() -> Vec<(&'static str, Rheology, f64)> {
    vec![
        (
            "standard solid",
            Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap(),
            1e-6,
        ),
        (
            "Kelvin-Voigt",
            Rheology::new(1.0, vec![], 0.4).unwrap(),
            3e-3,
        ),
        (
            "Prony, 3 terms",
            Rheology::new(0.5, vec![(2.0, 0.02), (1.0, 0.2), (1.5, 2.0)], 0.0).unwrap(),
            1e-6,
        ),
        (
            "Maxwell",
            Rheology::new(0.0, vec![(3.0, 0.5)], 0.0).unwrap(),
            1e-6,
        ),
    ]
}

/// Largest |a - b| over the largest |b|.
fn deviation(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

/// The elements converge to Ting's solution as the profile and the steps are refined
/// (both discretise the same MDR model: the elements with a contact-edge error, Ting's
/// solution with its area function's, second order in dx, and each with its own
/// second-order error in the step). Ting's solution at n = 500 and 4 substeps is within
/// 1e-5 of its refined self (measured 2.4e-6 to 3.5e-6).
#[test]
fn elements_converge_to_tings_solution() {
    let (times, depth) = ramp_hold_retract(230);
    for (name, r, bound) in media() {
        let at = |n: usize, substeps: usize, elements: bool| {
            let (g, dx) = half_parabola(n, 1.0, 0.5);
            let curve = Curve::new(
                g,
                dx,
                times.clone(),
                depth.clone(),
                Control::Depth,
                substeps,
            )
            .unwrap();
            let curve = if elements {
                curve.elements_only()
            } else {
                curve
            };
            curve.evaluate(&r, &[]).unwrap()
        };
        let reference = at(4000, 16, false);
        assert_eq!(reference.forward, Forward::Hereditary);
        let errors: Vec<f64> = [(500, 1), (2000, 4), (8000, 16)]
            .iter()
            .map(|&(n, substeps)| deviation(&at(n, substeps, true).values, &reference.values))
            .collect();
        let coarse = deviation(&at(500, 4, false).values, &reference.values);
        assert!(
            errors[2] < errors[1] && errors[1] < errors[0],
            "{name}: {errors:?}"
        );
        assert!(errors[2] < bound, "{name}: {errors:?}");
        assert!(coarse < 1e-5, "{name}: {coarse:e}");
    }
}

/// An elastic medium: F = 8 G A(d) with A = (2/3) d a, a = sqrt(d / (2 c)), at every sample,
/// approach and retraction alike, to the area function's error at n = 500 (measured 2.5e-6).
#[test]
fn elastic_force_is_the_area_function() {
    let (times, depth) = ramp_hold_retract(230);
    let (g, dx) = half_parabola(500, 1.0, 0.5);
    let r = Rheology::new(2.0, vec![], 0.0).unwrap();
    let e = Curve::new(g, dx, times, depth.clone(), Control::Depth, 1)
        .unwrap()
        .evaluate(&r, &[])
        .unwrap();
    let exact: Vec<f64> = depth
        .iter()
        .map(|&d| 8.0 * 2.0 * (2.0 / 3.0) * d * (d / 2.0).sqrt())
        .collect();
    let error = deviation(&e.values, &exact);
    assert!(error < 1e-5, "{error:e}");
}

/// Histories and profiles outside Ting's case are stepped by the elements: a depth that
/// rises again after falling, and a profile that falls somewhere.
#[test]
fn other_cases_step_the_elements() {
    let times: Vec<f64> = (1..=30).map(|k| 0.1 * k as f64).collect();
    let twice: Vec<f64> = times
        .iter()
        .map(|&t| 0.1 * (1.0 + (3.0 * t).sin()))
        .collect();
    let (g, dx) = half_parabola(100, 1.0, 0.5);
    let r = Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap();
    let again = Curve::new(g.clone(), dx, times.clone(), twice, Control::Depth, 1).unwrap();
    assert_eq!(again.evaluate(&r, &[]).unwrap().forward, Forward::Elements);
    let mut dented = g;
    dented[10] = dented[11] * 1.5;
    let once: Vec<f64> = times.iter().map(|&t| 0.1 * t.min(3.0 - t)).collect();
    let curve = Curve::new(dented, dx, times, once, Control::Depth, 1).unwrap();
    assert_eq!(curve.evaluate(&r, &[]).unwrap().forward, Forward::Elements);
}
