//! Ting's solution with the spring in series (`spring_hereditary`) against the elements
//! stepped under spring control, which converge to it, and its derivatives against central
//! differences.

use super::tests::standard_solid_tangents;
use super::*;
use crate::model::medium::power_law::PronyOfPowerLaw;

/// The half profile 2 x^2 of the paraboloid z = r^2 (MDR) at x = (i + 1/2) dx, to 0.5.
fn half_parabola(n: usize) -> (Vec<f64>, f64) {
    let dx = 0.5 / n as f64;
    let g = (0..n)
        .map(|i| 2.0 * ((i as f64 + 0.5) * dx).powi(2))
        .collect();
    (g, dx)
}

/// The drive (m) at t of an approach from 0.05 before contact at 0.25 per s for 1 s, a
/// dwell of `dwell` s, and (`retract`) a retraction at the same speed to the start.
fn drive(t: f64, dwell: f64, retract: bool) -> f64 {
    let approach = -0.05 + 0.25 * t.min(1.0);
    if retract && t > 1.0 + dwell {
        approach - 0.25 * (t - 1.0 - dwell).min(1.0)
    } else {
        approach
    }
}

/// The protocols: (name, times, drive).
fn protocols(samples: usize) -> Vec<(&'static str, Vec<f64>, Vec<f64>)> {
    let with = |end: f64, dwell: f64, retract: bool| {
        let times: Vec<f64> = (1..=samples)
            .map(|k| end * k as f64 / samples as f64)
            .collect();
        let u = times.iter().map(|&t| drive(t, dwell, retract)).collect();
        (times, u)
    };
    let (t1, u1) = with(2.0, 0.0, true);
    let (t2, u2) = with(1.6, 0.6, false);
    let (t3, u3) = with(2.5, 0.5, true);
    vec![
        ("approach-retract", t1, u1),
        ("approach-dwell", t2, u2),
        ("approach-dwell-retract", t3, u3),
    ]
}

