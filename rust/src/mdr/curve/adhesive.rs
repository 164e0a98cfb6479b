//! An adhesive curve: JKR contact of an elastic body by MDR with a contact edge that moves
//! continuously between the elements, the forward model of fits to approach and retract
//! curves whose retract dips below the baseline.
//!
//! The half profile is the piecewise-linear g(x) through (0, g_0) and the elements' heights
//! at x_i = (i + 1/2) dx, rising away from the axis. The state is the contact radius a, and
//! the force of the elastic foundation attached over |x| < a at depth d is
//! F = 2 E* (a d - integral_0^a g dx). Heß's rule in the continuum: the edge recedes while its
//! elongation g(a) - d exceeds sqrt(2 pi a w / E*), to the outermost radius where it no longer
//! does (the JKR equilibrium of the edge); none left is the pull-off. How the edge advances is
//! the `Approach`: where the indenter reaches the surface (`Touch`, g(a) = d: the contact grows
//! as a hard one, Hertz on a paraboloid's approach, and is held at its largest radius on the
//! retract until the edge's elongation reaches the limit), or, once the indenter touches the
//! axis, to the outermost radius of the JKR equilibrium (`Equilibrium`: the contact jumps in at
//! the touch and loads and unloads on the JKR branch, the limit of a cohesive zone of vanishing
//! range). Under a spring (an AFM cantilever) the depth balances it: k (u - d) = F(a, d).
//!
//! Between samples the prescribed depth or drive varies linearly, and the edge's position
//! after a monotone stretch depends on its end only, so the curve is settled at the samples:
//! no time steps, no element loop, a few microseconds per sample. The force is continuous in
//! the parameters, except at a pull-off, so finite differences give its derivatives.

use super::{Control, Curve};
use crate::model::medium::rheology::Rheology;
use crate::support::error::{check_finite, check_positive, Error, Result};
use std::f64::consts::PI;

/// An adhesive curve's computed quantity at the sample times.
#[derive(Debug, Clone, PartialEq)]
pub struct AdhesiveEvaluation {
    /// Force (N) at each sample time (depth and spring control).
    pub values: Vec<f64>,
    /// Contact radius (m) at each sample time: 0 out of contact.
    pub contact_radius: Vec<f64>,
    /// Depth (m) at each sample time (the prescribed one under depth control).
    pub depth: Vec<f64>,
    /// Elements of the half profile in contact (centres within the contact radius) at each
    /// sample time: their number when the contact reaches the profile's end.
    pub contact: Vec<usize>,
}

/// The half profile as a piecewise-linear function of x, with its running integral.
struct Profile {
    /// Knots: x = 0, then the element centres.
    x: Vec<f64>,
    /// g at the knots (m).
    g: Vec<f64>,
    /// integral_0^x g at the knots (m^2).
    integral: Vec<f64>,
}

impl Profile {
    fn new(g: &[f64], dx: f64) -> Result<Self> {
        if let Some(i) = g.windows(2).position(|w| w[1] < w[0]) {
            return Err(Error::InvalidInput(format!(
                "an adhesive curve needs a profile that rises away from its axis: g falls from {} to {} at element {}",
                g[i],
                g[i + 1],
                i + 1
            )));
        }
        let mut x = vec![0.0];
        x.extend((0..g.len()).map(|i| (i as f64 + 0.5) * dx));
        let mut knots = vec![g[0]];
        knots.extend_from_slice(g);
        let mut integral = vec![0.0];
        for j in 1..x.len() {
            let area = 0.5 * (x[j] - x[j - 1]) * (knots[j] + knots[j - 1]);
            integral.push(integral[j - 1] + area);
        }
        Ok(Profile {
            x,
            g: knots,
            integral,
        })
    }

    /// The profile's end (m): the outermost element centre.
    fn reach(&self) -> f64 {
        *self.x.last().unwrap_or(&0.0)
    }

    /// The cell [x_j, x_{j+1}] holding x (the last cell beyond the end).
    fn cell(&self, x: f64) -> usize {
        let j = self.x.partition_point(|&k| k <= x);
        j.saturating_sub(1).min(self.x.len() - 2)
    }

    /// g (m) and integral_0^x g (m^2) at x (m).
    fn at(&self, x: f64) -> (f64, f64) {
        let j = self.cell(x);
        let s = (x - self.x[j]) / (self.x[j + 1] - self.x[j]);
        let g = self.g[j] + s * (self.g[j + 1] - self.g[j]);
        (
            g,
            self.integral[j] + 0.5 * (x - self.x[j]) * (self.g[j] + g),
        )
    }
}

