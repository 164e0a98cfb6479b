//! Curves driven through a spring (an AFM cantilever), the elements stepped: against algebra for an elastic
//! medium, against the depth-controlled curve of the depths they compute, against depth
//! control for a stiff spring, and their derivatives against central differences.

use super::tests::standard_solid_tangents;
use super::*;

fn half_parabola(n: usize) -> (Vec<f64>, f64) {
    let dx = 0.5 / n as f64;
    let g = (0..n)
        .map(|i| 2.0 * ((i as f64 + 0.5) * dx).powi(2))
        .collect();
    (g, dx)
}

/// A drive from 0.05 before contact to 0.25 past it and back to 0.05 before, 60 samples.
fn drive() -> (Vec<f64>, Vec<f64>) {
    let times: Vec<f64> = (0..=60).map(|k| 0.05 * k as f64).collect();
    let u = times
        .iter()
        .map(|&t| -0.05 + 0.2 * t.min(3.0 - t))
        .collect();
    (times, u)
}

fn standard_solid() -> Rheology {
    Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap()
}

/// Elastic: each sample's force solves k (u - d) = 8 G dx sum (d - g_i)+ (found here by
/// bisection), to round-off.
#[test]
fn elastic_force_balances_the_spring() {
    let (g, dx) = half_parabola(300);
    let (times, u) = drive();
    let (shear, k) = (2.0, 0.7);
    let r = Rheology::new(shear, vec![], 0.0).unwrap();
    let e = Curve::new(g.clone(), dx, times, u.clone(), Control::Spring(k), 1)
        .unwrap()
        .elements_only()
        .evaluate(&r, &[])
        .unwrap();
    let scale = e.values.iter().fold(0.0f64, |a, b| a.max(*b));
    assert!(scale > 0.0);
    for (&f, &drive) in e.values.iter().zip(&u) {
        let unbalanced = |d: f64| {
            8.0 * shear * dx * g.iter().map(|gi| (d - gi).max(0.0)).sum::<f64>() - k * (drive - d)
        };
        let (mut lo, mut hi) = (drive.min(0.0) - 1.0, drive.max(0.0) + 1.0);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if unbalanced(mid) > 0.0 {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        let exact = k * (drive - 0.5 * (lo + hi));
        assert!((f - exact).abs() <= 1e-12 * scale, "{f} vs {exact}");
    }
}

/// A standard solid: the depths d = u - F / k the spring curve implies, prescribed to a
/// depth-controlled curve stepped by the elements with the same steps, give the same
/// forces (round-off); a stiff spring (k = 1e8) gives depth control's forces at u.
#[test]
fn spring_curve_is_depth_control_at_its_own_depths() {
    let (g, dx) = half_parabola(300);
    let (times, u) = drive();
    let r = standard_solid();
    let k = 0.5;
    let e = Curve::new(
        g.clone(),
        dx,
        times.clone(),
        u.clone(),
        Control::Spring(k),
        1,
    )
    .unwrap()
    .elements_only()
    .evaluate(&r, &[])
    .unwrap();
    let depth: Vec<f64> = u.iter().zip(&e.values).map(|(u, f)| u - f / k).collect();
    let again = Curve::new(g.clone(), dx, times.clone(), depth, Control::Depth, 1)
        .unwrap()
        .elements_only()
        .evaluate(&r, &[])
        .unwrap();
    let scale = e.values.iter().fold(0.0f64, |a, b| a.max(*b));
    for (a, b) in e.values.iter().zip(&again.values) {
        assert!((a - b).abs() <= 1e-10 * scale, "{a} vs {b}");
    }
    let stiff = Curve::new(
        g.clone(),
        dx,
        times.clone(),
        u.clone(),
        Control::Spring(1e8),
        1,
    )
    .unwrap()
    .elements_only()
    .evaluate(&r, &[])
    .unwrap();
    let held = Curve::new(g, dx, times, u, Control::Depth, 1)
        .unwrap()
        .elements_only()
        .evaluate(&r, &[])
        .unwrap();
    let scale = held.values.iter().fold(0.0f64, |a, b| a.max(*b));
    for (a, b) in stiff.values.iter().zip(&held.values) {
        assert!((a - b).abs() <= 1e-5 * scale, "{a} vs {b}");
    }
}

/// Derivatives in ln G_inf, ln G1, ln tau1 and along the drive's shift against central
/// differences (step 1e-6: ~1e-9 relative), through contact, release and the slack spring.
#[test]
fn spring_derivatives_match_central_differences() {
    let (g, dx) = half_parabola(300);
    let (times, u) = drive();
    let curve = Curve::new(g, dx, times.clone(), u, Control::Spring(0.5), 2)
        .unwrap()
        .elements_only();
    let build = |p: &[f64]| Rheology::new(p[0].exp(), vec![(p[1].exp(), p[2].exp())], 0.0).unwrap();
    let params = [0.0, 0.7, -1.2];
    let r = build(&params);
    let tangents = standard_solid_tangents(&r);
    let shift = 0.01;
    let e = curve.evaluate_shifted(&r, &tangents, shift).unwrap();
    assert_eq!(e.forward, Forward::Elements);
    let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let h = 1e-6;
    for j in 0..4 {
        let (up, down) = if j < 3 {
            let (mut a, mut b) = (params, params);
            a[j] += h;
            b[j] -= h;
            (
                curve
                    .evaluate_shifted(&build(&a), &[], shift)
                    .unwrap()
                    .values,
                curve
                    .evaluate_shifted(&build(&b), &[], shift)
                    .unwrap()
                    .values,
            )
        } else {
            (
                curve.evaluate_shifted(&r, &[], shift + h).unwrap().values,
                curve.evaluate_shifted(&r, &[], shift - h).unwrap().values,
            )
        };
        for k in 0..times.len() {
            let numeric = (up[k] - down[k]) / (2.0 * h);
            let analytic = e.jacobian[k * 4 + j];
            assert!(
                (numeric - analytic).abs() <= 1e-6 * biggest,
                "param {j} sample {k}: {analytic} vs {numeric}"
            );
        }
    }
}
