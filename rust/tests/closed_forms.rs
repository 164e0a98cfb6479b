//! Every number the binary prints for the quick paper and for the standard-solid unloading
//! example, against closed forms written here from the literature (no code of the crate):
//! the viscous flat punch, Lee–Radok for the viscous paraboloid, Ting (1966) for loading and
//! unloading a paraboloid on a standard linear solid. Bounds are stated as multiples of the
//! resolution, with the largest value measured at the quick resolutions in brackets.

mod support;

use support::{mdrvisc, numbers};

const FORCE: f64 = 1.0;
const ETA: f64 = 1.0;

fn run_json(args: &[&str]) -> serde_json::Value {
    let (code, out, err) = mdrvisc(args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).expect("JSON")
}

/// A flat punch of radius a on a viscous half-space (E* = 4 eta d/dt): F = 8 eta a dd/dt,
/// central pressure F / (2 pi a^2).
#[test]
fn quick_paper_rod_follows_the_flat_punch() {
    let doc = run_json(&["paper", "--quick", "--json"]);
    let (a, t) = (1.0, 1.0);
    let rate = FORCE / (8.0 * ETA * a);
    let p0 = FORCE / (2.0 * std::f64::consts::PI * a * a);
    for entry in doc.as_array().unwrap().iter().take(2) {
        let r = &entry["result"];
        let method = r["method"].as_str().unwrap();
        let dx = r["dx"].as_f64().unwrap();
        let rel = |key: &str, exact: f64| (numbers(r, key)[0] / exact - 1.0).abs();
        let length = (numbers(r, "contact_length")[0] - 2.0 * a).abs();
        if method == "mdr" {
            // the MDR punch is exact: rate and depth to round-off [0], p0 [0], length [0]
            for (key, exact) in [("depth", rate * t), ("velocity", rate)] {
                assert!(rel(key, exact) < 1e-12, "{key}");
            }
            assert!(rel("central_pressure", p0) < 1e-12);
            assert!(rel("stiffness_length", 2.0 * a) < 1e-12);
            assert!(length < 1e-12);
        } else {
            // BEM, first order in dx / a at the punch's singular edge: rate and depth
            // [0.12 dx / a], p0 [0.24 dx / a], 2 sqrt(A / pi) [0.03 dx]
            let h = dx / a;
            for (key, exact) in [("depth", rate * t), ("velocity", rate)] {
                assert!(rel(key, exact) < 0.5 * h, "{key}: {}", rel(key, exact));
            }
            assert!(rel("central_pressure", p0) < 1.0 * h);
            assert!(rel("stiffness_length", 2.0 * a) < 0.5 * h);
            assert!(length < 0.25 * dx, "{length}");
        }
    }
}

/// A paraboloid h = c r^2 (R = 1 / 2c) under a constant force on a viscous half-space
/// (Lee–Radok): d^(3/2) = 3 F t / (16 eta sqrt(R)), a = sqrt(R d), and the stiffness length
/// F / (4 eta dd/dt) equals 2a. Rows whose contact leaves the inscribed circle of the square
/// footprint have no closed form and are skipped.
#[test]
fn quick_paper_paraboloids_follow_lee_radok() {
    let doc = run_json(&["paper", "--quick", "--json"]);
    let mut checked = 0;
    for entry in doc.as_array().unwrap().iter().skip(2) {
        let c = entry["input"]["indenter"]["c"].as_f64().unwrap();
        let half_edge = entry["input"]["indenter"]["edge"].as_f64().unwrap() / 2.0;
        let r = &entry["result"];
        let bem = r["method"].as_str().unwrap() == "bem";
        let dx = r["dx"].as_f64().unwrap();
        let radius = 1.0 / (2.0 * c);
        let (depth, length, stiffness) = (
            numbers(r, "depth"),
            numbers(r, "contact_length"),
            numbers(r, "stiffness_length"),
        );
        for (i, t) in numbers(r, "t").into_iter().enumerate() {
            let d = (3.0 * FORCE * t / (16.0 * ETA * radius.sqrt())).powf(2.0 / 3.0);
            let a = (radius * d).sqrt();
            if a > half_edge {
                continue;
            }
            checked += 1;
            // depth, second order in dx / a: BEM [0.062 (dx/a)^2], MDR [0.16 (dx/a)^2]
            let depth_bound = if bem { 0.2 } else { 0.5 } * (dx / a).powi(2);
            assert!(
                (depth[i] / d - 1.0).abs() < depth_bound,
                "c = {c}, t = {t}: depth {} against {d}",
                depth[i]
            );
            // lengths within one element: BEM's 2 sqrt(A / pi) [0.52 dx], its stiffness length
            // [0.39 dx]; MDR's edge sits on an element centre, each end within dx / 2 [0.99 dx]
            for (name, value) in [("contact", length[i]), ("stiffness", stiffness[i])] {
                assert!(
                    (value - 2.0 * a).abs() <= dx,
                    "c = {c}, t = {t}: {name} length {value} against {}",
                    2.0 * a
                );
            }
        }
    }
    // every row of both methods but c = 0.05 at t >= 2 s and c = 0.2 at t = 5 s, whose
    // contact outgrows the inscribed circle
    assert_eq!(checked, 2 * (25 - 5));
}