/// The largest x in [lo, hi] where `f` changes sign, f(lo) and f(hi) of opposite signs
/// (bisection to round-off: f is continuous and piecewise smooth).
fn bisect(f: impl Fn(f64) -> f64, mut lo: f64, mut hi: f64) -> f64 {
    let f_lo = f(lo);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if (f(mid) > 0.0) == (f_lo > 0.0) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The radius in `span` (within cell `j`) where g(x) - d - sqrt(crack x) turns positive,
/// `f` that function: in closed form under a prescribed depth (with g linear in the cell it
/// is a quadratic in sqrt(x)), by bisection under a spring.
fn root(
    profile: &Profile,
    drive: Drive,
    crack: f64,
    j: usize,
    span: (f64, f64),
    f: impl Fn(f64) -> f64,
) -> f64 {
    let (lo, hi) = span;
    let Drive::Depth(d) = drive else {
        return bisect(f, lo, hi);
    };
    let slope = (profile.g[j + 1] - profile.g[j]) / (profile.x[j + 1] - profile.x[j]);
    // slope s^2 - sqrt(crack) s + q = 0 in s = sqrt(x), its larger root (where the convex
    // quadratic turns positive)
    let q = profile.g[j] - slope * profile.x[j] - d;
    let b = crack.sqrt();
    let s = if slope > 0.0 {
        let disc = (crack - 4.0 * slope * q).max(0.0).sqrt();
        if b + disc > 0.0 {
            (b + disc) / (2.0 * slope)
        } else {
            0.0
        }
    } else if b > 0.0 {
        q / b
    } else {
        return bisect(f, lo, hi);
    };
    (s * s).clamp(lo, hi)
}

/// The drive of one sample: a prescribed depth, or a drive through a spring.
#[derive(Clone, Copy)]
enum Drive {
    Depth(f64),
    /// Drive u (m), spring stiffness over the contact modulus times 2 (m), and an
    /// attraction over the same (m^2; DMT's while the surfaces touch).
    Spring {
        u: f64,
        kappa: f64,
        pull: f64,
    },
}

impl Drive {
    /// The depth (m) at contact radius a (m): the prescribed one, or the one balancing the
    /// spring, kappa (u - d) = a d - integral_0^a g - pull.
    fn depth(self, a: f64, integral: f64) -> f64 {
        match self {
            Drive::Depth(d) => d,
            Drive::Spring { u, kappa, pull } => (kappa * u + integral + pull) / (kappa + a),
        }
    }

    /// The prescribed depth or drive (m).
    fn value(self) -> f64 {
        match self {
            Drive::Depth(d) => d,
            Drive::Spring { u, .. } => u,
        }
    }
}

/// How a JKR contact's edge advances on an approach.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Approach {
    /// Where the indenter reaches the surface: the contact grows as a hard one.
    Touch,
    /// To the JKR equilibrium (the outermost radius whose elongation is within the limit),
    /// once the indenter touches the axis: a jump in at the touch.
    Equilibrium,
}

/// The contact radius (m) after `drive` from radius `a` (m) on `profile`, with `crack` the
/// detachment elongation's square over the radius (2 pi w / E*, m) and the edge advancing by
/// `approach`.
fn settle(profile: &Profile, a: f64, drive: Drive, crack: f64, approach: Approach) -> f64 {
    // g - d at x: < 0 where the indenter has reached the surface
    let gap = |x: f64| {
        let (g, int) = profile.at(x);
        g - drive.depth(x, int)
    };
    // elongation beyond the edge's limit: > 0 where the edge lets go
    let over = |x: f64| gap(x) - (crack * x).sqrt();
    let mut a = a;
    if a > 0.0 && over(a) > 0.0 {
        // recede to the outermost radius below a where the edge holds
        let j = profile.cell(a);
        let inner = (0..=j)
            .rev()
            .find(|&i| profile.x[i] < a && over(profile.x[i]) <= 0.0);
        a = match inner {
            Some(i) => {
                let hi = a.min(profile.x[i + 1]);
                if over(hi) <= 0.0 {
                    hi
                } else {
                    root(profile, drive, crack, i, (profile.x[i], hi), over)
                }
            }
            None => 0.0,
        };
    }
    // advance to where the indenter meets the surface, or to the equilibrium radius (the
    // profile's end at most)
    let limit = match approach {
        Approach::Touch => 0.0,
        Approach::Equilibrium => crack,
    };
    let reached = |x: f64| gap(x) - (limit * x).sqrt();
    if gap(a) < 0.0 || (a > 0.0 && reached(a) < 0.0) {
        let end = profile.reach();
        let j = profile.cell(a);
        let outer = (j + 1..profile.x.len()).find(|&i| reached(profile.x[i]) >= 0.0);
        a = match outer {
            Some(i) => root(
                profile,
                drive,
                limit,
                i - 1,
                (a.max(profile.x[i - 1]), profile.x[i]),
                reached,
            ),
            None => end,
        };
    }
    a
}

