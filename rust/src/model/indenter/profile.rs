//! A tabulated axisymmetric profile h = f(r): a measured tip, or a profile sampled from a
//! function only the caller can evaluate. Between samples f is the cubic Hermite
//! interpolant of the given slopes (or piecewise linear without slopes); its MDR profile
//! g(x) = x * integral_0^x f'(r) / sqrt(x^2 - r^2) dr is integrated exactly for that
//! interpolant at the sample radii and interpolated in between.

use crate::support::error::{check_finite, check_positive, Error, Result};
use serde::{Deserialize, Serialize};

/// A tabulated profile as written in scene files: radii r (m) from 0, increasing; heights
/// h (m) above the tip, h(0) = 0, h >= 0; optional slopes dh/dr (dimensionless).
#[derive(Debug, Clone, PartialEq, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ProfileTable {
    /// Sample radii (m), starting at 0 and strictly increasing.
    pub r: Vec<f64>,
    /// Heights above the tip (m) at the sample radii.
    pub h: Vec<f64>,
    /// Slopes dh/dr at the sample radii; absent: piecewise linear between samples.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope: Option<Vec<f64>>,
    /// Side of a centred square footprint (m).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub edge: Option<f64>,
    /// Radius of a disc footprint (m); neither: unbounded up to the last sample.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius: Option<f64>,
}

/// A validated tabulated profile with its MDR profile at the sample radii.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    table: ProfileTable,
    /// g at the sample radii (m).
    g: Vec<f64>,
    /// dg/dx at the sample radii, for the Hermite interpolation of g.
    dg: Vec<f64>,
}

impl TryFrom<ProfileTable> for Profile {
    type Error = Error;

    fn try_from(table: ProfileTable) -> Result<Self> {
        let (r, h) = (&table.r, &table.h);
        if r.len() < 2 {
            return Err(Error::InvalidInput(format!(
                "profile: needs at least 2 samples, got {}",
                r.len()
            )));
        }
        if h.len() != r.len() {
            return Err(Error::InvalidInput(format!(
                "profile: r has {} samples but h has {}",
                r.len(),
                h.len()
            )));
        }
        check_finite("profile r", r)?;
        check_finite("profile h", h)?;
        if r[0] != 0.0 || r.windows(2).any(|w| w[1] <= w[0]) {
            return Err(Error::InvalidInput(
                "profile: r must start at 0 and strictly increase".into(),
            ));
        }
        let scale = h.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
        if h[0].abs() > 1e-12 * scale {
            return Err(Error::InvalidInput(format!(
                "profile: h(0) must be 0 (the tip is the origin), got {}",
                h[0]
            )));
        }
        if let Some(v) = h.iter().find(|&&v| v < -1e-12 * scale) {
            return Err(Error::InvalidInput(format!(
                "profile: heights must be >= 0 (above the tip), got {v}"
            )));
        }
        if let Some(s) = &table.slope {
            if s.len() != r.len() {
                return Err(Error::InvalidInput(format!(
                    "profile: r has {} samples but slope has {}",
                    r.len(),
                    s.len()
                )));
            }
            check_finite("profile slope", s)?;
        }
        match (table.edge, table.radius) {
            (Some(_), Some(_)) => {
                return Err(Error::InvalidInput(
                    "profile: give edge or radius, not both".into(),
                ))
            }
            (Some(v), None) => check_positive("profile edge", v)?,
            (None, Some(v)) => check_positive("profile radius", v)?,
            (None, None) => {}
        }
        let g: Vec<f64> = r.iter().map(|&x| mdr_integral(&table, x)).collect();
        let dg = hermite_slopes(r, &g);
        Ok(Profile { table, g, dg })
    }
}

impl From<Profile> for ProfileTable {
    fn from(p: Profile) -> Self {
        p.table
    }
}

/// Index k of the interval [r_k, r_{k+1}] holding `x` (clamped to the table).
fn interval(r: &[f64], x: f64) -> usize {
    r.partition_point(|&v| v <= x).clamp(1, r.len() - 1) - 1
}