/// Ting's solution for a paraboloid pushed in at speed v until t_m and withdrawn at v on a
/// standard linear solid G(t) = G_inf + G1 exp(-t / tau), incompressible (E* = 4 G).
struct Ting {
    g_inf: f64,
    g1: f64,
    tau: f64,
    radius: f64,
    v: f64,
    t_m: f64,
}

impl Ting {
    fn modulus(&self, t: f64) -> f64 {
        self.g_inf + self.g1 * (-t / self.tau).exp()
    }

    /// The integral of G(t - s) ds over s in [lo, hi].
    fn modulus_integral(&self, t: f64, lo: f64, hi: f64) -> f64 {
        self.g_inf * (hi - lo)
            + self.g1 * self.tau * ((-(t - hi) / self.tau).exp() - (-(t - lo) / self.tau).exp())
    }

    /// The time t1 <= t_m of the loading branch whose contact radius the shrinking contact
    /// has at t: the root of int_t1^t G(t - s) dd/ds ds = 0 (None after separation).
    fn matching_time(&self, t: f64) -> Option<f64> {
        if t <= self.t_m {
            return Some(t);
        }
        let balance = |t1: f64| {
            self.modulus_integral(t, t1, self.t_m) - self.modulus_integral(t, self.t_m, t)
        };
        if balance(0.0) <= 0.0 {
            return None;
        }
        let (mut lo, mut hi) = (0.0, self.t_m);
        for _ in 0..200 {
            let mid = 0.5 * (lo + hi);
            if balance(mid) > 0.0 {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        Some(0.5 * (lo + hi))
    }

    /// Force (N) and contact radius (m) at t: F = 16/3 sqrt(R) int_0^t1 G(t - s) d/ds d^(3/2)
    /// ds, by Simpson's rule in u = sqrt(s), where the integrand is smooth.
    fn force_and_radius(&self, t: f64) -> (f64, f64) {
        let Some(t1) = self.matching_time(t) else {
            return (0.0, 0.0);
        };
        let intervals = 4000;
        let top = t1.sqrt();
        let h = top / intervals as f64;
        let f = |u: f64| self.modulus(t - u * u) * u * u;
        let mut sum = f(0.0) + f(top);
        for k in 1..intervals {
            sum += f(k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        let integral = sum * h / 3.0;
        // d/ds (v s)^(3/2) ds = 3/2 v^(3/2) sqrt(s) ds = 3 v^(3/2) u^2 du
        let force = 16.0 * self.radius.sqrt() * self.v.powf(1.5) * integral;
        (force, (self.radius * self.v * t1).sqrt())
    }
}

#[test]
fn standard_solid_unloading_example_follows_ting() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/examples/standard_solid_unloading.toml"
    );
    let doc = run_json(&["run", path, "--json"]);
    let r = &doc[0]["result"];
    let ting = Ting {
        g_inf: 1.0,
        g1: 3.0,
        tau: 0.5,
        radius: 0.5,
        v: 0.2,
        t_m: 1.0,
    };
    let dx = r["dx"].as_f64().unwrap();
    let (force, length) = (numbers(r, "force"), numbers(r, "contact_length"));
    let exact: Vec<(f64, f64)> = numbers(r, "t")
        .into_iter()
        .map(|t| ting.force_and_radius(t))
        .collect();
    let peak = exact.iter().map(|e| e.0).fold(0.0, f64::max);
    let mut separated = 0;
    for (i, &(f, a)) in exact.iter().enumerate() {
        // MDR n = 8001: force [3.9e-6 of the peak], radius on an element centre [0.39 dx]
        assert!(
            (force[i] - f).abs() < 2e-5 * peak,
            "{i}: {} against {f}",
            force[i]
        );
        assert!((length[i] / 2.0 - a).abs() <= 0.5 * dx, "{i}");
        if f == 0.0 {
            separated += 1;
            assert_eq!(force[i], 0.0);
        }
    }
    // separation at 1.5095 s: the outputs at 1.75, 2, 2.5 and 3 s are out of contact
    assert_eq!(separated, 4);
}