/// An adhesive law of the curve.
#[derive(Clone, Copy)]
enum Law {
    /// JKR: the detachment elongation's square over the radius, 2 pi w / E* (m), and how
    /// the edge advances.
    Jkr { crack: f64, approach: Approach },
    /// DMT: the attraction while the surfaces touch (N).
    Dmt { attraction: f64 },
}

impl Curve {
    /// The force (N) at the sample times of a depth- or spring-controlled curve on an
    /// elastic body of contact modulus `e_star` (Pa) in JKR contact of work of adhesion `w`
    /// (J/m^2), its edge advancing by `approach`, with `shift` (m) added to every prescribed
    /// depth or drive; also the contact radius and the depth. The curve starts at rest out of
    /// contact. A contact that reaches the profile's end stays there (its radius then equals
    /// the outermost element centre).
    pub fn evaluate_jkr(
        &self,
        e_star: f64,
        w: f64,
        shift: f64,
        approach: Approach,
    ) -> Result<AdhesiveEvaluation> {
        check_positive("contact modulus E*", e_star)?;
        check_positive("work of adhesion", w)?;
        let crack = 2.0 * PI * w / e_star;
        self.evaluate_adhesive(e_star, Law::Jkr { crack, approach }, shift)
    }

    /// `evaluate_jkr` for DMT: the hard contact plus the `attraction` (N, 2 pi w R) while the
    /// surfaces touch. The contact forms when the indenter reaches the surface (under a
    /// spring it then jumps in) and lets go when the balance finds no depth that touches.
    pub fn evaluate_dmt(
        &self,
        e_star: f64,
        attraction: f64,
        shift: f64,
    ) -> Result<AdhesiveEvaluation> {
        check_positive("contact modulus E*", e_star)?;
        check_positive("attraction", attraction)?;
        self.evaluate_adhesive(e_star, Law::Dmt { attraction }, shift)
    }