/// A standard solid, a Prony series of three terms and a power law (G0 = 1 at t0 = 1 s,
/// beta = 0.3, its series over the curves' times).
fn media() -> Vec<(&'static str, Rheology)> {
    vec![
        (
            "standard solid",
            Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap(),
        ),
        (
            "Prony, 3 terms",
            Rheology::new(0.5, vec![(2.0, 0.02), (1.0, 0.2), (1.5, 2.0)], 0.0).unwrap(),
        ),
        (
            "power law",
            PronyOfPowerLaw::new(1.0, 0.3, 1.0, 1e-3, 3.0)
                .unwrap()
                .rheology,
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

/// The elements stepped under spring control (k = 0.5: the deflection comparable to the
/// indentation) converge to Ting's solution with the spring as the profile and the steps
/// are refined, on every protocol and medium: their deviation from it (n = 4000, 32
/// substeps) falls at each refinement and is below 1e-6 of the peak force at the same n and
/// steps (measured 4.2e-8 to 4.4e-8), and Ting's solution at n = 500 and 8 substeps is
/// within 1e-4 of its refined self (measured 1.8e-6 to 2.0e-5, the power law's largest).
#[test]
fn elements_under_a_spring_converge_to_tings_solution() {
    for (protocol, times, u) in protocols(100) {
        for (name, r) in media() {
            let at = |n: usize, substeps: usize, elements: bool| {
                let (g, dx) = half_parabola(n);
                let curve = Curve::new(
                    g,
                    dx,
                    times.clone(),
                    u.clone(),
                    Control::Spring(0.5),
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
            let reference = at(4000, 32, false);
            assert_eq!(reference.forward, Forward::Hereditary, "{protocol} {name}");
            let errors: Vec<f64> = [(250, 2), (1000, 8), (4000, 32)]
                .iter()
                .map(|&(n, substeps)| {
                    let e = at(n, substeps, true);
                    assert_eq!(e.forward, Forward::Elements);
                    deviation(&e.values, &reference.values)
                })
                .collect();
            let coarse = deviation(&at(500, 8, false).values, &reference.values);
            assert!(
                errors[2] < errors[1] && errors[1] < errors[0],
                "{protocol} {name}: {errors:?}"
            );
            assert!(errors[2] < 1e-6, "{protocol} {name}: {errors:?}");
            assert!(coarse < 1e-4, "{protocol} {name}: {coarse:e}");
        }
    }
}

/// A stiff spring (k = 1e9) makes the drive the depth: Ting's solution under depth control
/// at the drive (both from 0 before contact), to 1e-5 of the peak force with 16 substeps
/// (the two interpolate t1 within a step differently: linearly in the force, and along
/// the area).
#[test]
fn a_stiff_spring_is_depth_control() {
    let (g, dx) = half_parabola(500);
    for (protocol, times, u) in protocols(100) {
        let r = Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap();
        let u: Vec<f64> = u.iter().map(|&v| v.max(0.0)).collect();
        let spring = Curve::new(
            g.clone(),
            dx,
            times.clone(),
            u.clone(),
            Control::Spring(1e9),
            16,
        )
        .unwrap()
        .evaluate(&r, &[])
        .unwrap();
        let held = Curve::new(g.clone(), dx, times, u, Control::Depth, 16)
            .unwrap()
            .evaluate(&r, &[])
            .unwrap();
        assert_eq!(spring.forward, Forward::Hereditary);
        assert_eq!(held.forward, Forward::Hereditary);
        let error = deviation(&spring.values, &held.values);
        assert!(error < 1e-5, "{protocol}: {error:e}");
    }
}

/// Derivatives in ln G_inf, ln G1, ln tau1 (a standard solid, a Maxwell fluid and a
/// Kelvin–Voigt solid: ln G, ln eta) and along
/// the drive's shift against central differences (step 1e-6), through the approach, the
/// dwell, the release and the slack spring after it.
#[test]
fn derivatives_match_central_differences() {
    let (g, dx) = half_parabola(300);
    let (_, times, u) = protocols(80).remove(2);
    let curve = Curve::new(g, dx, times.clone(), u, Control::Spring(0.5), 2).unwrap();
    type Build = fn(&[f64]) -> Rheology;
    let solid: Build = |p| Rheology::new(p[0].exp(), vec![(p[1].exp(), p[2].exp())], 0.0).unwrap();
    let maxwell: Build = |p| Rheology::new(0.0, vec![(p[0].exp(), p[1].exp())], 0.0).unwrap();
    let voigt: Build = |p| Rheology::new(p[0].exp(), vec![], p[1].exp()).unwrap();
    for (build, params) in [
        (solid, vec![0.0, 0.7, -1.2]),
        (maxwell, vec![0.7, -1.2]),
        (voigt, vec![0.0, -1.0]),
    ] {
        let r = build(&params);
        let tangents = if r.terms.is_empty() {
            let with = |g_inf: f64, eta: f64| Rheology {
                g_inf,
                terms: vec![],
                eta,
            };
            vec![with(r.g_inf, 0.0), with(0.0, r.eta)]
        } else if r.g_inf == 0.0 {
            standard_solid_tangents(&r)[1..].to_vec()
        } else {
            standard_solid_tangents(&r)
        };
        let shift = 0.01;
        let e = curve.evaluate_shifted(&r, &tangents, shift).unwrap();
        assert_eq!(e.forward, Forward::Hereditary);
        let p = params.len() + 1;
        let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
        let h = 1e-6;
        for j in 0..p {
            let (up, down) = if j < params.len() {
                let (mut a, mut b) = (params.clone(), params.clone());
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
                let analytic = e.jacobian[k * p + j];
                assert!(
                    (numeric - analytic).abs() <= 1e-6 * biggest,
                    "param {j} sample {k}: {analytic} vs {numeric}"
                );
            }
        }
    }
}

/// Histories outside Ting's case step the elements: a drive that presses again after the
/// contact has let go, and a profile that falls somewhere.
#[test]
fn other_cases_step_the_elements() {
    let (g, dx) = half_parabola(200);
    let times: Vec<f64> = (1..=60).map(|k| 0.05 * k as f64).collect();
    let twice: Vec<f64> = times
        .iter()
        .map(|&t| -0.05 + 0.1 * (1.0 - (4.0 * t).cos()))
        .collect();
    let r = Rheology::new(1.0, vec![(2.0, 0.3)], 0.0).unwrap();
    let again = Curve::new(g.clone(), dx, times.clone(), twice, Control::Spring(0.5), 1).unwrap();
    assert_eq!(again.evaluate(&r, &[]).unwrap().forward, Forward::Elements);
    let mut dented = g;
    dented[10] = dented[11] * 1.5;
    let once: Vec<f64> = times.iter().map(|&t| drive(t, 0.5, true)).collect();
    let curve = Curve::new(
        dented,
        dx,
        times.clone(),
        once.clone(),
        Control::Spring(0.5),
        1,
    )
    .unwrap();
    assert_eq!(curve.evaluate(&r, &[]).unwrap().forward, Forward::Elements);
}

/// A power law's derivatives in ln G0 and beta (its series' slow term moves its relaxation
/// time with beta) and along the drive's shift against central differences (step 1e-6),
/// through the approach, the dwell, the release and the slack spring after it.
#[test]
fn power_law_derivatives_match_central_differences() {
    let (g, dx) = half_parabola(300);
    let (_, times, u) = protocols(80).remove(2);
    let curve = Curve::new(g, dx, times.clone(), u, Control::Spring(0.5), 2).unwrap();
    let (t_lo, t_hi) = curve.time_range();
    let series = |p: &[f64]| PronyOfPowerLaw::new(p[0].exp(), p[1], 1.0, t_lo, t_hi).unwrap();
    let params = [0.3, 0.25];
    let at = series(&params);
    let r = at.rheology.clone();
    let scaled = Rheology {
        g_inf: r.g_inf,
        terms: r.terms.iter().map(|&(g, _)| (g, 0.0)).collect(),
        eta: r.eta,
    };
    let shift = 0.01;
    let e = curve
        .evaluate_shifted(&r, &[scaled, at.d_beta()], shift)
        .unwrap();
    assert_eq!(e.forward, Forward::Hereditary);
    let p = params.len() + 1;
    let biggest = e.jacobian.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    let h = 1e-6;
    for j in 0..p {
        let values = |sign: f64| {
            let (mut x, mut s) = (params.to_vec(), shift);
            if j < params.len() {
                x[j] += sign * h;
            } else {
                s += sign * h;
            }
            let e = curve
                .evaluate_shifted(&series(&x).rheology, &[], s)
                .unwrap();
            assert_eq!(e.forward, Forward::Hereditary);
            e.values
        };
        let (up, down) = (values(1.0), values(-1.0));
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

/// Media with a dashpot (eta delta(t) in G(t)): Kelvin–Voigt, a standard solid with a
/// dashpot in parallel, and a viscous fluid.
fn dashpot_media() -> Vec<(&'static str, Rheology)> {
    vec![
        ("Kelvin-Voigt", Rheology::new(1.0, vec![], 0.3).unwrap()),
        (
            "standard solid and dashpot",
            Rheology::new(1.0, vec![(2.0, 0.3)], 0.05).unwrap(),
        ),
        ("viscous", Rheology::new(0.0, vec![], 0.3).unwrap()),
    ]
}

/// With a dashpot the elements stepped under spring control converge to Ting's solution
/// too (the depth's balance takes the dashpot's eta dA/dt, the step's mean, while the
/// contact grows, as the elements' dashpots sum to; on retraction the dashpot's share of
/// phi, eta dd/dt, moves t1 at once): their deviation from it (n = 4000, 32 substeps)
/// falls at each refinement (measured 7e-4 to 3.5e-3 at n = 250 and 2 substeps) and is
/// below 1e-6 of the peak force at the same n and steps (measured 4.4e-8 to 5.6e-8, the
/// contact edge's share as without a dashpot), on every protocol.
#[test]
fn dashpots_under_a_spring_converge_to_tings_solution() {
    for (protocol, times, u) in protocols(100) {
        for (name, r) in dashpot_media() {
            let at = |n: usize, substeps: usize, elements: bool| {
                let (g, dx) = half_parabola(n);
                let curve = Curve::new(
                    g,
                    dx,
                    times.clone(),
                    u.clone(),
                    Control::Spring(0.5),
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
            let reference = at(4000, 32, false);
            assert_eq!(reference.forward, Forward::Hereditary, "{protocol} {name}");
            let errors: Vec<f64> = [(250, 2), (1000, 8), (4000, 32)]
                .iter()
                .map(|&(n, substeps)| {
                    let e = at(n, substeps, true);
                    assert_eq!(e.forward, Forward::Elements);
                    deviation(&e.values, &reference.values)
                })
                .collect();
            assert!(
                errors[2] < errors[1] && errors[1] < errors[0],
                "{protocol} {name}: {errors:?}"
            );
            assert!(errors[2] < 1e-6, "{protocol} {name}: {errors:?}");
        }
    }
}

/// A dashpot's force is continuous in the drive as the contact forms: F = k (u - d) with
/// the depth d non-decreasing in the drive u at unit rate at most, so moving the whole drive
/// by delta moves no sample's force by more than k delta. Swept over one sampling step of
/// the drive (the first contact crossing every point of a step), with a dashpot whose force
/// at the first contact dwarfs k delta (eta / h a (d - d_prev) with a = dx / 2 there).
#[test]
fn dashpot_force_is_continuous_as_the_contact_forms() {
    let (g, dx) = half_parabola(300);
    let (_, times, u) = protocols(80).remove(0);
    let k = 0.5;
    let curve = Curve::new(g, dx, times.clone(), u, Control::Spring(k), 1).unwrap();
    let voigt = Rheology::new(1.0, vec![], 3.0).unwrap();
    let step = 0.25 * times[0];
    let count = 2000;
    let delta = step / count as f64;
    let mut before = curve.evaluate_shifted(&voigt, &[], 0.0).unwrap();
    for i in 1..=count {
        let e = curve
            .evaluate_shifted(&voigt, &[], i as f64 * delta)
            .unwrap();
        assert_eq!(e.forward, Forward::Hereditary);
        for (s, (a, b)) in e.values.iter().zip(&before.values).enumerate() {
            assert!(
                (a - b).abs() <= k * delta * (1.0 + 1e-6),
                "shift {i}, sample {s}: {b} -> {a} ({:e} > k delta {:e})",
                (a - b).abs(),
                k * delta
            );
        }
        before = e;
    }
}