/// Coefficients (b0, b1, b2) of f'(r_k + t) = b0 + b1 t + b2 t^2 on interval k.
fn slope_poly(table: &ProfileTable, k: usize) -> (f64, f64, f64) {
    let (r, h) = (&table.r, &table.h);
    let w = r[k + 1] - r[k];
    let secant = (h[k + 1] - h[k]) / w;
    match &table.slope {
        None => (secant, 0.0, 0.0),
        Some(s) => {
            // Cubic Hermite: f = h0 + s0 t + c2 t^2 + c3 t^3 on [0, w].
            let c2 = (3.0 * secant - 2.0 * s[k] - s[k + 1]) / w;
            let c3 = (s[k] + s[k + 1] - 2.0 * secant) / (w * w);
            (s[k], 2.0 * c2, 3.0 * c3)
        }
    }
}

/// Height (m) of the interpolant at radius `x` (m) inside the table.
fn height_at(table: &ProfileTable, x: f64) -> f64 {
    let (r, h) = (&table.r, &table.h);
    let k = interval(r, x);
    let t = x - r[k];
    let (b0, b1, b2) = slope_poly(table, k);
    (h[k] + t * (b0 + t * (0.5 * b1 + t * b2 / 3.0))).max(0.0)
}

/// g(x) = x * integral_0^x f'(r) / sqrt(x^2 - r^2) dr for the interpolant, exactly: with
/// f'(r) = a0 + a1 r + a2 r^2 on each interval, the antiderivatives are asin(r/x),
/// -sqrt(x^2 - r^2) and (x^2 asin(r/x) - r sqrt(x^2 - r^2)) / 2.
fn mdr_integral(table: &ProfileTable, x: f64) -> f64 {
    if x <= 0.0 {
        return 0.0;
    }
    let r = &table.r;
    let anti = |a: (f64, f64, f64), v: f64| {
        let v = v.min(x);
        let th = (v / x).clamp(-1.0, 1.0).asin();
        let root = ((x - v) * (x + v)).max(0.0).sqrt();
        a.0 * th - a.1 * root + a.2 * 0.5 * (x * x * th - v * root)
    };
    let mut total = 0.0;
    for k in 0..r.len() - 1 {
        if r[k] >= x {
            break;
        }
        let (b0, b1, b2) = slope_poly(table, k);
        let rk = r[k];
        let a = (b0 - b1 * rk + b2 * rk * rk, b1 - 2.0 * b2 * rk, b2);
        total += anti(a, r[k + 1]) - anti(a, rk);
    }
    x * total
}

/// Derivatives of the samples (x_k, y_k) by the three-point formula on uneven spacing
/// (one-sided at the ends), for a C1 cubic Hermite interpolant.
fn hermite_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    if n == 2 {
        let s = (y[1] - y[0]) / (x[1] - x[0]);
        return vec![s, s];
    }
    (0..n)
        .map(|k| {
            let (i, j, l) = match k {
                0 => (0, 1, 2),
                k if k == n - 1 => (n - 3, n - 2, n - 1),
                k => (k - 1, k, k + 1),
            };
            // derivative at x_k of the parabola through points i, j, l
            let (xi, xj, xl) = (x[i], x[j], x[l]);
            let xk = x[k];
            y[i] * (2.0 * xk - xj - xl) / ((xi - xj) * (xi - xl))
                + y[j] * (2.0 * xk - xi - xl) / ((xj - xi) * (xj - xl))
                + y[l] * (2.0 * xk - xi - xj) / ((xl - xi) * (xl - xj))
        })
        .collect()
}

impl Profile {
    /// The table as given.
    pub fn table(&self) -> &ProfileTable {
        &self.table
    }

    /// Largest tabulated radius (m).
    pub fn extent(&self) -> f64 {
        *self.table.r.last().expect("validated: at least 2 samples")
    }

    /// Height (m) at radius `r` (m); an error beyond the table.
    pub fn height(&self, r: f64) -> Result<f64> {
        self.check_extent(r)?;
        Ok(height_at(&self.table, r))
    }