    /// `evaluate_jkr` (touch approach, depth control) on a viscoelastic body of relaxation
    /// modulus `medium` (shear; the contact modulus is 4 G(t)) with a relaxed modulus: the
    /// edge lets go by Heß's rule with the relaxed contact modulus E*_inf, an elongation of the
    /// edge that is geometric (g(a) - d), so the radius follows the elastic curve of E*_inf;
    /// an element attached at t_x (when the indenter reached it) then carries
    /// E*_inf (d - g) + sum_k E*_k integral_{t_x}^t exp(-(t - s) / tau_k) dd/ds ds, and the
    /// force is twice the integral of that over 0 < x < a. The depth is linear between samples,
    /// which the hereditary integrals take exactly; the curve must be one approach and one
    /// retract (the radius rises, then falls).
    pub fn evaluate_jkr_viscoelastic(
        &self,
        medium: &Rheology,
        w: f64,
        shift: f64,
    ) -> Result<AdhesiveEvaluation> {
        if medium.eta != 0.0 {
            return Err(Error::InvalidInput(
                "a viscoelastic adhesive curve takes a medium without a dashpot in parallel".into(),
            ));
        }
        if !matches!(self.control, Control::Depth) {
            return Err(Error::InvalidInput(
                "a viscoelastic adhesive curve is depth-controlled".into(),
            ));
        }
        let e_inf = 4.0 * medium.g_inf;
        check_positive("relaxed contact modulus E*_inf", e_inf)?;
        let mut out = self.evaluate_jkr(e_inf, w, shift, Approach::Touch)?;
        let a = &out.contact_radius;
        let top = (0..a.len()).fold(0, |m, i| if a[i] > a[m] { i } else { m });
        if a[..=top].windows(2).any(|p| p[1] < p[0]) || a[top..].windows(2).any(|p| p[1] > p[0]) {
            return Err(Error::InvalidInput(
                "a viscoelastic adhesive curve is one approach and one retract: its contact radius must rise and then fall"
                    .into(),
            ));
        }
        let profile = Profile::new(&self.g, self.dx)?;
        let t = &self.times;
        let d = &out.depth;
        // h_k(t_i) = integral_{t_0}^{t_i} exp(-(t_i - s) / tau_k) dd/ds ds, the depth linear
        // between samples
        let ramp = |tau: f64, h: f64, dt: f64, slope: f64| {
            let decay = (-dt / tau).exp();
            decay * h + slope * tau * (1.0 - decay)
        };
        let h: Vec<Vec<f64>> = medium
            .terms
            .iter()
            .map(|&(_, tau)| {
                let mut row = vec![0.0; t.len()];
                for i in 1..t.len() {
                    let dt = t[i] - t[i - 1];
                    let slope = if dt > 0.0 {
                        (d[i] - d[i - 1]) / dt
                    } else {
                        0.0
                    };
                    row[i] = ramp(tau, row[i - 1], dt, slope);
                }
                row
            })
            .collect();
        // the attachment of the point x of the half profile: its time and h_k there (the first
        // sample reaching it, the depth interpolated to where it meets g(x))
        let attach = |x: f64| -> (f64, Vec<f64>) {
            let j = a[..=top].partition_point(|&r| r < x).min(top);
            if j == 0 {
                return (t[0], vec![0.0; medium.terms.len()]);
            }
            let gx = profile.at(x).0;
            let dt = t[j] - t[j - 1];
            let rise = d[j] - d[j - 1];
            let s = if rise > 0.0 {
                ((gx - d[j - 1]) / rise).clamp(0.0, 1.0)
            } else {
                1.0
            };
            let slope = if dt > 0.0 { rise / dt } else { 0.0 };
            let hk = medium
                .terms
                .iter()
                .zip(&h)
                .map(|(&(_, tau), row)| ramp(tau, row[j - 1], s * dt, slope))
                .collect();
            (t[j - 1] + s * dt, hk)
        };
        // attachments of the elements' midpoints, and of the covered part of a partial one
        let attached: Vec<(f64, Vec<f64>)> = (0..)
            .map(|m| (m as f64 + 0.5) * self.dx)
            .take_while(|&x| x - 0.5 * self.dx < a[top])
            .map(attach)
            .collect();
        for i in 0..t.len() {
            let ai = a[i];
            if ai <= 0.0 {
                continue;
            }
            let mut viscous = 0.0;
            for (k, &(g_k, tau)) in medium.terms.iter().enumerate() {
                let mut integral = 0.0;
                for (m, (tx, hx)) in attached.iter().enumerate() {
                    let lo = m as f64 * self.dx;
                    if lo >= ai {
                        break;
                    }
                    let width = (ai - lo).min(self.dx);
                    let (tx, hxk) = if width < self.dx {
                        let (tp, hp) = attach(lo + 0.5 * width);
                        (tp, hp[k])
                    } else {
                        (*tx, hx[k])
                    };
                    integral += width * (h[k][i] - (-(t[i] - tx) / tau).exp() * hxk);
                }
                viscous += 4.0 * g_k * integral;
            }
            out.values[i] += 2.0 * viscous;
        }
        Ok(out)
    }

