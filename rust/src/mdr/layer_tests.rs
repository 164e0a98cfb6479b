use super::*;
use crate::model::loading::{DepthHistory, ForceHistory};
use crate::support::monitor::Silent;

/// A thin layer's limit of phi as a function of chi.
type Limit = Box<dyn Fn(f64) -> f64>;

fn layer(h: f64, base: Base) -> Layer {
    Layer { thickness: h, base }
}

/// (2 / pi) integral_0^inf (1 - R(u)) du by Gauss panels, independent of the M table.
fn leading(nu: f64, base: Base) -> f64 {
    let gauss = gauss_legendre(16);
    let mut sum = 0.0;
    for k in 0..1000 {
        for &(x, w) in &gauss {
            let u = (k as f64 + x + 0.5) * 0.03;
            sum += w * 0.03 * (1.0 - compliance_ratio(u, nu, base));
        }
    }
    2.0 * sum / std::f64::consts::PI
}

/// A thick layer: phi = 1 + c1 chi + c1^2 chi^2 + O(chi^3), c1 = (2 / pi) integral (1 - R)
/// (the Neumann series of the punch equation with the kernel's value at 0).
#[test]
fn thick_layer_punch_follows_its_expansion() {
    for base in [Base::Bonded, Base::Frictionless] {
        for nu in [0.0, 0.3, 0.5] {
            let c1 = leading(nu, base);
            let p = PunchStiffness::new(nu, base).unwrap();
            for chi in [0.02, 0.04] {
                let series = 1.0 + c1 * chi + c1 * c1 * chi * chi;
                let err = (p.phi(chi) - series).abs();
                assert!(
                    err < 2.0 * chi.powi(3),
                    "{base:?} nu={nu} chi={chi}: {err:e}"
                );
            }
        }
    }
    // the exact leading coefficients quoted in docs/layers.md
    assert!((leading(0.5, Base::Bonded) - 1.1270).abs() < 1e-4);
    assert!((leading(0.3, Base::Frictionless) - 0.743).abs() < 1e-3);
}

/// Doubling the Nyström points changes phi by under 1e-9 (the round-off of the thin
/// incompressible layer's ill-conditioned system; 1e-11 for chi <= 3).
#[test]
fn punch_equation_converges_under_refinement() {
    for base in [Base::Bonded, Base::Frictionless] {
        let m = m_cached(0.5, base);
        for chi in [0.5, 3.0, 8.0] {
            let s = Nystrom::new(&m, chi).unwrap();
            let ones = vec![1.0; s.points.len()];
            let coarse = s.integral(&s.solve(&ones));
            let nodes = 2 * nodes_for(chi);
            let points: Vec<(f64, f64)> = gauss_legendre(nodes)
                .into_iter()
                .map(|(x, w)| (x + 0.5, w))
                .collect();
            let a = Mat::from_fn(nodes, nodes, |i, j| {
                let k = kernel(&m, chi, points[i].0, points[j].0) * points[j].1;
                if i == j {
                    1.0 + k
                } else {
                    k
                }
            });
            let lu = a.partial_piv_lu();
            let f = lu.solve(ColRef::from_slice(&vec![1.0; nodes]));
            let fine: f64 = (0..nodes).map(|j| points[j].1 * f[j]).sum();
            assert!((coarse / fine - 1.0).abs() < 1e-9, "{base:?} chi={chi}");
        }
    }
}

/// Thin layers: Winkler foundations under the punch, k -> pi a^2 E_c / h (frictionless:
/// phi -> (pi / 2) chi; bonded, nu = 0.3: (pi / 2) chi (1 - nu)^2 / (1 - 2 nu)), and the
/// squeezed incompressible film, k -> 3 pi G a^4 / (8 h^3) (phi -> (3 pi / 64) chi^3); the
/// relative error falls like 1 / chi or faster (edge effects a thickness wide; the film's
/// is still 94 % at chi = 8).
#[test]
fn thin_layer_punch_tends_to_its_foundations() {
    let cases: [(f64, Base, Limit); 3] = [
        (
            0.3,
            Base::Frictionless,
            Box::new(|c: f64| 0.5 * std::f64::consts::PI * c),
        ),
        (
            0.3,
            Base::Bonded,
            Box::new(|c: f64| 0.5 * std::f64::consts::PI * c * 0.49 / 0.4),
        ),
        (
            0.5,
            Base::Bonded,
            Box::new(|c: f64| 3.0 * std::f64::consts::PI / 64.0 * c.powi(3)),
        ),
    ];
    for (nu, base, limit) in cases {
        let p = PunchStiffness::new(nu, base).unwrap();
        let err = |chi: f64| (p.phi(chi) / limit(chi) - 1.0).abs();
        let (e2, e4, e8) = (err(2.0), err(4.0), err(8.0));
        assert!(
            e4 < 0.55 * e2 && e8 < 0.55 * e4,
            "{base:?} nu={nu}: {e2} {e4} {e8}"
        );
    }
}