    /// MDR profile g (m) at |x| (m); an error beyond the table.
    pub fn profile_1d(&self, x: f64) -> Result<f64> {
        let x = x.abs();
        self.check_extent(x)?;
        let r = &self.table.r;
        let k = interval(r, x);
        let w = r[k + 1] - r[k];
        let t = (x - r[k]) / w;
        let (h00, h10) = (
            (1.0 + 2.0 * t) * (1.0 - t) * (1.0 - t),
            t * (1.0 - t) * (1.0 - t),
        );
        let (h01, h11) = (t * t * (3.0 - 2.0 * t), t * t * (t - 1.0));
        let g =
            h00 * self.g[k] + h10 * w * self.dg[k] + h01 * self.g[k + 1] + h11 * w * self.dg[k + 1];
        Ok(g.max(0.0))
    }

    fn check_extent(&self, r: f64) -> Result<()> {
        let extent = self.extent();
        if r > extent * (1.0 + 1e-12) {
            Err(Error::Domain(format!(
                "the tabulated profile ends at r = {extent} m, but r = {r} m is needed: tabulate it further"
            )))
        } else {
            Ok(())
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(f: impl Fn(f64) -> f64, df: Option<&dyn Fn(f64) -> f64>, n: usize) -> Profile {
        let r: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
        Profile::try_from(ProfileTable {
            h: r.iter().map(|&x| f(x)).collect(),
            slope: df.map(|d| r.iter().map(|&x| d(x)).collect()),
            r,
            edge: None,
            radius: None,
        })
        .unwrap()
    }

    /// A paraboloid is exactly cubic: its tabulated MDR profile is 2 c x^2 to round-off.
    #[test]
    fn paraboloid_table_is_exact() {
        let p = table(|r| 3.0 * r * r, Some(&|r| 6.0 * r), 11);
        for x in [0.0, 0.013, 0.25, 0.5, 0.77, 1.0] {
            assert!(
                (p.profile_1d(x).unwrap() - 6.0 * x * x).abs() < 1e-12,
                "x = {x}"
            );
            assert!((p.height(x).unwrap() - 3.0 * x * x).abs() < 1e-14);
        }
    }

    /// A cone is exactly piecewise linear: without slopes its MDR profile is (pi/2) s |x|.
    #[test]
    fn cone_table_is_exact() {
        let p = table(|r| 0.4 * r, None, 5);
        for x in [0.1, 0.5, 0.99] {
            let exact = 0.5 * std::f64::consts::PI * 0.4 * x;
            assert!(
                (p.profile_1d(-x).unwrap() - exact).abs() < 1e-6 * exact,
                "x = {x}"
            );
        }
    }

    /// The sphere's MDR profile |x| artanh(|x|/R) from a table of its cap converges at
    /// fourth order in the sample spacing.
    #[test]
    fn sphere_table_converges() {
        let radius = 2.0;
        let cap = |r: f64| r * r / (radius + ((radius - r) * (radius + r)).sqrt());
        let dcap = |r: f64| r / ((radius - r) * (radius + r)).sqrt();
        let err = |n| {
            let p = table(cap, Some(&dcap), n);
            let x = 0.613;
            (p.profile_1d(x).unwrap() - x * (x / radius).atanh()).abs()
        };
        let (coarse, fine) = (err(21), err(41));
        assert!(fine < 1e-7 && coarse / fine > 6.0, "{coarse} {fine}");
    }

    #[test]
    fn bad_tables_are_refused() {
        let bad = |r: Vec<f64>, h: Vec<f64>| {
            Profile::try_from(ProfileTable {
                r,
                h,
                slope: None,
                edge: None,
                radius: None,
            })
            .unwrap_err()
        };
        assert!(matches!(bad(vec![0.0], vec![0.0]), Error::InvalidInput(_)));
        assert!(matches!(
            bad(vec![0.0, 0.0], vec![0.0, 1.0]),
            Error::InvalidInput(_)
        ));
        assert!(matches!(
            bad(vec![0.0, 1.0], vec![0.5, 1.0]),
            Error::InvalidInput(_)
        ));
        assert!(matches!(
            bad(vec![0.0, 1.0], vec![0.0, -1.0]),
            Error::InvalidInput(_)
        ));
        let p = table(|r| r, None, 3);
        assert!(matches!(p.profile_1d(1.5), Err(Error::Domain(_))));
    }
}