    fn evaluate_adhesive(&self, e_star: f64, law: Law, shift: f64) -> Result<AdhesiveEvaluation> {
        check_finite("depth shift", &[shift])?;
        let profile = Profile::new(&self.g, self.dx)?;
        let (crack, attraction) = match law {
            Law::Jkr { crack, .. } => (crack, 0.0),
            Law::Dmt { attraction } => (0.0, attraction),
        };
        let k = self.values.len();
        let mut out = AdhesiveEvaluation {
            values: Vec::with_capacity(k),
            contact_radius: Vec::with_capacity(k),
            depth: Vec::with_capacity(k),
            contact: Vec::with_capacity(k),
        };
        let mut a = 0.0;
        let mut touching = false;
        for &v in &self.values {
            let drive = match self.control {
                Control::Depth => Drive::Depth(v + shift),
                Control::Spring(stiffness) => Drive::Spring {
                    u: v + shift,
                    kappa: stiffness / (2.0 * e_star),
                    pull: attraction / (2.0 * e_star),
                },
                Control::Force => {
                    return Err(Error::InvalidInput(
                        "an adhesive curve is depth- or spring-controlled".into(),
                    ))
                }
            };
            match law {
                Law::Jkr { approach, .. } => {
                    // the contact forms where the indenter reaches the axis
                    if a > 0.0 || drive.value() >= profile.g[0] {
                        a = settle(&profile, a, drive, crack, approach);
                    }
                }
                Law::Dmt { .. } => {
                    // the surfaces touch once the indenter reaches them; through a spring
                    // they stay in touch while the balance has a depth that reaches them
                    let reaches = drive.value() > profile.g[0];
                    touching = reaches || (touching && matches!(drive, Drive::Spring { .. }));
                    a = if touching {
                        settle(&profile, a, drive, 0.0, Approach::Touch)
                    } else {
                        0.0
                    };
                    touching &= a > 0.0;
                }
            }
            let (force, depth) = if a > 0.0 {
                let integral = profile.at(a).1;
                let d = drive.depth(a, integral);
                (2.0 * e_star * (a * d - integral) - attraction, d)
            } else {
                (0.0, drive.value())
            };
            out.values.push(force);
            out.contact_radius.push(a);
            out.depth.push(depth);
            out.contact
                .push(profile.x[1..].partition_point(|&x| x <= a));
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A drive (m) over `k_samples` samples: from `start` up to `top` over the first half,
    /// then down at `down` times the approach's rate of a drive from 0.
    fn drive(k_samples: usize, start: f64, top: f64, down: f64) -> Vec<f64> {
        (0..k_samples)
            .map(|i| {
                let s = i as f64 / (k_samples - 1) as f64;
                if s < 0.5 {
                    start + 2.0 * s * (top - start)
                } else {
                    top - 2.0 * (s - 0.5) * down * top
                }
            })
            .collect()
    }

    /// A paraboloid g = x^2 / R, sampled finely.
    fn paraboloid(
        n: usize,
        half: f64,
        r: f64,
        times: Vec<f64>,
        values: Vec<f64>,
        control: Control,
    ) -> Curve {
        let dx = half / n as f64;
        let g = (0..n)
            .map(|i| {
                let x = (i as f64 + 0.5) * dx;
                x * x / r
            })
            .collect();
        Curve::new(g, dx, times, values, control, 1).unwrap()
    }

    /// Depth control: Hertz on the approach, the contact pinned at its largest radius, then
    /// the JKR branch d = a^2 / R - sqrt(2 pi w a / E*), F = 4 E* a^3 / (3 R) - sqrt(8 pi w
    /// E* a^3), down to its unstable end at -5/6 pi w R, then no force.
    #[test]
    fn a_paraboloid_under_depth_control_follows_jkr() {
        let (r, e, w) = (1.0, 1.0, 0.001);
        let d_max = 0.04;
        let k = 4001;
        let values: Vec<f64> = (0..k)
            .map(|i| {
                let s = i as f64 / (k - 1) as f64;
                if s < 0.5 {
                    2.0 * s * d_max
                } else {
                    d_max - 2.0 * (s - 0.5) * 1.6 * d_max
                }
            })
            .collect();
        let times = (1..=k).map(|i| i as f64).collect();
        let curve = paraboloid(20000, 0.3, r, times, values.clone(), Control::Depth);
        let out = curve.evaluate_jkr(e, w, 0.0, Approach::Touch).unwrap();
        let a_max = (r * d_max).sqrt();
        let d1 = a_max * a_max / r - (2.0 * PI * a_max * w / e).sqrt();
        let mut least = 0.0f64;
        for (i, (&d, &f)) in values.iter().zip(&out.values).enumerate() {
            let exact = if i <= k / 2 {
                4.0 / 3.0 * e * r.sqrt() * d.max(0.0).powf(1.5)
            } else if d >= d1 {
                2.0 * e * (a_max * d - a_max.powi(3) / (3.0 * r))
            } else {
                f
            };
            assert!(
                (f - exact).abs() < 1e-6 * e * d_max.powf(1.5),
                "{i}: {f} vs {exact}"
            );
            if i > k / 2 && d < d1 && f != 0.0 {
                // on the JKR branch: the force of the radius
                let a = out.contact_radius[i];
                let branch =
                    4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a.powi(3)).sqrt();
                assert!(
                    (f - branch).abs() < 1e-6 * e * d_max.powf(1.5),
                    "{i}: {f} vs {branch}"
                );
                let depth = a * a / r - (2.0 * PI * w * a / e).sqrt();
                assert!((d - depth).abs() < 1e-6 * d_max, "{i}: {d} vs {depth}");
            }
            least = least.min(f);
        }
        // the branch's least force is force control's pull-off; it lets go at its
        // unstable end, a^(3/2) = (R / 4) sqrt(2 pi w / E*), at -5/6 pi w R
        assert!((least / (-1.5 * PI * w * r) - 1.0).abs() < 1e-4, "{least}");
        let a_end = ((r / 4.0) * (2.0 * PI * w / e).sqrt()).powf(2.0 / 3.0);
        let d_end = a_end * a_end / r - (2.0 * PI * w * a_end / e).sqrt();
        let f_end = 4.0 * e * a_end.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a_end.powi(3)).sqrt();
        assert!((f_end / (-5.0 / 6.0 * PI * w * r) - 1.0).abs() < 1e-12);
        for (i, (&d, &f)) in values.iter().zip(&out.values).enumerate().skip(k / 2) {
            let tol = 1e-4 * d_max;
            assert!(
                d > d_end - tol || f == 0.0,
                "{i}: in contact at {d} < {d_end}"
            );
            assert!(d < d_end + tol || f != 0.0, "{i}: let go at {d} > {d_end}");
        }
        assert_eq!(*out.values.last().unwrap(), 0.0);
    }