/// Dimitriadis et al. (2002)'s bonded incompressible punch, fitted to Hayes et al.'s (1972)
/// solutions, 1 + 1.133 chi + 1.283 chi^2 + 0.769 chi^3 + 0.0975 chi^4: its correction
/// (phi - 1) within 3 % of the exact one for chi <= 0.3 (0.5 % from its leading
/// coefficient, 1.133 against the exact 1.1270; the crate's BEM finds the same deviations).
#[test]
fn bonded_punch_agrees_with_dimitriadis() {
    let p = PunchStiffness::new(0.5, Base::Bonded).unwrap();
    for chi in [0.01f64, 0.1, 0.2, 0.3] {
        let d = 1.0 + 1.133 * chi + 1.283 * chi * chi + 0.769 * chi.powi(3) + 0.0975 * chi.powi(4);
        let err = ((p.phi(chi) - 1.0) / (d - 1.0) - 1.0).abs();
        assert!(err < 0.03, "chi={chi}: {err:e}");
    }
}

/// The weighted foundation with the layered profile gives the exact elastic force of the
/// punch equation (computed directly, `force_at_radius`) for a paraboloid and a cone on both
/// bases, thick to thin: Mossakovskii's dF/dd = k(a) checked against the force integral,
/// to the foundation's discretisation (dx / a)^2 (measured 1e-6 to 1.1e-5).
#[test]
fn foundation_force_is_the_punch_equations_force() {
    let (n, half) = (1001, 3.0);
    let dx = 2.0 * half / n as f64;
    let profiles: [Box<dyn Fn(f64) -> Result<f64> + Sync>; 2] =
        [Box::new(|x: f64| Ok(x * x)), Box::new(|x: f64| Ok(x.abs()))];
    for base in [Base::Bonded, Base::Frictionless] {
        for g1 in &profiles {
            for h in [10.0, 1.0, 0.4] {
                let l = layer(h, base);
                let g = layered_profile(g1.as_ref(), n, dx, l, 0.5).unwrap();
                let w = element_weights(n, dx, l, 0.5).unwrap();
                let a = 1.0;
                let d = depth_at_radius(g1.as_ref(), a, l, 0.5).unwrap();
                let exact = force_at_radius(g1.as_ref(), a, d, l, 0.5).unwrap();
                let f: f64 = (0..n)
                    .filter(|&i| g[i] < d)
                    .map(|i| w[i] * dx * (d - g[i]))
                    .sum();
                assert!(
                    (f / exact - 1.0).abs() < (dx / a).powi(2),
                    "{base:?} h={h}: {f} vs {exact}"
                );
            }
        }
    }
}

/// A layer 1000 contact radii thick: the half-space's Hertz force to the layer's first
/// order, F = F_Hertz (1 + c1 sqrt(R d) / h), under depth control; and the force-controlled
/// run returns the depth-controlled one's depth.
#[test]
fn thick_layer_is_hertz_to_first_order() {
    let (n, half, h) = (8001, 2.0, 1000.0);
    let dx = 2.0 * half / n as f64;
    // paraboloid z = r^2 / (2 R), R = 1: g1 = x^2 / R
    let g1 = |x: f64| Ok(x * x);
    let l = layer(h, Base::Bonded);
    let g = layered_profile(&g1, n, dx, l, 0.5).unwrap();
    let w = element_weights(n, dx, l, 0.5).unwrap();
    let medium = Rheology::new(0.25, vec![], 0.0).unwrap(); // E* = 4 G' = 1
    let depth = DepthHistory::piecewise_linear(vec![0.0, 1.0], vec![0.0, 1.0]).unwrap();
    let times = [0.5, 1.0];
    let request = Request {
        times: &times,
        dt: 0.01,
        fields_at: &[],
        field_rates: false,
    };
    let s = run_mdr_layer(
        &g,
        dx,
        &w,
        &medium,
        &Loading::Depth(depth),
        &request,
        &mut Silent,
    )
    .unwrap();
    let c1 = leading(0.5, Base::Bonded);
    for (d, f) in s.depth.iter().zip(&s.force) {
        let hertz = 4.0 / 3.0 * d.powf(1.5) * (1.0 + c1 * d.sqrt() / h);
        assert!((f / hertz - 1.0).abs() < 2e-6, "d={d}: {f} vs {hertz}");
    }
    let force = ForceHistory::piecewise_linear(vec![0.0, 1.0], vec![0.0, s.force[1]]).unwrap();
    let r = run_mdr_layer(
        &g,
        dx,
        &w,
        &medium,
        &Loading::Force(force),
        &request,
        &mut Silent,
    )
    .unwrap();
    assert!((r.depth[1] - 1.0).abs() < 1e-9);
}