    /// Through a spring (an AFM cantilever) the force balances it at every sample, and the
    /// retract passes JKR's least force, -3/2 pi w R, before the contact lets go.
    #[test]
    fn a_spring_balances_the_contact_through_the_pull_off() {
        let (r, e, w) = (1.0, 1.0, 0.001);
        let k_samples = 4001;
        let (stiffness, u_max) = (1.0, 0.05);
        let values = drive(k_samples, 0.0, u_max, 8.0);
        let times = (1..=k_samples).map(|i| i as f64).collect();
        let curve = paraboloid(20000, 0.4, r, times, values, Control::Spring(stiffness));
        let out = curve.evaluate_jkr(e, w, 0.0, Approach::Touch).unwrap();
        for ((&f, &d), &u) in out.values.iter().zip(&out.depth).zip(&curve.values) {
            assert!((f - stiffness * (u - d)).abs() < 1e-12 * stiffness * u_max);
        }
        let least = out.values.iter().copied().fold(0.0, f64::min);
        assert!((least / (-1.5 * PI * w * r) - 1.0).abs() < 1e-4, "{least}");
        assert_eq!(*out.values.last().unwrap(), 0.0);
    }

    /// The equilibrium approach: the contact jumps in at the touch onto the JKR branch,
    /// d = a^2 / R - sqrt(2 pi w a / E*) with F = 4 E* a^3 / (3 R) - sqrt(8 pi w E* a^3),
    /// at radius (2 pi w R^2 / E*)^(1/3) at zero depth and (9 pi w R^2 / (2 E*))^(1/3) at zero
    /// load, and the retract retraces its stable part (a above the unstable end) to that end.
    #[test]
    fn the_equilibrium_approach_loads_and_unloads_on_the_jkr_branch() {
        let (r, e, w) = (1.0, 1.0, 0.001);
        let d_max = 0.04;
        let k = 4001;
        let values: Vec<f64> = (0..k)
            .map(|i| {
                let s = i as f64 / (k - 1) as f64;
                if s < 0.5 {
                    -0.01 + 2.0 * s * (d_max + 0.01)
                } else {
                    d_max - 2.0 * (s - 0.5) * 1.6 * d_max
                }
            })
            .collect();
        let times = (1..=k).map(|i| i as f64).collect();
        let curve = paraboloid(20000, 0.3, r, times, values.clone(), Control::Depth);
        let out = curve
            .evaluate_jkr(e, w, 0.0, Approach::Equilibrium)
            .unwrap();
        let scale = e * d_max.powf(1.5);
        let a_end = ((r / 4.0) * (2.0 * PI * w / e).sqrt()).powf(2.0 / 3.0);
        let d_end = a_end * a_end / r - (2.0 * PI * w * a_end / e).sqrt();
        for (i, (&d, &f)) in values.iter().zip(&out.values).enumerate() {
            let a = out.contact_radius[i];
            if i <= k / 2 {
                // out of contact before the touch (the profile's lowest knot), on the branch
                // after it
                assert_eq!(a > 0.0, d >= curve.g[0], "{i}: {d} {a}");
            } else if d < d_end - 1e-4 * d_max {
                assert_eq!(f, 0.0, "{i}: in contact at {d}");
            }
            if a > 0.0 {
                let branch =
                    4.0 * e * a.powi(3) / (3.0 * r) - (8.0 * PI * w * e * a.powi(3)).sqrt();
                assert!((f - branch).abs() < 1e-6 * scale, "{i}: {f} vs {branch}");
                let depth = a * a / r - (2.0 * PI * w * a / e).sqrt();
                assert!((d - depth).abs() < 1e-6 * d_max, "{i}: {d} vs {depth}");
                assert!(a >= a_end * (1.0 - 1e-3), "{i}: {a} on the unstable part");
            }
        }
        // zero depth and zero load: interpolated radii against the closed forms
        let radius_at = |target: &dyn Fn(usize) -> f64| {
            let i = (1..k / 2)
                .find(|&i| out.contact_radius[i] > 0.0 && target(i) >= 0.0)
                .unwrap();
            let (f0, f1) = (target(i - 1), target(i));
            let (a0, a1) = (out.contact_radius[i - 1], out.contact_radius[i]);
            a0 + (a1 - a0) * (-f0) / (f1 - f0)
        };
        let at_zero_load = radius_at(&|i| out.values[i]);
        let exact = (9.0 * PI * w * r * r / (2.0 * e)).powf(1.0 / 3.0);
        assert!(
            (at_zero_load / exact - 1.0).abs() < 1e-3,
            "{at_zero_load} vs {exact}"
        );
        let first = (0..k).find(|&i| out.contact_radius[i] > 0.0).unwrap();
        let at_touch = (2.0 * PI * w * r * r / e).powf(1.0 / 3.0);
        // the first contact is the jump in: at a depth just above zero, a radius just above
        assert!(
            out.contact_radius[first] >= at_touch && out.contact_radius[first] < 1.05 * at_touch
        );
        let least = out.values.iter().copied().fold(0.0, f64::min);
        assert!((least / (-1.5 * PI * w * r) - 1.0).abs() < 1e-4, "{least}");
    }

    /// Through a spring the equilibrium approach jumps in at the touch (the spring balancing
    /// the JKR branch's tension), and the retract lets go past -3/2 pi w R.
    #[test]
    fn the_equilibrium_approach_through_a_spring_jumps_in() {
        let (r, e, w) = (1.0, 1.0, 0.001);
        let k_samples = 4001;
        let (stiffness, u_max) = (1.0, 0.05);
        let values = drive(k_samples, -0.01, u_max, 8.0);
        let times = (1..=k_samples).map(|i| i as f64).collect();
        let curve = paraboloid(20000, 0.4, r, times, values, Control::Spring(stiffness));
        let out = curve
            .evaluate_jkr(e, w, 0.0, Approach::Equilibrium)
            .unwrap();
        let first = (0..k_samples)
            .find(|&i| out.contact_radius[i] > 0.0)
            .unwrap();
        assert!(curve.values[first] >= 0.0 && curve.values[first - 1] < 0.0);
        assert!(out.values[first] < 0.0, "jumps in under tension");
        for (i, ((&f, &d), &u)) in out
            .values
            .iter()
            .zip(&out.depth)
            .zip(&curve.values)
            .enumerate()
        {
            assert!((f - stiffness * (u - d)).abs() < 1e-12 * stiffness * u_max);
            let a = out.contact_radius[i];
            if a > 0.0 {
                let depth = a * a / r - (2.0 * PI * w * a / e).sqrt();
                assert!((d - depth).abs() < 1e-6 * u_max, "{i}: {d} vs {depth}");
            }
        }
        let least = out.values.iter().copied().fold(0.0, f64::min);
        assert!((least / (-1.5 * PI * w * r) - 1.0).abs() < 1e-4, "{least}");
        assert_eq!(*out.values.last().unwrap(), 0.0);
    }