/// A standard-solid layer under a depth ramp: Lee–Radok's integral of the elastic layer's
/// force increments (the same foundation's elastic forces) against the hereditary stepping.
#[test]
fn viscoelastic_layer_follows_lee_radok() {
    let (n, half) = (2001, 2.0);
    let dx = 2.0 * half / n as f64;
    let g1 = |x: f64| Ok(x * x);
    let l = layer(0.5, Base::Bonded);
    let g = layered_profile(&g1, n, dx, l, 0.5).unwrap();
    let w = element_weights(n, dx, l, 0.5).unwrap();
    let (g_inf, g1m, tau) = (1.0, 2.0, 0.3);
    let medium = Rheology::new(g_inf, vec![(g1m, tau)], 0.0).unwrap();
    let elastic = |d: f64| -> f64 {
        4.0 * dx
            * (0..n)
                .filter(|&i| g[i] < d)
                .map(|i| w[i] * (d - g[i]))
                .sum::<f64>()
    };
    let depth = DepthHistory::piecewise_linear(vec![0.0, 1.0], vec![0.0, 0.8]).unwrap();
    let times = [0.25, 0.5, 1.0];
    let request = Request {
        times: &times,
        dt: 1e-3,
        fields_at: &[],
        field_rates: false,
    };
    let s = run_mdr_layer(
        &g,
        dx,
        &w,
        &medium,
        &Loading::Depth(depth),
        &request,
        &mut Silent,
    )
    .unwrap();
    for (t, f) in s.t.iter().zip(&s.force) {
        // F(t) = integral_0^t G(t - s) dF_e(d(s)), d = 0.8 s, by the midpoint rule
        let steps = 20000;
        let h = t / steps as f64;
        let mut lee = 0.0;
        for k in 0..steps {
            let (s0, s1) = (k as f64 * h, (k + 1) as f64 * h);
            let relax = g_inf + g1m * (-(t - 0.5 * (s0 + s1)) / tau).exp();
            lee += relax * (elastic(0.8 * s1) - elastic(0.8 * s0));
        }
        assert!((f / lee - 1.0).abs() < 1e-4, "t={t}: {f} vs {lee}");
    }
}

/// The half-space-equivalent profile gives the weighted foundation's force: the same
/// contact by both (paraboloid and cone, both bases, h = 0.5), to the stretched grid's
/// discretisation (dxi / xi(a))^2, xi(a) = a phi(a / h).
#[test]
fn half_space_equivalent_is_the_weighted_foundation() {
    let (n, half) = (1001, 2.0);
    let profiles: [Box<dyn Fn(f64) -> Result<f64> + Sync>; 2] =
        [Box::new(|x: f64| Ok(x * x)), Box::new(|x: f64| Ok(x.abs()))];
    for base in [Base::Bonded, Base::Frictionless] {
        for g1 in &profiles {
            let l = layer(0.5, base);
            let (g, dxi) = half_space_equivalent(g1.as_ref(), n / 2, half, l, 0.3).unwrap();
            let d = depth_at_radius(g1.as_ref(), 1.0, l, 0.3).unwrap();
            let exact = force_at_radius(g1.as_ref(), 1.0, d, l, 0.3).unwrap();
            let f: f64 = 2.0 * dxi * g.iter().filter(|&&v| v < d).map(|v| d - v).sum::<f64>();
            let xi_a = PunchStiffness::new(0.3, base).unwrap().phi(1.0 / 0.5);
            let tolerance = (dxi / xi_a).powi(2);
            assert!(
                (f / exact - 1.0).abs() < tolerance,
                "{base:?}: {f} vs {exact}"
            );
        }
    }
    assert!(
        half_space_equivalent(&|x: f64| Ok(x * x), 10, 9.0, layer(1.0, Base::Bonded), 0.3).is_err()
    );
}