    /// A viscoelastic body on the approach: Lee and Radok's hereditary Hertz force for a
    /// ramp d = v t on a standard solid, F(t) = (4/3) sqrt(R) integral_0^t E*(t - s)
    /// d(d^(3/2))/ds ds with E*(t) = 4 (G_inf + G_1 exp(-t / tau)) (the integral by Simpson's
    /// rule in u = sqrt(s)); on the retract the radius is the relaxed elastic curve's.
    #[test]
    fn a_viscoelastic_approach_is_lee_and_radoks() {
        let (r, w) = (1.0, 0.001);
        let (g_inf, g1, tau) = (0.25, 0.75, 0.3);
        let medium = Rheology {
            g_inf,
            terms: vec![(g1, tau)],
            eta: 0.0,
        };
        let (k, v, t_top) = (801, 0.04, 1.0);
        let times: Vec<f64> = (0..k)
            .map(|i| 2.0 * t_top * i as f64 / (k - 1) as f64)
            .collect();
        let values: Vec<f64> = times
            .iter()
            .map(|&t| {
                if t <= t_top {
                    v * t
                } else {
                    v * (2.0 * t_top - t) * 1.5 - 0.5 * v * t_top
                }
            })
            .collect();
        let curve = paraboloid(20000, 0.5, r, times.clone(), values, Control::Depth);
        let out = curve.evaluate_jkr_viscoelastic(&medium, w, 0.0).unwrap();
        let relaxed = curve
            .evaluate_jkr(4.0 * g_inf, w, 0.0, Approach::Touch)
            .unwrap();
        let scale = 4.0 * (g_inf + g1) * (v * t_top).powf(1.5);
        for i in (1..k).filter(|&i| times[i] <= t_top) {
            let t = times[i];
            let m = 400;
            let h = t.sqrt() / m as f64;
            let f = |u: f64| 3.0 * u * u * (-(t - u * u) / tau).exp();
            let simpson: f64 = (0..=m)
                .map(|j| {
                    let weight = if j == 0 || j == m {
                        1.0
                    } else if j % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    weight * f(j as f64 * h)
                })
                .sum::<f64>()
                * h
                / 3.0;
            let exact =
                4.0 / 3.0 * r.sqrt() * v.powf(1.5) * 4.0 * (g_inf * t.powf(1.5) + g1 * simpson);
            assert!(
                (out.values[i] - exact).abs() < 2e-4 * scale,
                "{i}: {} vs {exact}",
                out.values[i]
            );
        }
        assert_eq!(out.contact_radius, relaxed.contact_radius);
        assert!(out.values.iter().any(|&f| f < 0.0));
    }

    /// DMT: Hertz less the attraction while the surfaces touch; through a spring the
    /// contact jumps in at the touch and holds down to the drive -P / k, where the depth
    /// reaches the surface, carrying -P.
    #[test]
    fn dmt_is_hertz_less_the_attraction_while_touching() {
        let (r, e, p): (f64, f64, f64) = (1.0, 1.0, 0.01);
        let k_samples = 2001;
        let (stiffness, u_max) = (1.0, 0.05);
        let values = drive(k_samples, -0.01, u_max, 2.0);
        let times: Vec<f64> = (1..=k_samples).map(|i| i as f64).collect();
        let hertz = |d: f64| 4.0 / 3.0 * e * r.sqrt() * d.max(0.0).powf(1.5);
        let depth = paraboloid(20000, 0.4, r, times.clone(), values.clone(), Control::Depth);
        let out = depth.evaluate_dmt(e, p, 0.0).unwrap();
        for (&d, &f) in values.iter().zip(&out.values) {
            let exact = if d > depth.g[0] { hertz(d) - p } else { 0.0 };
            assert!((f - exact).abs() < 1e-8, "{d}: {f} vs {exact}");
        }
        let spring = paraboloid(
            20000,
            0.4,
            r,
            times,
            values.clone(),
            Control::Spring(stiffness),
        );
        let out = spring.evaluate_dmt(e, p, 0.0).unwrap();
        let top = k_samples / 2;
        for (i, ((&u, &f), &d)) in values.iter().zip(&out.values).zip(&out.depth).enumerate() {
            assert!((f - stiffness * (u - d)).abs() < 1e-12);
            let touching = if i <= top {
                u > 0.0
            } else {
                u > -p / stiffness
            };
            assert_eq!(f != 0.0, touching, "{i}: u = {u}");
            if touching {
                assert!((f - (hertz(d) - p)).abs() < 1e-8, "{i}: {f}");
            }
        }
    }
}
